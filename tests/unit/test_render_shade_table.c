/* test_render_shade_table.c — the shading-code + colour-table stage
 * (bvox_shade_codes, bvox_shade_table_build, bvox_shade_table_apply) that the
 * viewer draws its 3D pane with: codes of a hand-made pre-image per mode and
 * on a cut plane, table entries computed by hand (depth curve, Phong, depth
 * factor, object colour, cut tint), strides and stray codes, bad options, and
 * agreement with bvox_render on a real cast (binary shading and the cut face
 * exactly, gradient shading within the bins' error). */
#include "harness.h"

#include <stdlib.h>
#include <string.h>

#define IDX(nx, ny, nz) (((nx) + 1) * 9 + ((ny) + 1) * 3 + ((nz) + 1))

/* 4 x 1 pixels over our own arrays, the +z axis frame, unit steps. */
static int32_t hand_depth[4] = {-1, 0, 5, 9};
static uint8_t hand_code[4] = {BVOX_CODE_BACKGROUND, IDX(0, 0, -1), IDX(1, 0, 0) | 3 << 5,
                               IDX(0, 0, -1) | 7 << 5};

static bvox_preimage hand_pre(void)
{
    bvox_preimage p;
    memset(&p, 0, sizeof p);
    p.width = 4, p.height = 1;
    p.depth = hand_depth, p.code = hand_code;
    p.depth_range = 10;
    p.depth_step = 1, p.pixel_size[0] = p.pixel_size[1] = 1;
    p.eye[0] = p.eye[4] = p.eye[8] = 1;
    p.spacing[0] = p.spacing[1] = p.spacing[2] = 1;
    return p;
}

/* ambient 0.1 + diffuse 0.5, no specular, light from the viewer: a normal
 * facing the viewer is 0.6 * 255 = 153 */
static bvox_shade_opts hand_opts(bvox_shade_mode mode)
{
    bvox_shade_opts o = BVOX_SHADE_OPTS_INIT;
    o.mode = mode;
    o.light.azimuth = 0, o.light.elevation = 90;
    o.light.ambient = 0.1, o.light.diffuse = 0.5, o.light.specular = 0;
    o.background[0] = 1, o.background[1] = 2, o.background[2] = 3;
    return o;
}

TEST(codes_per_mode)
{
    bvox_preimage p = hand_pre();
    uint16_t c[4];
    bvox_shade_opts o = hand_opts(BVOX_SHADE_DEPTH);
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[0], BVOX_SCODE_BACKGROUND);
    CHECK_EQ(c[1], 0);
    CHECK_EQ(c[2], 141); /* 5 * 255 / 9 */
    CHECK_EQ(c[3], 255);
    o.mode = BVOX_SHADE_BINARY;
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[0], BVOX_SCODE_BACKGROUND);
    for (int i = 1; i < 4; i++) CHECK_EQ(c[i], hand_code[i]);
    o.mode = BVOX_SHADE_BINARY_DEPTH; /* 16 levels: d * 16 / 10 */
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[1], IDX(0, 0, -1));
    CHECK_EQ(c[2], IDX(1, 0, 0) | 8 << 5);
    CHECK_EQ(c[3], IDX(0, 0, -1) | 14 << 5);
    o.mode = BVOX_SHADE_GRADIENT; /* depths 0, 5, 9 along a row: Sobel gx */
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[0], BVOX_SCODE_BACKGROUND);
    for (int i = 1; i < 4; i++) CHECK(c[i] < 4096);
    /* pixel 1 (depth 0): its left neighbour is background and the rows above
     * and below are outside, all taking the centre's 0; the right one is 5:
     * gx = 2 * 5 / 8 = 1.25, gy = 0, normal (1.25, 0, 1) / 1.6008: right
     * 0.7809 -> bin floor(1.7809 * 32) = 56, up 0 -> bin 32 */
    CHECK_EQ(c[1], 56 + 64 * 32);
    return 0;
}

TEST(codes_cut_face)
{
    bvox_preimage p = hand_pre();
    uint16_t c[4];
    bvox_shade_opts o = hand_opts(BVOX_SHADE_BINARY);
    o.cut = 1;
    /* z >= 5.5 kept: the face the cut exposed is z = 5.5, entered at depth
     * 5; a pixel is on it when its entry point, the middle of its depth step
     * (z = d + 0.5), has z - 5.5 < half a voxel (0.5) + half a step (0.5) */
    o.plane[0] = 0, o.plane[1] = 0, o.plane[2] = 1, o.plane[3] = -5.5;
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[0], BVOX_SCODE_BACKGROUND);
    CHECK_EQ(c[2], BVOX_SCODE_CUT | 141); /* d 5: 0 */
    CHECK_EQ(c[3], hand_code[3]);         /* d 9: 4, far behind the plane */
    hand_depth[2] = 7;                    /* 2: not on it */
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    hand_depth[2] = 5;
    CHECK_EQ(c[2], hand_code[2]);
    /* thick sections: voxels 3 long in z, the plane z >= 16.5 (1.5 past the
     * centre 15 of voxel 5): half a voxel is 1.5 and half a step 0.5, so an
     * entry at z = d + 0.5 is on the face while below 16.5 + 2 = 18.5 */
    p.spacing[2] = 3;
    p.depth_range = 30;
    o.plane[3] = -16.5;
    hand_depth[3] = 17; /* 17.5: on it */
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[3], BVOX_SCODE_CUT | 149); /* 17 * 255 / 29 */
    hand_depth[3] = 19; /* 19.5: not */
    CHECK_OK(bvox_shade_codes(&p, &o, c));
    CHECK_EQ(c[3], hand_code[3]);
    hand_depth[3] = 9;
    return 0;
}

