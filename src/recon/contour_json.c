/*
 * contour_json.c — the JSON contour stack format, read and written:
 *
 *   {"unit": "um", "pixel": P, "spacing": S, "width": W, "height": H, "origin": [X, Y],
 *    "sections": [{"z": Z, "name": "s01.png",
 *                  "contours": [[[x, y], [x, y], ...], ...],
 *                  "markers": [[x, y], ...]}, ...]}
 *
 * "sections" is required; "unit" (default ""), "pixel", "spacing" (default
 * 1), "width"/"height" (default 0: the contours' bounds), "origin" (physical
 * position of pixel coordinate (0, 0), default [0, 0]), and per section
 * "z" (default: index * spacing), "name" and "markers" are optional; other
 * keys are skipped (any JSON value, depth-limited). A contour's last point
 * may repeat its first; consecutive duplicates are dropped; fewer than 3
 * distinct points is an error naming the section. Holes are found from
 * containment (bvox__section_nest); filling is even-odd anyway.
 *
 * The reader is a schema-directed pull parser over the text (no DOM, so a
 * large file costs only its contours), written here because no JSON library
 * is a dependency of libbvox (cli/json.c is a writer, and not part of the
 * library). Strict JSON (RFC 8259): no comments, no trailing commas, no NaN.
 * Nesting is limited to BVOX__MAX_DEPTH, the text to BVOX__MAX_TEXT_BYTES.
 * Errors are BVOX_EFORMAT "NAME:LINE:COLUMN: what".
 */
#include "contour_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Keys bvox does not read in a section (another tool's fields): warned about
 * once per key after parsing, with how many sections had it, rather than once
 * per section (a 1000-section file would bury the message). */
#define UNKNOWN_KEYS 8
typedef struct unknown_key {
    char key[32];
    int32_t first, count;
} unknown_key;

typedef struct lex {
    const char *start, *p, *end;
    const char *name;
    unknown_key unknown[UNKNOWN_KEYS];
    int nunknown;
} lex;

static void note_section_key(lex *L, const char *key, int32_t index)
{
    for (int i = 0; i < L->nunknown; i++)
        if (!strcmp(L->unknown[i].key, key)) {
            L->unknown[i].count++;
            return;
        }
    if (L->nunknown == UNKNOWN_KEYS) return;
    unknown_key *u = &L->unknown[L->nunknown++];
    snprintf(u->key, sizeof u->key, "%s", key);
    u->first = index;
    u->count = 1;
}

static void warn_section_keys(const lex *L)
{
    for (int i = 0; i < L->nunknown; i++) {
        const unknown_key *u = &L->unknown[i];
        bvox__warn("%s: section %d%s: unknown key \"%s\" ignored (a section has z, name, "
                   "contours, markers)",
                   L->name, (int)u->first + 1, u->count > 1 ? " and others" : "", u->key);
    }
}

