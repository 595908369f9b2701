/* test_measure.c — bvox_measure against known answers (a voxel, boxes, a
 * hollow box, a torus, spheres and ellipsoids in isotropic and anisotropic
 * voxels, the Crofton weights' published values) and against the slow
 * per-voxel references of tests/ref/measref.c on random volumes at awkward
 * sizes; thread count and SIMD path must not change the result. */
#include "harness.h"
#include "internal.h"
#include "measure/measure.h"
#include "ref/measref.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

static bvox_volume *make(int nx, int ny, int nz, double sx, double sy, double sz)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){nx, ny, nz}, &v)) return NULL;
    bvox_volume_set_spacing(v, sx, sy, sz, "mm");
    return v;
}

static int rel_near(double a, double b, double rel)
{
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)) + 1e-12;
}

_Static_assert(MEASREF_NCLASS == BVOX__NDIR && BVOX__DIR_XYZ == 6, "same class order");

/* Compare a measure with the reference. */
static int check_against_ref(const bvox_measures *m, const measref *o, const double *w)
{
    CHECK_EQ(m->count, o->count);
    for (int a = 0; a < 3; a++) CHECK_EQ(m->faces[a], o->faces[a]);
    CHECK_EQ(m->euler, o->euler);
    CHECK_EQ(m->components, o->components);
    CHECK_EQ(m->cavities, o->cavities);
    CHECK_EQ(m->cavities_26, o->cavities_26);
    double area = 0;
    for (int c = 0; c < BVOX__NDIR; c++) area += w[c] * (double)o->trans[c];
    CHECK(rel_near(m->area, area, 1e-12));
    for (int i = 0; i < 3; i++) CHECK(fabs(m->centroid[i] - o->centroid[i]) <= 1e-9);
    for (int i = 0; i < 9; i++) CHECK(fabs(m->covariance[i] - o->cov[i]) <= 1e-9);
    return 0;
}

/* ---- the Crofton weights ---- */

TEST(crofton_weights)
{
    /* cubic voxels: the published spherical Voronoi areas (MorphoLibJ, ITK) */
    double omega[BVOX__NDIR];
    bvox__crofton_solid_angles((const double[3]){1, 1, 1}, omega);
    const double want[3] = {0.04577789120476, 0.03698062787608, 0.03519563978232};
    for (int c = 0; c < 3; c++) CHECK_NEAR(omega[c] / (4 * M_PI), want[0], 1e-13);
    for (int c = 3; c < 6; c++) CHECK_NEAR(omega[c] / (4 * M_PI), want[1], 1e-13);
    CHECK_NEAR(omega[6] / (4 * M_PI), want[2], 1e-13);
    /* any spacing: the 26 cells tile the sphere; permuting the spacing
     * permutes the cells */
    const double sp[][3] = {{1, 1, 2.5}, {0.3, 1, 1}, {1, 2, 5}, {5, 2, 1}, {0.01, 1, 100}};
    for (int s = 0; s < 5; s++) {
        bvox__crofton_solid_angles(sp[s], omega);
        double total = 2 * (omega[0] + omega[1] + omega[2]) +
                       4 * (omega[3] + omega[4] + omega[5]) + 8 * omega[6];
        CHECK_NEAR(total, 4 * M_PI, 1e-12);
        for (int c = 0; c < BVOX__NDIR; c++) CHECK(omega[c] >= 0);
    }
    double a[BVOX__NDIR], b[BVOX__NDIR];
    bvox__crofton_solid_angles((const double[3]){1, 2, 5}, a);
    bvox__crofton_solid_angles((const double[3]){5, 2, 1}, b);
    CHECK_NEAR(a[BVOX__DIR_X], b[BVOX__DIR_Z], 1e-13);
    CHECK_NEAR(a[BVOX__DIR_XY], b[BVOX__DIR_YZ], 1e-13);
    CHECK_NEAR(a[BVOX__DIR_XZ], b[BVOX__DIR_XZ], 1e-13);
    CHECK_NEAR(a[BVOX__DIR_XYZ], b[BVOX__DIR_XYZ], 1e-13);
    return 0;
}

/* ---- hand-computed cases ---- */

