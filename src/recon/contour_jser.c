/*
 * contour_jser.c — PyReconstruct's .jser series (one JSON file holding the
 * whole series), read into a contour stack. Two layouts, both still opened by
 * PyReconstruct:
 *   current  {"sections": [SECTION or null, ...], "series": {...}, "log": ...}
 *            (the list index is the section number);
 *   older    {"NAME.0": SECTION, "NAME.1": SECTION, ..., "NAME.ser": {...}}
 *            (one key per hidden-folder file; the number after the last '.'
 *            is the section number, any other key is the series).
 * A SECTION is {"thickness": T, "mag": M, "tforms": {ALIGNMENT: [6 numbers]},
 *               "contours": {OBJECT: [TRACE, ...]}, ...}
 * and a TRACE is [x-list, y-list, color, closed, negative, hidden, mode, tags]
 * (current) or an object with those names (older); older files may hold any
 * of these fields as strings ("0.05", "True", "1.0, 2.5, 3"), read as such.
 * The series' "alignment" names the transform applied: [a, b, c, d, e, f]
 * maps (x, y) to (a x + b y + c, d x + e y + f), as PyReconstruct's
 * Transform (QTransform(a, d, b, e, c, f)) does; "no-alignment", or a section
 * without that alignment, leaves the points as they are (the latter warned);
 * an object with its own alignment in the series' "obj_attrs" that the
 * section has uses that one (as PyReconstruct's series data does).
 * Closed traces become contours; open traces are lines, not outlines: skipped
 * with one warning counting them. Negative traces lie inside the positive
 * ones they cut out (holes, by containment: even-odd fill). Units are
 * microns; z of a section = the sum of the thicknesses of the sections before
 * it; spacing = the first kept section's thickness. y is flipped (the field's
 * y points up) and points are converted to pixels of the traces' larger
 * extent / 512, as the Reconstruct XML reader does without images (a section
 * mag of nanometres per pixel would give images of 10^4 pixels and more).
 * object != NULL keeps only that object's traces and the sections from its
 * first to its last; an object found nowhere is an error naming some that
 * are there.
 *
 * The file is parsed into a small DOM (a node array, sizes grown with checks,
 * depth limited to BVOX__MAX_DEPTH, charged to the memory budget while it
 * lives): the series' alignment may come after
 * the sections. Strict JSON; NaN and Infinity (Python's json writes them) and
 * numbers beyond a double are refused, as are coordinates beyond 1e9 um.
 */
#include "contour_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_UM 1e9      /* |coordinate| in microns */
#define MAX_NAMES 6     /* object names listed when --object matches none */
/* JSON values (nodes, 32 bytes each) a file may hold: 512 MiB. A list of
 * numbers only (a trace's xs, a transform) is one node, so a series of a
 * million traces needs about 11 million. */
#define MAX_NODES ((size_t)1 << 24)

/* J_NUMS: an array of numbers only, kept as its text (checked when parsed,
 * read again by num_list). */
enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ, J_NUMS };

/* Children of an array follow `first` through `next`; an object's are
 * key, value, key, value... (n counts members). A string is raw text;
 * off/len fit 32 bits as the text is at most BVOX__MAX_TEXT_BYTES. */
typedef struct jnode {
    uint8_t type, b;
    int32_t n, first, next;
    uint32_t off, len;
    double num;
} jnode;

typedef struct jdoc {
    const char *text, *p, *end, *name;
    jnode *nodes;
    size_t nnodes, cap;
    size_t charged; /* bytes of nodes charged to the memory budget */
} jdoc;

