/* test_render_image.c — image operations: the paper's Figure 5 (zoom x2 with
 * pixel averaging) exactly, replication zoom, pan, 3x3 convolution presets
 * and custom kernels on hand-computed cases with saturation and rounding,
 * colour maps, PNG round trips (8/16-bit, gray/RGB) and bad input. */
#include "harness.h"
#include "io/io.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <dirent.h>

static bvox_image *make8(int w, int h, int ch, const uint8_t *px)
{
    bvox_image *im = NULL;
    if (bvox_image_create(w, h, ch, 8, &im)) return NULL;
    memcpy(im->pixels, px, (size_t)w * h * ch);
    return im;
}

static int same8(const bvox_image *im, int w, int h, const uint8_t *want)
{
    CHECK(im != NULL);
    CHECK_EQ(im->width, w);
    CHECK_EQ(im->height, h);
    for (int i = 0; i < w * h * im->channels; i++)
        if (im->pixels[i] != want[i]) {
            fprintf(stderr, "sample %d: %d, want %d\n", i, im->pixels[i], want[i]);
            return 1;
        }
    return 0;
}

TEST(figure5_zoom_average)
{
    const uint8_t a[] = {13, 5, 0, 8};
    const uint8_t want[] = {13, 9, 5, 3, 7, 7, 7, 3, 0, 4, 8, 4, 0, 2, 4, 2};
    bvox_image *in = make8(2, 2, 1, a), *out;
    CHECK_OK(bvox_image_zoom2_average(in, &out));
    CHECK_EQ(same8(out, 4, 4, want), 0);
    bvox_image_destroy(out);
    /* 16-bit: the same arithmetic, rounding half up: (1 + 2 + 1) / 2 -> 2 */
    bvox_image *w16;
    CHECK_OK(bvox_image_create(2, 1, 1, 16, &w16));
    w16->pixels16[0] = 60001, w16->pixels16[1] = 60002;
    CHECK_OK(bvox_image_zoom2_average(w16, &out));
    CHECK_EQ(out->pixels16[0], 60001);
    CHECK_EQ(out->pixels16[1], 60002); /* (60001 + 60002 + 1) / 2 */
    CHECK_EQ(out->pixels16[3], 30001); /* (60002 + 0 + 1) / 2 */
    CHECK_EQ(out->pixels16[4], 30001); /* (60001 + 0 + 1) / 2 */
    CHECK_EQ(out->pixels16[5], 30001); /* (60001 + 60002 + 2) / 4 */
    bvox_image_destroy(out);
    bvox_image_destroy(w16);
    bvox_image_destroy(in);
    return 0;
}

TEST(zoom_replication)
{
    const uint8_t a[] = {1, 2, 3, 4, 5, 6}; /* 3 x 2 */
    bvox_image *in = make8(3, 2, 1, a), *out;
    for (int f = 1; f <= 8; f *= 2) {
        CHECK_OK(bvox_image_zoom(in, f, &out));
        CHECK_EQ(out->width, 3 * f);
        CHECK_EQ(out->height, 2 * f);
        for (int y = 0; y < 2 * f; y++)
            for (int x = 0; x < 3 * f; x++) CHECK_EQ(out->pixels[y * 3 * f + x], a[(y / f) * 3 + x / f]);
        bvox_image_destroy(out);
    }
    CHECK_STATUS(bvox_image_zoom(in, 3, &out), BVOX_EINVAL);
    CHECK(out == NULL);
    bvox_image_destroy(in);
    /* RGB keeps its triples together */
    const uint8_t rgb[] = {10, 20, 30, 40, 50, 60};
    in = make8(2, 1, 3, rgb);
    CHECK_OK(bvox_image_zoom(in, 2, &out));
    const uint8_t want[] = {10, 20, 30, 10, 20, 30, 40, 50, 60, 40, 50, 60,
                            10, 20, 30, 10, 20, 30, 40, 50, 60, 40, 50, 60};
    CHECK_EQ(same8(out, 4, 2, want), 0);
    bvox_image_destroy(out);
    bvox_image_destroy(in);
    return 0;
}

