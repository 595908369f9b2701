/*
 * voxref.h — the slow byte-per-voxel reference model used by differential
 * tests and benchmarks. Deliberately naive: one byte per voxel, x fastest,
 * one voxel at a time, sharing no code with src/.
 */
#ifndef BVOX_VOXREF_H
#define BVOX_VOXREF_H

#include "bvox.h"

#include <stdint.h>

typedef struct voxref {
    int nx, ny, nz;
    uint8_t *v; /* v[(z * ny + y) * nx + x] is 0 or 1 */
} voxref;

voxref *voxref_create(int nx, int ny, int nz);
void voxref_destroy(voxref *r);
voxref *voxref_copy(const voxref *r);
static inline uint8_t *voxref_at(const voxref *r, int x, int y, int z)
{
    return &r->v[((size_t)z * (size_t)r->ny + (size_t)y) * (size_t)r->nx + (size_t)x];
}
int voxref_get(const voxref *r, int x, int y, int z); /* 0 outside */
/* Random fill with probability num/den of a 1 (rand: the harness's or any 64-bit rng). */
void voxref_random(voxref *r, unsigned num, unsigned den, uint64_t (*rand64)(void));
int64_t voxref_count(const voxref *r);
/* dst = dst OP src with src placed at offset (same semantics as bvox_csg_apply). */
void voxref_csg(voxref *dst, bvox_csg_op op, const voxref *src, const int offset[3]);
void voxref_complement(voxref *r);
void voxref_fill_box(voxref *r, bvox_box b, int value);
voxref *voxref_crop(const voxref *r, bvox_box b);        /* b already inside */
voxref *voxref_pad(const voxref *r, const int before[3], const int after[3]);
/* 1 and the tight box, or 0 if empty. */
int voxref_bbox(const voxref *r, bvox_box *b);

/* Conversions through the public per-voxel API only. */
bvox_volume *voxref_to_volume(const voxref *r);
voxref *voxref_from_volume(const bvox_volume *v);
/* 1 if identical (dims and voxels); prints the first difference otherwise. */
int voxref_matches(const voxref *r, const bvox_volume *v);

#endif
