/*
 * align_fit.c — similarity transforms of the plane: least-squares fit of
 * point pairs (Kabsch / Umeyama in 2-D, closed form), matching two marker
 * sets by trying every pair-to-pair correspondence of equal length (N is
 * small) and keeping the transform that carries most markers onto distinct
 * partners, and the chain of section-to-neighbour steps to a reference.
 */
#include "section_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bvox_sim2 bvox_sim2_identity(void)
{
    return (bvox_sim2){0, 1, 0, 0};
}

bvox_point2 bvox_sim2_apply(const bvox_sim2 *t, bvox_point2 p)
{
    double c = cos(t->angle) * t->scale, s = sin(t->angle) * t->scale;
    return (bvox_point2){c * p.x - s * p.y + t->tx, s * p.x + c * p.y + t->ty};
}

static double wrap_angle(double a)
{
    while (a > M_PI) a -= 2 * M_PI;
    while (a <= -M_PI) a += 2 * M_PI;
    return a;
}

bvox_sim2 bvox_sim2_compose(const bvox_sim2 *a, const bvox_sim2 *b)
{
    /* a(b(p)) = sa Ra (sb Rb p + tb) + ta */
    bvox_point2 t = bvox_sim2_apply(a, (bvox_point2){b->tx, b->ty});
    return (bvox_sim2){wrap_angle(a->angle + b->angle), a->scale * b->scale, t.x, t.y};
}

bvox_sim2 bvox_sim2_inverse(const bvox_sim2 *t)
{
    bvox_sim2 r = {wrap_angle(-t->angle), 1 / t->scale, 0, 0};
    bvox_point2 o = bvox_sim2_apply(&r, (bvox_point2){t->tx, t->ty});
    r.tx = -o.x;
    r.ty = -o.y;
    return r;
}

bvox_status bvox_sim2_fit(const bvox_point2 *src, const bvox_point2 *dst, int32_t n,
                          int allow_scale, bvox_sim2 *t, double *rms)
{
    if (n < 2) return bvox__fail(BVOX_EINVAL, "a transform needs at least 2 point pairs, not %d", (int)n);
    double ax = 0, ay = 0, bx = 0, by = 0;
    for (int32_t i = 0; i < n; i++) {
        if (!isfinite(src[i].x) || !isfinite(src[i].y) || !isfinite(dst[i].x) || !isfinite(dst[i].y))
            return bvox__fail(BVOX_EINVAL, "a point is not finite");
        ax += src[i].x, ay += src[i].y, bx += dst[i].x, by += dst[i].y;
    }
    ax /= n, ay /= n, bx /= n, by /= n;
    double sdot = 0, scross = 0, saa = 0;
    for (int32_t i = 0; i < n; i++) {
        double px = src[i].x - ax, py = src[i].y - ay, qx = dst[i].x - bx, qy = dst[i].y - by;
        sdot += px * qx + py * qy;
        scross += px * qy - py * qx;
        saa += px * px + py * py;
    }
    if (saa <= 1e-18) return bvox__fail(BVOX_EINVAL, "the points of a fit all coincide");
    bvox_sim2 r;
    r.angle = atan2(scross, sdot);
    r.scale = allow_scale ? sqrt(sdot * sdot + scross * scross) / saa : 1.0;
    double c = cos(r.angle) * r.scale, s = sin(r.angle) * r.scale;
    r.tx = bx - (c * ax - s * ay);
    r.ty = by - (s * ax + c * ay);
    if (rms) {
        double e = 0;
        for (int32_t i = 0; i < n; i++) {
            bvox_point2 p = bvox_sim2_apply(&r, src[i]);
            e += (p.x - dst[i].x) * (p.x - dst[i].x) + (p.y - dst[i].y) * (p.y - dst[i].y);
        }
        *rms = sqrt(e / n);
    }
    *t = r;
    return BVOX_OK;
}

/* ------------------------------------------------------------- matching */

#define MAX_MARKERS 16

typedef struct pairing {
    int32_t match[MAX_MARKERS];
    int32_t n;
} pairing;

