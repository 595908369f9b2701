/*
 * measure_enclosed.c — the background that can hold a cavity, for the
 * labelled route of measure_cavities.c (bvox__cavity_hull = 1; the
 * default lists U's runs instead, measure_hull_runs.c).
 *
 * A background voxel with no object voxel below it in its column, or none
 * above, reaches the border along that straight line: it is never in a
 * cavity. So only U, the background strictly between the first and the last
 * object voxel of each column, is labelled; the rest of the background, E, is
 * all "outside". A 6-component of U is a cavity exactly when none of its
 * voxels is a 6-neighbour of E: a background component either holds a voxel
 * of E (it reaches the border) or lies in U whole, where it is a component of
 * U. Within a column U's runs end on object voxels, so contacts with E are
 * only across x and y, and they are found word by word from the neighbour
 * columns' z ranges.
 *
 * On the AAL atlas at 512^3 U holds 5.5 % of the background and a quarter of
 * its runs (sulci and ventricles); the whole-background labelling it replaces
 * spent most of its unions on the one exterior component. A coin toss keeps
 * the flood (its U is nearly all the background).
 */
#include "measure/measure.h"
#include "ops/components_label.h"

typedef struct enclosed_job {
    const bvox_volume *v;
    size_t x0, y0, nx, ny;
    uint64_t *u;
    int32_t *zr; /* per box column: U's hull [lo, hi) along z */
} enclosed_job;

static void enclosed_rows(void *ctx, int64_t begin, int64_t end)
{
    const enclosed_job *j = ctx;
    const bvox_volume *v = j->v;
    size_t wpc = v->wpc;
    for (size_t y = (size_t)begin; y < (size_t)end; y++)
        for (size_t x = 0; x < j->nx; x++) {
            size_t col = y * j->nx + x;
            const uint64_t *o = v->words + ((j->y0 + y) * (size_t)v->nx + j->x0 + x) * wpc;
            uint64_t *u = j->u + col * wpc;
            int32_t lo, hi;
            bool ring = x == 0 || y == 0 || x + 1 == j->nx || y + 1 == j->ny;
            bvox__column_hull(o, wpc, ring, &lo, &hi);
            j->zr[2 * col] = lo, j->zr[2 * col + 1] = hi;
            for (size_t k = 0; k < wpc; k++) u[k] = ~o[k] & bvox__range_bits(lo, hi, k);
        }
}

void bvox__enclosed_background(const bvox_volume *vol, size_t x0, size_t y0, size_t nx,
                               size_t ny, uint64_t *u, int32_t *zr)
{
    enclosed_job j = {vol, x0, y0, nx, ny, u, zr};
    bvox__parallel_for((int64_t)ny, 8, enclosed_rows, &j);
}

/* E's words of box column col (the background outside its hull), word k. */
static inline uint64_t exterior_word(const bvox_volume *v, const uint64_t *o, const int32_t *zr,
                                     size_t col, size_t k)
{
    int64_t base = (int64_t)k * 64;
    if (zr[2 * col] <= base && zr[2 * col + 1] >= base + 64) return 0; /* inside the hull */
    uint64_t bg = ~o[k] & (k + 1 == v->wpc ? v->tail_mask : ~0ull);
    return bg & ~bvox__range_bits(zr[2 * col], zr[2 * col + 1], k);
}

typedef struct mark_job {
    const bvox__labelruns *r;
    const bvox_volume *v;
    size_t x0, y0;
    const int32_t *zr;
    uint8_t *touched;
} mark_job;

/* T's words of U's column (x, y) of the box (inner), into t: U & the
 * 6-neighbourhood of E across x and y (U's runs end on object voxels along
 * z). */
static uint64_t touching_column(const mark_job *j, size_t x, size_t y, uint64_t *t)
{
    const bvox__labelruns *r = j->r;
    const bvox_volume *v = j->v;
    size_t nx = r->nx, wpc = r->wpc, vnx = (size_t)v->nx, col = y * nx + x;
    const uint64_t *u = r->words + col * wpc;
    const uint64_t *o = v->words + ((j->y0 + y) * vnx + j->x0 + x) * wpc;
    const size_t nb[4] = {col - 1, col + 1, col - nx, col + nx};
    const uint64_t *onb[4] = {o - wpc, o + wpc, o - vnx * wpc, o + vnx * wpc};
    uint64_t any = 0;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t e = 0;
        if (u[k])
            for (int i = 0; i < 4; i++) e |= exterior_word(v, onb[i], j->zr, nb[i], k);
        t[k] = u[k] & e;
        any |= t[k];
    }
    return any;
}

static void mark_rows(void *ctx, int64_t begin, int64_t end)
{
    const mark_job *j = ctx;
    const bvox__labelruns *r = j->r;
    uint64_t t[(BVOX_MAX_DIM + 63) / 64];
    for (size_t y = (size_t)begin + 1; y < (size_t)end + 1; y++)
        for (size_t x = 1; x + 1 < r->nx; x++) {
            size_t col = y * r->nx + x;
            if (r->grp_start[col] == r->grp_start[col + 1]) continue;
            if (touching_column(j, x, y, t)) bvox__labelruns_mark_group(r, col, t, j->touched);
        }
}

void bvox__enclosed_mark_exterior(const bvox__labelruns *r, const bvox_volume *vol, size_t x0,
                                  size_t y0, const int32_t *zr, uint8_t *touched)
{
    if (r->ny < 3) return;
    mark_job j = {r, vol, x0, y0, zr, touched};
    bvox__parallel_for((int64_t)r->ny - 2, 8, mark_rows, &j);
}
