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

/* The smooth normal by brute force: minus the sum of the offsets (i, j, k)
 * with i^2 + j^2 + k^2 <= r^2 + r whose voxel is 1 (outside reads 0),
 * divided by the spacing; 0 when that sum is zero. */
static int ref_smooth_normal(const bvox_volume *v, int x, int y, int z, int r, const double sp[3],
                             double n[3])
{
    bvox_dims d = bvox_volume_dims(v);
    long m[3] = {0, 0, 0};
    for (int k = -r; k <= r; k++)
        for (int j = -r; j <= r; j++)
            for (int i = -r; i <= r; i++) {
                if (i * i + j * j + k * k > r * r + r) continue;
                int a = x + i, b = y + j, c = z + k;
                if (a < 0 || b < 0 || c < 0 || a >= d.nx || b >= d.ny || c >= d.nz) continue;
                if (!bvox_volume_get(v, a, b, c)) continue;
                m[0] += i, m[1] += j, m[2] += k;
            }
    double len = 0;
    for (int a = 0; a < 3; a++) n[a] = -(double)m[a] / sp[a], len += n[a] * n[a];
    if (len == 0) return 0;
    for (int a = 0; a < 3; a++) n[a] /= sqrt(len);
    return 1;
}

TEST(smooth_normal_matches_brute_force)
{
    /* random voxels (half set) in 9 x 7 x 133: columns of three words, so
     * the ball's windows cross word borders and every face of the volume,
     * at every voxel and one beyond, for each radius and a thick spacing */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){9, 7, 133}, &v));
    unsigned s = 12345;
    for (int z = 0; z < 133; z++)
        for (int y = 0; y < 7; y++)
            for (int x = 0; x < 9; x++) {
                s = s * 1103515245u + 12345u;
                if (s >> 16 & 1) bvox_volume_set(v, x, y, z, 1);
            }
    const double sp[3] = {0.5, 1, 3};
    CHECK_OK(bvox_volume_set_spacing(v, sp[0], sp[1], sp[2], NULL));
    long compared = 0;
    for (int r = 1; r <= 3; r++)
        for (int z = -1; z <= 133; z++)
            for (int y = -1; y <= 7; y++)
                for (int x = -1; x <= 9; x++) {
                    double n[3], e[3];
                    int got = bvox_smooth_normal(v, x, y, z, r, n), want = ref_smooth_normal(v, x, y, z, r, sp, e);
                    CHECK_EQ(got, want);
                    for (int a = 0; a < 3; a++) CHECK_NEAR(n[a], want ? e[a] : 0, 1e-12);
                    compared++;
                }
    CHECK_EQ(compared, 3L * 135 * 9 * 11);
    bvox_volume_destroy(v);
    return 0;
}

TEST(sphere_normals_within_10_degrees)
{
    bvox_volume *v = make(SN, in_sphere);
    CHECK(v != NULL);
    /* 200 pixels: smaller than a voxel (interpolated normals); 90: larger
     * (the nearest voxel's) */
    const double views[4][3] = {{0, 0, 200}, {30, 20, 200}, {-50, 65, 200}, {30, 20, 90}};
    for (int k = 0; k < 4; k++) {
        bvox_projection proj = BVOX_PROJECTION_INIT;
        proj.azimuth = views[k][0], proj.elevation = views[k][1];
        proj.width = proj.height = (int32_t)views[k][2];
        bvox_preimage *p;
        CHECK_OK(bvox_cast_projection(v, &proj, &p));
        double smooth = share_within(v, p, BVOX_SHADE_SMOOTH, 2);
        double smooth3 = share_within(v, p, BVOX_SHADE_SMOOTH, 3);
        double binary = share_within(v, p, BVOX_SHADE_BINARY, 0);
        double gradient = share_within(v, p, BVOX_SHADE_GRADIENT, 0);
        fprintf(stderr, "view %g,%g at %g pixels: within 10 degrees: smooth %.3f (radius 3: %.3f), "
                        "binary %.3f, gradient %.3f\n", views[k][0], views[k][1], views[k][2], smooth,
                smooth3, binary, gradient);
        CHECK(smooth >= 0.95);
        CHECK(smooth3 >= 0.95);
        CHECK(binary >= 0 && binary < 0.5);
        bvox_preimage_destroy(p);
    }
    bvox_volume_destroy(v);
    return 0;
}

