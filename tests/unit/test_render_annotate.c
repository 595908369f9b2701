/* test_render_annotate.c — colours, backgrounds, annotations and several
 * objects in one picture (issue 18 item 2, issue 19 item 4), against known
 * answers: the scale bar's round length in pixels for spacings that give 1,
 * 2 and 5 x 10^k, the triad's axes along the view's image axes, colour =
 * shade x colour / 255 pixel by pixel, the background and alpha per pixel,
 * the nearest of two objects winning from either side, label colours from a
 * table, the cut face in a lighter tone; then goldens of each (looked at). */
#include "harness.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bvox_volume *box_volume(bvox_dims d, bvox_box b)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create(d, &v)) return NULL;
    bvox_volume_fill_box(v, b, 1);
    return v;
}

static const uint8_t *px(const bvox_image *im, int x, int y)
{
    return im->pixels + ((size_t)y * (size_t)im->width + (size_t)x) * (size_t)im->channels;
}

static int is_rgb(const uint8_t *p, int r, int g, int b)
{
    return p[0] == r && p[1] == g && p[2] == b;
}

/* The bar of a width-100 axis view at spacing sx: from x = 8 (the margin),
 * want pixels long, on the rows height - 10 and - 9. */
static int bar_case(double sx, int want)
{
    bvox_volume *v = box_volume((bvox_dims){100, 40, 8}, (bvox_box){40, 5, 0, 60, 12, 8});
    CHECK(v);
    CHECK_OK(bvox_volume_set_spacing(v, sx, sx, 1, "mm"));
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    o.scale_bar = 1;
    bvox_image *img;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_EQ(img->width, 100);
    CHECK_EQ(img->channels, 3);
    for (int y = 30; y <= 31; y++) {
        CHECK(is_rgb(px(img, 7, y), 0, 0, 0));
        for (int x = 8; x < 8 + want; x++) CHECK(is_rgb(px(img, x, y), 255, 255, 255));
        CHECK(is_rgb(px(img, 8 + want, y), 0, 0, 0));
    }
    /* the end ticks rise 3 pixels; the label is above them */
    CHECK(is_rgb(px(img, 8, 27), 255, 255, 255));
    CHECK(is_rgb(px(img, 8 + want - 1, 27), 255, 255, 255));
    CHECK(is_rgb(px(img, 9, 27), 0, 0, 0));
    int ink = 0;
    for (int y = 19; y < 26; y++)
        for (int x = 0; x < 40; x++) ink += px(img, x, y)[0] == 255;
    CHECK(ink > 20);
    bvox_image_destroy(img);
    bvox_volume_destroy(v);
    return 0;
}

/* 100 px x 0.5 mm = 50 mm, a fifth 10: 1 x 10^1 = 20 px; 0.3: 6 -> 5 mm =
 * 16.7 -> 17 px; 0.8: 16 -> 10 mm = 12.5 -> 13 px; 2.2: 44 -> 20 mm = 9.1
 * -> 9 px. */
TEST(scale_bar_round_lengths)
{
    return bar_case(0.5, 20) || bar_case(0.3, 17) || bar_case(0.8, 13) || bar_case(2.2, 9);
}

/* The triad's origin at (68, 68) in a 100 x 100 picture (arms of 20): for +z
 * x goes right (red) and y down (green); for +x (columns y, rows z) y goes
 * right and z down (blue). */
TEST(axes_follow_the_view)
{
    bvox_volume *v = box_volume((bvox_dims){100, 100, 100}, (bvox_box){0, 0, 0, 5, 5, 5});
    CHECK(v);
    const char *views[2] = {"+z", "+x"};
    const int right[2] = {0, 1}, down[2] = {1, 2};
    const uint8_t colour[3][3] = {{230, 50, 50}, {40, 200, 60}, {70, 120, 255}};
    for (int k = 0; k < 2; k++) {
        bvox_render_opts o = bvox_render_opts_default();
        CHECK_OK(bvox_render_parse_view(views[k], &o));
        o.axes = 1;
        bvox_image *img;
        CHECK_OK(bvox_render(v, &o, &img, NULL));
        CHECK_EQ(img->width, 100);
        const uint8_t *r = colour[right[k]], *d = colour[down[k]];
        for (int t = 2; t <= 20; t++) {
            CHECK(is_rgb(px(img, 68 + t, 68), r[0], r[1], r[2]));
            CHECK(is_rgb(px(img, 68, 68 + t), d[0], d[1], d[2]));
        }
        CHECK(is_rgb(px(img, 68, 60), 0, 0, 0)); /* nothing goes up */
        bvox_image_destroy(img);
    }
    bvox_volume_destroy(v);
    return 0;
}

