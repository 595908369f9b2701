/*
 * surface.c — the boundary voxels of a volume (1-voxels with a 0 face
 * neighbour, the outside counting as 0), listed once so that any parallel
 * view can be cast by splatting them (cast_view.c) without touching the
 * volume again. The first voxel a ray meets always has a 0 neighbour on the
 * side the ray enters from, so nothing visible is lost.
 *
 * Built word-wise: per z-word, interior = v & (6 neighbour words) and
 * boundary = v & ~interior; a first pass counts per y row and neighbour
 * class (the 6 neighbour bits), a prefix sum gives each (class, row) its
 * place, a second pass writes the entries, so rows are independent and split
 * over the worker threads. Grouping by class lets a view skip the classes
 * that face away from it as whole ranges (back-face culling without a test
 * per voxel). Each entry packs
 * x, y, z (16 bits each: dimensions are at most 65535) and the 6 neighbour
 * bits (render.h's NB_*), from which the normal code and the per-view back
 * face cull follow. The bounding box comes from the counting pass too (each
 * row's x and z range of boundary voxels): every extreme 1-voxel is one.
 */
#include "render.h"

#include <stdlib.h>
#include <string.h>

typedef struct build_ctx {
    const bvox_volume *v;
    int64_t *at;       /* ny * 64: counts per row and class, then where each goes */
    int64_t *rowbox;   /* ny * 4: x and z range of each row's boundary (counting pass) */
    uint64_t *entries; /* NULL in the counting pass */
} build_ctx;

static void build_rows(void *arg, int64_t y0, int64_t y1)
{
    build_ctx *c = arg;
    const bvox_volume *v = c->v;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        int64_t *at = c->at + (size_t)y * 64;
        /* the bounding box comes from the boundary (every extreme 1-voxel is
         * on it), so the counting pass keeps each row's x and z range and no
         * separate scan of the volume is needed */
        int64_t *rb = c->rowbox + (size_t)y * 4;
        if (!c->entries) rb[0] = v->nx, rb[1] = -1, rb[2] = v->nz, rb[3] = -1;
        for (int32_t x = 0; x < v->nx; x++) {
            const uint64_t *col = bvox__column_c(v, x, y);
            for (size_t w = 0; w < v->wpc; w++) {
                if (!col[w]) continue;
                uint64_t nb[6];
                bvox__surface_neighbours(v, x, y, w, nb);
                uint64_t b = col[w] & ~(nb[0] & nb[1] & nb[2] & nb[3] & nb[4] & nb[5]);
                if (!c->entries && b) {
                    int64_t z0 = (int64_t)w * 64 + __builtin_ctzll(b);
                    int64_t z1 = (int64_t)w * 64 + 63 - __builtin_clzll(b);
                    if (x < rb[0]) rb[0] = x;
                    rb[1] = x;
                    if (z0 < rb[2]) rb[2] = z0;
                    if (z1 > rb[3]) rb[3] = z1;
                }
                while (b) {
                    unsigned k = (unsigned)__builtin_ctzll(b);
                    b &= b - 1;
                    uint64_t bits = bvox__surface_nb_bits(nb, k);
                    if (!c->entries) {
                        at[bits]++;
                        continue;
                    }
                    uint64_t z = w * 64 + k;
                    c->entries[at[bits]++] = (uint64_t)x | (uint64_t)y << 16 | z << 32 | bits << 48;
                }
            }
        }
    }
}

bvox_status bvox_surface_build(const bvox_volume *vol, bvox_surface **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "surface: no volume");
    bvox__clear_error();
    bvox_surface *s = bvox__mem_zalloc(1, sizeof *s);
    if (!s) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bvox_status st;
    size_t at_bytes = (size_t)vol->ny * (64 + 4) * sizeof(int64_t);
    int64_t *at = bvox__alloc(at_bytes, true, "surface rows", &st);
    if (!at) {
        free(s);
        return st;
    }
    build_ctx c = {vol, at, at + (size_t)vol->ny * 64, NULL};
    bvox__parallel_for(vol->ny, 8, build_rows, &c);
    /* the bounding box, as bvox_volume_bbox gives it (zero box if empty) */
    bvox_box bb = {vol->nx, vol->ny, vol->nz, -1, -1, -1};
    for (int32_t y = 0; y < vol->ny; y++) {
        const int64_t *rb = c.rowbox + (size_t)y * 4;
        if (rb[1] < 0) continue;
        if (y < bb.y0) bb.y0 = y;
        bb.y1 = y;
        if (rb[0] < bb.x0) bb.x0 = (int32_t)rb[0];
        if (rb[1] > bb.x1) bb.x1 = (int32_t)rb[1];
        if (rb[2] < bb.z0) bb.z0 = (int32_t)rb[2];
        if (rb[3] > bb.z1) bb.z1 = (int32_t)rb[3];
    }
    s->empty = bb.x1 < 0;
    s->bbox = s->empty ? (bvox_box){0, 0, 0, 0, 0, 0}
                       : (bvox_box){bb.x0, bb.y0, bb.z0, bb.x1 + 1, bb.y1 + 1, bb.z1 + 1};
    /* entries grouped by class, rows in order within a class */
    int64_t n = 0;
    for (int k = 0; k < 64; k++) {
        s->class_start[k] = n;
        for (int32_t y = 0; y < vol->ny; y++) {
            int64_t cnt = at[(size_t)y * 64 + (size_t)k];
            at[(size_t)y * 64 + (size_t)k] = n;
            n += cnt;
        }
    }
    s->class_start[64] = n;
    s->bytes = (size_t)(n ? n : 1) * sizeof(uint64_t);
    s->entries = bvox__alloc(s->bytes, false, "surface voxels", &st);
    if (!s->entries) {
        bvox__free(at, at_bytes);
        free(s);
        return st;
    }
    c.entries = s->entries;
    bvox__parallel_for(vol->ny, 8, build_rows, &c);
    bvox__free(at, at_bytes);
    s->count = n;
    s->dims = (bvox_dims){vol->nx, vol->ny, vol->nz};
    memcpy(s->spacing, vol->geom.spacing, sizeof s->spacing);
    *out = s;
    return BVOX_OK;
}

void bvox_surface_destroy(bvox_surface *surf)
{
    if (!surf) return;
    bvox__free(surf->entries, surf->bytes);
    free(surf);
}

int64_t bvox_surface_count(const bvox_surface *surf) { return surf ? surf->count : 0; }
