/*
 * contour_geom.c — geometry on contours: signed area, point in polygon,
 * closing, smoothing, Douglas-Peucker simplification, crossing check and 2-D
 * affine maps (declared in include/bvox/contours.h).
 */
#include "contour_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double bvox_polygon_signed_area(const bvox_point2 *p, int32_t n)
{
    if (!p || n < 3) return 0;
    /* relative to the first point: less cancellation far from the origin */
    double s = 0;
    for (int32_t i = 1; i + 1 < n; i++)
        s += (p[i].x - p[0].x) * (p[i + 1].y - p[0].y) - (p[i + 1].x - p[0].x) * (p[i].y - p[0].y);
    return s / 2;
}

/* the same half-open rule as contour_scan.c */
static int crossings(const bvox_point2 *pts, int32_t n, bvox_point2 c)
{
    int parity = 0;
    for (int32_t k = 0; k < n; k++) {
        bvox_point2 p = pts[k], q = pts[k + 1 < n ? k + 1 : 0];
        double lo = p.y < q.y ? p.y : q.y, hi = p.y < q.y ? q.y : p.y;
        if (!(lo <= c.y && c.y < hi)) continue;
        double dx = q.x - p.x, dy = q.y - p.y;
        double d = (c.x - p.x) * dy - (c.y - p.y) * dx;
        parity ^= dy > 0 ? d > 0 : d < 0;
    }
    return parity;
}

int bvox_polygon_contains(const bvox_point2 *points, int32_t n, bvox_point2 p)
{
    if (!points || n < 3) return 0;
    return crossings(points, n, p);
}

int bvox_section_contains(const bvox_section *sec, bvox_point2 p)
{
    if (!sec) return 0;
    int parity = 0;
    for (int32_t c = 0; c < sec->ncontours; c++)
        if (sec->contours[c].npoints >= 3)
            parity ^= crossings(sec->contours[c].points, sec->contours[c].npoints, p);
    return parity;
}

bvox_status bvox_contour_close(bvox_contour *c)
{
    if (!c || !c->points) return bvox__fail(BVOX_EINVAL, "bvox_contour_close: NULL contour");
    int32_t m = 0;
    for (int32_t i = 0; i < c->npoints; i++)
        if (m == 0 || c->points[i].x != c->points[m - 1].x || c->points[i].y != c->points[m - 1].y)
            m++;
    /* m counts without writing yet: the contour stays as it was on failure */
    int32_t distinct = m;
    if (distinct > 1 && c->points[0].x == c->points[c->npoints - 1].x &&
        c->points[0].y == c->points[c->npoints - 1].y)
        distinct--;
    if (distinct < 3)
        return bvox__fail(BVOX_EFORMAT, "a contour has only %d distinct points (at least 3 needed)",
                          (int)distinct);
    m = 0;
    for (int32_t i = 0; i < c->npoints; i++)
        if (m == 0 || c->points[i].x != c->points[m - 1].x || c->points[i].y != c->points[m - 1].y)
            c->points[m++] = c->points[i];
    if (c->points[0].x == c->points[m - 1].x && c->points[0].y == c->points[m - 1].y) m--;
    c->npoints = m;
    return BVOX_OK;
}

static bvox_point2 centroid(const bvox_point2 *p, int32_t n, double area)
{
    double cx = 0, cy = 0;
    if (fabs(area) > 0) {
        for (int32_t i = 0; i < n; i++) {
            bvox_point2 a = p[i], b = p[i + 1 < n ? i + 1 : 0];
            double cr = (a.x - p[0].x) * (b.y - p[0].y) - (b.x - p[0].x) * (a.y - p[0].y);
            cx += (a.x + b.x - 2 * p[0].x) * cr;
            cy += (a.y + b.y - 2 * p[0].y) * cr;
        }
        return (bvox_point2){p[0].x + cx / (6 * area), p[0].y + cy / (6 * area)};
    }
    for (int32_t i = 0; i < n; i++) {
        cx += p[i].x;
        cy += p[i].y;
    }
    return (bvox_point2){cx / n, cy / n};
}

