/*
 * contour_svg.c — one SVG document per section, read and written.
 *
 * Reading: <polygon points>, <polyline points> (closed, as every contour),
 * <path d> with M/L/H/V/C/S/Q/T/Z in absolute and relative form (cubic and
 * quadratic Bezier segments flattened to BVOX__SVG_TOLERANCE pixels after the
 * transform, so the tolerance is in output pixels), <rect> (square corners:
 * rx/ry are ignored), <circle>/<ellipse> (flattened). A <circle> whose class
 * or id contains "marker" is a reference marker at its centre, not a contour.
 * transform attributes (matrix, translate, scale, rotate, skewX, skewY) on the
 * element and on its <g>/<svg> ancestors are applied. Not supported, refused
 * with a message: elliptical arcs (A/a) in paths. Ignored: <use>, text, style
 * sheets, display/visibility, and everything inside <defs>, <clipPath>,
 * <mask>, <symbol>, <pattern>, <marker>. User units are pixels; the root's
 * width/height (plain numbers or "px", with no viewBox or "0 0 W H") give the
 * image size; the root's data-z, data-pixel, data-spacing, data-unit and
 * data-name attributes (written by bvox) give the section's z and the stack's
 * scale.
 *
 * Writing: section_0001.svg, ... in a folder (atomically through
 * bvox__dir_sink_*): one <path fill-rule="evenodd"> with a subpath per
 * contour, markers as <circle class="marker">, the data-* attributes above.
 */
#include "contour_internal.h"
#include "io/io.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define BVOX__SVG_TOLERANCE 0.1
#define MAX_SEGMENTS 1024 /* per Bezier segment or ellipse */

typedef struct svg_reader {
    bvox__xml x;
    bvox_contour_stack *stack;
    bvox_section *sec;
    int32_t index;
    bvox_xform2 ctm[BVOX__MAX_DEPTH + 1];
    int skip_depth; /* > 0: inside <defs> etc. (depth where it started) */
    bvox_point2 *pts;
    size_t npts, cap;
    const char *elem_at;
    double canvas[4];   /* x, y, w, h of the drawing (viewBox, else width x height) */
    const char *select; /* --svg-select list, or NULL: every visible outline */
    int hidden_depth;   /* > 0: inside a hidden element (depth where it started) */
    int selected_depth; /* > 0: inside an element the selection names */
    int n_background, n_hidden, n_unselected;
    int64_t background_line;
} svg_reader;

static bvox_status sec_fail(svg_reader *r, const char *what)
{
    char label[200];
    bvox__section_label(r->sec, r->index, label, sizeof label);
    return bvox__xml_fail(&r->x, r->elem_at, "%s: %s", label, what);
}

/* ---- numbers in attribute text (SVG grammar: "1.5.5" is 1.5 .5, "1-2" is 1 -2) ---- */

typedef struct scan {
    const char *p, *end;
} scan;

static void skip_sep(scan *s)
{
    while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r' ||
                             *s->p == ','))
        s->p++;
}

/* 1 and the number, 0 if there is none here (p unchanged). */
static int scan_number(scan *s, double *v)
{
    skip_sep(s);
    const char *p = s->p, *b = p;
    if (p < s->end && (*p == '+' || *p == '-')) p++;
    const char *digits = p;
    while (p < s->end && *p >= '0' && *p <= '9') p++;
    int nint = (int)(p - digits), nfrac = 0;
    if (p < s->end && *p == '.') {
        p++;
        const char *f = p;
        while (p < s->end && *p >= '0' && *p <= '9') p++;
        nfrac = (int)(p - f);
    }
    if (nint + nfrac == 0) return 0;
    if (p < s->end && (*p == 'e' || *p == 'E')) {
        const char *e = p + 1;
        if (e < s->end && (*e == '+' || *e == '-')) e++;
        if (e < s->end && *e >= '0' && *e <= '9') {
            while (e < s->end && *e >= '0' && *e <= '9') e++;
            p = e;
        }
    }
    if (p - b > 300) return 0;
    char buf[304];
    memcpy(buf, b, (size_t)(p - b));
    buf[p - b] = '\0';
    double x = strtod(buf, NULL);
    if (!isfinite(x)) return 0;
    *v = x;
    s->p = p;
    return 1;
}

/* ---- transforms ---- */

