/* test_render_gif.c — animated GIF output and turntables, read back with
 * giflib's own decoder (DGifSlurp): frame count, size, delays, the looping
 * block, gray frames exact through the gray palette, RGB frames close
 * through their median-cut palettes; a turntable's frames equal the views
 * rendered one by one; numbered PNG frames; failures leave no file behind. */
#include "harness.h"
#include "io/io.h"
#include "render/gif.h"

#include <dirent.h>
#include <gif_lib.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int count_files(const char *dir)
{
    int n = 0;
    DIR *d = opendir(dir);
    if (!d) return -1;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

/* Palette colour of pixel i of frame k. */
static const GifColorType *color_at(const GifFileType *g, int k, size_t i)
{
    const SavedImage *s = &g->SavedImages[k];
    const ColorMapObject *map = s->ImageDesc.ColorMap ? s->ImageDesc.ColorMap : g->SColorMap;
    return &map->Colors[s->RasterBits[i]];
}

static int has_loop_block(const GifFileType *g)
{
    const SavedImage *s = &g->SavedImages[0];
    for (int k = 0; k < s->ExtensionBlockCount; k++) {
        const ExtensionBlock *b = &s->ExtensionBlocks[k];
        if (b->Function == APPLICATION_EXT_FUNC_CODE && b->ByteCount == 11 &&
            !memcmp(b->Bytes, "NETSCAPE2.0", 11))
            return 1;
    }
    return 0;
}

TEST(gray_frames_exact)
{
    const char *path = harness_path("gray.gif");
    bvox__gif *g;
    CHECK_OK(bvox__gif_open(path, 5, 4, 7, &g));
    bvox_image *f;
    CHECK_OK(bvox_image_create(5, 4, 1, 8, &f));
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < 20; i++) f->pixels[i] = (uint8_t)(i * 13 + k * 50);
        CHECK_OK(bvox__gif_add(g, f));
    }
    CHECK_OK(bvox__gif_commit(g));
    bvox_image_destroy(f);

    int err = 0;
    GifFileType *d = DGifOpenFileName(path, &err);
    CHECK(d != NULL);
    CHECK_EQ(DGifSlurp(d), GIF_OK);
    CHECK_EQ(d->ImageCount, 3);
    CHECK_EQ(d->SWidth, 5);
    CHECK_EQ(d->SHeight, 4);
    CHECK(has_loop_block(d));
    for (int k = 0; k < 3; k++) {
        GraphicsControlBlock gcb;
        CHECK_EQ(DGifSavedExtensionToGCB(d, k, &gcb), GIF_OK);
        CHECK_EQ(gcb.DelayTime, 7);
        for (size_t i = 0; i < 20; i++) {
            const GifColorType *c = color_at(d, k, i);
            int want = (int)((i * 13 + (size_t)k * 50) & 255);
            CHECK(c->Red == want && c->Green == want && c->Blue == want);
        }
    }
    DGifCloseFile(d, &err);
    CHECK_EQ(count_files(harness_tmpdir()), 1); /* no temporary file left */
    return 0;
}

TEST(rgb_frames_close)
{
    const char *path = harness_path("rgb.gif");
    bvox__gif *g;
    CHECK_OK(bvox__gif_open(path, 16, 16, 4, &g));
    bvox_image *f;
    CHECK_OK(bvox_image_create(16, 16, 3, 8, &f));
    for (int k = 0; k < 2; k++) {
        for (int i = 0; i < 256; i++) {
            f->pixels[3 * i] = (uint8_t)(i + 40 * k);
            f->pixels[3 * i + 1] = (uint8_t)(i * 176 / 255);
            f->pixels[3 * i + 2] = (uint8_t)(255 - i);
        }
        CHECK_OK(bvox__gif_add(g, f));
    }
    CHECK_OK(bvox__gif_commit(g));
    int err = 0;
    GifFileType *d = DGifOpenFileName(path, &err);
    CHECK(d != NULL);
    CHECK_EQ(DGifSlurp(d), GIF_OK);
    CHECK_EQ(d->ImageCount, 2);
    for (int k = 0; k < 2; k++) {
        CHECK(d->SavedImages[k].ImageDesc.ColorMap != NULL); /* its own palette */
        for (int i = 0; i < 256; i++) {
            const GifColorType *c = color_at(d, k, (size_t)i);
            CHECK(abs(c->Red - (uint8_t)(i + 40 * k)) <= 12);
            CHECK(abs(c->Green - i * 176 / 255) <= 12);
            CHECK(abs(c->Blue - (255 - i)) <= 12);
        }
    }
    DGifCloseFile(d, &err);
    bvox_image_destroy(f);
    return 0;
}