bvox_status bvox_contour_smooth(bvox_contour *c, int32_t radius, int32_t iterations)
{
    if (!c || !c->points || c->npoints < 3)
        return bvox__fail(BVOX_EINVAL, "bvox_contour_smooth: not a contour");
    if (radius < 1 || iterations < 1 || iterations > 10000)
        return bvox__fail(BVOX_EINVAL, "smoothing radius %d and iterations %d must be >= 1",
                          (int)radius, (int)iterations);
    int32_t n = c->npoints;
    if (radius > (n - 1) / 2) radius = (n - 1) / 2;
    if (radius < 1) return BVOX_OK;
    bvox_point2 *tmp = bvox__mem_alloc((size_t)n * sizeof *tmp);
    if (!tmp) return bvox__fail(BVOX_ENOMEM, "out of memory smoothing a contour");
    double a0 = bvox_polygon_signed_area(c->points, n);
    for (int32_t it = 0; it < iterations; it++) {
        /* running window sum, closed */
        double sx = 0, sy = 0;
        for (int32_t k = -radius; k <= radius; k++) {
            bvox_point2 q = c->points[((k % n) + n) % n];
            sx += q.x;
            sy += q.y;
        }
        double w = 1.0 / (2 * radius + 1);
        for (int32_t i = 0; i < n; i++) {
            tmp[i] = (bvox_point2){sx * w, sy * w};
            bvox_point2 out = c->points[((i - radius) % n + n) % n];
            bvox_point2 in = c->points[(i + radius + 1) % n];
            sx += in.x - out.x;
            sy += in.y - out.y;
        }
        memcpy(c->points, tmp, (size_t)n * sizeof *tmp);
    }
    free(tmp);
    double a1 = bvox_polygon_signed_area(c->points, n);
    if (a0 * a1 > 0) { /* restore the area about the centroid */
        double k = sqrt(a0 / a1);
        bvox_point2 g = centroid(c->points, n, a1);
        for (int32_t i = 0; i < n; i++)
            c->points[i] = (bvox_point2){g.x + (c->points[i].x - g.x) * k,
                                         g.y + (c->points[i].y - g.y) * k};
    }
    return BVOX_OK;
}

static double seg_dist2(bvox_point2 p, bvox_point2 a, bvox_point2 b)
{
    double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0;
    if (t < 0) t = 0;
    if (t > 1) t = 1;
    double ex = a.x + t * dx - p.x, ey = a.y + t * dy - p.y;
    return ex * ex + ey * ey;
}

bvox_status bvox_contour_simplify(bvox_contour *c, double tolerance)
{
    if (!c || !c->points || c->npoints < 3)
        return bvox__fail(BVOX_EINVAL, "bvox_contour_simplify: not a contour");
    if (!(tolerance >= 0) || !isfinite(tolerance))
        return bvox__fail(BVOX_EINVAL, "simplification tolerance %g must be >= 0", tolerance);
    int32_t n = c->npoints;
    bvox_point2 *p = c->points;
    uint8_t *keep = bvox__mem_zalloc((size_t)n + 1, 1);
    int32_t *stack = bvox__mem_alloc(2 * ((size_t)n + 2) * sizeof *stack);
    if (!keep || !stack) {
        free(keep);
        free(stack);
        return bvox__fail(BVOX_ENOMEM, "out of memory simplifying a contour");
    }
    /* split the ring at point 0 and the point farthest from it */
    int32_t f = 1;
    double best = -1;
    for (int32_t i = 1; i < n; i++) {
        double dx = p[i].x - p[0].x, dy = p[i].y - p[0].y, d = dx * dx + dy * dy;
        if (d > best) best = d, f = i;
    }
    keep[0] = keep[f] = keep[n] = 1; /* index n stands for point 0 again */
    size_t sp = 0;
    stack[sp++] = 0;
    stack[sp++] = f;
    stack[sp++] = f;
    stack[sp++] = n;
    double tol2 = tolerance * tolerance;
    while (sp) {
        int32_t b = stack[--sp], a = stack[--sp];
        double dmax = -1;
        int32_t imax = -1;
        for (int32_t i = a + 1; i < b; i++) {
            double d = seg_dist2(p[i], p[a], p[b % n]);
            if (d > dmax) dmax = d, imax = i;
        }
        if (imax >= 0 && dmax > tol2) {
            keep[imax] = 1;
            stack[sp++] = a;
            stack[sp++] = imax;
            stack[sp++] = imax;
            stack[sp++] = b;
        }
    }
    int32_t kept = 0;
    for (int32_t i = 0; i < n; i++) kept += keep[i];
    if (kept < 3) { /* keep the point farthest from the chord as well */
        double dmax = -1;
        int32_t imax = -1;
        for (int32_t i = 1; i < n; i++) {
            if (keep[i]) continue;
            double d = seg_dist2(p[i], p[0], p[f]);
            if (d > dmax) dmax = d, imax = i;
        }
        if (imax >= 0) keep[imax] = 1;
    }
    int32_t m = 0;
    for (int32_t i = 0; i < n; i++)
        if (keep[i]) p[m++] = p[i];
    c->npoints = m;
    free(keep);
    free(stack);
    return BVOX_OK;
}

/* ---- crossing check: a sweep line (contour_sweep.c) over the edges ---- */

