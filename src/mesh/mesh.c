/*
 * mesh.c — the mesh container (budgeted growable arrays), its edge
 * structure (half-edges bucketed by their smaller vertex: boundary,
 * non-manifold and orientation counts, vertex adjacency for smoothing) and
 * the measures: signed volume from tetrahedra, area, bounding box.
 */
#include "mesh_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

void bvox__advise_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    /* Transparent huge pages for the 2 MiB-aligned inside of a large,
     * freshly allocated buffer: one fault per 2 MiB instead of 512. Only a
     * hint (ignored where THP is off). */
    const uintptr_t huge = (uintptr_t)2 << 20;
    if (bytes < 2 * huge) return;
    uintptr_t a = ((uintptr_t)p + huge - 1) & ~(huge - 1);
    uintptr_t b = ((uintptr_t)p + bytes) & ~(huge - 1);
    if (b > a) (void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

bvox_status bvox__buf_reserve(bvox__buf *b, size_t bytes, const char *what)
{
    if (bytes <= b->cap) return BVOX_OK;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < bytes) {
        if (cap > SIZE_MAX / 2) return bvox__fail(BVOX_ETOOBIG, "the %s is too large", what);
        cap *= 2;
    }
    bvox_status st;
    void *p = bvox__alloc(cap, false, what, &st);
    if (!p) return st;
    if (b->size) memcpy(p, b->data, b->size);
    if (b->data) bvox__free(b->data, b->cap);
    b->data = p;
    b->cap = cap;
    return BVOX_OK;
}

void bvox__buf_release(bvox__buf *b)
{
    if (b->data) bvox__free(b->data, b->cap);
    b->data = NULL;
    b->size = b->cap = 0;
}

int bvox__geometry_mirrored(const bvox_geometry *g)
{
    const double *d = g->direction;
    double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) +
                 d[2] * (d[3] * d[7] - d[4] * d[6]);
    return det < 0;
}

bvox_status bvox_mesh_create(bvox_mesh **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_create: out is NULL");
    *out = NULL;
    bvox_mesh *m = bvox__mem_zalloc(1, sizeof *m);
    if (!m) return bvox__fail(BVOX_ENOMEM, "out of memory (mesh)");
    *out = m;
    return BVOX_OK;
}

void bvox_mesh_destroy(bvox_mesh *m)
{
    if (!m) return;
    if (m->vertices) bvox__free(m->vertices, (size_t)m->vcap * 3 * sizeof(double));
    if (m->triangles) bvox__free(m->triangles, (size_t)m->tcap * 3 * sizeof(int32_t));
    free(m);
}

static bvox_status grow_array(void **arr, int64_t *cap, int64_t want, size_t elem, int64_t used,
                              const char *what)
{
    if (want <= *cap) return BVOX_OK;
    if (want > INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "a mesh of more than %d %s is not supported", INT32_MAX,
                          what);
    /* the first allocation exactly as asked (meshers know their sizes), then
     * doubling for appends */
    int64_t c = *cap ? *cap : want;
    while (c < want) c = c * 2 > INT32_MAX ? INT32_MAX : c * 2;
    bvox_status st;
    void *p = bvox__alloc((size_t)c * elem, false, what, &st);
    if (!p) return st;
    bvox__advise_huge(p, (size_t)c * elem);
    if (used) memcpy(p, *arr, (size_t)used * elem);
    if (*arr) bvox__free(*arr, (size_t)*cap * elem);
    *arr = p;
    *cap = c;
    return BVOX_OK;
}

bvox_status bvox__mesh_grow(bvox_mesh *m, int64_t nv, int64_t nt)
{
    bvox_status st = grow_array((void **)&m->vertices, &m->vcap, nv, 3 * sizeof(double),
                                m->nvertices, "mesh vertices");
    if (st) return st;
    return grow_array((void **)&m->triangles, &m->tcap, nt, 3 * sizeof(int32_t), m->ntriangles,
                      "mesh triangles");
}

bvox_status bvox_mesh_reserve(bvox_mesh *m, int64_t nv, int64_t nt)
{
    if (!m || nv < 0 || nt < 0) return bvox__fail(BVOX_EINVAL, "bvox_mesh_reserve: bad argument");
    return bvox__mesh_grow(m, nv, nt);
}

