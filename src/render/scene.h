/*
 * scene.h — private interface of the picture-making files of src/render/
 * (render_view.c, render_pipeline.c, sheet.c, turntable.c, pictures.c): a
 * scene is one volume prepared for several casts (the cut copy made once, the
 * boundary-voxel surface built once), so that stereo pairs, sheets and
 * turntables cast many views of it without redoing that work.
 *
 * Frames are 3x3 row-major matrices with rows right, down, view, in the
 * volume's axis-aligned physical frame (voxel (i, j, k) at (i sx, j sy, k sz)),
 * the convention of bvox_projection's matrix and of bvox_preimage's eye.
 */
#ifndef BVOX_RENDER_SCENE_H
#define BVOX_RENDER_SCENE_H

#include "render.h"

typedef struct bvox__scene {
    const bvox_render_opts *opts; /* cut and shading options (borrowed) */
    const bvox_volume *orig;      /* the input (borrowed) */
    const bvox_volume *vol;       /* what is cast: cut or orig */
    bvox_volume *cut;             /* the cut copy, owned; NULL without a cut */
    bvox_surface *surf;           /* built on the first projection, owned */
    /* The cut plane in the casting frame p: f(p) = m . p + e, kept where
     * keep_sign * f >= 0 (above), or < 0 (below). */
    double m[3], e;
    /* Per-object colours (bvox_render_objects, bvox_render_labels): the
     * colour of voxel (x, y, z), 0 when no object holds it (then the
     * default colour). NULL: one object. */
    int (*colour_at)(const void *ctx, int32_t x, int32_t y, int32_t z, uint8_t rgb[3]);
    const void *colour_ctx;
} bvox__scene;

/* Validate opts, make the cut copy if asked. On failure nothing is held. */
bvox_status bvox__scene_open(const bvox_volume *vol, const bvox_render_opts *opts,
                             bvox__scene *sc);
void bvox__scene_close(bvox__scene *sc);

/* One view (no stereo) of the scene as o says: the view and the image size
 * from o, everything else from the scene's opts. pre may be NULL. */
bvox_status bvox__scene_render_one(bvox__scene *sc, const bvox_render_opts *o, bvox_image **out,
                                   bvox_preimage **pre);
/* The same with o's stereo (two views composed). */
bvox_status bvox__scene_render(bvox__scene *sc, const bvox_render_opts *o, bvox_image **out,
                               bvox_preimage **pre);

/* ---- render_view.c ---- */
/* The frame of an axis view: its image axes (bvox_cast_axis) and the view. */
void bvox__axis_frame(bvox_view view, double f[9]);
/* The frame of o's view (axis view, matrix rows or azimuth/elevation),
 * orthonormalised. BVOX_EINVAL for non-finite or dependent rows. */
bvox_status bvox__opts_frame(const bvox_render_opts *o, double f[9]);
/* Turn a frame by deg degrees in its own right/view plane, about the image's
 * vertical axis: positive deg is the left eye's view (eye moved to the left). */
void bvox__frame_turn(double f[9], double deg);
/* Checks of opts shared by the entry points (not the light or depth tables,
 * which the shading checks). */
bvox_status bvox__render_opts_check(const bvox_render_opts *o);

/* bvox_render with per-object colours (colour_at as in bvox__scene; NULL:
 * one object) and the annotations. */
bvox_status bvox__render_coloured(const bvox_volume *vol, const bvox_render_opts *opts,
                                  int (*colour_at)(const void *, int32_t, int32_t, int32_t,
                                                   uint8_t[3]),
                                  const void *ctx, bvox_image **out, bvox_preimage **pre);

/* ---- annotate.c ---- */
/* Whether o asks for a colour image (colour, background, transparency or
 * annotations). */
int bvox__render_wants_colour(const bvox_render_opts *o);
/* Draw o's scale bar, axes and title on img (made RGB first if gray). pre:
 * the (left eye's) pre-image of the picture, for the pixel size. */
bvox_status bvox__annotate(const bvox_render_opts *o, const bvox_preimage *pre,
                           const char *unit, bvox_image **img);

#endif