static bvox_status lex_fail(const lex *L, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bvox_status lex_fail(const lex *L, const char *at, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    int64_t line, col;
    bvox__line_col(L->start, (size_t)(at - L->start), &line, &col);
    return bvox__fail(BVOX_EFORMAT, "%s:%lld:%lld: %s", L->name, (long long)line, (long long)col,
                      msg);
}

static void ws(lex *L)
{
    while (L->p < L->end && (*L->p == ' ' || *L->p == '\t' || *L->p == '\n' || *L->p == '\r'))
        L->p++;
}

/* Consume c (after white space) or fail. */
static bvox_status expect(lex *L, char c, const char *what)
{
    ws(L);
    if (L->p >= L->end) return lex_fail(L, L->p, "unexpected end of the file, expected %s", what);
    if (*L->p != c) return lex_fail(L, L->p, "expected %s", what);
    L->p++;
    return BVOX_OK;
}

/* After an element of an array/object: 1 if another follows (a comma was
 * consumed), 0 at the closing bracket (consumed), or an error. */
static bvox_status next_or_close(lex *L, char close, int *more)
{
    ws(L);
    if (L->p < L->end && *L->p == ',') {
        L->p++;
        ws(L);
        if (L->p < L->end && *L->p == close)
            return lex_fail(L, L->p, "a trailing comma before '%c'", close);
        *more = 1;
        return BVOX_OK;
    }
    if (L->p < L->end && *L->p == close) {
        L->p++;
        *more = 0;
        return BVOX_OK;
    }
    return lex_fail(L, L->p, "expected ',' or '%c'", close);
}

/* Opening bracket consumed: 1 if the container is empty (close consumed). */
static int empty_container(lex *L, char close)
{
    ws(L);
    if (L->p < L->end && *L->p == close) {
        L->p++;
        return 1;
    }
    return 0;
}

static int hex4(const char *p, const char *end, uint32_t *v)
{
    if (end - p < 4) return 0;
    uint32_t x = 0;
    for (int i = 0; i < 4; i++) {
        char c = p[i];
        x <<= 4;
        if (c >= '0' && c <= '9') x |= (uint32_t)(c - '0');
        else if (c >= 'a' && c <= 'f') x |= (uint32_t)(c - 'a' + 10);
        else if (c >= 'A' && c <= 'F') x |= (uint32_t)(c - 'A' + 10);
        else return 0;
    }
    *v = x;
    return 1;
}

/* A string: decoded into out (cap bytes incl. NUL; longer strings are
 * truncated) if out is not NULL, else skipped. */
static bvox_status string(lex *L, char *out, size_t cap)
{
    ws(L);
    if (L->p >= L->end || *L->p != '"') return lex_fail(L, L->p, "expected a string");
    const char *at = L->p++;
    size_t n = 0;
    char tmp[8];
    for (;;) {
        if (L->p >= L->end) return lex_fail(L, at, "unterminated string");
        unsigned char c = (unsigned char)*L->p;
        size_t k = 0;
        if (c == '"') {
            L->p++;
            break;
        }
        if (c < 0x20) return lex_fail(L, L->p, "a control character in a string");
        if (c == '\\') {
            if (L->end - L->p < 2) return lex_fail(L, at, "unterminated string");
            char e = L->p[1];
            L->p += 2;
            switch (e) {
            case '"': tmp[k++] = '"'; break;
            case '\\': tmp[k++] = '\\'; break;
            case '/': tmp[k++] = '/'; break;
            case 'b': tmp[k++] = '\b'; break;
            case 'f': tmp[k++] = '\f'; break;
            case 'n': tmp[k++] = '\n'; break;
            case 'r': tmp[k++] = '\r'; break;
            case 't': tmp[k++] = '\t'; break;
            case 'u': {
                uint32_t u;
                if (!hex4(L->p, L->end, &u)) return lex_fail(L, L->p, "bad \\u escape");
                L->p += 4;
                if (u >= 0xD800 && u < 0xDC00 && L->end - L->p >= 6 && L->p[0] == '\\' &&
                    L->p[1] == 'u') {
                    uint32_t lo;
                    if (hex4(L->p + 2, L->end, &lo) && lo >= 0xDC00 && lo < 0xE000) {
                        u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00);
                        L->p += 6;
                    }
                }
                if (u >= 0xD800 && u < 0xE000) u = 0xFFFD; /* a lone surrogate */
                bvox__put_utf8(tmp, &k, u);
                break;
            }
            default: return lex_fail(L, L->p - 2, "bad escape '\\%c'", e);
            }
        } else {
            tmp[k++] = (char)c;
            L->p++;
        }
        if (out)
            for (size_t i = 0; i < k && n + 1 < cap; i++) out[n++] = tmp[i];
    }
    if (out && cap) out[n] = '\0';
    return BVOX_OK;
}