static bvox_status parse_transform(svg_reader *r, const char *text, bvox_xform2 *out)
{
    bvox_xform2 t = {1, 0, 0, 1, 0, 0};
    scan s = {text, text + strlen(text)};
    for (;;) {
        skip_sep(&s);
        if (s.p >= s.end) break;
        const char *name = s.p;
        while (s.p < s.end && ((*s.p >= 'a' && *s.p <= 'z') || (*s.p >= 'A' && *s.p <= 'Z'))) s.p++;
        size_t nl = (size_t)(s.p - name);
        while (s.p < s.end && (*s.p == ' ' || *s.p == '\t' || *s.p == '\n' || *s.p == '\r')) s.p++;
        if (nl == 0 || s.p >= s.end || *s.p != '(')
            return sec_fail(r, "a transform that is not a list of name(numbers)");
        s.p++;
        double a[6];
        int n = 0;
        while (n < 6 && scan_number(&s, &a[n])) n++;
        skip_sep(&s);
        if (s.p >= s.end || *s.p != ')') return sec_fail(r, "a transform with a bad argument list");
        s.p++;
        bvox_xform2 m;
#define IS(w) (nl == strlen(w) && !memcmp(name, w, nl))
        if (IS("matrix") && n == 6) {
            m = (bvox_xform2){a[0], a[2], a[1], a[3], a[4], a[5]};
        } else if (IS("translate") && (n == 1 || n == 2)) {
            m = (bvox_xform2){1, 0, 0, 1, a[0], n == 2 ? a[1] : 0};
        } else if (IS("scale") && (n == 1 || n == 2)) {
            m = (bvox_xform2){a[0], 0, 0, n == 2 ? a[1] : a[0], 0, 0};
        } else if (IS("rotate") && (n == 1 || n == 3)) {
            double c = cos(a[0] * M_PI / 180), sn = sin(a[0] * M_PI / 180);
            double cx = n == 3 ? a[1] : 0, cy = n == 3 ? a[2] : 0;
            m = (bvox_xform2){c, -sn, sn, c, cx - c * cx + sn * cy, cy - sn * cx - c * cy};
        } else if (IS("skewX") && n == 1) {
            m = (bvox_xform2){1, tan(a[0] * M_PI / 180), 0, 1, 0, 0};
        } else if (IS("skewY") && n == 1) {
            m = (bvox_xform2){1, 0, tan(a[0] * M_PI / 180), 1, 0, 0};
        } else {
            char what[120];
            snprintf(what, sizeof what, "unsupported transform %.*s with %d numbers",
                     (int)(nl > 40 ? 40 : nl), name, n);
            return sec_fail(r, what);
        }
#undef IS
        t = bvox_xform2_compose(&m, &t); /* "A B": p -> A(B(p)); B is applied first */
    }
    if (!isfinite(t.a + t.b + t.c + t.d + t.tx + t.ty)) return sec_fail(r, "a non-finite transform");
    *out = t;
    return BVOX_OK;
}

/* ---- points of the contour being built ---- */

static bvox_status add_pt(svg_reader *r, bvox_point2 p)
{
    if (r->npts >= BVOX__MAX_POINTS) return sec_fail(r, "an outline of too many points");
    if (!isfinite(p.x) || !isfinite(p.y) || fabs(p.x) > BVOX__MAX_COORD ||
        fabs(p.y) > BVOX__MAX_COORD)
        return sec_fail(r, "a point is not finite or beyond the coordinate limit");
    if (!bvox__grow((void **)&r->pts, sizeof *r->pts, r->npts + 1, &r->cap, "points"))
        return BVOX_ENOMEM;
    r->pts[r->npts++] = p;
    return BVOX_OK;
}

/* Emit the points gathered so far as one contour (closed, duplicates dropped). */
static bvox_status flush(svg_reader *r)
{
    size_t m = 0;
    for (size_t i = 0; i < r->npts; i++)
        if (m == 0 || r->pts[i].x != r->pts[m - 1].x || r->pts[i].y != r->pts[m - 1].y)
            r->pts[m++] = r->pts[i];
    if (m > 1 && r->pts[0].x == r->pts[m - 1].x && r->pts[0].y == r->pts[m - 1].y) m--;
    size_t had = r->npts;
    r->npts = 0;
    if (had == 0) return BVOX_OK;
    if (m < 3) {
        char what[160];
        snprintf(what, sizeof what, "<%.*s>: an outline with %zu distinct points (at least 3 needed)",
                 (int)r->x.taglen, r->x.tag, m);
        return sec_fail(r, what);
    }
    bvox_status st = bvox_section_add_contour(r->sec, r->pts, (int32_t)m, 0, -1);
    if (st) {
        if (st == BVOX_ENOMEM) return st; /* not a format error */
        char what[300];
        snprintf(what, sizeof what, "%s", bvox_errmsg());
        return sec_fail(r, what);
    }
    return BVOX_OK;
}

static int segments_for(double second_diff, double k)
{
    double n = ceil(sqrt(k * second_diff / BVOX__SVG_TOLERANCE));
    if (!(n >= 1)) n = 1;
    return n > MAX_SEGMENTS ? MAX_SEGMENTS : (int)n;
}

/* Control points already transformed. */
static bvox_status cubic(svg_reader *r, bvox_point2 p0, bvox_point2 p1, bvox_point2 p2,
                         bvox_point2 p3)
{
    double d1 = hypot(p0.x - 2 * p1.x + p2.x, p0.y - 2 * p1.y + p2.y);
    double d2 = hypot(p1.x - 2 * p2.x + p3.x, p1.y - 2 * p2.y + p3.y);
    int n = segments_for(d1 > d2 ? d1 : d2, 0.75);
    bvox_status st;
    for (int i = 1; i <= n; i++) {
        double t = (double)i / n, u = 1 - t;
        double a = u * u * u, b = 3 * u * u * t, c = 3 * u * t * t, d = t * t * t;
        if ((st = add_pt(r, (bvox_point2){a * p0.x + b * p1.x + c * p2.x + d * p3.x,
                                          a * p0.y + b * p1.y + c * p2.y + d * p3.y})))
            return st;
    }
    return BVOX_OK;
}

