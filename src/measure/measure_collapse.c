/*
 * measure_collapse.c — bvox_measure's topology (components, cavities)
 * counted on a copy of the volume without its repeated slices.
 *
 * A slice equal to the one before it (row y's columns all equal to row
 * y - 1's, or x-slice x's to x - 1's) can be deleted without changing the
 * components, for 6, 18 and 26 alike. Deleting slice y maps every voxel of
 * it onto its twin in y - 1: a step within y or between y - 1 and y becomes
 * a step (or none) within y - 1 with the same x and z offsets, between
 * voxels that are set because the slices are equal; a step between y and
 * y + 1 becomes one between y - 1 and the next slice. Conversely a step
 * between y - 1 and y + 1 of the copy goes through the deleted slice's twin
 * of its first voxel. So the components map one to one, the object's and
 * the background's (the complements of equal slices are equal).
 *
 * The empty slices outside the object's box are dropped as well. The
 * background there reaches the border along straight lines, and a
 * background component of the box reaches it exactly when it has a voxel on
 * the box's faces, which the copy's faces are (a deleted last slice equals
 * the kept one before it): so the cavities, 6- and 26-connected, are the
 * same too. The Euler number and the surface are not: the scan stays on
 * the volume itself.
 *
 * Nearest-neighbour upsampling (an anisotropic stack made isotropic, the
 * AAL atlas at 512^3) repeats most slices: the atlas keeps 182 of its 512
 * rows and 148 of its x-slices, 146 x 180 in its box, AAL's own grid.
 * Rows come from the scan's twin flags, already paid for; x-slices are
 * compared here, column by column over the kept rows, each slice leaving
 * the comparison at its first difference (in a volume without repeats, in
 * its first rows with object). The copy is made only when it drops a
 * quarter of the box's columns or more (the box alone saves little: the
 * labeller passes over empty columns quickly).
 */
#include "measure/measure.h"

#include <stdlib.h>
#include <string.h>

typedef struct collapse_job {
    const bvox_volume *v;
    const uint32_t *rows; /* the kept rows */
    size_t x0, x1;        /* the box's x range */
    uint8_t *differs;     /* per x: slice x differs from x - 1 (over the kept rows) */
    const uint32_t *xs;   /* the kept x-slices */
    size_t nxs;
    uint64_t *dst; /* the copy: kept rows of kept columns */
} collapse_job;

static inline bool columns_differ(const uint64_t *a, const uint64_t *b, size_t wpc)
{
    uint64_t d = 0;
    for (size_t k = 0; k < wpc; k++) d |= a[k] ^ b[k];
    return d != 0;
}

/* Threads share the flags: a relaxed store of 1 by any of them, and a slice
 * already known to differ is not compared again. */
static void compare_rows(void *ctx, int64_t begin, int64_t end)
{
    const collapse_job *j = ctx;
    size_t wpc = j->v->wpc, nx = (size_t)j->v->nx;
    for (int64_t i = begin; i < end; i++) {
        const uint64_t *row = j->v->words + (size_t)j->rows[i] * nx * wpc;
        for (size_t x = j->x0 + 1; x < j->x1; x++)
            if (!__atomic_load_n(&j->differs[x], __ATOMIC_RELAXED) &&
                columns_differ(row + x * wpc, row + (x - 1) * wpc, wpc))
                __atomic_store_n(&j->differs[x], 1, __ATOMIC_RELAXED);
    }
}

static void copy_rows(void *ctx, int64_t begin, int64_t end)
{
    const collapse_job *j = ctx;
    size_t wpc = j->v->wpc, nx = (size_t)j->v->nx;
    for (int64_t i = begin; i < end; i++) {
        const uint64_t *row = j->v->words + (size_t)j->rows[i] * nx * wpc;
        uint64_t *dst = j->dst + (size_t)i * j->nxs * wpc;
        for (size_t k = 0; k < j->nxs; k++, dst += wpc)
            memcpy(dst, row + j->xs[k] * wpc, wpc * sizeof *dst);
    }
}

bvox_status bvox__collapse_repeats(const bvox_volume *vol, const int32_t bbox[6],
                                   const bvox__colhull *hulls, bvox_volume **out)
{
    *out = NULL;
    size_t nx = (size_t)vol->nx, wpc = vol->wpc;
    size_t x0 = (size_t)bbox[0], x1 = (size_t)bbox[3], y0 = (size_t)bbox[1], y1 = (size_t)bbox[4];
    uint32_t *rows = bvox__mem_alloc((y1 - y0) * sizeof *rows + (x1 - x0) * sizeof *rows);
    uint8_t *differs = bvox__mem_zalloc(nx, 1);
    if (!rows || !differs) {
        free(rows);
        free(differs);
        return bvox__fail(BVOX_ENOMEM, "out of memory collapsing repeated slices");
    }
    uint32_t *xs = rows + (y1 - y0);
    size_t nrows = 0, nxs = 0;
    for (size_t y = y0; y < y1; y++)
        if (y == y0 || !hulls[y * nx].twin_row) rows[nrows++] = (uint32_t)y;
    collapse_job j = {vol, rows, x0, x1, differs, xs, 0, NULL};
    /* a few hundred columns a thread at least: a row is often enough */
    bvox__parallel_for((int64_t)nrows, (int64_t)(4096 / (x1 - x0) + 1), compare_rows, &j);
    for (size_t x = x0; x < x1; x++)
        if (x == x0 || differs[x]) xs[nxs++] = (uint32_t)x;
    j.nxs = nxs;
    bvox_status st = BVOX_OK;
    if (4 * nrows * nxs <= 3 * (x1 - x0) * (y1 - y0)) {
        bvox_volume *c = NULL;
        st = bvox__volume_create_uninit((bvox_dims){(int32_t)nxs, (int32_t)nrows, vol->nz}, &c);
        if (!st) {
            c->geom = vol->geom;
            j.dst = c->words;
            bvox__parallel_for((int64_t)nrows, (int64_t)(16384 / (nxs * wpc) + 1), copy_rows, &j);
            *out = c;
        }
    }
    free(rows);
    free(differs);
    return st;
}
