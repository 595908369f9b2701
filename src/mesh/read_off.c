/*
 * read_off.c — Object File Format (Geomview, CGAL's data sets): "OFF" (or
 * COFF, NOFF, CNOFF: the extra per-vertex numbers are skipped), then
 * "nv nf ne", nv lines "x y z ...", nf lines "n i0 ... i(n-1) [colour]".
 * '#' starts a comment. The counts are checked against the file size
 * before anything is allocated (a vertex takes at least 6 bytes, a face 8).
 */
#include "mesh_private.h"

#include <stdlib.h>
#include <string.h>

bvox_status bvox__mesh_read_off(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    bvox__text t;
    bvox__text_init(&t, d, n, name);
    char tok[64];
    if (!bvox__text_token(&t, tok, sizeof tok, 0))
        return bvox__fail(BVOX_EFORMAT, "%s: empty file", name);
    size_t len = strlen(tok);
    if (len < 3 || len > 5 || strcmp(tok + len - 3, "OFF"))
        return bvox__fail(BVOX_EFORMAT, "%s: not an OFF file (it starts with '%s')", name,
                          tok[0] == 1 ? "(too long)" : tok);
    int64_t nv, nf, ne;
    bvox_status st = bvox__text_int(&t, 0, "vertex count", 0, INT32_MAX, &nv);
    if (!st) st = bvox__text_int(&t, 0, "face count", 0, INT32_MAX, &nf);
    if (!st) st = bvox__text_int(&t, 0, "edge count", 0, INT64_MAX, &ne);
    if (st) return st;
    size_t left = (size_t)(t.end - t.p);
    if ((uint64_t)nv * 6 > left || (uint64_t)nf * 8 > left ||
        (uint64_t)nv * 6 + (uint64_t)nf * 8 > left)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: %lld vertices and %lld faces cannot fit in %zu bytes (truncated "
                          "or corrupt counts)",
                          name, (long long)nv, (long long)nf, left);
    st = bvox__mesh_grow(m, nv, nf);
    bvox__text_next_line(&t);
    for (int64_t v = 0; v < nv && !st; v++) {
        double p[3];
        for (int k = 0; k < 3 && !st; k++) st = bvox__text_double(&t, k > 0, "coordinate", &p[k]);
        if (!st) st = bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
        bvox__text_next_line(&t);
    }
    int64_t small[16], *idx = small;
    int64_t cap = 16;
    for (int64_t f = 0; f < nf && !st; f++) {
        int64_t k;
        st = bvox__text_int(&t, 0, "face size", 3, 1 << 20, &k);
        if (st) break;
        int64_t line = t.line;
        if (k > cap) {
            if (idx != small) free(idx);
            idx = bvox__mem_alloc((size_t)k * sizeof *idx);
            cap = k;
            if (!idx) {
                idx = small;
                cap = 16;
                st = bvox__fail(BVOX_ENOMEM, "out of memory");
                break;
            }
        }
        for (int64_t i = 0; i < k && !st; i++)
            st = bvox__text_int(&t, 1, "vertex index", 0, nv - 1 < 0 ? 0 : nv - 1, &idx[i]);
        if (!st) st = bvox__mesh_add_polygon(m, idx, k, name, line);
        bvox__text_next_line(&t);
    }
    if (idx != small) free(idx);
    return st;
}
