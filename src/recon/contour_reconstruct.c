/*
 * contour_reconstruct.c — the Reconstruct series format (J. C. Fiala's
 * RECONSTRUCT, the XML serial-section anatomists already have): a series
 * file NAME.ser and one XML file per section, NAME.1, NAME.2, ... beside it.
 *
 * What is read, per section file:
 *   <Section index="N" thickness="T"> ... </Section>
 *   <Transform dim="D" xcoef="a0 a1 a2 a3 a4 a5" ycoef="b0 b1 b2 b3 b4 b5">
 *     the map x' = a0 + a1 x + a2 y + a3 x y + a4 x^2 + a5 y^2 (y' with b).
 *     dim 0: identity; dim 1: translation (a0, b0); dim 2: scales
 *     (x' = a0 + a1 x, y' = b0 + b1 y, as RECONSTRUCT's nform reads it);
 *     dim 3: affine (a0..a2, b0..b2); dim 4..6: the whole polynomial.
 *     RECONSTRUCT stores trace points in the transform's own frame: the
 *     position in the section is the INVERSE map applied to them (as
 *     PyRECONSTRUCT's worldpts does); a polynomial map is inverted per point
 *     by Newton's method from the affine part's inverse (at most 100 steps;
 *     a point where it does not converge is an error naming the section).
 *     <Contour name="..." closed="true" points="x y, x y, ..."/> inside a
 *     Transform: a closed trace becomes a contour; open traces
 *     (closed="false") are skipped (they are lines, not outlines); a trace
 *     whose name contains "marker" becomes a marker at its centroid.
 *     A Transform holding an <Image> is the image's domain: its contours
 *     (the domain boundary) are skipped, and the first image's mag (units per
 *     pixel) becomes the stack's pixel size.
 * All objects of the series go into one stack (no selection by object name).
 * Units: Reconstruct's are microns ("um"). Points are converted to pixels of
 * that size (without any image: the pixel is the traces' larger extent /
 * 512), y is flipped (Reconstruct's y points up, the stack's y down) so the
 * model is not mirrored. z: the first section at 0, each next one at the
 * previous z plus its own thickness; spacing = the first section's thickness.
 * The .ser file itself is only checked to be a <Series> document (its
 * display settings are not needed). Not supported: DTD entities,
 * ZContours, section images themselves.
 */
#include "contour_internal.h"

#include <ctype.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct pending {
    bvox_point2 *p;
    int32_t n;
    int marker;
} pending;

typedef struct rsec {
    bvox__xml x;
    bvox_section *sec;
    int32_t index;
    double thickness, mag;
    /* contours of the current Transform, committed at its end */
    pending *pend;
    size_t npend, cap;
    int has_image;
    bvox_xform2 inv; /* the inverse of the affine part */
    int poly;        /* the map has nonlinear terms: inverted by Newton's method */
    double a[6], b[6];
    int in_transform;
    const char *at;
} rsec;

static bvox_status rfail(rsec *r, const char *at, const char *what)
{
    char label[200];
    bvox__section_label(r->sec, r->index, label, sizeof label);
    return bvox__xml_fail(&r->x, at, "%s: %s", label, what);
}

static void drop_pending(rsec *r)
{
    for (size_t i = 0; i < r->npend; i++) free(r->pend[i].p);
    r->npend = 0;
}

/* Numbers of an attribute, at most max, separated by white space/commas. */
static int numbers(const char *t, double *v, int max, int *extra)
{
    int n = 0;
    *extra = 0;
    const char *p = t;
    for (;;) {
        while (*p && (isspace((unsigned char)*p) || *p == ',')) p++;
        if (!*p) break;
        char *e;
        double d = strtod(p, &e);
        if (e == p || !isfinite(d)) return -1;
        if (n < max) v[n++] = d;
        else *extra = 1;
        p = e;
    }
    return n;
}

static bvox_status attr_text(rsec *r, const char *name, char **out)
{
    *out = NULL;
    const bvox__xml_attr *a = bvox__xml_attr_get(&r->x, name);
    if (!a) return BVOX_OK;
    bvox_status st;
    *out = bvox__xml_attr_dup(&r->x, a, &st);
    return st;
}

