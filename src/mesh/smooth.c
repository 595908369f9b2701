/*
 * smooth.c — Taubin's lambda/mu smoothing (Taubin 1995): a Laplacian step
 * with lambda > 0 (shrinks) followed by one with mu < -lambda (inflates),
 * uniform weights over the shared-vertex adjacency. The pair is a low-pass
 * filter that removes the voxel staircase while keeping the enclosed volume
 * nearly unchanged. Vertices are updated in parallel from the previous
 * positions (Jacobi), so the result does not depend on the thread count.
 */
#include "mesh_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct sm {
    const bvox__adjacency *a;
    const double *src;
    double *dst;
    double f;
} sm;

static void step(void *ctx, int64_t begin, int64_t end)
{
    const sm *s = ctx;
    for (int64_t v = begin; v < end; v++) {
        int64_t b = s->a->start[v], e = s->a->start[v + 1];
        const double *p = s->src + 3 * v;
        double *q = s->dst + 3 * v;
        if (e == b) {
            q[0] = p[0];
            q[1] = p[1];
            q[2] = p[2];
            continue;
        }
        double sx = 0, sy = 0, sz = 0;
        for (int64_t i = b; i < e; i++) {
            const double *n = s->src + 3 * s->a->adj[i];
            sx += n[0];
            sy += n[1];
            sz += n[2];
        }
        double inv = 1.0 / (double)(e - b);
        q[0] = p[0] + s->f * (sx * inv - p[0]);
        q[1] = p[1] + s->f * (sy * inv - p[1]);
        q[2] = p[2] + s->f * (sz * inv - p[2]);
    }
}

bvox_status bvox_mesh_smooth(bvox_mesh *m, int iterations, double lambda, double mu)
{
    BVOX_CHECK_MESH(m);
    bvox__clear_error();
    if (!m) return bvox__fail(BVOX_EINVAL, "bvox_mesh_smooth: mesh is NULL");
    if (iterations < 0 || !isfinite(lambda) || !isfinite(mu) || lambda <= 0 || lambda >= 1 ||
        mu >= 0 || mu <= -1)
        return bvox__fail(BVOX_EINVAL,
                          "smoothing needs iterations >= 0, 0 < lambda < 1 and -1 < mu < 0");
    if (iterations == 0 || m->nvertices == 0) return BVOX_OK;
    bvox__adjacency a;
    bvox_status st = bvox__mesh_adjacency(m, &a);
    if (st) return st;
    size_t bytes = (size_t)m->nvertices * 3 * sizeof(double);
    double *tmp = bvox__alloc(bytes, false, "smoothing buffer", &st);
    if (!tmp) {
        bvox__adjacency_release(&a);
        return st;
    }
    sm s = {&a, m->vertices, tmp, lambda};
    for (int it = 0; it < iterations; it++) {
        s.src = m->vertices;
        s.dst = tmp;
        s.f = lambda;
        bvox__parallel_for(m->nvertices, 4096, step, &s);
        s.src = tmp;
        s.dst = m->vertices;
        s.f = mu;
        bvox__parallel_for(m->nvertices, 4096, step, &s);
        /* canceled: the vertices are half smoothed; the caller discards the mesh */
        if ((st = bvox__progress_steps(it + 1, iterations))) break;
    }
    bvox__free(tmp, bytes);
    if (st) {
        bvox__adjacency_release(&a);
        return st;
    }
    bvox__adjacency_release(&a);
    BVOX_CHECK_MESH(m);
    return BVOX_OK;
}
