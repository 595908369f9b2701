/*
 * mesh_write.c — mesh writers: STL (binary, or ASCII), PLY (binary little
 * endian, or ASCII; double coordinates so a round trip is exact), OBJ and
 * OFF (text, %.17g). Written through a bvox__sink (temporary file, fsync,
 * rename) in 1 MiB blocks; a failure leaves no partial file.
 */
#include "io/io.h"
#include "mesh_private.h"

#include <stdarg.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define BLOCK BVOX__MESH_OUT_BLOCK
typedef bvox__mesh_out out;

static void flush(out *o)
{
    if (o->n && !o->st) o->st = bvox__sink_write(&o->sink, o->buf, o->n);
    o->n = 0;
}

void bvox__mesh_out_put(out *o, const void *p, size_t n)
{
    if (o->n + n > BLOCK) flush(o);
    memcpy(o->buf + o->n, p, n);
    o->n += n;
}
#define put bvox__mesh_out_put

void bvox__mesh_out_printf(out *o, const char *fmt, ...)
{
    if (o->n + 256 > BLOCK) flush(o);
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(o->buf + o->n, BLOCK - o->n, fmt, ap);
    va_end(ap);
    if (k > 0) o->n += (size_t)k;
}
#define putf bvox__mesh_out_printf

void bvox__mesh_out_le32(out *o, uint32_t v)
{
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    put(o, b, 4);
}
#define put_le32 bvox__mesh_out_le32
static void put_f32(out *o, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_le32(o, u);
}
void bvox__mesh_out_f64(out *o, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put_le32(o, (uint32_t)u);
    put_le32(o, (uint32_t)(u >> 32));
}
#define put_f64 bvox__mesh_out_f64

bvox_status bvox__mesh_out_open(out *o, const char *path)
{
    memset(o, 0, sizeof *o);
    bvox_status st;
    o->buf = bvox__alloc(BLOCK, false, "mesh output buffer", &st);
    if (!o->buf) return st;
    st = bvox__sink_open(path, 0, &o->sink);
    if (st) {
        bvox__free(o->buf, BLOCK);
        o->buf = NULL;
    }
    return st;
}

bvox_status bvox__mesh_out_close(out *o, bool commit)
{
    flush(o);
    bvox__free(o->buf, BLOCK);
    o->buf = NULL;
    if (o->st || !commit) {
        bvox__sink_abort(&o->sink);
        return o->st;
    }
    return bvox__sink_commit(&o->sink);
}

static void normal(const bvox_mesh *m, int64_t t, double n[3])
{
    const double *a = m->vertices + 3 * m->triangles[3 * t],
                 *b = m->vertices + 3 * m->triangles[3 * t + 1],
                 *c = m->vertices + 3 * m->triangles[3 * t + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) n[k] = l > 0 ? n[k] / l : 0;
}

static void write_stl(out *o, const bvox_mesh *m, int ascii)
{
    if (ascii) {
        putf(o, "solid bvox\n");
        for (int64_t t = 0; t < m->ntriangles; t++) {
            double n[3];
            normal(m, t, n);
            putf(o, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n[0], n[1], n[2]);
            for (int k = 0; k < 3; k++) {
                const double *p = m->vertices + 3 * m->triangles[3 * t + k];
                putf(o, "      vertex %.9g %.9g %.9g\n", (double)(float)p[0], (double)(float)p[1],
                     (double)(float)p[2]);
            }
            putf(o, "    endloop\n  endfacet\n");
        }
        putf(o, "endsolid bvox\n");
        return;
    }
    char header[80];
    memset(header, 0, sizeof header);
    snprintf(header, sizeof header, "binary STL written by bvox %s", bvox_version());
    put(o, header, 80);
    put_le32(o, (uint32_t)m->ntriangles);
    for (int64_t t = 0; t < m->ntriangles; t++) {
        double n[3];
        normal(m, t, n);
        for (int k = 0; k < 3; k++) put_f32(o, (float)n[k]);
        for (int k = 0; k < 3; k++) {
            const double *p = m->vertices + 3 * m->triangles[3 * t + k];
            for (int j = 0; j < 3; j++) put_f32(o, (float)p[j]);
        }
        uint8_t attr[2] = {0, 0};
        put(o, attr, 2);
    }
}

static void write_ply(out *o, const bvox_mesh *m, int ascii)
{
    putf(o,
         "ply\nformat %s 1.0\ncomment written by bvox %s\nelement vertex %lld\n"
         "property double x\nproperty double y\nproperty double z\nelement face %lld\n"
         "property list uchar int vertex_indices\nend_header\n",
         ascii ? "ascii" : "binary_little_endian", bvox_version(), (long long)m->nvertices,
         (long long)m->ntriangles);
    for (int64_t v = 0; v < m->nvertices; v++) {
        const double *p = m->vertices + 3 * v;
        if (ascii) putf(o, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
        else
            for (int k = 0; k < 3; k++) put_f64(o, p[k]);
    }
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        if (ascii) {
            putf(o, "3 %d %d %d\n", tr[0], tr[1], tr[2]);
        } else {
            uint8_t three = 3;
            put(o, &three, 1);
            for (int k = 0; k < 3; k++) put_le32(o, (uint32_t)tr[k]);
        }
    }
}

