/*
 * pictures.c — the paper's four pictures (section 4 and its plates) made
 * from one volume, for `bvox demo`:
 *   1  binary gradient and depth shaded;
 *   2  depth shaded, zoomed x2 (with the pixel averaging of Figure 5) and
 *      high-pass filtered;
 *   3  "the same" (as 2), but the object resliced along a plane;
 *   4  the voxel data set as stored in one of the frame buffers (mosaic).
 * Beside them (issue 18) pictures 1 and 3 smooth-shaded (normals from the
 * occupancy around each hit voxel, bvox_smooth_normal), so the paper's
 * binary shading and today's can be compared view for view. Picture 2 is
 * picture 1's view in depth shading and picture 4 the stored bits: neither
 * has a smooth counterpart of its own.
 * And the paper's own two methods where it used them (issue 18, item 3):
 * picture 1 is "binary gradient shaded", and the paper computes binary
 * normals either in the ray cast (the 26 codes, picture1.png) or by "a binary
 * gradient operator over the pre-image" (picture1_preimage.png); pictures 2
 * and 3 are the depth pre-image "zoomed x2" with the pixel averaging of
 * Figure 5, after which "we may again run any gradient operator ... over the
 * enlarged pre-image to obtain a shaded surface view" (picture2_enlarged.png,
 * picture3_enlarged.png: Sobel over the enlarged depths, lit).
 * The view is the isometric one from (+1, +1, +1), z up, so the specimen
 * stands on end; the reslicing plane is x = the centre of the volume,
 * keeping the lower x, so the view sees the cut face (the bored hole, the
 * ring's and the cap's sections) beside the untouched surface. The frame buffer held 128^3 voxels: a larger
 * section is shown by every n-th column (whole columns of words copied), so
 * the 256 x 256 x 128 specimen fills the paper's 512 x 512 exactly.
 */
#include "scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PICTURE_SIZE 512

/* Every step-th column in x and y: nx and ny at most 128. */
static bvox_status subsample_xy(const bvox_volume *vol, bvox_volume **out)
{
    int32_t step = 1;
    while ((vol->nx + step - 1) / step > 128 || (vol->ny + step - 1) / step > 128) step++;
    bvox_dims d = {(vol->nx + step - 1) / step, (vol->ny + step - 1) / step, vol->nz};
    bvox_status st = bvox_volume_create(d, out);
    if (st) return st;
    bvox_geometry g = vol->geom;
    g.spacing[0] *= step, g.spacing[1] *= step;
    (*out)->geom = g;
    for (int32_t y = 0; y < d.ny; y++)
        for (int32_t x = 0; x < d.nx; x++)
            memcpy(bvox__column(*out, x, y), bvox__column_c(vol, x * step, y * step),
                   vol->wpc * sizeof(uint64_t));
    return BVOX_OK;
}

static void picture_opts(const bvox_volume *vol, int k, bvox_render_opts *o)
{
    *o = bvox_render_opts_default();
    bvox_render_parse_view("iso", o); /* cannot fail */
    o->proj.width = o->proj.height = k == 1 ? PICTURE_SIZE : PICTURE_SIZE / 2;
    if (k == 1) return; /* binary gradient + depth */
    o->shade = BVOX_SHADE_DEPTH;
    o->depth.far_value = 0; /* the object spans only part of the sphere's depth */
    o->average = 1;
    o->filter = BVOX_FILTER_HIGHPASS;
    if (k == 3) {
        /* through the centre of the volume, across its index x axis (the
         * world direction of that axis is column 0 of direction) */
        const bvox_geometry *g = &vol->geom;
        const double half[3] = {(vol->nx - 1) * 0.5 * g->spacing[0],
                                (vol->ny - 1) * 0.5 * g->spacing[1],
                                (vol->nz - 1) * 0.5 * g->spacing[2]};
        o->cut = 1;
        o->plane[3] = 0;
        for (int r = 0; r < 3; r++) {
            double centre = g->origin[r];
            for (int a = 0; a < 3; a++) centre += g->direction[3 * r + a] * half[a];
            o->plane[r] = g->direction[3 * r];
            o->plane[3] -= o->plane[r] * centre;
        }
        o->keep_above = 0;
    }
}