static bvox_status number(lex *L, double *v)
{
    ws(L);
    const char *s = L->p, *p = s;
    if (p < L->end && *p == '-') p++;
    if (p >= L->end || !(*p >= '0' && *p <= '9')) return lex_fail(L, s, "expected a number");
    if (*p == '0') p++;
    else
        while (p < L->end && *p >= '0' && *p <= '9') p++;
    if (p < L->end && *p == '.') {
        p++;
        if (p >= L->end || !(*p >= '0' && *p <= '9')) return lex_fail(L, s, "bad number");
        while (p < L->end && *p >= '0' && *p <= '9') p++;
    }
    if (p < L->end && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < L->end && (*p == '+' || *p == '-')) p++;
        if (p >= L->end || !(*p >= '0' && *p <= '9')) return lex_fail(L, s, "bad number");
        while (p < L->end && *p >= '0' && *p <= '9') p++;
    }
    if (p - s > 400) return lex_fail(L, s, "a number of %d characters", (int)(p - s));
    char buf[404];
    memcpy(buf, s, (size_t)(p - s));
    buf[p - s] = '\0';
    double x = strtod(buf, NULL);
    if (!isfinite(x)) return lex_fail(L, s, "number %s out of range", buf);
    *v = x;
    L->p = p;
    return BVOX_OK;
}

static bvox_status skip_value(lex *L, int depth)
{
    ws(L);
    if (L->p >= L->end) return lex_fail(L, L->p, "unexpected end of the file, expected a value");
    if (depth > BVOX__MAX_DEPTH)
        return lex_fail(L, L->p, "nesting deeper than %d levels", BVOX__MAX_DEPTH);
    char c = *L->p;
    bvox_status st;
    int more = 1;
    if (c == '{') {
        L->p++;
        if (empty_container(L, '}')) return BVOX_OK;
        while (more) {
            if ((st = string(L, NULL, 0)) || (st = expect(L, ':', "':'")) ||
                (st = skip_value(L, depth + 1)) || (st = next_or_close(L, '}', &more)))
                return st;
        }
        return BVOX_OK;
    }
    if (c == '[') {
        L->p++;
        if (empty_container(L, ']')) return BVOX_OK;
        while (more)
            if ((st = skip_value(L, depth + 1)) || (st = next_or_close(L, ']', &more))) return st;
        return BVOX_OK;
    }
    if (c == '"') return string(L, NULL, 0);
    static const char *const words[3] = {"true", "false", "null"};
    for (int i = 0; i < 3; i++) {
        size_t n = strlen(words[i]);
        if ((size_t)(L->end - L->p) >= n && !memcmp(L->p, words[i], n)) {
            L->p += n;
            return BVOX_OK;
        }
    }
    double d;
    return number(L, &d);
}

/* [x, y] */
static bvox_status point(lex *L, bvox_point2 *pt)
{
    bvox_status st;
    if ((st = expect(L, '[', "'[' starting a point [x, y]")) || (st = number(L, &pt->x)) ||
        (st = expect(L, ',', "',' in a point [x, y]")) || (st = number(L, &pt->y)))
        return st;
    ws(L);
    if (L->p < L->end && *L->p == ',') return lex_fail(L, L->p, "a point has more than 2 numbers");
    return expect(L, ']', "']' ending a point [x, y]");
}

typedef struct ptbuf {
    bvox_point2 *p;
    size_t n, cap;
} ptbuf;

static bvox_status section_label_fail(lex *L, const char *at, const bvox_section *sec,
                                      int32_t index, const char *what)
{
    char label[200];
    bvox__section_label(sec, index, label, sizeof label);
    return lex_fail(L, at, "%s: %s", label, what);
}