/* A hand-made pre-image of w x h with the given depths (-1 background), the
 * frame of a +z axis view of unit voxels. */
static bvox_preimage *hand_pre(int32_t w, int32_t h, const int32_t *depth)
{
    bvox_preimage *p = NULL;
    if (bvox__preimage_alloc(w, h, &p)) return NULL;
    for (int32_t i = 0; i < w * h; i++) {
        p->depth[i] = depth[i];
        p->code[i] = depth[i] < 0 ? BVOX_CODE_BACKGROUND : BVOX_NORMAL_NONE;
    }
    p->depth_range = 64;
    p->depth_step = 1;
    p->pixel_size[0] = p->pixel_size[1] = 1;
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(p->eye, eye, sizeof eye);
    p->spacing[0] = p->spacing[1] = p->spacing[2] = 1;
    return p;
}

TEST(enlarge_figure5)
{
    /* the paper's Figure 5: 13 5 / 0 8 (and zeros around, depths here) */
    const int32_t d[16] = {13, 5, 0, 0, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    const int32_t want[16] = {13, 9, 5, 3, 7, 7, 7, 3, 0, 4, 8, 4, 0, 2, 4, 2};
    bvox_preimage *p = hand_pre(4, 4, d), *big;
    CHECK(p != NULL);
    CHECK_OK(bvox_preimage_enlarge(p, &big));
    CHECK_EQ(big->width, 8);
    CHECK_EQ(big->height, 8);
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) CHECK_EQ(big->depth[r * 8 + c], want[r * 4 + c]);
    CHECK_NEAR(big->pixel_size[0], 0.5, 0);
    bvox_preimage_destroy(big);
    /* the background is neither averaged in nor grown: 13 5 / - 8 */
    p->depth[4] = -1;
    p->code[4] = BVOX_CODE_BACKGROUND;
    CHECK_OK(bvox_preimage_enlarge(p, &big));
    CHECK_EQ(big->depth[8 * 1 + 0], 13);  /* (13 + bg) -> 13 */
    CHECK_EQ(big->depth[8 * 1 + 1], 9);   /* (13 + 5 + bg + 8) / 3 = 8.67 -> 9 */
    CHECK_EQ(big->depth[8 * 2 + 0], -1);  /* replicated background */
    CHECK_EQ(big->depth[8 * 3 + 1], -1);
    CHECK_EQ(big->code[8 * 2 + 1], BVOX_CODE_BACKGROUND);
    bvox_preimage_destroy(big);
    bvox_preimage_destroy(p);
    CHECK_STATUS(bvox_preimage_enlarge(NULL, &big), BVOX_EINVAL);
    CHECK(big == NULL);
    return 0;
}

TEST(preimage_binary_operator)
{
    /* a ramp deeper to the right (+x), flat in y, with a background column */
    const int32_t d[15] = {0, 1, 2, 3, -1, 0, 1, 2, 3, -1, 0, 1, 2, 3, -1};
    bvox_preimage *p = hand_pre(5, 3, d);
    CHECK(p != NULL);
    float n[45];
    CHECK_OK(bvox_preimage_normals(NULL, p, BVOX_SHADE_PREIMAGE_BINARY, 0, n));
    /* (1, 1, 1): x = 1, row 1: left is nearer (1), right deeper (0); above
     * and below equal (both 1): n = (1, 0, 1) / sqrt 2, right and towards us */
    const size_t i = 3 * (size_t)(1 * 5 + 1);
    CHECK_NEAR(n[i + 0], sqrt(0.5), 1e-6);
    CHECK_NEAR(n[i + 1], 0, 1e-6);
    CHECK_NEAR(n[i + 2], sqrt(0.5), 1e-6);
    /* row 0: the pixel above is outside (0), the one below equal (1): the
     * normal gains "up" */
    const size_t k = 3 * (size_t)(0 * 5 + 2);
    CHECK_NEAR(n[k + 0], 1 / sqrt(3.0), 1e-6);
    CHECK_NEAR(n[k + 1], 1 / sqrt(3.0), 1e-6);
    /* at x = 3 the right neighbour is background (0): same as deeper */
    CHECK_NEAR(n[3 * (size_t)(1 * 5 + 3)], sqrt(0.5), 1e-6);
    /* background gives zeros; smooth needs a volume */
    CHECK(n[3 * 4] == 0 && n[3 * 4 + 2] == 0);
    CHECK_STATUS(bvox_preimage_normals(NULL, p, BVOX_SHADE_SMOOTH, 0, n), BVOX_EINVAL);
    bvox_preimage_destroy(p);
    return 0;
}