TEST(single_voxel)
{
    const double sx = 0.5, sy = 2, sz = 3;
    for (int n = 1; n <= 3; n += 2) { /* alone in the volume, and inside */
        bvox_volume *v = make(n, n, n, sx, sy, sz);
        CHECK(v);
        int c = n / 2;
        CHECK_OK(bvox_volume_set(v, c, c, c, 1));
        bvox_measures m;
        CHECK_OK(bvox_measure(v, &m));
        CHECK_EQ(m.count, 1);
        CHECK_NEAR(m.volume, sx * sy * sz, 1e-12);
        for (int a = 0; a < 3; a++) CHECK_EQ(m.faces[a], 2);
        CHECK_NEAR(m.area_faces, 2 * (sx * sy + sy * sz + sx * sz), 1e-12);
        CHECK_EQ(m.euler, 1);
        CHECK_EQ(m.components, 1);
        CHECK_EQ(m.cavities, 0);
        CHECK_EQ(m.tunnels, 0);
        CHECK(m.bbox.x0 == c && m.bbox.x1 == c + 1 && m.bbox.z0 == c && m.bbox.z1 == c + 1);
        CHECK_NEAR(m.centroid[0], c * sx, 1e-12);
        CHECK_NEAR(m.centroid[2], c * sz, 1e-12);
        CHECK_NEAR(m.extent_min[1], (c - 0.5) * sy, 1e-12);
        CHECK_NEAR(m.extent_max[1], (c + 0.5) * sy, 1e-12);
        for (int i = 0; i < 9; i++) CHECK_NEAR(m.covariance[i], 0, 1e-12);
        CHECK(m.area > 0);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(empty_and_full)
{
    bvox_volume *v = make(5, 6, 70, 1, 2, 3);
    CHECK(v);
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.count, 0);
    CHECK_EQ(m.euler, 0);
    CHECK_EQ(m.components + m.cavities + m.tunnels, 0);
    CHECK(m.area == 0 && m.area_faces == 0 && m.sphericity == 0);
    CHECK(m.principal_axes[0] == 1 && m.principal_axes[4] == 1 && m.principal_axes[8] == 1);
    bvox_volume_fill(v, 1); /* the whole volume is a box touching every border */
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.count, 5 * 6 * 70);
    CHECK_EQ(m.faces[0], 2 * 6 * 70);
    CHECK_EQ(m.faces[1], 2 * 5 * 70);
    CHECK_EQ(m.faces[2], 2 * 5 * 6);
    CHECK_EQ(m.euler, 1);
    CHECK_EQ(m.cavities, 0);
    CHECK_NEAR(m.extent_min[2], -1.5, 1e-12);
    CHECK_NEAR(m.extent_max[2], 70 * 3 - 1.5, 1e-12);
    bvox_volume_destroy(v);
    return 0;
}

/* Crofton area of an a x b x c box from its transitions in closed form: a
 * pair along (1,1,0) has one end in and one out in 2 (abc - (a-1)(b-1)c)
 * cases, and so on. */
static double box_crofton(int a, int b, int c, const double *w)
{
    double n = (double)a * b * c, A = a - 1, B = b - 1, C = c - 1;
    double t[BVOX__NDIR] = {2.0 * b * c, 2.0 * a * c, 2.0 * a * b, 2 * 2 * (n - A * B * c),
                            2 * 2 * (n - A * b * C), 2 * 2 * (n - a * B * C), 4 * 2 * (n - A * B * C)};
    double area = 0;
    for (int k = 0; k < BVOX__NDIR; k++) area += w[k] * t[k];
    return area;
}

