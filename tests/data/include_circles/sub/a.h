/* fixture for lint.include_circles_found: a header circle */
#include "../b.h"
