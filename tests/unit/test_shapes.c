/* test_shapes.c — shapes drawn into volumes, voxel by voxel against a naive
 * per-voxel-centre inside test written here (its own formulas: cross products
 * instead of the library's projections), analytic volumes, the five
 * operations, shapes partly or wholly outside, bad shapes, and the tail-bit
 * invariant after every draw. */
#include "harness.h"
#include "ref/voxref.h"

#include <string.h>

/* ---- the reference: per voxel centre, no cleverness ---- */

static void ref_axis(const double *a, double *u)
{
    double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (n == 0) {
        u[0] = u[1] = 0;
        u[2] = 1;
        return;
    }
    for (int i = 0; i < 3; i++) u[i] = a[i] / n;
}

static double fmax3(double a, double b, double c) { return fmax(a, fmax(b, c)); }

/* Inside test at point p; *f gets a signed, scale-free distance to the
 * boundary (<= 0 inside) so that comparisons can tell a genuine error from a
 * centre lying on the surface to within rounding. */
static int ref_inside(const bvox_shape *s, const double *p, double *f)
{
    double d[3] = {p[0] - s->center[0], p[1] - s->center[1], p[2] - s->center[2]};
    double u[3], t = 0, perp2 = 0;
    if (s->kind >= BVOX_SHAPE_CYLINDER) {
        ref_axis(s->axis, u);
        t = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
        double c[3] = {d[1] * u[2] - d[2] * u[1], d[2] * u[0] - d[0] * u[2],
                       d[0] * u[1] - d[1] * u[0]};
        perp2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    }
    switch (s->kind) {
    case BVOX_SHAPE_SPHERE: {
        double r2 = s->radius * s->radius;
        double q = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        *f = (q - r2) / (r2 + 1);
        return q <= r2;
    }
    case BVOX_SHAPE_ELLIPSOID: {
        double q = 0;
        for (int i = 0; i < 3; i++) q += (d[i] / s->semi_axes[i]) * (d[i] / s->semi_axes[i]);
        *f = q - 1;
        return q <= 1;
    }
    case BVOX_SHAPE_BOX: {
        const double *a = s->semi_axes;
        *f = fmax3(fabs(d[0]) - a[0], fabs(d[1]) - a[1], fabs(d[2]) - a[2]) /
             (a[0] + a[1] + a[2] + 1);
        return fabs(d[0]) <= a[0] && fabs(d[1]) <= a[1] && fabs(d[2]) <= a[2];
    }
    case BVOX_SHAPE_CYLINDER: {
        double L = s->radius + s->height + 1, r2 = s->radius * s->radius;
        *f = fmax((fabs(t) - s->height / 2) / L, (perp2 - r2) / (L * L));
        return fabs(t) <= s->height / 2 && perp2 <= r2;
    }
    case BVOX_SHAPE_CONE: {
        double L = s->radius + s->height + 1, rad = s->radius * (1 - t / s->height);
        *f = fmax3(-t, t - s->height, sqrt(perp2) - rad) / L;
        return t >= 0 && t <= s->height && sqrt(perp2) <= rad;
    }
    case BVOX_SHAPE_TORUS: {
        double L = s->radius + s->minor_radius + 1, e = sqrt(perp2) - s->radius;
        double q = e * e + t * t, r2 = s->minor_radius * s->minor_radius;
        *f = (q - r2) / (L * L);
        return q <= r2;
    }
    }
    *f = 1;
    return 0;
}

static int ref_op(int d, int in, bvox_csg_op op)
{
    switch (op) {
    case BVOX_CSG_UNION:
    case BVOX_CSG_REPLACE: return d | in;
    case BVOX_CSG_INTERSECTION: return d & in;
    case BVOX_CSG_DIFFERENCE: return d & !in;
    case BVOX_CSG_XOR: return d ^ in;
    }
    return d;
}

