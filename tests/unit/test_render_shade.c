/* test_render_shade.c — lookup-table shading: depth tables, binary gradient
 * (Phong) tables from hand-computed normals and lights, a light change that
 * reshades one pre-image with no re-cast (the volume is gone by then),
 * full-depth shading, gradient shading from the depth map on a wedge whose
 * slope is known, and a shaded sphere written as PNG. */
#include "harness.h"
#include "render/render.h"

#include <math.h>
#include <string.h>

#define IDX(nx, ny, nz) (((nx) + 1) * 9 + ((ny) + 1) * 3 + ((nz) + 1))

TEST(lut_depth)
{
    bvox_depth_shading s = BVOX_DEPTH_SHADING_INIT;
    s.near_value = 255, s.far_value = 40, s.background = 7;
    bvox_lut lut;
    CHECK_OK(bvox_lut_depth(&s, &lut));
    CHECK_EQ(lut.value[IDX(0, 0, -1)], 255);               /* cue 0 */
    CHECK_EQ(lut.value[IDX(1, 1, 1) | 7 << 5], 40);         /* cue 7 */
    CHECK_EQ(lut.value[5 | 3 << 5], 163);                   /* 255 - 215 * 3/7 = 162.9 */
    CHECK_EQ(lut.value[BVOX_CODE_BACKGROUND], 7);
    CHECK_EQ(lut.value[27 | 2 << 5], 7);
    s.curve = BVOX_DEPTH_EXP, s.decay = 2;
    CHECK_OK(bvox_lut_depth(&s, &lut));
    CHECK_EQ(lut.value[0], 255);
    CHECK_EQ(lut.value[7 << 5], (int)(40 + 215 * exp(-2.0) + 0.5)); /* 69 */
    s.decay = 0;
    CHECK_STATUS(bvox_lut_depth(&s, &lut), BVOX_EINVAL);
    s.curve = BVOX_DEPTH_LINEAR, s.near_value = 300;
    CHECK_STATUS(bvox_lut_depth(&s, &lut), BVOX_EINVAL);
    return 0;
}

static int cast_box(bvox_preimage **p, double sz)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){10, 10, 10}, &vol));
    CHECK_OK(bvox_volume_set_spacing(vol, 1, 1, sz, NULL));
    bvox_volume_fill_box(vol, (bvox_box){2, 2, 2, 8, 8, 8}, 1);
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, p));
    bvox_volume_destroy(vol);
    return 0;
}

TEST(lut_light)
{
    bvox_preimage *p;
    CHECK_EQ(cast_box(&p, 1.0), 0);
    bvox_light l = BVOX_LIGHT_INIT;
    bvox_lut lut;
    /* headlight: a face towards the viewer gets everything, clamped */
    l.azimuth = 0, l.elevation = 90;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    CHECK_EQ(lut.value[IDX(0, 0, -1)], 255);
    CHECK_EQ(lut.value[BVOX_NORMAL_NONE], 255); /* no normal faces the viewer */
    CHECK_EQ(lut.value[BVOX_CODE_BACKGROUND], 0);
    /* light from the right (image +x = volume +x in the +z view) */
    l.elevation = 0, l.ambient = 0.2, l.diffuse = 0.6, l.specular = 0;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    CHECK_EQ(lut.value[IDX(1, 0, 0)], 204);   /* (0.2 + 0.6) * 255 */
    CHECK_EQ(lut.value[IDX(-1, 0, 0)], 51);   /* ambient only */
    CHECK_EQ(lut.value[IDX(1, 0, -1)], 159);  /* 0.2 + 0.6 / sqrt 2 = 0.624 */
    CHECK_EQ(lut.value[IDX(0, 0, -1)], 51);   /* grazing: N.L = 0 */
    /* light from the top of the image: image up is volume -y */
    l.azimuth = 90;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    CHECK_EQ(lut.value[IDX(0, -1, 0)], 204);
    CHECK_EQ(lut.value[IDX(0, 1, 0)], 51);
    /* depth cue: cue 7 at depth_cue 0.5 halves */
    l.azimuth = 0, l.depth_cue = 0.5;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    CHECK_EQ(lut.value[IDX(1, 0, 0) | 7 << 5], 102);
    CHECK_EQ(lut.value[IDX(1, 0, 0)], 204);
    l.depth_cue = 2;
    CHECK_STATUS(bvox_lut_light(p, &l, &lut), BVOX_EINVAL);
    l.depth_cue = 0, l.ambient = NAN;
    CHECK_STATUS(bvox_lut_light(p, &l, &lut), BVOX_EINVAL);
    bvox_preimage_destroy(p);

    /* thick sections: spacing (1, 1, 4) turns the (1, 0, -1) normal towards x:
     * (1, 0, 1/4) normalised, N.L = 0.970 -> (0.2 + 0.582) * 255 = 199.4 */
    CHECK_EQ(cast_box(&p, 4.0), 0);
    l = (bvox_light)BVOX_LIGHT_INIT;
    l.azimuth = 0, l.elevation = 0, l.ambient = 0.2, l.diffuse = 0.6, l.specular = 0;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    CHECK_EQ(lut.value[IDX(1, 0, -1)], 199);
    bvox_preimage_destroy(p);
    return 0;
}

