/* test_morph.c — dilation and erosion against a voxel-by-voxel reference
 * (every voxel scans its whole structuring element) at awkward sizes. */
#include "harness.h"
#include "ref/voxref.h"
#include "ops/morph_ball.h"

#include <stdlib.h>

/* in_element(dx, dy, dz): membership of an offset in the element */
typedef int (*element_fn)(int dx, int dy, int dz, const double *s, double r);

static int conn6(int dx, int dy, int dz, const double *s, double r)
{
    return abs(dx) + abs(dy) + abs(dz) <= 1;
}
static int conn18(int dx, int dy, int dz, const double *s, double r)
{
    return abs(dx) <= 1 && abs(dy) <= 1 && abs(dz) <= 1 && abs(dx) + abs(dy) + abs(dz) <= 2;
}
static int conn26(int dx, int dy, int dz, const double *s, double r)
{
    return abs(dx) <= 1 && abs(dy) <= 1 && abs(dz) <= 1;
}
static int in_ball(int dx, int dy, int dz, const double *s, double r)
{
    double x = dx * s[0], y = dy * s[1], z = dz * s[2];
    return x * x + y * y + z * z <= r * r;
}

static voxref *ref_morph(const voxref *a, element_fn el, const double *s, double r, int reach,
                         int erode)
{
    voxref *o = voxref_create(a->nx, a->ny, a->nz);
    for (int z = 0; z < a->nz; z++)
        for (int y = 0; y < a->ny; y++)
            for (int x = 0; x < a->nx; x++) {
                int acc = erode;
                for (int dz = -reach; dz <= reach; dz++)
                    for (int dy = -reach; dy <= reach; dy++)
                        for (int dx = -reach; dx <= reach; dx++) {
                            if (!el(dx, dy, dz, s, r)) continue;
                            int v = voxref_get(a, x + dx, y + dy, z + dz);
                            acc = erode ? (acc && v) : (acc || v);
                        }
                *voxref_at(o, x, y, z) = (uint8_t)acc;
            }
    return o;
}

static const int sizes[][3] = {{1, 1, 1}, {5, 3, 1}, {3, 7, 63}, {6, 5, 64}, {7, 4, 65}, {5, 6, 130}};