static bvox_status jfail(const jdoc *d, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bvox_status jfail(const jdoc *d, const char *at, const char *fmt, ...)
{
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int64_t line, col;
    bvox__line_col(d->text, (size_t)(at - d->text), &line, &col);
    return bvox__fail(BVOX_EFORMAT, "%s:%lld:%lld: %s", d->name, (long long)line, (long long)col,
                      msg);
}

static void jws(jdoc *d)
{
    while (d->p < d->end && (*d->p == ' ' || *d->p == '\t' || *d->p == '\n' || *d->p == '\r'))
        d->p++;
}

static bvox_status new_node(jdoc *d, int type, int32_t *idx)
{
    if (d->nnodes >= MAX_NODES)
        return jfail(d, d->p, "more than %zu JSON values (lists of numbers count as one)",
                     MAX_NODES);
    if (d->nnodes == d->cap) { /* the node array is about to grow: charge what it adds */
        size_t add = (d->cap ? d->cap : 8) * sizeof *d->nodes;
        bvox_status st;
        if (!bvox__budget_charge(add, "the .jser's JSON values", &st)) return st;
        d->charged += add;
    }
    if (!bvox__grow((void **)&d->nodes, sizeof *d->nodes, d->nnodes + 1, &d->cap, "JSON values"))
        return BVOX_ENOMEM;
    jnode *n = &d->nodes[d->nnodes];
    memset(n, 0, sizeof *n);
    n->type = (uint8_t)type;
    n->first = n->next = -1;
    *idx = (int32_t)d->nnodes++;
    return BVOX_OK;
}

/* A string's raw extent (escapes checked, not decoded). */
static bvox_status jstring(jdoc *d, int32_t *idx)
{
    const char *at = d->p++;
    const char *s = d->p;
    while (d->p < d->end && *d->p != '"') {
        unsigned char c = (unsigned char)*d->p;
        if (c < 0x20) return jfail(d, d->p, "a control character in a string");
        if (c == '\\') {
            if (d->end - d->p < 2) break;
            if (!strchr("\"\\/bfnrtu", d->p[1])) return jfail(d, d->p, "bad escape");
            d->p++;
        }
        d->p++;
    }
    if (d->p >= d->end) return jfail(d, at, "unterminated string");
    bvox_status st = new_node(d, J_STR, idx);
    if (st) return st;
    d->nodes[*idx].off = (uint32_t)(s - d->text);
    d->nodes[*idx].len = (uint32_t)(d->p - s);
    d->p++;
    return BVOX_OK;
}

static bvox_status jvalue(jdoc *d, int depth, int32_t *idx);

/* A JSON number at d->p into *v (d->p moved past it). */
static bvox_status jnumber(jdoc *d, double *v)
{
    const char *s = d->p, *p = s;
    if (p < d->end && *p == '-') p++;
    if (p < d->end && (*p == 'N' || *p == 'I'))
        return jfail(d, s, "NaN or Infinity is not a number bvox reads");
    if (p >= d->end || !(*p >= '0' && *p <= '9')) return jfail(d, s, "expected a value");
    while (p < d->end && ((*p >= '0' && *p <= '9') || *p == '.' || *p == 'e' || *p == 'E' ||
                          *p == '+' || *p == '-'))
        p++;
    if (p - s > 64) return jfail(d, s, "a number of %d characters", (int)(p - s));
    char buf[72], *e;
    memcpy(buf, s, (size_t)(p - s));
    buf[p - s] = '\0';
    double x = strtod(buf, &e);
    if (*e) return jfail(d, s, "bad number '%s'", buf);
    if (!isfinite(x)) return jfail(d, s, "number %s out of range", buf);
    *v = x;
    d->p = p;
    return BVOX_OK;
}

/* After '[': a list of numbers only, up to its ']', as one J_NUMS node;
 * 0 (d->p unchanged) if it holds anything else. */
static bvox_status jnums(jdoc *d, const char *open, int32_t *idx, int *done)
{
    const char *save = d->p;
    int32_t count = 0;
    *done = 0;
    for (;;) {
        jws(d);
        if (d->p >= d->end || !(*d->p == '-' || (*d->p >= '0' && *d->p <= '9'))) break;
        double v;
        bvox_status st = jnumber(d, &v);
        if (st) return st;
        if (count == INT32_MAX) return jfail(d, open, "too many elements");
        count++;
        jws(d);
        if (d->p < d->end && *d->p == ',') {
            d->p++;
            continue;
        }
        if (d->p < d->end && *d->p == ']') {
            bvox_status st2 = new_node(d, J_NUMS, idx);
            if (st2) return st2;
            d->nodes[*idx].off = (uint32_t)(open + 1 - d->text);
            d->nodes[*idx].len = (uint32_t)(d->p - open - 1);
            d->nodes[*idx].n = count;
            d->p++;
            *done = 1;
            return BVOX_OK;
        }
        break;
    }
    d->p = save;
    return BVOX_OK;
}

/* An array or object: children linked in order. */
static bvox_status jcontainer(jdoc *d, int depth, int32_t *idx)
{
    int obj = *d->p == '{';
    char close = obj ? '}' : ']';
    const char *at = d->p++;
    if (depth >= BVOX__MAX_DEPTH) return jfail(d, at, "nesting deeper than %d levels", BVOX__MAX_DEPTH);
    bvox_status st;
    if (!obj) {
        int done;
        if ((st = jnums(d, at, idx, &done)) || done) return st;
    }
    st = new_node(d, obj ? J_OBJ : J_ARR, idx);
    if (st) return st;
    int32_t last = -1, count = 0;
    jws(d);
    if (d->p < d->end && *d->p == close) {
        d->p++;
        return BVOX_OK;
    }
    for (;;) {
        int32_t k = -1, v;
        jws(d);
        if (obj) {
            if (d->p >= d->end || *d->p != '"') return jfail(d, d->p, "expected a key string");
            if ((st = jstring(d, &k))) return st;
            jws(d);
            if (d->p >= d->end || *d->p != ':') return jfail(d, d->p, "expected ':' after a key");
            d->p++;
        }
        if ((st = jvalue(d, depth + 1, &v))) return st;
        if (k >= 0) d->nodes[k].next = v;
        int32_t head = k >= 0 ? k : v;
        if (last < 0) d->nodes[*idx].first = head;
        else d->nodes[last].next = head;
        last = v;
        if (count == INT32_MAX) return jfail(d, at, "too many elements");
        count++;
        jws(d);
        if (d->p < d->end && *d->p == ',') {
            d->p++;
            continue;
        }
        if (d->p < d->end && *d->p == close) {
            d->p++;
            break;
        }
        return jfail(d, d->p, "expected ',' or '%c'", close);
    }
    d->nodes[*idx].n = count;
    return BVOX_OK;
}

static bvox_status jvalue(jdoc *d, int depth, int32_t *idx)
{
    jws(d);
    if (d->p >= d->end) return jfail(d, d->p, "unexpected end of the file, expected a value");
    char c = *d->p;
    if (c == '{' || c == '[') return jcontainer(d, depth, idx);
    if (c == '"') return jstring(d, idx);
    static const char *const words[] = {"true", "false", "null"};
    for (int i = 0; i < 3; i++) {
        size_t n = strlen(words[i]);
        if ((size_t)(d->end - d->p) >= n && !memcmp(d->p, words[i], n)) {
            bvox_status st = new_node(d, i == 2 ? J_NULL : J_BOOL, idx);
            if (st) return st;
            d->nodes[*idx].b = i == 0;
            d->p += n;
            return BVOX_OK;
        }
    }
    double x;
    bvox_status st = jnumber(d, &x);
    if (st) return st;
    if ((st = new_node(d, J_NUM, idx))) return st;
    d->nodes[*idx].num = x;
    return BVOX_OK;
}

/* ------------------------------------------------------- DOM queries */

static const jnode *N(const jdoc *d, int32_t i) { return &d->nodes[i]; }

/* The decoded text of a string node into buf (truncated to cap - 1). */
static void jtext(const jdoc *d, int32_t i, char *buf, size_t cap)
{
    const char *s = d->text + N(d, i)->off, *e = s + N(d, i)->len;
    size_t n = 0;
    while (s < e && n + 5 < cap) {
        if (*s != '\\') {
            buf[n++] = *s++;
            continue;
        }
        char c = s[1];
        s += 2;
        if (c == 'u') {
            uint32_t u = 0;
            for (int k = 0; k < 4 && s < e; k++, s++) {
                char h = *s;
                u = u * 16 + (uint32_t)(h <= '9' ? h - '0' : (h | 32) - 'a' + 10);
            }
            if (u >= 0xD800 && u < 0xE000) u = 0xFFFD;
            bvox__put_utf8(buf, &n, u & 0xFFFF);
        } else {
            buf[n++] = c == 'n' ? '\n' : c == 't' ? '\t' : c == 'r' ? '\r' : c == 'b' ? '\b'
                     : c == 'f' ? '\f' : c;
        }
    }
    buf[n] = '\0';
}

static bool key_is(const jdoc *d, int32_t k, const char *key)
{
    size_t n = strlen(key);
    return N(d, k)->len == n && !memcmp(d->text + N(d, k)->off, key, n);
}

/* The value of key in object o, or -1. */
static int32_t jget(const jdoc *d, int32_t o, const char *key)
{
    if (o < 0 || N(d, o)->type != J_OBJ) return -1;
    for (int32_t k = N(d, o)->first; k >= 0; k = N(d, N(d, k)->next)->next)
        if (key_is(d, k, key)) return N(d, k)->next;
    return -1;
}

/* The i-th element of array a, or -1. */
static int32_t jat(const jdoc *d, int32_t a, int32_t i)
{
    if (a < 0 || N(d, a)->type != J_ARR || i >= N(d, a)->n) return -1;
    int32_t c = N(d, a)->first;
    while (i-- > 0) c = N(d, c)->next;
    return c;
}

/* A number, or a string holding one (older files). */
static bool jnum(const jdoc *d, int32_t i, double *v)
{
    if (i < 0) return false;
    if (N(d, i)->type == J_NUM) {
        *v = N(d, i)->num;
        return true;
    }
    if (N(d, i)->type != J_STR || N(d, i)->len == 0 || N(d, i)->len > 64) return false;
    char buf[72], *e;
    jtext(d, i, buf, sizeof buf);
    double x = strtod(buf, &e);
    while (*e == ' ') e++;
    if (*e || e == buf || !isfinite(x)) return false;
    *v = x;
    return true;
}

/* true/false, 1/0, or a string "True"/"true"/"1"/... (older files). */
static bool jbool(const jdoc *d, int32_t i, bool dflt)
{
    if (i < 0) return dflt;
    const jnode *n = N(d, i);
    if (n->type == J_BOOL) return n->b;
    if (n->type == J_NUM) return n->num != 0;
    if (n->type == J_STR) {
        char buf[16];
        jtext(d, i, buf, sizeof buf);
        return !strcmp(buf, "True") || !strcmp(buf, "true") || !strcmp(buf, "1");
    }
    return dflt;
}

/* ------------------------------------------------------- the series */

typedef struct reader {
    jdoc d;
    const char *object;
    char alignment[128];
    int32_t obj_attrs; /* the series' "obj_attrs" object, or -1 */
    bvox_point2 *pts;
    size_t npts, cap;
    double *vals;
    size_t nvals, vcap;
    int64_t open, missing_tform, short_traces;
    char names[MAX_NAMES][64];
    int nnames;
    double lo[2], hi[2];
} reader;

typedef struct secref {
    int64_t num;
    int32_t node;
} secref;

static int cmp_secref(const void *a, const void *b)
{
    const secref *x = a, *y = b;
    return x->num < y->num ? -1 : x->num > y->num;
}

/* A list of numbers: an array (of numbers or numeric strings) or one string
 * of numbers separated by commas/spaces, optionally in brackets. Into
 * r->vals. */
static bvox_status num_list(reader *r, int32_t i, const char *what, const char *sec)
{
    r->nvals = 0;
    const jdoc *d = &r->d;
    if (i < 0) return bvox__fail(BVOX_EFORMAT, "%s: section %s: a trace has no %s", d->name, sec, what);
    if (N(d, i)->type == J_ARR) {
        if (!bvox__grow((void **)&r->vals, sizeof *r->vals, (size_t)N(d, i)->n, &r->vcap, "points"))
            return BVOX_ENOMEM;
        for (int32_t c = N(d, i)->first; c >= 0; c = N(d, c)->next) {
            double v;
            if (!jnum(d, c, &v))
                return jfail(d, d->text + N(d, c)->off, "section %s: a trace's %s holds a "
                             "value that is not a number", sec, what);
            r->vals[r->nvals++] = v;
        }
        return BVOX_OK;
    }
    if (N(d, i)->type != J_STR && N(d, i)->type != J_NUMS)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: a trace's %s is not a list of numbers",
                          d->name, sec, what);
    const char *s = d->text + N(d, i)->off, *e = s + N(d, i)->len;
    while (s < e) {
        while (s < e && strchr(" ,[]\t\r\n", *s)) s++;
        if (s >= e) break;
        const char *t = s;
        while (t < e && !strchr(" ,[]\t\r\n", *t)) t++;
        char buf[72], *end;
        if (t - s > 64) return jfail(d, s, "section %s: a number of %d characters", sec, (int)(t - s));
        memcpy(buf, s, (size_t)(t - s));
        buf[t - s] = '\0';
        double v = strtod(buf, &end);
        if (*end || !isfinite(v))
            return jfail(d, s, "section %s: '%s' in a trace's %s is not a number", sec, buf, what);
        if (!bvox__grow((void **)&r->vals, sizeof *r->vals, r->nvals + 1, &r->vcap, "points"))
            return BVOX_ENOMEM;
        r->vals[r->nvals++] = v;
        s = t;
    }
    return BVOX_OK;
}