/* "contours": [[[x, y], ...], ...] */
static bvox_status contours(lex *L, bvox_section *sec, int32_t index, ptbuf *buf)
{
    bvox_status st;
    if ((st = expect(L, '[', "'[' starting the list of contours"))) return st;
    if (empty_container(L, ']')) return BVOX_OK;
    int more = 1;
    while (more) {
        ws(L);
        const char *at = L->p;
        if ((st = expect(L, '[', "'[' starting a contour (a list of [x, y] points)"))) return st;
        buf->n = 0;
        if (!empty_container(L, ']')) {
            int pmore = 1;
            while (pmore) {
                if (buf->n >= BVOX__MAX_POINTS)
                    return lex_fail(L, L->p, "a contour of more than %d points", BVOX__MAX_POINTS);
                if (!bvox__grow((void **)&buf->p, sizeof *buf->p, buf->n + 1, &buf->cap, "points"))
                    return BVOX_ENOMEM;
                if ((st = point(L, &buf->p[buf->n]))) return st;
                const bvox_point2 q = buf->p[buf->n];
                if (fabs(q.x) > BVOX__MAX_COORD || fabs(q.y) > BVOX__MAX_COORD)
                    return lex_fail(L, L->p, "a point beyond +-%g pixels", BVOX__MAX_COORD);
                buf->n++;
                if ((st = next_or_close(L, ']', &pmore))) return st;
            }
        }
        /* drop consecutive duplicates and a repeated first point */
        size_t m = 0;
        for (size_t i = 0; i < buf->n; i++)
            if (m == 0 || buf->p[i].x != buf->p[m - 1].x || buf->p[i].y != buf->p[m - 1].y)
                buf->p[m++] = buf->p[i];
        if (m > 1 && buf->p[0].x == buf->p[m - 1].x && buf->p[0].y == buf->p[m - 1].y) m--;
        if (m < 3) {
            char what[120];
            snprintf(what, sizeof what, "contour %d has %zu distinct points (at least 3 needed)",
                     (int)sec->ncontours + 1, m);
            return section_label_fail(L, at, sec, index, what);
        }
        if ((st = bvox_section_add_contour(sec, buf->p, (int32_t)m, 0, -1))) {
            if (st == BVOX_ENOMEM) return st; /* not a format error */
            char what[300];
            snprintf(what, sizeof what, "%s", bvox_errmsg());
            return section_label_fail(L, at, sec, index, what);
        }
        if ((st = next_or_close(L, ']', &more))) return st;
    }
    return BVOX_OK;
}

static bvox_status markers(lex *L, bvox_section *sec, int32_t index)
{
    bvox_status st;
    if ((st = expect(L, '[', "'[' starting the list of markers"))) return st;
    if (empty_container(L, ']')) return BVOX_OK;
    int more = 1;
    while (more) {
        ws(L);
        const char *at = L->p;
        bvox_point2 m;
        if ((st = point(L, &m))) return st;
        if ((st = bvox_section_add_marker(sec, m))) {
            if (st == BVOX_ENOMEM) return st; /* not a format error */
            char what[300];
            snprintf(what, sizeof what, "%s", bvox_errmsg());
            return section_label_fail(L, at, sec, index, what);
        }
        if ((st = next_or_close(L, ']', &more))) return st;
    }
    return BVOX_OK;
}

static bvox_status section(lex *L, bvox_contour_stack *s, uint8_t *has_z, ptbuf *buf)
{
    bvox_status st;
    ws(L);
    const char *at = L->p;
    if ((st = expect(L, '{', "'{' starting a section"))) return st;
    if (s->nsections >= BVOX__MAX_SECTIONS)
        return lex_fail(L, at, "more than %d sections", BVOX__MAX_SECTIONS);
    int32_t index = s->nsections;
    if ((st = bvox_stack_add_section(s, 0, NULL, NULL))) return st;
    has_z[index] = 0;
    if (empty_container(L, '}')) return BVOX_OK;
    int more = 1;
    while (more) {
        char key[32];
        bvox_section *sec = &s->sections[index];
        if ((st = string(L, key, sizeof key)) || (st = expect(L, ':', "':' after a key"))) return st;
        if (!strcmp(key, "z")) {
            if ((st = number(L, &sec->z))) return st;
            has_z[index] = 1;
        } else if (!strcmp(key, "name")) {
            char name[256];
            if ((st = string(L, name, sizeof name))) return st;
            free(sec->name);
            sec->name = bvox__mem_strdup(name);
            if (!sec->name) return bvox__fail(BVOX_ENOMEM, "out of memory");
        } else if (!strcmp(key, "contours")) {
            if ((st = contours(L, sec, index, buf))) return st;
        } else if (!strcmp(key, "markers")) {
            if ((st = markers(L, sec, index))) return st;
        } else {
            note_section_key(L, key, index);
            if ((st = skip_value(L, 2))) return st;
        }
        if ((st = next_or_close(L, '}', &more))) return st;
    }
    return BVOX_OK;
}

