/* test_render_pipeline.c — bvox_render end to end: it equals the stages run
 * by hand (cast, table, shade, zoom, average, filter); the depth map's
 * values; view names and the isometric frames; the cut face of Picture 3
 * (where it must be, how it is lit, and for projections within a voxel);
 * stereo pairs and anaglyph channels against the single eye images; the
 * sheet's layout; turntable frames; bad options and allocation failures. */
#include "harness.h"
#include "internal.h"
#include "render/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bvox_volume *box_volume(int n, bvox_box b)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    bvox_volume_fill_box(v, b, 1);
    return v;
}

static int same_image(const bvox_image *a, const bvox_image *b)
{
    CHECK(a && b);
    CHECK_EQ(a->width, b->width);
    CHECK_EQ(a->height, b->height);
    CHECK_EQ(a->channels, b->channels);
    CHECK_EQ(a->bits, b->bits);
    size_t n = (size_t)a->width * a->height * a->channels;
    CHECK(!memcmp(a->pixels, b->pixels, n));
    return 0;
}

/* bvox_render of an axis view is the pipeline run by hand. */
TEST(axis_view_equals_stages)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){13, 9, 70}, &v));
    for (int i = 0; i < 300; i++) {
        uint64_t r = harness_rand();
        bvox_volume_set(v, (int)(r % 13), (int)(r >> 8) % 9, (int)((r >> 16) % 70), 1);
    }
    bvox_render_opts o = bvox_render_opts_default();
    o.view = BVOX_VIEW_NEG_X;
    bvox_preimage *cast, *pre;
    CHECK_OK(bvox_cast_axis(v, BVOX_VIEW_NEG_X, &cast));
    bvox_image *img, *want, *tmp;
    bvox_lut lut;

    o.shade = BVOX_SHADE_BINARY;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    CHECK_EQ(pre->width, cast->width);
    CHECK(!memcmp(pre->depth, cast->depth, sizeof(int32_t) * 9 * 70));
    CHECK(!memcmp(pre->code, cast->code, 9 * 70));
    CHECK_OK(bvox_lut_light(cast, &o.light, &lut));
    CHECK_OK(bvox_shade(cast, &lut, &want));
    CHECK_EQ(same_image(img, want), 0);
    bvox_image_destroy(img), bvox_image_destroy(want), bvox_preimage_destroy(pre);

    /* depth, zoom 2, average, high pass: in that order */
    o.shade = BVOX_SHADE_DEPTH;
    o.zoom = 2, o.average = 1, o.filter = BVOX_FILTER_HIGHPASS;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_OK(bvox_shade_depth(cast, &o.depth, &want));
    CHECK_OK(bvox_image_zoom(want, 2, &tmp));
    bvox_image_destroy(want);
    CHECK_OK(bvox_image_zoom2_average(tmp, &want));
    bvox_image_destroy(tmp);
    CHECK_OK(bvox_image_filter(want, BVOX_FILTER_HIGHPASS, &tmp));
    CHECK_EQ(same_image(img, tmp), 0);
    CHECK_EQ(img->width, 9 * 4);
    bvox_image_destroy(img), bvox_image_destroy(want), bvox_image_destroy(tmp);

    /* gradient: Sobel over the depth map */
    o = bvox_render_opts_default();
    o.view = BVOX_VIEW_NEG_X;
    o.shade = BVOX_SHADE_GRADIENT;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_OK(bvox_shade_gradient(cast, BVOX_GRADIENT_SOBEL, &o.light, &want));
    CHECK_EQ(same_image(img, want), 0);
    bvox_image_destroy(img), bvox_image_destroy(want);

    /* binary + depth: the cue-free table times 1 - k t (k = 0.5 by default) */
    o.shade = BVOX_SHADE_BINARY_DEPTH;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    bvox_light l = o.light;
    l.depth_cue = 0;
    CHECK_OK(bvox_lut_light(cast, &l, &lut));
    for (size_t i = 0; i < 9 * 70; i++) {
        int32_t d = cast->depth[i];
        int w = d < 0 ? 0 : (int)(lut.value[cast->code[i]] * (1.0 - 0.5 * ((double)d / 12)) + 0.5);
        CHECK_EQ(img->pixels[i], w);
    }
    bvox_image_destroy(img);
    bvox_preimage_destroy(cast);
    bvox_volume_destroy(v);
    return 0;
}