/* Pixel by pixel: the coloured picture is the gray one times the colour. */
TEST(color_modulates_the_shading)
{
    bvox_volume *v;
    CHECK_OK(bvox_demo_specimen(&v));
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("iso", &o));
    o.proj.width = o.proj.height = 64;
    o.shade = BVOX_SHADE_SMOOTH;
    bvox_image *gray, *col;
    bvox_preimage *pre;
    CHECK_OK(bvox_render(v, &o, &gray, &pre));
    o.color_set = 1;
    o.color[0] = 255, o.color[1] = 128, o.color[2] = 0;
    CHECK_OK(bvox_render(v, &o, &col, NULL));
    CHECK_EQ(gray->channels, 1);
    CHECK_EQ(col->channels, 3);
    int object = 0;
    for (int i = 0; i < 64 * 64; i++) {
        const uint8_t g = gray->pixels[i], *c = col->pixels + 3 * i;
        object += pre->depth[i] >= 0;
        for (int ch = 0; ch < 3; ch++) CHECK_EQ(c[ch], (g * o.color[ch] + 127) / 255);
    }
    CHECK(object > 500);
    bvox_preimage_destroy(pre);
    bvox_image_destroy(gray);
    bvox_image_destroy(col);
    bvox_volume_destroy(v);
    return 0;
}

TEST(background_and_transparency)
{
    bvox_volume *v = box_volume((bvox_dims){20, 20, 4}, (bvox_box){5, 5, 0, 15, 15, 4});
    CHECK(v);
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    bvox_image *gray, *img;
    bvox_preimage *pre;
    CHECK_OK(bvox_render(v, &o, &gray, &pre));
    o.background[0] = 10, o.background[1] = 20, o.background[2] = 30;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_EQ(img->channels, 3);
    for (int i = 0; i < 400; i++) {
        const uint8_t *p = img->pixels + 3 * i;
        if (pre->depth[i] < 0) CHECK(is_rgb(p, 10, 20, 30));
        else CHECK(is_rgb(p, gray->pixels[i], gray->pixels[i], gray->pixels[i]));
    }
    bvox_image_destroy(img);
    o.transparent = 1;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_EQ(img->channels, 4);
    for (int i = 0; i < 400; i++) {
        const uint8_t *p = img->pixels + 4 * i;
        if (pre->depth[i] < 0) CHECK(is_rgb(p, 0, 0, 0) && p[3] == 0);
        else CHECK(is_rgb(p, gray->pixels[i], gray->pixels[i], gray->pixels[i]) && p[3] == 255);
    }
    CHECK_EQ(img->pixels[0 * 4 + 3], 0);
    CHECK_EQ(img->pixels[(10 * 20 + 10) * 4 + 3], 255);
    bvox_image_destroy(img);
    /* an anaglyph has no alpha */
    o.stereo = BVOX_STEREO_ANAGLYPH;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    bvox_preimage_destroy(pre);
    bvox_image_destroy(gray);
    bvox_volume_destroy(v);
    return 0;
}

/* A (x 0..10, z 10..20) red and B (x 5..15, z 2..5) blue overlap in x 5..10:
 * seen along +z (rays enter at z = 0) B is in front there, along -z A. */
