/*
 * read_ply.c — PLY (Stanford): ascii, binary_little_endian and
 * binary_big_endian. The header declares elements, each with scalar
 * properties (char/int8, uchar/uint8, short/int16, ushort/uint16,
 * int/int32, uint/uint32, float/float32, double/float64) and list
 * properties (a count type and an item type). bvox takes x, y, z of
 * "vertex" and the list "vertex_indices" (or "vertex_index") of "face";
 * every other element and property is read past. Element counts are
 * checked against the bytes left before anything is allocated.
 */
#include "mesh_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ELEMS 16
#define MAX_PROPS 32

typedef enum { T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64, T_BAD } ptype;

typedef struct prop {
    ptype type;        /* scalar, or the item type of a list */
    ptype count_type;  /* T_BAD: a scalar */
    int role;          /* 0 other, 1..3 x/y/z, 4 face indices */
} prop;

typedef struct elem {
    char name[32];
    int64_t count;
    prop props[MAX_PROPS];
    int nprops;
} elem;

static ptype parse_type(const char *s)
{
    static const char *const names[][2] = {{"char", "int8"},    {"uchar", "uint8"},
                                           {"short", "int16"},  {"ushort", "uint16"},
                                           {"int", "int32"},    {"uint", "uint32"},
                                           {"float", "float32"}, {"double", "float64"}};
    for (int i = 0; i < 8; i++)
        if (!strcmp(s, names[i][0]) || !strcmp(s, names[i][1])) return (ptype)i;
    return T_BAD;
}

static const size_t type_size[] = {1, 1, 2, 2, 4, 4, 4, 8};

/* A binary value at p (size checked by the caller) as a double. */
static double bin_value(const uint8_t *p, ptype t, int big)
{
    uint8_t b[8];
    size_t n = type_size[t];
    for (size_t i = 0; i < n; i++) b[i] = big ? p[n - 1 - i] : p[i];
    switch (t) {
    case T_I8: return (int8_t)b[0];
    case T_U8: return b[0];
    case T_I16: { int16_t v; memcpy(&v, b, 2); return v; }
    case T_U16: { uint16_t v; memcpy(&v, b, 2); return v; }
    case T_I32: { int32_t v; memcpy(&v, b, 4); return v; }
    case T_U32: { uint32_t v; memcpy(&v, b, 4); return v; }
    case T_F32: { float v; memcpy(&v, b, 4); return v; }
    default: { double v; memcpy(&v, b, 8); return v; }
    }
}

typedef struct reader {
    bvox__text t;     /* ascii: the tokenizer; binary: t.p is the cursor */
    int binary, big;
    const char *name;
} reader;

/* Next value of type ty; integer types must be whole numbers. */
static bvox_status next_value(reader *r, ptype ty, const char *what, double *out)
{
    if (!r->binary) {
        bvox_status st = bvox__text_double(&r->t, 0, what, out);
        if (st) return st;
        if (ty < T_F32 && *out != floor(*out))
            return bvox__fail(BVOX_EFORMAT, "%s: line %lld: %s is not an integer", r->name,
                              (long long)r->t.line, what);
        return BVOX_OK;
    }
    size_t n = type_size[ty];
    if ((size_t)(r->t.end - r->t.p) < n)
        return bvox__fail(BVOX_EFORMAT, "%s: the data ends inside an element (truncated?)",
                          r->name);
    *out = bin_value((const uint8_t *)r->t.p, ty, r->big);
    r->t.p += n;
    if (!isfinite(*out))
        return bvox__fail(BVOX_EFORMAT, "%s: %s is not finite (NaN or infinite)", r->name, what);
    return BVOX_OK;
}