/* Draw s with op into v (whose content is init) and compare every voxel with
 * the reference. A difference is tolerated only where the centre lies on
 * the boundary to within tol (relative); tol = 0 demands exact equality. */
static int draw_and_compare(bvox_volume *v, const voxref *init, const bvox_shape *s,
                            bvox_csg_op op, double tol)
{
    CHECK_OK(bvox_shape_draw(v, s, op));
    CHECK_OK(bvox_volume_check(v));
    const bvox_geometry *g = bvox_volume_geometry(v);
    long tolerated = 0;
    for (int z = 0; z < init->nz; z++)
        for (int y = 0; y < init->ny; y++)
            for (int x = 0; x < init->nx; x++) {
                double p[3] = {g->origin[0] + x * g->spacing[0],
                               g->origin[1] + y * g->spacing[1],
                               g->origin[2] + z * g->spacing[2]};
                double f;
                int in = ref_inside(s, p, &f);
                int want = ref_op(*voxref_at(init, x, y, z), in, op);
                int got = bvox_volume_get(v, x, y, z);
                if (got == want) continue;
                if (tol > 0 && fabs(f) <= tol) {
                    tolerated++;
                    continue;
                }
                fprintf(stderr,
                        "%s op %d: voxel (%d,%d,%d) at (%g,%g,%g): got %d, want %d "
                        "(margin %g)\n",
                        bvox_shape_kind_name(s->kind), (int)op, x, y, z, p[0], p[1], p[2],
                        got, want, f);
                return 1;
            }
    /* boundary coincidences at random positions must stay rare */
    CHECK(tolerated <= 2);
    return 0;
}

/* New volume with given dims/spacing/origin holding init's voxels. */
static bvox_volume *make_volume(const voxref *init, const double *sp, const double *org)
{
    bvox_volume *v = voxref_to_volume(init);
    if (!v) return NULL;
    bvox_geometry g = *bvox_volume_geometry(v);
    for (int i = 0; i < 3; i++) {
        g.spacing[i] = sp[i];
        g.origin[i] = org[i];
    }
    if (bvox_volume_set_geometry(v, &g) != BVOX_OK) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

static double urand(void) { return (double)(harness_rand() >> 11) / 9007199254740992.0; }
static double urange(double lo, double hi) { return lo + (hi - lo) * urand(); }

/* A random shape of a kind, of a size comparable to the extent ext (physical),
 * centred near mid but possibly sticking out of the volume. */
static bvox_shape random_shape(bvox_shape_kind kind, const double *mid, const double *ext)
{
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = kind;
    double e = fmin(ext[0], fmin(ext[1], ext[2]));
    for (int i = 0; i < 3; i++) {
        s.center[i] = mid[i] + urange(-0.45, 0.45) * ext[i];
        s.semi_axes[i] = urange(0.1, 0.4) * ext[i];
    }
    /* axes along and across z, and nearly so (the degenerate quadratics) */
    static const double special[][3] = {{0, 0, 1},  {0, 0, -3},       {1, 0, 0},
                                        {0, 2, 0},  {0, 0, 0},        {1, 1, 0},
                                        {1, 0, 1},  {0, 1, 1e-9},     {1e-9, 0, 1},
                                        {1e-13, -1e-12, -1}, {-1, 1e-12, 1e-13}};
    const uint64_t nspecial = sizeof special / sizeof special[0];
    uint64_t pick = harness_rand() % (2 * nspecial);
    for (int i = 0; i < 3; i++)
        s.axis[i] = pick < nspecial ? special[pick][i] : urange(-1, 1);
    s.radius = urange(0.1, 0.35) * e;
    s.height = urange(0.2, 0.8) * e;
    s.minor_radius = urange(0.05, 0.2) * e;
    if (kind == BVOX_SHAPE_TORUS && harness_rand() % 4 == 0)
        s.minor_radius = s.radius * urange(1.0, 1.5); /* spindle */
    return s;
}

static const int vol_sizes[][3] = {{23, 19, 1}, {21, 17, 63}, {19, 23, 64},
                                   {17, 21, 65}, {15, 13, 130}};
#define NVOL (int)(sizeof vol_sizes / sizeof vol_sizes[0])

/* Every kind, many random placements and orientations, anisotropic voxels,
 * into an empty volume and with each op into random content. */
static int sweep(bvox_shape_kind kind)
{
    for (int vi = 0; vi < NVOL; vi++) {
        const int *n = vol_sizes[vi];
        for (int rep = 0; rep < 6; rep++) {
            double sp[3] = {urange(0.3, 2.0), urange(0.3, 2.0), urange(0.3, 2.0)};
            double org[3] = {urange(-50, 50), urange(-50, 50), urange(-50, 50)};
            double ext[3], mid[3];
            for (int i = 0; i < 3; i++) {
                ext[i] = n[i] * sp[i];
                mid[i] = org[i] + ext[i] / 2;
            }
            if (n[2] == 1) ext[2] = fmax(ext[0], ext[1]); /* shapes thicker than one slice */
            bvox_shape s = random_shape(kind, mid, ext);
            for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
                voxref *init = voxref_create(n[0], n[1], n[2]);
                CHECK(init != NULL);
                if (op != BVOX_CSG_UNION || rep % 2) voxref_random(init, 1, 2, harness_rand);
                bvox_volume *v = make_volume(init, sp, org);
                CHECK(v != NULL);
                int rc = draw_and_compare(v, init, &s, (bvox_csg_op)op, 1e-9);
                bvox_volume_destroy(v);
                voxref_destroy(init);
                if (rc) {
                    fprintf(stderr, "volume %dx%dx%d rep %d\n", n[0], n[1], n[2], rep);
                    return 1;
                }
            }
        }
    }
    return 0;
}

