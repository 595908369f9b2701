/*
 * turntable.c — rotation shown as a turntable (the paper's "real time
 * rotation" depth cue, for talks and supplementary material): n frames of
 * the object spinning about its upright axis, written as an animated GIF or
 * as numbered PNG files. One scene serves every frame, so the cut copy and
 * the boundary-voxel surface are made once and each frame is only a cast.
 * The annotations (scale bar, axes, title) are drawn on every frame.
 */
#include "gif.h"
#include "scene.h"
#include "common/names.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* path without ".png", then _NNN.png (4 digits from 1001 frames; n <= 3600). */
static char *frame_name(const char *path, int i, int n)
{
    size_t stem = strlen(path) - (bvox__ends_with_ci(path, ".png") ? 4 : 0);
    char num[16];
    snprintf(num, sizeof num, n > 1000 ? "%04d" : "%03d", i % 10000);
    size_t size = stem + strlen(num) + 8;
    char *s = bvox__mem_alloc(size);
    if (s) snprintf(s, size, "%.*s_%s.png", (int)stem, path, num);
    return s;
}

static void remove_frames(const char *path, int count, int n)
{
    for (int i = 0; i < count; i++) {
        char *name = frame_name(path, i, n);
        if (name) unlink(name);
        free(name);
    }
}

static bvox_status turntable(const bvox_volume *vol, const bvox_render_opts *opts, int n,
                             const char *path);

bvox_status bvox_render_turntable(const bvox_volume *vol, const bvox_render_opts *opts, int n,
                                  const char *path)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "turntable");
    return bvox__progress_end(&ps, turntable(vol, opts, n, path));
}

/* Progress: one step per frame; a cancel removes the frames written. */
static bvox_status turntable(const bvox_volume *vol, const bvox_render_opts *opts, int n,
                             const char *path)
{
    if (!path || !*path) return bvox__fail(BVOX_EINVAL, "turntable: no output path");
    if (n < 1 || n > 3600)
        return bvox__fail(BVOX_EINVAL, "turntable: %d frames is outside 1..3600", n);
    bvox__scene sc;
    bvox_status st = bvox__scene_open(vol, opts, &sc);
    if (st) return st;
    bvox__clear_error();
    const int gif = bvox__ends_with_ci(path, ".gif");
    int delay = (400 + n / 2) / n; /* a turn in about 4 s */
    delay = delay < 2 ? 2 : delay > 100 ? 100 : delay;
    bvox__gif *g = NULL;
    int written = 0;
    /* annotations on every frame: the axes turn with the object, the scale
     * bar and the title stay (each frame's own pre-image gives its pixel) */
    const int note = opts->scale_bar || opts->axes || opts->title;
    for (int i = 0; i < n && !st; i++) {
        bvox_render_opts fo;
        bvox_image *img = NULL;
        bvox_preimage *pre = NULL;
        st = bvox_turntable_view(opts, i, n, &fo);
        if (!st) st = bvox__scene_render(&sc, &fo, &img, note ? &pre : NULL);
        if (!st && note) st = bvox__annotate(&fo, pre, vol->geom.unit, &img);
        bvox_preimage_destroy(pre);
        if (!st && gif) {
            if (!g) st = bvox__gif_open(path, img->width, img->height, delay, &g);
            if (!st) st = bvox__gif_add(g, img);
        } else if (!st) {
            char *name = frame_name(path, i, n);
            st = name ? bvox_image_write_png(img, name) : bvox__fail(BVOX_ENOMEM, "out of memory");
            if (!st) written++;
            free(name);
        }
        bvox_image_destroy(img);
        if (!st) st = bvox__progress_steps(i + 1, n);
    }
    if (g) {
        if (st) bvox__gif_abort(g);
        else st = bvox__gif_commit(g);
    }
    if (st && !gif) remove_frames(path, written, n);
    bvox__scene_close(&sc);
    return st;
}
