/* fixture: uses x.c, which uses this file */
int bvox_x(void);
int bvox_y(void)
{
    return bvox_x() + 1;
}