static void note_name(reader *r, const char *name)
{
    for (int i = 0; i < r->nnames; i++)
        if (!strcmp(r->names[i], name)) return;
    if (r->nnames < MAX_NAMES) snprintf(r->names[r->nnames++], sizeof r->names[0], "%.63s", name);
}

/* Whether section s holds a closed trace of the selected object (all
 * objects when none is selected). */
static bool section_has(reader *r, int32_t s)
{
    const jdoc *d = &r->d;
    int32_t c = jget(d, s, "contours");
    if (c < 0 || N(d, c)->type != J_OBJ) return false;
    char name[256];
    for (int32_t k = N(d, c)->first; k >= 0; k = N(d, N(d, k)->next)->next) {
        jtext(d, k, name, sizeof name);
        note_name(r, name);
        if (r->object && strcmp(name, r->object)) continue;
        int32_t traces = N(d, k)->next;
        if (N(d, traces)->type != J_ARR) continue;
        for (int32_t t = N(d, traces)->first; t >= 0; t = N(d, t)->next) {
            int32_t cl = N(d, t)->type == J_OBJ ? jget(d, t, "closed") : jat(d, t, 3);
            if (jbool(d, cl, true)) return true;
        }
    }
    return false;
}

static bvox_status add_trace(reader *r, bvox_section *sec, int32_t t, const double tf[6],
                             const char *label)
{
    const jdoc *d = &r->d;
    int obj = N(d, t)->type == J_OBJ;
    if (!obj && N(d, t)->type != J_ARR)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: a trace is neither a list nor an object",
                          d->name, label);
    if (!jbool(d, obj ? jget(d, t, "closed") : jat(d, t, 3), true)) {
        r->open++;
        return BVOX_OK;
    }
    bvox_status st = num_list(r, obj ? jget(d, t, "x") : jat(d, t, 0), "x", label);
    if (st) return st;
    size_t n = r->nvals;
    if (!bvox__grow((void **)&r->pts, sizeof *r->pts, n, &r->cap, "points")) return BVOX_ENOMEM;
    for (size_t i = 0; i < n; i++) r->pts[i].x = r->vals[i];
    if ((st = num_list(r, obj ? jget(d, t, "y") : jat(d, t, 1), "y", label))) return st;
    if (r->nvals != n)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: a trace has %zu x and %zu y values",
                          d->name, label, n, r->nvals);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        double x = r->pts[i].x, y = r->vals[i];
        if (!(fabs(x) <= MAX_UM && fabs(y) <= MAX_UM))
            return bvox__fail(BVOX_EFORMAT, "%s: section %s: a trace point (%g, %g) beyond "
                              "%g um", d->name, label, x, y, MAX_UM);
        bvox_point2 p = {tf[0] * x + tf[1] * y + tf[2], tf[3] * x + tf[4] * y + tf[5]};
        if (!(fabs(p.x) <= MAX_UM && fabs(p.y) <= MAX_UM))
            return bvox__fail(BVOX_EFORMAT, "%s: section %s: the alignment moves a trace point "
                              "beyond %g um", d->name, label, MAX_UM);
        if (m && p.x == r->pts[m - 1].x && p.y == r->pts[m - 1].y) continue;
        r->pts[m++] = p;
    }
    if (m > 1 && r->pts[m - 1].x == r->pts[0].x && r->pts[m - 1].y == r->pts[0].y) m--;
    if (m < 3) {
        r->short_traces++;
        return BVOX_OK;
    }
    if (m > BVOX__MAX_POINTS)
        return bvox__fail(BVOX_ETOOBIG, "%s: section %s: a trace of %zu points", d->name, label, m);
    for (size_t i = 0; i < m; i++) {
        if (r->pts[i].x < r->lo[0]) r->lo[0] = r->pts[i].x;
        if (r->pts[i].y < r->lo[1]) r->lo[1] = r->pts[i].y;
        if (r->pts[i].x > r->hi[0]) r->hi[0] = r->pts[i].x;
        if (r->pts[i].y > r->hi[1]) r->hi[1] = r->pts[i].y;
    }
    st = bvox_section_add_contour(sec, r->pts, (int32_t)m, 0, -1);
    if (st) return bvox__fail(st, "%s: section %s: %s", d->name, label, bvox_errmsg());
    return BVOX_OK;
}