static bvox_status quad(svg_reader *r, bvox_point2 p0, bvox_point2 p1, bvox_point2 p2)
{
    int n = segments_for(hypot(p0.x - 2 * p1.x + p2.x, p0.y - 2 * p1.y + p2.y), 0.25);
    bvox_status st;
    for (int i = 1; i <= n; i++) {
        double t = (double)i / n, u = 1 - t;
        double a = u * u, b = 2 * u * t, c = t * t;
        if ((st = add_pt(r, (bvox_point2){a * p0.x + b * p1.x + c * p2.x,
                                          a * p0.y + b * p1.y + c * p2.y})))
            return st;
    }
    return BVOX_OK;
}

static bvox_status path(svg_reader *r, const char *d, const bvox_xform2 *T)
{
    scan s = {d, d + strlen(d)};
    bvox_point2 cur = {0, 0}, start = {0, 0}, ctrl = {0, 0}; /* untransformed */
    char prev = 0, cmd = 0;
    bvox_status st;
#define TP(p) bvox_xform2_apply(T, (p))
    for (;;) {
        skip_sep(&s);
        if (s.p >= s.end) break;
        char c = *s.p;
        if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) {
            cmd = c;
            s.p++;
        } else if (!cmd) {
            return sec_fail(r, "<path>: path data does not start with a command");
        } else if (cmd == 'M') {
            cmd = 'L'; /* numbers after M are implicit L */
        } else if (cmd == 'm') {
            cmd = 'l';
        } else if (cmd == 'Z' || cmd == 'z') {
            return sec_fail(r, "<path>: numbers after Z");
        }
        int rel = cmd >= 'a';
        char C = (char)(rel ? cmd - 32 : cmd);
        double a[6];
        int need = C == 'M' || C == 'L' || C == 'T' ? 2 : C == 'H' || C == 'V' ? 1
                   : C == 'C' ? 6 : C == 'S' || C == 'Q' ? 4 : 0;
        if (C == 'A') return sec_fail(r, "<path>: elliptical arcs (A) are not supported");
        if (C != 'M' && C != 'L' && C != 'H' && C != 'V' && C != 'C' && C != 'S' && C != 'Q' &&
            C != 'T' && C != 'Z') {
            char what[80];
            snprintf(what, sizeof what, "<path>: unknown command '%c'", cmd);
            return sec_fail(r, what);
        }
        for (int i = 0; i < need; i++)
            if (!scan_number(&s, &a[i])) {
                char what[80];
                snprintf(what, sizeof what, "<path>: command '%c' needs %d numbers", cmd, need);
                return sec_fail(r, what);
            }
        bvox_point2 o = rel ? cur : (bvox_point2){0, 0};
        switch (C) {
        case 'M':
            if ((st = flush(r))) return st;
            cur = start = (bvox_point2){o.x + a[0], o.y + a[1]};
            if ((st = add_pt(r, TP(cur)))) return st;
            ctrl = cur;
            break;
        case 'L':
        case 'H':
        case 'V':
            if (r->npts == 0 && (st = add_pt(r, TP(cur)))) return st;
            if (C == 'L') cur = (bvox_point2){o.x + a[0], o.y + a[1]};
            else if (C == 'H') cur.x = (rel ? cur.x : 0) + a[0];
            else cur.y = (rel ? cur.y : 0) + a[0];
            if ((st = add_pt(r, TP(cur)))) return st;
            ctrl = cur;
            break;
        case 'C':
        case 'S': {
            bvox_point2 c1, c2, e;
            if (C == 'C') {
                c1 = (bvox_point2){o.x + a[0], o.y + a[1]};
                c2 = (bvox_point2){o.x + a[2], o.y + a[3]};
                e = (bvox_point2){o.x + a[4], o.y + a[5]};
            } else {
                int smooth = prev == 'C' || prev == 'S';
                c1 = smooth ? (bvox_point2){2 * cur.x - ctrl.x, 2 * cur.y - ctrl.y} : cur;
                c2 = (bvox_point2){o.x + a[0], o.y + a[1]};
                e = (bvox_point2){o.x + a[2], o.y + a[3]};
            }
            if (r->npts == 0 && (st = add_pt(r, TP(cur)))) return st;
            if ((st = cubic(r, TP(cur), TP(c1), TP(c2), TP(e)))) return st;
            ctrl = c2;
            cur = e;
            break;
        }
        case 'Q':
        case 'T': {
            bvox_point2 c1, e;
            if (C == 'Q') {
                c1 = (bvox_point2){o.x + a[0], o.y + a[1]};
                e = (bvox_point2){o.x + a[2], o.y + a[3]};
            } else {
                int smooth = prev == 'Q' || prev == 'T';
                c1 = smooth ? (bvox_point2){2 * cur.x - ctrl.x, 2 * cur.y - ctrl.y} : cur;
                e = (bvox_point2){o.x + a[0], o.y + a[1]};
            }
            if (r->npts == 0 && (st = add_pt(r, TP(cur)))) return st;
            if ((st = quad(r, TP(cur), TP(c1), TP(e)))) return st;
            ctrl = c1;
            cur = e;
            break;
        }
        case 'Z':
            if ((st = flush(r))) return st;
            cur = ctrl = start;
            break;
        }
        prev = C;
        if (!isfinite(cur.x) || !isfinite(cur.y) || fabs(cur.x) > 1e15 || fabs(cur.y) > 1e15)
            return sec_fail(r, "<path>: coordinates out of range");
    }
