#include "bvox.h"
#include <stdio.h>
int main(void) { printf("bvox %s\n", bvox_version()); return 0; }