TEST(pan)
{
    const uint8_t a[] = {1, 2, 3, 4, 5, 6}; /* 3 x 2 */
    bvox_image *in = make8(3, 2, 1, a), *out;
    CHECK_OK(bvox_image_pan(in, 1, -1, &out));
    const uint8_t w1[] = {0, 4, 5, 0, 0, 0};
    CHECK_EQ(same8(out, 3, 2, w1), 0);
    bvox_image_destroy(out);
    CHECK_OK(bvox_image_pan(in, -2, 1, &out));
    const uint8_t w2[] = {0, 0, 0, 3, 0, 0};
    CHECK_EQ(same8(out, 3, 2, w2), 0);
    bvox_image_destroy(out);
    CHECK_OK(bvox_image_pan(in, 5, 0, &out));
    const uint8_t w3[] = {0, 0, 0, 0, 0, 0};
    CHECK_EQ(same8(out, 3, 2, w3), 0);
    bvox_image_destroy(out);
    CHECK_OK(bvox_image_pan(in, INT32_MIN, INT32_MAX, &out));
    CHECK_EQ(same8(out, 3, 2, w3), 0);
    bvox_image_destroy(out);
    bvox_image_destroy(in);
    return 0;
}

static const uint8_t A[] = {10, 20, 30, 40, 50, 60, 70, 80, 90};
static const uint8_t B[] = {0, 0, 0, 0, 200, 0, 0, 0, 0};

TEST(convolve_presets)
{
    bvox_image *a = make8(3, 3, 1, A), *b = make8(3, 3, 1, B), *o;
    /* smooth: centre 800/16 = 50; corner (0,0) with edges repeated 320/16 = 20 */
    CHECK_OK(bvox_image_filter(a, BVOX_FILTER_SMOOTH, &o));
    CHECK_EQ(o->pixels[4], 50);
    CHECK_EQ(o->pixels[0], 20);
    bvox_image_destroy(o);
    /* high pass: 9*50 - 400 = 50 on A; 9*200 saturates to 255 on B, the
     * border pixels next to it go to -200 and saturate to 0 */
    CHECK_OK(bvox_image_filter(a, BVOX_FILTER_HIGHPASS, &o));
    CHECK_EQ(o->pixels[4], 50);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_filter(b, BVOX_FILTER_HIGHPASS, &o));
    const uint8_t hb[] = {0, 0, 0, 0, 255, 0, 0, 0, 0};
    CHECK_EQ(same8(o, 3, 3, hb), 0);
    bvox_image_destroy(o);
    /* Laplacian: flat ramp centre 0; corner (2,2): 360 - 320 = 40; corner
     * (0,0): 40 - 80 saturates to 0; B's centre 800 -> 255 */
    CHECK_OK(bvox_image_filter(a, BVOX_FILTER_LAPLACIAN, &o));
    CHECK_EQ(o->pixels[4], 0);
    CHECK_EQ(o->pixels[8], 40);
    CHECK_EQ(o->pixels[0], 0);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_filter(b, BVOX_FILTER_LAPLACIAN, &o));
    CHECK_EQ(o->pixels[4], 255);
    CHECK_EQ(o->pixels[1], 0);
    bvox_image_destroy(o);
    /* Sobel: centre gx 80, gy 240 -> sqrt(64000) = 252.98 -> 253; corner
     * (0,0): gx 40, gy 120 -> 126.49 -> 126; B's centre: 0 */
    CHECK_OK(bvox_image_filter(a, BVOX_FILTER_SOBEL, &o));
    CHECK_EQ(o->pixels[4], 253);
    CHECK_EQ(o->pixels[0], 126);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_filter(b, BVOX_FILTER_SOBEL, &o));
    CHECK_EQ(o->pixels[4], 0);
    CHECK_EQ(o->pixels[1], 255); /* gy = 2*200 = 400 saturates */
    bvox_image_destroy(o);
    /* a flat image stays flat under smoothing (edges repeated, not zero) */
    const uint8_t flat[] = {77, 77, 77, 77, 77, 77};
    bvox_image *f = make8(3, 2, 1, flat);
    CHECK_OK(bvox_image_filter(f, BVOX_FILTER_SMOOTH, &o));
    CHECK_EQ(same8(o, 3, 2, flat), 0);
    bvox_image_destroy(o);
    bvox_image_destroy(f);
    CHECK_EQ(bvox_filter_parse("sobel"), BVOX_FILTER_SOBEL);
    CHECK_EQ(bvox_filter_parse("blur"), -1);
    CHECK_STATUS(bvox_image_filter(a, (bvox_filter)9, &o), BVOX_EINVAL);
    bvox_image_destroy(a);
    bvox_image_destroy(b);
    return 0;
}

