/* voxref.c — see voxref.h: the slow, obvious reference. */
#include "voxref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

voxref *voxref_create(int nx, int ny, int nz)
{
    voxref *r = malloc(sizeof *r);
    if (!r) return NULL;
    r->nx = nx;
    r->ny = ny;
    r->nz = nz;
    r->v = calloc((size_t)nx * ny * nz, 1);
    if (!r->v) {
        free(r);
        return NULL;
    }
    return r;
}

void voxref_destroy(voxref *r)
{
    if (!r) return;
    free(r->v);
    free(r);
}

voxref *voxref_copy(const voxref *r)
{
    voxref *c = voxref_create(r->nx, r->ny, r->nz);
    if (c) memcpy(c->v, r->v, (size_t)r->nx * r->ny * r->nz);
    return c;
}

int voxref_get(const voxref *r, int x, int y, int z)
{
    if (x < 0 || y < 0 || z < 0 || x >= r->nx || y >= r->ny || z >= r->nz) return 0;
    return *voxref_at(r, x, y, z);
}

void voxref_random(voxref *r, unsigned num, unsigned den, uint64_t (*rand64)(void))
{
    size_t n = (size_t)r->nx * r->ny * r->nz;
    for (size_t i = 0; i < n; i++) r->v[i] = (rand64() % den) < num;
}

int64_t voxref_count(const voxref *r)
{
    size_t n = (size_t)r->nx * r->ny * r->nz;
    int64_t c = 0;
    for (size_t i = 0; i < n; i++) c += r->v[i];
    return c;
}

void voxref_csg(voxref *dst, bvox_csg_op op, const voxref *src, const int offset[3])
{
    for (int z = 0; z < dst->nz; z++)
        for (int y = 0; y < dst->ny; y++)
            for (int x = 0; x < dst->nx; x++) {
                int sx = x - offset[0], sy = y - offset[1], sz = z - offset[2];
                int inside = sx >= 0 && sy >= 0 && sz >= 0 && sx < src->nx && sy < src->ny &&
                             sz < src->nz;
                int s = inside ? *voxref_at(src, sx, sy, sz) : 0;
                uint8_t *d = voxref_at(dst, x, y, z);
                switch (op) {
                case BVOX_CSG_UNION: *d = *d | s; break;
                case BVOX_CSG_INTERSECTION: *d = *d & s; break;
                case BVOX_CSG_DIFFERENCE: *d = *d & !s; break;
                case BVOX_CSG_XOR: *d = *d ^ s; break;
                case BVOX_CSG_REPLACE: if (inside) *d = (uint8_t)s; break;
                }
            }
}

void voxref_complement(voxref *r)
{
    size_t n = (size_t)r->nx * r->ny * r->nz;
    for (size_t i = 0; i < n; i++) r->v[i] = !r->v[i];
}

void voxref_fill_box(voxref *r, bvox_box b, int value)
{
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                if (x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1 && z >= b.z0 && z < b.z1)
                    *voxref_at(r, x, y, z) = value != 0;
}

voxref *voxref_crop(const voxref *r, bvox_box b)
{
    voxref *c = voxref_create(b.x1 - b.x0, b.y1 - b.y0, b.z1 - b.z0);
    if (!c) return NULL;
    for (int z = 0; z < c->nz; z++)
        for (int y = 0; y < c->ny; y++)
            for (int x = 0; x < c->nx; x++)
                *voxref_at(c, x, y, z) = *voxref_at(r, x + b.x0, y + b.y0, z + b.z0);
    return c;
}

voxref *voxref_pad(const voxref *r, const int before[3], const int after[3])
{
    voxref *p = voxref_create(r->nx + before[0] + after[0], r->ny + before[1] + after[1],
                              r->nz + before[2] + after[2]);
    if (!p) return NULL;
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                *voxref_at(p, x + before[0], y + before[1], z + before[2]) = *voxref_at(r, x, y, z);
    return p;
}

int voxref_bbox(const voxref *r, bvox_box *b)
{
    int found = 0;
    memset(b, 0, sizeof *b);
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++) {
                if (!*voxref_at(r, x, y, z)) continue;
                if (!found) {
                    *b = (bvox_box){x, y, z, x + 1, y + 1, z + 1};
                    found = 1;
                    continue;
                }
                if (x < b->x0) b->x0 = x;
                if (y < b->y0) b->y0 = y;
                if (z < b->z0) b->z0 = z;
                if (x + 1 > b->x1) b->x1 = x + 1;
                if (y + 1 > b->y1) b->y1 = y + 1;
                if (z + 1 > b->z1) b->z1 = z + 1;
            }
    return found;
}

bvox_volume *voxref_to_volume(const voxref *r)
{
    bvox_volume *v = NULL;
    bvox_dims d = {r->nx, r->ny, r->nz};
    if (bvox_volume_create(d, &v) != BVOX_OK) return NULL;
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                if (*voxref_at(r, x, y, z)) bvox_volume_set(v, x, y, z, 1);
    return v;
}

voxref *voxref_from_volume(const bvox_volume *v)
{
    bvox_dims d = bvox_volume_dims(v);
    voxref *r = voxref_create(d.nx, d.ny, d.nz);
    if (!r) return NULL;
    for (int z = 0; z < d.nz; z++)
        for (int y = 0; y < d.ny; y++)
            for (int x = 0; x < d.nx; x++) *voxref_at(r, x, y, z) = (uint8_t)bvox_volume_get(v, x, y, z);
    return r;
}

int voxref_matches(const voxref *r, const bvox_volume *v)
{
    bvox_dims d = bvox_volume_dims(v);
    if (d.nx != r->nx || d.ny != r->ny || d.nz != r->nz) {
        fprintf(stderr, "dims differ: ref %dx%dx%d, volume %dx%dx%d\n", r->nx, r->ny, r->nz,
                d.nx, d.ny, d.nz);
        return 0;
    }
    for (int z = 0; z < d.nz; z++)
        for (int y = 0; y < d.ny; y++)
            for (int x = 0; x < d.nx; x++)
                if (*voxref_at(r, x, y, z) != bvox_volume_get(v, x, y, z)) {
                    fprintf(stderr, "voxel (%d,%d,%d): ref %d, volume %d\n", x, y, z,
                            *voxref_at(r, x, y, z), bvox_volume_get(v, x, y, z));
                    return 0;
                }
    if (bvox_volume_check(v) != BVOX_OK) {
        fprintf(stderr, "invariant: %s\n", bvox_errmsg());
        return 0;
    }
    return 1;
}