bvox_status bvox_mesh_add_vertex(bvox_mesh *m, double x, double y, double z)
{
    if (!m) return bvox__fail(BVOX_EINVAL, "bvox_mesh_add_vertex: mesh is NULL");
    if (!isfinite(x) || !isfinite(y) || !isfinite(z))
        return bvox__fail(BVOX_EINVAL, "vertex coordinates must be finite");
    /* Measures multiply up to four coordinate differences (areas square a
     * cross product): beyond this they would overflow to inf or NaN. */
    double far = fmax(fabs(x), fmax(fabs(y), fabs(z)));
    if (far > BVOX_MESH_COORD_MAX)
        return bvox__fail(BVOX_EINVAL,
                          "vertex %lld has a coordinate of %g, beyond the supported range "
                          "(-%g..%g)",
                          (long long)m->nvertices + 1, far == fabs(x) ? x : far == fabs(y) ? y : z,
                          BVOX_MESH_COORD_MAX, BVOX_MESH_COORD_MAX);
    if (m->nvertices == m->vcap) {
        bvox_status st = bvox__mesh_grow(m, m->nvertices + 1, m->ntriangles);
        if (st) return st;
    }
    double *p = m->vertices + 3 * m->nvertices++;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return BVOX_OK;
}

bvox_status bvox_mesh_add_triangle(bvox_mesh *m, int32_t a, int32_t b, int32_t c)
{
    if (!m) return bvox__fail(BVOX_EINVAL, "bvox_mesh_add_triangle: mesh is NULL");
    if (a < 0 || b < 0 || c < 0 || a >= m->nvertices || b >= m->nvertices || c >= m->nvertices)
        return bvox__fail(BVOX_EINVAL, "triangle index out of range (%lld vertices)",
                          (long long)m->nvertices);
    if (m->ntriangles == m->tcap) {
        bvox_status st = bvox__mesh_grow(m, m->nvertices, m->ntriangles + 1);
        if (st) return st;
    }
    int32_t *t = m->triangles + 3 * m->ntriangles++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    return BVOX_OK;
}

/* Polygons of up to this many corners are fans from their first corner (the
 * usual reading of OBJ/OFF/PLY faces, kept for the common quads). */
#define FAN_MAX 16

bvox_status bvox__mesh_add_polygon(bvox_mesh *m, const int64_t *idx, int64_t n, const char *name,
                                   int64_t line)
{
    if (n < 3)
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: a face needs at least 3 vertices",
                          name, (long long)line);
    for (int64_t i = 0; i < n; i++)
        if (idx[i] < 0 || idx[i] >= m->nvertices)
            return bvox__fail(BVOX_EFORMAT,
                              "%s: line %lld: vertex index %lld out of range (%lld vertices)",
                              name, (long long)line, (long long)idx[i],
                              (long long)m->nvertices);
    if (m->ntriangles + n - 2 > m->tcap) {
        int64_t want = m->ntriangles + n - 2;
        bvox_status st = bvox__mesh_grow(m, m->nvertices, want);
        if (st) return st;
    }
    if (n <= FAN_MAX) {
        for (int64_t i = 1; i + 1 < n; i++) {
            int32_t *t = m->triangles + 3 * m->ntriangles++;
            t[0] = (int32_t)idx[0];
            t[1] = (int32_t)idx[i];
            t[2] = (int32_t)idx[i + 1];
        }
        return BVOX_OK;
    }
    /* Long polygons: corners 0..n-1 split by halving. Each chain a..b (the
     * chord b-a closes it) gives triangle (a, mid, b) and the chains a..mid
     * and mid..b. No corner is in more than about 2 log2(n) triangles, and
     * on a convex face the triangles of one depth together span the face
     * once, so the work that follows (edge tables, rays, the shell's
     * triangle-box tests) grows like n log n, not like n times the face as
     * with a fan of n slivers. An explicit stack: depth is at most log2(n). */
    int64_t stack[2 * 64], top = 0;
    stack[top++] = 0;
    stack[top++] = n - 1;
    while (top > 0) {
        int64_t b = stack[--top], a = stack[--top];
        if (b - a < 2) continue;
        int64_t mid = a + (b - a) / 2;
        int32_t *t = m->triangles + 3 * m->ntriangles++;
        t[0] = (int32_t)idx[a];
        t[1] = (int32_t)idx[mid];
        t[2] = (int32_t)idx[b];
        stack[top++] = mid; /* pushed second: a..mid is done first */
        stack[top++] = b;
        stack[top++] = a;
        stack[top++] = mid;
    }
    return BVOX_OK;
}

