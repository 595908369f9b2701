/*
 * cast_axis.c — the six axis views, on whole words (the paper's ray cast
 * along a main axis, 64 voxels per test instead of 8).
 *
 *  - Along +-z a ray is one column: the first non-zero word and its count of
 *    trailing (+z) or leading (-z) zeros give the hit.
 *  - Along +-x and +-y the rays are the bits of the z-words: a sweep walks
 *    the slices in view order keeping a "not yet hit" mask per z-word; the
 *    rays a word hits are word & notyet, recorded with the current step as
 *    depth, then notyet &= ~word. It stops when every ray has hit. Both sweeps
 *    read memory in order: +-x walks the contiguous columns of one y row,
 *    +-y walks whole y rows (one notyet mask per column of the row).
 *
 * The normal code of a hit needs its 6 face neighbours; the sweeps form them
 * as words for the 64 rays at once (the z neighbours are the word shifted by
 * one with the carry from the next word; x and y neighbours are the same word
 * of the neighbouring columns) and then read one bit per hit ray.
 * Outside the volume counts as 0. Rows (or column blocks) are independent, so
 * they are split over the worker threads.
 */
#include "render.h"

#include <string.h>

typedef struct cast_ctx {
    const bvox_volume *v;
    bvox_preimage *pre;
    int dir;           /* +1 or -1 */
    bvox__cue cue;     /* for the extent along the view */
    uint64_t *notyet;  /* +-y: nx * wpc words */
} cast_ctx;

static inline unsigned bit_at(const uint64_t *col, int32_t z)
{
    return (unsigned)(col[z >> 6] >> (z & 63)) & 1u;
}

/* ------------------------------------------------------------------ +-z */

static void cast_z_rows(void *arg, int64_t y0, int64_t y1)
{
    const cast_ctx *c = arg;
    const bvox_volume *v = c->v;
    const size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    const int32_t nx = v->nx, ny = v->ny, nz = v->nz;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        int32_t *dst_d = c->pre->depth + (size_t)y * (size_t)nx;
        uint8_t *dst_c = c->pre->code + (size_t)y * (size_t)nx;
        for (int32_t x = 0; x < nx; x++) {
            const uint64_t *col = bvox__column_c(v, x, y);
            int32_t z = -1;
            if (c->dir > 0) {
                for (size_t w = 0; w < wpc; w++)
                    if (col[w]) {
                        z = (int32_t)(w * 64 + (size_t)__builtin_ctzll(col[w]));
                        break;
                    }
            } else {
                for (size_t w = wpc; w-- > 0;)
                    if (col[w]) {
                        z = (int32_t)(w * 64 + 63 - (size_t)__builtin_clzll(col[w]));
                        break;
                    }
            }
            if (z < 0) continue;
            unsigned nb = 0;
            if (z > 0 && bit_at(col, z - 1)) nb |= NB_ZM;
            if (z + 1 < nz && bit_at(col, z + 1)) nb |= NB_ZP;
            if (x > 0 && bit_at(col - wpc, z)) nb |= NB_XM;
            if (x + 1 < nx && bit_at(col + wpc, z)) nb |= NB_XP;
            if (y > 0 && bit_at(col - row, z)) nb |= NB_YM;
            if (y + 1 < ny && bit_at(col + row, z)) nb |= NB_YP;
            int32_t depth = c->dir > 0 ? z : nz - 1 - z;
            dst_d[x] = depth;
            dst_c[x] = bvox__code(nb, depth, &c->cue);
        }
    }
}

/* ---------------------------------------------------------- sweep helper */

/* Record the rays `hit` of word w of column col (voxel x, y) at depth step.
 * pix_base + z * pix_stride is the pixel of ray z. */
static inline void record_hits(const bvox_volume *v, const uint64_t *col, int32_t x, int32_t y,
                               size_t w, uint64_t hit, int32_t step, bvox_preimage *pre,
                               size_t pix_base, size_t pix_stride, const bvox__cue *cue)
{
    const size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    uint64_t word = col[w];
    uint64_t xm = x > 0 ? col[w - wpc] : 0;
    uint64_t xp = x + 1 < v->nx ? col[w + wpc] : 0;
    uint64_t ym = y > 0 ? col[w - row] : 0;
    uint64_t yp = y + 1 < v->ny ? col[w + row] : 0;
    uint64_t zm = word << 1 | (w > 0 ? col[w - 1] >> 63 : 0);
    uint64_t zp = word >> 1 | (w + 1 < wpc ? col[w + 1] << 63 : 0); /* tail bits are 0 */
    do {
        unsigned b = (unsigned)__builtin_ctzll(hit);
        hit &= hit - 1;
        unsigned nb = (unsigned)(xm >> b & 1) * NB_XM | (unsigned)(xp >> b & 1) * NB_XP |
                      (unsigned)(ym >> b & 1) * NB_YM | (unsigned)(yp >> b & 1) * NB_YP |
                      (unsigned)(zm >> b & 1) * NB_ZM | (unsigned)(zp >> b & 1) * NB_ZP;
        size_t p = pix_base + (w * 64 + b) * pix_stride;
        pre->depth[p] = step;
        pre->code[p] = bvox__code(nb, step, cue);
    } while (hit);
}