TEST(neighbourhoods_against_reference)
{
    const int conns[3] = {6, 18, 26};
    element_fn fns[3] = {conn6, conn18, conn26};
    double unit[3] = {1, 1, 1};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const int *sz = sizes[i];
        voxref *a = voxref_create(sz[0], sz[1], sz[2]);
        /* sparse for dilation to be visible, dense for erosion */
        for (int pass = 0; pass < 2; pass++) {
            voxref_random(a, pass ? 7 : 1, pass ? 8 : 12, harness_rand);
            bvox_volume *v = voxref_to_volume(a);
            for (int c = 0; c < 3; c++) {
                for (int erode = 0; erode < 2; erode++) {
                    bvox_volume *out;
                    CHECK_OK(erode ? bvox_morph_erode(v, conns[c], &out)
                                   : bvox_morph_dilate(v, conns[c], &out));
                    voxref *r = ref_morph(a, fns[c], unit, 0, 1, erode);
                    if (!voxref_matches(r, out)) {
                        fprintf(stderr, "conn %d erode %d size %dx%dx%d\n", conns[c], erode,
                                sz[0], sz[1], sz[2]);
                        return 1;
                    }
                    voxref_destroy(r);
                    bvox_volume_destroy(out);
                }
            }
            bvox_volume_destroy(v);
        }
        voxref_destroy(a);
    }
    bvox_volume *v, *out = (bvox_volume *)1;
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
    CHECK_STATUS(bvox_morph_dilate(v, 8, &out), BVOX_EINVAL);
    CHECK(out == NULL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(ball_anisotropic_against_reference)
{
    const double spacings[][3] = {{1, 1, 1}, {0.5, 0.5, 1.5}, {1, 2, 0.7}};
    const double radii[] = {0, 1.5, 2.3};
    for (size_t si = 0; si < 3; si++)
        for (size_t ri = 0; ri < 3; ri++) {
            voxref *a = voxref_create(9, 8, 70);
            voxref_random(a, 1, 40, harness_rand);
            bvox_volume *v = voxref_to_volume(a);
            const double *s = spacings[si];
            CHECK_OK(bvox_volume_set_spacing(v, s[0], s[1], s[2], "mm"));
            int reach = (int)(radii[ri] / 0.5) + 1;
            for (int erode = 0; erode < 2; erode++) {
                if (erode) { /* erode the dilated volume: dense enough to matter */
                    bvox_volume *d;
                    CHECK_OK(bvox_morph_dilate_ball(v, radii[ri], &d));
                    voxref_destroy(a);
                    a = voxref_from_volume(d);
                    bvox_volume_destroy(v);
                    v = d;
                }
                bvox_volume *out;
                CHECK_OK(erode ? bvox_morph_erode_ball(v, radii[ri], &out)
                               : bvox_morph_dilate_ball(v, radii[ri], &out));
                voxref *r = ref_morph(a, in_ball, s, radii[ri], reach, erode);
                if (!voxref_matches(r, out)) {
                    fprintf(stderr, "spacing %zu radius %g erode %d\n", si, radii[ri], erode);
                    return 1;
                }
                voxref_destroy(r);
                bvox_volume_destroy(out);
            }
            bvox_volume_destroy(v);
            voxref_destroy(a);
        }
    return 0;
}

TEST(dilate_single_voxel_counts)
{
    /* hand-computed: one voxel in the middle grows to 7, 19, 27 voxels */
    bvox_volume *v, *out;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 5, 130}, &v));
    CHECK_OK(bvox_volume_set(v, 2, 2, 64, 1)); /* z neighbours straddle a word boundary */
    const int conns[3] = {6, 18, 26}, want[3] = {7, 19, 27};
    for (int c = 0; c < 3; c++) {
        CHECK_OK(bvox_morph_dilate(v, conns[c], &out));
        CHECK_EQ(bvox_volume_count(out), want[c]);
        CHECK_EQ(bvox_volume_get(out, 2, 2, 63), 1);
        bvox_volume *back;
        CHECK_OK(bvox_morph_erode(out, conns[c], &back));
        CHECK(bvox_volume_equal(back, v)); /* the element eroded is the centre */
        bvox_volume_destroy(back);
        bvox_volume_destroy(out);
    }
    bvox_volume_destroy(v);
    return 0;
}

/* The fused 26-neighbourhood pass splits rows into one chunk per thread
 * (each recomputing its neighbour rows) and the x pass works on 64 words of
 * a column at a time: tall volumes, 1..4 threads, and columns longer than
 * 64 words must all match the reference. */
TEST(box26_threads_and_long_columns)
{
    static const int big[][3] = {{3, 40, 70}, {9, 70, 5}, {2, 17, 64 * 65 + 3}};
    double unit[3] = {1, 1, 1};
    for (size_t i = 0; i < sizeof big / sizeof big[0]; i++) {
        const int *sz = big[i];
        voxref *a = voxref_create(sz[0], sz[1], sz[2]);
        for (int pass = 0; pass < 2; pass++) {
            voxref_random(a, pass ? 7 : 1, pass ? 8 : 12, harness_rand);
            bvox_volume *v = voxref_to_volume(a);
            for (int erode = 0; erode < 2; erode++) {
                voxref *r = ref_morph(a, conn26, unit, 0, 1, erode);
                for (int threads = 1; threads <= 4; threads++) {
                    bvox_set_threads(threads);
                    bvox_volume *out;
                    CHECK_OK(erode ? bvox_morph_erode(v, 26, &out) : bvox_morph_dilate(v, 26, &out));
                    CHECK_OK(bvox_volume_check(out));
                    if (!voxref_matches(r, out)) {
                        fprintf(stderr, "erode %d size %dx%dx%d threads %d\n", erode, sz[0], sz[1],
                                sz[2], threads);
                        return 1;
                    }
                    bvox_volume_destroy(out);
                }
                voxref_destroy(r);
            }
            bvox_volume_destroy(v);
        }
        voxref_destroy(a);
    }
    bvox_set_threads(0);
    return 0;
}

