/*
 * contour_edt.c — exact signed Euclidean distance map of a bitmap, the input
 * of shape-based interpolation.
 *
 * Separable (Felzenszwalb & Huttenlocher, "Distance transforms of sampled
 * functions", 2012): first, per column, the distance along y to the nearest 1
 * pixel and to the nearest 0 pixel (a top-down and a bottom-up sweep, done a
 * row at a time so that the inner loop runs along contiguous memory); then,
 * per row, the lower envelope of the parabolas g(q)^2 + (x - q)^2 gives the
 * squared distance. Both channels (to the object, to the background) are
 * done together. Values are exact: squared distances are integers held in
 * doubles.
 */
#include "contour_internal.h"

#include <math.h>

#define COL_INF 0x3fffffffu
#define SQ_INF 1e20

size_t bvox__edt_scratch_doubles(int32_t nx, int32_t ny)
{
    /* two uint32 channels of nx * ny (as doubles: half of that), plus the
     * envelope buffers */
    size_t n = (size_t)nx * (size_t)ny;
    size_t m = (size_t)(nx > ny ? nx : ny) + 1;
    return n + 6 * m + 2;
}

/* Squared distances d[x], lo <= x < hi, to the lower envelope of the
 * parabolas (x - q)^2 + f[q] of the finite f[q], lo <= q < hi
 * (Felzenszwalb-Huttenlocher); f[q] >= SQ_INF adds no parabola, and with none
 * at all d = SQ_INF. */
static void envelope(const double *f, int32_t lo, int32_t hi, double *d, int32_t *v, double *z)
{
    int32_t k = -1;
    for (int32_t q = lo; q < hi; q++) {
        if (f[q] >= SQ_INF) continue;
        if (k < 0) {
            k = 0;
            v[0] = q;
            z[0] = -HUGE_VAL; /* stops the loop below at k = 0 (s is finite) */
            z[1] = HUGE_VAL;
            continue;
        }
        double fq = f[q] + (double)q * q;
        double s = (fq - (f[v[k]] + (double)v[k] * v[k])) / (2.0 * (q - v[k]));
        while (s <= z[k]) {
            k--;
            s = (fq - (f[v[k]] + (double)v[k] * v[k])) / (2.0 * (q - v[k]));
        }
        k++;
        v[k] = q;
        z[k] = s;
        z[k + 1] = HUGE_VAL;
    }
    if (k < 0) {
        for (int32_t q = lo; q < hi; q++) d[q] = SQ_INF;
        return;
    }
    k = 0;
    for (int32_t q = lo; q < hi; q++) {
        while (z[k + 1] < q) k++;
        double dq = (double)(q - v[k]);
        d[q] = dq * dq + f[v[k]];
    }
}