static void notyet_init(uint64_t *notyet, const bvox_volume *v)
{
    for (size_t w = 0; w < v->wpc; w++) notyet[w] = ~0ull;
    notyet[v->wpc - 1] = v->tail_mask;
}

/* ------------------------------------------------------------------ +-x */

static void cast_x_rows(void *arg, int64_t y0, int64_t y1)
{
    const cast_ctx *c = arg;
    const bvox_volume *v = c->v;
    const size_t wpc = v->wpc;
    uint64_t notyet[(BVOX_MAX_DIM + 63) / 64];
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        notyet_init(notyet, v);
        int64_t remaining = v->nz;
        for (int32_t s = 0; s < v->nx && remaining > 0; s++) {
            int32_t x = c->dir > 0 ? s : v->nx - 1 - s;
            const uint64_t *col = bvox__column_c(v, x, y);
            for (size_t w = 0; w < wpc; w++) {
                uint64_t hit = col[w] & notyet[w];
                if (!hit) continue;
                notyet[w] &= ~hit;
                remaining -= bvox__popcount64(hit);
                /* pixel (column y, row z) */
                record_hits(v, col, x, y, w, hit, s, c->pre, (size_t)y, (size_t)v->ny, &c->cue);
            }
        }
    }
}

/* ------------------------------------------------------------------ +-y */

static void cast_y_cols(void *arg, int64_t x0, int64_t x1)
{
    const cast_ctx *c = arg;
    const bvox_volume *v = c->v;
    const size_t wpc = v->wpc;
    uint64_t *notyet = c->notyet + (size_t)x0 * wpc;
    for (int64_t x = x0; x < x1; x++) notyet_init(notyet + (size_t)(x - x0) * wpc, v);
    int64_t remaining = (x1 - x0) * (int64_t)v->nz;
    for (int32_t s = 0; s < v->ny && remaining > 0; s++) {
        int32_t y = c->dir > 0 ? s : v->ny - 1 - s;
        for (int32_t x = (int32_t)x0; x < (int32_t)x1; x++) {
            const uint64_t *col = bvox__column_c(v, x, y);
            uint64_t *ny_ = notyet + (size_t)(x - x0) * wpc;
            for (size_t w = 0; w < wpc; w++) {
                uint64_t hit = col[w] & ny_[w];
                if (!hit) continue;
                ny_[w] &= ~hit;
                remaining -= bvox__popcount64(hit);
                /* pixel (column x, row z) */
                record_hits(v, col, x, y, w, hit, s, c->pre, (size_t)x, (size_t)v->nx, &c->cue);
            }
        }
    }
}

/* ------------------------------------------------------------------ entry */

bvox_status bvox_cast_axis(const bvox_volume *vol, bvox_view view, bvox_preimage **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "cast: no volume");
    if ((unsigned)view >= 6u) return bvox__fail(BVOX_EINVAL, "cast: unknown view %d", (int)view);
    bvox__clear_error();
    const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
    const int32_t n[3] = {vol->nx, vol->ny, vol->nz};
    /* image axes: the two other axes in increasing order */
    const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
    bvox_preimage *pre;
    bvox_status st = bvox__preimage_alloc(n[cu], n[cv], &pre);
    if (st) return st;
    const double *sp = vol->geom.spacing;
    pre->depth_range = n[axis];
    pre->depth_step = sp[axis];
    pre->pixel_size[0] = sp[cu];
    pre->pixel_size[1] = sp[cv];
    memcpy(pre->spacing, sp, sizeof pre->spacing);
    memset(pre->eye, 0, sizeof pre->eye);
    pre->eye[0 + cu] = 1;
    pre->eye[3 + cv] = 1;
    pre->eye[6 + axis] = dir;
    memset(pre->origin, 0, sizeof pre->origin);
    if (dir < 0) pre->origin[axis] = (double)(n[axis] - 1) * sp[axis];

    cast_ctx c = {vol, pre, dir, {{0}}, NULL};
    bvox__cue_init(&c.cue, n[axis]);
    if (axis == 2) {
        bvox__parallel_for(vol->ny, 16, cast_z_rows, &c);
    } else if (axis == 0) {
        bvox__parallel_for(vol->ny, 16, cast_x_rows, &c);
    } else {
        size_t bytes = (size_t)vol->nx * vol->wpc * sizeof(uint64_t);
        c.notyet = bvox__alloc(bytes, false, "cast masks", &st);
        if (!c.notyet) {
            bvox_preimage_destroy(pre);
            return st;
        }
        bvox__parallel_for(vol->nx, 64, cast_y_cols, &c);
        bvox__free(c.notyet, bytes);
    }
    bvox__render_count_cast();
    *out = pre;
    return BVOX_OK;
}
