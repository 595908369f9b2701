/*
 * read_obj.c — Wavefront OBJ: "v x y z [w]" vertices and "f" faces whose
 * corners are "i", "i/t", "i//n" or "i/t/n" (only the position index i is
 * used; negative i counts back from the last vertex read so far). Polygons
 * become triangles (bvox__mesh_add_polygon). vt, vn, g, o, s, usemtl, mtllib, l and comments
 * are ignored. Faces are checked once all vertices are known (an index may
 * refer to a vertex defined later).
 */
#include "mesh_private.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

bvox_status bvox__mesh_read_obj(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    bvox__text t;
    bvox__text_init(&t, d, n, name);
    /* faces as records: line, count, indices (all int64), checked at the end */
    bvox__buf faces = {0};
    bvox_status st = BVOX_OK;
    char tok[64];
    while (!st) {
        bvox__text_skip_ws(&t);
        if (t.p >= t.end) break;
        if (!bvox__text_token(&t, tok, sizeof tok, 1)) {
            bvox__text_next_line(&t);
            continue;
        }
        if (!strcmp(tok, "v")) {
            double p[3];
            for (int k = 0; k < 3 && !st; k++) st = bvox__text_double(&t, 1, "coordinate", &p[k]);
            if (!st) st = bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
        } else if (!strcmp(tok, "f")) {
            int64_t line = t.line;
            size_t at = faces.size;
            st = bvox__buf_reserve(&faces, at + 2 * sizeof(int64_t), "OBJ faces");
            if (st) break;
            faces.size += 2 * sizeof(int64_t);
            int64_t count = 0;
            while (!st && bvox__text_token(&t, tok, sizeof tok, 1)) {
                char *end;
                errno = 0;
                long long i = strtoll(tok, &end, 10);
                if (end == tok || (*end && *end != '/') || errno == ERANGE || i == 0) {
                    st = bvox__fail(BVOX_EFORMAT, "%s: line %lld: bad face index '%s'", name,
                                    (long long)line, tok[0] == 1 ? "(too long)" : tok);
                    break;
                }
                int64_t idx = i > 0 ? i - 1 : m->nvertices + i;
                if (idx < 0) {
                    st = bvox__fail(BVOX_EFORMAT,
                                    "%s: line %lld: face index %lld out of range (%lld vertices "
                                    "so far)",
                                    name, (long long)line, i, (long long)m->nvertices);
                    break;
                }
                st = bvox__buf_reserve(&faces, faces.size + sizeof(int64_t), "OBJ faces");
                if (st) break;
                memcpy((char *)faces.data + faces.size, &idx, sizeof idx);
                faces.size += sizeof(int64_t);
                count++;
            }
            if (st) break;
            int64_t head[2] = {line, count};
            memcpy((char *)faces.data + at, head, sizeof head);
            if (count < 3) {
                st = bvox__fail(BVOX_EFORMAT, "%s: line %lld: a face needs at least 3 vertices",
                                name, (long long)line);
                break;
            }
        }
        bvox__text_next_line(&t); /* the rest of the line (w, or an ignored record) */
    }
    const int64_t *f = faces.data;
    size_t nf = faces.size / sizeof(int64_t);
    /* every line of a non-OBJ file is an ignored record: say so, not "empty mesh" */
    if (!st && m->nvertices == 0 && nf == 0)
        st = bvox__fail(BVOX_EFORMAT, "%s: no vertices or faces found (not an OBJ file?)", name);
    for (size_t i = 0; i < nf && !st;) {
        int64_t line = f[i], count = f[i + 1];
        for (int64_t k = 0; k < count && !st; k++)
            if (f[i + 2 + k] >= m->nvertices)
                st = bvox__fail(BVOX_EFORMAT,
                                "%s: line %lld: face index %lld out of range (%lld vertices)",
                                name, (long long)line, (long long)f[i + 2 + k] + 1,
                                (long long)m->nvertices);
        if (!st) st = bvox__mesh_add_polygon(m, f + i + 2, count, name, line);
        i += 2 + (size_t)count;
    }
    bvox__buf_release(&faces);
    return st;
}