TEST(box_exact)
{
    const int a = 8, b = 12, c = 20;
    const double sp[3] = {0.5, 1, 2};
    bvox_volume *v = make(20, 17, 70, sp[0], sp[1], sp[2]);
    CHECK(v);
    bvox_geometry g = *bvox_volume_geometry(v);
    g.origin[0] = 10, g.origin[1] = -3, g.origin[2] = 1000; /* far away: no cancellation */
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    bvox_volume_fill_box(v, (bvox_box){3, 2, 40, 3 + a, 2 + b, 40 + c}, 1);
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.count, a * b * c);
    CHECK_EQ(m.faces[0], 2 * b * c);
    CHECK_EQ(m.faces[1], 2 * a * c);
    CHECK_EQ(m.faces[2], 2 * a * b);
    double A = a * sp[0], B = b * sp[1], C = c * sp[2];
    CHECK_NEAR(m.area_faces, 2 * (A * B + B * C + A * C), 1e-9);
    CHECK_NEAR(m.centroid[0], 10 + (3 + (a - 1) / 2.0) * sp[0], 1e-9);
    CHECK_NEAR(m.centroid[1], -3 + (2 + (b - 1) / 2.0) * sp[1], 1e-9);
    CHECK_NEAR(m.centroid[2], 1000 + (40 + (c - 1) / 2.0) * sp[2], 1e-9);
    /* discrete uniform variance s^2 (n^2 - 1) / 12, exactly; no cross terms */
    double var[3] = {sp[0] * sp[0] * (a * a - 1) / 12.0, sp[1] * sp[1] * (b * b - 1) / 12.0,
                     sp[2] * sp[2] * (c * c - 1) / 12.0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) CHECK_NEAR(m.covariance[i * 3 + j], i == j ? var[i] : 0, 1e-9);
    /* sorted largest first: z (40 long), y (12), x (4) */
    CHECK_NEAR(m.principal_moments[0], var[2], 1e-9);
    CHECK_NEAR(m.principal_moments[1], var[1], 1e-9);
    CHECK_NEAR(m.principal_moments[2], var[0], 1e-9);
    CHECK_NEAR(m.principal_axes[2], 1, 1e-12);
    CHECK_NEAR(m.principal_axes[4], 1, 1e-12);
    CHECK_NEAR(m.principal_axes[6], 1, 1e-12);
    /* inertia of a solid box about its long axis: M (A^2 + B^2) / 12 in the
     * continuous form; the point masses miss the voxels' own s^2/12 */
    double M = m.volume;
    CHECK_NEAR(m.principal_inertia[0], M * (var[0] + var[1]), 1e-6);
    CHECK(rel_near(m.principal_inertia[0], M * (A * A + B * B) / 12, 0.02));
    CHECK(rel_near(m.principal_inertia[2], M * (B * B + C * C) / 12, 0.02));
    CHECK_NEAR(m.inertia[0], M * (var[1] + var[2]), 1e-6);
    CHECK_EQ(m.euler, 1);
    CHECK_EQ(m.tunnels, 0);
    CHECK_NEAR(m.extent_min[0], 10 + 2.5 * sp[0], 1e-12);
    CHECK_NEAR(m.extent_max[2], 1000 + 59.5 * sp[2], 1e-12);
    /* positions ignore direction (the frame of the shapes) */
    double cz = m.centroid[2];
    g.direction[0] = g.direction[4] = 0, g.direction[1] = g.direction[3] = 1;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    CHECK_OK(bvox_measure(v, &m));
    CHECK(m.centroid[2] == cz && m.principal_axes[2] > 0.999);
    double w[BVOX__NDIR];
    bvox__crofton_weights(sp, w);
    CHECK(rel_near(m.area, box_crofton(a, b, c, w), 1e-12));
    bvox_volume_destroy(v);

    /* Crofton area of a cube, cubic voxels, in closed form: a pair along
     * (1,1,0) crosses the boundary when one end is in and the other out,
     * 2 (n^3 - (n-1)^2 n) such pairs, and so on; published weights. */
    for (int k = 0; k < 2; k++) {
        const int e = k ? 40 : 20;
        v = make(e + 6, e + 6, e + 6, 1, 1, 1);
        bvox_volume_fill_box(v, (bvox_box){3, 3, 3, 3 + e, 3 + e, 3 + e}, 1);
        CHECK_OK(bvox_measure(v, &m));
        double pub[BVOX__NDIR] = {0.04577789120476, 0.04577789120476, 0.04577789120476,
                                  0.03698062787608, 0.03698062787608, 0.03698062787608,
                                  0.03519563978232};
        for (int c2 = 0; c2 < BVOX__NDIR; c2++) /* Omega/pi / |d| */
            pub[c2] *= 4 / sqrt(c2 < 3 ? 1 : c2 < 6 ? 2 : 3);
        CHECK(rel_near(m.area, box_crofton(e, e, e, pub), 1e-12));
        /* under by 7.3% for a large cube (the axis-aligned plane), a bit more
         * for a small one (its edges) */
        CHECK(m.area < 0.93 * 6 * e * e && m.area > 0.89 * 6 * e * e);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(hollow_box)
{
    bvox_volume *v = make(20, 21, 70, 1, 1.5, 0.7);
    CHECK(v);
    bvox_volume_fill_box(v, (bvox_box){2, 3, 30, 14, 15, 66}, 1);
    bvox_volume_fill_box(v, (bvox_box){5, 6, 40, 9, 10, 50}, 0);
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.cavities, 1);
    CHECK_EQ(m.euler, 2);
    CHECK_EQ(m.components, 1);
    CHECK_EQ(m.tunnels, 0);
    CHECK_EQ(m.faces[0], 2 * 12 * 36 + 2 * 4 * 10);
    /* a second cavity; then open the first to the outside: a dent, no cavity */
    bvox_volume_fill_box(v, (bvox_box){5, 6, 55, 9, 10, 60}, 0);
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.cavities, 2);
    CHECK_EQ(m.euler, 3);
    bvox_volume_fill_box(v, (bvox_box){5, 6, 40, 9, 10, 66}, 0);
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.cavities, 0);
    CHECK_EQ(m.euler, 1);
    /* a cavity only diagonally open (26- but not 6-connected to the
     * outside) is still a cavity for the 6-connected background */
    bvox_volume_destroy(v);
    v = make(5, 5, 5, 1, 1, 1);
    bvox_volume_fill_box(v, (bvox_box){0, 0, 0, 3, 3, 3}, 1);
    CHECK_OK(bvox_volume_set(v, 1, 1, 1, 0));
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.cavities, 1);
    CHECK_EQ(m.euler, 2);
    bvox_volume_destroy(v);
    return 0;
}