TEST(light_change_reshades_without_recast)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){40, 40, 40}, &vol));
    bvox_shape s = {BVOX_SHAPE_SPHERE, {19.5, 19.5, 19.5}, {0, 0, 0}, {0, 0, 0}, 15, 0, 0};
    CHECK_OK(bvox_shape_draw(vol, &s, BVOX_CSG_UNION));
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, &p));
    bvox_volume_destroy(vol); /* shading cannot re-cast: there is no volume */
    long casts = bvox__render_cast_count();
    bvox_light l1 = BVOX_LIGHT_INIT, l2 = BVOX_LIGHT_INIT;
    l2.azimuth = -45;
    bvox_lut t1, t2;
    CHECK_OK(bvox_lut_light(p, &l1, &t1));
    CHECK_OK(bvox_lut_light(p, &l2, &t2));
    bvox_image *a, *b;
    CHECK_OK(bvox_shade(p, &t1, &a));
    size_t used = bvox_memory_in_use();
    CHECK_OK(bvox_image_create(40, 40, 1, 8, &b));
    size_t used2 = bvox_memory_in_use();
    CHECK_OK(bvox_shade_into(p, &t2, b));
    CHECK_EQ(bvox_memory_in_use(), used2); /* reshading allocates nothing */
    CHECK(used2 > used);
    CHECK_EQ(bvox__render_cast_count(), casts);
    int differ = 0;
    for (int i = 0; i < 40 * 40; i++) {
        CHECK_EQ(a->pixels[i], t1.value[p->code[i]]);
        CHECK_EQ(b->pixels[i], t2.value[p->code[i]]);
        differ += a->pixels[i] != b->pixels[i];
    }
    CHECK(differ > 100);
    /* upper left lit by l1 (from the upper left), lower right by l2 */
    CHECK(a->pixels[10 * 40 + 10] > a->pixels[29 * 40 + 29]);
    CHECK(b->pixels[10 * 40 + 10] < b->pixels[29 * 40 + 29]);
    bvox_image *wrong;
    CHECK_OK(bvox_image_create(41, 40, 1, 8, &wrong));
    CHECK_STATUS(bvox_shade_into(p, &t1, wrong), BVOX_EINVAL);
    bvox_image_destroy(wrong);
    bvox_image_destroy(a);
    bvox_image_destroy(b);
    bvox_preimage_destroy(p);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(shade_full_depth)
{
    bvox_preimage *p;
    CHECK_EQ(cast_box(&p, 1.0), 0);
    bvox_depth_shading s = BVOX_DEPTH_SHADING_INIT;
    s.near_value = 255, s.far_value = 40, s.background = 3;
    bvox_image *im;
    CHECK_OK(bvox_shade_depth(p, &s, &im));
    CHECK_EQ(im->pixels[5 * 10 + 5], 207); /* depth 2 of 0..9: 255 - 215 * 2/9 */
    CHECK_EQ(im->pixels[0], 3);
    bvox_image_destroy(im);
    bvox_preimage_destroy(p);
    return 0;
}

