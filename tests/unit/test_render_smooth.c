/* test_render_smooth.c — the shading of issue 18 against known answers:
 * smooth normals of planes (exact by symmetry, any spacing), of a voxelized
 * sphere against its true normals (within 10 degrees on 95 % of the hit
 * pixels, where the paper's binary normals are not), the paper's enlarged
 * pre-image on Figure 5's numbers, the binary gradient operator over the
 * pre-image on a hand-made depth map, ambient occlusion (open floor vs a
 * corner) and cast shadows of a block on a floor. */
#include "harness.h"
#include "render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double pi = 3.14159265358979323846;

/* A volume of n^3 with the voxels where inside(x, y, z) is true. */
static bvox_volume *make(int n, int (*inside)(int, int, int))
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++)
                if (inside(x, y, z)) bvox_volume_set(v, x, y, z, 1);
    return v;
}

static int half_z(int x, int y, int z) { (void)x, (void)y; return z >= 10; }
static int half_xy(int x, int y, int z) { (void)z; return x + y >= 32; }
static int half_x2y(int x, int y, int z) { (void)y; return 2 * x + z >= 40; }

TEST(smooth_normal_planes)
{
    for (int r = 1; r <= 3; r++) {
        double n[3];
        bvox_volume *v = make(32, half_z);
        CHECK(v != NULL);
        CHECK_EQ(bvox_smooth_normal(v, 16, 16, 10, r, n), 1);
        CHECK_NEAR(n[0], 0, 1e-12);
        CHECK_NEAR(n[1], 0, 1e-12);
        CHECK_NEAR(n[2], -1, 1e-12);
        /* thick sections: the plane z = const keeps its normal */
        CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.5, 4, NULL));
        CHECK_EQ(bvox_smooth_normal(v, 5, 20, 10, r, n), 1);
        CHECK_NEAR(n[2], -1, 1e-12);
        /* inside the solid and in empty space: no direction */
        CHECK_EQ(bvox_smooth_normal(v, 16, 16, 20, r, n), 0);
        CHECK_EQ(bvox_smooth_normal(v, 16, 16, 2, r, n), 0);
        CHECK(n[0] == 0 && n[1] == 0 && n[2] == 0);
        bvox_volume_destroy(v);
        /* x + y = 32: (-1, -1, 0) / sqrt 2 by the x <-> y symmetry */
        CHECK((v = make(32, half_xy)) != NULL);
        CHECK_EQ(bvox_smooth_normal(v, 16, 16, 16, r, n), 1);
        CHECK_NEAR(n[0], -sqrt(0.5), 1e-12);
        CHECK_NEAR(n[1], -sqrt(0.5), 1e-12);
        CHECK_NEAR(n[2], 0, 1e-12);
        /* spacing (2, 1, 1) makes the same voxels the physical plane x / 2 + y
         * = 16: normal (1/2, 1, 0) / |.| pointing out (negative) */
        CHECK_OK(bvox_volume_set_spacing(v, 2, 1, 1, NULL));
        CHECK_EQ(bvox_smooth_normal(v, 16, 16, 16, r, n), 1);
        CHECK_NEAR(n[0] / n[1], 0.5, 1e-12);
        CHECK(n[0] < 0 && n[1] < 0);
        bvox_volume_destroy(v);
    }
    /* a slope 2 x + z = 40 away from the diagonals: the 5x5x5 ball's answer
     * is within 3 degrees of (-2, 0, -1) / sqrt 5 */
    bvox_volume *v = make(40, half_x2y);
    CHECK(v != NULL);
    double n[3], dot = 0, want[3] = {-2 / sqrt(5.0), 0, -1 / sqrt(5.0)};
    CHECK_EQ(bvox_smooth_normal(v, 15, 20, 10, 2, n), 1);
    for (int a = 0; a < 3; a++) dot += n[a] * want[a];
    CHECK(acos(dot) < 3 * pi / 180);
    /* outside the volume reads 0; a NULL volume is no normal */
    CHECK_EQ(bvox_smooth_normal(NULL, 0, 0, 0, 2, n), 0);
    bvox_volume_destroy(v);
    return 0;
}