static void write_obj(out *o, const bvox_mesh *m)
{
    putf(o, "# written by bvox %s: %lld vertices, %lld triangles\n", bvox_version(),
         (long long)m->nvertices, (long long)m->ntriangles);
    for (int64_t v = 0; v < m->nvertices; v++) {
        const double *p = m->vertices + 3 * v;
        putf(o, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        putf(o, "f %lld %lld %lld\n", (long long)tr[0] + 1, (long long)tr[1] + 1,
             (long long)tr[2] + 1);
    }
}

static void write_off(out *o, const bvox_mesh *m)
{
    putf(o, "OFF\n%lld %lld 0\n", (long long)m->nvertices, (long long)m->ntriangles);
    for (int64_t v = 0; v < m->nvertices; v++) {
        const double *p = m->vertices + 3 * v;
        putf(o, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    }
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        putf(o, "3 %d %d %d\n", tr[0], tr[1], tr[2]);
    }
}

const char *bvox_mesh_format_for_path(const char *path)
{
    if (!path) return NULL;
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return NULL;
    static const char *const names[] = {"stl", "ply", "obj", "off"};
    for (int i = 0; i < 4; i++)
        if (!strcasecmp(dot + 1, names[i])) return names[i];
    return NULL;
}

typedef struct position {
    double p[3];
} position;

static int cmp_position(const void *a, const void *b)
{
    const double *p = ((const position *)a)->p, *q = ((const position *)b)->p;
    for (int k = 0; k < 3; k++)
        if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}

/* Vertices at exactly the position of another vertex (a cuberille mesh
 * keeps two where cubes touch only along an edge, which keeps it manifold).
 * STL stores triangles, not vertices: every reader welds by position, and
 * these become non-manifold. -1 when the count could not be made. */
static int64_t shared_positions(const bvox_mesh *m)
{
    if (m->nvertices < 2) return 0;
    position *v = bvox__mem_alloc((size_t)m->nvertices * sizeof *v);
    if (!v) return -1;
    memcpy(v, m->vertices, (size_t)m->nvertices * sizeof *v);
    qsort(v, (size_t)m->nvertices, sizeof *v, cmp_position);
    int64_t n = 0;
    for (int64_t i = 1; i < m->nvertices; i++) n += cmp_position(&v[i - 1], &v[i]) == 0;
    free(v);
    return n;
}

bvox_status bvox_mesh_write(const char *path, const bvox_mesh *m, const char *format, int ascii)
{
    BVOX_CHECK_MESH(m);
    bvox__clear_error();
    if (!path || !m) return bvox__fail(BVOX_EINVAL, "bvox_mesh_write: NULL argument");
    const char *f = format ? format : bvox_mesh_format_for_path(path);
    if (!f)
        return bvox__fail(BVOX_EINVAL,
                          "%s: cannot tell the mesh format from the name (use .stl, .ply, "
                          ".obj or .off)",
                          path);
    int kind = !strcmp(f, "stl") ? 0 : !strcmp(f, "ply") ? 1 : !strcmp(f, "obj") ? 2
             : !strcmp(f, "off") ? 3 : -1;
    if (kind < 0)
        return bvox__fail(BVOX_EINVAL, "unknown mesh format '%s' (stl, ply, obj, off)", f);
    if (kind == 0 && m->ntriangles > UINT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "%s: too many triangles for STL", path);
    for (int64_t i = 0; i < 3 * m->ntriangles; i++)
        if (m->triangles[i] < 0 || m->triangles[i] >= m->nvertices)
            return bvox__fail(BVOX_EINVAL, "bvox_mesh_write: triangle index out of range");
    if (kind == 0) {
        int64_t shared = shared_positions(m);
        if (shared > 0)
            bvox__warn("%s: %lld vertices share their position with another (as a cuberille mesh "
                       "has where cubes touch along an edge); STL keeps no vertices, so the mesh "
                       "is not manifold once welded: write .ply, .obj or .off to keep it",
                       path, (long long)shared);
    }
    out o;
    bvox_status st = bvox__mesh_out_open(&o, path);
    if (st) return st;
    switch (kind) {
    case 0: write_stl(&o, m, ascii); break;
    case 1: write_ply(&o, m, ascii); break;
    case 2: write_obj(&o, m); break;
    default: write_off(&o, m); break;
    }
    return bvox__mesh_out_close(&o, true);
}
