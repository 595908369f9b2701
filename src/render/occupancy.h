/*
 * occupancy.h — counting 1-voxels near a voxel from the packed words, for
 * smooth normals (smooth.c) and ambient occlusion (occlusion.c): a column's
 * bits z-32 .. z+31 are fetched as one word (two words shifted together), and
 * a window z-h .. z+h of it is one mask, so a column's share of a ball or a
 * cube is one popcount, never a loop over voxels.
 */
#ifndef BVOX_RENDER_OCCUPANCY_H
#define BVOX_RENDER_OCCUPANCY_H

#include "render.h"

/* Bits start .. start+63 of column (x, y) of v, bit 0 = voxel start; voxels
 * outside the volume (any coordinate) read as 0 (tail bits are zero). */
static inline uint64_t bvox__column_window(const bvox_volume *v, int32_t x, int32_t y,
                                           int64_t start)
{
    if (x < 0 || y < 0 || x >= v->nx || y >= v->ny) return 0;
    const uint64_t *col = bvox__column_c(v, x, y);
    const int64_t wpc = (int64_t)v->wpc;
    int64_t w = start >= 0 ? start / 64 : -((-start + 63) / 64); /* floor */
    unsigned sh = (unsigned)(start - w * 64);
    uint64_t lo = w >= 0 && w < wpc ? col[w] : 0;
    if (!sh) return lo;
    uint64_t hi = w + 1 >= 0 && w + 1 < wpc ? col[w + 1] : 0;
    return lo >> sh | hi << (64 - sh);
}

/* Bits 32+a .. 32+b (a <= b, both in -32..31) of a window: voxels z+a .. z+b. */
static inline uint64_t bvox__window_mask(int a, int b)
{
    unsigned n = (unsigned)(b - a + 1);
    uint64_t m = n >= 64 ? ~0ull : (1ull << n) - 1;
    return m << (32 + a);
}

/* Clamp a smooth-normal radius (0: the default 2). */
static inline int bvox__smooth_radius(int r) { return r <= 0 ? 2 : r > 3 ? 3 : r; }

#endif
