/* fixture: uses y.c, which uses this file */
int bvox_y(void);
int bvox_x(void) { return bvox_y(); }