static bvox_status transform(rsec *r)
{
    char *dim_t, *xt, *yt;
    bvox_status st;
    if ((st = attr_text(r, "dim", &dim_t))) return st;
    if ((st = attr_text(r, "xcoef", &xt))) {
        free(dim_t);
        return st;
    }
    if ((st = attr_text(r, "ycoef", &yt))) {
        free(dim_t);
        free(xt);
        return st;
    }
    double a[6] = {0, 1, 0, 0, 0, 0}, b[6] = {0, 0, 1, 0, 0, 0}, dimv = 0;
    int extra, ok = 1, na = 0, nb = 0, nd = 0;
    if (dim_t) nd = numbers(dim_t, &dimv, 1, &extra), ok &= nd == 1 && !extra;
    if (xt) na = numbers(xt, a, 6, &extra), ok &= na >= 1 && !extra;
    if (yt) nb = numbers(yt, b, 6, &extra), ok &= nb >= 1 && !extra;
    free(dim_t);
    free(xt);
    free(yt);
    if (!ok || dimv < 0 || dimv > 6 || dimv != floor(dimv))
        return rfail(r, NULL, "<Transform>: dim must be 0..6 and xcoef/ycoef up to 6 numbers");
    int dim = (int)dimv;
    bvox_xform2 f = {1, 0, 0, 1, 0, 0};
    r->poly = 0;
    if (dim == 1) {
        f.tx = a[0];
        f.ty = b[0];
    } else if (dim == 2) { /* scales: x' = a0 + a1 x, y' = b0 + b1 y (RECONSTRUCT's nform) */
        f = (bvox_xform2){a[1], 0, 0, b[1], a[0], b[0]};
    } else if (dim >= 3) {
        f = (bvox_xform2){a[1], a[2], b[1], b[2], a[0], b[0]};
        if (dim >= 4 && (a[3] != 0 || a[4] != 0 || a[5] != 0 || b[3] != 0 || b[4] != 0 || b[5] != 0)) {
            r->poly = 1;
            memcpy(r->a, a, sizeof r->a);
            memcpy(r->b, b, sizeof r->b);
        }
    }
    if (bvox_xform2_invert(&f, &r->inv)) return rfail(r, NULL, "<Transform> is singular");
    r->in_transform = 1;
    r->has_image = 0;
    drop_pending(r);
    return BVOX_OK;
}

/* The point (x, y) whose forward map is (u, v), by Newton's method from the
 * affine part's inverse (*q holds it on entry), as RECONSTRUCT inverts its
 * polynomial transforms; false if it does not converge. */
static bool poly_inverse(const rsec *r, double u, double v, bvox_point2 *q)
{
    const double *a = r->a, *b = r->b;
    double x = q->x, y = q->y;
    double tol = 1e-10 * (1 + fabs(u) + fabs(v));
    for (int it = 0; it < 100; it++) {
        double fu = a[0] + a[1] * x + a[2] * y + a[3] * x * y + a[4] * x * x + a[5] * y * y;
        double fv = b[0] + b[1] * x + b[2] * y + b[3] * x * y + b[4] * x * x + b[5] * y * y;
        double eu = u - fu, ev = v - fv;
        if (!isfinite(eu) || !isfinite(ev)) return false;
        if (fabs(eu) + fabs(ev) <= tol) {
            *q = (bvox_point2){x, y};
            return true;
        }
        double l = a[1] + a[3] * y + 2 * a[4] * x, m = a[2] + a[3] * x + 2 * a[5] * y;
        double n = b[1] + b[3] * y + 2 * b[4] * x, o = b[2] + b[3] * x + 2 * b[5] * y;
        double det = l * o - m * n;
        if (!(fabs(det) > 1e-300)) return false;
        x += (o * eu - m * ev) / det;
        y += (l * ev - n * eu) / det;
    }
    return false;
}