TEST(torus_and_blobs)
{
    bvox_volume *v = make(64, 64, 30, 1, 1, 1);
    CHECK(v);
    bvox_shape t = {.kind = BVOX_SHAPE_TORUS, .center = {31.7, 32.2, 14.6}, .axis = {0, 0, 1},
                    .radius = 20, .minor_radius = 7};
    CHECK_OK(bvox_shape_draw(v, &t, BVOX_CSG_UNION));
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.euler, 0);
    CHECK_EQ(m.components, 1);
    CHECK_EQ(m.cavities, 0);
    CHECK_EQ(m.tunnels, 1);
    double area = 4 * M_PI * M_PI * 20 * 7;
    CHECK(rel_near(m.area, area, 0.03));
    bvox_volume_destroy(v);

    v = make(60, 40, 40, 1, 1, 1);
    bvox_shape s = {.kind = BVOX_SHAPE_SPHERE, .center = {15, 20, 20}, .radius = 10};
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    s.center[0] = 45, s.radius = 8;
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.components, 2);
    CHECK_EQ(m.euler, 2);
    CHECK_EQ(m.tunnels, 0);
    bvox_measures *per = NULL;
    int64_t n = 0;
    CHECK_OK(bvox_measure_components(v, 26, &per, &n));
    CHECK_EQ(n, 2);
    CHECK_EQ(per[0].count + per[1].count, m.count);
    CHECK(per[0].count > per[1].count);
    CHECK_NEAR(per[0].centroid[0], 15, 1e-9);
    CHECK_NEAR(per[1].centroid[0], 45, 1e-9);
    CHECK(per[1].bbox.x0 == 37 && per[1].bbox.x1 == 54);
    CHECK_EQ(per[0].euler + per[1].euler, 2);
    CHECK_EQ(per[0].components, 1);
    CHECK(rel_near(per[0].area + per[1].area, m.area, 1e-12));
    bvox_free(per);
    bvox_volume_destroy(v);
    return 0;
}