TEST(objects_nearest_wins)
{
    bvox_dims d = {16, 10, 24};
    bvox_volume *a = box_volume(d, (bvox_box){0, 0, 10, 10, 10, 20});
    bvox_volume *b = box_volume(d, (bvox_box){5, 0, 2, 15, 10, 5});
    CHECK(a && b);
    const bvox_volume *vols[2] = {a, b};
    const uint8_t colors[2][3] = {{255, 0, 0}, {0, 0, 255}};
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    bvox_image *img;
    for (int k = 0; k < 2; k++) {
        CHECK_OK(bvox_render_parse_view(k ? "-z" : "+z", &o));
        CHECK_OK(bvox_render_objects(vols, colors, 2, &o, &img));
        CHECK_EQ(img->channels, 3);
        const uint8_t *left = px(img, 2, 5), *mid = px(img, 7, 5), *right = px(img, 12, 5);
        CHECK(left[0] > 0 && left[1] == 0 && left[2] == 0);     /* A alone */
        CHECK(right[0] == 0 && right[1] == 0 && right[2] > 0);  /* B alone */
        if (k == 0) CHECK(mid[0] == 0 && mid[2] > 0);           /* B in front */
        else CHECK(mid[0] > 0 && mid[2] == 0);                  /* A in front */
        bvox_image_destroy(img);
    }
    /* one grid only */
    bvox_volume *c = box_volume((bvox_dims){16, 10, 25}, (bvox_box){0, 0, 0, 1, 1, 1});
    const bvox_volume *bad[2] = {a, c};
    CHECK_STATUS(bvox_render_objects(bad, colors, 2, &o, &img), BVOX_EINVAL);
    CHECK_STATUS(bvox_render_objects(vols, colors, 0, &o, &img), BVOX_EINVAL);
    bvox_volume_destroy(c);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return 0;
}

static bvox_labelset *small_labels(void)
{
    static uint8_t v[6 * 5 * 4];
    memset(v, 0, sizeof v);
    for (int z = 1; z <= 2; z++)
        for (int y = 1; y <= 2; y++)
            for (int x = 1; x <= 4; x++) v[(z * 5 + y) * 6 + x] = x <= 2 ? 3 : 7;
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    o.raw_dims = (bvox_dims){6, 5, 4};
    o.raw_dtype = BVOX_DT_U8;
    bvox_labelset *set = NULL;
    return bvox_labels_read_memory(v, sizeof v, "t", &o, 0, &set) ? NULL : set;
}

TEST(labels_in_table_colours)
{
    bvox_labelset *set = small_labels();
    CHECK(set);
    CHECK_EQ(set->n, 2);
    const char *lut = "3 Left 255 0 0 0\n7 Right 0 255 0 0\n";
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_parse(lut, strlen(lut), "lut", &t));
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    bvox_image *img;
    CHECK_OK(bvox_render_labels(set, t, &o, &img));
    const uint8_t *l3 = px(img, 1, 1), *l7 = px(img, 4, 2), *bg = px(img, 0, 0);
    CHECK(l3[0] > 0 && l3[1] == 0 && l3[2] == 0);
    CHECK(l7[0] == 0 && l7[1] > 0 && l7[2] == 0);
    CHECK(is_rgb(bg, 0, 0, 0));
    bvox_image_destroy(img);
    /* no table: the palette, label 3 at hue 52.5 degrees (r > g > b > 0),
     * label 7 at 242.5 (b > r, g) */
    CHECK_OK(bvox_render_labels(set, NULL, &o, &img));
    l3 = px(img, 1, 1), l7 = px(img, 4, 2);
    CHECK(l3[0] > l3[1] && l3[1] > l3[2] && l3[2] > 0);
    CHECK(l7[2] > l7[0] && l7[2] > l7[1]);
    bvox_image_destroy(img);
    bvox_label_table_destroy(t);
    bvox_labelset_destroy(set);
    return 0;
}

/* Every hit of a box cut at z = 3 seen along +z is on the cut face: it takes
 * a lighter tone of the object's colour (200, 0, 0) -> (222, 102, 102), so
 * green appears; without the cut the red object has none. */
TEST(cut_face_in_lighter_colour)
{
    bvox_volume *v = box_volume((bvox_dims){10, 10, 8}, (bvox_box){2, 2, 0, 8, 8, 8});
    CHECK(v);
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    o.color_set = 1;
    o.color[0] = 200, o.color[1] = 0, o.color[2] = 0;
    bvox_image *img;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK(px(img, 5, 5)[0] > 0 && px(img, 5, 5)[1] == 0);
    bvox_image_destroy(img);
    o.cut = 1;
    o.plane[0] = 0, o.plane[1] = 0, o.plane[2] = 1, o.plane[3] = -3;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    const uint8_t *p = px(img, 5, 5);
    CHECK(p[1] > 0 && p[1] == p[2]);
    CHECK_NEAR((double)p[0] / p[1], 222.0 / 102.0, 0.05);
    bvox_image_destroy(img);
    bvox_volume_destroy(v);
    return 0;
}

