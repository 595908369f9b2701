/*
 * measure_scan.h — the kernels of the measure scan (measure_scan.c, the
 * portable reference; measure_scan_avx512.c; measure_scan_avx2.c): the
 * cells of one row of vertex columns at a time, so that a vector kernel
 * reduces its accumulators once per row, not once per column; the moments
 * of one voxel column. The
 * window geometry and the formulas are documented in measure_scan.c.
 */
#ifndef BVOX_MEASURE_SCAN_H
#define BVOX_MEASURE_SCAN_H

#include "measure/measure.h"
#include <string.h>

/* Adds the Euler number's V - E and the transitions of the vertex row
 * between voxel rows prev (y - 1) and cur (y) to s (its F - C is added once
 * per scan from the totals, measure_scan.c); either may be NULL (outside the
 * volume). nx + 1 vertex columns; zero is a zero column of wpc words.
 * extra: nz is a multiple of 64, so the top vertex z = nz lies in one more
 * word (hi = 0, lo = the top voxel). */
typedef void (*bvox__cells_row_fn)(const uint64_t *prev, const uint64_t *cur, size_t nx,
                                   size_t wpc, bool extra, const uint64_t *zero, bvox__scan *s);

/* Adds count, sums and z range of the 1-voxels of the voxel column (x, y)
 * of wpc words to s; columns come in increasing y. */
typedef void (*bvox__moments_fn)(const uint64_t *col, size_t wpc, int32_t x, int32_t y,
                                 bvox__scan *s);

/* The moments of the row of nx voxel columns at row, y its index: as
 * bvox__moments_fn for every column in turn (the vector kernels keep the
 * row's sums in registers). */
typedef void (*bvox__row_moments_fn)(const uint64_t *row, size_t nx, size_t wpc, int32_t y,
                                     bvox__scan *s);

/* The AVX-512 (F, BW, VL, VPOPCNTDQ) and AVX2 (+ POPCNT + BMI2) kernels,
 * NULL where the build has none; the caller checks the CPU. */
extern const bvox__cells_row_fn bvox__cells_row_avx512;
extern const bvox__cells_row_fn bvox__cells_row_avx2;
extern const bvox__row_moments_fn bvox__row_moments_avx512;
extern const bvox__row_moments_fn bvox__row_moments_avx2;

/* The four voxel columns a = (x-1, y-1), b = (x, y-1), c = (x-1, y),
 * d = (x, y) of vertex column x, zero where outside. */
static inline void bvox__cells_cols(const uint64_t *prev, const uint64_t *cur, size_t x, size_t nx,
                                    size_t wpc, const uint64_t *zero, const uint64_t *col[4])
{
    col[0] = prev && x > 0 ? prev + (x - 1) * wpc : zero;
    col[1] = prev && x < nx ? prev + x * wpc : zero;
    col[2] = cur && x > 0 ? cur + (x - 1) * wpc : zero;
    col[3] = cur && x < nx ? cur + x * wpc : zero;
}

/* The 64 windows of one word: hi words ah..dh, lo words al..dl: V - E of
 * the Euler number into *eul (F - C comes from totals, measure_scan.c) and
 * the transitions into t. All-0 windows add nothing and are skipped; all-1
 * ones add only V - E = 1 - 3 each. hw: use the POPCNT instruction (only
 * inlined into code built for it). */
static inline __attribute__((always_inline)) void
bvox__cells_word(uint64_t ah, uint64_t bh, uint64_t ch, uint64_t dh, uint64_t al, uint64_t bl,
                 uint64_t cl, uint64_t dl, int64_t *eul, int64_t t[BVOX__NDIR], bool hw)
{
#define pc(w) ((int64_t)(hw ? (unsigned)__builtin_popcountll(w) : bvox__popcount64(w)))
    uint64_t any = ah | bh | ch | dh | al | bl | cl | dl;
    if (!any) return;
    if ((ah & bh & ch & dh & al & bl & cl & dl) == ~0ull) {
        *eul -= 64 * 2; /* V - E of 64 full windows: 1 - 3 each */
        return;
    }
    *eul += pc(any)                                                           /* V */
            - pc(ah | bh | ch | dh) - pc(bh | bl | dh | dl) - pc(ch | cl | dh | dl); /* E */
    t[BVOX__DIR_X] += pc(ch ^ dh);
    t[BVOX__DIR_Y] += pc(bh ^ dh);
    t[BVOX__DIR_Z] += pc(dl ^ dh);
    t[BVOX__DIR_XY] += pc(ah ^ dh) + pc(bh ^ ch);
    t[BVOX__DIR_XZ] += pc(cl ^ dh) + pc(ch ^ dl);
    t[BVOX__DIR_YZ] += pc(bl ^ dh) + pc(bh ^ dl);
    t[BVOX__DIR_XYZ] += pc(al ^ dh) + pc(bl ^ ch) + pc(cl ^ bh) + pc(dl ^ ah);
#undef pc
}

/* Column x of row y, with 1-voxels in [zlo, zhi), added to s's box. */
static inline void bvox__bbox_add(bvox__scan *s, int32_t x, int32_t y, int32_t zlo, int32_t zhi)
{
    if (!s->boxed) {
        s->boxed = true;
        s->bbox[0] = s->bbox[3] = x;
        s->bbox[1] = s->bbox[4] = y;
        s->bbox[2] = zlo;
        s->bbox[5] = zhi;
    }
    if (x < s->bbox[0]) s->bbox[0] = x;
    if (x + 1 > s->bbox[3]) s->bbox[3] = x + 1;
    if (y + 1 > s->bbox[4]) s->bbox[4] = y + 1; /* rows come in increasing y */
    if (zlo < s->bbox[2]) s->bbox[2] = zlo;
    if (zhi > s->bbox[5]) s->bbox[5] = zhi;
}

/* One column's count n, sums sz and szz of z and z^2, and z range
 * [zlo, zhi) added to s (nothing when n = 0). */
static inline void bvox__moments_add(bvox__scan *s, int32_t x, int32_t y, int64_t n, int64_t sz,
                                     int64_t szz, int32_t zlo, int32_t zhi)
{
    if (!n) return;
    bvox__bbox_add(s, x, y, zlo, zhi);
    uint64_t X = (uint64_t)x, N = (uint64_t)n, SZ = (uint64_t)sz;
    s->row[0] += N, s->row[1] += X * N, s->row[2] += X * X * N;
    s->row[3] += SZ, s->row[4] += (uint64_t)szz, s->row[5] += X * SZ;
}

/* Row y's sums (s->row) moved into s's totals. */
static inline void bvox__moments_row(bvox__scan *s, int32_t y)
{
    const uint64_t *r = s->row;
    bvox__wide Y = y;
    s->count += (int64_t)r[0];
    s->s[0] += r[1], s->s[1] += Y * r[0], s->s[2] += r[3];
    s->ss[0] += r[2], s->ss[1] += Y * Y * r[0], s->ss[2] += r[4];
    s->ss[3] += Y * r[1], s->ss[4] += r[5], s->ss[5] += Y * r[3];
    memset(s->row, 0, sizeof s->row);
}

#endif
