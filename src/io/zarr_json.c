/*
 * zarr_json.c — a small, bounded JSON tree for Zarr metadata (.zarray,
 * .zattrs, .zgroup). Strict RFC 8259: no comments, no trailing commas, no
 * NaN literals (Zarr writes a NaN fill value as the string "NaN"). The text
 * is copied once; strings are decoded in place in that copy (an escape never
 * decodes longer than it is written), so nodes point into it. Nodes live in
 * one growing array, children linked by index. Input over
 * BVOX__JTREE_MAX_BYTES or nested deeper than BVOX__JTREE_MAX_DEPTH is refused.
 * The contour reader (recon/contour_json.c) is a schema-directed pull parser
 * for large files; this one serves small documents read by key.
 */
#include "zarr.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct parser {
    char *p, *end, *start;
    const char *name;
    bvox__jtree *j;
} parser;

static bvox_status pfail(const parser *P, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bvox_status pfail(const parser *P, const char *fmt, ...)
{
    int line = 1;
    for (const char *c = P->start; c < P->p && c < P->end; c++) line += *c == '\n';
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return bvox__fail(BVOX_EFORMAT, "%s: line %d: %s", P->name, line, msg);
}

static void ws(parser *P)
{
    while (P->p < P->end && (*P->p == ' ' || *P->p == '\t' || *P->p == '\n' || *P->p == '\r'))
        P->p++;
}

static int32_t new_node(parser *P, bvox__jtype t)
{
    bvox__jtree *j = P->j;
    if (j->n == j->cap) {
        int32_t cap = j->cap ? j->cap * 2 : 16;
        void *q = bvox__mem_resize(j->nodes, (size_t)cap * sizeof *j->nodes);
        if (!q) return -1;
        j->nodes = q;
        j->cap = cap;
    }
    bvox__jnode *n = &j->nodes[j->n];
    memset(n, 0, sizeof *n);
    n->type = t;
    n->first_child = n->next = -1;
    return j->n++;
}

static int hexval(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

static bool hex4(const char *p, const char *end, uint32_t *v)
{
    if (end - p < 4) return false;
    *v = 0;
    for (int i = 0; i < 4; i++) {
        int h = hexval(p[i]);
        if (h < 0) return false;
        *v = *v << 4 | (uint32_t)h;
    }
    return true;
}

/* P->p at the opening quote; decodes into the same buffer. */
static bvox_status string(parser *P, const char **out, size_t *len)
{
    char *w = ++P->p, *s = w;
    for (;;) {
        if (P->p >= P->end) return pfail(P, "unterminated string");
        unsigned char c = (unsigned char)*P->p;
        if (c == '"') break;
        if (c < 0x20) return pfail(P, "control character in a string");
        if (c != '\\') {
            *w++ = *P->p++;
            continue;
        }
        if (P->end - P->p < 2) return pfail(P, "unterminated escape");
        char e = P->p[1];
        P->p += 2;
        switch (e) {
        case '"': *w++ = '"'; break;
        case '\\': *w++ = '\\'; break;
        case '/': *w++ = '/'; break;
        case 'b': *w++ = '\b'; break;
        case 'f': *w++ = '\f'; break;
        case 'n': *w++ = '\n'; break;
        case 'r': *w++ = '\r'; break;
        case 't': *w++ = '\t'; break;
        case 'u': {
            uint32_t u;
            if (!hex4(P->p, P->end, &u)) return pfail(P, "bad \\u escape");
            P->p += 4;
            if (u >= 0xD800 && u < 0xDC00) {
                uint32_t lo;
                if (P->end - P->p < 6 || P->p[0] != '\\' || P->p[1] != 'u' ||
                    !hex4(P->p + 2, P->end, &lo) || lo < 0xDC00 || lo > 0xDFFF)
                    return pfail(P, "unpaired surrogate in \\u escape");
                P->p += 6;
                u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
            } else if (u >= 0xDC00 && u < 0xE000) {
                return pfail(P, "unpaired surrogate in \\u escape");
            }
            if (u < 0x80) {
                *w++ = (char)u;
            } else if (u < 0x800) {
                *w++ = (char)(0xC0 | u >> 6);
                *w++ = (char)(0x80 | (u & 63));
            } else if (u < 0x10000) {
                *w++ = (char)(0xE0 | u >> 12);
                *w++ = (char)(0x80 | (u >> 6 & 63));
                *w++ = (char)(0x80 | (u & 63));
            } else {
                *w++ = (char)(0xF0 | u >> 18);
                *w++ = (char)(0x80 | (u >> 12 & 63));
                *w++ = (char)(0x80 | (u >> 6 & 63));
                *w++ = (char)(0x80 | (u & 63));
            }
            break;
        }
        default: return pfail(P, "bad escape \\%c", e);
        }
    }
    *len = (size_t)(w - s);
    *w = '\0'; /* w <= the closing quote's position */
    P->p++;
    *out = s;
    return BVOX_OK;
}

static bvox_status number(parser *P, double *v, bool *is_int)
{
    char *s = P->p;
    char *q = s;
    if (q < P->end && *q == '-') q++;
    if (q >= P->end || *q < '0' || *q > '9') return pfail(P, "unexpected character");
    if (*q == '0') q++;
    else
        while (q < P->end && *q >= '0' && *q <= '9') q++;
    *is_int = true;
    if (q < P->end && *q == '.') {
        *is_int = false;
        q++;
        if (q >= P->end || *q < '0' || *q > '9') return pfail(P, "bad number");
        while (q < P->end && *q >= '0' && *q <= '9') q++;
    }
    if (q < P->end && (*q == 'e' || *q == 'E')) {
        *is_int = false;
        q++;
        if (q < P->end && (*q == '+' || *q == '-')) q++;
        if (q >= P->end || *q < '0' || *q > '9') return pfail(P, "bad number");
        while (q < P->end && *q >= '0' && *q <= '9') q++;
    }
    char buf[64];
    size_t n = (size_t)(q - s);
    if (n >= sizeof buf) {
        /* long digit strings: strtod on the copy (the text is NUL-terminated) */
        char save = *q;
        *q = '\0';
        *v = strtod(s, NULL);
        *q = save;
    } else {
        memcpy(buf, s, n);
        buf[n] = '\0';
        *v = strtod(buf, NULL);
    }
    if (!isfinite(*v)) return pfail(P, "number out of range");
    P->p = q;
    return BVOX_OK;
}

static bool literal(parser *P, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(P->end - P->p) < n || memcmp(P->p, word, n)) return false;
    P->p += n;
    return true;
}

static bvox_status value(parser *P, int depth, int32_t *out);

static bvox_status container(parser *P, int depth, int32_t self, char close)
{
    bool object = close == '}';
    P->p++;
    ws(P);
    if (P->p < P->end && *P->p == close) {
        P->p++;
        return BVOX_OK;
    }
    int32_t last = -1;
    for (;;) {
        ws(P);
        const char *key = NULL;
        if (object) {
            size_t klen;
            if (P->p >= P->end || *P->p != '"') return pfail(P, "expected a member name");
            bvox_status st = string(P, &key, &klen);
            if (st) return st;
            ws(P);
            if (P->p >= P->end || *P->p != ':') return pfail(P, "expected ':'");
            P->p++;
        }
        int32_t child;
        bvox_status st = value(P, depth + 1, &child);
        if (st) return st;
        bvox__jnode *nodes = P->j->nodes;
        nodes[child].key = key;
        if (last < 0) nodes[self].first_child = child;
        else nodes[last].next = child;
        last = child;
        if (nodes[self].count == INT32_MAX) return pfail(P, "too many elements");
        nodes[self].count++;
        ws(P);
        if (P->p >= P->end) return pfail(P, "unexpected end of text");
        if (*P->p == ',') {
            P->p++;
            continue;
        }
        if (*P->p == close) {
            P->p++;
            return BVOX_OK;
        }
        return pfail(P, "expected ',' or '%c'", close);
    }
}

static bvox_status value(parser *P, int depth, int32_t *out)
{
    if (depth > BVOX__JTREE_MAX_DEPTH)
        return pfail(P, "nested deeper than %d levels", BVOX__JTREE_MAX_DEPTH);
    ws(P);
    if (P->p >= P->end) return pfail(P, "unexpected end of text");
    char c = *P->p;
    bvox__jtype t;
    if (c == '{') t = BVOX__JT_OBJECT;
    else if (c == '[') t = BVOX__JT_ARRAY;
    else if (c == '"') t = BVOX__JT_STRING;
    else if (c == 'n') t = BVOX__JT_NULL;
    else if (c == 't') t = BVOX__JT_TRUE;
    else if (c == 'f') t = BVOX__JT_FALSE;
    else t = BVOX__JT_NUMBER;
    int32_t self = new_node(P, t);
    if (self < 0) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", P->name);
    *out = self;
    switch (t) {
    case BVOX__JT_OBJECT: return container(P, depth, self, '}');
    case BVOX__JT_ARRAY: return container(P, depth, self, ']');
    case BVOX__JT_STRING: {
        const char *s;
        size_t len;
        bvox_status st = string(P, &s, &len);
        if (st) return st;
        P->j->nodes[self].str = s;
        P->j->nodes[self].len = len;
        return BVOX_OK;
    }
    case BVOX__JT_NULL: return literal(P, "null") ? BVOX_OK : pfail(P, "unexpected word");
    case BVOX__JT_TRUE: return literal(P, "true") ? BVOX_OK : pfail(P, "unexpected word");
    case BVOX__JT_FALSE: return literal(P, "false") ? BVOX_OK : pfail(P, "unexpected word");
    default: {
        double v = 0;
        bool is_int = false;
        bvox_status st = number(P, &v, &is_int);
        if (st) return st;
        P->j->nodes[self].num = v;
        P->j->nodes[self].is_int = is_int;
        return BVOX_OK;
    }
    }
}

bvox_status bvox__jtree_parse(const char *text, size_t size, const char *name, bvox__jtree *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "input";
    if (size > BVOX__JTREE_MAX_BYTES)
        return bvox__fail(BVOX_ETOOBIG, "%s: %zu bytes of JSON metadata, more than the %zu "
                          "allowed", name, size, BVOX__JTREE_MAX_BYTES);
    out->text = bvox__mem_alloc(size + 1);
    if (!out->text) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    if (size) memcpy(out->text, text, size);
    out->text[size] = '\0';
    parser P = {out->text, out->text + size, out->text, name, out};
    /* a UTF-8 byte-order mark is not JSON but some tools write one */
    if (size >= 3 && !memcmp(P.p, "\xEF\xBB\xBF", 3)) P.p += 3;
    int32_t root;
    bvox_status st = value(&P, 0, &root);
    if (!st) {
        ws(&P);
        if (P.p != P.end) st = pfail(&P, "text after the JSON value");
    }
    if (st) bvox__jtree_release(out);
    return st;
}

void bvox__jtree_release(bvox__jtree *j)
{
    free(j->nodes);
    free(j->text);
    memset(j, 0, sizeof *j);
}

const bvox__jnode *bvox__jtree_get(const bvox__jtree *j, const bvox__jnode *obj,
                                      const char *key)
{
    if (!obj || obj->type != BVOX__JT_OBJECT) return NULL;
    const bvox__jnode *found = NULL;
    for (int32_t i = obj->first_child; i >= 0; i = j->nodes[i].next)
        if (!strcmp(j->nodes[i].key, key)) found = &j->nodes[i]; /* last duplicate wins */
    return found;
}

const bvox__jnode *bvox__jtree_at(const bvox__jtree *j, const bvox__jnode *arr, int32_t k)
{
    if (!arr || arr->type != BVOX__JT_ARRAY || k < 0 || k >= arr->count) return NULL;
    int32_t i = arr->first_child;
    while (k-- > 0) i = j->nodes[i].next;
    return &j->nodes[i];
}