static bvox_status contour(rsec *r)
{
    char *closed, *name, *pts;
    bvox_status st;
    if ((st = attr_text(r, "closed", &closed))) return st;
    int is_closed = !closed || strcmp(closed, "false") != 0;
    free(closed);
    if (!is_closed) return BVOX_OK;
    if ((st = attr_text(r, "name", &name))) return st;
    int marker = name && strstr(name, "marker") != NULL;
    free(name);
    if ((st = attr_text(r, "points", &pts))) return st;
    if (!pts) return rfail(r, NULL, "<Contour> without points");
    pending pd = {NULL, 0, marker};
    size_t cap = 0;
    const char *p = pts;
    for (;;) {
        while (*p && (isspace((unsigned char)*p) || *p == ',')) p++;
        if (!*p) break;
        char *e;
        double x = strtod(p, &e);
        if (e == p) break;
        p = e;
        while (*p && isspace((unsigned char)*p)) p++;
        double y = strtod(p, &e);
        if (e == p) {
            free(pd.p);
            free(pts);
            return rfail(r, NULL, "<Contour> points: an odd count of numbers");
        }
        p = e;
        bvox_point2 q = bvox_xform2_apply(&r->inv, (bvox_point2){x, y});
        if (r->poly && !poly_inverse(r, x, y, &q)) {
            free(pd.p);
            free(pts);
            char what[160];
            snprintf(what, sizeof what,
                     "<Contour>: the polynomial <Transform> cannot be inverted at (%g, %g)", x, y);
            return rfail(r, NULL, what);
        }
        q.y = -q.y; /* y up -> y down */
        if (!isfinite(q.x) || !isfinite(q.y) || fabs(q.x) > 1e12 || fabs(q.y) > 1e12 ||
            pd.n >= BVOX__MAX_POINTS) {
            free(pd.p);
            free(pts);
            return rfail(r, NULL, "<Contour> points out of range");
        }
        if (!bvox__grow((void **)&pd.p, sizeof *pd.p, (size_t)pd.n + 1, &cap, "points")) {
            free(pd.p);
            free(pts);
            return BVOX_ENOMEM;
        }
        pd.p[pd.n++] = q;
    }
    int trailing = *p != '\0';
    free(pts);
    if (trailing) {
        free(pd.p);
        return rfail(r, NULL, "<Contour> points: not a list of \"x y\" pairs");
    }
    /* drop consecutive duplicates */
    int32_t m = 0;
    for (int32_t i = 0; i < pd.n; i++)
        if (m == 0 || pd.p[i].x != pd.p[m - 1].x || pd.p[i].y != pd.p[m - 1].y) pd.p[m++] = pd.p[i];
    if (m > 1 && pd.p[0].x == pd.p[m - 1].x && pd.p[0].y == pd.p[m - 1].y) m--;
    pd.n = m;
    if (!marker && m < 3) {
        free(pd.p);
        char what[120];
        snprintf(what, sizeof what, "a closed <Contour> with %d distinct points (at least 3 needed)",
                 (int)m);
        return rfail(r, NULL, what);
    }
    if (marker && m < 1) {
        free(pd.p);
        return BVOX_OK;
    }
    if (!bvox__grow((void **)&r->pend, sizeof *r->pend, r->npend + 1, &r->cap, "contours")) {
        free(pd.p);
        return BVOX_ENOMEM;
    }
    r->pend[r->npend++] = pd;
    return BVOX_OK;
}

static bvox_status commit(rsec *r)
{
    bvox_status st = BVOX_OK;
    if (!r->has_image) {
        for (size_t i = 0; i < r->npend && !st; i++) {
            pending *pd = &r->pend[i];
            if (pd->marker) {
                double cx = 0, cy = 0;
                for (int32_t k = 0; k < pd->n; k++) cx += pd->p[k].x, cy += pd->p[k].y;
                st = bvox_section_add_marker(r->sec, (bvox_point2){cx / pd->n, cy / pd->n});
            } else {
                st = bvox_section_add_contour(r->sec, pd->p, pd->n, 0, -1);
            }
            if (st && st != BVOX_ENOMEM) { /* out of memory is not a format error */
                char what[300];
                snprintf(what, sizeof what, "%s", bvox_errmsg());
                st = rfail(r, r->at, what);
            }
        }
    }
    drop_pending(r);
    r->in_transform = 0;
    return st;
}