/* A floor (z >= 30) with a block on it (x, y in 15..24, z in 10..29). */
static int floor_block(int x, int y, int z)
{
    return z >= 30 || (x >= 15 && x < 25 && y >= 15 && y < 25 && z >= 10);
}

TEST(ao_open_floor_and_corner)
{
    bvox_volume *v = make(40, floor_block);
    CHECK(v != NULL);
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(v, BVOX_VIEW_POS_Z, &p));
    uint8_t ao[1600];
    CHECK_OK(bvox_preimage_ao(v, p, 0, ao));
    CHECK_EQ(ao[20 * 40 + 20], 255); /* the block's top: open */
    CHECK_EQ(ao[35 * 40 + 35], 255); /* the floor far from the block */
    /* the floor in the corner beside the block sees the wall: darker, and
     * darker still than one voxel farther out */
    CHECK(ao[20 * 40 + 14] < 230);
    CHECK(ao[20 * 40 + 14] < ao[20 * 40 + 11]);
    bvox_preimage_destroy(p);
    bvox_volume_destroy(v);
    return 0;
}

TEST(shadows_of_a_block)
{
    bvox_volume *v = make(40, floor_block);
    CHECK(v != NULL);
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(v, BVOX_VIEW_POS_Z, &p));
    /* light from the right (+x) at 45 degrees towards the viewer (-z): a
     * floor point (x, y, 30) sees it along (1, 0, -1), which crosses the
     * block (x = 15, z = 30 - (15 - x) in 10..29) for x in -4..14 */
    bvox_light light = BVOX_LIGHT_INIT;
    light.azimuth = 0, light.elevation = 45;
    uint8_t lit[1600];
    CHECK_OK(bvox_preimage_shadows(v, p, &light, 0, lit));
    for (int y = 17; y < 23; y++) {
        for (int x = 2; x < 12; x++) CHECK_EQ(lit[y * 40 + x], 0);  /* behind the block */
        for (int x = 28; x < 38; x++) CHECK_EQ(lit[y * 40 + x], 1); /* in front of it */
        for (int x = 17; x < 23; x++) CHECK_EQ(lit[y * 40 + x], 1); /* its top */
    }
    for (int x = 2; x < 12; x++) CHECK_EQ(lit[5 * 40 + x], 1); /* beside the shadow */
    /* the light from the left: the shadow moves to the other side */
    light.azimuth = 180;
    CHECK_OK(bvox_preimage_shadows(v, p, &light, 0, lit));
    CHECK_EQ(lit[20 * 40 + 5], 1);
    CHECK_EQ(lit[20 * 40 + 30], 0);
    bvox_preimage_destroy(p);
    bvox_volume_destroy(v);
    return 0;
}

static int golden_lit(const char *name, bvox_shade_mode mode, int ao, int shadows, int ss,
                      int32_t want_w, double elevation);

/* ---- golden pictures of the new modes: the built-in specimen from the iso
 * view, compared pixel by pixel (mean absolute difference at most 1 gray
 * level, and no pixel off by more than 24: a moved edge or a changed shade
 * fails). BVOX_UPDATE_GOLDEN=1 rewrites them and fails (see harness.h). */