/* The section's transform for alignment al (identity if none: counted). */
static bvox_status section_tform(reader *r, int32_t s, const char *label, const char *al,
                                 double tf[6])
{
    static const double id[6] = {1, 0, 0, 0, 1, 0};
    memcpy(tf, id, sizeof id);
    if (!strcmp(al, "no-alignment")) return BVOX_OK;
    int32_t t = jget(&r->d, jget(&r->d, s, "tforms"), al);
    if (t < 0) {
        r->missing_tform++;
        return BVOX_OK;
    }
    bvox_status st = num_list(r, t, "transform", label);
    if (st) return st;
    if (r->nvals != 6)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: transform '%s' has %zu numbers, not 6",
                          r->d.name, label, al, r->nvals);
    for (int i = 0; i < 6; i++) {
        if (fabs(r->vals[i]) > MAX_UM)
            return bvox__fail(BVOX_EFORMAT, "%s: section %s: transform '%s' has %g", r->d.name,
                              label, al, r->vals[i]);
        tf[i] = r->vals[i];
    }
    if (tf[0] * tf[4] - tf[1] * tf[3] == 0)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: transform '%s' is singular", r->d.name,
                          label, al);
    return BVOX_OK;
}

/* An object with its own alignment (series "obj_attrs": {NAME: {"alignment":
 * A}}) that the section has: that transform, as PyReconstruct does; else
 * the series' one (series_tf). */