TEST(writer_errors)
{
    const char *path = harness_path("bad.gif");
    bvox__gif *g;
    CHECK_STATUS(bvox__gif_open(path, 70000, 4, 5, &g), BVOX_EINVAL);
    CHECK_OK(bvox__gif_open(path, 4, 4, 5, &g));
    bvox_image *f;
    CHECK_OK(bvox_image_create(5, 4, 1, 8, &f));
    CHECK_STATUS(bvox__gif_add(g, f), BVOX_EINVAL); /* wrong size */
    bvox_image_destroy(f);
    CHECK_STATUS(bvox__gif_commit(g), BVOX_EINVAL); /* no frames */
    CHECK_EQ(count_files(harness_tmpdir()), 0);
    /* a failing write: no file, no temporary file */
    CHECK_OK(bvox__gif_open(path, 4, 4, 5, &g));
    CHECK_OK(bvox_image_create(4, 4, 1, 8, &f));
    bvox__sink_fail_after(1);
    bvox_status st = bvox__gif_add(g, f);
    if (!st) st = bvox__gif_commit(g);
    else bvox__gif_abort(g);
    bvox__sink_fail_after(0);
    CHECK(st != BVOX_OK);
    CHECK_EQ(count_files(harness_tmpdir()), 0);
    bvox_image_destroy(f);
    bvox__gif_abort(NULL);
    return 0;
}

static bvox_volume *object(void)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){20, 16, 24}, &v)) return NULL;
    bvox_volume_fill_box(v, (bvox_box){4, 4, 3, 16, 12, 20}, 1);
    bvox_volume_fill_box(v, (bvox_box){8, 0, 8, 12, 16, 12}, 1); /* a bar along y */
    bvox_volume_fill_box(v, (bvox_box){0, 0, 0, 3, 3, 3}, 1);   /* no symmetry */
    return v;
}

TEST(turntable_gif_frames)
{
    bvox_volume *v = object();
    CHECK(v != NULL);
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("iso", &o));
    o.proj.width = 48, o.proj.height = 40;
    const char *path = harness_path("spin.GIF");
    CHECK_OK(bvox_render_turntable(v, &o, 6, path));
    int err = 0;
    GifFileType *d = DGifOpenFileName(path, &err);
    CHECK(d != NULL);
    CHECK_EQ(DGifSlurp(d), GIF_OK);
    CHECK_EQ(d->ImageCount, 6);
    CHECK_EQ(d->SWidth, 48);
    CHECK_EQ(d->SHeight, 40);
    CHECK(has_loop_block(d));
    GraphicsControlBlock gcb;
    CHECK_EQ(DGifSavedExtensionToGCB(d, 0, &gcb), GIF_OK);
    CHECK_EQ(gcb.DelayTime, 67); /* a turn in 4 s */
    int differ = 0;
    for (int k = 0; k < 6; k++) {
        bvox_render_opts f;
        bvox_image *img;
        CHECK_OK(bvox_turntable_view(&o, k, 6, &f));
        CHECK_OK(bvox_render(v, &f, &img, NULL));
        for (size_t i = 0; i < 48 * 40; i++) CHECK_EQ(color_at(d, k, i)->Red, img->pixels[i]);
        if (k) differ += memcmp(d->SavedImages[k].RasterBits, d->SavedImages[0].RasterBits, 48 * 40) != 0;
        bvox_image_destroy(img);
    }
    CHECK_EQ(differ, 5); /* the object turns */
    DGifCloseFile(d, &err);
    bvox_volume_destroy(v);
    return 0;
}

TEST(turntable_png_frames)
{
    bvox_volume *v = object();
    CHECK(v != NULL);
    bvox_render_opts o = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view("15,25", &o));
    o.proj.width = o.proj.height = 32;
    o.cut = 1, o.plane[0] = 1, o.plane[3] = -10; /* RGB frames */
    CHECK_OK(bvox_render_turntable(v, &o, 3, harness_path("frame.png")));
    CHECK_EQ(count_files(harness_tmpdir()), 3);
    for (int k = 0; k < 3; k++) {
        char name[32];
        snprintf(name, sizeof name, "frame_%03d.png", k);
        bvox_image *got, *want;
        bvox_render_opts f;
        CHECK_OK(bvox_image_read_png(harness_path(name), &got));
        CHECK_OK(bvox_turntable_view(&o, k, 3, &f));
        CHECK_OK(bvox_render(v, &f, &want, NULL));
        CHECK_EQ(got->channels, 3);
        CHECK(!memcmp(got->pixels, want->pixels, 32 * 32 * 3));
        bvox_image_destroy(got), bvox_image_destroy(want);
    }
    /* a failure on the third file removes the two written before */
    CHECK_OK(bvox_render_turntable(v, &o, 3, harness_path("other")));
    CHECK_EQ(count_files(harness_tmpdir()), 6); /* other_000.png ... */
    CHECK_EQ(mkdir(harness_path("fail_002.png"), 0777), 0); /* cannot be replaced */
    CHECK(bvox_render_turntable(v, &o, 4, harness_path("fail.png")) != BVOX_OK);
    CHECK_EQ(count_files(harness_tmpdir()), 7);
    CHECK_EQ(rmdir(harness_path("fail_002.png")), 0);
    /* a failing GIF leaves nothing either */
    bvox__sink_fail_after(2);
    CHECK(bvox_render_turntable(v, &o, 4, harness_path("fail.gif")) != BVOX_OK);
    bvox__sink_fail_after(0);
    CHECK_EQ(count_files(harness_tmpdir()), 6);
    CHECK_STATUS(bvox_render_turntable(v, &o, 0, harness_path("x.gif")), BVOX_EINVAL);
    CHECK_STATUS(bvox_render_turntable(v, &o, 3601, harness_path("x.gif")), BVOX_EINVAL);
    CHECK_STATUS(bvox_render_turntable(v, &o, 2, NULL), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}
