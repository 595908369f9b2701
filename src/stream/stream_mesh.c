/*
 * stream_mesh.c — marching cubes by slabs, each slab's triangles handed on
 * (to a file, or to a mesh in memory) as soon as the slab is done.
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
 * space (spacing 1, origin 0) and moved into place.
 *
 * Welding. Within a slab the kept triangles use the slab mesh's own
 * vertices (one per crossed edge or loop centre, as in memory). The
 * triangles of the slab with core [z0, z1) have their vertices at index z
 * z0 - 1 .. z1 - 1, so two slabs share vertices only in the plane z1 - 1
 * (the "seam"): those vertices are kept in a table by position, the next
 * slab welds its vertices of that plane against it, and the table is then
 * forgotten. Memory: one slab's mesh and one seam, never the whole mesh.
 *
 * A slab whose mesh does not fit the budget (BVOX_ETOOBIG before anything
 * of it was handed on) is retried at half the depth, down to one slice.
 */
#include "stream/stream.h"

#include "mesh/mesh_sink.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the seam: vertex positions of one plane -> their global index ---- */

typedef struct seam_slot {
    double p[3];
    int64_t g1; /* global index + 1; 0 empty */
} seam_slot;

typedef struct seam {
    seam_slot *slot;
    size_t cap, n; /* cap a power of two, or 0 */
} seam;

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

static void seam_release(seam *s)
{
    if (s->slot) bvox__free(s->slot, s->cap * sizeof *s->slot);
    memset(s, 0, sizeof *s);
}

static void seam_clear(seam *s)
{
    if (s->slot) memset(s->slot, 0, s->cap * sizeof *s->slot);
    s->n = 0;
}

static size_t seam_find(const seam *s, const double p[3])
{
    size_t h = hash3(p) & (s->cap - 1);
    while (s->slot[h].g1) {
        const double *q = s->slot[h].p;
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) break;
        h = (h + 1) & (s->cap - 1);
    }
    return h;
}

/* The global index at p, or -1. */
static int64_t seam_get(const seam *s, const double p[3])
{
    return s->n ? s->slot[seam_find(s, p)].g1 - 1 : -1;
}

/* Room for n entries in all (so that seam_put does not allocate). */
static bvox_status seam_reserve(seam *s, size_t n)
{
    if ((n + 1) * 2 > s->cap) {
        size_t cap = s->cap ? s->cap : 1 << 12;
        while ((n + 1) * 2 > cap) cap *= 2;
        bvox_status st;
        seam_slot *slot = bvox__alloc(cap * sizeof *slot, true, "mesh seam", &st);
        if (!slot) return st;
        seam old = *s;
        s->slot = slot;
        s->cap = cap;
        for (size_t i = 0; i < old.cap; i++)
            if (old.slot[i].g1) s->slot[seam_find(s, old.slot[i].p)] = old.slot[i];
        seam_release(&old); /* s->n stays */
    }
    return BVOX_OK;
}

static bvox_status seam_put(seam *s, const double p[3], int64_t g)
{
    bvox_status st = seam_reserve(s, s->n + 1);
    if (st) return st;
    size_t h = seam_find(s, p);
    if (!s->slot[h].g1) {
        memcpy(s->slot[h].p, p, sizeof s->slot[h].p);
        s->slot[h].g1 = g + 1;
        s->n++;
    }
    return BVOX_OK;
}

/* ---- one slab ---- */

typedef struct run {
    const bvox__slab_source *src;
    const bvox__mesh_emit *emit;
    bvox__mesh_tally *tally; /* or NULL */
    seam below, above;       /* the seam at z0 - 1 (from the slab before), at z1 - 1 */
    int64_t nv;              /* vertices handed on */
} run;

/* Whether triangle k of part (read from slice r0) belongs to the core
 * [z0, z1) of a volume nz deep. */
static bool owned(const bvox_mesh *part, int64_t k, int32_t r0, int32_t z0, int32_t z1, int32_t nz)
{
    const int32_t *tri = &part->triangles[3 * k];
    double zs[3];
    for (int i = 0; i < 3; i++) zs[i] = part->vertices[3 * tri[i] + 2] + r0;
    double lo = fmin(zs[0], fmin(zs[1], zs[2])), hi = fmax(zs[0], fmax(zs[1], zs[2]));
    if (lo == hi && lo == floor(lo)) return lo >= z0 && lo < z1; /* flat in slice plane lo */
    double cell = floor(lo); /* the upper slice cell + 1 in the core */
    return (cell + 1 >= z0 && cell + 1 < z1) || (z1 == nz && cell == nz - 1);
}