TEST(convolve_kernel_rounding)
{
    const int32_t id[9] = {0, 0, 0, 0, 1, 0, 0, 0, 0};
    const int32_t box[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1};
    const uint8_t one[] = {1}, three[] = {3};
    bvox_image *a = make8(3, 3, 1, A), *p1 = make8(1, 1, 1, one), *p3 = make8(1, 1, 1, three), *o;
    CHECK_OK(bvox_image_convolve(a, box, 9, 0, &o));
    CHECK_EQ(o->pixels[4], 50);
    CHECK_EQ(o->pixels[0], 23); /* (4*10 + 2*20 + 2*40 + 50) / 9 = 23.3 */
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_convolve(p1, id, 2, 0, &o)); /* 0.5 rounds up to 1 */
    CHECK_EQ(o->pixels[0], 1);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_convolve(p3, id, -2, 10, &o)); /* -1.5 -> -1, + 10 */
    CHECK_EQ(o->pixels[0], 9);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_convolve(p1, id, -2, 0, &o)); /* -0.5 -> 0 */
    CHECK_EQ(o->pixels[0], 0);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_convolve(p3, id, 1, 300, &o)); /* bias saturates */
    CHECK_EQ(o->pixels[0], 255);
    bvox_image_destroy(o);
    CHECK_STATUS(bvox_image_convolve(a, id, 0, 0, &o), BVOX_EINVAL);
    CHECK(o == NULL);
    bvox_image *w16;
    CHECK_OK(bvox_image_create(2, 2, 1, 16, &w16));
    CHECK_STATUS(bvox_image_convolve(w16, id, 1, 0, &o), BVOX_EINVAL);
    bvox_image_destroy(w16);
    bvox_image_destroy(a);
    bvox_image_destroy(p1);
    bvox_image_destroy(p3);
    return 0;
}

TEST(colormaps)
{
    const uint8_t g[] = {0, 128, 255};
    bvox_image *in = make8(3, 1, 1, g), *o;
    CHECK_OK(bvox_image_colormap(in, BVOX_CMAP_GRAY, &o));
    const uint8_t wg[] = {0, 0, 0, 128, 128, 128, 255, 255, 255};
    CHECK_EQ(same8(o, 3, 1, wg), 0);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_colormap(in, BVOX_CMAP_HOT, &o));
    /* t = 128/255: red 3t > 1 -> 255, green 3t-1 = 0.506 -> 129, blue 0 */
    const uint8_t wh[] = {0, 0, 0, 255, 129, 0, 255, 255, 255};
    CHECK_EQ(same8(o, 3, 1, wh), 0);
    bvox_image_destroy(o);
    CHECK_OK(bvox_image_colormap(in, BVOX_CMAP_BONE, &o));
    CHECK_EQ(o->pixels[6], 255);
    CHECK_EQ(o->pixels[0], 0);
    CHECK(o->pixels[5] > o->pixels[3]); /* bluish in the middle */
    bvox_image_destroy(o);
    CHECK_EQ(bvox_colormap_parse("Hot"), BVOX_CMAP_HOT);
    CHECK_EQ(bvox_colormap_parse("jet"), -1);
    CHECK_STATUS(bvox_image_colormap(in, (bvox_colormap)77, &o), BVOX_EINVAL);
    bvox_image_destroy(in);
    return 0;
}