TEST(sphere_vs_reference) { return sweep(BVOX_SHAPE_SPHERE); }
TEST(ellipsoid_vs_reference) { return sweep(BVOX_SHAPE_ELLIPSOID); }
TEST(box_vs_reference) { return sweep(BVOX_SHAPE_BOX); }
TEST(cylinder_vs_reference) { return sweep(BVOX_SHAPE_CYLINDER); }
TEST(cone_vs_reference) { return sweep(BVOX_SHAPE_CONE); }
TEST(torus_vs_reference) { return sweep(BVOX_SHAPE_TORUS); }

/* Integer placements where many centres lie exactly on the surface: the
 * boundary is inclusive and must match exactly (tol 0), with hand-counted
 * totals (lattice points of a ball of radius 5: 515). */
TEST(exact_boundaries)
{
    static const double unit[3] = {1, 1, 1}, org[3] = {0, 0, 0};
    struct {
        bvox_shape s;
        int64_t count;
    } cases[] = {
        {{BVOX_SHAPE_SPHERE, {10, 10, 10}, {0}, {0}, 5, 0, 0}, 515},
        {{BVOX_SHAPE_SPHERE, {3, 4, 5}, {0}, {0}, 0, 0, 0}, 1},
        {{BVOX_SHAPE_BOX, {10, 10, 10}, {2, 2, 2}, {0}, 0, 0, 0}, 125},
        {{BVOX_SHAPE_BOX, {10.5, 10.5, 10.5}, {2, 2, 2}, {0}, 0, 0, 0}, 64},
        {{BVOX_SHAPE_BOX, {7, 8, 9}, {0, 0, 0}, {0}, 0, 0, 0}, 1},
        /* along x: 7 slabs of the 29 lattice points of a disc of radius 3 */
        {{BVOX_SHAPE_CYLINDER, {10, 10, 10}, {0}, {1, 0, 0}, 3, 0, 6}, 203},
        {{BVOX_SHAPE_CYLINDER, {10, 10, 10}, {0}, {0, 0, -2}, 3, 0, 6}, 203},
        {{BVOX_SHAPE_CYLINDER, {10, 10, 10}, {0}, {0}, 2, 0, 0}, 13},
        {{BVOX_SHAPE_CONE, {10, 4, 10}, {0}, {0, 1, 0}, 4, 0, 8}, 165},
        {{BVOX_SHAPE_TORUS, {10, 10, 10}, {0}, {0, 0, 1}, 6, 2, 0}, 408},
        {{BVOX_SHAPE_TORUS, {10, 10, 10}, {0}, {1, 0, 0}, 6, 2, 0}, 408},
        {{BVOX_SHAPE_TORUS, {10, 10, 10}, {0}, {0, -1, 0}, 6, 2, 0}, 408},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
            voxref *init = voxref_create(21, 22, 23);
            if (op != BVOX_CSG_UNION) voxref_random(init, 1, 3, harness_rand);
            bvox_volume *v = make_volume(init, unit, org);
            CHECK(v != NULL);
            int rc = draw_and_compare(v, init, &cases[c].s, (bvox_csg_op)op, 0);
            if (!rc && op == BVOX_CSG_UNION && bvox_volume_count(v) != cases[c].count) {
                fprintf(stderr, "case %zu: count %lld, want %lld\n", c,
                        (long long)bvox_volume_count(v), (long long)cases[c].count);
                rc = 1;
            }
            bvox_volume_destroy(v);
            voxref_destroy(init);
            if (rc) {
                fprintf(stderr, "exact case %zu op %d\n", c, op);
                return 1;
            }
        }
    }
    return 0;
}