TEST(depth_map_values)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 2, 5}, &v));
    bvox_volume_set(v, 0, 0, 0, 1);
    bvox_volume_set(v, 2, 1, 3, 1);
    bvox_volume_set(v, 2, 1, 4, 1);
    bvox_render_opts o = bvox_render_opts_default();
    bvox_image *img, *d;
    bvox_preimage *pre;
    o.view = BVOX_VIEW_POS_Z;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    CHECK_OK(bvox_preimage_depth_map(pre, &d));
    CHECK_EQ(d->bits, 16);
    const uint16_t want_pz[6] = {1, 0, 0, 0, 0, 4}; /* (x, y): column x, row y */
    for (int i = 0; i < 6; i++) CHECK_EQ(d->pixels16[i], want_pz[i]);
    bvox_image_destroy(img), bvox_image_destroy(d), bvox_preimage_destroy(pre);
    o.view = BVOX_VIEW_NEG_Z; /* rays enter at z = 4 */
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    CHECK_OK(bvox_preimage_depth_map(pre, &d));
    const uint16_t want_nz[6] = {5, 0, 0, 0, 0, 1};
    for (int i = 0; i < 6; i++) CHECK_EQ(d->pixels16[i], want_nz[i]);
    bvox_image_destroy(img), bvox_image_destroy(d), bvox_preimage_destroy(pre);
    CHECK_STATUS(bvox_preimage_depth_map(NULL, &d), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(view_names_and_iso_frames)
{
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("-y", &o));
    CHECK(o.axis_view && o.view == BVOX_VIEW_NEG_Y);
    CHECK_OK(bvox_render_parse_view("30,-20.5", &o));
    CHECK(!o.axis_view && !o.proj.use_matrix);
    CHECK_NEAR(o.proj.azimuth, 30, 0);
    CHECK_NEAR(o.proj.elevation, -20.5, 0);
    const char *names[] = {"iso", "iso+x+y+z", "iso-x+y-z", "iso+x-y-z"};
    const int from[][3] = {{1, 1, 1}, {1, 1, 1}, {-1, 1, -1}, {1, -1, -1}};
    for (int k = 0; k < 4; k++) {
        CHECK_OK(bvox_render_parse_view(names[k], &o));
        CHECK(!o.axis_view && o.proj.use_matrix);
        const double *r = o.proj.matrix, *dn = r + 3, *vw = r + 6;
        for (int a = 0; a < 3; a++) CHECK_NEAR(vw[a], -from[k][a] / sqrt(3.0), 1e-12);
        CHECK(dn[2] < 0); /* z up on the screen */
        CHECK_NEAR(dn[0] * vw[0] + dn[1] * vw[1] + dn[2] * vw[2], 0, 1e-12);
        /* right x down = view: a true (unmirrored) picture */
        CHECK_NEAR(r[1] * dn[2] - r[2] * dn[1], vw[0], 1e-12);
        CHECK_NEAR(r[2] * dn[0] - r[0] * dn[2], vw[1], 1e-12);
        CHECK_NEAR(r[0] * dn[1] - r[1] * dn[0], vw[2], 1e-12);
    }
    const char *bad[] = {"", "iso+x", "iso+y+x+z", "isoz", "iso+x+y+z+", "1,2,3", "+w", "a,b", "1,", "nan,0"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_STATUS(bvox_render_parse_view(bad[k], &o), BVOX_EINVAL);
    CHECK_EQ(bvox_shade_mode_parse("binary+depth"), BVOX_SHADE_BINARY_DEPTH);
    CHECK_EQ(bvox_shade_mode_parse("phong"), -1);
    CHECK(!strcmp(bvox_shade_mode_name(BVOX_SHADE_GRADIENT), "gradient"));
    return 0;
}

/* In the iso view (z up) a voxel high in z lands higher in the image. */
TEST(iso_view_z_is_up)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){20, 20, 20}, &v));
    bvox_volume_fill_box(v, (bvox_box){9, 9, 0, 11, 11, 3}, 1);   /* low */
    bvox_volume_fill_box(v, (bvox_box){9, 9, 17, 11, 11, 20}, 1); /* high */
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("iso", &o));
    o.proj.width = o.proj.height = 64;
    bvox_preimage *pre;
    bvox_image *img;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    /* the image rows of the two blobs, from their hit points' z */
    double top_z = 0, bottom_z = 0;
    int top_n = 0, bottom_n = 0;
    for (int r = 0; r < 64; r++)
        for (int c = 0; c < 64; c++) {
            int32_t d = pre->depth[r * 64 + c];
            if (d < 0) continue;
            double z = pre->origin[2] + c * pre->pixel_size[0] * pre->eye[2] +
                       r * pre->pixel_size[1] * pre->eye[5] + d * pre->depth_step * pre->eye[8];
            if (r < 32) top_z += z, top_n++;
            else bottom_z += z, bottom_n++;
        }
    CHECK(top_n > 0 && bottom_n > 0);
    CHECK(top_z / top_n > 15 && bottom_z / bottom_n < 5);
    bvox_image_destroy(img), bvox_preimage_destroy(pre), bvox_volume_destroy(v);
    return 0;
}

