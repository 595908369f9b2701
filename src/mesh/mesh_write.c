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

void bvox__mesh_out_flush(out *o)
{
    if (o->n && !o->st) o->st = bvox__sink_write(&o->sink, o->buf, o->n);
    o->n = 0;
}

void bvox__mesh_out_put(out *o, const void *p, size_t n)
{
    if (o->n + n > BLOCK) bvox__mesh_out_flush(o);
    memcpy(o->buf + o->n, p, n);
    o->n += n;
}
#define put bvox__mesh_out_put

void bvox__mesh_out_printf(out *o, const char *fmt, ...)
{
    if (o->n + 256 > BLOCK) bvox__mesh_out_flush(o);
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
    bvox__mesh_out_flush(o);
    bvox__free(o->buf, BLOCK);
    o->buf = NULL;
    if (o->st || !commit) {
        bvox__sink_abort(&o->sink);
        return o->st;
    }
    return bvox__sink_commit(&o->sink);
}

/* The unit normal of triangle a b c (zeros when degenerate). */
static void normal(const double *a, const double *b, const double *c, double n[3])
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) n[k] = l > 0 ? n[k] / l : 0;
}

/* ---- one element at a time: what the whole-mesh writers below and the
 * streamed writer (mesh_sink.c) both write ---- */

void bvox__mesh_out_stl_triangle(out *o, const double *const p[3], int ascii)
{
    double n[3];
    normal(p[0], p[1], p[2], n);
    if (ascii) {
        putf(o, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n[0], n[1], n[2]);
        for (int k = 0; k < 3; k++)
            putf(o, "      vertex %.9g %.9g %.9g\n", (double)(float)p[k][0],
                 (double)(float)p[k][1], (double)(float)p[k][2]);
        putf(o, "    endloop\n  endfacet\n");
        return;
    }
    for (int k = 0; k < 3; k++) put_f32(o, (float)n[k]);
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) put_f32(o, (float)p[k][j]);
    uint8_t attr[2] = {0, 0};
    put(o, attr, 2);
}

void bvox__mesh_out_stl_header(out *o, uint32_t ntriangles, int ascii)
{
    if (ascii) {
        putf(o, "solid bvox\n");
        return;
    }
    char header[80];
    memset(header, 0, sizeof header);
    snprintf(header, sizeof header, "binary STL written by bvox %s", bvox_version());
    put(o, header, 80);
    put_le32(o, ntriangles);
}

/* "x y z" of PLY (ASCII) and OFF, or PLY's three little-endian doubles. */
void bvox__mesh_out_vertex(out *o, const double *p, int ascii)
{
    if (ascii) putf(o, "%.17g %.17g %.17g\n", p[0], p[1], p[2]);
    else
        for (int k = 0; k < 3; k++) put_f64(o, p[k]);
}

/* "3 a b c" of PLY (ASCII) and OFF, or PLY's binary list of int. */
void bvox__mesh_out_face(out *o, int64_t a, int64_t b, int64_t c, int ascii)
{
    if (ascii) {
        putf(o, "3 %lld %lld %lld\n", (long long)a, (long long)b, (long long)c);
        return;
    }
    uint8_t three = 3;
    put(o, &three, 1);
    put_le32(o, (uint32_t)a);
    put_le32(o, (uint32_t)b);
    put_le32(o, (uint32_t)c);
}

int bvox__mesh_header(char *buf, size_t size, int kind, int64_t nv, int64_t nt, int ascii,
                      size_t pad)
{
    char sp[BVOX__MESH_HEADER_PAD + 1];
    if (pad > BVOX__MESH_HEADER_PAD) pad = BVOX__MESH_HEADER_PAD;
    memset(sp, ' ', pad);
    sp[pad] = 0;
    switch (kind) {
    case 1:
        return snprintf(buf, size,
                        "ply\nformat %s 1.0\ncomment written by bvox %s%s\nelement vertex %lld\n"
                        "property double x\nproperty double y\nproperty double z\n"
                        "element face %lld\nproperty list uchar int vertex_indices\nend_header\n",
                        ascii ? "ascii" : "binary_little_endian", bvox_version(), sp,
                        (long long)nv, (long long)nt);
    case 2:
        return snprintf(buf, size, "# written by bvox %s: %lld vertices, %lld triangles%s\n",
                        bvox_version(), (long long)nv, (long long)nt, sp);
    default:
        return snprintf(buf, size, "OFF\n%lld %lld 0%s\n", (long long)nv, (long long)nt, sp);
    }
}