#undef TP
    return flush(r);
}

static bvox_status points_attr(svg_reader *r, const char *text, const bvox_xform2 *T)
{
    scan s = {text, text + strlen(text)};
    double x, y;
    bvox_status st;
    while (scan_number(&s, &x)) {
        if (!scan_number(&s, &y)) return sec_fail(r, "points: an odd count of numbers");
        if ((st = add_pt(r, bvox_xform2_apply(T, (bvox_point2){x, y})))) return st;
    }
    skip_sep(&s);
    if (s.p < s.end) return sec_fail(r, "points: not a list of numbers");
    return flush(r);
}

/* A number attribute (0 when absent); 1 if present and valid. */
static int num_attr(svg_reader *r, const char *name, double *v, bvox_status *st)
{
    *v = 0;
    const bvox__xml_attr *a = bvox__xml_attr_get(&r->x, name);
    if (!a) return 0;
    char *t = bvox__xml_attr_dup(&r->x, a, st);
    if (!t) return 0;
    scan s = {t, t + strlen(t)};
    int ok = scan_number(&s, v);
    if (ok && s.p < s.end && !strcmp(s.p, "px")) s.p = s.end;
    skip_sep(&s);
    ok = ok && s.p == s.end;
    free(t);
    if (!ok) {
        char what[120];
        snprintf(what, sizeof what, "attribute %s is not a number", name);
        *st = sec_fail(r, what);
    }
    return ok;
}

/* A length: a number, "Npx", or "N%" of ref (a rect's 100% x 100%). Other
 * units are an error, as in num_attr. 0 when absent. */
static int length_attr(svg_reader *r, const char *name, double ref, double *v, bvox_status *st)
{
    *v = 0;
    const bvox__xml_attr *a = bvox__xml_attr_get(&r->x, name);
    if (!a || a->vlen == 0 || a->value[a->vlen - 1] != '%') return num_attr(r, name, v, st);
    char *t = bvox__xml_attr_dup(&r->x, a, st);
    if (!t) return 0;
    t[strlen(t) - 1] = '\0';
    scan sc = {t, t + strlen(t)};
    int ok = scan_number(&sc, v);
    skip_sep(&sc);
    ok = ok && sc.p == sc.end;
    free(t);
    if (!ok) {
        char what[120];
        snprintf(what, sizeof what, "attribute %s is not a number", name);
        *st = sec_fail(r, what);
        return 0;
    }
    *v *= ref / 100;
    return 1;
}

/* The root's width/height as plain numbers (or px), without failing on the
 * units editors write ("210mm", "100%"): the viewBox then gives the canvas. */
static int plain_length(const bvox__xml *x, const char *name, double *v)
{
    const bvox__xml_attr *a = bvox__xml_attr_get(x, name);
    if (!a || a->vlen == 0 || a->vlen > 60) return 0;
    char t[64];
    memcpy(t, a->value, a->vlen);
    t[a->vlen] = '\0';
    scan sc = {t, t + a->vlen};
    if (!scan_number(&sc, v)) return 0;
    if (sc.p < sc.end && !strcmp(sc.p, "px")) sc.p = sc.end;
    skip_sep(&sc);
    return sc.p == sc.end;
}

static bvox_status ellipse(svg_reader *r, double cx, double cy, double rx, double ry,
                           const bvox_xform2 *T)
{
    double scale = sqrt(fabs(T->a * T->d - T->b * T->c));
    double rmax = (rx > ry ? rx : ry) * scale;
    /* chord error r (1 - cos(pi / n)) ~ r pi^2 / (2 n^2) <= tolerance */
    double fn = ceil(M_PI * sqrt(rmax / (2 * BVOX__SVG_TOLERANCE)));
    int n = fn < 8 ? 8 : fn > MAX_SEGMENTS ? MAX_SEGMENTS : (int)fn;
    bvox_status st;
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n;
        if ((st = add_pt(r, bvox_xform2_apply(T, (bvox_point2){cx + rx * cos(a), cy + ry * sin(a)}))))
            return st;
    }
    return flush(r);
}