/* The ball kernel (morph_ball.c) streams bands of rows (one per thread)
 * through x tiles: narrow tiles, 1..16 threads, radii up to 6, columns of
 * one, two and three words, anisotropic voxels, every SIMD level of the
 * inner loops (morph_ball_kern.h); dilation of a sparse
 * volume and erosion of its dilation against the voxel-by-voxel reference. */
TEST(ball_tiles_and_threads_against_reference)
{
    static const struct {
        int nx, ny, nz;
        double r, s[3];
    } cases[] = {{37, 41, 70, 4.0, {1, 1, 1}},   {29, 33, 130, 6.0, {1, 1, 1}},
                 {31, 26, 63, 3.2, {1, 0.8, 1}}, {24, 35, 150, 2.6, {0.6, 1, 0.3}},
                 {20, 19, 5, 10.0, {1, 1, 1}}};
    static const int tiles[] = {0, 1, 5};
    static const int threads[] = {1, 16};
    static const bvox_simd levels[3] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        voxref *a = voxref_create(cases[c].nx, cases[c].ny, cases[c].nz);
        voxref_random(a, 1, 300, harness_rand);
        bvox_volume *v = voxref_to_volume(a);
        const double *s = cases[c].s;
        CHECK_OK(bvox_volume_set_spacing(v, s[0], s[1], s[2], "mm"));
        double smin = s[0] < s[1] ? s[0] : s[1];
        smin = smin < s[2] ? smin : s[2];
        int reach = (int)(cases[c].r / smin) + 1;
        for (int erode = 0; erode < 2; erode++) {
            if (erode) { /* erode the dilation: dense enough to matter */
                bvox_volume *d;
                bvox__morph_ball_test_tile = 0;
                bvox_set_threads(0);
                CHECK_OK(bvox_morph_dilate_ball(v, cases[c].r, &d));
                voxref_destroy(a);
                a = voxref_from_volume(d);
                bvox_volume_destroy(v);
                v = d;
            }
            voxref *r = ref_morph(a, in_ball, s, cases[c].r, reach, erode);
            for (size_t ti = 0; ti < sizeof tiles / sizeof tiles[0]; ti++)
                for (size_t th = 0; th < sizeof threads / sizeof threads[0]; th++)
                for (int lv = 0; lv < 3; lv++) {
                    if (bvox_simd_set(levels[lv]) != BVOX_OK) continue; /* not on this CPU */
                    bvox__morph_ball_test_tile = tiles[ti];
                    bvox_set_threads(threads[th]);
                    bvox_volume *out;
                    CHECK_OK(erode ? bvox_morph_erode_ball(v, cases[c].r, &out)
                                   : bvox_morph_dilate_ball(v, cases[c].r, &out));
                    CHECK_OK(bvox_volume_check(out));
                    if (!voxref_matches(r, out)) {
                        fprintf(stderr, "case %zu erode %d tile %d threads %d simd %s\n", c,
                                erode, tiles[ti], threads[th], bvox_simd_name(levels[lv]));
                        return 1;
                    }
                    bvox_volume_destroy(out);
                }
            voxref_destroy(r);
        }
        bvox_volume_destroy(v);
        voxref_destroy(a);
    }
    bvox__morph_ball_test_tile = 0;
    bvox_set_threads(0);
    bvox_simd_set(BVOX_SIMD_AUTO);
    return 0;
}
