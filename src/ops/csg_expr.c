/*
 * csg_expr.c — recursive-descent parser of CSG expressions (grammar at
 * bvox_csg_eval in bvox.h) into the tree of csg_expr.h. Every error names
 * what was expected and the 1-based column: "csg: expected ')' at column 17".
 * Primitive parameters are checked here too (names, counts, values, via
 * bvox_shape_volume for the shapes), so a parse-only run catches everything
 * but missing files. Recursion depth is bounded by BVOX_CSG_MAX_DEPTH (each
 * '(' and '~' counts) and chains are built iteratively.
 */
#include "ops/csg_expr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct parser {
    const char *s;
    size_t pos, len;
    int depth;
    bvox__csg_tree *t;
} parser;

#define COL(p) ((int)(p)->pos + 1)

static bvox_status fail_at(size_t pos, const char *what)
{
    return bvox__fail(BVOX_EINVAL, "csg: %s at column %d", what, (int)pos + 1);
}

static void skip_ws(parser *p)
{
    while (p->s[p->pos] == ' ' || p->s[p->pos] == '\t' || p->s[p->pos] == '\n' ||
           p->s[p->pos] == '\r')
        p->pos++;
}

static char peek(parser *p)
{
    skip_ws(p);
    return p->s[p->pos];
}

static bool is_name_char(char c)
{
    return (unsigned char)c > ' ' && c != 127 && !strchr("()+*^~@,=\"'", c);
}