TEST(table_by_hand)
{
    bvox_preimage p = hand_pre();
    bvox_shade_table *t = malloc(sizeof *t);
    CHECK(t != NULL);
    /* depth: linear 255 .. 40 */
    bvox_shade_opts o = hand_opts(BVOX_SHADE_DEPTH);
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[0][0], 255);
    CHECK_EQ(t->rgb[255][1], 40);
    CHECK_EQ(t->rgb[141][2], 136); /* 255 - 215 * 141 / 255 = 136.1 */
    CHECK(!memcmp(t->rgb[BVOX_SCODE_BACKGROUND], o.background, 3));
    /* binary: the normal facing the viewer 153, one facing right lit only by
     * the ambient 0.1 * 255 = 25.5 -> 26; the same as bvox_lut_light's table */
    o.mode = BVOX_SHADE_BINARY;
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[IDX(0, 0, -1)][0], 153);
    CHECK_EQ(t->rgb[IDX(1, 0, 0)][1], 26);
    bvox_lut lut;
    CHECK_OK(bvox_lut_light(&p, &o.light, &lut));
    for (int c = 0; c < 256; c++)
        for (int ch = 0; ch < 3; ch++) CHECK_EQ(t->rgb[c][ch], lut.value[c]);
    /* binary + depth: level 8 of 16 darkens by 1 - 0.5 * 8.5 / 16 */
    o.mode = BVOX_SHADE_BINARY_DEPTH;
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[IDX(0, 0, -1) | 8 << 5][0], 112); /* 153 * 0.734375 = 112.4 */
    CHECK_EQ(t->rgb[IDX(0, 0, -1)][0], 151);          /* 153 * (1 - 0.5 * 0.5 / 16) = 150.6 */
    /* an object colour scales the shade per channel */
    o.mode = BVOX_SHADE_BINARY;
    o.color[0] = 255, o.color[1] = 128, o.color[2] = 0;
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[IDX(0, 0, -1)][0], 153);
    CHECK_EQ(t->rgb[IDX(0, 0, -1)][1], 77); /* (153 * 128 + 127) / 255 = 77.3 */
    CHECK_EQ(t->rgb[IDX(0, 0, -1)][2], 0);
    /* the cut face: lit flat by the plane's normal (facing the viewer: 153),
     * tinted 255, 176, 96; binary + depth darkens the farthest level by half */
    o.color[1] = o.color[2] = 255;
    o.cut = 1;
    o.plane[0] = 0, o.plane[1] = 0, o.plane[2] = -2, o.plane[3] = 9; /* either sign, any length */
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 17][0], 153);
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 17][1], 106); /* 153 * 176 / 255 = 105.6 */
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 17][2], 58);  /* 153 * 96 / 255 = 57.6 */
    o.mode = BVOX_SHADE_BINARY_DEPTH;
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 0][0], 153);
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 128][0], 115); /* 153 (1 - 0.5 * 128 / 255) = 114.6 */
    o.mode = BVOX_SHADE_DEPTH; /* the cut face keeps its depth shade, tinted */
    CHECK_OK(bvox_shade_table_build(&p, &o, t));
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 141][0], 136);
    CHECK_EQ(t->rgb[BVOX_SCODE_CUT | 141][2], 51); /* 136 * 96 / 255 = 51.2 */
    free(t);
    return 0;
}

TEST(apply_strides_and_stray_codes)
{
    bvox_shade_table *t = calloc(1, sizeof *t);
    CHECK(t != NULL);
    t->rgb[5][0] = 50, t->rgb[6][1] = 60;
    t->rgb[BVOX_SCODE_BACKGROUND][2] = 99;
    const uint16_t codes[2 * 3] = {5, 6, 777, 60000, 5, 777};
    uint8_t rgb[2 * 12];
    memset(rgb, 0xee, sizeof rgb);
    bvox_shade_table_apply(t, codes, 2, 2, 3, rgb, 12);
    const uint8_t want[2 * 12] = {50, 0, 0, 0, 60, 0, 0xee, 0xee, 0xee, 0xee, 0xee, 0xee,
                                  0, 0, 99, 50, 0, 0, 0xee, 0xee, 0xee, 0xee, 0xee, 0xee};
    CHECK(!memcmp(rgb, want, sizeof want));
    free(t);
    return 0;
}

