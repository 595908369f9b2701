/* test_render_mosaic.c — Picture 4, the data set as the frame buffer held
 * it: exact bytes of a hand-made volume, the three display tables and the
 * plane mask, the paper's 128^3 -> 512 x 512 layout, random volumes of
 * awkward sizes against a voxel-by-voxel reference, the paper's volume by
 * histogram (popcount of the bytes = voxel count), and bad options. */
#include "harness.h"
#include "internal.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

static int px(const bvox_image *im, int x, int y) { return im->pixels[(size_t)y * im->width + x]; }

/* 3 x 2 x 20: 3 sections (slices 0-7, 8-15, 16-19), a 2 x 2 grid, 6 x 4 pixels. */
static bvox_volume *hand_volume(void)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){3, 2, 20}, &v)) return NULL;
    bvox_volume_set(v, 0, 0, 0, 1);  /* section 0, pixel (0,0), bit 0 */
    bvox_volume_set(v, 1, 0, 3, 1);  /* section 0, pixel (1,0), bits 3 and 5: 40 */
    bvox_volume_set(v, 1, 0, 5, 1);
    bvox_volume_set(v, 2, 1, 9, 1);  /* section 1 (cell 1,0), pixel (2,1), bit 1 */
    bvox_volume_set(v, 0, 1, 16, 1); /* section 2 (cell 0,1), pixel (0,1), bits 0, 3 */
    bvox_volume_set(v, 0, 1, 19, 1);
    return v;
}

TEST(hand_volume_exact_bytes)
{
    bvox_volume *v = hand_volume();
    CHECK(v != NULL);
    bvox_mosaic_opts o = BVOX_MOSAIC_OPTS_INIT;
    o.display = BVOX_MOSAIC_BYTES;
    bvox_image *im;
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(im->width, 6);
    CHECK_EQ(im->height, 4);
    CHECK_EQ(im->channels, 1);
    CHECK_EQ(im->bits, 8);
    const uint8_t want[4][6] = {{1, 40, 0, 0, 0, 0},
                                {0, 0, 0, 0, 0, 2},
                                {0, 0, 0, 0, 0, 0},
                                {9, 0, 0, 0, 0, 0}};
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 6; x++) CHECK_EQ(px(im, x, y), want[y][x]);
    bvox_image_destroy(im);

    /* one section per row */
    o.columns = 1;
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(im->width, 3);
    CHECK_EQ(im->height, 6);
    CHECK_EQ(px(im, 1, 0), 40);
    CHECK_EQ(px(im, 2, 3), 2);
    CHECK_EQ(px(im, 0, 5), 9);
    bvox_image_destroy(im);
    bvox_volume_destroy(v);
    return 0;
}

TEST(plane_mask_and_displays)
{
    bvox_volume *v = hand_volume();
    CHECK(v != NULL);
    bvox_image *im;
    /* bit 3 only, "any": white where slice 8s+3 is set */
    bvox_mosaic_opts o = {0x08, BVOX_MOSAIC_ANY, 0};
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(px(im, 1, 0), 255); /* 40 & 8 */
    CHECK_EQ(px(im, 0, 3), 255); /* 9 & 8 */
    CHECK_EQ(px(im, 0, 0), 0);
    CHECK_EQ(px(im, 5, 1), 0);
    bvox_image_destroy(im);
    /* bits 0, 3, 5 (3 planes), "count": 255 * set / 3, rounded */
    o = (bvox_mosaic_opts){0x29, BVOX_MOSAIC_COUNT, 0};
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(px(im, 0, 0), 85);  /* bit 0 */
    CHECK_EQ(px(im, 1, 0), 170); /* bits 3, 5 */
    CHECK_EQ(px(im, 5, 1), 0);   /* bit 1 is not selected */
    CHECK_EQ(px(im, 0, 3), 170); /* bits 0, 3 */
    bvox_image_destroy(im);
    /* "bytes" masks the stored byte */
    o = (bvox_mosaic_opts){0x21, BVOX_MOSAIC_BYTES, 0};
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(px(im, 1, 0), 32);
    CHECK_EQ(px(im, 0, 3), 1);
    bvox_image_destroy(im);
    /* no plane: all black */
    o = (bvox_mosaic_opts){0, BVOX_MOSAIC_COUNT, 0};
    CHECK_OK(bvox_mosaic(v, &o, &im));
    for (int i = 0; i < 24; i++) CHECK_EQ(im->pixels[i], 0);
    bvox_image_destroy(im);
    /* the default is count over all 8 planes */
    CHECK_OK(bvox_mosaic(v, NULL, &im));
    CHECK_EQ(px(im, 1, 0), (255 * 2 + 4) / 8);
    bvox_image_destroy(im);
    bvox_volume_destroy(v);
    return 0;
}

TEST(lut_tables)
{
    bvox_lut t;
    CHECK_OK(bvox_mosaic_lut(0xff, BVOX_MOSAIC_BYTES, &t));
    for (int b = 0; b < 256; b++) CHECK_EQ(t.value[b], b);
    CHECK_OK(bvox_mosaic_lut(0xf0, BVOX_MOSAIC_ANY, &t));
    for (int b = 0; b < 256; b++) CHECK_EQ(t.value[b], (b & 0xf0) ? 255 : 0);
    CHECK_OK(bvox_mosaic_lut(0xff, BVOX_MOSAIC_COUNT, &t));
    CHECK_EQ(t.value[0], 0);
    CHECK_EQ(t.value[0xff], 255);
    CHECK_EQ(t.value[0x0f], 128); /* 4 of 8: 127.5 rounded up */
    CHECK_EQ(t.value[0x01], 32);  /* 31.875 */
    CHECK_STATUS(bvox_mosaic_lut(0xff, (bvox_mosaic_display)3, &t), BVOX_EINVAL);
    CHECK_EQ(bvox_mosaic_display_parse("any"), BVOX_MOSAIC_ANY);
    CHECK_EQ(bvox_mosaic_display_parse("bytes"), BVOX_MOSAIC_BYTES);
    CHECK_EQ(bvox_mosaic_display_parse("count"), BVOX_MOSAIC_COUNT);
    CHECK_EQ(bvox_mosaic_display_parse("all"), -1);
    CHECK(!strcmp(bvox_mosaic_display_name(BVOX_MOSAIC_ANY), "any"));
    return 0;
}