/* Hand on the triangles of part that the core [z0, z1) owns; map: part
 * vertex -> global index (-1 not yet), part->nvertices long. */
static bvox_status hand_on(run *r, const bvox_mesh *part, int64_t *map, int32_t r0, int32_t z0,
                           int32_t z1)
{
    const int32_t nz = r->src->dims.nz;
    const bvox_geometry *g = &r->src->geom;
    bvox_status st = BVOX_OK;
    for (int64_t k = 0; !st && k < part->ntriangles; k++) {
        if (!owned(part, k, r0, z0, z1, nz)) continue;
        double q[3][3];
        const double *qp[3] = {q[0], q[1], q[2]};
        int64_t idx[3];
        bool top[3];
        for (int i = 0; i < 3 && !st; i++) {
            int32_t pi = part->triangles[3 * k + i];
            const double *p = &part->vertices[3 * pi];
            double zi = p[2] + r0;
            q[i][0] = g->origin[0] + p[0] * g->spacing[0];
            q[i][1] = g->origin[1] + p[1] * g->spacing[1];
            q[i][2] = g->origin[2] + zi * g->spacing[2];
            top[i] = z1 < nz && zi == z1 - 1;
            if (map[pi] < 0) {
                int64_t gi = z0 > 0 && zi == z0 - 1 ? seam_get(&r->below, q[i]) : -1;
                if (gi < 0) {
                    gi = r->nv++;
                    st = r->emit->vertex(r->emit->ctx, q[i]);
                    if (!st && r->tally) bvox__mesh_tally_vertex(r->tally, q[i]);
                    if (!st && top[i]) st = seam_put(&r->above, q[i], gi);
                }
                map[pi] = gi;
            }
            idx[i] = map[pi];
        }
        if (!st) st = r->emit->triangle(r->emit->ctx, idx, qp);
        if (!st && r->tally) st = bvox__mesh_tally_triangle(r->tally, idx, qp, top);
    }
    return st;
}

/* Room, before anything of the slab is handed on, for what handing it on
 * adds: its vertices in the seam plane z1 - 1 and the edges of its kept
 * triangles (not those of the caps the slab's mesh has where it is cut). */
static bvox_status reserve(run *r, const bvox_mesh *part, int32_t r0, int32_t z0, int32_t z1)
{
    const int32_t nz = r->src->dims.nz;
    /* the seam plane in the slab's z (none above the last slab) */
    const double top = z1 < nz ? z1 - 1 - r0 : -2;
    int64_t ntop = 0;
    for (int64_t i = 0; i < part->nvertices; i++) ntop += part->vertices[3 * i + 2] == top;
    bvox_status st = seam_reserve(&r->above, (size_t)ntop);
    if (st || !r->tally) return st;
    int64_t ncur = 0, ncarry = 0;
    for (int64_t k = 0; k < part->ntriangles; k++) {
        if (!owned(part, k, r0, z0, z1, nz)) continue;
        const int32_t *t = &part->triangles[3 * k];
        for (int i = 0; i < 3; i++) {
            bool both = part->vertices[3 * t[i] + 2] == top &&
                        part->vertices[3 * t[(i + 1) % 3] + 2] == top;
            ncarry += both;
            ncur += !both;
        }
    }
    return bvox__mesh_tally_reserve(r->tally, ncur, ncarry);
}

/* Mesh slices z0..z1-1's cells and hand them on. BVOX_ETOOBIG before
 * anything was handed on means: try a thinner slab. */
static bvox_status slab(run *r, int32_t z0, int32_t z1, bool *handed)
{
    const int32_t nz = r->src->dims.nz;
    int32_t r0 = z0 > 0 ? z0 - 1 : 0, r1 = z1 < nz ? z1 + 1 : nz;
    bvox_volume *v = NULL;
    bvox_mesh *part = NULL;
    *handed = false;
    bvox_status st = r->src->read(r->src, r0, r1, &v);
    if (!st) {
        bvox_geometry ig = bvox_geometry_default(); /* index space */
        st = bvox_volume_set_geometry(v, &ig);
    }
    bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
    if (!st) st = bvox_mesh_from_volume(v, &mo, &part);
    bvox_volume_destroy(v);
    size_t map_bytes = (size_t)(part && part->nvertices ? part->nvertices : 1) * sizeof(int64_t);
    int64_t *map = st ? NULL : bvox__alloc(map_bytes, false, "mesh vertex map", &st);
    if (!st) st = reserve(r, part, r0, z0, z1);
    if (!st) {
        memset(map, 0xff, map_bytes); /* -1 */
        *handed = true;
        st = hand_on(r, part, map, r0, z0, z1);
    }
    if (map) bvox__free(map, map_bytes);
    bvox_mesh_destroy(part);
    if (!st && r->tally) st = bvox__mesh_tally_slab_done(r->tally, z1 == nz);
    return st;
}