static int attr_contains(const bvox__xml *x, const char *name, const char *word)
{
    const bvox__xml_attr *a = bvox__xml_attr_get(x, name);
    if (!a) return 0;
    size_t n = strlen(word);
    for (size_t i = 0; i + n <= a->vlen; i++) {
        size_t k = 0;
        while (k < n && (a->value[i + k] | 0x20) == word[k]) k++;
        if (k == n) return 1;
    }
    return 0;
}

static bvox_status root_attrs(svg_reader *r, int *has_z)
{
    bvox_status st = BVOX_OK;
    double v, w = 0, h = 0;
    int hw = plain_length(&r->x, "width", &w);
    int hh = plain_length(&r->x, "height", &h);
    if (hw && hh) {
        r->canvas[2] = w;
        r->canvas[3] = h;
    }
    const bvox__xml_attr *vb = bvox__xml_attr_get(&r->x, "viewBox");
    int vb_ok = 1;
    if (vb) {
        char *t = bvox__xml_attr_dup(&r->x, vb, &st);
        if (!t) return st;
        scan s = {t, t + strlen(t)};
        double b[4] = {0, 0, 0, 0};
        int n = 0;
        while (n < 4 && scan_number(&s, &b[n])) n++;
        vb_ok = n == 4 && b[0] == 0 && b[1] == 0 && b[2] == w && b[3] == h;
        if (n == 4 && b[2] > 0 && b[3] > 0) memcpy(r->canvas, b, sizeof b);
        free(t);
    }
    if (hw && hh && vb_ok && w >= 1 && h >= 1 && w <= BVOX_MAX_DIM && h <= BVOX_MAX_DIM &&
        w == floor(w) && h == floor(h) && r->stack->width == 0 && r->stack->height == 0) {
        r->stack->width = (int32_t)w;
        r->stack->height = (int32_t)h;
    }
    if (num_attr(r, "data-z", &v, &st)) {
        r->sec->z = v;
        r->sec->z_from_index = 0;
        *has_z = 1;
    }
    if (st) return st;
    if (num_attr(r, "data-pixel", &v, &st) && v > 0 && v < 1e12) {
        r->stack->pixel = v;
        r->stack->given |= BVOX_STACK_GIVEN_PIXEL;
    }
    if (st) return st;
    if (num_attr(r, "data-spacing", &v, &st) && v > 0 && v < 1e12) {
        r->stack->spacing = v;
        r->stack->given |= BVOX_STACK_GIVEN_SPACING;
    }
    if (st) return st;
    const bvox__xml_attr *a = bvox__xml_attr_get(&r->x, "data-unit");
    if (a) {
        char *t = bvox__xml_attr_dup(&r->x, a, &st);
        if (!t) return st;
        if (strlen(t) < sizeof r->stack->unit) {
            strcpy(r->stack->unit, t);
            if (t[0]) r->stack->given |= BVOX_STACK_GIVEN_UNIT;
        }
        free(t);
    }
    a = bvox__xml_attr_get(&r->x, "data-name");
    if (a) {
        char *t = bvox__xml_attr_dup(&r->x, a, &st);
        if (!t) return st;
        free(r->sec->name);
        r->sec->name = t;
    }
    return BVOX_OK;
}

static bvox_status element(svg_reader *r, const bvox_xform2 *T)
{
    bvox_status st = BVOX_OK;
    bvox__xml *x = &r->x;
    const char *attr = bvox__xml_is(x, "path") ? "d"
                       : bvox__xml_is(x, "polygon") || bvox__xml_is(x, "polyline") ? "points"
                                                                                  : NULL;
    if (attr) {
        const bvox__xml_attr *a = bvox__xml_attr_get(x, attr);
        if (!a) return BVOX_OK; /* nothing drawn */
        char *t = bvox__xml_attr_dup(x, a, &st);
        if (!t) return st;
        st = attr[0] == 'd' ? path(r, t, T) : points_attr(r, t, T);
        free(t);
        return st;
    }
    double cx, cy, rx, ry, w, h;
    if (bvox__xml_is(x, "circle")) {
        num_attr(r, "cx", &cx, &st);
        if (!st) num_attr(r, "cy", &cy, &st);
        if (!st) num_attr(r, "r", &rx, &st);
        if (st) return st;
        if (attr_contains(x, "class", "marker") || attr_contains(x, "id", "marker")) {
            st = bvox_section_add_marker(r->sec, bvox_xform2_apply(T, (bvox_point2){cx, cy}));
            if (st) {
                if (st == BVOX_ENOMEM) return st; /* not a format error */
                char what[300];
                snprintf(what, sizeof what, "%s", bvox_errmsg());
                return sec_fail(r, what);
            }
            return BVOX_OK;
        }
        return rx > 0 ? ellipse(r, cx, cy, rx, rx, T) : BVOX_OK;
    }
    if (bvox__xml_is(x, "ellipse")) {
        num_attr(r, "cx", &cx, &st);
        if (!st) num_attr(r, "cy", &cy, &st);
        if (!st) num_attr(r, "rx", &rx, &st);
        if (!st) num_attr(r, "ry", &ry, &st);
        if (st) return st;
        return rx > 0 && ry > 0 ? ellipse(r, cx, cy, rx, ry, T) : BVOX_OK;
    }
    if (bvox__xml_is(x, "rect")) {
        num_attr(r, "x", &cx, &st);
        if (!st) num_attr(r, "y", &cy, &st);
        if (!st) length_attr(r, "width", r->canvas[2], &w, &st);
        if (!st) length_attr(r, "height", r->canvas[3], &h, &st);
        if (st) return st;
        if (!(w > 0 && h > 0)) return BVOX_OK;
        bvox_point2 c[4] = {{cx, cy}, {cx + w, cy}, {cx + w, cy + h}, {cx, cy + h}};
        for (int i = 0; i < 4; i++)
            if ((st = add_pt(r, bvox_xform2_apply(T, c[i])))) return st;
        return flush(r);
    }
    return BVOX_OK;
}