TEST(bad_options)
{
    bvox_preimage p = hand_pre();
    uint16_t c[4];
    bvox_shade_table *t = malloc(sizeof *t);
    CHECK(t != NULL);
    bvox_shade_opts o = hand_opts(BVOX_SHADE_BINARY);
    o.mode = (bvox_shade_mode)9;
    CHECK_STATUS(bvox_shade_codes(&p, &o, c), BVOX_EINVAL);
    CHECK_STATUS(bvox_shade_table_build(&p, &o, t), BVOX_EINVAL);
    o = hand_opts(BVOX_SHADE_BINARY);
    o.cut = 1, o.plane[0] = o.plane[1] = o.plane[2] = 0;
    CHECK_STATUS(bvox_shade_codes(&p, &o, c), BVOX_EINVAL);
    o = hand_opts(BVOX_SHADE_BINARY);
    o.light.diffuse = NAN;
    CHECK_STATUS(bvox_shade_table_build(&p, &o, t), BVOX_EINVAL);
    o = hand_opts(BVOX_SHADE_DEPTH);
    o.depth.near_value = 300;
    CHECK_STATUS(bvox_shade_table_build(&p, &o, t), BVOX_EINVAL);
    o = hand_opts(BVOX_SHADE_BINARY);
    CHECK_STATUS(bvox_shade_codes(NULL, &o, c), BVOX_EINVAL);
    CHECK_STATUS(bvox_shade_codes(&p, NULL, c), BVOX_EINVAL);
    CHECK_STATUS(bvox_shade_table_build(&p, &o, NULL), BVOX_EINVAL);
    free(t);
    return 0;
}

/* codes + table = table-shaded image of pre for mode (and the cut face) */
static int stage_image(const bvox_preimage *pre, const bvox_shade_opts *o, uint8_t *rgb)
{
    size_t n = (size_t)pre->width * (size_t)pre->height;
    uint16_t *codes = malloc(n * sizeof *codes);
    bvox_shade_table *t = malloc(sizeof *t);
    CHECK(codes && t);
    CHECK_OK(bvox_shade_codes(pre, o, codes));
    CHECK_OK(bvox_shade_table_build(pre, o, t));
    bvox_shade_table_apply(t, codes, pre->width, pre->height, (size_t)pre->width, rgb,
                           3 * (size_t)pre->width);
    free(codes), free(t);
    return 0;
}

TEST(agrees_with_render)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){40, 36, 30}, &v));
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_SPHERE, s.center[0] = 19, s.center[1] = 17, s.center[2] = 14, s.radius = 12;
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    CHECK_OK(bvox_volume_set_spacing(v, 1, 1, 1.5, "mm"));
    bvox_render_opts r = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("30,20", &r));
    r.proj.width = 120, r.proj.height = 100;
    for (int cut = 0; cut <= 1; cut++)
        for (int mode = BVOX_SHADE_BINARY; mode <= BVOX_SHADE_GRADIENT; mode++) {
            r.shade = (bvox_shade_mode)mode;
            r.cut = cut;
            r.plane[0] = 0.3, r.plane[1] = 0.2, r.plane[2] = 1, r.plane[3] = -22; /* world = voxel frame here */
            bvox_image *img;
            bvox_preimage *pre;
            CHECK_OK(bvox_render(v, &r, &img, &pre));
            bvox_shade_opts o = BVOX_SHADE_OPTS_INIT;
            o.mode = r.shade, o.light = r.light, o.cut = cut;
            memcpy(o.plane, r.plane, sizeof o.plane);
            o.background[0] = o.background[1] = o.background[2] = r.light.background;
            size_t n = (size_t)pre->width * (size_t)pre->height;
            uint8_t *rgb = malloc(3 * n);
            CHECK(rgb != NULL);
            CHECK(!stage_image(pre, &o, rgb));
            long tinted = 0, sum = 0, worst = 0;
            for (size_t i = 0; i < n; i++)
                for (int ch = 0; ch < 3; ch++) {
                    int want = img->pixels[img->channels == 3 ? 3 * i + (size_t)ch : i];
                    int d = abs(want - rgb[3 * i + (size_t)ch]);
                    tinted += ch == 0 && rgb[3 * i] > rgb[3 * i + 2] + 40;
                    /* the cut face is the same set of pixels in both */
                    if (ch == 0 && cut) CHECK_EQ(rgb[3 * i] > rgb[3 * i + 2] + 40, want > img->pixels[3 * i + 2] + 40);
                    sum += d;
                    worst = d > worst ? d : worst;
                }
            fprintf(stderr, "cut %d mode %d: mean %.3f worst %ld tinted %ld\n", cut, mode,
                    (double)sum / (3.0 * (double)n), worst, tinted);
            if (mode == BVOX_SHADE_BINARY) CHECK(worst <= 1); /* rounding of the tint only */
            else CHECK((double)sum / (3.0 * (double)n) < 1.0); /* 64 x 64 normal bins */
            if (cut) CHECK(tinted > 500);
            else CHECK_EQ(tinted, 0);
            free(rgb);
            bvox_image_destroy(img);
            bvox_preimage_destroy(pre);
        }
    bvox_volume_destroy(v);
    return 0;
}
