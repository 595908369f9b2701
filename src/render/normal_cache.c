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