static bvox_status object_tform(reader *r, int32_t s, const char *name, const char *label,
                                const double series_tf[6], double tf[6])
{
    const jdoc *d = &r->d;
    int32_t a = jget(d, jget(d, r->obj_attrs, name), "alignment");
    memcpy(tf, series_tf, 6 * sizeof *tf);
    if (a < 0 || N(d, a)->type != J_STR) return BVOX_OK;
    char al[128];
    jtext(d, a, al, sizeof al);
    if (strcmp(al, "no-alignment") && jget(d, jget(d, s, "tforms"), al) < 0) return BVOX_OK;
    return section_tform(r, s, label, al, tf);
}

static bvox_status read_section(reader *r, bvox_contour_stack *s, const secref *ref, double z)
{
    const jdoc *d = &r->d;
    char label[32];
    snprintf(label, sizeof label, "%lld", (long long)ref->num);
    double series_tf[6], tf[6];
    bvox_status st = section_tform(r, ref->node, label, r->alignment, series_tf);
    if (st) return st;
    bvox_section *sec;
    if ((st = bvox_stack_add_section(s, z, label, &sec))) return st;
    int32_t c = jget(d, ref->node, "contours");
    if (c < 0) return BVOX_OK;
    if (N(d, c)->type != J_OBJ)
        return bvox__fail(BVOX_EFORMAT, "%s: section %s: \"contours\" is not an object", d->name,
                          label);
    char name[256];
    for (int32_t k = N(d, c)->first; k >= 0; k = N(d, N(d, k)->next)->next) {
        jtext(d, k, name, sizeof name);
        if (r->object && strcmp(name, r->object)) continue;
        int32_t traces = N(d, k)->next;
        if (N(d, traces)->type != J_ARR)
            return bvox__fail(BVOX_EFORMAT, "%s: section %s: object '%s' is not a list of traces",
                              d->name, label, name);
        if ((st = object_tform(r, ref->node, name, label, series_tf, tf))) return st;
        for (int32_t t = N(d, traces)->first; t >= 0; t = N(d, t)->next)
            if ((st = add_trace(r, sec, t, tf, label))) return st;
    }
    bvox__section_nest(sec);
    return BVOX_OK;
}