/* ---- the sphere ---- */
#define SN 96
#define SR 40.0
static int in_sphere(int x, int y, int z)
{
    double c = (SN - 1) / 2.0, dx = x - c, dy = y - c, dz = z - c;
    return dx * dx + dy * dy + dz * dz <= SR * SR;
}

/* The true eye-frame normal of pixel (c, r): where the pixel's ray meets the
 * sphere of the voxel boxes' mean radius, or its closest approach beside it. */
static void true_normal(const bvox_preimage *p, int32_t c, int32_t r, double n[3])
{
    const double *e = p->eye, ctr = (SN - 1) / 2.0, R = SR + 0.5;
    double o[3], d[3], oc[3], b = 0, cc = 0;
    for (int a = 0; a < 3; a++) {
        o[a] = p->origin[a] + c * p->pixel_size[0] * e[a] + r * p->pixel_size[1] * e[3 + a];
        d[a] = e[6 + a];
        oc[a] = o[a] - ctr;
        b += oc[a] * d[a];
        cc += oc[a] * oc[a];
    }
    double disc = b * b - (cc - R * R), t = disc > 0 ? -b - sqrt(disc) : -b, v[3], len = 0;
    for (int a = 0; a < 3; a++) {
        v[a] = oc[a] + t * d[a];
        len += v[a] * v[a];
    }
    for (int a = 0; a < 3; a++) v[a] /= sqrt(len);
    n[0] = e[0] * v[0] + e[1] * v[1] + e[2] * v[2];
    n[1] = -(e[3] * v[0] + e[4] * v[1] + e[5] * v[2]);
    n[2] = -(e[6] * v[0] + e[7] * v[1] + e[8] * v[2]);
}

/* The share of hit pixels whose normal (mode) is within 10 degrees of the
 * truth. */
static double share_within(const bvox_volume *v, const bvox_preimage *p, bvox_shade_mode mode,
                           int radius)
{
    const size_t n = (size_t)p->width * (size_t)p->height;
    float *nrm = calloc(3 * n, sizeof *nrm);
    if (!nrm || bvox_preimage_normals(v, p, mode, radius, nrm)) {
        free(nrm);
        return -1;
    }
    size_t hits = 0, good = 0;
    for (int32_t r = 0; r < p->height; r++)
        for (int32_t c = 0; c < p->width; c++) {
            size_t i = (size_t)r * (size_t)p->width + (size_t)c;
            if (p->depth[i] < 0) continue;
            double t[3], dot = 0;
            true_normal(p, c, r, t);
            for (int a = 0; a < 3; a++) dot += t[a] * nrm[3 * i + a];
            hits++;
            good += dot >= cos(10 * pi / 180);
        }
    free(nrm);
    return hits ? (double)good / (double)hits : -1;
}

TEST(sphere_normals_within_10_degrees)
{
    bvox_volume *v = make(SN, in_sphere);
    CHECK(v != NULL);
    const double views[3][2] = {{0, 0}, {30, 20}, {-50, 65}};
    for (int k = 0; k < 3; k++) {
        bvox_projection proj = BVOX_PROJECTION_INIT;
        proj.azimuth = views[k][0], proj.elevation = views[k][1];
        proj.width = proj.height = 200;
        bvox_preimage *p;
        CHECK_OK(bvox_cast_projection(v, &proj, &p));
        double smooth = share_within(v, p, BVOX_SHADE_SMOOTH, 2);
        double smooth3 = share_within(v, p, BVOX_SHADE_SMOOTH, 3);
        double binary = share_within(v, p, BVOX_SHADE_BINARY, 0);
        double gradient = share_within(v, p, BVOX_SHADE_GRADIENT, 0);
        fprintf(stderr, "view %g,%g: within 10 degrees: smooth %.3f (radius 3: %.3f), binary %.3f, "
                        "gradient %.3f\n", views[k][0], views[k][1], smooth, smooth3, binary, gradient);
        CHECK(smooth >= 0.95);
        CHECK(smooth3 >= 0.95);
        CHECK(binary >= 0 && binary < 0.5);
        bvox_preimage_destroy(p);
    }
    bvox_volume_destroy(v);
    return 0;
}
