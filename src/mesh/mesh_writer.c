/*
 * mesh_writer.c — bvox_mesh_writer, the public face of the streamed mesh
 * sink (mesh_sink.c): pieces of a mesh, each with its own vertices, some of
 * them written by an earlier piece (the vertices on a seam between rows of
 * chunks), mapped to the file's numbering here.
 */
#include "mesh/mesh_sink.h"

#include <stdlib.h>

struct bvox_mesh_writer {
    bvox__mesh_sink *sink;
    int64_t nv, nt;
    bvox_status failed; /* the first failure: close(commit) refuses */
};

bvox_status bvox_mesh_writer_open(const char *path, const char *format, int ascii,
                                  bvox_mesh_writer **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_writer_open: NULL argument");
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "bvox_mesh_writer_open: NULL argument");
    bvox_mesh_writer *w = bvox__mem_zalloc(1, sizeof *w);
    if (!w) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bvox_status st = bvox__mesh_sink_open(path, format, ascii, &w->sink);
    if (st) {
        free(w);
        return st;
    }
    *out = w;
    return BVOX_OK;
}

static bvox_status add(bvox_mesh_writer *w, const double *v, int64_t nv, const int64_t *global,
                       const int32_t *tri, int64_t nt, int64_t *map)
{
    /* checked before anything is written: a bad piece leaves the file as it was */
    for (int64_t i = 0; global && i < nv; i++)
        if (global[i] < -1 || global[i] >= w->nv)
            return bvox__fail(BVOX_EINVAL, "bvox_mesh_writer_add: vertex %lld refers to %lld, "
                              "not written before", (long long)i, (long long)global[i]);
    for (int64_t i = 0; i < 3 * nt; i++)
        if (tri[i] < 0 || tri[i] >= nv)
            return bvox__fail(BVOX_EINVAL, "bvox_mesh_writer_add: triangle index out of range");
    bvox_status st = BVOX_OK;
    for (int64_t i = 0; !st && i < nv; i++) {
        map[i] = global ? global[i] : -1;
        if (map[i] >= 0) continue;
        st = bvox__mesh_sink_vertex(w->sink, v + 3 * i);
        map[i] = w->nv++;
    }
    for (int64_t k = 0; !st && k < nt; k++) {
        const int32_t *t = tri + 3 * k;
        const int64_t idx[3] = {map[t[0]], map[t[1]], map[t[2]]};
        const double *p[3] = {v + 3 * t[0], v + 3 * t[1], v + 3 * t[2]};
        st = bvox__mesh_sink_triangle(w->sink, idx, p);
        w->nt++;
    }
    return st;
}

bvox_status bvox_mesh_writer_add(bvox_mesh_writer *w, const double *vertices, int64_t nvertices,
                                 const int64_t *global, const int32_t *triangles,
                                 int64_t ntriangles)
{
    bvox__clear_error();
    if (!w || nvertices < 0 || ntriangles < 0 || (nvertices && !vertices) ||
        (ntriangles && !triangles))
        return bvox__fail(BVOX_EINVAL, "bvox_mesh_writer_add: NULL or negative argument");
    if (w->failed) return bvox__fail(w->failed, "bvox_mesh_writer_add: an earlier piece failed");
    size_t bytes = (size_t)(nvertices ? nvertices : 1) * sizeof(int64_t);
    bvox_status st;
    int64_t *map = bvox__alloc(bytes, false, "mesh writer's vertex map", &st);
    if (!map) return st;
    st = add(w, vertices, nvertices, global, triangles, ntriangles, map);
    bvox__free(map, bytes);
    if (st && st != BVOX_EINVAL) w->failed = st; /* something was written */
    return st;
}

void bvox_mesh_writer_counts(const bvox_mesh_writer *w, int64_t *nvertices, int64_t *ntriangles)
{
    if (nvertices) *nvertices = w ? w->nv : 0;
    if (ntriangles) *ntriangles = w ? w->nt : 0;
}

bvox_status bvox_mesh_writer_close(bvox_mesh_writer *w, int commit)
{
    bvox__clear_error();
    if (!w) return BVOX_OK;
    bool keep = commit && !w->failed;
    bvox_status st = bvox__mesh_sink_close(w->sink, keep);
    if (commit && w->failed)
        st = bvox__fail(w->failed, "bvox_mesh_writer_close: a piece failed; nothing written");
    free(w);
    return st;
}
