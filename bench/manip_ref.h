/*
 * manip_ref.h — deliberately naive byte-per-voxel references for
 * bench_manip.c: dilation by a list of offsets (a voxel is set if any offset
 * neighbour is; stops at the first hit, as a straightforward loop would),
 * 26-connected labelling (the classic two-pass union-find over voxels, 13
 * earlier neighbours each), the measures that have a one-line-per-voxel
 * definition (count, faces, first and second moments) and a plane cut. One
 * voxel at a time, sharing no code with src/; header-only because
 * bench/CMakeLists.txt makes one executable per bench_*.c.
 */
#ifndef BVOX_BENCH_MANIP_REF_H
#define BVOX_BENCH_MANIP_REF_H

#include "ref/voxref.h"

#include <stdint.h>
#include <stdlib.h>

typedef struct ref_offset {
    int dx, dy, dz;
} ref_offset;

/* The 27 offsets of the 3x3x3 box, or those of a ball of radius r voxels
 * (dx^2 + dy^2 + dz^2 <= r^2); returns how many (out holds 4096). */
static int ref_offsets(int box, double r, ref_offset *out)
{
    int n = 0, R = box ? 1 : (int)r;
    for (int dz = -R; dz <= R; dz++)
        for (int dy = -R; dy <= R; dy++)
            for (int dx = -R; dx <= R; dx++)
                if (box || dx * dx + dy * dy + dz * dz <= r * r)
                    out[n++] = (ref_offset){dx, dy, dz};
    return n;
}

static void ref_dilate(const voxref *in, const ref_offset *offs, int noffs, voxref *out)
{
    for (int z = 0; z < in->nz; z++)
        for (int y = 0; y < in->ny; y++)
            for (int x = 0; x < in->nx; x++) {
                uint8_t v = 0;
                for (int i = 0; i < noffs && !v; i++)
                    v = (uint8_t)voxref_get(in, x + offs[i].dx, y + offs[i].dy, z + offs[i].dz);
                *voxref_at(out, x, y, z) = v;
            }
}

static int32_t ref_find(int32_t *p, int32_t i)
{
    while (p[i] != i) {
        p[i] = p[p[i]];
        i = p[i];
    }
    return i;
}

/* Number of 26-connected components; parent holds nx*ny*nz entries. */
static int64_t ref_label26(const voxref *r, int32_t *parent)
{
    const int nx = r->nx, ny = r->ny, nz = r->nz;
    int64_t n = 0;
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                int32_t i = (int32_t)(((int64_t)z * ny + y) * nx + x);
                if (!r->v[i]) {
                    parent[i] = -1;
                    continue;
                }
                parent[i] = i;
                n++;
                /* the 13 neighbours that come earlier in x-fastest order */
                for (int dz = -1; dz <= 0; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                            int xx = x + dx, yy = y + dy, zz = z + dz;
                            if (xx < 0 || yy < 0 || zz < 0 || xx >= nx || yy >= ny) continue;
                            int32_t j = (int32_t)(((int64_t)zz * ny + yy) * nx + xx);
                            if (!r->v[j]) continue;
                            int32_t a = ref_find(parent, i), b = ref_find(parent, j);
                            if (a == b) continue;
                            if (a < b) parent[b] = a;
                            else parent[a] = b;
                            n--;
                        }
            }
    return n;
}

typedef struct ref_measures {
    int64_t count, faces[3];
    double centroid[3], covariance[9];
} ref_measures;

static void ref_measure(const voxref *r, ref_measures *m)
{
    double s[3] = {0, 0, 0}, ss[9] = {0};
    *m = (ref_measures){0};
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++) {
                if (!*voxref_at(r, x, y, z)) continue;
                const double p[3] = {x, y, z};
                m->count++;
                m->faces[0] += !voxref_get(r, x - 1, y, z) + !voxref_get(r, x + 1, y, z);
                m->faces[1] += !voxref_get(r, x, y - 1, z) + !voxref_get(r, x, y + 1, z);
                m->faces[2] += !voxref_get(r, x, y, z - 1) + !voxref_get(r, x, y, z + 1);
                for (int a = 0; a < 3; a++) {
                    s[a] += p[a];
                    for (int b = 0; b < 3; b++) ss[a * 3 + b] += p[a] * p[b];
                }
            }
    if (!m->count) return;
    double c = (double)m->count;
    for (int a = 0; a < 3; a++) m->centroid[a] = s[a] / c;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            m->covariance[a * 3 + b] = ss[a * 3 + b] / c - m->centroid[a] * m->centroid[b];
}

/* Clear the voxels whose centre (index space) has a*x + b*y + c*z + d < 0. */
static void ref_cut_plane(voxref *r, double a, double b, double c, double d)
{
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                if (a * x + b * y + c * z + d < 0) *voxref_at(r, x, y, z) = 0;
}

#endif