void bvox__signed_edt(const uint64_t *bits, size_t wpr, int32_t nx, int32_t ny, float cap,
                      double *tmp, float *out)
{
    size_t n = (size_t)nx * (size_t)ny;
    uint32_t *g1 = (uint32_t *)tmp;       /* column distance to the nearest 1 */
    uint32_t *g0 = g1 + n;                /* ... to the nearest 0 */
    size_t m = (size_t)(nx > ny ? nx : ny) + 1;
    double *f1 = tmp + n, *f0 = f1 + m, *d1 = f0 + m, *d0 = d1 + m, *z = d0 + m;
    int32_t *v = (int32_t *)(z + m + 1);
    int any1, any0;
    /* every squared distance is below nx^2 + ny^2 */
    const int small = (double)nx * nx + (double)ny * ny < 16777216.0;

#define BIT(y, x) ((bits[(size_t)(y) * wpr + ((size_t)(x) >> 6)] >> ((x) & 63)) & 1u)
    uint8_t *brow = (uint8_t *)d1; /* one row as bytes 0/1 (d1 is free until the rows) */
    {
        uint64_t ones = 0;
        size_t full = (size_t)nx / 64, rem = (size_t)nx % 64;
        for (int32_t y = 0; y < ny; y++) {
            const uint64_t *row = bits + (size_t)y * wpr;
            for (size_t w = 0; w < full; w++) ones += (uint64_t)__builtin_popcountll(row[w]);
            if (rem) ones += (uint64_t)__builtin_popcountll(row[full] & ((1ull << rem) - 1));
        }
        any1 = ones > 0;
        any0 = ones < (uint64_t)n;
    }
    /* top-down, a row at a time (branch-free, so the compiler vectorises) */
    for (int32_t y = 0; y < ny; y++) {
        uint32_t *r1 = g1 + (size_t)y * nx, *r0 = g0 + (size_t)y * nx;
        const uint64_t *row = bits + (size_t)y * wpr;
        for (int32_t x = 0; x < nx; x++) brow[x] = (uint8_t)((row[x >> 6] >> (x & 63)) & 1);
        if (y == 0) {
            for (int32_t x = 0; x < nx; x++) {
                uint32_t mk = 0u - (uint32_t)brow[x];
                r1[x] = COL_INF & ~mk;
                r0[x] = COL_INF & mk;
            }
            continue;
        }
        const uint32_t *p1 = r1 - nx, *p0 = r0 - nx;
        for (int32_t x = 0; x < nx; x++) {
            uint32_t mk = 0u - (uint32_t)brow[x];
            uint32_t u1 = p1[x] + 1, u0 = p0[x] + 1;
            u1 = u1 < COL_INF ? u1 : COL_INF;
            u0 = u0 < COL_INF ? u0 : COL_INF;
            r1[x] = u1 & ~mk;
            r0[x] = u0 & mk;
        }
    }
    /* bottom-up */
    for (int32_t y = ny - 2; y >= 0; y--) {
        uint32_t *r1 = g1 + (size_t)y * nx, *r0 = g0 + (size_t)y * nx;
        const uint32_t *n1 = r1 + nx, *n0 = r0 + nx;
        for (int32_t x = 0; x < nx; x++) {
            uint32_t a = n1[x] + 1, b = n0[x] + 1;
            if (a < r1[x]) r1[x] = a;
            if (b < r0[x]) r0[x] = b;
        }
    }
    /* rows. The distance to a 0 pixel is needed only at the row's 1 pixels,
     * all within [a, b] (first and last 1 of the row): columns outside
     * [a - 1, b + 1] are 0 pixels (f = 0) farther than a - 1 or b + 1, so
     * their parabolas never win there. */
    for (int32_t y = 0; y < ny; y++) {
        const uint32_t *r1 = g1 + (size_t)y * nx, *r0 = g0 + (size_t)y * nx;
        float *o = out + (size_t)y * nx;
        int32_t a = nx, b = -1;
        for (size_t w = 0; w < wpr; w++) {
            uint64_t word = bits[(size_t)y * wpr + w];
            if (!word) continue;
            int32_t lo = (int32_t)(w * 64) + __builtin_ctzll(word);
            int32_t hi = (int32_t)(w * 64) + 63 - __builtin_clzll(word);
            if (lo < a) a = lo;
            if (hi > b) b = hi;
        }
        if (any1) {
            for (int32_t x = 0; x < nx; x++)
                f1[x] = r1[x] >= COL_INF ? SQ_INF : (double)r1[x] * r1[x];
            envelope(f1, 0, nx, d1, v, z);
        }
        int32_t lo0 = a > 0 ? a - 1 : 0, hi0 = b + 2 < nx ? b + 2 : nx;
        if (any0 && b >= 0) {
            for (int32_t x = lo0; x < hi0; x++)
                f0[x] = r0[x] >= COL_INF ? SQ_INF : (double)r0[x] * r0[x];
            envelope(f0, lo0, hi0, d0, v, z);
        }
        if (any0 && any1) {
            /* both maps are finite where they are read: d1 everywhere (a
             * column holds a 1, so every row has a finite parabola), d0 on
             * [lo0, hi0), which holds the row's 1 pixels and a 0 pixel or a
             * column with one. The row's bits as bytes (f1 is free now), d0
             * defined everywhere, so that the loop below has no branch. */
            uint8_t *ob = (uint8_t *)f1;
            for (int32_t x = 0; x < nx; x++) ob[x] = (uint8_t)BIT(y, x);
            if (b < 0) lo0 = hi0 = 0;
            for (int32_t x = 0; x < lo0; x++) d0[x] = 0;
            for (int32_t x = hi0; x < nx; x++) d0[x] = 0;
            if (small) {
                /* squared distances are integers below 2^24, exact in float,
                 * and sqrtf of them equals (float)sqrt(double) (double
                 * rounding is harmless for sqrt from 53 to 24 bits) */
                for (int32_t x = 0; x < nx; x++) {
                    float dd = (float)(ob[x] ? d0[x] : d1[x]);
                    float dist = sqrtf(dd);
                    dist = dist < cap ? dist : cap;
                    o[x] = ob[x] ? -dist : dist;
                }
            } else {
                for (int32_t x = 0; x < nx; x++) {
                    float dist = (float)sqrt(ob[x] ? d0[x] : d1[x]);
                    dist = dist < cap ? dist : cap;
                    o[x] = ob[x] ? -dist : dist;
                }
            }
        } else {
            for (int32_t x = 0; x < nx; x++) o[x] = any1 ? -cap : cap; /* all 1 / all 0 */
        }
    }
#undef BIT
}