static int golden(const char *name, bvox_shade_mode mode, int ao, int shadows, int ss,
                  int32_t want_w)
{
    return golden_lit(name, mode, ao, shadows, ss, want_w, 45);
}

static int golden_lit(const char *name, bvox_shade_mode mode, int ao, int shadows, int ss,
                      int32_t want_w, double elevation)
{
    bvox_volume *v;
    CHECK_OK(bvox_demo_specimen(&v));
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("iso", &o));
    o.proj.width = o.proj.height = 128;
    o.shade = mode, o.ao = ao, o.shadows = shadows, o.supersample = ss;
    o.light.azimuth = 150, o.light.elevation = elevation; /* low: long shadows */
    bvox_image *img;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    bvox_volume_destroy(v);
    CHECK_EQ(img->width, want_w);
    CHECK_EQ(img->channels, 1);
    return harness_golden_compare(img, name, 1.0, 24);
}

TEST(golden_smooth) { return golden("shade_smooth", BVOX_SHADE_SMOOTH, 0, 0, 0, 128); }
TEST(golden_binary_preimage)
{
    return golden("shade_binary_preimage", BVOX_SHADE_PREIMAGE_BINARY, 0, 0, 0, 128);
}
TEST(golden_enlarged_gradient)
{
    return golden("shade_enlarged_gradient", BVOX_SHADE_ENLARGED_GRADIENT, 0, 0, 0, 256);
}
TEST(golden_ao) { return golden("shade_smooth_ao", BVOX_SHADE_SMOOTH, 1, 0, 0, 128); }
TEST(golden_shadows)
{
    return golden_lit("shade_smooth_shadows", BVOX_SHADE_SMOOTH, 0, 1, 0, 128, 15);
}
TEST(golden_supersample)
{
    return golden_lit("shade_smooth_ss3", BVOX_SHADE_SMOOTH, 1, 1, 3, 128, 15);
}

TEST(shade_codes_smooth)
{
    /* the viewer's path: smooth codes are the gradient layout, made from the
     * volume; the sphere's middle faces the viewer, its left rim the left */
    bvox_volume *v = make(SN, in_sphere);
    CHECK(v != NULL);
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(v, BVOX_VIEW_NEG_Z, &p));
    uint16_t *codes = calloc((size_t)SN * SN, sizeof *codes);
    CHECK(codes != NULL);
    bvox_shade_opts o = BVOX_SHADE_OPTS_INIT;
    o.mode = BVOX_SHADE_SMOOTH;
    CHECK_STATUS(bvox_shade_codes(p, &o, codes), BVOX_EINVAL);
    CHECK_OK(bvox_shade_codes_volume(v, p, &o, codes));
    const unsigned mid = codes[48 * SN + 48], rim = codes[48 * SN + 9];
    CHECK((mid & 63) >= 31 && (mid & 63) <= 33 && (mid >> 6) >= 31 && (mid >> 6) <= 33);
    CHECK((rim & 63) < 8);                        /* pointing left: right component ~ -1 */
    CHECK((rim >> 6) >= 28 && (rim >> 6) <= 35);  /* neither up nor down */
    CHECK_EQ(codes[0], BVOX_SCODE_BACKGROUND);
    /* the table lights the bins: facing the viewer is bright, the rim dim */
    bvox_shade_table *t = malloc(sizeof *t);
    CHECK(t != NULL);
    o.light.azimuth = 0, o.light.elevation = 90;
    CHECK_OK(bvox_shade_table_build(p, &o, t));
    CHECK(t->rgb[mid][0] > 240 && t->rgb[rim][0] < 100);
    o.smooth_radius = 4;
    CHECK_STATUS(bvox_shade_codes_volume(v, p, &o, codes), BVOX_EINVAL);
    free(t);
    free(codes);
    bvox_preimage_destroy(p);
    bvox_volume_destroy(v);
    return 0;
}
