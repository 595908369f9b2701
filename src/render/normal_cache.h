/*
 * normal_cache.h — the smooth normals' ball moments kept across frames
 * (bvox_normal_cache, normal_cache.c): a frame of the viewer's smooth mode
 * needs the moments of ~600 k voxels of a 512^3 sphere, and a turn of the
 * view shows mostly voxels an earlier frame already needed. Looking one up
 * here costs a load; computing it ~20 column fetches.
 *
 * One 64-bit word per voxel, so threads read and write it without locks
 * (relaxed atomics: a slot holds one whole entry or another, never half):
 *   bit 63: valid; bits 36..62: the tag; bits 0..35: the moment, three
 *   signed 12-bit fields (|m| <= 2047; a ball of radius 3 reaches ~250).
 * Direct-mapped by voxel: the voxel's 4 x 4 x 4 brick (its coordinates + 1,
 * packed, then mixed by a bijection of their bits) picks 64 consecutive
 * slots and the voxel's place in the brick one of them, so the 8 voxels
 * around a pixel's hit point share a cache line or two; the mixed key's bits
 * above the slot index are the tag, so (slot, tag) names one voxel exactly.
 */
#ifndef BVOX_RENDER_NORMAL_CACHE_H
#define BVOX_RENDER_NORMAL_CACHE_H

#include "render.h"

#include <stdatomic.h>

struct bvox_normal_cache {
    _Atomic uint64_t *slot;
    unsigned slot_bits;   /* 2^slot_bits slots (6 of them: the place in a brick) */
    size_t bytes;         /* of slot, for bvox__free */
    /* what the entries were made for; another volume shape or radius clears */
    int32_t nx, ny, nz;
    int radius;
    unsigned key_bits;    /* bits of a packed brick key */
    unsigned bx_bits, by_bits; /* of brick x and y in the packed key */
    int usable;           /* key fits the tag (else every lookup misses) */
};

enum { BVOX__NC_FIELD = 12, BVOX__NC_TAG_SHIFT = 36 };

/* The slot and the tagged word of voxel q (coordinates -1 .. n); 0 when the
 * cache cannot hold it. */
static inline uint64_t bvox__nc_key(const struct bvox_normal_cache *c, const int32_t q[3],
                                    size_t *slot)
{
    const uint64_t x = (uint64_t)(q[0] + 1), y = (uint64_t)(q[1] + 1), z = (uint64_t)(q[2] + 1);
    const unsigned kb = c->key_bits;
    const uint64_t mask = kb >= 64 ? ~0ull : (1ull << kb) - 1;
    uint64_t k = (x >> 2) | (y >> 2) << c->bx_bits | (z >> 2) << (c->bx_bits + c->by_bits);
    /* a bijection of kb bits: odd multipliers and xor-shifts */
    k = (k * 0x9E3779B97F4A7C15ull) & mask;
    k ^= k >> (kb / 2 + 1);
    k = (k * 0xC2B2AE3D27D4EB4Full) & mask;
    const unsigned bb = c->slot_bits - 6; /* brick slots */
    *slot = (size_t)((k & ((1ull << bb) - 1)) << 6 | (x & 3) | (y & 3) << 2 | (z & 3) << 4);
    return 1ull << 63 | (k >> bb) << BVOX__NC_TAG_SHIFT;
}

static inline int bvox__nc_get(const struct bvox_normal_cache *c, const int32_t q[3], int64_t m[3])
{
    if (!c->usable) return 0;
    size_t s;
    const uint64_t tag = bvox__nc_key(c, q, &s);
    const uint64_t e = atomic_load_explicit(&c->slot[s], memory_order_relaxed);
    if ((e & ~((1ull << BVOX__NC_TAG_SHIFT) - 1)) != tag) return 0;
    for (int a = 0; a < 3; a++) {
        int64_t v = (int64_t)(e >> (BVOX__NC_FIELD * a) & 0xfff);
        m[a] = v >= 2048 ? v - 4096 : v;
    }
    return 1;
}

static inline void bvox__nc_put(struct bvox_normal_cache *c, const int32_t q[3], const int64_t m[3])
{
    if (!c->usable) return;
    uint64_t e = 0;
    for (int a = 0; a < 3; a++) {
        if (m[a] < -2048 || m[a] > 2047) return;
        e |= ((uint64_t)m[a] & 0xfff) << (BVOX__NC_FIELD * a);
    }
    size_t s;
    e |= bvox__nc_key(c, q, &s);
    atomic_store_explicit(&c->slot[s], e, memory_order_relaxed);
}

/* Ready the cache for vol and radius (cleared when either changed). */
void bvox__normal_cache_bind(struct bvox_normal_cache *c, const bvox_volume *vol, int radius);

#endif