static bvox_status parse_section(rsec *r)
{
    bvox_status st;
    bvox__xml *x = &r->x;
    int root = 0;
    for (;;) {
        if ((st = bvox__xml_next(x))) return st;
        if (x->kind == BVOX__XML_EOF) break;
        if (x->kind == BVOX__XML_END) {
            if (bvox__xml_is(x, "Transform") && r->in_transform && (st = commit(r))) return st;
            continue;
        }
        if (!root) {
            root = 1;
            if (!bvox__xml_is(x, "Section"))
                return bvox__xml_fail(x, x->at, "the root element is <%.*s>, not <Section>",
                                      (int)x->taglen, x->tag);
            char *t;
            if ((st = attr_text(r, "thickness", &t))) return st;
            if (t) {
                double v = 0;
                int extra, n = numbers(t, &v, 1, &extra);
                free(t);
                if (n != 1 || extra || !(v > 0) || v > 1e9)
                    return rfail(r, x->at, "<Section thickness> must be a number > 0");
                r->thickness = v;
            }
            continue;
        }
        if (bvox__xml_is(x, "Transform")) {
            if (r->in_transform) return rfail(r, x->at, "a <Transform> inside a <Transform>");
            r->at = x->at;
            if ((st = transform(r))) return st;
        } else if (bvox__xml_is(x, "Image") && r->in_transform) {
            r->has_image = 1;
            char *t;
            if ((st = attr_text(r, "mag", &t))) return st;
            if (t) {
                double v = 0;
                int extra, n = numbers(t, &v, 1, &extra);
                free(t);
                if (n == 1 && v > 0 && v < 1e9 && r->mag == 0) r->mag = v;
            }
        } else if (bvox__xml_is(x, "Contour") && r->in_transform) {
            if ((st = contour(r))) return st;
        }
    }
    if (!root) return bvox__xml_fail(x, x->p, "no <Section> element");
    return BVOX_OK;
}

/* Append one section with points in Reconstruct units (y flipped). */
static bvox_status read_one(const char *data, size_t size, const char *name, bvox_contour_stack *s,
                            double *thickness, double *mag)
{
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    rsec *r = bvox__mem_zalloc(1, sizeof *r);
    if (!r) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int32_t before = s->nsections;
    bvox_status st = bvox_stack_add_section(s, 0, base, &r->sec);
    if (!st) {
        r->index = before;
        bvox__xml_init(&r->x, data, size, name);
        st = parse_section(r);
    }
    drop_pending(r);
    free(r->pend);
    *thickness = r->thickness;
    *mag = r->mag;
    free(r);
    if (st && s->nsections > before) bvox__stack_drop_last(s); /* take the half-read one back */
    return st;
}

static void rescale(bvox_section *sec, double k)
{
    for (int32_t c = 0; c < sec->ncontours; c++)
        for (int32_t i = 0; i < sec->contours[c].npoints; i++) {
            sec->contours[c].points[i].x *= k;
            sec->contours[c].points[i].y *= k;
        }
    for (int32_t m = 0; m < sec->nmarkers; m++) {
        sec->markers[m].x *= k;
        sec->markers[m].y *= k;
    }
}

bvox_status bvox_stack_read_reconstruct_section_memory(const char *data, size_t size,
                                                       const char *name,
                                                       bvox_contour_stack **stack)
{
    bvox__clear_error();
    if (!stack)
        return bvox__fail(BVOX_EINVAL, "bvox_stack_read_reconstruct_section_memory: stack is NULL");
    bvox_status st = bvox__text_input_check("bvox_stack_read_reconstruct_section_memory", data,
                                            size, &name);
    if (st) return st;
    bvox_contour_stack *s = *stack, *made = NULL;
    if (!s) {
        if ((st = bvox_stack_create(&made))) return st;
        s = made;
        strcpy(s->unit, "um");
    }
    double th = 0, mag = 0;
    st = read_one(data, size, name, s, &th, &mag);
    if (st) {
        bvox_stack_destroy(made);
        return st;
    }
    if (made) {
        s->given |= BVOX_STACK_GIVEN_UNIT; /* Reconstruct's unit is the micron */
        if (mag > 0) s->pixel = mag, s->given |= BVOX_STACK_GIVEN_PIXEL;
        if (th > 0) s->spacing = th, s->given |= BVOX_STACK_GIVEN_SPACING;
    }
    bvox_section *sec = &s->sections[s->nsections - 1];
    rescale(sec, 1 / s->pixel);
    sec->z = s->nsections > 1 ? s->sections[s->nsections - 2].z + (th > 0 ? th : s->spacing) : 0;
    bvox__section_nest(sec);
    *stack = s;
    return BVOX_OK;
}