static bvox_status parse_header(bvox__text *t, const char *name, elem *el, int *nel, int *binary,
                                int *big)
{
    char tok[64];
    if (!bvox__text_token(t, tok, sizeof tok, 0) || strcmp(tok, "ply"))
        return bvox__fail(BVOX_EFORMAT, "%s: not a PLY file (no 'ply' magic)", name);
    bvox__text_next_line(t);
    int have_format = 0;
    *nel = 0;
    for (;;) {
        bvox__text_skip_blank(t);
        if (t->p >= t->end) return bvox__fail(BVOX_EFORMAT, "%s: no end_header", name);
        if (!bvox__text_token(t, tok, sizeof tok, 1)) {
            bvox__text_next_line(t);
            continue;
        }
        if (!strcmp(tok, "end_header")) {
            /* the data starts after this line's newline */
            while (t->p < t->end && *t->p != '\n') t->p++;
            if (t->p < t->end) {
                t->p++;
                t->line++;
            }
            break;
        }
        if (!strcmp(tok, "comment") || !strcmp(tok, "obj_info")) {
            bvox__text_next_line(t);
            continue;
        }
        if (!strcmp(tok, "format")) {
            bvox__text_token(t, tok, sizeof tok, 1);
            if (!strcmp(tok, "ascii")) *binary = 0;
            else if (!strcmp(tok, "binary_little_endian")) *binary = 1, *big = 0;
            else if (!strcmp(tok, "binary_big_endian")) *binary = 1, *big = 1;
            else return bvox__fail(BVOX_EFORMAT, "%s: unknown PLY format '%s'", name, tok);
            have_format = 1;
        } else if (!strcmp(tok, "element")) {
            if (*nel == MAX_ELEMS)
                return bvox__fail(BVOX_EFORMAT, "%s: more than %d elements", name, MAX_ELEMS);
            elem *e = &el[(*nel)++];
            memset(e, 0, sizeof *e);
            if (!bvox__text_token(t, tok, sizeof tok, 1))
                return bvox__fail(BVOX_EFORMAT, "%s: line %lld: element without a name", name,
                                  (long long)t->line);
            snprintf(e->name, sizeof e->name, "%.31s", tok);
            bvox_status st = bvox__text_int(t, 1, "element count", 0, INT32_MAX, &e->count);
            if (st) return st;
        } else if (!strcmp(tok, "property")) {
            if (*nel == 0)
                return bvox__fail(BVOX_EFORMAT, "%s: line %lld: property before any element",
                                  name, (long long)t->line);
            elem *e = &el[*nel - 1];
            if (e->nprops == MAX_PROPS)
                return bvox__fail(BVOX_EFORMAT, "%s: more than %d properties", name, MAX_PROPS);
            prop *p = &e->props[e->nprops++];
            p->count_type = T_BAD;
            p->role = 0;
            bvox__text_token(t, tok, sizeof tok, 1);
            if (!strcmp(tok, "list")) {
                bvox__text_token(t, tok, sizeof tok, 1);
                p->count_type = parse_type(tok);
                bvox__text_token(t, tok, sizeof tok, 1);
                p->type = parse_type(tok);
                if (p->count_type == T_BAD || p->type == T_BAD || p->count_type >= T_F32)
                    return bvox__fail(BVOX_EFORMAT, "%s: line %lld: bad list property types",
                                      name, (long long)t->line);
            } else {
                p->type = parse_type(tok);
                if (p->type == T_BAD)
                    return bvox__fail(BVOX_EFORMAT, "%s: line %lld: unknown property type '%s'",
                                      name, (long long)t->line, tok);
            }
            if (!bvox__text_token(t, tok, sizeof tok, 1))
                return bvox__fail(BVOX_EFORMAT, "%s: line %lld: property without a name", name,
                                  (long long)t->line);
            if (!strcmp(e->name, "vertex") && p->count_type == T_BAD) {
                if (!strcmp(tok, "x")) p->role = 1;
                if (!strcmp(tok, "y")) p->role = 2;
                if (!strcmp(tok, "z")) p->role = 3;
            }
            if (!strcmp(e->name, "face") && p->count_type != T_BAD &&
                (!strcmp(tok, "vertex_indices") || !strcmp(tok, "vertex_index")))
                p->role = 4;
        } else {
            return bvox__fail(BVOX_EFORMAT, "%s: line %lld: unknown header line '%s'", name,
                              (long long)t->line, tok[0] == 1 ? "(too long)" : tok);
        }
        bvox__text_next_line(t);
    }
    if (!have_format) return bvox__fail(BVOX_EFORMAT, "%s: no format line", name);
    return BVOX_OK;
}