typedef struct dist_pair {
    double d;
    int32_t i, j;
} dist_pair;

static int by_dist(const void *a, const void *b)
{
    const dist_pair *x = a, *y = b;
    return (x->d > y->d) - (x->d < y->d);
}

/* Greedy one-to-one pairing of the mapped src with dst within tol. */
static void pair_up(const bvox_sim2 *t, const bvox_point2 *src, int32_t ns, const bvox_point2 *dst,
                    int32_t nd, double tol, pairing *p)
{
    dist_pair dp[MAX_MARKERS * MAX_MARKERS];
    int32_t m = 0;
    for (int32_t i = 0; i < ns; i++) {
        bvox_point2 q = bvox_sim2_apply(t, src[i]);
        for (int32_t j = 0; j < nd; j++) {
            double d = hypot(q.x - dst[j].x, q.y - dst[j].y);
            if (d <= tol) dp[m++] = (dist_pair){d, i, j};
        }
    }
    qsort(dp, (size_t)m, sizeof *dp, by_dist);
    int used_dst[MAX_MARKERS] = {0};
    for (int32_t i = 0; i < ns; i++) p->match[i] = -1;
    p->n = 0;
    for (int32_t k = 0; k < m; k++) {
        if (p->match[dp[k].i] >= 0 || used_dst[dp[k].j]) continue;
        p->match[dp[k].i] = dp[k].j;
        used_dst[dp[k].j] = 1;
        p->n++;
    }
}

static int plausible(const bvox_sim2 *t, double max_angle, double max_scale_change)
{
    return fabs(t->angle) <= max_angle + 1e-12 && fabs(t->scale - 1) <= max_scale_change + 1e-12;
}

/* Least-squares refit on a pairing; rms out. */
static bvox_status refit(const bvox_point2 *src, int32_t ns, const bvox_point2 *dst,
                         const pairing *p, int allow_scale, bvox_sim2 *t, double *rms)
{
    bvox_point2 a[MAX_MARKERS], b[MAX_MARKERS];
    int32_t m = 0;
    for (int32_t i = 0; i < ns; i++)
        if (p->match[i] >= 0) {
            a[m] = src[i];
            b[m] = dst[p->match[i]];
            m++;
        }
    return bvox_sim2_fit(a, b, m, allow_scale, t, rms);
}

bvox_status bvox_markers_match(const bvox_point2 *src, int32_t ns, const bvox_point2 *dst,
                               int32_t nd, const bvox_marker_opts *opts, bvox_sim2 *t,
                               int32_t *match, int32_t *nmatched, double *rms)
{
    bvox_marker_opts o = opts ? *opts : bvox_marker_opts_default();
    double tol = o.tolerance > 0 ? o.tolerance : 4.0;
    double max_angle = o.max_angle > 0 ? o.max_angle : 30 * M_PI / 180;
    double max_sc = o.allow_scale ? (o.max_scale_change > 0 ? o.max_scale_change : 0.2) : 0;
    if (nmatched) *nmatched = 0;
    if (match)
        for (int32_t i = 0; i < ns; i++) match[i] = -1;
    if (ns > MAX_MARKERS || nd > MAX_MARKERS)
        return bvox__fail(BVOX_EINVAL, "at most %d markers per section can be matched", MAX_MARKERS);
    if (ns < 2 || nd < 2)
        return bvox__fail(BVOX_ENOTFOUND, "%d and %d markers: at least 2 on each side are needed",
                          (int)ns, (int)nd);
    pairing best = {{0}, 0};
    bvox_sim2 best_t = bvox_sim2_identity();
    double best_rms = INFINITY;
    for (int32_t i1 = 0; i1 < ns; i1++)
        for (int32_t i2 = i1 + 1; i2 < ns; i2++) {
            double ds = hypot(src[i1].x - src[i2].x, src[i1].y - src[i2].y);
            if (ds < 2 * tol) continue;
            for (int32_t j1 = 0; j1 < nd; j1++)
                for (int32_t j2 = 0; j2 < nd; j2++) {
                    if (j1 == j2) continue;
                    double dd = hypot(dst[j1].x - dst[j2].x, dst[j1].y - dst[j2].y);
                    if (fabs(dd - ds) > 2 * tol + max_sc * ds) continue;
                    bvox_point2 a[2] = {src[i1], src[i2]}, b[2] = {dst[j1], dst[j2]};
                    bvox_sim2 h;
                    if (bvox_sim2_fit(a, b, 2, o.allow_scale, &h, NULL)) continue;
                    if (!plausible(&h, max_angle, max_sc)) continue;
                    pairing p;
                    pair_up(&h, src, ns, dst, nd, tol, &p);
                    if (p.n < 2 || p.n < best.n) continue;
                    bvox_sim2 f;
                    double e;
                    if (refit(src, ns, dst, &p, o.allow_scale, &f, &e)) continue;
                    if (!plausible(&f, max_angle, max_sc)) continue;
                    if (p.n > best.n || e < best_rms) {
                        best = p;
                        best_t = f;
                        best_rms = e;
                    }
                }
        }
    bvox__clear_error();
    if (best.n < 2)
        return bvox__fail(BVOX_ENOTFOUND, "no 2 markers of %d match 2 of the neighbour's %d "
                                          "within %g pixels", (int)ns, (int)nd, tol);
    *t = best_t;
    if (match) memcpy(match, best.match, (size_t)ns * sizeof *match);
    if (nmatched) *nmatched = best.n;
    if (rms) *rms = best_rms;
    return BVOX_OK;
}