/* The cut of Picture 3 seen along +z: box 2..13, plane x + z = 9.5, keep
 * above. Columns x >= 8 keep their top face (z = 2); columns 2..7 are hit at
 * z = 10 - x, through a face the cut exposed. */
TEST(cut_face_axis_view)
{
    bvox_volume *v = box_volume(16, (bvox_box){2, 2, 2, 14, 14, 14});
    CHECK(v != NULL);
    const int64_t before = bvox_volume_count(v);
    bvox_render_opts o = bvox_render_opts_default();
    o.shade = BVOX_SHADE_BINARY;
    o.light = (bvox_light){0, 90, 0.2, 0.8, 0, 1, 0, 0}; /* from the viewer, no specular */
    o.cut = 1;
    o.plane[0] = 1, o.plane[1] = 0, o.plane[2] = 1, o.plane[3] = -9.5;
    o.keep_above = 1;
    o.cut_color[0] = 255, o.cut_color[1] = 0, o.cut_color[2] = 0;
    bvox_image *img;
    bvox_preimage *pre;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    CHECK_EQ(bvox_volume_count(v), before); /* the input is not cut */
    CHECK_EQ(img->channels, 3);
    /* the cut face: normal -(1, 0, 1)/sqrt 2, lit from the viewer */
    const int lit = (int)(255 * (0.2 + 0.8 / sqrt(2.0)) + 0.5);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            const uint8_t *p = img->pixels + 3 * (y * 16 + x);
            int inside = x >= 2 && x < 14 && y >= 2 && y < 14;
            if (!inside) {
                CHECK(p[0] == 0 && p[1] == 0 && p[2] == 0);
                continue;
            }
            if (x <= 7) {
                CHECK_EQ(pre->depth[y * 16 + x], 10 - x);
                CHECK_EQ(p[0], lit);
                CHECK(p[1] == 0 && p[2] == 0);
            } else {
                CHECK_EQ(pre->depth[y * 16 + x], 2);
                CHECK(p[0] == p[1] && p[1] == p[2]); /* gray surface */
                if (x >= 9 && x <= 12 && y >= 3 && y <= 12) CHECK_EQ(p[0], 255); /* faces us */
            }
        }
    bvox_image_destroy(img), bvox_preimage_destroy(pre);
    /* keep below: the other half, seen along -x (from x = 15) through its
     * cut face, everything else is its original surface */
    o.keep_above = 0;
    o.view = BVOX_VIEW_NEG_X;
    o.shade = BVOX_SHADE_DEPTH;
    o.cut_color[0] = 0, o.cut_color[1] = 255, o.cut_color[2] = 0;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    /* pixel (column y, row z): hit where x + z < 9.5 with x < 14, x >= 2 */
    for (int z = 0; z < 16; z++)
        for (int y = 0; y < 16; y++) {
            const uint8_t *p = img->pixels + 3 * (z * 16 + y);
            int32_t d = pre->depth[z * 16 + y];
            if (y < 2 || y >= 14 || z < 2 || z > 7) {
                CHECK_EQ(d, -1);
                continue;
            }
            int xhit = 9 - z; /* the largest x with x + z < 9.5 */
            CHECK_EQ(d, 15 - xhit);
            CHECK(p[0] == 0 && p[2] == 0 && p[1] > 0); /* every hit is on the cut face */
        }
    bvox_image_destroy(img), bvox_preimage_destroy(pre);
    bvox_volume_destroy(v);
    return 0;
}

