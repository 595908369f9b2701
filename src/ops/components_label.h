/*
 * components_label.h — the labelling core behind components.c: runs of
 * column groups joined by a union-find (components_label.c).
 *
 * A group is g x g neighbouring columns: g = 2 for 26-connectivity, g = 1
 * for 6 and 18. With 26-connectivity any two voxels of a 2 x 2 group whose
 * z differ by at most one touch, so a maximal run along z of the OR of the
 * group's four columns is connected: it is one union-find node. On a coin-toss
 * volume that is about 16 times fewer nodes than runs of single columns (the
 * OR is 15/16 full, so its runs are long), and 4 times fewer column pairs to
 * join. Groups are numbered x fastest, then y; runs of a group by increasing
 * z; group (X, Y) holds columns x = gX .. gX + g - 1, y = gY .. gY + g - 1
 * (fewer at an odd edge).
 */
#ifndef BVOX_COMPONENTS_LABEL_H
#define BVOX_COMPONENTS_LABEL_H

#include "internal.h"

typedef struct bvox__labelruns {
    size_t nx, ny, wpc;
    int g;                 /* group side: 2 or 1 */
    size_t gx, gy, ngrp;   /* groups per row, rows of groups, groups */
    const uint64_t *words; /* the labelled words (borrowed) */
    uint64_t *uw;          /* OR of each group's columns, ngrp * wpc words; NULL when g == 1 */
    uint32_t *grp_start;   /* runs of group i: [grp_start[i], grp_start[i + 1]) */
    uint32_t *parent;      /* union-find parent per run (+ extra), budgeted */
    size_t nruns, extra;
} bvox__labelruns;

/* Labels the runs of words (nx * ny columns of wpc words) for conn 6, 18 or
 * 26: on return parent[] is a forest whose roots are the smallest run of
 * each component, and parent[i] <= i. extra entries after the runs are left
 * for the caller. copy, when not NULL, receives a copy of words during the
 * first pass (which reads them anyway) and is what out->words then points
 * to. BVOX_ENOMEM / BVOX_ETOOBIG (budget, or 2^32 runs). */
bvox_status bvox__labelruns_find(const uint64_t *words, uint64_t *copy, size_t nx, size_t ny,
                                 size_t wpc, int conn, size_t extra, bvox__labelruns *out);
void bvox__labelruns_free(bvox__labelruns *r);

/* The OR words of group grp (the column itself when g == 1). */
static inline const uint64_t *bvox__labelruns_group(const bvox__labelruns *r, size_t grp)
{
    return (r->g == 1 ? r->words : r->uw) + grp * r->wpc;
}

/* Column (x, y) of group grp's corner (gX + i, gY + j), or NULL when that
 * column lies outside the volume. */
static inline const uint64_t *bvox__labelruns_column(const bvox__labelruns *r, size_t grp, size_t i, size_t j)
{
    size_t x = grp % r->gx * (size_t)r->g + i, y = grp / r->gx * (size_t)r->g + j;
    return x < r->nx && y < r->ny ? r->words + (y * r->nx + x) * r->wpc : NULL;
}

/* Join every run that touches the border of the volume to node `outside`
 * (an extra entry the caller initialised). */
void bvox__labelruns_join_border(bvox__labelruns *r, size_t nz, uint32_t outside);

/* touched[root] = 1 for the root of every run of group grp holding a voxel
 * of mask (wpc words); parent[] flattened (every entry a root). Safe from
 * several threads at once (each store writes the same 1). */
void bvox__labelruns_mark_group(const bvox__labelruns *r, size_t grp, const uint64_t *mask,
                                uint8_t *touched);

/* The first pass for one 2 x 2 group: the OR of columns c00..c11 (NULL
 * where outside the volume; c00 never) into dst (wpc words), and the
 * number of its runs returned. components_label_avx512.c, NULL where the
 * build has no AVX-512; the caller checks the CPU. */
typedef uint32_t (*bvox__group_runs_fn)(const uint64_t *c00, const uint64_t *c10,
                                        const uint64_t *c01, const uint64_t *c11, size_t wpc,
                                        uint64_t *dst);
extern const bvox__group_runs_fn bvox__group_runs_avx512;

static inline uint64_t bvox__run_starts(uint64_t w, uint64_t carry)
{
    return w & ~((w << 1) | carry);
}

static inline uint32_t bvox__uf_find(uint32_t *parent, uint32_t i)
{
    /* Most runs point at their root or are one: answer those without the
     * redundant store of path halving. */
    uint32_t p = parent[i];
    if (p == i) return i;
    if (parent[p] == p) return p;
    while (parent[i] != i) {
        uint32_t g = parent[parent[i]];
        parent[i] = g;
        i = g;
    }
    return i;
}

/* Union by smaller index: roots stay the smallest run of their component. */
static inline void bvox__uf_unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = bvox__uf_find(parent, a);
    b = bvox__uf_find(parent, b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

#endif /* BVOX_COMPONENTS_LABEL_H */