static bool is_container_skipped(const bvox__xml *x)
{
    static const char *const skipped[] = {"defs", "clipPath", "mask", "symbol", "pattern",
                                          "marker", "metadata", "style", "title", "desc"};
    for (size_t i = 0; i < sizeof skipped / sizeof skipped[0]; i++)
        if (bvox__xml_is(x, skipped[i])) return true;
    return false;
}

/* A <rect> covering the whole canvas: the editor's page, not a tracing. */
static int is_background(svg_reader *r, const bvox_xform2 *T, bvox_status *st)
{
    double x0, y0, w, h;
    num_attr(r, "x", &x0, st);
    if (!*st) num_attr(r, "y", &y0, st);
    if (!*st) length_attr(r, "width", r->canvas[2], &w, st);
    if (!*st) length_attr(r, "height", r->canvas[3], &h, st);
    if (*st || !(w > 0 && h > 0)) return 0;
    bvox_point2 c[4] = {{x0, y0}, {x0 + w, y0}, {x0 + w, y0 + h}, {x0, y0 + h}};
    for (int i = 0; i < 4; i++) c[i] = bvox_xform2_apply(T, c[i]);
    if (!bvox__svg_covers_canvas(c, r->canvas)) return 0;
    int64_t line, col;
    bvox__line_col(r->x.start, (size_t)(r->elem_at - r->x.start), &line, &col);
    if (!r->n_background++) r->background_line = line;
    return 1;
}

static bool is_drawn(const bvox__xml *x)
{
    static const char *const drawn[] = {"path", "polygon", "polyline", "circle", "ellipse", "rect"};
    for (size_t i = 0; i < sizeof drawn / sizeof drawn[0]; i++)
        if (bvox__xml_is(x, drawn[i])) return true;
    return false;
}

/* One line per file saying what was not read as an outline, and why. */
static void warn_skipped(const svg_reader *r)
{
    if (!r->n_background && !r->n_hidden && !r->n_unselected) return;
    char msg[400] = "";
    size_t n = 0;
    if (r->n_background)
        n += (size_t)snprintf(msg + n, sizeof msg - n, ", %d full-canvas background <rect>%s (line %lld)",
                              r->n_background, r->n_background > 1 ? "s" : "",
                              (long long)r->background_line);
    if (r->n_hidden && n < sizeof msg)
        n += (size_t)snprintf(msg + n, sizeof msg - n, ", %d hidden element%s", r->n_hidden,
                              r->n_hidden > 1 ? "s" : "");
    if (r->n_unselected && n < sizeof msg)
        snprintf(msg + n, sizeof msg - n, ", %d element%s not named by --svg-select", r->n_unselected,
                 r->n_unselected > 1 ? "s" : "");
    bvox__warn("%s: skipped%s", r->x.name, msg + 1);
}