/* The sections of either layout, sorted by number; the series node. */
static bvox_status gather(reader *r, secref **out, int32_t *nout, int32_t *series)
{
    const jdoc *d = &r->d;
    int32_t root = 0, secs = jget(d, root, "sections");
    *series = jget(d, root, "series");
    int32_t cap = N(d, root)->n + (secs >= 0 ? N(d, secs)->n : 0);
    if (secs >= 0 && N(d, secs)->type != J_ARR && N(d, secs)->type != J_NUMS)
        return bvox__fail(BVOX_EFORMAT, "%s: \"sections\" is not a list", d->name);
    secref *v = bvox__mem_alloc((size_t)(cap > 0 ? cap : 1) * sizeof *v);
    if (!v) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int32_t n = 0;
    if (secs >= 0 || *series >= 0) {
        int64_t num = 0;
        for (int32_t c = secs >= 0 ? N(d, secs)->first : -1; c >= 0; c = N(d, c)->next, num++)
            if (N(d, c)->type == J_OBJ) v[n++] = (secref){num, c};
    } else {
        char key[256];
        for (int32_t k = N(d, root)->first; k >= 0; k = N(d, N(d, k)->next)->next) {
            jtext(d, k, key, sizeof key);
            const char *ext = strrchr(key, '.');
            ext = ext ? ext + 1 : key;
            size_t len = strlen(ext);
            bool digits = len > 0 && len <= 9;
            for (size_t i = 0; i < len && digits; i++) digits = ext[i] >= '0' && ext[i] <= '9';
            if (digits && N(d, N(d, k)->next)->type == J_OBJ)
                v[n++] = (secref){strtoll(ext, NULL, 10), N(d, k)->next};
            else if (!digits && N(d, N(d, k)->next)->type == J_OBJ &&
                     (*series < 0 || !strcmp(ext, "ser")))
                *series = N(d, k)->next; /* NAME.ser (not "log" or the like) */
        }
    }
    if (n > BVOX__MAX_SECTIONS) {
        free(v);
        return bvox__fail(BVOX_ETOOBIG, "%s: %d sections (at most %d)", d->name, (int)n,
                          BVOX__MAX_SECTIONS);
    }
    qsort(v, (size_t)n, sizeof *v, cmp_secref);
    *out = v;
    *nout = n;
    return BVOX_OK;
}

