/*
 * edit.h — private helpers shared by the in-place edits (edit.c) and the
 * plane cut and half-space (cut.c): changing one bit run of a column with
 * whole-word masks while recording the tight box of the voxels whose value
 * really changed, and merging those boxes across the worker threads.
 */
#ifndef BVOX_EDIT_H
#define BVOX_EDIT_H

#include "internal.h"

#include <pthread.h>

/* Tight box of changed voxels, inclusive bounds; empty while x0 > x1. */
typedef struct bvox__change {
    int32_t x0, y0, z0, x1, y1, z1;
} bvox__change;

static inline void bvox__change_init(bvox__change *c)
{
    *c = (bvox__change){INT32_MAX, INT32_MAX, INT32_MAX, -1, -1, -1};
}

/* The same, shared by the threads of one operation: each chunk accumulates
 * its own bvox__change and merges it once at its end. */
typedef struct bvox__change_shared {
    pthread_mutex_t lock;
    bvox__change c;
} bvox__change_shared;

void bvox__change_shared_init(bvox__change_shared *s);
void bvox__change_merge(bvox__change_shared *s, const bvox__change *part);
void bvox__change_shared_done(bvox__change_shared *s);
/* Half-open box of c (all zero when nothing changed); out may be NULL. */
void bvox__change_to_box(const bvox__change *c, bvox_box *out);

enum { BVOX__RUN_SET = 0, BVOX__RUN_CLEAR = 1, BVOX__RUN_FLIP = 2 };

/* Set, clear or flip bits [z0, z1) of column (x, y) (0 <= z0, z1 <= nz, so the
 * zero tail bits are never touched) and add the voxels that changed to c.
 * Set and clear first look for the first and last word that will change
 * (usually the run's end words) and write only between them: a run that
 * changes nothing costs reads only, and the words in between are plain
 * stores (memset-like), never per-voxel work. */
static inline void bvox__run_apply(uint64_t *col, int64_t z0, int64_t z1, int mode, int32_t x,
                                   int32_t y, bvox__change *c)
{
    if (z0 >= z1) return;
    int64_t w0 = z0 >> 6, w1 = (z1 - 1) >> 6, zlo, zhi;
    const uint64_t m0 = ~0ull << (z0 & 63), m1 = ~0ull >> (63 - ((z1 - 1) & 63));
#define BVOX__RUN_MASK(w) (((w) == w0 ? m0 : ~0ull) & ((w) == w1 ? m1 : ~0ull))
    if (mode == BVOX__RUN_FLIP) {
        if (w0 == w1) {
            col[w0] ^= m0 & m1;
        } else {
            col[w0] ^= m0;
            for (int64_t w = w0 + 1; w < w1; w++) col[w] = ~col[w];
            col[w1] ^= m1;
        }
        zlo = z0;
        zhi = z1 - 1;
    } else {
        /* the bits that change in word w: (col[w] ^ inv) & mask(w) */
        const uint64_t inv = mode == BVOX__RUN_SET ? ~0ull : 0;
        int64_t f = w0, l = w1;
        uint64_t d;
        for (;; f++) {
            if (f > w1) return; /* nothing changes */
            if ((d = (col[f] ^ inv) & BVOX__RUN_MASK(f))) break;
        }
        zlo = f * 64 + __builtin_ctzll(d);
        while (!(d = (col[l] ^ inv) & BVOX__RUN_MASK(l))) l--; /* stops at f at the latest */
        zhi = l * 64 + 63 - __builtin_clzll(d);
        col[f] ^= (col[f] ^ inv) & BVOX__RUN_MASK(f);
        if (l > f) {
            col[l] ^= (col[l] ^ inv) & BVOX__RUN_MASK(l);
            /* whole words; the value is made opaque so that the compiler
             * does not turn a run of a few words into a memset call */
            uint64_t fill = inv;
            __asm__("" : "+r"(fill));
            for (int64_t w = f + 1; w < l; w++) col[w] = fill;
        }
    }
#undef BVOX__RUN_MASK
    if (x < c->x0) c->x0 = x;
    if (x > c->x1) c->x1 = x;
    if (y < c->y0) c->y0 = y;
    if (y > c->y1) c->y1 = y;
    if (zlo < c->z0) c->z0 = (int32_t)zlo;
    if (zhi > c->z1) c->z1 = (int32_t)zhi;
}

/* ---- cut.c: the half-space in index space ---- */
/* Combine the half-space f(i, j, k) >= 0 with vol by op, where
 * f = ((p[3] + p[1]*j) + p[0]*i) + p[2]*k, evaluated in that order (the
 * coefficients must be finite). changed may be NULL. Never fails. */
void bvox__halfspace_index(bvox_volume *vol, const double p[4], bvox_csg_op op,
                           bvox_box *changed);

#endif