/* The paper's layout: 128^3 -> 512 x 512, 4 x 4 sections of 128 x 128. */
TEST(paper_layout_128)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){128, 128, 128}, &v));
    /* one voxel per section s at (s, 2s mod 128, 8s + s % 8) */
    for (int s = 0; s < 16; s++) CHECK_OK(bvox_volume_set(v, s, (2 * s) % 128, 8 * s + s % 8, 1));
    bvox_mosaic_opts o = {0xff, BVOX_MOSAIC_BYTES, 0};
    bvox_image *im;
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(im->width, 512);
    CHECK_EQ(im->height, 512);
    int64_t nonzero = 0;
    for (size_t i = 0; i < 512u * 512u; i++) nonzero += im->pixels[i] != 0;
    CHECK_EQ(nonzero, 16);
    for (int s = 0; s < 16; s++)
        CHECK_EQ(px(im, (s % 4) * 128 + s, (s / 4) * 128 + (2 * s) % 128), 1 << (s % 8));
    bvox_image_destroy(im);
    bvox_volume_destroy(v);
    return 0;
}

/* Every pixel against the definition, voxel by voxel, at awkward sizes. */
TEST(random_against_reference)
{
    const int sizes[][3] = {{37, 5, 130}, {1, 1, 1}, {9, 4, 64}, {5, 7, 65}, {3, 3, 8}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        voxref *r = voxref_create(sizes[k][0], sizes[k][1], sizes[k][2]);
        CHECK(r != NULL);
        voxref_random(r, 1, 3, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        CHECK(v != NULL);
        for (int columns = 0; columns <= 3; columns++) {
            const uint8_t planes = (uint8_t)(harness_rand() | 1);
            bvox_mosaic_opts o = {planes, BVOX_MOSAIC_BYTES, columns};
            bvox_image *im;
            CHECK_OK(bvox_mosaic(v, &o, &im));
            int sections = (r->nz + 7) / 8, cols = columns;
            if (!cols)
                while (cols * cols < sections) cols++;
            int rows = (sections + cols - 1) / cols;
            CHECK_EQ(im->width, cols * r->nx);
            CHECK_EQ(im->height, rows * r->ny);
            int64_t bits = 0;
            for (int s = 0; s < rows * cols; s++)
                for (int y = 0; y < r->ny; y++)
                    for (int x = 0; x < r->nx; x++) {
                        int want = 0;
                        for (int b = 0; b < 8 && s < sections; b++)
                            want |= voxref_get(r, x, y, 8 * s + b) << b;
                        want &= planes;
                        CHECK_EQ(px(im, (s % cols) * r->nx + x, (s / cols) * r->ny + y), want);
                        bits += __builtin_popcount((unsigned)want);
                    }
            if (planes == 0xff) CHECK_EQ(bits, voxref_count(r));
            bvox_image_destroy(im);
        }
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    return 0;
}

/* The paper counted voxels with the frame buffer's histogram: the sum over
 * byte values of (pixels with that value) * (its one bits). */
TEST(histogram_counts_voxels)
{
    bvox_volume *v;
    CHECK_OK(bvox_demo_specimen(&v));
    bvox_mosaic_opts o = {0xff, BVOX_MOSAIC_BYTES, 0};
    bvox_image *im;
    CHECK_OK(bvox_mosaic(v, &o, &im));
    CHECK_EQ(im->width, 4 * 256);
    CHECK_EQ(im->height, 4 * 256);
    int64_t hist[256] = {0}, count = 0;
    for (size_t i = 0; i < (size_t)im->width * im->height; i++) hist[im->pixels[i]]++;
    for (int b = 0; b < 256; b++) count += hist[b] * __builtin_popcount((unsigned)b);
    CHECK_EQ(count, bvox_volume_count(v));
    bvox_image_destroy(im);
    bvox_volume_destroy(v);
    return 0;
}

TEST(bad_options)
{
    bvox_volume *v;
    bvox_image *im = (bvox_image *)1;
    CHECK_OK(bvox_volume_create((bvox_dims){60000, 1, 8}, &v));
    bvox_mosaic_opts o = {0xff, BVOX_MOSAIC_COUNT, 20}; /* 1.2M pixels wide */
    CHECK_STATUS(bvox_mosaic(v, &o, &im), BVOX_EINVAL);
    CHECK(im == NULL);
    o.columns = -1;
    CHECK_STATUS(bvox_mosaic(v, &o, &im), BVOX_EINVAL);
    o.columns = 0;
    o.display = (bvox_mosaic_display)9;
    CHECK_STATUS(bvox_mosaic(v, &o, &im), BVOX_EINVAL);
    CHECK_STATUS(bvox_mosaic(NULL, NULL, &im), BVOX_EINVAL);
    bvox_volume_destroy(v);
    /* allocation failure: a clean status, nothing leaks */
    v = hand_volume();
    CHECK(v != NULL);
    bvox__alloc_fail_after(1);
    CHECK_STATUS(bvox_mosaic(v, NULL, &im), BVOX_ENOMEM);
    bvox__alloc_fail_after(0);
    CHECK(im == NULL);
    bvox_volume_destroy(v);
    return 0;
}
