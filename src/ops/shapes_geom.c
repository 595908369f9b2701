/*
 * shapes_geom.c — geometry of the primitives (see shapes_geom.h): validation,
 * the exact inside predicate, bounding boxes, and where a line parallel to z
 * meets each shape. The rasteriser in shapes.c turns those z intervals into
 * bit ranges, so the per-voxel predicate is only evaluated at interval ends.
 *
 * Lines: the column at (x, y) is p(s) = (x, y, cz + s). With d0 = (dx, dy, 0)
 * the offset from the centre at s = 0, the axial coordinate is
 * t(s) = t0 + s*uz and the vector from the axis is w(s) = w0 + s*w1, where
 * w0 = d0 - t0*u and w1 = e_z - uz*u. A cylinder or cone side is then the
 * quadratic |w(s)|^2 <= radius(t(s))^2 and the caps are a slab in s.
 */
#include "ops/shapes_geom.h"

#include <math.h>

/* Coordinates and sizes above this are refused: their squares (and sums of
 * squares) must stay finite for the quadratics below. */
#define SHAPE_LIMIT 1e100

static bool finite_in(double v) { return isfinite(v) && fabs(v) <= SHAPE_LIMIT; }

static bvox_status check_size(const char *what, double v, bool zero_ok)
{
    if (!finite_in(v) || v < 0 || (!zero_ok && v == 0))
        return bvox__fail(BVOX_EINVAL, "shape %s %g must be a finite number %s", what, v,
                          zero_ok ? ">= 0" : "> 0");
    return BVOX_OK;
}

/* Unit axis; (0,0,0) means +z. Scaled by the largest component first so that
 * tiny or huge (finite) axes normalise without underflow or overflow, and so
 * that an axis along x, y or z comes out exact ((0,0,5) gives uz == 1): the
 * z-parallel special cases below depend on it. */
static bvox_status unit_axis(const double *axis, double *u)
{
    double m = 0;
    for (int i = 0; i < 3; i++) {
        if (!isfinite(axis[i])) return bvox__fail(BVOX_EINVAL, "shape axis is not finite");
        if (fabs(axis[i]) > m) m = fabs(axis[i]);
    }
    if (m == 0) {
        u[0] = u[1] = 0;
        u[2] = 1;
        return BVOX_OK;
    }
    double v[3] = {axis[0] / m, axis[1] / m, axis[2] / m};
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) u[i] = v[i] / n;
    return BVOX_OK;
}

/* sin of the angle between the unit axis u and coordinate axis i: the extent
 * along i of a unit circle around u */
static double sin_to(const double *u, int i) { return sqrt(fmax(0.0, 1.0 - u[i] * u[i])); }

