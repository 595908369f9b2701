/*
 * stream_mesh_info.c — what bvox_mesh_measure says of a mesh, gathered
 * while the mesh streams past (stream_mesh.c) and is never held whole.
 *
 * Counts, bounding box, area and the degenerate triangles are sums or
 * extremes over the elements. The volume is the sum of signed tetrahedra
 * from a fixed point, the centre of the volume's box (bvox_mesh_measure
 * takes the mesh's bounding-box centre, unknown until the end): the same
 * volume but for rounding in the last digits.
 *
 * Edge counts: every undirected edge with its uses is sorted and counted
 * per slab, except the edges with both ends in the slab's top seam plane
 * (z1 - 1), which the next slab's triangles may also use: those half-edges
 * are carried into the next slab's count. No edge lies in two seams, so
 * each edge is counted once, with all its uses.
 */
#include "stream/stream.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct half_edge {
    int64_t lo;
    int64_t hi2; /* hi * 2 + (traversed lo -> hi) */
} half_edge;

typedef struct edges {
    half_edge *e;
    size_t n, cap;
} edges;

struct bvox__mesh_tally {
    bvox_mesh_info info;
    double o[3];
    double vol, area;
    bool want_edges;
    edges cur, carry; /* counted at the slab's end / carried to the next slab */
};

static void edges_release(edges *a)
{
    if (a->e) bvox__free(a->e, a->cap * sizeof *a->e);
    memset(a, 0, sizeof *a);
}

static bvox_status edges_grow(edges *a, size_t want, bool exact)
{
    if (want > a->cap) {
        size_t cap = a->cap ? a->cap : 1 << 12;
        while (cap < want) cap *= 2;
        if (exact) cap = want;
        bvox_status st;
        half_edge *e = bvox__alloc(cap * sizeof *e, false, "mesh edge tally", &st);
        if (!e) return st;
        if (a->n) memcpy(e, a->e, a->n * sizeof *e);
        size_t n = a->n;
        edges_release(a);
        a->e = e;
        a->n = n;
        a->cap = cap;
    }
    return BVOX_OK;
}

static bvox_status edges_push(edges *a, int64_t u, int64_t v)
{
    if (a->n == a->cap) {
        bvox_status st = edges_grow(a, a->n + 1, false);
        if (st) return st;
    }
    half_edge *h = &a->e[a->n++];
    h->lo = u < v ? u : v;
    h->hi2 = (u < v ? v : u) * 2 + (u < v);
    return BVOX_OK;
}

static int cmp_edge(const void *a, const void *b)
{
    const half_edge *p = a, *q = b;
    if (p->lo != q->lo) return p->lo < q->lo ? -1 : 1;
    int64_t x = p->hi2 >> 1, y = q->hi2 >> 1;
    return (x > y) - (x < y);
}

bvox_status bvox__mesh_tally_begin(const bvox__slab_source *src, bool want_edges,
                                   bvox__mesh_tally **out)
{
    *out = bvox__mem_zalloc(1, sizeof **out);
    if (!*out) return bvox__fail(BVOX_ENOMEM, "out of memory");
    (*out)->want_edges = want_edges;
    const int32_t n[3] = {src->dims.nx, src->dims.ny, src->dims.nz};
    for (int k = 0; k < 3; k++)
        (*out)->o[k] = src->geom.origin[k] + src->geom.spacing[k] * 0.5 * (double)n[k];
    return BVOX_OK;
}

void bvox__mesh_tally_vertex(bvox__mesh_tally *t, const double p[3])
{
    bvox_mesh_info *i = &t->info;
    for (int k = 0; k < 3; k++) {
        if (!i->vertices || p[k] < i->bbox_min[k]) i->bbox_min[k] = p[k];
        if (!i->vertices || p[k] > i->bbox_max[k]) i->bbox_max[k] = p[k];
    }
    i->vertices++;
}

bvox_status bvox__mesh_tally_triangle(bvox__mesh_tally *t, const int64_t idx[3],
                                      const double *const p[3], const bool top[3])
{
    t->info.triangles++;
    if (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2]) t->info.degenerate_triangles++;
    const double *o = t->o;
    double ax = p[0][0] - o[0], ay = p[0][1] - o[1], az = p[0][2] - o[2];
    double bx = p[1][0] - o[0], by = p[1][1] - o[1], bz = p[1][2] - o[2];
    double cx = p[2][0] - o[0], cy = p[2][1] - o[1], cz = p[2][2] - o[2];
    t->vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
    double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    t->area += 0.5 * sqrt(nx * nx + ny * ny + nz * nz);
    for (int k = 0; t->want_edges && k < 3; k++) {
        int l = (k + 1) % 3;
        edges *to = top[k] && top[l] ? &t->carry : &t->cur;
        bvox_status st = edges_push(to, idx[k], idx[l]);
        if (st) return st;
    }
    return BVOX_OK;
}

bvox_status bvox__mesh_tally_reserve(bvox__mesh_tally *t, int64_t ncur, int64_t ncarry)
{
    if (!t->want_edges) return BVOX_OK;
    bvox_status st = edges_grow(&t->cur, t->cur.n + (size_t)ncur, true);
    return st ? st : edges_grow(&t->carry, t->carry.n + (size_t)ncarry, true);
}

bvox_status bvox__mesh_tally_slab_done(bvox__mesh_tally *t, bool last)
{
    (void)last; /* the last slab carries nothing: no seam above it */
    edges *c = &t->cur;
    if (c->n) qsort(c->e, c->n, sizeof *c->e, cmp_edge);
    for (size_t s = 0; s < c->n;) {
        size_t r = s + 1;
        while (r < c->n && !cmp_edge(&c->e[r], &c->e[s])) r++;
        size_t k = r - s;
        t->info.edges++;
        if (k == 1) t->info.boundary_edges++;
        else if (k > 2) t->info.nonmanifold_edges++;
        else if ((c->e[s].hi2 & 1) == (c->e[s + 1].hi2 & 1)) t->info.inconsistent_edges++;
        s = r;
    }
    edges_release(&t->cur); /* the carried edges start the next slab's count */
    t->cur = t->carry;
    memset(&t->carry, 0, sizeof t->carry);
    return BVOX_OK;
}

bvox_status bvox__mesh_tally_finish(bvox__mesh_tally *t, bvox_mesh_info *info)
{
    if (!isfinite(t->vol) || !isfinite(t->area))
        return bvox__fail(BVOX_EINVAL, "the mesh is too large to measure (its volume or area "
                                       "overflows)");
    *info = t->info;
    info->volume = t->vol / 6.0;
    info->area = t->area;
    info->watertight = t->want_edges && info->triangles > 0 && info->boundary_edges == 0 &&
                       info->nonmanifold_edges == 0 && info->degenerate_triangles == 0;
    return BVOX_OK;
}

void bvox__mesh_tally_release(bvox__mesh_tally *t)
{
    if (!t) return;
    edges_release(&t->cur);
    edges_release(&t->carry);
    free(t);
}