/* ---- the series: NAME.ser and NAME.<n> beside it ---- */

typedef struct secfile {
    long index;
    char *path;
} secfile;

static int cmp_secfile(const void *a, const void *b)
{
    long x = ((const secfile *)a)->index, y = ((const secfile *)b)->index;
    return (x > y) - (x < y);
}

/* The series' units= attribute (Reconstruct writes "microns"; users set
 * nanometers for EM, millimeters for gross anatomy), as the short unit names
 * the rest of bvox knows. Unknown names are refused rather than guessed: a
 * unit off by 10^3 makes every volume off by 10^9. */
static bvox_status series_unit(const bvox__xml *x, const char *path, char unit[16])
{
    static const struct {
        const char *name, *unit;
    } names[] = {
        {"microns", "um"},     {"micron", "um"},     {"micrometers", "um"}, {"um", "um"},
        {"\xc2\xb5m", "um"}, {"nanometers", "nm"}, {"nm", "nm"},          {"millimeters", "mm"},
        {"mm", "mm"},          {"centimeters", "cm"}, {"cm", "cm"},         {"meters", "m"},
        {"m", "m"},
    };
    const bvox__xml_attr *a = bvox__xml_attr_get(x, "units");
    if (!a) return BVOX_OK;
    bvox_status st = BVOX_OK;
    char *t = bvox__xml_attr_dup(x, a, &st);
    if (!t) return st;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcasecmp(t, names[i].name)) {
            strcpy(unit, names[i].unit);
            free(t);
            return BVOX_OK;
        }
    st = bvox__fail(BVOX_EFORMAT,
                    "%s: <Series units=\"%.40s\"> is not a unit bvox knows (microns, nanometers, "
                    "millimeters, centimeters, meters)",
                    path, t);
    free(t);
    return st;
}

