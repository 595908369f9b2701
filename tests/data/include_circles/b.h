/* fixture: includes sub/a.h, which includes this file */
#include "sub/a.h"