/* A projection of the same cut: tinted pixels lie at the cut (x <= 8 by
 * their hit point), untinted ones on the top face (x >= 7), within a voxel. */
TEST(cut_face_projection)
{
    bvox_volume *v = box_volume(16, (bvox_box){2, 2, 2, 14, 14, 14});
    CHECK(v != NULL);
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("10,15", &o));
    o.proj.width = o.proj.height = 96;
    o.cut = 1;
    o.plane[0] = 1, o.plane[2] = 1, o.plane[3] = -9.5;
    o.cut_color[0] = 255, o.cut_color[1] = 0, o.cut_color[2] = 0;
    bvox_image *img;
    bvox_preimage *pre;
    CHECK_OK(bvox_render(v, &o, &img, &pre));
    int cut = 0, surface = 0;
    for (int r = 0; r < 96; r++)
        for (int c = 0; c < 96; c++) {
            int32_t d = pre->depth[r * 96 + c];
            if (d < 0) continue;
            const uint8_t *p = img->pixels + 3 * (r * 96 + c);
            double x = pre->origin[0] + c * pre->pixel_size[0] * pre->eye[0] +
                       r * pre->pixel_size[1] * pre->eye[3] + (d + 0.5) * pre->depth_step * pre->eye[6];
            double z = pre->origin[2] + c * pre->pixel_size[0] * pre->eye[2] +
                       r * pre->pixel_size[1] * pre->eye[5] + (d + 0.5) * pre->depth_step * pre->eye[8];
            if (p[1] == 0 && p[0] > 0) {
                cut++;
                CHECK(x + z < 9.5 + 2.5); /* near the plane */
            } else {
                CHECK(p[0] == p[1] && p[1] == p[2]);
                if (z < 2.0) CHECK(x > 6.5); /* the top face: only where the cut left it */
                surface++;
            }
        }
    CHECK(cut > 500 && surface > 500);
    bvox_image_destroy(img), bvox_preimage_destroy(pre);
    bvox_volume_destroy(v);
    return 0;
}

/* The eye images of a stereo pair, rendered one by one. */
static int eyes(const bvox_volume *v, const bvox_render_opts *o, bvox_image **l, bvox_image **r)
{
    double f[9];
    CHECK_OK(bvox__opts_frame(o, f));
    for (int k = 0; k < 2; k++) {
        bvox_render_opts e = *o;
        e.stereo = BVOX_STEREO_NONE;
        e.axis_view = 0;
        e.proj.use_matrix = 1;
        memcpy(e.proj.matrix, f, sizeof f);
        bvox__frame_turn(e.proj.matrix, k ? -o->stereo_angle : o->stereo_angle);
        CHECK_OK(bvox_render(v, &e, k ? r : l, NULL));
    }
    return 0;
}

