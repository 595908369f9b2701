/*
 * volume_box.c — whole-word box operations: fill or clear a box, crop, pad.
 * Along z a box becomes a bit mask per word, so each column costs
 * ceil(depth / 64) word operations, never one per voxel.
 */
#include "internal.h"

#include <string.h>

void bvox__column_fill(uint64_t *col, int32_t z0, int32_t z1, int value)
{
    if (z0 >= z1) return;
    int32_t w0 = z0 >> 6, w1 = (z1 - 1) >> 6;
    for (int32_t w = w0; w <= w1; w++) {
        unsigned lo = w == w0 ? (unsigned)(z0 & 63) : 0;
        unsigned hi = w == w1 ? (unsigned)(z1 - (w1 << 6)) : 64;
        uint64_t m = bvox__bit_range(lo, hi);
        col[w] = value ? (col[w] | m) : (col[w] & ~m);
    }
}

bvox_box bvox__box_clip(const bvox_volume *v, bvox_box b)
{
    if (b.x0 < 0) b.x0 = 0;
    if (b.y0 < 0) b.y0 = 0;
    if (b.z0 < 0) b.z0 = 0;
    if (b.x1 > v->nx) b.x1 = v->nx;
    if (b.y1 > v->ny) b.y1 = v->ny;
    if (b.z1 > v->nz) b.z1 = v->nz;
    return b;
}

static bool box_empty(bvox_box b) { return b.x0 >= b.x1 || b.y0 >= b.y1 || b.z0 >= b.z1; }

void bvox_volume_fill_box(bvox_volume *vol, bvox_box box, int value)
{
    box = bvox__box_clip(vol, box);
    if (box_empty(box)) return;
    for (int32_t y = box.y0; y < box.y1; y++)
        for (int32_t x = box.x0; x < box.x1; x++)
            bvox__column_fill(bvox__column(vol, x, y), box.z0, box.z1, value);
}

void bvox_volume_fill(bvox_volume *vol, int value)
{
    if (!value) {
        memset(vol->words, 0, vol->nwords * sizeof(uint64_t));
        return;
    }
    memset(vol->words, 0xff, vol->nwords * sizeof(uint64_t));
    if (vol->tail_mask != ~0ull)
        for (size_t c = vol->wpc - 1; c < vol->nwords; c += vol->wpc) vol->words[c] = vol->tail_mask;
}

/* dst column = bits [shift, shift + dst->nz) of the src column, shift may be
 * negative (padding before). The src tail bits are zero, so only the last
 * dst word needs masking. */
static void copy_column(uint64_t *dst, const bvox_volume *dv, const uint64_t *src,
                        const bvox_volume *sv, int64_t shift)
{
    for (size_t j = 0; j < dv->wpc; j++)
        dst[j] = bvox__extract_bits(src, sv->wpc, (int64_t)j * 64 + shift);
    dst[dv->wpc - 1] &= dv->tail_mask;
}

/* Move the origin by a voxel offset so that voxels keep their world position
 * (also used by the label splitter, labels_read.c, for its crops). */
void bvox__geometry_shift(bvox_geometry *g, double di, double dj, double dk)
{
    double d[3] = {di * g->spacing[0], dj * g->spacing[1], dk * g->spacing[2]};
    for (int r = 0; r < 3; r++)
        g->origin[r] += g->direction[r * 3 + 0] * d[0] + g->direction[r * 3 + 1] * d[1] +
                        g->direction[r * 3 + 2] * d[2];
}

bvox_status bvox_volume_crop(const bvox_volume *vol, bvox_box box, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    box = bvox__box_clip(vol, box);
    if (box_empty(box))
        return bvox__fail(BVOX_EINVAL, "crop box does not overlap the %ldx%ldx%ld volume",
                          (long)vol->nx, (long)vol->ny, (long)vol->nz);
    bvox_dims d = {box.x1 - box.x0, box.y1 - box.y0, box.z1 - box.z0};
    bvox_volume *c;
    bvox_status st = bvox__volume_create_uninit(d, &c);
    if (st) return st;
    for (int32_t y = 0; y < d.ny; y++)
        for (int32_t x = 0; x < d.nx; x++)
            copy_column(bvox__column(c, x, y), c, bvox__column_c(vol, x + box.x0, y + box.y0),
                        vol, box.z0);
    c->geom = vol->geom;
    bvox__geometry_shift(&c->geom, box.x0, box.y0, box.z0);
    *out = c;
    BVOX_CHECK_VOLUME(*out);
    return BVOX_OK;
}

bvox_status bvox_volume_pad(const bvox_volume *vol, const int32_t before[3],
                            const int32_t after[3], bvox_volume **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    for (int i = 0; i < 3; i++)
        if (before[i] < 0 || after[i] < 0 || before[i] > BVOX_MAX_DIM || after[i] > BVOX_MAX_DIM)
            return bvox__fail(BVOX_EINVAL, "padding must be between 0 and %d", BVOX_MAX_DIM);
    bvox_dims d = {vol->nx + before[0] + after[0], vol->ny + before[1] + after[1],
                   vol->nz + before[2] + after[2]};
    bvox_volume *p;
    bvox_status st = bvox_volume_create(d, &p);
    if (st) return st;
    for (int32_t y = 0; y < vol->ny; y++)
        for (int32_t x = 0; x < vol->nx; x++)
            copy_column(bvox__column(p, x + before[0], y + before[1]), p,
                        bvox__column_c(vol, x, y), vol, -(int64_t)before[2]);
    p->geom = vol->geom;
    bvox__geometry_shift(&p->geom, -before[0], -before[1], -before[2]);
    *out = p;
    BVOX_CHECK_VOLUME(*out);
    return BVOX_OK;
}