/* ---- edges: half-edges bucketed by their smaller vertex ---- */

typedef struct half {
    int32_t hi;
    int32_t fwd; /* 1: traversed lo -> hi */
} half;

static int half_cmp(const void *a, const void *b)
{
    const half *x = a, *y = b;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->fwd - y->fwd;
}

typedef struct buckets {
    int64_t *start; /* nv + 1 */
    half *h;        /* 3 * nt */
    size_t start_bytes, h_bytes;
} buckets;

static void buckets_release(buckets *b)
{
    if (b->start) bvox__free(b->start, b->start_bytes);
    if (b->h) bvox__free(b->h, b->h_bytes);
    memset(b, 0, sizeof *b);
}

static bvox_status buckets_build(const bvox_mesh *m, buckets *b)
{
    memset(b, 0, sizeof *b);
    bvox_status st;
    b->start_bytes = (size_t)(m->nvertices + 1) * sizeof(int64_t);
    b->h_bytes = (size_t)m->ntriangles * 3 * sizeof(half) + 1;
    b->start = bvox__alloc(b->start_bytes, true, "mesh edge table", &st);
    if (!b->start) return st;
    b->h = bvox__alloc(b->h_bytes, false, "mesh edge table", &st);
    if (!b->h) {
        buckets_release(b);
        return st;
    }
    const int32_t *t = m->triangles;
    for (int64_t i = 0; i < 3 * m->ntriangles; i++) {
        int32_t a = t[i], c = t[(i % 3 == 2) ? i - 2 : i + 1];
        b->start[(a < c ? a : c) + 1]++;
    }
    for (int64_t v = 0; v < m->nvertices; v++) b->start[v + 1] += b->start[v];
    /* fill using start[v] as a cursor, then shift back */
    for (int64_t i = 0; i < 3 * m->ntriangles; i++) {
        int32_t a = t[i], c = t[(i % 3 == 2) ? i - 2 : i + 1];
        int32_t lo = a < c ? a : c, hi = a < c ? c : a;
        b->h[b->start[lo]++] = (half){hi, a < c};
    }
    for (int64_t v = m->nvertices; v > 0; v--) b->start[v] = b->start[v - 1];
    b->start[0] = 0;
    for (int64_t v = 0; v < m->nvertices; v++) {
        int64_t s = b->start[v], e = b->start[v + 1];
        if (e - s > 24) {
            qsort(b->h + s, (size_t)(e - s), sizeof(half), half_cmp);
            continue;
        }
        for (int64_t i = s + 1; i < e; i++) { /* insertion sort: buckets are small */
            half x = b->h[i];
            int64_t j = i;
            while (j > s && half_cmp(&b->h[j - 1], &x) > 0) {
                b->h[j] = b->h[j - 1];
                j--;
            }
            b->h[j] = x;
        }
    }
    return BVOX_OK;
}

bvox_status bvox__mesh_edge_stats(const bvox_mesh *m, int64_t *edges, int64_t *boundary,
                                  int64_t *nonmanifold, int64_t *inconsistent)
{
    buckets b;
    bvox_status st = buckets_build(m, &b);
    if (st) return st;
    int64_t ne = 0, nb = 0, nn = 0, ni = 0;
    for (int64_t v = 0; v < m->nvertices; v++) {
        int64_t s = b.start[v], e = b.start[v + 1];
        while (s < e) {
            int64_t r = s + 1;
            while (r < e && b.h[r].hi == b.h[s].hi) r++;
            int64_t k = r - s;
            ne++;
            if (k == 1) nb++;
            else if (k > 2) nn++;
            else if (b.h[s].fwd == b.h[s + 1].fwd) ni++;
            s = r;
        }
    }
    buckets_release(&b);
    *edges = ne;
    *boundary = nb;
    *nonmanifold = nn;
    *inconsistent = ni;
    return BVOX_OK;
}