static int count_files(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL) n += e->d_name[0] != '.' || strlen(e->d_name) > 2;
    if (d) closedir(d);
    return n;
}

TEST(png_round_trip)
{
    static const int kinds[][2] = {{1, 8}, {3, 8}, {1, 16}, {3, 16}};
    for (int k = 0; k < 4; k++) {
        bvox_image *im, *back;
        CHECK_OK(bvox_image_create(7, 5, kinds[k][0], kinds[k][1], &im));
        size_t n = 7 * 5 * (size_t)kinds[k][0];
        for (size_t i = 0; i < n; i++) {
            if (kinds[k][1] == 8) im->pixels[i] = (uint8_t)(harness_rand() & 255);
            else im->pixels16[i] = (uint16_t)(harness_rand() & 65535);
        }
        const char *path = harness_path("im.png");
        CHECK_OK(bvox_image_write_png(im, path));
        CHECK_OK(bvox_image_read_png(path, &back));
        CHECK_EQ(back->channels, kinds[k][0]);
        CHECK_EQ(back->bits, kinds[k][1]);
        CHECK_EQ(back->width, 7);
        CHECK_EQ(back->height, 5);
        if (kinds[k][1] == 8) CHECK(memcmp(back->pixels, im->pixels, n) == 0);
        else CHECK(memcmp(back->pixels16, im->pixels16, n * 2) == 0);
        bvox_image_destroy(back);
        bvox_image_destroy(im);
    }
    CHECK_EQ(count_files(harness_tmpdir()), 1); /* no temporary files left */
    return 0;
}

TEST(png_bad_input)
{
    bvox_image *im;
    CHECK_STATUS(bvox_image_read_png_memory("not a png", 9, "x", &im), BVOX_EFORMAT);
    CHECK(im == NULL);
    /* a valid file cut short */
    bvox_image *src;
    CHECK_OK(bvox_image_create(40, 30, 3, 8, &src));
    for (int i = 0; i < 40 * 30 * 3; i++) src->pixels[i] = (uint8_t)(i * 7);
    const char *path = harness_path("t.png");
    CHECK_OK(bvox_image_write_png(src, path));
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    uint8_t buf[8192];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    CHECK(n > 100 && n < sizeof buf);
    for (size_t cut = 8; cut < n; cut += 37) {
        CHECK_STATUS(bvox_image_read_png_memory(buf, cut, "cut", &im), BVOX_EFORMAT);
        CHECK(im == NULL);
    }
    CHECK_OK(bvox_image_read_png_memory(buf, n, "whole", &im));
    CHECK(memcmp(im->pixels, src->pixels, 40 * 30 * 3) == 0);
    bvox_image_destroy(im);
    /* a failing write leaves nothing behind and the old file unchanged */
    bvox__sink_fail_after(1);
    CHECK(bvox_image_write_png(src, path) != BVOX_OK);
    bvox__sink_fail_after(0);
    CHECK_OK(bvox_image_read_png(path, &im));
    bvox_image_destroy(im);
    CHECK_EQ(count_files(harness_tmpdir()), 1);
    CHECK_STATUS(bvox_image_write_png(src, "/nonexistent-dir/x.png"), BVOX_ENOTFOUND);
    CHECK_STATUS(bvox_image_read_png("/nonexistent-dir/x.png", &im), BVOX_ENOTFOUND);
    bvox_image_destroy(src);
    CHECK_STATUS(bvox_image_create(0, 5, 1, 8, &im), BVOX_EINVAL);
    CHECK_STATUS(bvox_image_create(5, 5, 2, 8, &im), BVOX_EINVAL);
    CHECK_STATUS(bvox_image_create(5, 5, 1, 12, &im), BVOX_EINVAL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