/* A sphere of radius 50 in physical units, in isotropic and anisotropic voxels. */
TEST(sphere_area_volume)
{
    const double sp[][3] = {{1, 1, 1}, {1, 1, 2.5}, {0.8, 1.3, 2}};
    const double r = 50;
    for (int k = 0; k < 3; k++) {
        int n[3];
        for (int a = 0; a < 3; a++) n[a] = (int)(2 * r / sp[k][a]) + 6;
        bvox_volume *v = make(n[0], n[1], n[2], sp[k][0], sp[k][1], sp[k][2]);
        CHECK(v);
        bvox_shape s = {.kind = BVOX_SHAPE_SPHERE, .center = {53.3, 52.7, 53.1}, .radius = r};
        CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
        bvox_measures m;
        CHECK_OK(bvox_measure(v, &m));
        double V = 4.0 / 3 * M_PI * r * r * r, A = 4 * M_PI * r * r;
        CHECK(rel_near(m.volume, V, 0.01));
        CHECK(rel_near(m.area, A, 0.01)); /* asked for 3%; Crofton gives 0.2% */
        CHECK(rel_near(m.sphericity, 1, 0.01));
        CHECK(rel_near(m.equivalent_diameter, 2 * r, 0.01));
        /* voxel faces of a sphere: 1.5 times its area (mean |nx|+|ny|+|nz|) */
        CHECK(rel_near(m.area_faces, 1.5 * A, 0.03));
        for (int a = 0; a < 3; a++) {
            CHECK_NEAR(m.centroid[a], s.center[a], 0.02);
            CHECK(rel_near(m.principal_moments[a], r * r / 5, 0.02));
        }
        CHECK_EQ(m.euler, 1);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(ellipsoid_axes)
{
    /* semi-axes 10 (x), 30 (y), 20 (z): the axes come out y, z, x */
    const double sp[][3] = {{1, 1, 1}, {0.7, 1.1, 2.5}};
    for (int k = 0; k < 2; k++) {
        bvox_volume *v = make((int)(26 / sp[k][0]), (int)(66 / sp[k][1]), (int)(46 / sp[k][2]),
                              sp[k][0], sp[k][1], sp[k][2]);
        CHECK(v);
        bvox_shape e = {.kind = BVOX_SHAPE_ELLIPSOID, .center = {12.9, 32.6, 22.3},
                        .semi_axes = {10, 30, 20}};
        CHECK_OK(bvox_shape_draw(v, &e, BVOX_CSG_UNION));
        bvox_measures m;
        CHECK_OK(bvox_measure(v, &m));
        const int axis_of[3] = {1, 2, 0};
        for (int i = 0; i < 3; i++) {
            CHECK(m.principal_axes[i * 3 + axis_of[i]] > 0.9999);
            double semi = e.semi_axes[axis_of[i]];
            CHECK(rel_near(m.principal_moments[i], semi * semi / 5, 0.03));
        }
        CHECK(rel_near(m.volume, bvox_shape_volume(&e), 0.01));
        bvox_volume_destroy(v);
    }
    /* an oblique cylinder: the first axis follows it */
    bvox_volume *v = make(80, 80, 24, 1, 1, 1);
    bvox_shape c = {.kind = BVOX_SHAPE_CYLINDER, .center = {40, 40, 12}, .axis = {1, 1, 0},
                    .radius = 5, .height = 80};
    CHECK_OK(bvox_shape_draw(v, &c, BVOX_CSG_UNION));
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK(m.principal_axes[0] > 0.7071 - 1e-3 && m.principal_axes[1] > 0.7071 - 1e-3);
    double *a = m.principal_axes;
    for (int i = 0; i < 3; i++) /* orthonormal rows */
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(a[i * 3] * a[j * 3] + a[i * 3 + 1] * a[j * 3 + 1] + a[i * 3 + 2] * a[j * 3 + 2],
                       i == j, 1e-9);
    bvox_volume_destroy(v);
    return 0;
}

/* ---- random volumes against the slow references ---- */

static const int sizes[][3] = {{1, 1, 1},  {3, 5, 1},  {7, 3, 63},   {5, 7, 64},  {9, 3, 65},
                               {3, 11, 130}, {17, 1, 129}, {1, 13, 200}, {6, 5, 128}, {4, 4, 192}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

TEST(random_vs_reference)
{
    const double sp[3] = {0.7, 1.3, 2.1};
    double w[BVOX__NDIR];
    bvox__crofton_weights(sp, w);
    const unsigned dens[] = {1, 4, 6, 9}; /* of 10 */
    for (int i = 0; i < NSIZES; i++)
        for (int d = 0; d < 4; d++) {
            const int *s = sizes[i];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, dens[d], 10, harness_rand);
            bvox_volume *v = voxref_to_volume(r);
            CHECK(v);
            CHECK_OK(bvox_volume_set_spacing(v, sp[0], sp[1], sp[2], NULL));
            bvox_measures m;
            CHECK_OK(bvox_measure(v, &m));
            measref o;
            measref_compute(r, sp, &o);
            if (check_against_ref(&m, &o, w)) {
                fprintf(stderr, "  size %dx%dx%d density %u/10\n", s[0], s[1], s[2], dens[d]);
                return 1;
            }
            bvox_box b;
            if (voxref_bbox(r, &b)) CHECK(memcmp(&b, &m.bbox, sizeof b) == 0);
            CHECK_EQ(m.tunnels, m.components + m.cavities - m.euler);
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    return 0;
}

/* Sparse solid blobs: many components, cavities and tunnels at once. */
TEST(random_blobs_topology)
{
    const double sp[3] = {1, 1, 1};
    double w[BVOX__NDIR];
    bvox__crofton_weights(sp, w);
    for (int iter = 0; iter < 6; iter++) {
        voxref *r = voxref_create(23, 19, 67);
        for (int k = 0; k < 40; k++) { /* random boxes, some hollowed */
            int x = (int)(harness_rand() % 20), y = (int)(harness_rand() % 16),
                z = (int)(harness_rand() % 62);
            int dx = 1 + (int)(harness_rand() % 6), dy = 1 + (int)(harness_rand() % 6),
                dz = 1 + (int)(harness_rand() % 9);
            voxref_fill_box(r, (bvox_box){x, y, z, x + dx, y + dy, z + dz}, (k % 5) != 4);
        }
        bvox_volume *v = voxref_to_volume(r);
        bvox_measures m;
        CHECK_OK(bvox_measure(v, &m));
        measref o;
        measref_compute(r, sp, &o);
        CHECK(!check_against_ref(&m, &o, w));
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    return 0;
}

TEST(threads_deterministic)
{
    voxref *r = voxref_create(150, 131, 130);
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    voxref_destroy(r);
    bvox_measures a, b;
    int threads = bvox_threads();
    bvox_set_threads(1);
    CHECK_OK(bvox_measure(v, &a));
    bvox_set_threads(3);
    CHECK_OK(bvox_measure(v, &b));
    bvox_set_threads(threads);
    CHECK_EQ(a.euler, b.euler);
    for (int i = 0; i < 3; i++) CHECK_EQ(a.faces[i], b.faces[i]);
    CHECK(a.area == b.area && a.centroid[1] == b.centroid[1]);
    CHECK(memcmp(a.covariance, b.covariance, sizeof a.covariance) == 0);
    bvox_volume_destroy(v);
    return 0;
}

/* Every SIMD level this CPU runs (the POPCNT clone under avx2, the vector
 * scan kernel under avx512) against the portable path, the whole measure. */
TEST(simd_paths_agree)
{
    voxref *r = voxref_create(37, 29, 129);
    voxref_random(r, 2, 5, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    voxref_destroy(r);
    bvox_simd saved = bvox_simd_active();
    const bvox_simd levels[] = {BVOX_SIMD_AVX2, BVOX_SIMD_AVX512, BVOX_SIMD_AUTO};
    bvox_measures a, b;
    CHECK_OK(bvox_simd_set(BVOX_SIMD_GENERIC));
    CHECK_OK(bvox_measure(v, &a));
    for (int l = 0; l < 3; l++) {
        if (!bvox_simd_supported(levels[l])) continue;
        CHECK_OK(bvox_simd_set(levels[l]));
        CHECK_OK(bvox_measure(v, &b));
        CHECK_EQ(a.euler, b.euler);
        for (int i = 0; i < 3; i++) CHECK_EQ(a.faces[i], b.faces[i]);
        CHECK(a.area == b.area);
        /* the moments (run or popcount sums per word) and the topology too */
        CHECK(memcmp(a.centroid, b.centroid, sizeof a.centroid) == 0);
        CHECK(memcmp(a.covariance, b.covariance, sizeof a.covariance) == 0);
        CHECK_EQ(a.components, b.components);
        CHECK_EQ(a.cavities, b.cavities);
        CHECK_EQ(a.cavities_26, b.cavities_26);
    }
    CHECK_OK(bvox_simd_set(saved));
    bvox_volume_destroy(v);
    return 0;
}

/* Every integer of two scans. */
static int scans_equal(const bvox__scan *a, const bvox__scan *b)
{
    CHECK_EQ(a->count, b->count);
    CHECK_EQ(a->euler, b->euler);
    for (int i = 0; i < BVOX__NDIR; i++) CHECK_EQ(a->trans[i], b->trans[i]);
    for (int i = 0; i < 3; i++) CHECK(a->s[i] == b->s[i]);
    for (int i = 0; i < 6; i++) CHECK(a->ss[i] == b->ss[i]);
    if (a->count) CHECK(memcmp(a->bbox, b->bbox, sizeof a->bbox) == 0);
    return 0;
}

/* Per column of r: its hull record by voxels (bvox__colhull: the z range
 * strictly between its first and last 1-voxel, runs of 1s in it minus one),
 * compared with h. */
static int hulls_match_voxels(const voxref *r, const bvox__colhull *h)
{
    for (int y = 0; y < r->ny; y++) {
        /* the row's flag: all of row y equals row y - 1 */
        int twin = y > 0;
        for (int x = 0; x < r->nx && twin; x++)
            for (int z = 0; z < r->nz && twin; z++)
                twin = *voxref_at(r, x, y, z) == *voxref_at(r, x, y - 1, z);
        for (int x = 0; x < r->nx; x++) {
            int first = -1, last = -1, runs = 0;
            for (int z = 0; z < r->nz; z++) {
                if (!*voxref_at(r, x, y, z)) continue;
                if (first < 0) first = z;
                runs += z == 0 || !*voxref_at(r, x, y, z - 1);
                last = z;
            }
            const bvox__colhull *c = &h[(size_t)y * (size_t)r->nx + (size_t)x];
            CHECK_EQ(c->twin_row, twin);
            if (first < 0) {
                CHECK(c->lo == 0 && c->hi == 0 && c->runs == 0);
                continue;
            }
            CHECK_EQ(c->lo, first + 1);
            CHECK_EQ(c->hi, last);
            CHECK_EQ(c->runs, (uint32_t)(runs - 1));
        }
    }
    return 0;
}

/* Scans the volume at every supported level; all must equal the generic
 * scan, its column hulls included, and that one (when r is given) the
 * per-voxel reference's Euler number, transitions and hulls, so a mistake
 * shared by the kernels cannot hide. */
static int scan_levels_agree(const voxref *r, const bvox_volume *v)
{
    const bvox_simd levels[] = {BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
    bvox_simd saved = bvox_simd_active();
    bvox__scan g, o;
    size_t ncol = (size_t)v->nx * (size_t)v->ny;
    bvox__colhull *hg = calloc(ncol, sizeof *hg), *ho = calloc(ncol, sizeof *ho);
    CHECK(hg && ho);
    memset(hg, 0xab, ncol * sizeof *hg);
    CHECK_OK(bvox_simd_set(BVOX_SIMD_GENERIC));
    CHECK_OK(bvox__measure_scan_hulls(v, hg, &g));
    if (r) {
        measref ref;
        measref_compute(r, (const double[3]){1, 1, 1}, &ref);
        CHECK_EQ(g.euler, ref.euler);
        for (int c = 0; c < BVOX__NDIR; c++) CHECK_EQ(g.trans[c], ref.trans[c]);
        CHECK_EQ(g.count, ref.count);
        CHECK(!hulls_match_voxels(r, hg));
        /* the box and the first moments too (twin rows take them over) */
        int32_t box[6] = {INT32_MAX, INT32_MAX, INT32_MAX, -1, -1, -1};
        for (int z = 0; z < r->nz; z++)
            for (int y = 0; y < r->ny; y++)
                for (int x = 0; x < r->nx; x++) {
                    if (!*voxref_at(r, x, y, z)) continue;
                    const int p[3] = {x, y, z};
                    for (int a = 0; a < 3; a++) {
                        if (p[a] < box[a]) box[a] = p[a];
                        if (p[a] + 1 > box[a + 3]) box[a + 3] = p[a] + 1;
                    }
                }
        if (g.count)
            for (int a = 0; a < 6; a++) CHECK_EQ(g.bbox[a], box[a]);
        for (int a = 0; a < 3 && g.count; a++)
            CHECK_NEAR((double)g.s[a] / (double)g.count, ref.centroid[a], 1e-9);
    }
    for (int l = 0; l < 2; l++) {
        if (!bvox_simd_supported(levels[l])) continue;
        CHECK_OK(bvox_simd_set(levels[l]));
        memset(ho, 0xab, ncol * sizeof *ho); /* every record must be written */
        CHECK_OK(bvox__measure_scan_hulls(v, ho, &o));
        if (scans_equal(&g, &o) || memcmp(hg, ho, ncol * sizeof *hg) != 0) {
            fprintf(stderr, "  level %s\n", bvox_simd_name(levels[l]));
            bvox_simd_set(saved);
            return 1;
        }
    }
    free(hg);
    free(ho);
    CHECK_OK(bvox_simd_set(saved));
    return 0;
}

/* The scan kernels' raw sums on random densities 0.01..0.99 at awkward
 * sizes: nz < 64, nz a multiple of 64 (the extra top word) and not, wpc
 * below, at and past the AVX-512 kernel's 8 words, thin and odd shapes. */
/* Columns repeated along x and y (an upsampled volume, where the vector
 * kernels reuse a column's sums and take the cells of x-equal windows by
 * their short formula), some copies differing in one voxel, anywhere along
 * z: every level against the generic scan and the per-voxel reference. */
/* Whole rows repeated (an upsampled volume's twin rows: the scan takes over
 * the row before's moments and hulls, and counts the windows between the
 * two by the short formula), in streaks longer and shorter than a block of
 * rows, some twins then changed in one voxel (or two swapped along z, which
 * keeps the column's count): every level against the generic scan and that
 * against the per-voxel reference. */
TEST(scan_repeated_rows)
{
    static const int shapes[][3] = {{17, 90, 512}, {12, 70, 700}, {30, 40, 100}, {9, 33, 64}};
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        for (unsigned dens = 20; dens <= 80; dens += 30) {
            const int *sh = shapes[i];
            voxref *r = voxref_create(sh[0], sh[1], sh[2]);
            voxref_random(r, dens, 100, harness_rand);
            int streak = 0;
            for (int y = 1; y < sh[1]; y++) {
                if (!streak && harness_rand() % 2) streak = 1 + (int)(harness_rand() % 20);
                if (!streak) continue;
                streak--;
                for (int x = 0; x < sh[0]; x++)
                    for (int z = 0; z < sh[2]; z++)
                        *voxref_at(r, x, y, z) = *voxref_at(r, x, y - 1, z);
                unsigned change = (unsigned)(harness_rand() % 6);
                int x = (int)(harness_rand() % (unsigned)sh[0]);
                int z = (int)(harness_rand() % (unsigned)(sh[2] - 1));
                if (change == 0) *voxref_at(r, x, y, z) ^= 1;
                if (change == 1) {
                    uint8_t t = *voxref_at(r, x, y, z);
                    *voxref_at(r, x, y, z) = *voxref_at(r, x, y, z + 1);
                    *voxref_at(r, x, y, z + 1) = t;
                }
            }
            bvox_volume *v = voxref_to_volume(r);
            CHECK(v);
            for (int t = 0; t < 3; t++) {
                bvox_set_threads(t == 0 ? 1 : t == 1 ? 3 : 16);
                if (scan_levels_agree(r, v)) {
                    fprintf(stderr, "  size %dx%dx%d density %u/100 threads %d\n", sh[0], sh[1],
                            sh[2], dens, bvox_threads());
                    bvox_set_threads(0);
                    return 1;
                }
            }
            bvox_set_threads(0);
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    return 0;
}

TEST(scan_repeated_columns)
{
    static const int shapes[][3] = {{17, 9, 512}, {12, 10, 700}, {9, 13, 100}, {11, 8, 1100}};
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        for (unsigned dens = 20; dens <= 80; dens += 30) {
            const int *sh = shapes[i];
            voxref *r = voxref_create(sh[0], sh[1], sh[2]);
            voxref_random(r, dens, 100, harness_rand);
            /* each column becomes the one before it in x (or in y), 2 in 3 */
            for (int y = 0; y < sh[1]; y++)
                for (int x = 0; x < sh[0]; x++) {
                    unsigned pick = (unsigned)(harness_rand() % 3);
                    int sx = x, sy = y;
                    if (pick == 0 && x > 0) sx = x - 1;
                    if (pick == 1 && y > 0) sy = y - 1;
                    for (int z = 0; z < sh[2]; z++)
                        *voxref_at(r, x, y, z) = *voxref_at(r, sx, sy, z);
                    if (harness_rand() % 5 == 0)
                        *voxref_at(r, x, y, (int)(harness_rand() % (unsigned)sh[2])) ^= 1;
                }
            bvox_volume *v = voxref_to_volume(r);
            CHECK(v);
            if (scan_levels_agree(r, v)) {
                fprintf(stderr, "  size %dx%dx%d density %u/100\n", sh[0], sh[1], sh[2], dens);
                return 1;
            }
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    return 0;
}

TEST(scan_kernels_agree)
{
    static const int shapes[][3] = {{1, 1, 1},   {1, 1, 64},  {2, 1, 63},  {3, 2, 5},
                                    {5, 7, 64},  {4, 3, 128}, {3, 4, 511}, {2, 3, 512},
                                    {3, 2, 513}, {1, 9, 576}, {9, 1, 600}, {6, 5, 1024},
                                    {2, 2, 1100}, {13, 11, 65}, {1, 1, 1088}};
    const unsigned dens[] = {1, 10, 30, 50, 70, 90, 99}; /* of 100 */
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        for (int d = 0; d < 7; d++) {
            const int *sh = shapes[i];
            voxref *r = voxref_create(sh[0], sh[1], sh[2]);
            voxref_random(r, dens[d], 100, harness_rand);
            bvox_volume *v = voxref_to_volume(r);
            CHECK(v);
            if (scan_levels_agree(r, v)) {
                fprintf(stderr, "  size %dx%dx%d density %u/100\n", sh[0], sh[1], sh[2],
                        dens[d]);
                return 1;
            }
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    /* uniform words beside mixed ones: solid slabs, full and empty columns,
     * a full volume (every group skipped but the borders) */
    voxref *r = voxref_create(7, 6, 640);
    voxref_fill_box(r, (bvox_box){0, 0, 0, 7, 6, 640}, 1);
    bvox_volume *v = voxref_to_volume(r);
    CHECK(!scan_levels_agree(r, v));
    bvox_volume_destroy(v);
    voxref_fill_box(r, (bvox_box){1, 1, 64, 6, 5, 577}, 0);
    voxref_fill_box(r, (bvox_box){2, 2, 100, 4, 4, 300}, 1);
    for (int k = 0; k < 200; k++)
        *voxref_at(r, (int)(harness_rand() % 7), (int)(harness_rand() % 6),
                   (int)(harness_rand() % 640)) ^= 1;
    v = voxref_to_volume(r);
    CHECK(!scan_levels_agree(r, v));
    bvox_volume_destroy(v);
    voxref_destroy(r);
    return 0;
}

/* The AAL atlas (91 x 109 x 91: two words a column, against the reference)
 * and the same shifted up in z into 512 and 600 voxels (8 words and the
 * extra top word; 10 words), kernels against each other. */
TEST(realdata_aal_scan_kernels_agree)
{
    bvox_volume *v = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    CHECK_OK(bvox_read("/usr/share/mricron/templates/aal.nii.gz", &ro, &v));
    voxref *r = voxref_from_volume(v);
    CHECK(!scan_levels_agree(r, v));
    bvox_volume_destroy(v);
    const int before[2][3] = {{0, 0, 400}, {0, 0, 7}}, after[2][3] = {{0, 0, 21}, {0, 0, 502}};
    for (int i = 0; i < 2; i++) {
        voxref *p = voxref_pad(r, before[i], after[i]);
        v = voxref_to_volume(p);
        CHECK(!scan_levels_agree(NULL, v));
        bvox_volume_destroy(v);
        voxref_destroy(p);
    }
    voxref_destroy(r);
    return 0;
}

TEST(alloc_failure_is_clean)
{
    bvox_volume *v = make(20, 20, 70, 1, 1, 1);
    CHECK(v);
    bvox_volume_fill_box(v, (bvox_box){2, 2, 2, 10, 10, 60}, 1);
    size_t before = bvox_memory_in_use();
    bvox__alloc_fail_after(1); /* the complement's copy */
    bvox_measures m;
    CHECK_STATUS(bvox_measure(v, &m), BVOX_ENOMEM);
    CHECK_EQ(bvox_memory_in_use(), before);
    bvox__alloc_fail_after(1);
    bvox_measures *per = (bvox_measures *)1;
    int64_t n = 5;
    CHECK_STATUS(bvox_measure_components(v, 26, &per, &n), BVOX_ENOMEM);
    CHECK(per == NULL && n == 0);
    CHECK_EQ(bvox_memory_in_use(), before);
    bvox__alloc_fail_after(0);
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.count, 8 * 8 * 58);
    bvox_volume_destroy(v);
    return 0;
}