bvox_status bvox__mesh_read_ply(const uint8_t *d, size_t n, const char *name, bvox_mesh *m)
{
    reader r;
    memset(&r, 0, sizeof r);
    r.name = name;
    bvox__text_init(&r.t, d, n, name);
    elem el[MAX_ELEMS];
    int nel = 0;
    bvox_status st = parse_header(&r.t, name, el, &nel, &r.binary, &r.big);
    if (st) return st;
    /* counts against the bytes left: every property takes >= 1 byte in
     * binary and >= 2 in ascii */
    size_t left = (size_t)(r.t.end - r.t.p);
    uint64_t need = 0;
    int have_xyz = 0;
    for (int i = 0; i < nel; i++) {
        uint64_t per = 0;
        for (int j = 0; j < el[i].nprops; j++)
            per += r.binary ? type_size[el[i].props[j].count_type == T_BAD ? el[i].props[j].type
                                                                            : el[i].props[j].count_type]
                            : 2;
        need += (uint64_t)el[i].count * per;
        if (!strcmp(el[i].name, "vertex")) {
            int roles = 0;
            for (int j = 0; j < el[i].nprops; j++)
                if (el[i].props[j].role >= 1 && el[i].props[j].role <= 3)
                    roles |= 1 << el[i].props[j].role;
            have_xyz = roles == 14;
        }
    }
    if (need > left)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: the header's element counts need at least %llu bytes, the data "
                          "has %zu (truncated or corrupt counts)",
                          name, (unsigned long long)need, left);
    if (!have_xyz) return bvox__fail(BVOX_EFORMAT, "%s: no vertex element with x, y, z", name);
    int64_t idx_small[16], *idx = idx_small, cap = 16;
    for (int i = 0; i < nel && !st; i++) {
        elem *e = &el[i];
        int is_vertex = !strcmp(e->name, "vertex"), is_face = !strcmp(e->name, "face");
        if (is_vertex) st = bvox__mesh_grow(m, m->nvertices + e->count, m->ntriangles);
        for (int64_t k = 0; k < e->count && !st; k++) {
            double p[3] = {0, 0, 0};
            for (int j = 0; j < e->nprops && !st; j++) {
                prop *pr = &e->props[j];
                double v;
                if (pr->count_type == T_BAD) {
                    st = next_value(&r, pr->type, "a property value", &v);
                    if (!st && pr->role >= 1 && pr->role <= 3) p[pr->role - 1] = v;
                    continue;
                }
                double cnt;
                st = next_value(&r, pr->count_type, "a list length", &cnt);
                if (st) break;
                if (cnt < 0 || cnt > (double)(1 << 20)) {
                    st = bvox__fail(BVOX_EFORMAT, "%s: list length %g out of range", name, cnt);
                    break;
                }
                int64_t c = (int64_t)cnt;
                if (pr->role == 4 && c > cap) {
                    if (idx != idx_small) free(idx);
                    idx = bvox__mem_alloc((size_t)c * sizeof *idx);
                    cap = c;
                    if (!idx) {
                        idx = idx_small;
                        cap = 16;
                        st = bvox__fail(BVOX_ENOMEM, "out of memory");
                        break;
                    }
                }
                for (int64_t q = 0; q < c && !st; q++) {
                    st = next_value(&r, pr->type, "a list item", &v);
                    if (!st && pr->role == 4) {
                        if (v < 0 || v >= (double)m->nvertices) {
                            st = bvox__fail(BVOX_EFORMAT,
                                            "%s: face %lld: vertex index %.0f out of range "
                                            "(%lld vertices)",
                                            name, (long long)k, v, (long long)m->nvertices);
                            break;
                        }
                        idx[q] = (int64_t)v;
                    }
                }
                if (!st && pr->role == 4 && is_face)
                    st = bvox__mesh_add_polygon(m, idx, c, name, r.binary ? k + 1 : r.t.line);
            }
            if (!st && is_vertex) st = bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
        }
    }
    if (idx != idx_small) free(idx);
    return st;
}