TEST(stereo_pairs)
{
    bvox_volume *v;
    CHECK_OK(bvox_demo_specimen(&v));
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("40,0", &o));
    o.proj.width = 96, o.proj.height = 80;
    bvox_image *l, *r, *img;
    CHECK_EQ(eyes(v, &o, &l, &r), 0);
    CHECK(memcmp(l->pixels, r->pixels, 96 * 80)); /* the eyes differ */
    /* side by side: left eye's image on the left */
    o.stereo = BVOX_STEREO_SBS;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_EQ(img->width, 192);
    CHECK_EQ(img->height, 80);
    CHECK_EQ(img->channels, 1);
    for (int y = 0; y < 80; y++) {
        CHECK(!memcmp(img->pixels + y * 192, l->pixels + y * 96, 96));
        CHECK(!memcmp(img->pixels + y * 192 + 96, r->pixels + y * 96, 96));
    }
    bvox_image_destroy(img);
    /* anaglyph: red = left, green = blue = right */
    o.stereo = BVOX_STEREO_ANAGLYPH;
    CHECK_OK(bvox_render(v, &o, &img, NULL));
    CHECK_EQ(img->channels, 3);
    CHECK_EQ(img->width, 96);
    for (int i = 0; i < 96 * 80; i++) {
        CHECK_EQ(img->pixels[3 * i], l->pixels[i]);
        CHECK_EQ(img->pixels[3 * i + 1], r->pixels[i]);
        CHECK_EQ(img->pixels[3 * i + 2], r->pixels[i]);
    }
    bvox_image_destroy(img);
    /* at elevation 0 the left eye is azimuth + 3 degrees (nearly all pixels
     * equal: another route through floating point) */
    bvox_render_opts a = o;
    a.stereo = BVOX_STEREO_NONE;
    a.proj.azimuth = 43;
    CHECK_OK(bvox_render(v, &a, &img, NULL));
    int differ = 0;
    for (int i = 0; i < 96 * 80; i++) differ += abs(img->pixels[i] - l->pixels[i]) > 2;
    CHECK(differ < 96 * 80 / 100);
    bvox_image_destroy(img);
    bvox_image_destroy(l), bvox_image_destroy(r);
    bvox_volume_destroy(v);
    return 0;
}