/* A wedge seen along +z: the surface depth is x * slope, so the depth
 * gradient is known exactly. */
static int wedge(double sz, bvox_preimage **p)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){16, 8, 40}, &vol));
    CHECK_OK(bvox_volume_set_spacing(vol, 1, 1, sz, NULL));
    for (int x = 0; x < 16; x++) bvox_volume_fill_box(vol, (bvox_box){x, 0, x, x + 1, 8, 40}, 1);
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, p));
    bvox_volume_destroy(vol);
    return 0;
}

TEST(shade_gradient_from_depth)
{
    bvox_light l = BVOX_LIGHT_INIT;
    l.azimuth = 0, l.elevation = 0, l.ambient = 0.2, l.diffuse = 0.6, l.specular = 0;
    for (int op = 0; op < 2; op++) {
        bvox_preimage *p;
        bvox_image *im;
        CHECK_EQ(wedge(1.0, &p), 0);
        CHECK_EQ(p->depth[3 * 16 + 5], 5);
        /* slope 1: normal (1, 0, 1)/sqrt 2 in (right, up, viewer) */
        CHECK_OK(bvox_shade_gradient(p, (bvox_gradient)op, &l, &im));
        for (int y = 1; y < 7; y++)
            for (int x = 1; x < 15; x++) CHECK_EQ(im->pixels[y * 16 + x], 159);
        /* at the left edge the difference is one-sided: (1 - 0) / 2 */
        CHECK_EQ(im->pixels[3 * 16], (int)(255 * (0.2 + 0.6 * 0.5 / sqrt(1.25)) + 0.5));
        bvox_image_destroy(im);
        bvox_preimage_destroy(p);
        /* slope 2 in physical units: (2, 0, 1)/sqrt 5 -> 187.8 */
        CHECK_EQ(wedge(2.0, &p), 0);
        CHECK_OK(bvox_shade_gradient(p, (bvox_gradient)op, &l, &im));
        CHECK_EQ(im->pixels[3 * 16 + 7], 188);
        bvox_image_destroy(im);
        bvox_preimage_destroy(p);
    }
    return 0;
}

TEST(shaded_sphere_png)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){96, 96, 96}, &vol));
    bvox_shape s = {BVOX_SHAPE_SPHERE, {47.5, 47.5, 47.5}, {0, 0, 0}, {0, 0, 0}, 40, 0, 0};
    CHECK_OK(bvox_shape_draw(vol, &s, BVOX_CSG_UNION));
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, &p));
    bvox_volume_destroy(vol);
    bvox_light l = BVOX_LIGHT_INIT;
    bvox_lut lut;
    CHECK_OK(bvox_lut_light(p, &l, &lut));
    bvox_image *im, *back;
    CHECK_OK(bvox_shade(p, &lut, &im));
    const char *path = harness_path("sphere.png");
    CHECK_OK(bvox_image_write_png(im, path));
    CHECK_OK(bvox_image_read_png(path, &back));
    CHECK(memcmp(back->pixels, im->pixels, 96 * 96) == 0);
    /* lit from the upper left: that quadrant is brighter than the lower right;
     * the centre faces the viewer; the corners are background */
    long ul = 0, lr = 0;
    for (int y = 20; y < 40; y++)
        for (int x = 20; x < 40; x++) {
            ul += im->pixels[y * 96 + x];
            lr += im->pixels[(y + 36) * 96 + x + 36];
        }
    CHECK(ul > lr + 20 * 20 * 40);
    CHECK_EQ(im->pixels[0], 0);
    CHECK(im->pixels[48 * 96 + 48] > 100);
    bvox_image_destroy(back);
    bvox_image_destroy(im);
    bvox_preimage_destroy(p);
    return 0;
}