/* Count times voxel volume approaches the analytic volume at good resolution. */
static int volume_close(const bvox_shape *s, const int *n, const double *sp, double rel)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){n[0], n[1], n[2]}, &v));
    CHECK_OK(bvox_volume_set_spacing(v, sp[0], sp[1], sp[2], "mm"));
    CHECK_OK(bvox_shape_draw(v, s, BVOX_CSG_UNION));
    CHECK_OK(bvox_volume_check(v));
    double got = (double)bvox_volume_count(v) * sp[0] * sp[1] * sp[2];
    double want = bvox_shape_volume(s);
    bvox_volume_destroy(v);
    if (fabs(got - want) > rel * want) {
        fprintf(stderr, "%s: voxel volume %g, analytic %g\n", bvox_shape_kind_name(s->kind),
                got, want);
        return 1;
    }
    return 0;
}

TEST(volumes_converge)
{
    const double one[3] = {1, 1, 1}, aniso[3] = {0.5, 0.8, 1.25};
    const int n100[3] = {100, 100, 100}, n_an[3] = {200, 125, 80};
    /* sphere r = 40 voxels: within 0.5 % */
    bvox_shape sphere = {BVOX_SHAPE_SPHERE, {50.3, 49.8, 50.1}, {0}, {0}, 40, 0, 0};
    CHECK(!volume_close(&sphere, n100, one, 0.005));
    /* the same physical sphere on anisotropic voxels */
    CHECK(!volume_close(&sphere, n_an, aniso, 0.005));
    bvox_shape ell = {BVOX_SHAPE_ELLIPSOID, {50, 50, 50}, {45, 30, 20}, {0}, 0, 0, 0};
    CHECK(!volume_close(&ell, n_an, aniso, 0.005));
    bvox_shape box = {BVOX_SHAPE_BOX, {50, 50, 50}, {40.2, 30.3, 20.4}, {0}, 0, 0, 0};
    CHECK(!volume_close(&box, n100, one, 0.02));
    bvox_shape cyl = {BVOX_SHAPE_CYLINDER, {50, 50, 50}, {0}, {1, 2, 3}, 20, 0, 60};
    CHECK(!volume_close(&cyl, n_an, aniso, 0.01));
    bvox_shape cone = {BVOX_SHAPE_CONE, {40, 45, 35}, {0}, {1, 1, 2}, 30, 0, 50};
    CHECK(!volume_close(&cone, n100, one, 0.01));
    bvox_shape torus = {BVOX_SHAPE_TORUS, {50, 50, 50}, {0}, {1, -2, 0.5}, 30, 12, 0};
    CHECK(!volume_close(&torus, n_an, aniso, 0.01));
    bvox_shape ztorus = {BVOX_SHAPE_TORUS, {50.3, 49.6, 50.2}, {0}, {0, 0, 1}, 30, 12, 0};
    CHECK(!volume_close(&ztorus, n100, one, 0.01));
    bvox_shape spindle = {BVOX_SHAPE_TORUS, {50, 50, 50}, {0}, {0, 1, 1}, 15, 25, 0};
    CHECK(!volume_close(&spindle, n100, one, 0.01));
    return 0;
}