/* ---- goldens: the specimen from the iso view at 128 x 128, compared pixel
 * by pixel (mean absolute difference at most 1, no sample off by more than
 * 24: a moved bar, letter or edge fails). BVOX_UPDATE_GOLDEN=1 rewrites them
 * and fails (harness.h). */
static int compare_golden(bvox_image *img, const char *name)
{
    return harness_golden_compare(img, name, 1.0, 24);
}

static bvox_render_opts iso_opts(void)
{
    bvox_render_opts o = bvox_render_opts_default();
    bvox_render_parse_view("iso", &o);
    o.proj.width = o.proj.height = 128;
    o.shade = BVOX_SHADE_SMOOTH;
    return o;
}

static int golden_specimen(const char *name, const bvox_render_opts *o)
{
    bvox_volume *v;
    CHECK_OK(bvox_demo_specimen(&v));
    bvox_image *img;
    CHECK_OK(bvox_render(v, o, &img, NULL));
    bvox_volume_destroy(v);
    CHECK_EQ(img->channels, 3);
    return compare_golden(img, name);
}

TEST(golden_scale_bar)
{
    bvox_render_opts o = iso_opts();
    o.scale_bar = 1;
    return golden_specimen("annot_scale_bar", &o);
}
TEST(golden_axes)
{
    bvox_render_opts o = iso_opts();
    o.axes = 1;
    return golden_specimen("annot_axes", &o);
}
TEST(golden_title)
{
    bvox_render_opts o = iso_opts();
    o.title = "Specimen";
    return golden_specimen("annot_title", &o);
}
TEST(golden_background)
{
    bvox_render_opts o = iso_opts();
    o.background[0] = 240, o.background[1] = 240, o.background[2] = 232;
    return golden_specimen("annot_background", &o);
}
TEST(golden_color_cut)
{
    bvox_render_opts o = iso_opts();
    o.color_set = 1;
    o.color[0] = 230, o.color[1] = 140, o.color[2] = 60;
    o.cut = 1;
    o.plane[0] = 1, o.plane[1] = 0, o.plane[2] = 0, o.plane[3] = -1300; /* um */
    o.keep_above = 0;
    return golden_specimen("annot_color_cut", &o);
}

/* Two objects: the specimen's halves either side of x = 1280 um (voxel 128). */
TEST(golden_objects)
{
    bvox_volume *a, *b;
    CHECK_OK(bvox_demo_specimen(&a));
    CHECK_OK(bvox_volume_copy(a, &b));
    CHECK_OK(bvox_cut_plane(a, 1, 0, 0, -1280, 0, NULL));
    CHECK_OK(bvox_cut_plane(b, 1, 0, 0, -1280, 1, NULL));
    const bvox_volume *vols[2] = {a, b};
    const uint8_t colors[2][3] = {{255, 0, 0}, {0, 255, 136}};
    bvox_render_opts o = iso_opts();
    bvox_image *img;
    CHECK_OK(bvox_render_objects(vols, colors, 2, &o, &img));
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return compare_golden(img, "annot_objects");
}

/* A label volume of three balls (labels 1, 2, 5) in the default palette. */
TEST(golden_labels)
{
    enum { N = 40 };
    static uint8_t v[N * N * N];
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                int d1 = (x - 13) * (x - 13) + (y - 20) * (y - 20) + (z - 20) * (z - 20);
                int d2 = (x - 27) * (x - 27) + (y - 20) * (y - 20) + (z - 20) * (z - 20);
                int d5 = (x - 20) * (x - 20) + (y - 20) * (y - 20) + (z - 31) * (z - 31);
                v[(z * N + y) * N + x] = d5 < 36 ? 5 : d1 < 81 ? 1 : d2 < 81 ? 2 : 0;
            }
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    ro.format = "raw";
    ro.raw_dims = (bvox_dims){N, N, N};
    ro.raw_dtype = BVOX_DT_U8;
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(v, sizeof v, "balls", &ro, 0, &set));
    CHECK_EQ(set->n, 3);
    bvox_render_opts o = iso_opts();
    bvox_image *img;
    CHECK_OK(bvox_render_labels(set, NULL, &o, &img));
    bvox_labelset_destroy(set);
    return compare_golden(img, "annot_labels");
}