static double orient(bvox_point2 a, bvox_point2 b, bvox_point2 c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* 1 for a proper crossing or a collinear overlap of positive length; touching
 * at a point is not reported. *at gets a point of the crossing. */
static int segments_cross(bvox_point2 a, bvox_point2 b, bvox_point2 c, bvox_point2 d, bvox_point2 *at)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
        double t = o3 / (o3 - o4);
        *at = (bvox_point2){a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        return 1;
    }
    if (o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0) {
        /* collinear: project on the longer axis */
        int useX = fabs(b.x - a.x) >= fabs(b.y - a.y);
        double a0 = useX ? a.x : a.y, a1 = useX ? b.x : b.y;
        double c0 = useX ? c.x : c.y, c1 = useX ? d.x : d.y;
        if (a0 > a1) { double t = a0; a0 = a1; a1 = t; }
        if (c0 > c1) { double t = c0; c0 = c1; c1 = t; }
        double lo = a0 > c0 ? a0 : c0, hi = a1 < c1 ? a1 : c1;
        if (hi > lo) {
            double t = a1 > a0 ? ((lo + hi) / 2 - a0) / (a1 - a0) : 0;
            if (useX ? a.x > b.x : a.y > b.y) t = 1 - t;
            *at = (bvox_point2){a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
            return 1;
        }
    }
    return 0;
}

typedef struct check_ctx {
    const bvox_section *sec;
    const int32_t *contour, *index; /* per edge */
    int32_t c1, i1, c2, i2;         /* the crossing edges, when found */
    bvox_point2 at;
    uint64_t tests;
} check_ctx;

static int edges_cross(void *ctx, size_t i, size_t j)
{
    check_ctx *k = ctx;
    k->tests++;
    const bvox_contour *ci = &k->sec->contours[k->contour[i]];
    const bvox_contour *cj = &k->sec->contours[k->contour[j]];
    if (k->contour[i] == k->contour[j]) {
        int32_t d = k->index[i] - k->index[j], n = ci->npoints;
        if (d == 1 || d == -1 || d == n - 1 || d == 1 - n) return 0; /* neighbours */
    }
    bvox_point2 a = ci->points[k->index[i]], b = ci->points[(k->index[i] + 1) % ci->npoints];
    bvox_point2 c = cj->points[k->index[j]], d = cj->points[(k->index[j] + 1) % cj->npoints];
    if (!segments_cross(a, b, c, d, &k->at)) return 0;
    k->c1 = k->contour[i], k->i1 = k->index[i];
    k->c2 = k->contour[j], k->i2 = k->index[j];
    return 1;
}

static _Thread_local uint64_t last_tests;
uint64_t bvox__check_simple_tests(void) { return last_tests; }

bvox_status bvox_section_check_simple(const bvox_section *sec, int32_t section_index)
{
    if (!sec) return bvox__fail(BVOX_EINVAL, "bvox_section_check_simple: section is NULL");
    size_t ne = 0;
    for (int32_t c = 0; c < sec->ncontours; c++) ne += (size_t)sec->contours[c].npoints;
    last_tests = 0;
    if (ne == 0) return BVOX_OK;
    bvox_point2 *p = bvox__mem_alloc(ne * sizeof *p), *q = bvox__mem_alloc(ne * sizeof *q);
    int32_t *contour = bvox__mem_alloc(ne * sizeof *contour), *index = bvox__mem_alloc(ne * sizeof *index);
    int found = -1;
    check_ctx k = {sec, contour, index, 0, 0, 0, 0, {0, 0}, 0};
    if (p && q && contour && index) {
        size_t e = 0;
        for (int32_t c = 0; c < sec->ncontours; c++) {
            const bvox_contour *ct = &sec->contours[c];
            for (int32_t i = 0; i < ct->npoints; i++, e++) {
                p[e] = ct->points[i];
                q[e] = ct->points[i + 1 < ct->npoints ? i + 1 : 0];
                contour[e] = c;
                index[e] = i;
            }
        }
        found = bvox__sweep_crossing(p, q, ne, edges_cross, &k);
    }
    last_tests = k.tests;
    free(p);
    free(q);
    free(contour);
    free(index);
    if (found < 0) return bvox__fail(BVOX_ENOMEM, "out of memory checking contours");
    if (!found) return BVOX_OK;
    char label[200];
    bvox__section_label(sec, section_index, label, sizeof label);
    int32_t c1 = k.c1, c2 = k.c2, i1 = k.i1, i2 = k.i2;
    if (c1 > c2 || (c1 == c2 && i1 > i2)) {
        int32_t t = c1; c1 = c2; c2 = t;
        t = i1; i1 = i2; i2 = t;
    }
    if (c1 == c2)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: contour %d crosses itself (edges %d and %d, near %.2f, %.2f)",
                          label, (int)c1 + 1, (int)i1 + 1, (int)i2 + 1, k.at.x, k.at.y);
    return bvox__fail(BVOX_EFORMAT,
                      "%s: contours %d and %d cross (edges %d and %d, near %.2f, %.2f)",
                      label, (int)c1 + 1, (int)c2 + 1, (int)i1 + 1, (int)i2 + 1, k.at.x, k.at.y);
}