static bvox_status read_svg(svg_reader *r, int *has_z)
{
    bvox_status st;
    bvox__xml *x = &r->x;
    r->ctm[0] = (bvox_xform2){1, 0, 0, 1, 0, 0};
    int root_seen = 0;
    for (;;) {
        if ((st = bvox__xml_next(x))) return st;
        if (x->kind == BVOX__XML_EOF) break;
        if (x->kind == BVOX__XML_END) {
            if (r->skip_depth && x->depth < r->skip_depth) r->skip_depth = 0;
            if (r->hidden_depth && x->depth < r->hidden_depth) r->hidden_depth = 0;
            if (r->selected_depth && x->depth < r->selected_depth) r->selected_depth = 0;
            continue;
        }
        r->elem_at = x->at;
        int depth = x->depth; /* after the start tag: 1 for the root */
        if (!root_seen) {
            root_seen = 1;
            if (!bvox__xml_is(x, "svg"))
                return bvox__xml_fail(x, x->at, "the root element is <%.*s>, not <svg>",
                                      (int)x->taglen, x->tag);
            if ((st = root_attrs(r, has_z))) return st;
        }
        bvox_xform2 local = {1, 0, 0, 1, 0, 0};
        const bvox__xml_attr *ta = bvox__xml_attr_get(x, "transform");
        if (ta) {
            char *t = bvox__xml_attr_dup(x, ta, &st);
            if (!t) return st;
            st = parse_transform(r, t, &local);
            free(t);
            if (st) return st;
        }
        r->ctm[depth] = bvox_xform2_compose(&local, &r->ctm[depth - 1]);
        if (r->skip_depth) continue;
        if (is_container_skipped(x)) {
            r->skip_depth = depth;
            continue;
        }
        if (!r->hidden_depth && bvox__svg_hides(x)) r->hidden_depth = depth;
        if (r->select && !r->selected_depth && bvox__svg_selected(x, r->select))
            r->selected_depth = depth;
        if (!is_drawn(x)) continue;
        if (r->hidden_depth) {
            r->n_hidden++;
            continue;
        }
        if (bvox__xml_is(x, "rect")) {
            int bg = is_background(r, &r->ctm[depth], &st);
            if (st) return st;
            if (bg) continue;
        }
        if (r->select && !r->selected_depth) {
            r->n_unselected++;
            continue;
        }
        if ((st = element(r, &r->ctm[depth]))) return st;
    }
    if (!root_seen) return bvox__xml_fail(x, x->p, "no <svg> element");
    warn_skipped(r);
    bvox__section_nest(r->sec);
    return BVOX_OK;
}

bvox_status bvox_stack_read_svg_memory(const char *data, size_t size, const char *name, double z,
                                       bvox_contour_stack **stack)
{
    bvox__clear_error();
    return bvox__svg_read(data, size, name, z, NULL, stack);
}

