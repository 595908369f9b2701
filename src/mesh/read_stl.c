/*
 * read_stl.c — STL, binary (80-byte header, uint32 count, 50 bytes per
 * triangle) or ASCII (solid / facet normal / outer loop / vertex x3 /
 * endloop / endfacet / endsolid). STL repeats every corner per triangle;
 * corners with exactly the same coordinates are welded into one vertex
 * (an open-addressing table keyed on the coordinates' bits, -0 as +0), so
 * a closed STL reads as a closed mesh. A file starting with "solid" whose
 * size matches the binary layout is binary (many exporters do that).
 */
#include "mesh_private.h"

#include <math.h>
#include <string.h>

typedef struct weld {
    int32_t *slots; /* vertex index + 1, 0 empty */
    size_t cap;     /* power of two */
    size_t bytes;
} weld;

static uint64_t key_bits(double d)
{
    if (d == 0) d = 0; /* -0 -> +0 */
    uint64_t u;
    memcpy(&u, &d, 8);
    return u;
}

static uint64_t hash3(const double *p)
{
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int k = 0; k < 3; k++) {
        h ^= key_bits(p[k]);
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
    }
    return h;
}

static bvox_status weld_init(weld *w, int64_t max_vertices)
{
    w->cap = 1024;
    while ((int64_t)w->cap < 2 * max_vertices) w->cap *= 2;
    w->bytes = w->cap * sizeof(int32_t);
    bvox_status st;
    w->slots = bvox__alloc(w->bytes, true, "STL vertex table", &st);
    return w->slots ? BVOX_OK : st;
}

static void weld_release(weld *w)
{
    if (w->slots) bvox__free(w->slots, w->bytes);
    w->slots = NULL;
}

/* The vertex at p (added if new). The table never fills: it holds at least
 * twice the vertices a file of this size can have. */
static bvox_status weld_vertex(weld *w, bvox_mesh *m, const double *p, int32_t *idx)
{
    size_t mask = w->cap - 1, h = (size_t)hash3(p) & mask;
    for (;;) {
        int32_t s = w->slots[h];
        if (!s) break;
        const double *q = m->vertices + 3 * (s - 1);
        if (key_bits(q[0]) == key_bits(p[0]) && key_bits(q[1]) == key_bits(p[1]) &&
            key_bits(q[2]) == key_bits(p[2])) {
            *idx = s - 1;
            return BVOX_OK;
        }
        h = (h + 1) & mask;
    }
    bvox_status st = bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
    if (st) return st;
    *idx = (int32_t)(m->nvertices - 1);
    w->slots[h] = (int32_t)m->nvertices;
    return BVOX_OK;
}

static float le_f32(const uint8_t *b)
{
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 |
                 (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static bvox_status read_binary(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    uint32_t count = (uint32_t)d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 |
                     (uint32_t)d[83] << 24;
    if ((uint64_t)count * 50 > n - 84)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: binary STL claims %u triangles but holds only %zu bytes of them "
                          "(truncated?)",
                          name, count, n - 84);
    if ((int64_t)count * 3 > INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "%s: too many triangles (%u)", name, count);
    weld w;
    bvox_status st = weld_init(&w, 3 * (int64_t)count);
    if (!st) st = bvox__mesh_grow(m, 0, count);
    for (uint32_t t = 0; t < count && !st; t++) {
        const uint8_t *r = d + 84 + 50 * (size_t)t + 12;
        int32_t id[3];
        for (int k = 0; k < 3 && !st; k++) {
            double p[3];
            for (int j = 0; j < 3; j++) p[j] = le_f32(r + 12 * k + 4 * j);
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                st = bvox__fail(BVOX_EFORMAT, "%s: triangle %u: coordinate is not finite (NaN "
                                              "or infinite)",
                                name, t);
                break;
            }
            st = weld_vertex(&w, m, p, &id[k]);
        }
        if (!st) st = bvox_mesh_add_triangle(m, id[0], id[1], id[2]);
    }
    weld_release(&w);
    return st;
}

static bvox_status expect(bvox__text *t, const char *word)
{
    char tok[32];
    if (!bvox__text_token(t, tok, sizeof tok, 0))
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: expected '%s', found the end (truncated?)",
                          t->name, (long long)t->line, word);
    if (strcmp(tok, word))
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: expected '%s', found '%s'", t->name,
                          (long long)t->line, word, tok[0] == 1 ? "(too long)" : tok);
    return BVOX_OK;
}

static bvox_status read_ascii(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    bvox__text t;
    bvox__text_init(&t, d, n, name);
    /* every facet takes more than 60 bytes: a bound on the vertices */
    weld w;
    bvox_status st = weld_init(&w, (int64_t)(n / 20) + 3);
    if (st) return st;
    st = expect(&t, "solid");
    if (!st) bvox__text_next_line(&t); /* the solid's name */
    char tok[32];
    while (!st) {
        if (!bvox__text_token(&t, tok, sizeof tok, 0)) {
            st = bvox__fail(BVOX_EFORMAT, "%s: missing 'endsolid' (truncated?)", name);
            break;
        }
        if (!strcmp(tok, "endsolid")) {
            bvox__text_next_line(&t);
            if (!bvox__text_token(&t, tok, sizeof tok, 0)) break; /* the end */
            if (strcmp(tok, "solid")) {
                st = bvox__fail(BVOX_EFORMAT, "%s: line %lld: expected 'solid', found '%s'",
                                name, (long long)t.line, tok);
                break;
            }
            bvox__text_next_line(&t);
            continue;
        }
        if (strcmp(tok, "facet")) {
            st = bvox__fail(BVOX_EFORMAT, "%s: line %lld: expected 'facet', found '%s'", name,
                            (long long)t.line, tok[0] == 1 ? "(too long)" : tok);
            break;
        }
        double nrm;
        st = expect(&t, "normal");
        for (int k = 0; k < 3 && !st; k++) st = bvox__text_double(&t, 1, "normal", &nrm);
        if (!st) st = expect(&t, "outer");
        if (!st) st = expect(&t, "loop");
        int32_t id[3];
        for (int k = 0; k < 3 && !st; k++) {
            double p[3];
            st = expect(&t, "vertex");
            for (int j = 0; j < 3 && !st; j++) st = bvox__text_double(&t, 1, "coordinate", &p[j]);
            if (!st && m->nvertices >= (int64_t)(w.cap / 2))
                st = bvox__fail(BVOX_EFORMAT, "%s: too many vertices for the file size", name);
            if (!st) st = weld_vertex(&w, m, p, &id[k]);
        }
        if (!st) st = expect(&t, "endloop");
        if (!st) st = expect(&t, "endfacet");
        if (!st) st = bvox_mesh_add_triangle(m, id[0], id[1], id[2]);
    }
    weld_release(&w);
    return st;
}

bvox_status bvox__mesh_read_stl(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    size_t i = 0;
    while (i < n && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
    int solid = n - i >= 5 && !memcmp(d + i, "solid", 5);
    if (n >= 84) {
        uint32_t k = (uint32_t)d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 |
                     (uint32_t)d[83] << 24;
        if (!solid || (uint64_t)k * 50 + 84 == n) return read_binary(d, n, name, m);
    }
    if (solid) return read_ascii(d, n, name, m);
    return bvox__fail(BVOX_EFORMAT, "%s: too short for a binary STL (%zu bytes, 84 needed)", name,
                      n);
}