/* ---- 2-D affine maps ---- */

bvox_xform2 bvox_xform2_similarity(double angle, double scale, double tx, double ty)
{
    double c = cos(angle) * scale, s = sin(angle) * scale;
    return (bvox_xform2){c, -s, s, c, tx, ty};
}

bvox_xform2 bvox_xform2_compose(const bvox_xform2 *f, const bvox_xform2 *g)
{
    /* g(f(p)) = G (F p + tf) + tg */
    return (bvox_xform2){g->a * f->a + g->b * f->c, g->a * f->b + g->b * f->d,
                         g->c * f->a + g->d * f->c, g->c * f->b + g->d * f->d,
                         g->a * f->tx + g->b * f->ty + g->tx, g->c * f->tx + g->d * f->ty + g->ty};
}

bvox_status bvox_xform2_invert(const bvox_xform2 *t, bvox_xform2 *out)
{
    double det = t->a * t->d - t->b * t->c;
    if (!(fabs(det) > 1e-300) || !isfinite(det))
        return bvox__fail(BVOX_EINVAL, "the 2-D transform is singular (determinant %g)", det);
    double ia = t->d / det, ib = -t->b / det, ic = -t->c / det, id = t->a / det;
    *out = (bvox_xform2){ia, ib, ic, id, -(ia * t->tx + ib * t->ty), -(ic * t->tx + id * t->ty)};
    return BVOX_OK;
}

bvox_point2 bvox_xform2_apply(const bvox_xform2 *t, bvox_point2 p)
{
    return (bvox_point2){t->a * p.x + t->b * p.y + t->tx, t->c * p.x + t->d * p.y + t->ty};
}

void bvox_section_transform(bvox_section *sec, const bvox_xform2 *t)
{
    if (!sec || !t) return;
    int flip = t->a * t->d - t->b * t->c < 0;
    for (int32_t c = 0; c < sec->ncontours; c++) {
        bvox_contour *ct = &sec->contours[c];
        for (int32_t i = 0; i < ct->npoints; i++) ct->points[i] = bvox_xform2_apply(t, ct->points[i]);
        if (flip)
            for (int32_t i = 0, j = ct->npoints - 1; i < j; i++, j--) {
                bvox_point2 tmp = ct->points[i];
                ct->points[i] = ct->points[j];
                ct->points[j] = tmp;
            }
    }
    for (int32_t m = 0; m < sec->nmarkers; m++) sec->markers[m] = bvox_xform2_apply(t, sec->markers[m]);
}

/* ---- nesting of the contours of a section ---- */

/* Whether contour a lies inside contour b: a majority vote of up to 5 of a's
 * vertices (traced outlines may touch at single points). */
static int inside_of(const bvox_contour *a, const bvox_contour *b)
{
    int votes = 0, n = a->npoints < 5 ? a->npoints : 5;
    for (int k = 0; k < n; k++) {
        int32_t i = (int32_t)((int64_t)a->npoints * k / n);
        votes += crossings(b->points, b->npoints, a->points[i]);
    }
    return 2 * votes > n;
}

static double contour_area(const bvox_contour *c)
{
    return fabs(bvox_polygon_signed_area(c->points, c->npoints));
}

void bvox__section_nest(bvox_section *sec)
{
    int32_t n = sec->ncontours;
    if (n > 4096) return;
    /* the areas once each; without memory for them, each is computed where
     * it is needed: slower, the same answer, so nesting cannot fail */
    double *area = bvox__mem_alloc((size_t)n * sizeof *area + 1);
    if (area)
        for (int32_t i = 0; i < n; i++) area[i] = contour_area(&sec->contours[i]);
#define AREA(k) (area ? area[k] : contour_area(&sec->contours[k]))
    for (int32_t i = 0; i < n; i++) {
        int depth = 0;
        int32_t parent = -1;
        double ai = AREA(i);
        for (int32_t j = 0; j < n; j++) {
            if (j == i) continue;
            double aj = AREA(j);
            if (aj < ai || (aj == ai && j > i)) continue;
            if (!inside_of(&sec->contours[i], &sec->contours[j])) continue;
            depth++;
            if (parent < 0 || aj < AREA(parent)) parent = j;
        }
        sec->contours[i].hole = depth % 2;
        sec->contours[i].parent = parent;
    }
#undef AREA
    free(area);
}