bvox_status bvox__svg_read(const char *data, size_t size, const char *name, double z,
                           const char *select, bvox_contour_stack **stack)
{
    if (!stack) return bvox__fail(BVOX_EINVAL, "bvox_stack_read_svg_memory: stack is NULL");
    bvox_status st = bvox__text_input_check("bvox_stack_read_svg_memory", data, size, &name);
    if (st) return st;
    bvox_contour_stack *s = *stack, *made = NULL;
    if (!s) {
        if ((st = bvox_stack_create(&made))) return st;
        s = made;
    }
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    svg_reader *r = bvox__mem_zalloc(1, sizeof *r);
    if (!r) {
        bvox_stack_destroy(made);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    int32_t before = s->nsections;
    st = bvox_stack_add_section(s, z, base, &r->sec);
    if (!st) r->sec->z_from_index = 1; /* until the root's data-z says otherwise */
    if (!st) {
        r->stack = s;
        r->index = before;
        r->select = select && *select ? select : NULL;
        bvox__xml_init(&r->x, data, size, name);
        int has_z = 0;
        st = read_svg(r, &has_z);
    }
    free(r->pts);
    free(r);
    if (st) {
        if (made) {
            bvox_stack_destroy(made);
        } else if (s->nsections > before) { /* take the half-read section back */
            bvox__stack_drop_last(s);
        }
        return st;
    }
    *stack = s;
    return BVOX_OK;
}

bvox_status bvox_stack_read_svg_files(const char *const *paths, int32_t n, bvox_contour_stack **out)
{
    bvox__clear_error();
    return bvox__svg_read_files(paths, n, NULL, out);
}

bvox_status bvox__svg_read_files(const char *const *paths, int32_t n, const char *select,
                                 bvox_contour_stack **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_read_svg_files: out is NULL");
    *out = NULL;
    if (!paths || n < 1) return bvox__fail(BVOX_EINVAL, "no SVG files given");
    bvox_contour_stack *s = NULL;
    bvox_status st = bvox_stack_create(&s);
    if (st) return st;
    for (int32_t i = 0; i < n; i++) {
        char *text;
        size_t size;
        if ((st = bvox__read_text(paths[i], &text, &size))) break;
        /* until a file says otherwise (data-z), sections are `spacing` apart */
        st = bvox__svg_read(text, size, paths[i], i * s->spacing, select, &s);
        free(text);
        if (st) break;
    }
    if (st) {
        bvox_stack_destroy(s);
        return st;
    }
    *out = s;
    return BVOX_OK;
}

/* ------------------------------------------------------------- writer */

static void bounds(const bvox_contour_stack *s, double *x0, double *y0, double *x1, double *y1)
{
    *x0 = *y0 = HUGE_VAL;
    *x1 = *y1 = -HUGE_VAL;
    for (int32_t i = 0; i < s->nsections; i++) {
        const bvox_section *sec = &s->sections[i];
        for (int32_t c = 0; c < sec->ncontours; c++)
            for (int32_t k = 0; k < sec->contours[c].npoints; k++) {
                bvox_point2 p = sec->contours[c].points[k];
                if (p.x < *x0) *x0 = p.x;
                if (p.x > *x1) *x1 = p.x;
                if (p.y < *y0) *y0 = p.y;
                if (p.y > *y1) *y1 = p.y;
            }
        for (int32_t m = 0; m < sec->nmarkers; m++) {
            bvox_point2 p = sec->markers[m];
            if (p.x < *x0) *x0 = p.x;
            if (p.x > *x1) *x1 = p.x;
            if (p.y < *y0) *y0 = p.y;
            if (p.y > *y1) *y1 = p.y;
        }
    }
    if (*x0 > *x1) *x0 = *y0 = 0, *x1 = *y1 = 1;
}

static void write_section(bvox__strbuf *b, const bvox_contour_stack *s, const bvox_section *sec,
                          const double *box)
{
    char unit[sizeof s->unit + 1];
    memcpy(unit, s->unit, sizeof s->unit);
    unit[sizeof s->unit] = '\0';
    bvox__sb_puts(b, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                     "<svg xmlns=\"http://www.w3.org/2000/svg\"");
    if (s->width > 0 && s->height > 0) {
        bvox__sb_printf(b, " width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\"", (int)s->width,
                        (int)s->height, (int)s->width, (int)s->height);
    } else {
        bvox__sb_puts(b, " viewBox=\"");
        bvox__sb_double(b, floor(box[0]) - 1);
        bvox__sb_puts(b, " ");
        bvox__sb_double(b, floor(box[1]) - 1);
        bvox__sb_puts(b, " ");
        bvox__sb_double(b, ceil(box[2]) - floor(box[0]) + 2);
        bvox__sb_puts(b, " ");
        bvox__sb_double(b, ceil(box[3]) - floor(box[1]) + 2);
        bvox__sb_puts(b, "\"");
    }
    bvox__sb_puts(b, "\n     data-z=\"");
    bvox__sb_double(b, sec->z);
    bvox__sb_puts(b, "\" data-pixel=\"");
    bvox__sb_double(b, s->pixel);
    bvox__sb_puts(b, "\" data-spacing=\"");
    bvox__sb_double(b, s->spacing);
    bvox__sb_puts(b, "\" data-unit=\"");
    bvox__sb_xml_text(b, unit);
    bvox__sb_puts(b, "\"");
    if (sec->name) {
        bvox__sb_puts(b, " data-name=\"");
        bvox__sb_xml_text(b, sec->name);
        bvox__sb_puts(b, "\"");
    }
    bvox__sb_puts(b, ">\n");
    if (sec->ncontours) {
        bvox__sb_puts(b, "<path class=\"contours\" fill=\"black\" fill-rule=\"evenodd\" d=\"");
        for (int32_t c = 0; c < sec->ncontours; c++) {
            const bvox_contour *ct = &sec->contours[c];
            for (int32_t k = 0; k < ct->npoints; k++) {
                bvox__sb_puts(b, k == 0 ? (c ? "\n M" : "M") : " L");
                bvox__sb_double(b, ct->points[k].x);
                bvox__sb_puts(b, " ");
                bvox__sb_double(b, ct->points[k].y);
            }
            bvox__sb_puts(b, " Z");
        }
        bvox__sb_puts(b, "\"/>\n");
    }
    for (int32_t m = 0; m < sec->nmarkers; m++) {
        bvox__sb_puts(b, "<circle class=\"marker\" fill=\"red\" r=\"2\" cx=\"");
        bvox__sb_double(b, sec->markers[m].x);
        bvox__sb_puts(b, "\" cy=\"");
        bvox__sb_double(b, sec->markers[m].y);
        bvox__sb_puts(b, "\"/>\n");
    }
    bvox__sb_puts(b, "</svg>\n");
}

bvox_status bvox_stack_write_svg_dir(const char *dir, const bvox_contour_stack *stack)
{
    return bvox_stack_write_svg_dir_opts(dir, stack, NULL);
}

bvox_status bvox_stack_write_svg_dir_opts(const char *dir, const bvox_contour_stack *stack,
                                          const bvox_write_opts *opts)
{
    bvox__clear_error();
    if (!dir || !stack) return bvox__fail(BVOX_EINVAL, "bvox_stack_write_svg_dir: NULL argument");
    double box[4];
    bounds(stack, &box[0], &box[1], &box[2], &box[3]);
    bvox__dir_sink ds;
    bvox_status st = bvox__dir_sink_open(dir, BVOX__DIR_SVG_SECTIONS, opts && opts->force, &ds);
    if (st) return st;
    const char *tmp = ds.tmp;
    size_t flen = strlen(tmp) + 40;
    char *file = bvox__mem_alloc(flen);
    if (!file) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    int digits = stack->nsections >= 10000 ? 5 : 4;
    for (int32_t i = 0; i < stack->nsections && !st; i++) {
        bvox__strbuf b = {0};
        write_section(&b, stack, &stack->sections[i], box);
        snprintf(file, flen, "%s/section_%0*d.svg", tmp, digits, (int)i + 1);
        st = bvox__sb_write_file(&b, file);
        bvox__sb_free(&b);
    }
    free(file);
    if (st) bvox__dir_sink_abort(&ds);
    else st = bvox__dir_sink_commit(&ds);
    return st;
}