TEST(analytic_volume_formulas)
{
    bvox_shape s = {BVOX_SHAPE_SPHERE, {1, 2, 3}, {2, 3, 4}, {0}, 2, 1, 3};
    CHECK_NEAR(bvox_shape_volume(&s), 32.0 / 3.0 * M_PI, 1e-12);
    s.kind = BVOX_SHAPE_ELLIPSOID;
    CHECK_NEAR(bvox_shape_volume(&s), 4.0 / 3.0 * M_PI * 24, 1e-12);
    s.kind = BVOX_SHAPE_BOX;
    CHECK_NEAR(bvox_shape_volume(&s), 8.0 * 24, 1e-12);
    s.kind = BVOX_SHAPE_CYLINDER;
    CHECK_NEAR(bvox_shape_volume(&s), M_PI * 4 * 3, 1e-12);
    s.kind = BVOX_SHAPE_CONE;
    CHECK_NEAR(bvox_shape_volume(&s), M_PI * 4 * 3 / 3.0, 1e-12);
    s.kind = BVOX_SHAPE_TORUS;
    CHECK_NEAR(bvox_shape_volume(&s), 2 * M_PI * M_PI * 2 * 1, 1e-12);
    /* spindle torus: continuous at minor == ring radius, a sphere at ring 0 */
    s.minor_radius = 2 * (1 + 1e-12);
    CHECK_NEAR(bvox_shape_volume(&s), 2 * M_PI * M_PI * 8, 1e-9);
    s.radius = 0;
    s.minor_radius = 3;
    CHECK_NEAR(bvox_shape_volume(&s), 4.0 / 3.0 * M_PI * 27, 1e-9);
    s.radius = -1;
    CHECK(bvox_shape_volume(&s) == -1);
    s.kind = (bvox_shape_kind)17;
    CHECK(bvox_shape_volume(&s) == -1);
    CHECK(bvox_shape_volume(NULL) == -1);
    return 0;
}

TEST(kind_names)
{
    for (int k = BVOX_SHAPE_SPHERE; k <= BVOX_SHAPE_TORUS; k++)
        CHECK_EQ(bvox_shape_kind_parse(bvox_shape_kind_name((bvox_shape_kind)k)), k);
    CHECK(!strcmp(bvox_shape_kind_name(BVOX_SHAPE_CONE), "cone"));
    CHECK_EQ(bvox_shape_kind_parse("Torus"), BVOX_SHAPE_TORUS);
    CHECK_EQ(bvox_shape_kind_parse("cube"), -1);
    CHECK_EQ(bvox_shape_kind_parse(""), -1);
    CHECK_EQ(bvox_shape_kind_parse(NULL), -1);
    return 0;
}

