/* contourref.c — see contourref.h. */
#include "contourref.h"

#include <math.h>

int contourref_inside(const contourref_poly *polys, int npolys, int64_t i, int64_t j)
{
    int64_t cx = 4 * i + 2, cy = 4 * j + 2;
    int parity = 0;
    for (int p = 0; p < npolys; p++) {
        const contourref_poly *P = &polys[p];
        for (int k = 0; k < P->n; k++) {
            int k2 = (k + 1) % P->n;
            int64_t ax = P->x4[k], ay = P->y4[k], bx = P->x4[k2], by = P->y4[k2];
            int64_t lo = ay < by ? ay : by, hi = ay < by ? by : ay;
            if (!(lo <= cy && cy < hi)) continue;
            /* sign of (cx - ax) * dy - (cy - ay) * dx, exact in 64 bits */
            int64_t d = (cx - ax) * (by - ay) - (cy - ay) * (bx - ax);
            int right = (by > ay) ? d > 0 : d < 0;
            parity ^= right;
        }
    }
    return parity;
}

double contourref_signed_distance(const uint8_t *in, int nx, int ny, int x, int y, double cap)
{
    int me = in[y * nx + x];
    double best = INFINITY;
    for (int v = 0; v < ny; v++)
        for (int u = 0; u < nx; u++)
            if (in[v * nx + u] != me) {
                double d = sqrt((double)(u - x) * (u - x) + (double)(v - y) * (v - y));
                if (d < best) best = d;
            }
    if (best > cap) best = cap;
    return me ? -best : best;
}