static bvox_status positive(lex *L, const char *at, double v, const char *what)
{
    if (!(v > 0) || v > 1e12) return lex_fail(L, at, "%s must be > 0 and at most 1e12 (it is %g)", what, v);
    return BVOX_OK;
}

static bvox_status parse(lex *L, bvox_contour_stack *s)
{
    bvox_status st;
    uint8_t *has_z = bvox__mem_alloc(BVOX__MAX_SECTIONS);
    ptbuf buf = {NULL, 0, 0};
    if (!has_z) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int got_sections = 0, more = 1;
    ws(L);
    if (L->p + 3 <= L->end && (unsigned char)L->p[0] == 0xEF && (unsigned char)L->p[1] == 0xBB &&
        (unsigned char)L->p[2] == 0xBF)
        L->p += 3; /* a UTF-8 byte order mark */
    if ((st = expect(L, '{', "'{': a contour stack is a JSON object"))) goto done;
    if (empty_container(L, '}')) more = 0;
    while (more) {
        char key[32];
        ws(L);
        const char *at;
        if ((st = string(L, key, sizeof key)) || (st = expect(L, ':', "':' after a key"))) goto done;
        ws(L);
        at = L->p;
        if (!strcmp(key, "unit")) {
            char unit[64];
            if ((st = string(L, unit, sizeof unit))) goto done;
            if (strlen(unit) >= sizeof s->unit) {
                st = lex_fail(L, at, "unit \"%s\" is longer than %zu characters", unit,
                              sizeof s->unit - 1);
                goto done;
            }
            strcpy(s->unit, unit);
            if (unit[0]) s->given |= BVOX_STACK_GIVEN_UNIT;
        } else if (!strcmp(key, "pixel") || !strcmp(key, "spacing")) {
            double v;
            if ((st = number(L, &v)) || (st = positive(L, at, v, key))) goto done;
            if (key[0] == 'p') s->pixel = v, s->given |= BVOX_STACK_GIVEN_PIXEL;
            else s->spacing = v, s->given |= BVOX_STACK_GIVEN_SPACING;
        } else if (!strcmp(key, "origin")) {
            bvox_point2 o;
            if ((st = point(L, &o))) goto done;
            s->origin[0] = o.x;
            s->origin[1] = o.y;
        } else if (!strcmp(key, "width") || !strcmp(key, "height")) {
            double v;
            if ((st = number(L, &v))) goto done;
            if (!(v >= 0 && v <= BVOX_MAX_DIM && v == floor(v))) {
                st = lex_fail(L, at, "%s must be an integer in 0..%d", key, BVOX_MAX_DIM);
                goto done;
            }
            if (key[0] == 'w') s->width = (int32_t)v;
            else s->height = (int32_t)v;
        } else if (!strcmp(key, "sections")) {
            if (got_sections) {
                st = lex_fail(L, at, "\"sections\" appears twice");
                goto done;
            }
            got_sections = 1;
            if ((st = expect(L, '[', "'[' starting the list of sections"))) goto done;
            int smore = !empty_container(L, ']');
            while (smore) {
                if ((st = section(L, s, has_z, &buf)) || (st = next_or_close(L, ']', &smore)))
                    goto done;
            }
        } else {
            bvox__warn("%s: unknown key \"%s\" ignored (a contour stack has unit, pixel, "
                       "spacing, width, height, origin, sections)",
                       L->name, key);
            if ((st = skip_value(L, 1))) goto done;
        }
        if ((st = next_or_close(L, '}', &more))) goto done;
    }
    ws(L);
    if (L->p != L->end) {
        st = lex_fail(L, L->p, "text after the end of the JSON object");
        goto done;
    }
    if (!got_sections) {
        st = lex_fail(L, L->start, "no \"sections\" list");
        goto done;
    }
    warn_section_keys(L);
    for (int32_t i = 0; i < s->nsections; i++) {
        if (!has_z[i]) s->sections[i].z = i * s->spacing;
        s->sections[i].z_from_index = !has_z[i];
        bvox__section_nest(&s->sections[i]);
    }
    st = BVOX_OK;
done:
    free(has_z);
    free(buf.p);
    return st;
}