bvox_status bvox__mesh_adjacency(const bvox_mesh *m, bvox__adjacency *a)
{
    memset(a, 0, sizeof *a);
    buckets b;
    bvox_status st = buckets_build(m, &b);
    if (st) return st;
    a->start_bytes = (size_t)(m->nvertices + 1) * sizeof(int64_t);
    a->start = bvox__alloc(a->start_bytes, true, "mesh adjacency", &st);
    int64_t ne = 0;
    if (a->start) {
        for (int64_t v = 0; v < m->nvertices; v++)
            for (int64_t i = b.start[v]; i < b.start[v + 1]; i++) {
                if (i > b.start[v] && b.h[i].hi == b.h[i - 1].hi) continue;
                if (b.h[i].hi == v) continue; /* degenerate */
                a->start[v + 1]++;
                a->start[b.h[i].hi + 1]++;
                ne++;
            }
        a->adj_bytes = (size_t)(2 * ne + 1) * sizeof(int32_t);
        a->adj = bvox__alloc(a->adj_bytes, false, "mesh adjacency", &st);
    }
    if (!a->start || !a->adj) {
        buckets_release(&b);
        bvox__adjacency_release(a);
        return st;
    }
    for (int64_t v = 0; v < m->nvertices; v++) a->start[v + 1] += a->start[v];
    /* fill with start[v] as the cursor, then shift back */
    for (int64_t v = 0; v < m->nvertices; v++)
        for (int64_t i = b.start[v]; i < b.start[v + 1]; i++) {
            if (i > b.start[v] && b.h[i].hi == b.h[i - 1].hi) continue;
            int32_t w = b.h[i].hi;
            if (w == v) continue;
            a->adj[a->start[v]++] = w;
            a->adj[a->start[w]++] = (int32_t)v;
        }
    for (int64_t v = m->nvertices; v > 0; v--) a->start[v] = a->start[v - 1];
    a->start[0] = 0;
    buckets_release(&b);
    a->nedges = ne;
    return BVOX_OK;
}

void bvox__adjacency_release(bvox__adjacency *a)
{
    if (a->start) bvox__free(a->start, a->start_bytes);
    if (a->adj) bvox__free(a->adj, a->adj_bytes);
    memset(a, 0, sizeof *a);
}

/* ---- measures ---- */

bvox_status bvox_mesh_measure(const bvox_mesh *m, bvox_mesh_info *info)
{
    bvox__clear_error();
    if (!m || !info) return bvox__fail(BVOX_EINVAL, "bvox_mesh_measure: NULL argument");
    memset(info, 0, sizeof *info);
    info->vertices = m->nvertices;
    info->triangles = m->ntriangles;
    const double *v = m->vertices;
    if (m->nvertices > 0) {
        for (int k = 0; k < 3; k++) info->bbox_min[k] = info->bbox_max[k] = v[k];
        for (int64_t i = 1; i < m->nvertices; i++)
            for (int k = 0; k < 3; k++) {
                double c = v[3 * i + k];
                if (c < info->bbox_min[k]) info->bbox_min[k] = c;
                if (c > info->bbox_max[k]) info->bbox_max[k] = c;
            }
    }
    /* tetrahedra from the bbox centre: less cancellation than from (0,0,0) */
    double o[3];
    for (int k = 0; k < 3; k++) o[k] = 0.5 * (info->bbox_min[k] + info->bbox_max[k]);
    double vol = 0, area = 0;
    int64_t degenerate = 0;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2]) degenerate++;
        const double *a = v + 3 * tr[0], *b = v + 3 * tr[1], *c = v + 3 * tr[2];
        double ax = a[0] - o[0], ay = a[1] - o[1], az = a[2] - o[2];
        double bx = b[0] - o[0], by = b[1] - o[1], bz = b[2] - o[2];
        double cx = c[0] - o[0], cy = c[1] - o[1], cz = c[2] - o[2];
        vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        double ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
        double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
        area += 0.5 * sqrt(nx * nx + ny * ny + nz * nz);
    }
    if (!isfinite(vol) || !isfinite(area))
        return bvox__fail(BVOX_EINVAL, "the mesh is too large to measure (its volume or area "
                                       "overflows)");
    info->volume = vol / 6.0;
    info->area = area;
    info->degenerate_triangles = degenerate;
    bvox_status st = bvox__mesh_edge_stats(m, &info->edges, &info->boundary_edges,
                                           &info->nonmanifold_edges, &info->inconsistent_edges);
    if (st) return st;
    info->watertight = m->ntriangles > 0 && info->boundary_edges == 0 &&
                       info->nonmanifold_edges == 0 && degenerate == 0;
    return BVOX_OK;
}
