/*
 * normal_cache.c — bvox_normal_cache: the smooth normals' ball moments kept
 * across the frames of a view (layout and lookups in normal_cache.h). The
 * caller owns it and clears it when the volume's voxels change; a volume of
 * another shape or another radius clears it by itself.
 */
#include "normal_cache.h"

#include <stdlib.h>

static unsigned bits_of(uint64_t v)
{
    unsigned n = 1;
    while (v >>= 1) n++;
    return n;
}

bvox_status bvox_normal_cache_create(size_t entries, bvox_normal_cache **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "normal cache: no output");
    *out = NULL;
    if (entries == 0) entries = (size_t)1 << 22;
    unsigned b = 12;
    while (b < 26 && ((size_t)1 << b) < entries) b++;
    bvox_normal_cache *c = bvox__mem_zalloc(1, sizeof *c);
    if (!c) return bvox__fail(BVOX_ENOMEM, "normal cache: out of memory");
    bvox_status st = BVOX_OK;
    c->slot_bits = b;
    c->bytes = ((size_t)1 << b) * sizeof *c->slot;
    c->slot = bvox__alloc(c->bytes, true, "normal cache", &st);
    if (!c->slot) {
        free(c);
        return st;
    }
    c->radius = -1; /* bound to nothing yet */
    *out = c;
    return BVOX_OK;
}

void bvox_normal_cache_clear(bvox_normal_cache *c)
{
    if (!c) return;
    const size_t n = (size_t)1 << c->slot_bits;
    for (size_t i = 0; i < n; i++) atomic_store_explicit(&c->slot[i], 0, memory_order_relaxed);
}

/* The entries of a brick live in 64 consecutive slots that no other voxel of
 * that brick shares, so zeroing those slots forgets the brick (and perhaps a
 * colliding brick's entries: only a miss). Voxels are cached for coordinates
 * -1 .. n, and a voxel's moments read its ball of radius c->radius, so the
 * box grown by the radius, clamped to that range, holds every stale entry. */
void bvox_normal_cache_clear_box(bvox_normal_cache *c, const bvox_box *box)
{
    if (!c || !box || c->radius < 0 || !c->usable) return;
    const int32_t n[3] = {c->nx, c->ny, c->nz};
    const int32_t lo_in[3] = {box->x0, box->y0, box->z0}, hi_in[3] = {box->x1, box->y1, box->z1};
    int32_t blo[3], bhi[3]; /* brick ranges, inclusive */
    for (int a = 0; a < 3; a++) {
        if (hi_in[a] <= lo_in[a]) return;
        int64_t lo = (int64_t)lo_in[a] - c->radius, hi = (int64_t)hi_in[a] - 1 + c->radius;
        if (lo < -1) lo = -1;
        if (hi > n[a]) hi = n[a];
        if (hi < lo) return; /* entirely outside what the cache holds */
        blo[a] = (int32_t)((lo + 1) >> 2), bhi[a] = (int32_t)((hi + 1) >> 2);
    }
    for (int32_t bz = blo[2]; bz <= bhi[2]; bz++)
        for (int32_t by = blo[1]; by <= bhi[1]; by++)
            for (int32_t bx = blo[0]; bx <= bhi[0]; bx++) {
                /* the brick's first voxel (coordinates + 1 = 4 * brick) */
                const int32_t q[3] = {4 * bx - 1, 4 * by - 1, 4 * bz - 1};
                size_t s;
                (void)bvox__nc_key(c, q, &s);
                for (size_t i = 0; i < 64; i++)
                    atomic_store_explicit(&c->slot[s + i], 0, memory_order_relaxed);
            }
}

void bvox_normal_cache_destroy(bvox_normal_cache *c)
{
    if (!c) return;
    bvox__free((void *)c->slot, c->bytes);
    free(c);
}

void bvox__normal_cache_bind(bvox_normal_cache *c, const bvox_volume *vol, int radius)
{
    if (c->nx == vol->nx && c->ny == vol->ny && c->nz == vol->nz && c->radius == radius) return;
    bvox_normal_cache_clear(c);
    c->nx = vol->nx, c->ny = vol->ny, c->nz = vol->nz, c->radius = radius;
    /* voxel coordinates + 1 run 0 .. n + 1 (one beyond each side) */
    c->bx_bits = bits_of((uint64_t)(vol->nx + 1) >> 2);
    c->by_bits = bits_of((uint64_t)(vol->ny + 1) >> 2);
    c->key_bits = c->bx_bits + c->by_bits + bits_of((uint64_t)(vol->nz + 1) >> 2);
    /* the tag (key bits above the brick slots) must fit its 27 bits */
    c->usable = c->key_bits <= c->slot_bits - 6 + 27;
}
