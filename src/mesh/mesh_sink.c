/*
 * mesh_sink.c — the streamed mesh writer (mesh_sink.h). The elements are
 * written by mesh_write.c's record writers, so a streamed file has the
 * bytes bvox_mesh_write gives for the same elements in the same order.
 *
 * Where the header needs counts that are known only at the end:
 *  - binary STL: the triangle count at byte 80, overwritten at the end;
 *  - OBJ: the first comment line (counts) is reserved at its widest and
 *    overwritten; vertices and faces follow each other piece by piece
 *    (a face refers only to vertices written before it);
 *  - PLY and OFF: the header is reserved the same way and the vertices go
 *    into the output as they come, but the faces must follow all vertices:
 *    they go to a second temporary file beside the output, appended at the
 *    end. Both temporary files are removed on any failure.
 */
#include "mesh/mesh_sink.h"

#include "mesh_private.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(BVOX__MESH_SINK_BYTES == 2 * BVOX__MESH_OUT_BLOCK, "the sink's two blocks");

struct bvox__mesh_sink {
    int kind, ascii;
    bvox__mesh_out out, faces; /* faces: PLY and OFF only */
    bool has_faces;
    int64_t nv, nt;
    size_t header_len; /* reserved (PLY, OBJ, OFF) */
};

static int widest_header(int kind, int ascii, size_t *len)
{
    char h[BVOX__MESH_HEADER_MAX];
    int n = bvox__mesh_header(h, sizeof h, kind, INT64_MAX, INT64_MAX, ascii, 0);
    *len = (size_t)n;
    return n;
}

/* The header for the counts now, padded to the reserved length. */
static void header_now(const bvox__mesh_sink *s, char *h, size_t size)
{
    int n = bvox__mesh_header(h, size, s->kind, s->nv, s->nt, s->ascii, 0);
    bvox__mesh_header(h, size, s->kind, s->nv, s->nt, s->ascii, s->header_len - (size_t)n);
}

bvox_status bvox__mesh_sink_open(const char *path, const char *format, int ascii,
                                 bvox__mesh_sink **out)
{
    *out = NULL;
    bvox__clear_error();
    int kind;
    bvox_status st = bvox__mesh_format_kind(path, format, &kind);
    if (st) return st;
    bvox__mesh_sink *s = bvox__mem_zalloc(1, sizeof *s);
    if (!s) return bvox__fail(BVOX_ENOMEM, "out of memory");
    s->kind = kind;
    s->ascii = kind == 3 ? 1 : kind == 2 ? 0 : ascii;
    st = bvox__mesh_out_open(&s->out, path);
    if (st) {
        free(s);
        return st;
    }
    if (kind == 0) {
        bvox__mesh_out_stl_header(&s->out, 0, s->ascii);
    } else {
        widest_header(kind, s->ascii, &s->header_len);
        char h[BVOX__MESH_HEADER_MAX];
        header_now(s, h, sizeof h);
        bvox__mesh_out_put(&s->out, h, s->header_len);
    }
    if (kind == 1 || kind == 3) {
        st = bvox__mesh_out_open(&s->faces, path);
        if (st) {
            bvox__mesh_out_close(&s->out, false);
            free(s);
            return st;
        }
        s->has_faces = true;
    }
    *out = s;
    return s->out.st;
}

bvox_status bvox__mesh_sink_vertex(bvox__mesh_sink *s, const double p[3])
{
    if (s->kind == 1 && s->nv > (int64_t)INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "%s: more than 2^31 vertices for PLY (write .obj)",
                          s->out.sink.name);
    s->nv++;
    if (s->kind == 1 || s->kind == 3) bvox__mesh_out_vertex(&s->out, p, s->ascii);
    else if (s->kind == 2) bvox__mesh_out_obj_vertex(&s->out, p);
    return s->out.st;
}

bvox_status bvox__mesh_sink_triangle(bvox__mesh_sink *s, const int64_t idx[3],
                                     const double *const p[3])
{
    if (s->kind == 0 && !s->ascii && s->nt >= (int64_t)UINT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "%s: too many triangles for STL", s->out.sink.name);
    s->nt++;
    switch (s->kind) {
    case 0: bvox__mesh_out_stl_triangle(&s->out, p, s->ascii); return s->out.st;
    case 2: bvox__mesh_out_obj_face(&s->out, idx[0], idx[1], idx[2]); return s->out.st;
    default: bvox__mesh_out_face(&s->faces, idx[0], idx[1], idx[2], s->ascii); return s->faces.st;
    }
}

/* Append the faces' temporary file to the output. */
static void append_faces(bvox__mesh_sink *s)
{
    bvox__mesh_out_flush(&s->faces);
    if (s->faces.st) {
        s->out.st = s->faces.st;
        return;
    }
    if (fflush(s->faces.sink.file) != 0) {
        s->out.st = bvox__fail(BVOX_EIO, "%s: write failed", s->faces.sink.name);
        return;
    }
    FILE *f = fopen(s->faces.sink.tmp_path, "rb");
    if (!f) {
        s->out.st = bvox__fail(BVOX_EIO, "%s: cannot read back the faces", s->faces.sink.name);
        return;
    }
    bvox__mesh_out_flush(&s->out);
    size_t k;
    while (!s->out.st && (k = fread(s->out.buf, 1, BVOX__MESH_OUT_BLOCK, f)) > 0) {
        s->out.n = k;
        bvox__mesh_out_flush(&s->out);
    }
    if (!s->out.st && ferror(f))
        s->out.st = bvox__fail(BVOX_EIO, "%s: cannot read back the faces", s->faces.sink.name);
    fclose(f);
}

bvox_status bvox__mesh_sink_close(bvox__mesh_sink *s, bool commit)
{
    if (!s) return BVOX_OK;
    bvox_status st = BVOX_OK;
    if (commit && !s->out.st) {
        if (s->has_faces) append_faces(s);
        if (s->kind == 0 && s->ascii) bvox__mesh_out_printf(&s->out, "endsolid bvox\n");
        bvox__mesh_out_flush(&s->out);
        if (!s->out.st && s->kind == 0 && !s->ascii) {
            uint8_t b[4] = {(uint8_t)s->nt, (uint8_t)(s->nt >> 8), (uint8_t)(s->nt >> 16),
                            (uint8_t)(s->nt >> 24)};
            s->out.st = bvox__sink_pwrite(&s->out.sink, 80, b, 4);
        } else if (!s->out.st && s->kind != 0) {
            char h[BVOX__MESH_HEADER_MAX];
            header_now(s, h, sizeof h);
            s->out.st = bvox__sink_pwrite(&s->out.sink, 0, h, s->header_len);
        }
    }
    if (s->has_faces) bvox__mesh_out_close(&s->faces, false);
    st = bvox__mesh_out_close(&s->out, commit);
    if (!commit && !st) st = BVOX_OK;
    free(s);
    return st;
}