static bvox_status build(reader *r, bvox_contour_stack *s)
{
    const jdoc *d = &r->d;
    if (N(d, 0)->type != J_OBJ)
        return bvox__fail(BVOX_EFORMAT, "%s: a .jser series is a JSON object", d->name);
    secref *v = NULL;
    int32_t n = 0, series = -1;
    bvox_status st = gather(r, &v, &n, &series);
    if (st) return st;
    snprintf(r->alignment, sizeof r->alignment, "default");
    int32_t al = jget(d, series, "alignment");
    if (al >= 0 && N(d, al)->type == J_STR) jtext(d, al, r->alignment, sizeof r->alignment);
    r->obj_attrs = jget(d, series, "obj_attrs");
    /* thickness of every section, and which to keep */
    double *thick = bvox__mem_alloc((size_t)(n > 0 ? n : 1) * sizeof *thick);
    if (!thick) {
        free(v);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    int32_t first = -1, last = -1;
    for (int32_t i = 0; i < n; i++) {
        int32_t t = jget(d, v[i].node, "thickness");
        thick[i] = 0.05; /* PyReconstruct's default */
        if (t >= 0 && (!jnum(d, t, &thick[i]) || !(thick[i] > 0 && thick[i] <= 1e6))) {
            st = bvox__fail(BVOX_EFORMAT, "%s: section %lld: thickness is not a number in "
                            "(0, 1e6] um", d->name, (long long)v[i].num);
            goto done;
        }
        if (section_has(r, v[i].node)) {
            if (first < 0) first = i;
            last = i;
        }
    }
    if (first < 0) {
        if (r->object) {
            char list[MAX_NAMES * 66] = "";
            for (int i = 0; i < r->nnames; i++) {
                if (i) strcat(list, ", ");
                strcat(list, r->names[i]);
            }
            st = bvox__fail(BVOX_EINVAL, "%s: no closed trace of object '%s' (objects: %s%s)",
                            d->name, r->object, r->nnames ? list : "none",
                            r->nnames == MAX_NAMES ? ", ..." : "");
        } else {
            st = bvox__fail(BVOX_EFORMAT, "%s: no closed trace in any section", d->name);
        }
        goto done;
    }
    double z = 0;
    for (int32_t i = 0; i < first; i++) z += thick[i];
    r->lo[0] = r->lo[1] = INFINITY;
    r->hi[0] = r->hi[1] = -INFINITY;
    for (int32_t i = first; i <= last; i++) {
        if ((st = read_section(r, s, &v[i], z))) goto done;
        z += thick[i];
    }
    double ext = fmax(r->hi[0] - r->lo[0], r->hi[1] - r->lo[1]);
    double pixel = ext > 0 ? ext / 512 : 1;
    strcpy(s->unit, "um");
    s->pixel = pixel;
    s->spacing = thick[first];
    s->given |= BVOX_STACK_GIVEN_UNIT | BVOX_STACK_GIVEN_PIXEL | BVOX_STACK_GIVEN_SPACING;
    if (fabs(r->lo[0]) / pixel > BVOX__MAX_COORD || fabs(r->hi[0]) / pixel > BVOX__MAX_COORD ||
        fabs(r->lo[1]) / pixel > BVOX__MAX_COORD || fabs(r->hi[1]) / pixel > BVOX__MAX_COORD) {
        st = bvox__fail(BVOX_EFORMAT, "%s: the traces lie beyond %g pixels of %g um from the "
                        "origin", d->name, BVOX__MAX_COORD, pixel);
        goto done;
    }
    /* to pixels, y down (a reflection: bvox_section_transform keeps orientations) */
    bvox_xform2 px = {1 / pixel, 0, 0, -1 / pixel, 0, 0};
    for (int32_t i = 0; i < s->nsections; i++) bvox_section_transform(&s->sections[i], &px);
    if (r->open)
        bvox__warn("%s: %lld open trace%s skipped (lines, not outlines)", d->name,
                   (long long)r->open, r->open == 1 ? "" : "s");
    if (r->short_traces)
        bvox__warn("%s: %lld trace%s of fewer than 3 distinct points skipped", d->name,
                   (long long)r->short_traces, r->short_traces == 1 ? "" : "s");
    if (r->missing_tform)
        bvox__warn("%s: %lld section%s without a transform for alignment '%s': points used "
                   "as they are", d->name, (long long)r->missing_tform,
                   r->missing_tform == 1 ? "" : "s", r->alignment);
done:
    free(thick);
    free(v);
    return st;
}

bvox_status bvox_stack_read_jser_memory(const char *data, size_t size, const char *name,
                                        const char *object, bvox_contour_stack **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_read_jser_memory: out is NULL");
    *out = NULL;
    if (!data && size) return bvox__fail(BVOX_EINVAL, "bvox_stack_read_jser_memory: no data");
    if (!name) name = "<memory>";
    if (size > BVOX__MAX_TEXT_BYTES)
        return bvox__fail(BVOX_ETOOBIG, "%s: %zu bytes, over the limit of a contour file", name,
                          size);
    const char *text = data ? data : "";
    reader r = {.d = {.text = text, .p = text, .end = text + size, .name = name},
                .object = object && *object ? object : NULL};
    if (size >= 3 && (unsigned char)text[0] == 0xEF && (unsigned char)text[1] == 0xBB &&
        (unsigned char)text[2] == 0xBF)
        r.d.p += 3; /* a UTF-8 byte order mark */
    int32_t root;
    bvox_status st = jvalue(&r.d, 0, &root);
    if (!st) {
        jws(&r.d);
        if (r.d.p != r.d.end) st = jfail(&r.d, r.d.p, "text after the end of the JSON value");
    }
    bvox_contour_stack *s = NULL;
    if (!st) st = bvox_stack_create(&s);
    if (!st) st = build(&r, s);
    free(r.d.nodes);
    bvox__budget_refund(r.d.charged);
    free(r.pts);
    free(r.vals);
    if (st) {
        bvox_stack_destroy(s);
        return st;
    }
    *out = s;
    return BVOX_OK;
}