TEST(bad_shapes_rejected)
{
    const double nan = NAN, inf = INFINITY;
    bvox_shape good = {BVOX_SHAPE_CONE, {5, 5, 5}, {1, 1, 1}, {0, 0, 1}, 2, 1, 3};
    bvox_shape bad[14];
    for (int i = 0; i < 14; i++) bad[i] = good;
    bad[0].radius = -1;
    bad[1].radius = nan;
    bad[2].height = 0; /* a cone needs a height */
    bad[3].center[1] = inf;
    bad[4].axis[2] = nan;
    bad[5].kind = (bvox_shape_kind)6;
    bad[6].kind = BVOX_SHAPE_ELLIPSOID, bad[6].semi_axes[2] = 0;
    bad[7].kind = BVOX_SHAPE_BOX, bad[7].semi_axes[0] = -0.5;
    bad[8].kind = BVOX_SHAPE_TORUS, bad[8].minor_radius = -2;
    bad[9].kind = BVOX_SHAPE_CYLINDER, bad[9].height = -1;
    bad[10].kind = BVOX_SHAPE_SPHERE, bad[10].radius = inf;
    bad[11].kind = BVOX_SHAPE_SPHERE, bad[11].radius = 1e300; /* its square overflows */
    bad[12].kind = BVOX_SHAPE_ELLIPSOID, bad[12].semi_axes[1] = nan;
    bad[13].kind = BVOX_SHAPE_CONE, bad[13].height = 1e-300; /* radius / height overflows */
    voxref *init = voxref_create(11, 12, 70);
    voxref_random(init, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(init);
    for (int i = 0; i < 14; i++) {
        CHECK_STATUS(bvox_shape_draw(v, &bad[i], BVOX_CSG_UNION), BVOX_EINVAL);
        CHECK(strlen(bvox_errmsg()) > 0);
        CHECK(bvox_shape_volume(&bad[i]) == -1);
    }
    CHECK_STATUS(bvox_shape_draw(v, &good, (bvox_csg_op)9), BVOX_EINVAL);
    CHECK_STATUS(bvox_shape_draw(v, NULL, BVOX_CSG_UNION), BVOX_EINVAL);
    CHECK_STATUS(bvox_shape_draw(NULL, &good, BVOX_CSG_UNION), BVOX_EINVAL);
    CHECK(voxref_matches(init, v)); /* refused draws change nothing */
    /* zero sizes where they make sense are fine */
    bvox_shape flat = {BVOX_SHAPE_CYLINDER, {5, 5, 5}, {0}, {0}, 0, 0, 0};
    CHECK_OK(bvox_shape_draw(v, &flat, BVOX_CSG_UNION));
    CHECK_EQ(bvox_volume_get(v, 5, 5, 5), 1);
    bvox_volume_destroy(v);
    voxref_destroy(init);
    return 0;
}

/* The axis need not be unit length, (0,0,0) means +z, and -z draws the same
 * cylinder; a cone pointing down is the mirror image of one pointing up. */
TEST(axis_conventions)
{
    bvox_shape a = {BVOX_SHAPE_CYLINDER, {15.2, 14.7, 40.3}, {0}, {0, 0, 0}, 9.5, 0, 50};
    bvox_shape b = a, c = a;
    b.axis[2] = 7;
    c.axis[2] = -0.01;
    bvox_volume *va, *vb, *vc;
    CHECK_OK(bvox_volume_create((bvox_dims){31, 30, 90}, &va));
    CHECK_OK(bvox_volume_create((bvox_dims){31, 30, 90}, &vb));
    CHECK_OK(bvox_volume_create((bvox_dims){31, 30, 90}, &vc));
    CHECK_OK(bvox_shape_draw(va, &a, BVOX_CSG_UNION));
    CHECK_OK(bvox_shape_draw(vb, &b, BVOX_CSG_UNION));
    CHECK_OK(bvox_shape_draw(vc, &c, BVOX_CSG_UNION));
    CHECK(bvox_volume_count(va) > 0);
    CHECK(bvox_volume_equal(va, vb));
    CHECK(bvox_volume_equal(va, vc));
    /* cone up from z = 10 vs cone down from z = 79 in a 90-deep volume */
    bvox_shape up = {BVOX_SHAPE_CONE, {15, 15, 10}, {0}, {0, 0, 1}, 12, 0, 60};
    bvox_shape down = up;
    down.center[2] = 79;
    down.axis[2] = -1;
    bvox_volume_fill(va, 0);
    bvox_volume_fill(vb, 0);
    CHECK_OK(bvox_shape_draw(va, &up, BVOX_CSG_UNION));
    CHECK_OK(bvox_shape_draw(vb, &down, BVOX_CSG_UNION));
    CHECK(bvox_volume_count(va) > 1000);
    for (int z = 0; z < 90; z++)
        for (int y = 0; y < 30; y++)
            for (int x = 0; x < 31; x++)
                CHECK_EQ(bvox_volume_get(va, x, y, z), bvox_volume_get(vb, x, y, 89 - z));
    bvox_volume_destroy(va);
    bvox_volume_destroy(vb);
    bvox_volume_destroy(vc);
    return 0;
}

/* Outside the volume: union/difference/xor change nothing, intersection
 * clears everything; straddling a corner matches the reference. */
TEST(outside_and_straddling)
{
    static const double sp[3] = {1.5, 0.75, 1.0}, org[3] = {-10, 20, 3};
    voxref *init = voxref_create(25, 27, 65);
    voxref_random(init, 1, 2, harness_rand);
    bvox_shape far = {BVOX_SHAPE_SPHERE, {-100, 20, 30}, {0}, {0}, 20, 0, 0};
    for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
        bvox_volume *v = make_volume(init, sp, org);
        CHECK_OK(bvox_shape_draw(v, &far, (bvox_csg_op)op));
        CHECK_OK(bvox_volume_check(v));
        CHECK_EQ(bvox_volume_count(v), op == BVOX_CSG_INTERSECTION ? 0 : voxref_count(init));
        bvox_volume_destroy(v);
    }
    for (int k = BVOX_SHAPE_SPHERE; k <= BVOX_SHAPE_TORUS; k++) {
        /* centred on the corner (x0, y1, z1) of the volume */
        bvox_shape s = {(bvox_shape_kind)k, {-10, 20 + 26 * 0.75, 3 + 64}, {12, 9, 20},
                        {1, 1, 1}, 14, 5, 30};
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
            bvox_volume *v = make_volume(init, sp, org);
            int rc = draw_and_compare(v, init, &s, (bvox_csg_op)op, 1e-9);
            bvox_volume_destroy(v);
            CHECK(rc == 0);
        }
    }
    voxref_destroy(init);
    return 0;
}

/* Rows are split over threads: the result must not depend on their number. */
TEST(threads_agree)
{
    bvox_shape s = {BVOX_SHAPE_TORUS, {60, 55, 50}, {0}, {0.3, 1, 0.2}, 35, 10, 0};
    bvox_volume *a, *b;
    CHECK_OK(bvox_volume_create((bvox_dims){120, 110, 100}, &a));
    CHECK_OK(bvox_volume_create((bvox_dims){120, 110, 100}, &b));
    int saved = bvox_threads();
    for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
        bvox_volume_fill(a, 0);
        bvox_volume_fill_box(a, (bvox_box){10, 10, 10, 100, 90, 70}, 1);
        bvox_volume_fill(b, 0);
        bvox_volume_fill_box(b, (bvox_box){10, 10, 10, 100, 90, 70}, 1);
        bvox_set_threads(1);
        CHECK_OK(bvox_shape_draw(a, &s, (bvox_csg_op)op));
        bvox_set_threads(2);
        CHECK_OK(bvox_shape_draw(b, &s, (bvox_csg_op)op));
        CHECK(bvox_volume_equal(a, b));
        CHECK_OK(bvox_volume_check(b));
    }
    bvox_set_threads(saved);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return 0;
}