static void put_header(out *o, int kind, const bvox_mesh *m, int ascii)
{
    char h[BVOX__MESH_HEADER_MAX];
    int n = bvox__mesh_header(h, sizeof h, kind, m->nvertices, m->ntriangles, ascii, 0);
    put(o, h, (size_t)n);
}

static void write_stl(out *o, const bvox_mesh *m, int ascii)
{
    bvox__mesh_out_stl_header(o, (uint32_t)m->ntriangles, ascii);
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++) p[k] = m->vertices + 3 * m->triangles[3 * t + k];
        bvox__mesh_out_stl_triangle(o, p, ascii);
    }
    if (ascii) putf(o, "endsolid bvox\n");
}

/* PLY (kind 1) and OFF (kind 3, always text): header, vertices, faces. */
static void write_ply_off(out *o, const bvox_mesh *m, int kind, int ascii)
{
    put_header(o, kind, m, ascii);
    for (int64_t v = 0; v < m->nvertices; v++) bvox__mesh_out_vertex(o, m->vertices + 3 * v, ascii);
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        bvox__mesh_out_face(o, tr[0], tr[1], tr[2], ascii);
    }
}

void bvox__mesh_out_obj_vertex(out *o, const double *p)
{
    putf(o, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
}

/* a, b, c 0-based */
void bvox__mesh_out_obj_face(out *o, int64_t a, int64_t b, int64_t c)
{
    putf(o, "f %lld %lld %lld\n", (long long)a + 1, (long long)b + 1, (long long)c + 1);
}

static void write_obj(out *o, const bvox_mesh *m)
{
    put_header(o, 2, m, 0);
    for (int64_t v = 0; v < m->nvertices; v++) bvox__mesh_out_obj_vertex(o, m->vertices + 3 * v);
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        bvox__mesh_out_obj_face(o, tr[0], tr[1], tr[2]);
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

bvox_status bvox__mesh_format_kind(const char *path, const char *format, int *kind)
{
    const char *f = format ? format : bvox_mesh_format_for_path(path);
    if (!f)
        return bvox__fail(BVOX_EINVAL,
                          "%s: cannot tell the mesh format from the name (use .stl, .ply, "
                          ".obj or .off)",
                          path);
    *kind = !strcmp(f, "stl") ? 0 : !strcmp(f, "ply") ? 1 : !strcmp(f, "obj") ? 2
             : !strcmp(f, "off") ? 3 : -1;
    if (*kind < 0)
        return bvox__fail(BVOX_EINVAL, "unknown mesh format '%s' (stl, ply, obj, off)", f);
    return BVOX_OK;
}

bvox_status bvox_mesh_write(const char *path, const bvox_mesh *m, const char *format, int ascii)
{
    BVOX_CHECK_MESH(m);
    bvox__clear_error();
    if (!path || !m) return bvox__fail(BVOX_EINVAL, "bvox_mesh_write: NULL argument");
    int kind;
    bvox_status st = bvox__mesh_format_kind(path, format, &kind);
    if (st) return st;
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
    st = bvox__mesh_out_open(&o, path);
    if (st) return st;
    switch (kind) {
    case 0: write_stl(&o, m, ascii); break;
    case 1: write_ply_off(&o, m, 1, ascii); break;
    case 2: write_obj(&o, m); break;
    default: write_ply_off(&o, m, 3, 1); break;
    }
    return bvox__mesh_out_close(&o, true);
}