bvox_status bvox__shape_prepare(const bvox_shape *s, bvox__shape_geom *g)
{
    bvox_status st = BVOX_OK;
    *g = (bvox__shape_geom){0};
    if (!s) return bvox__fail(BVOX_EINVAL, "no shape");
    if ((unsigned)s->kind > BVOX_SHAPE_TORUS)
        return bvox__fail(BVOX_EINVAL, "unknown shape kind %d", (int)s->kind);
    g->kind = s->kind;
    for (int i = 0; i < 3; i++) {
        if (!finite_in(s->center[i]))
            return bvox__fail(BVOX_EINVAL, "shape centre %g is not a finite coordinate",
                              s->center[i]);
        g->c[i] = s->center[i];
    }
    double size = 0;
    switch (s->kind) {
    case BVOX_SHAPE_SPHERE:
        if ((st = check_size("radius", s->radius, true))) return st;
        g->r = s->radius;
        for (int i = 0; i < 3; i++) g->lo[i] = g->c[i] - g->r, g->hi[i] = g->c[i] + g->r;
        size = g->r;
        break;
    case BVOX_SHAPE_ELLIPSOID:
    case BVOX_SHAPE_BOX:
        for (int i = 0; i < 3; i++) {
            if ((st = check_size("semi-axis", s->semi_axes[i], s->kind == BVOX_SHAPE_BOX)))
                return st;
            g->a[i] = s->semi_axes[i];
            g->lo[i] = g->c[i] - g->a[i];
            g->hi[i] = g->c[i] + g->a[i];
            size += g->a[i];
        }
        break;
    case BVOX_SHAPE_CYLINDER:
    case BVOX_SHAPE_CONE:
        if ((st = check_size("radius", s->radius, true))) return st;
        if ((st = check_size("height", s->height, s->kind == BVOX_SHAPE_CYLINDER))) return st;
        if ((st = unit_axis(s->axis, g->u))) return st;
        g->r = s->radius;
        if (s->kind == BVOX_SHAPE_CYLINDER) {
            g->h = s->height / 2;
            for (int i = 0; i < 3; i++) {
                double e = g->h * fabs(g->u[i]) + g->r * sin_to(g->u, i);
                g->lo[i] = g->c[i] - e;
                g->hi[i] = g->c[i] + e;
            }
        } else {
            g->h = s->height;
            double k = g->r / g->h;
            if (!isfinite(k * k))
                return bvox__fail(BVOX_EINVAL, "cone of radius %g and height %g is too flat",
                                  g->r, g->h);
            for (int i = 0; i < 3; i++) {
                double e = g->r * sin_to(g->u, i), apex = g->c[i] + g->h * g->u[i];
                g->lo[i] = fmin(g->c[i] - e, apex);
                g->hi[i] = fmax(g->c[i] + e, apex);
            }
        }
        size = g->r + g->h;
        break;
    case BVOX_SHAPE_TORUS:
        if ((st = check_size("radius", s->radius, true))) return st;
        if ((st = check_size("minor radius", s->minor_radius, true))) return st;
        if ((st = unit_axis(s->axis, g->u))) return st;
        g->r = s->radius;
        g->rr = s->minor_radius;
        for (int i = 0; i < 3; i++) {
            double e = g->r * sin_to(g->u, i) + g->rr;
            g->lo[i] = g->c[i] - e;
            g->hi[i] = g->c[i] + e;
        }
        size = g->r + g->rr;
        break;
    }
    /* Widening of candidate intervals: far above the rounding error of the
     * quadratics, far below any sensible voxel size; the caller verifies the
     * end voxels anyway, so a wider candidate only costs a test or two. */
    g->eps = 1e-7 * size;
    return BVOX_OK;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

bool bvox__shape_inside(const bvox__shape_geom *g, double x, double y, double z)
{
    double d[3] = {x - g->c[0], y - g->c[1], z - g->c[2]};
    switch (g->kind) {
    case BVOX_SHAPE_SPHERE: return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= g->r * g->r;
    case BVOX_SHAPE_ELLIPSOID: {
        double e0 = d[0] / g->a[0], e1 = d[1] / g->a[1], e2 = d[2] / g->a[2];
        return e0 * e0 + e1 * e1 + e2 * e2 <= 1.0;
    }
    case BVOX_SHAPE_BOX:
        return fabs(d[0]) <= g->a[0] && fabs(d[1]) <= g->a[1] && fabs(d[2]) <= g->a[2];
    default: break;
    }
    double t = dot3(d, g->u);
    double w[3] = {d[0] - t * g->u[0], d[1] - t * g->u[1], d[2] - t * g->u[2]};
    double w2 = dot3(w, w);
    switch (g->kind) {
    case BVOX_SHAPE_CYLINDER: return fabs(t) <= g->h && w2 <= g->r * g->r;
    case BVOX_SHAPE_CONE: {
        if (t < 0 || t > g->h) return false;
        double rad = g->r * (g->h - t) / g->h;
        return w2 <= rad * rad;
    }
    case BVOX_SHAPE_TORUS: {
        double e = sqrt(w2) - g->r;
        return e * e + t * t <= g->rr * g->rr;
    }
    default: return false;
    }
}

/* ---- intervals of s on a line ---- */

typedef struct span {
    double lo, hi;
} span;

/* The set {s : A s^2 + B s + C <= 0} as up to two spans, each widened by
 * eps. Returns their number. A near-tangent line (discriminant slightly
 * negative through rounding) yields the vertex, so a voxel touching the
 * surface is not lost before the caller's exact check. */
static int quad_le0(double A, double B, double C, double eps, span out[2])
{
    if (A == 0) {
        if (B == 0) {
            if (C > 0) return 0;
            out[0] = (span){-INFINITY, INFINITY};
            return 1;
        }
        double s = -C / B;
        out[0] = B > 0 ? (span){-INFINITY, s + eps} : (span){s - eps, INFINITY};
        return 1;
    }
    double disc = B * B - 4 * A * C;
    if (A > 0) {
        if (disc < 0) {
            if (disc < -1e-9 * (B * B + fabs(4 * A * C))) return 0;
            double v = -B / (2 * A);
            out[0] = (span){v - eps, v + eps};
            return 1;
        }
    } else if (disc <= 0) {
        out[0] = (span){-INFINITY, INFINITY};
        return 1;
    }
    /* stable roots (no cancellation between B and the square root) */
    double q = -0.5 * (B + copysign(sqrt(disc), B));
    double r1 = q != 0 ? q / A : 0, r2 = q != 0 ? C / q : 0;
    if (r1 > r2) {
        double t = r1;
        r1 = r2;
        r2 = t;
    }
    if (A > 0) {
        out[0] = (span){r1 - eps, r2 + eps};
        return 1;
    }
    out[0] = (span){-INFINITY, r1 + eps};
    out[1] = (span){r2 - eps, INFINITY};
    return 2;
}

/* Where t0 + s*uz lies in [tlo, thi], widened by eps (0 if nowhere). When uz
 * is 0 the answer is all or nothing, decided on the same t the exact
 * predicate computes. */
static int slab(double t0, double uz, double tlo, double thi, double eps, span *out)
{
    if (uz == 0) {
        if (t0 < tlo || t0 > thi) return 0;
        *out = (span){-INFINITY, INFINITY};
        return 1;
    }
    double a = (tlo - t0) / uz, b = (thi - t0) / uz;
    *out = a < b ? (span){a - eps, b + eps} : (span){b - eps, a + eps};
    return 1;
}

/* Hull of the non-empty intersections of the pieces with the slab. The true
 * set (a convex shape cut by a line) is one interval, so the hull only
 * absorbs rounding. */
static int clip_pieces(const span *pieces, int n, span cap, span *out)
{
    int found = 0;
    for (int i = 0; i < n; i++) {
        double lo = fmax(pieces[i].lo, cap.lo), hi = fmin(pieces[i].hi, cap.hi);
        if (lo > hi) continue;
        if (!found) *out = (span){lo, hi};
        else *out = (span){fmin(out->lo, lo), fmax(out->hi, hi)};
        found = 1;
    }
    return found;
}

/* Symmetric span [-sqrt(q), sqrt(q)] scaled by f; 0 when q is clearly
 * negative (beyond rounding of terms of size `scale`). */
static int sym(double q, double scale, double f, double eps, span *out)
{
    if (q < -1e-12 * scale) return 0;
    double s = f * sqrt(fmax(q, 0.0));
    *out = (span){-s - eps, s + eps};
    return 1;
}

static int axial_column(const bvox__shape_geom *g, double dx, double dy, span *out)
{
    const double *u = g->u;
    double t0 = dx * u[0] + dy * u[1];
    double w0[3] = {dx - t0 * u[0], dy - t0 * u[1], -t0 * u[2]};
    /* w1 = e_z - uz*u; its z part 1 - uz^2 is written ux^2 + uy^2 to avoid
     * cancellation when the axis is close to z */
    double w1[3] = {-u[2] * u[0], -u[2] * u[1], u[0] * u[0] + u[1] * u[1]};
    double A = dot3(w1, w1), B = 2 * dot3(w0, w1), C = dot3(w0, w0);
    span pieces[2], cap;
    int n;
    if (g->kind == BVOX_SHAPE_CYLINDER) {
        n = quad_le0(A, B, C - g->r * g->r, g->eps, pieces);
        if (!n || !slab(t0, u[2], -g->h, g->h, g->eps, &cap)) return 0;
    } else if (g->kind == BVOX_SHAPE_CONE) {
        /* |w|^2 <= k^2 (h - t)^2 with h - t = T - s*uz, T = h - t0: the double
         * cone; the slab 0 <= t <= h keeps the nappe of the base. */
        double k = g->r / g->h, k2 = k * k, T = g->h - t0;
        n = quad_le0(A - k2 * u[2] * u[2], B + 2 * k2 * T * u[2], C - k2 * T * T, g->eps,
                     pieces);
        if (!n || !slab(t0, u[2], 0, g->h, g->eps, &cap)) return 0;
    } else { /* torus: a superset, the bounding sphere cut by the slab |t| <= rr */
        double R = g->r + g->rr, d2 = dx * dx + dy * dy;
        if (!sym(R * R - d2, R * R + d2, 1.0, g->eps, &pieces[0])) return 0;
        n = 1;
        if (!slab(t0, u[2], -g->rr, g->rr, g->eps, &cap)) return 0;
    }
    return clip_pieces(pieces, n, cap, out);
}

int bvox__shape_column(const bvox__shape_geom *g, double x, double y, double *zlo,
                       double *zhi)
{
    double dx = x - g->c[0], dy = y - g->c[1];
    span s;
    int hit = 0;
    switch (g->kind) {
    case BVOX_SHAPE_SPHERE: {
        double r2 = g->r * g->r, d2 = dx * dx + dy * dy;
        hit = sym(r2 - d2, r2 + d2, 1.0, g->eps, &s);
        break;
    }
    case BVOX_SHAPE_ELLIPSOID: {
        double e0 = dx / g->a[0], e1 = dy / g->a[1], e2 = e0 * e0 + e1 * e1;
        hit = sym(1.0 - e2, 1.0 + e2, g->a[2], g->eps, &s);
        break;
    }
    case BVOX_SHAPE_BOX:
        if (!(fabs(dx) <= g->a[0] && fabs(dy) <= g->a[1])) return 0;
        s = (span){-g->a[2] - g->eps, g->a[2] + g->eps};
        hit = 1;
        break;
    case BVOX_SHAPE_TORUS:
        if (g->u[0] == 0 && g->u[1] == 0) {
            /* axis along z: the distance from the axis is constant on the
             * column, so the tube gives one exact interval */
            double e = sqrt(dx * dx + dy * dy) - g->r, rr2 = g->rr * g->rr;
            hit = sym(rr2 - e * e, rr2 + e * e, 1.0, g->eps, &s);
            break;
        }
        /* fall through */
    default: hit = axial_column(g, dx, dy, &s); break;
    }
    if (!hit) return 0;
    *zlo = g->c[2] + s.lo;
    *zhi = g->c[2] + s.hi;
    return 1;
}
