/*
 * sheet.c — a sheet of several views at once (one of the paper's depth
 * cues: "simultaneous projections from different viewpoints"): three axis
 * views and an isometric one in a 2 x 2 grid. All four are projections of
 * one size fitted to the same bounding sphere, so they share one scale and a
 * length reads the same in every cell. Annotations: each cell its own axes
 * triad (the cells look along different axes) and scale bar, the title once
 * at the top of the sheet.
 */
#include "scene.h"

#include <string.h>

bvox_status bvox_render_sheet(const bvox_volume *vol, const bvox_render_opts *opts,
                              bvox_image **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    bvox__scene sc;
    bvox_status st = bvox__scene_open(vol, opts, &sc);
    if (st) return st;
    if (opts->stereo != BVOX_STEREO_NONE) {
        bvox__scene_close(&sc);
        return bvox__fail(BVOX_EINVAL, "sheet: no stereo in a sheet of views");
    }
    bvox__clear_error();
    /* +z, +x and -y are the axis views whose image axes (right, down) and
     * view make a right-handed frame: true pictures, not mirror images */
    const char *const names[4] = {"+z", "+x", "-y", "iso"};
    bvox_image *cell[4] = {NULL, NULL, NULL, NULL};
    for (int k = 0; k < 4 && !st; k++) {
        bvox_render_opts o = *opts;
        st = bvox_render_parse_view(names[k], &o);
        if (st) break;
        if (o.axis_view) {
            bvox__axis_frame(o.view, o.proj.matrix);
            o.axis_view = 0;
            o.proj.use_matrix = 1;
        }
        if (!o.proj.width) o.proj.width = 256;
        if (!o.proj.height) o.proj.height = 256;
        o.title = NULL;
        const int note = o.scale_bar || o.axes;
        bvox_preimage *pre = NULL;
        st = bvox__scene_render_one(&sc, &o, &cell[k], note ? &pre : NULL);
        if (!st && note) st = bvox__annotate(&o, pre, vol->geom.unit, &cell[k]);
        bvox_preimage_destroy(pre);
    }
    if (!st) {
        const bvox_image *c0 = cell[0];
        const int64_t w = c0->width, h = c0->height;
        if (2 * w > BVOX_IMAGE_MAX_DIM || 2 * h > BVOX_IMAGE_MAX_DIM)
            st = bvox__fail(BVOX_EINVAL, "sheet: cells of %lld x %lld are too large",
                            (long long)w, (long long)h);
        else st = bvox_image_create((int32_t)(2 * w), (int32_t)(2 * h), c0->channels, 8, out);
        if (!st) {
            const size_t row = (size_t)w * (size_t)c0->channels;
            for (int k = 0; k < 4; k++)
                for (int64_t y = 0; y < h; y++) {
                    uint8_t *d = (*out)->pixels + ((size_t)(k / 2) * (size_t)h + (size_t)y) * 2 * row +
                                 (size_t)(k % 2) * row;
                    memcpy(d, cell[k]->pixels + (size_t)y * row, row);
                }
        }
    }
    if (!st && opts->title) { /* the title alone: no pixel size needed */
        bvox_render_opts t = bvox_render_opts_default();
        t.title = opts->title;
        memcpy(t.background, opts->background, sizeof t.background);
        t.transparent = opts->transparent;
        st = bvox__annotate(&t, NULL, vol->geom.unit, out);
    }
    if (st) {
        bvox_image_destroy(*out);
        *out = NULL;
    }
    for (int k = 0; k < 4; k++) bvox_image_destroy(cell[k]);
    bvox__scene_close(&sc);
    return st;
}