bvox_status bvox_demo_picture(const bvox_volume *vol, int k, bvox_image **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "picture: no volume");
    if (k < 1 || k > 4) return bvox__fail(BVOX_EINVAL, "picture %d: there are pictures 1..4", k);
    if (k == 4) {
        bvox_volume *small = NULL;
        bvox_status st = subsample_xy(vol, &small);
        if (!st) st = bvox_mosaic(small, NULL, out);
        bvox_volume_destroy(small);
        return st;
    }
    bvox_render_opts o;
    picture_opts(vol, k, &o);
    return bvox_render(vol, &o, out, NULL);
}

bvox_status bvox__demo_picture_smooth(const bvox_volume *vol, int k, bvox_image **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "picture: no volume");
    if (k != 1 && k != 3) return bvox__fail(BVOX_EINVAL, "picture %d: smooth pictures are 1 and 3", k);
    bvox_render_opts o;
    picture_opts(vol, k, &o);
    /* picture 3's view and cut at picture 1's size, without picture 2's
     * zoom and filter (made for depth shading) */
    o.proj.width = o.proj.height = PICTURE_SIZE;
    o.shade = BVOX_SHADE_SMOOTH;
    o.average = 0;
    o.filter = -1;
    return bvox_render(vol, &o, out, NULL);
}

bvox_status bvox__demo_picture_paper(const bvox_volume *vol, int k, bvox_image **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "picture: no volume");
    if (k < 1 || k > 3) return bvox__fail(BVOX_EINVAL, "picture %d: the paper's modes are for 1..3", k);
    bvox_render_opts o;
    picture_opts(vol, k, &o);
    if (k == 1) {
        o.shade = BVOX_SHADE_PREIMAGE_BINARY; /* its cue bits keep the depth shading */
        return bvox_render(vol, &o, out, NULL);
    }
    /* pictures 2 and 3's 256 x 256 pre-image enlarged to 512 x 512, the
     * gradient operator in place of the zoom and the high-pass filter */
    o.shade = BVOX_SHADE_ENLARGED_GRADIENT;
    o.average = 0;
    o.filter = -1;
    return bvox_render(vol, &o, out, NULL);
}

/* The files, in the order written: picture1..4.png, the smooth ones, then
 * the paper's pre-image methods. */
#define NPICTURES 9
static const char *const picture_names[NPICTURES] = {
    "picture1.png",         "picture2.png",          "picture3.png",
    "picture4.png",         "picture1_smooth.png",   "picture3_smooth.png",
    "picture1_preimage.png", "picture2_enlarged.png", "picture3_enlarged.png"};

bvox_status bvox_demo_pictures(const bvox_volume *vol, const char *dir)
{
    if (!dir) return bvox__fail(BVOX_EINVAL, "pictures: no folder");
    size_t size = strlen(dir) + 32;
    char *path = bvox__mem_alloc(size);
    if (!path) return bvox__fail(BVOX_ENOMEM, "out of memory");
    /* all made before any is written, and the ones written removed if a
     * later one fails: a failed call leaves no partial set behind */
    bvox_image *img[NPICTURES] = {NULL};
    bvox_status st = BVOX_OK;
    for (int k = 0; k < 4 && !st; k++) st = bvox_demo_picture(vol, k + 1, &img[k]);
    if (!st) st = bvox__demo_picture_smooth(vol, 1, &img[4]);
    if (!st) st = bvox__demo_picture_smooth(vol, 3, &img[5]);
    for (int k = 0; k < 3 && !st; k++) st = bvox__demo_picture_paper(vol, k + 1, &img[6 + k]);
    int written = 0;
    for (; written < NPICTURES && !st; written++) {
        snprintf(path, size, "%s/%s", dir, picture_names[written]);
        st = bvox_image_write_png(img[written], path);
        if (st) break;
    }
    for (int k = 0; st && k < written; k++) {
        snprintf(path, size, "%s/%s", dir, picture_names[k]);
        unlink(path);
    }
    for (int k = 0; k < NPICTURES; k++) bvox_image_destroy(img[k]);
    free(path);
    return st;
}