/* -------------------------------------------------------------- the chain */

bvox_status bvox_markers_align(const bvox_point2 *const *markers, const int32_t *counts,
                               int32_t n, int32_t reference, const bvox_marker_opts *opts,
                               bvox_align_result *result)
{
    if (n < 1) return bvox__fail(BVOX_EINVAL, "no sections to align");
    if (reference >= n)
        return bvox__fail(BVOX_EINVAL, "the reference section %d is beyond the %d sections",
                          (int)reference + 1, (int)n);
    if (reference < 0) {
        /* the middle one, or the nearest to it with at least 2 markers */
        reference = n / 2;
        for (int32_t d = 0; d < n; d++) {
            if (reference - d >= 0 && counts[reference - d] >= 2) {
                reference -= d;
                break;
            }
            if (reference + d < n && counts[reference + d] >= 2) {
                reference += d;
                break;
            }
        }
    }
    for (int32_t k = 0; k < n; k++) {
        result[k].transform = bvox_sim2_identity();
        result[k].step = bvox_sim2_identity();
        result[k].neighbour = -1;
        result[k].matched = 0;
        result[k].residual = 0;
        result[k].fallback = 0;
    }
    result[reference].matched = counts[reference];
    for (int dir = -1; dir <= 1; dir += 2) {
        for (int32_t k = reference + dir; k >= 0 && k < n; k += dir) {
            bvox_align_result *r = &result[k];
            /* nearest section towards the reference with usable markers */
            int32_t j = k - dir;
            while (j != reference && (result[j].fallback || counts[j] < 2)) j -= dir;
            bvox_sim2 step;
            int32_t nm = 0;
            double rms = 0;
            bvox_status st = BVOX_ENOTFOUND;
            if (counts[k] >= 2 && counts[j] >= 2)
                st = bvox_markers_match(markers[k], counts[k], markers[j], counts[j], opts, &step,
                                        NULL, &nm, &rms);
            if (st == BVOX_EINVAL) return st;
            if (st) {
                /* fallback: the adjacent section's transform, identity step */
                r->neighbour = k - dir;
                r->transform = result[k - dir].transform;
                r->fallback = 1;
                continue;
            }
            r->neighbour = j;
            r->step = step;
            r->matched = nm;
            r->residual = rms;
            r->transform = bvox_sim2_compose(&result[j].transform, &step);
        }
    }
    bvox__clear_error();
    return BVOX_OK;
}