bvox_status bvox__stack_read_reconstruct_series(const char *ser_path, bvox_contour_stack **out)
{
    *out = NULL;
    char *text;
    size_t size;
    bvox_status st = bvox__read_text(ser_path, &text, &size);
    if (st) return st;
    bvox__xml x;
    bvox__xml_init(&x, text, size, ser_path);
    do {
        st = bvox__xml_next(&x);
    } while (!st && x.kind == BVOX__XML_END);
    if (!st && (x.kind != BVOX__XML_START || !bvox__xml_is(&x, "Series")))
        st = bvox__xml_fail(&x, x.at, "not a Reconstruct series (the root element is not <Series>)");
    char unit[16] = "um"; /* Reconstruct's default unit */
    if (!st) st = series_unit(&x, ser_path, unit);
    free(text);
    if (st) return st;

    /* the folder and NAME */
    const char *slash = strrchr(ser_path, '/');
    size_t dlen = slash ? (size_t)(slash - ser_path) : 0;
    char *dir = slash ? bvox__mem_strndup(ser_path, dlen ? dlen : 1) : bvox__mem_strdup(".");
    const char *base = slash ? slash + 1 : ser_path;
    const char *dot = strrchr(base, '.');
    size_t blen = dot ? (size_t)(dot - base) : strlen(base);
    if (!dir) return bvox__fail(BVOX_ENOMEM, "out of memory");
    DIR *d = opendir(dir);
    if (!d) {
        free(dir);
        return bvox__fail(BVOX_EIO, "%s: cannot list the folder of the series", ser_path);
    }
    secfile *files = NULL;
    size_t nf = 0, cap = 0;
    struct dirent *e;
    st = BVOX_OK;
    while ((e = readdir(d)) && !st) {
        const char *n = e->d_name;
        if (strncmp(n, base, blen) || n[blen] != '.') continue;
        const char *num = n + blen + 1;
        if (!*num || strlen(num) > 9) continue;
        int digits = 1;
        for (const char *q = num; *q; q++) digits &= isdigit((unsigned char)*q) != 0;
        if (!digits) continue;
        if (nf >= BVOX__MAX_SECTIONS) {
            st = bvox__fail(BVOX_ETOOBIG, "%s: more than %d section files", ser_path, BVOX__MAX_SECTIONS);
            break;
        }
        if (!bvox__grow((void **)&files, sizeof *files, nf + 1, &cap, "section files")) {
            st = BVOX_ENOMEM;
            break;
        }
        size_t plen = strlen(dir) + strlen(n) + 2;
        files[nf].path = bvox__mem_alloc(plen);
        if (!files[nf].path) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            break;
        }
        snprintf(files[nf].path, plen, "%s/%s", dir, n);
        files[nf].index = strtol(num, NULL, 10);
        nf++;
    }
    closedir(d);
    if (!st && nf == 0)
        st = bvox__fail(BVOX_EFORMAT, "%s: no section files %.*s.1, %.*s.2, ... beside it", ser_path,
                        (int)blen, base, (int)blen, base);
    bvox_contour_stack *s = NULL;
    if (!st) st = bvox_stack_create(&s);
    double pixel = 0, first_th = 0;
    if (!st) {
        strcpy(s->unit, unit);
        s->given |= BVOX_STACK_GIVEN_UNIT;
        qsort(files, nf, sizeof *files, cmp_secfile);
        double z = 0;
        for (size_t i = 0; i < nf && !st; i++) {
            if ((st = bvox__read_text(files[i].path, &text, &size))) break;
            double th = 0, mag = 0;
            st = read_one(text, size, files[i].path, s, &th, &mag);
            free(text);
            if (st) break;
            if (i == 0) first_th = th;
            if (i > 0) z += th > 0 ? th : (first_th > 0 ? first_th : 1);
            s->sections[s->nsections - 1].z = z;
            if (pixel == 0 && mag > 0) pixel = mag;
        }
    }
    for (size_t i = 0; i < nf; i++) free(files[i].path);
    free(files);
    free(dir);
    if (st) {
        bvox_stack_destroy(s);
        return st;
    }
    if (pixel == 0) { /* no image: the traces' larger extent is 512 pixels */
        double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
        for (int32_t i = 0; i < s->nsections; i++)
            for (int32_t c = 0; c < s->sections[i].ncontours; c++)
                for (int32_t k = 0; k < s->sections[i].contours[c].npoints; k++) {
                    bvox_point2 p = s->sections[i].contours[c].points[k];
                    x0 = fmin(x0, p.x), x1 = fmax(x1, p.x), y0 = fmin(y0, p.y), y1 = fmax(y1, p.y);
                }
        double ext = x1 > x0 ? fmax(x1 - x0, y1 - y0) : 0;
        pixel = ext > 0 ? ext / 512 : 1;
    }
    s->given |= BVOX_STACK_GIVEN_PIXEL; /* an image's mag, or Reconstruct's own default rule */
    s->pixel = pixel;
    s->spacing = first_th > 0 ? first_th : 1;
    if (first_th > 0) s->given |= BVOX_STACK_GIVEN_SPACING;
    for (int32_t i = 0; i < s->nsections; i++) {
        rescale(&s->sections[i], 1 / pixel);
        for (int32_t c = 0; c < s->sections[i].ncontours; c++)
            for (int32_t k = 0; k < s->sections[i].contours[c].npoints; k++) {
                bvox_point2 p = s->sections[i].contours[c].points[k];
                if (fabs(p.x) > BVOX__MAX_COORD || fabs(p.y) > BVOX__MAX_COORD) {
                    char label[200];
                    bvox__section_label(&s->sections[i], i, label, sizeof label);
                    bvox_stack_destroy(s);
                    return bvox__fail(BVOX_EFORMAT, "%s: %s: a point beyond %g pixels of %g um",
                                      ser_path, label, BVOX__MAX_COORD, pixel);
                }
            }
        bvox__section_nest(&s->sections[i]);
    }
    *out = s;
    return BVOX_OK;
}