bvox_status bvox__stream_mesh_emit(const bvox__slab_source *src, const bvox__mesh_emit *emit,
                                   bvox__mesh_tally *tally)
{
    const int32_t nz = src->dims.nz;
    const bvox_geometry *g = &src->geom;
    for (int i = 0; i < 9; i++)
        if (g->direction[i] != (i % 4 == 0 ? 1.0 : 0.0))
            return bvox__fail(BVOX_EUNSUPPORTED, "%s: meshing by slabs needs the identity "
                              "direction", src->name);
    run r = {.src = src, .emit = emit, .tally = tally};
    int32_t align = src->chunk_z > 0 ? src->chunk_z : 1;
    int32_t t = bvox__stream_depth(src, 1, align, 4, emit->bytes);
    bvox_status st = BVOX_OK;
    for (int32_t z0 = 0; !st && z0 < nz;) {
        int32_t z1 = z0 + t < nz ? z0 + t : nz;
        bool handed;
        st = slab(&r, z0, z1, &handed);
        if (st == BVOX_ETOOBIG && !handed && t > 1) { /* thinner, aligned while it can be */
            t = t / 2 >= align ? t / 2 / align * align : t / 2;
            bvox__clear_error();
            st = BVOX_OK;
            continue;
        }
        seam tmp = r.below; /* the seam above becomes the one below */
        r.below = r.above;
        r.above = tmp;
        seam_clear(&r.above);
        z0 = z1;
    }
    seam_release(&r.below);
    seam_release(&r.above);
    return st;
}

/* ---- into a mesh in memory ---- */

static bvox_status mesh_vertex(void *ctx, const double p[3])
{
    bvox_mesh *m = ctx;
    if (m->nvertices >= INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "mesh: more than %d vertices", INT32_MAX);
    return bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
}

static bvox_status mesh_triangle(void *ctx, const int64_t idx[3], const double *const p[3])
{
    (void)p;
    return bvox_mesh_add_triangle(ctx, (int32_t)idx[0], (int32_t)idx[1], (int32_t)idx[2]);
}

bvox_status bvox__stream_mesh(const bvox__slab_source *src, bvox_mesh **out)
{
    *out = NULL;
    bvox_mesh *m = NULL;
    bvox_status st = bvox_mesh_create(&m);
    if (st) return st;
    bvox__mesh_emit e = {mesh_vertex, mesh_triangle, m, 0};
    st = bvox__stream_mesh_emit(src, &e, NULL);
    if (st) {
        bvox_mesh_destroy(m);
        return st;
    }
    *out = m;
    return BVOX_OK;
}

/* ---- into a file ---- */

static bvox_status file_vertex(void *ctx, const double p[3])
{
    return bvox__mesh_sink_vertex(ctx, p);
}

static bvox_status file_triangle(void *ctx, const int64_t idx[3], const double *const p[3])
{
    return bvox__mesh_sink_triangle(ctx, idx, p);
}

bvox_status bvox__stream_mesh_write(const bvox__slab_source *src, const char *path,
                                    const char *format, int ascii, bvox_mesh_info *info,
                                    bool edges)
{
    bvox__mesh_sink *sink = NULL;
    bvox_status st = bvox__mesh_sink_open(path, format, ascii, &sink);
    if (st) return st;
    bvox__mesh_tally *tally = NULL;
    if (info) st = bvox__mesh_tally_begin(src, edges, &tally);
    bvox__mesh_emit e = {file_vertex, file_triangle, sink, BVOX__MESH_SINK_BYTES};
    if (!st) st = bvox__stream_mesh_emit(src, &e, tally);
    if (!st && info) st = bvox__mesh_tally_finish(tally, info);
    bvox__mesh_tally_release(tally);
    bvox_status cst = bvox__mesh_sink_close(sink, !st);
    return st ? st : cst;
}