static bool is_ident_start(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

static bool is_ident_char(char c) { return is_ident_start(c) || (c >= '0' && c <= '9'); }

/* Length of the identifier at pos (0 if none). */
static size_t ident_len(const parser *p, size_t pos)
{
    if (!is_ident_start(p->s[pos])) return 0;
    size_t n = 1;
    while (is_ident_char(p->s[pos + n])) n++;
    return n;
}

/* ---- the tree ---- */

static bvox_status new_node(parser *p, bvox__csg_kind kind, int col, int32_t *out)
{
    bvox__csg_tree *t = p->t;
    if (t->n == t->cap) {
        int32_t cap = t->cap ? t->cap * 2 : 16;
        bvox__csg_node *nodes = bvox__mem_resize(t->nodes, (size_t)cap * sizeof *nodes);
        if (!nodes) return bvox__fail(BVOX_ENOMEM, "csg: out of memory");
        t->nodes = nodes;
        t->cap = cap;
    }
    bvox__csg_node *n = &t->nodes[t->n];
    memset(n, 0, sizeof *n);
    n->kind = kind;
    n->col = col;
    n->child = n->next = -1;
    *out = t->n++;
    return BVOX_OK;
}

static bvox_status add_name(parser *p, const char *s, size_t n, size_t *out)
{
    bvox__csg_tree *t = p->t;
    if (t->pool_used + n + 1 > t->pool_cap) {
        size_t cap = (t->pool_cap ? t->pool_cap * 2 : 256) + n + 1;
        char *pool = bvox__mem_resize(t->pool, cap);
        if (!pool) return bvox__fail(BVOX_ENOMEM, "csg: out of memory");
        t->pool = pool;
        t->pool_cap = cap;
    }
    memcpy(t->pool + t->pool_used, s, n);
    t->pool[t->pool_used + n] = '\0';
    *out = t->pool_used;
    t->pool_used += n + 1;
    return BVOX_OK;
}

void bvox__csg_tree_free(bvox__csg_tree *t)
{
    free(t->nodes);
    free(t->pool);
    memset(t, 0, sizeof *t);
}

/* ---- numbers ---- */

/* [+-]digits[.digits][(e|E)[+-]digits], at least one digit before the
 * exponent; finite. Not strtod alone: it would take "inf", "nan", hex. */
static bvox_status number(parser *p, double *out)
{
    skip_ws(p);
    size_t start = p->pos, i = start, digits = 0;
    const char *s = p->s;
    if (s[i] == '+' || s[i] == '-') i++;
    while (s[i] >= '0' && s[i] <= '9') i++, digits++;
    if (s[i] == '.') {
        i++;
        while (s[i] >= '0' && s[i] <= '9') i++, digits++;
    }
    if (digits && (s[i] == 'e' || s[i] == 'E')) {
        size_t j = i + 1;
        if (s[j] == '+' || s[j] == '-') j++;
        if (s[j] >= '0' && s[j] <= '9') {
            while (s[j] >= '0' && s[j] <= '9') j++;
            i = j;
        }
    }
    char buf[64];
    if (!digits || i - start >= sizeof buf) return fail_at(start, "expected a number");
    memcpy(buf, s + start, i - start);
    buf[i - start] = '\0';
    double v = strtod(buf, NULL);
    if (!isfinite(v)) return fail_at(start, "number out of range");
    p->pos = i;
    *out = v;
    return BVOX_OK;
}

static bvox_status expect(parser *p, char c)
{
    if (peek(p) != c) {
        char what[32];
        snprintf(what, sizeof what, "expected '%c'", c);
        return fail_at(p->pos, what);
    }
    p->pos++;
    return BVOX_OK;
}

/* ---- file operands ---- */

/* '@' I,J,K (integers, voxels) or '@' (X,Y,Z) (physical). */
static bvox_status placement(parser *p, bvox__csg_node *n)
{
    if (peek(p) != '@') return BVOX_OK;
    p->pos++;
    bool physical = peek(p) == '(';
    if (physical) p->pos++;
    for (int i = 0; i < 3; i++) {
        if (i && expect(p, ',')) return BVOX_EINVAL;
        size_t at = (skip_ws(p), p->pos);
        bvox_status st = number(p, &n->offset[i]);
        if (st) return st;
        if (!(fabs(n->offset[i]) <= 1e9)) return fail_at(at, "offset too large");
        if (!physical && n->offset[i] != floor(n->offset[i]))
            return fail_at(at, "voxel offset must be an integer");
    }
    if (physical && expect(p, ')')) return BVOX_EINVAL;
    n->place = physical ? BVOX__PLACE_PHYSICAL : BVOX__PLACE_VOXELS;
    return BVOX_OK;
}

static bvox_status file_operand(parser *p, size_t start, size_t len, int32_t *out)
{
    int32_t id;
    bvox_status st = new_node(p, BVOX__CSG_FILE, (int)start + 1, &id);
    if (st) return st;
    size_t name = 0;
    if ((st = add_name(p, p->s + start, len, &name))) return st;
    p->t->nodes[id].name = name;
    if ((st = placement(p, &p->t->nodes[id]))) return st;
    *out = id;
    return BVOX_OK;
}

/* ---- primitives ---- */

#define MAXP 4
typedef struct pspec {
    const char *key;
    unsigned counts; /* bit n set: n values accepted */
    bool required;
} pspec;
typedef struct prim_spec {
    const char *name;
    int prim;
    pspec params[MAXP];
} prim_spec;

static const prim_spec prims[] = {
    {"sphere", BVOX_SHAPE_SPHERE, {{"r", 1u << 1, true}, {"at", 1u << 3, false}}},
    {"ellipsoid", BVOX_SHAPE_ELLIPSOID,
     {{"r", 1u << 1 | 1u << 3, true}, {"at", 1u << 3, false}}},
    {"box", BVOX_SHAPE_BOX,
     {{"size", 1u << 1 | 1u << 3, false}, {"at", 1u << 3, false},
      {"min", 1u << 3, false}, {"max", 1u << 3, false}}},
    {"cylinder", BVOX_SHAPE_CYLINDER,
     {{"r", 1u << 1, true}, {"h", 1u << 1, true}, {"at", 1u << 3, false},
      {"axis", 1u << 3, false}}},
    {"cone", BVOX_SHAPE_CONE,
     {{"r", 1u << 1, true}, {"h", 1u << 1, true}, {"at", 1u << 3, false},
      {"axis", 1u << 3, false}}},
    {"torus", BVOX_SHAPE_TORUS,
     {{"R", 1u << 1, true}, {"r", 1u << 1, true}, {"at", 1u << 3, false},
      {"axis", 1u << 3, false}}},
    {"halfspace", BVOX__PRIM_HALFSPACE, {{"n", 1u << 3, true}, {"d", 1u << 1, false}}},
};
#define NPRIMS (int)(sizeof prims / sizeof prims[0])

static const prim_spec *find_prim(const char *s, size_t n)
{
    for (int i = 0; i < NPRIMS; i++)
        if (strlen(prims[i].name) == n && !memcmp(prims[i].name, s, n)) return &prims[i];
    return NULL;
}

typedef struct args {
    int count[MAXP]; /* 0: not given */
    double v[MAXP][3];
} args;

static bvox_status prim_fail(const prim_spec *ps, size_t pos, const char *fmt, const char *key)
{
    char what[160];
    snprintf(what, sizeof what, fmt, ps->name, key);
    return fail_at(pos, what);
}

/* key=v[,v...] pairs up to ')'. A ',' followed by NAME '=' starts the next
 * pair; otherwise it separates values. */
static bvox_status parse_args(parser *p, const prim_spec *ps, args *a)
{
    memset(a, 0, sizeof *a);
    if (peek(p) == ')') {
        p->pos++;
        return BVOX_OK;
    }
    for (;;) {
        size_t kpos = (skip_ws(p), p->pos), kn = ident_len(p, kpos);
        if (!kn) return fail_at(kpos, "expected a parameter name");
        int k = -1;
        for (int i = 0; i < MAXP && ps->params[i].key; i++)
            if (strlen(ps->params[i].key) == kn && !memcmp(ps->params[i].key, p->s + kpos, kn))
                k = i;
        char key[40];
        snprintf(key, sizeof key, "%.*s", (int)(kn < 32 ? kn : 32), p->s + kpos);
        if (k < 0) return prim_fail(ps, kpos, "%s has no parameter '%s'", key);
        if (a->count[k]) return prim_fail(ps, kpos, "%s: parameter '%s' given twice", key);
        p->pos = kpos + kn;
        if (peek(p) != '=') {
            char what[80];
            snprintf(what, sizeof what, "expected '=' after '%s'", key);
            return fail_at(p->pos, what);
        }
        p->pos++;
        bool closed = false;
        for (;;) {
            size_t vpos = (skip_ws(p), p->pos);
            if (a->count[k] == 3) return prim_fail(ps, vpos, "%s: too many values for '%s'", key);
            bvox_status st = number(p, &a->v[k][a->count[k]]);
            if (st) return st;
            a->count[k]++;
            char c = peek(p);
            if (c == ')') {
                closed = true;
                break;
            }
            if (c != ',') return fail_at(p->pos, "expected ',' or ')'");
            size_t after = p->pos + 1, q = after;
            while (p->s[q] == ' ' || p->s[q] == '\t' || p->s[q] == '\n' || p->s[q] == '\r') q++;
            size_t n = ident_len(p, q), r = q + n;
            while (p->s[r] == ' ' || p->s[r] == '\t' || p->s[r] == '\n' || p->s[r] == '\r') r++;
            p->pos = after;
            if (n && p->s[r] == '=') break; /* the next key */
        }
        unsigned counts = ps->params[k].counts;
        if (!(counts >> a->count[k] & 1))
            return prim_fail(ps, kpos,
                             counts == (1u << 3) ? "%s: '%s' needs 3 values"
                             : counts == (1u << 1) ? "%s: '%s' needs 1 value"
                                                   : "%s: '%s' needs 1 or 3 values",
                             key);
        if (closed) {
            p->pos++;
            return BVOX_OK;
        }
    }
}

static void copy3(double *dst, const args *a, int k)
{
    for (int i = 0; i < 3; i++) dst[i] = a->v[k][a->count[k] == 1 ? 0 : i];
}

/* Fill the node from checked arguments; check the values. */
static bvox_status build_prim(const prim_spec *ps, const args *a, size_t pos, bvox__csg_node *n)
{
    for (int i = 0; i < MAXP && ps->params[i].key; i++)
        if (ps->params[i].required && !a->count[i])
            return prim_fail(ps, pos, "%s: missing parameter '%s'", ps->params[i].key);
    n->prim = ps->prim;
    if (ps->prim == BVOX__PRIM_HALFSPACE) {
        copy3(n->plane, a, 0);
        n->plane[3] = a->count[1] ? a->v[1][0] : 0.0;
        if (n->plane[0] == 0 && n->plane[1] == 0 && n->plane[2] == 0)
            return prim_fail(ps, pos, "%s: the normal n is zero%s", "");
        return BVOX_OK;
    }
    bvox_shape *s = &n->shape;
    s->kind = (bvox_shape_kind)ps->prim;
    s->axis[2] = 1;
    switch (ps->prim) {
    case BVOX_SHAPE_SPHERE: s->radius = a->v[0][0]; break;
    case BVOX_SHAPE_ELLIPSOID: copy3(s->semi_axes, a, 0); break;
    case BVOX_SHAPE_BOX:
        if (a->count[0] ? (a->count[2] || a->count[3]) : (!a->count[2] || !a->count[3] ||
                                                          a->count[1]))
            return prim_fail(ps, pos, "%s: give size=SX,SY,SZ [at=X,Y,Z] or min=... max=...%s",
                             "");
        if (a->count[0]) {
            copy3(s->semi_axes, a, 0);
            for (int i = 0; i < 3; i++) s->semi_axes[i] /= 2;
        } else {
            for (int i = 0; i < 3; i++) {
                if (a->v[3][i] < a->v[2][i])
                    return prim_fail(ps, pos, "%s: max is below min%s", "");
                s->center[i] = a->v[2][i] / 2 + a->v[3][i] / 2;
                s->semi_axes[i] = a->v[3][i] / 2 - a->v[2][i] / 2;
            }
            n->at_given = 1;
        }
        break;
    case BVOX_SHAPE_CYLINDER:
    case BVOX_SHAPE_CONE:
    case BVOX_SHAPE_TORUS:
        if (ps->prim == BVOX_SHAPE_TORUS) {
            s->radius = a->v[0][0];
            s->minor_radius = a->v[1][0];
        } else {
            s->radius = a->v[0][0];
            s->height = a->v[1][0];
        }
        if (a->count[3]) copy3(s->axis, a, 3);
        break;
    }
    int at = ps->prim == BVOX_SHAPE_BOX ? 1 : ps->prim <= BVOX_SHAPE_ELLIPSOID ? 1 : 2;
    if (a->count[at]) {
        copy3(s->center, a, at);
        n->at_given = 1;
    }
    /* the library's own validation (sizes, axis), with its message */
    if (bvox_shape_volume(s) < 0) {
        char msg[256];
        snprintf(msg, sizeof msg, "%s", bvox_errmsg());
        return bvox__fail(BVOX_EINVAL, "csg: %s at column %d: %s", ps->name, (int)pos + 1, msg);
    }
    return BVOX_OK;
}

static bvox_status primitive(parser *p, size_t start, const prim_spec *ps, int32_t *out)
{
    args a;
    bvox_status st = parse_args(p, ps, &a);
    if (st) return st;
    int32_t id;
    if ((st = new_node(p, BVOX__CSG_PRIM, (int)start + 1, &id))) return st;
    if ((st = build_prim(ps, &a, start, &p->t->nodes[id]))) return st;
    *out = id;
    return BVOX_OK;
}

/* ---- the grammar ---- */

static bvox_status parse_expr(parser *p, int32_t *out);

static bvox_status deeper(parser *p)
{
    if (++p->depth > BVOX_CSG_MAX_DEPTH) {
        char what[64];
        snprintf(what, sizeof what, "nesting deeper than %d", BVOX_CSG_MAX_DEPTH);
        return fail_at(p->pos, what);
    }
    return BVOX_OK;
}

static bvox_status parse_primary(parser *p, int32_t *out)
{
    char c = peek(p);
    size_t start = p->pos;
    bvox_status st;
    if (c == '(') {
        if ((st = deeper(p))) return st;
        p->pos++;
        if ((st = parse_expr(p, out))) return st;
        if (peek(p) != ')') return fail_at(p->pos, "expected ')'");
        p->pos++;
        p->depth--;
        return BVOX_OK;
    }
    if (c == '"' || c == '\'') {
        const char *end = strchr(p->s + start + 1, c);
        if (!end) return fail_at(start, "unterminated quoted file name");
        size_t n = (size_t)(end - (p->s + start + 1));
        if (!n) return fail_at(start, "empty file name");
        p->pos = (size_t)(end - p->s) + 1;
        return file_operand(p, start + 1, n, out);
    }
    if (!is_name_char(c) || c == '-') {
        if (c == '\0') return fail_at(start, "expected an operand, found the end");
        return fail_at(start, "expected an operand");
    }
    size_t n = 0;
    while (is_name_char(p->s[start + n])) n++;
    size_t id = ident_len(p, start);
    if (id == n) {
        p->pos = start + n;
        const prim_spec *ps = find_prim(p->s + start, n);
        if (peek(p) == '(') {
            if (!ps) {
                return bvox__fail(BVOX_EINVAL,
                                  "csg: unknown primitive '%.*s' at column %d (known: sphere, "
                                  "ellipsoid, box, cylinder, cone, torus, halfspace)",
                                  (int)(n < 32 ? n : 32), p->s + start, (int)start + 1);
            }
            p->pos++;
            return primitive(p, start, ps, out);
        }
        if (ps) return prim_fail(ps, start, "%s needs its parameters in parentheses%s", "");
    }
    p->pos = start + n;
    return file_operand(p, start, n, out);
}

static bvox_status parse_unary(parser *p, int32_t *out)
{
    if (peek(p) != '~') return parse_primary(p, out);
    size_t start = p->pos;
    bvox_status st = deeper(p);
    if (st) return st;
    p->pos++;
    int32_t child;
    if ((st = parse_unary(p, &child))) return st;
    p->depth--;
    int32_t id;
    if ((st = new_node(p, BVOX__CSG_NOT, (int)start + 1, &id))) return st;
    p->t->nodes[id].child = child;
    *out = id;
    return BVOX_OK;
}

/* A left-to-right chain of `sub` operands joined by the operators of ops
 * (whose set operations are in opv). One operand: no chain node. */
static bvox_status chain(parser *p, bvox_status (*sub)(parser *, int32_t *), const char *ops,
                         const bvox_csg_op *opv, int32_t *out)
{
    int32_t first, last;
    size_t start = (skip_ws(p), p->pos);
    bvox_status st = sub(p, &first);
    if (st) return st;
    last = first;
    int32_t id = -1;
    for (;;) {
        char c = peek(p);
        const char *o = c ? strchr(ops, c) : NULL;
        if (!o) break;
        p->pos++;
        int32_t m;
        if ((st = sub(p, &m))) return st;
        if (id < 0) {
            if ((st = new_node(p, BVOX__CSG_CHAIN, (int)start + 1, &id))) return st;
            p->t->nodes[id].child = first;
        }
        p->t->nodes[m].op = opv[o - ops];
        p->t->nodes[last].next = m;
        last = m;
    }
    *out = id >= 0 ? id : first;
    return BVOX_OK;
}

static bvox_status parse_term(parser *p, int32_t *out)
{
    static const bvox_csg_op opv[] = {BVOX_CSG_INTERSECTION};
    return chain(p, parse_unary, "*", opv, out);
}

static bvox_status parse_expr(parser *p, int32_t *out)
{
    static const bvox_csg_op opv[] = {BVOX_CSG_UNION, BVOX_CSG_DIFFERENCE, BVOX_CSG_XOR};
    return chain(p, parse_term, "+-^", opv, out);
}

bvox_status bvox__csg_parse(const char *expr, bvox__csg_tree *tree)
{
    memset(tree, 0, sizeof *tree);
    if (!expr) return bvox__fail(BVOX_EINVAL, "csg: no expression");
    size_t len = strnlen(expr, (size_t)BVOX_CSG_MAX_LENGTH + 1);
    if (len > BVOX_CSG_MAX_LENGTH)
        return bvox__fail(BVOX_EINVAL, "csg: expression longer than %d bytes",
                          BVOX_CSG_MAX_LENGTH);
    parser p = {expr, 0, len, 0, tree};
    if (!peek(&p)) return bvox__fail(BVOX_EINVAL, "csg: empty expression");
    bvox_status st = parse_expr(&p, &tree->root);
    if (!st && peek(&p)) {
        char c = peek(&p);
        st = fail_at(p.pos, c == ')' ? "unmatched ')'" : "expected an operator");
    }
    if (st) bvox__csg_tree_free(tree);
    return st;
}