TEST(sheet_layout)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){12, 10, 14}, &v));
    bvox_volume_fill_box(v, (bvox_box){2, 1, 3, 9, 6, 13}, 1);
    bvox_volume_fill_box(v, (bvox_box){0, 0, 0, 3, 3, 3}, 1);
    bvox_render_opts o = bvox_render_opts_default();
    o.proj.width = 40, o.proj.height = 30;
    bvox_image *sheet;
    CHECK_OK(bvox_render_sheet(v, &o, &sheet));
    CHECK_EQ(sheet->width, 80);
    CHECK_EQ(sheet->height, 60);
    const char *names[4] = {"+z", "+x", "-y", "iso"};
    for (int k = 0; k < 4; k++) {
        bvox_render_opts c = o;
        CHECK_OK(bvox_render_parse_view(names[k], &c));
        if (c.axis_view) {
            bvox__axis_frame(c.view, c.proj.matrix);
            c.axis_view = 0;
            c.proj.use_matrix = 1;
        }
        bvox_image *cell;
        CHECK_OK(bvox_render(v, &c, &cell, NULL));
        int lit = 0;
        for (int y = 0; y < 30; y++) {
            const uint8_t *s = sheet->pixels + ((k / 2) * 30 + y) * 80 + (k % 2) * 40;
            CHECK(!memcmp(s, cell->pixels + y * 40, 40));
            for (int x = 0; x < 40; x++) lit += s[x] != 0;
        }
        CHECK(lit > 100);
        bvox_image_destroy(cell);
    }
    bvox_image_destroy(sheet);
    o.stereo = BVOX_STEREO_SBS;
    CHECK_STATUS(bvox_render_sheet(v, &o, &sheet), BVOX_EINVAL);
    CHECK(sheet == NULL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(turntable_views)
{
    bvox_render_opts o = bvox_render_opts_default(), f;
    CHECK_OK(bvox_render_parse_view("iso", &o));
    CHECK_OK(bvox_turntable_view(&o, 0, 8, &f));
    for (int i = 0; i < 9; i++) CHECK_NEAR(f.proj.matrix[i], o.proj.matrix[i], 1e-12);
    /* half a turn about z (the axis nearest the vertical): from (-1, -1, +1) */
    CHECK_OK(bvox_turntable_view(&o, 4, 8, &f));
    const double r3 = 1 / sqrt(3.0);
    CHECK_NEAR(f.proj.matrix[6], r3, 1e-12);
    CHECK_NEAR(f.proj.matrix[7], r3, 1e-12);
    CHECK_NEAR(f.proj.matrix[8], -r3, 1e-12);
    CHECK_NEAR(f.proj.matrix[5], o.proj.matrix[5], 1e-12); /* down keeps its z */
    /* an axis view turns about its vertical image axis: +z (down = +y) */
    o = bvox_render_opts_default();
    CHECK_OK(bvox_turntable_view(&o, 1, 4, &f));
    CHECK(!f.axis_view && f.proj.use_matrix);
    CHECK_NEAR(fabs(f.proj.matrix[6]), 1, 1e-12); /* a quarter turn: along x */
    CHECK_NEAR(f.proj.matrix[4], 1, 1e-12);
    CHECK_STATUS(bvox_turntable_view(&o, 4, 4, &f), BVOX_EINVAL);
    CHECK_STATUS(bvox_turntable_view(&o, 0, 0, &f), BVOX_EINVAL);
    return 0;
}

TEST(bad_options)
{
    bvox_volume *v = box_volume(8, (bvox_box){1, 1, 1, 7, 7, 7});
    CHECK(v != NULL);
    bvox_image *img = (bvox_image *)1;
    bvox_render_opts o = bvox_render_opts_default();
    o.zoom = 3;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    CHECK(img == NULL);
    o = bvox_render_opts_default();
    o.filter = 4;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    o = bvox_render_opts_default();
    o.cut = 1;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL); /* zero normal */
    o.plane[0] = NAN;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    o = bvox_render_opts_default();
    o.stereo = BVOX_STEREO_SBS, o.stereo_angle = 90;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    o = bvox_render_opts_default();
    o.light.depth_cue = 2;
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    o.light.depth_cue = 0;
    o.axis_view = 0, o.proj.use_matrix = 1;
    memset(o.proj.matrix, 0, sizeof o.proj.matrix);
    CHECK_STATUS(bvox_render(v, &o, &img, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_render(NULL, &o, &img, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_render(v, NULL, &img, NULL), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}

/* Every allocation failing in turn: a clean status, nothing leaks (ASan). */
TEST(allocation_failures)
{
    bvox_volume *v = box_volume(20, (bvox_box){3, 4, 5, 15, 16, 17});
    CHECK(v != NULL);
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("20,30", &o));
    o.proj.width = o.proj.height = 32;
    o.cut = 1, o.plane[0] = 1, o.plane[3] = -9;
    o.stereo = BVOX_STEREO_ANAGLYPH;
    o.zoom = 2, o.average = 1, o.filter = BVOX_FILTER_SMOOTH;
    int ok = 0;
    for (long n = 1; n < 200 && !ok; n++) {
        bvox_image *img = NULL;
        bvox_preimage *pre = NULL;
        bvox__alloc_fail_after(n);
        bvox_status st = bvox_render(v, &o, &img, &pre);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            ok = 1;
            CHECK_EQ(img->width, 128);
        } else {
            CHECK(st == BVOX_ENOMEM);
            CHECK(img == NULL && pre == NULL);
        }
        bvox_image_destroy(img);
        bvox_preimage_destroy(pre);
    }
    CHECK(ok);
    bvox_volume_destroy(v);
    return 0;
}