bvox_status bvox_stack_read_json_memory(const char *data, size_t size, const char *name,
                                        bvox_contour_stack **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_read_json_memory: out is NULL");
    *out = NULL;
    bvox_status st = bvox__text_input_check("bvox_stack_read_json_memory", data, size, &name);
    if (st) return st;
    bvox_contour_stack *s = NULL;
    st = bvox_stack_create(&s);
    if (st) return st;
    const char *text = data ? data : "";
    lex L = {.start = text, .p = text, .end = text + size, .name = name};
    st = parse(&L, s);
    if (st) {
        bvox_stack_destroy(s);
        return st;
    }
    *out = s;
    return BVOX_OK;
}

/* ------------------------------------------------------------- writer */

static void write_point(bvox__strbuf *b, bvox_point2 p)
{
    bvox__sb_puts(b, "[");
    bvox__sb_double(b, p.x);
    bvox__sb_puts(b, ", ");
    bvox__sb_double(b, p.y);
    bvox__sb_puts(b, "]");
}

bvox_status bvox_stack_write_json(const char *path, const bvox_contour_stack *stack)
{
    bvox__clear_error();
    if (!path || !stack) return bvox__fail(BVOX_EINVAL, "bvox_stack_write_json: NULL argument");
    bvox__strbuf b = {0};
    char unit[sizeof stack->unit + 1];
    memcpy(unit, stack->unit, sizeof stack->unit);
    unit[sizeof stack->unit] = '\0';
    bvox__sb_puts(&b, "{\"unit\": ");
    bvox__sb_json_string(&b, unit);
    bvox__sb_puts(&b, ", \"pixel\": ");
    bvox__sb_double(&b, stack->pixel);
    bvox__sb_puts(&b, ", \"spacing\": ");
    bvox__sb_double(&b, stack->spacing);
    if (stack->width > 0 && stack->height > 0)
        bvox__sb_printf(&b, ", \"width\": %d, \"height\": %d", (int)stack->width,
                        (int)stack->height);
    if (stack->origin[0] != 0 || stack->origin[1] != 0) {
        bvox__sb_puts(&b, ", \"origin\": [");
        bvox__sb_double(&b, stack->origin[0]);
        bvox__sb_puts(&b, ", ");
        bvox__sb_double(&b, stack->origin[1]);
        bvox__sb_puts(&b, "]");
    }
    bvox__sb_puts(&b, ",\n \"sections\": [");
    for (int32_t i = 0; i < stack->nsections; i++) {
        const bvox_section *sec = &stack->sections[i];
        bvox__sb_puts(&b, i ? ",\n  {\"z\": " : "\n  {\"z\": ");
        bvox__sb_double(&b, sec->z);
        if (sec->name) {
            bvox__sb_puts(&b, ", \"name\": ");
            bvox__sb_json_string(&b, sec->name);
        }
        bvox__sb_puts(&b, ",\n   \"contours\": [");
        for (int32_t c = 0; c < sec->ncontours; c++) {
            const bvox_contour *ct = &sec->contours[c];
            bvox__sb_puts(&b, c ? ",\n    [" : "\n    [");
            for (int32_t k = 0; k < ct->npoints; k++) {
                if (k) bvox__sb_puts(&b, ", ");
                write_point(&b, ct->points[k]);
            }
            bvox__sb_puts(&b, "]");
        }
        bvox__sb_puts(&b, sec->ncontours ? "]" : "]");
        if (sec->nmarkers) {
            bvox__sb_puts(&b, ",\n   \"markers\": [");
            for (int32_t m = 0; m < sec->nmarkers; m++) {
                if (m) bvox__sb_puts(&b, ", ");
                write_point(&b, sec->markers[m]);
            }
            bvox__sb_puts(&b, "]");
        }
        bvox__sb_puts(&b, "}");
    }
    bvox__sb_puts(&b, "\n ]}\n");
    bvox_status st = bvox__sb_write_file(&b, path);
    bvox__sb_free(&b);
    return st;
}
