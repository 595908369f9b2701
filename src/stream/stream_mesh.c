/*
 * stream_mesh.c — marching cubes by slabs.
 *
 * A marching-cubes cell k (between the voxel slices k and k + 1, k from -1
 * to nz - 1 with the outside as background) depends only on its 8 corners,
 * so a slab that holds both slices computes it exactly. Each cell belongs to
 * one slab: the one whose core holds its upper slice (the last slab also
 * takes cell nz - 1). A triangle is attributed to its cell by its vertices'
 * z in voxel index space: the cell is floor(lowest z) unless the triangle
 * lies flat in a slice plane P, where cells P - 1 and P meet; such triangles
 * go to the slab whose core holds P, which reads one slice beyond its core on
 * each side so that both cells are exact there. Slabs are meshed in index
 * space (spacing 1, origin 0) and moved into place; vertices, each an edge
 * midpoint or a cell centre at a unique position, are welded by position so
 * that the triangles of two slabs share the seam's vertices as in memory.
 */
#include "stream/stream.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct weld {
    int64_t *slot;   /* vertex index + 1, 0 empty */
    size_t cap;      /* power of two */
    bvox_mesh *m;
} weld;

static uint64_t hash3(const double p[3])
{
    uint64_t h = 1469598103934665603ull, w;
    for (int a = 0; a < 3; a++) {
        double v = p[a] == 0 ? 0 : p[a]; /* -0 and 0 alike */
        memcpy(&w, &v, sizeof w);
        h = (h ^ w) * 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

static bvox_status weld_grow(weld *w)
{
    size_t cap = w->cap ? w->cap * 2 : 1 << 16;
    int64_t *s = bvox__mem_zalloc(cap, sizeof *s);
    if (!s) return bvox__fail(BVOX_ENOMEM, "out of memory welding the mesh");
    for (size_t i = 0; i < w->cap; i++) {
        if (!w->slot[i]) continue;
        size_t h = hash3(&w->m->vertices[3 * (w->slot[i] - 1)]) & (cap - 1);
        while (s[h]) h = (h + 1) & (cap - 1);
        s[h] = w->slot[i];
    }
    free(w->slot);
    w->slot = s;
    w->cap = cap;
    return BVOX_OK;
}

/* The index of the vertex at p, added when new. */
static bvox_status weld_vertex(weld *w, const double p[3], int32_t *idx)
{
    if ((size_t)(w->m->nvertices + 1) * 2 > w->cap) {
        bvox_status st = weld_grow(w);
        if (st) return st;
    }
    size_t h = hash3(p) & (w->cap - 1);
    while (w->slot[h]) {
        const double *q = &w->m->vertices[3 * (w->slot[h] - 1)];
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
            *idx = (int32_t)(w->slot[h] - 1);
            return BVOX_OK;
        }
        h = (h + 1) & (w->cap - 1);
    }
    if (w->m->nvertices >= INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "mesh: more than %d vertices", INT32_MAX);
    bvox_status st = bvox_mesh_add_vertex(w->m, p[0], p[1], p[2]);
    if (st) return st;
    *idx = (int32_t)(w->m->nvertices - 1);
    w->slot[h] = w->m->nvertices;
    return BVOX_OK;
}

bvox_status bvox__stream_mesh(const bvox__slab_source *src, bvox_mesh **out)
{
    *out = NULL;
    const int32_t nz = src->dims.nz;
    const bvox_geometry *g = &src->geom;
    for (int i = 0; i < 9; i++)
        if (g->direction[i] != (i % 4 == 0 ? 1.0 : 0.0))
            return bvox__fail(BVOX_EUNSUPPORTED, "%s: meshing by slabs needs the identity "
                              "direction", src->name);
    bvox_mesh *m = NULL;
    bvox_status st = bvox_mesh_create(&m);
    if (st) return st;
    weld w = {NULL, 0, m};
    int32_t t = bvox__stream_depth(src, 1, src->chunk_z, 4, 0);
    bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
    for (int32_t z0 = 0; !st && z0 < nz; z0 += t) {
        int32_t z1 = z0 + t < nz ? z0 + t : nz;
        int32_t r0 = z0 > 0 ? z0 - 1 : 0, r1 = z1 < nz ? z1 + 1 : nz;
        bvox_volume *slab = NULL;
        bvox_mesh *part = NULL;
        st = src->read(src, r0, r1, &slab);
        if (!st) {
            bvox_geometry ig = bvox_geometry_default(); /* index space */
            st = bvox_volume_set_geometry(slab, &ig);
        }
        if (!st) st = bvox_mesh_from_volume(slab, &mo, &part);
        bvox_volume_destroy(slab);
        for (int64_t k = 0; !st && k < part->ntriangles; k++) {
            const int32_t *tri = &part->triangles[3 * k];
            double zs[3];
            for (int i = 0; i < 3; i++) zs[i] = part->vertices[3 * tri[i] + 2] + r0;
            double lo = fmin(zs[0], fmin(zs[1], zs[2])), hi = fmax(zs[0], fmax(zs[1], zs[2]));
            bool keep;
            if (lo == hi && lo == floor(lo)) { /* flat in slice plane lo */
                keep = lo >= z0 && lo < z1;
            } else {
                double cell = floor(lo); /* the upper slice cell + 1 in the core */
                keep = (cell + 1 >= z0 && cell + 1 < z1) || (z1 == nz && cell == nz - 1);
            }
            if (!keep) continue;
            int32_t v[3];
            for (int i = 0; i < 3 && !st; i++) {
                const double *p = &part->vertices[3 * tri[i]];
                double q[3] = {g->origin[0] + p[0] * g->spacing[0],
                               g->origin[1] + p[1] * g->spacing[1],
                               g->origin[2] + (p[2] + r0) * g->spacing[2]};
                st = weld_vertex(&w, q, &v[i]);
            }
            if (!st) st = bvox_mesh_add_triangle(m, v[0], v[1], v[2]);
        }
        bvox_mesh_destroy(part);
    }
    free(w.slot);
    if (st) {
        bvox_mesh_destroy(m);
        return st;
    }
    *out = m;
    return BVOX_OK;
}
