/*
 * render_pipeline.c — bvox_render: the paper's display pipeline run end to
 * end for one picture (cut -> cast -> shade -> cut face -> zoom -> filter,
 * and stereo pairs), over a scene that keeps the cut copy and the surface of
 * boundary voxels so that several views of one volume share them.
 *
 * The cut face (Picture 3). For an axis view the hit voxel is known exactly
 * (pixel and depth are its indices) and so is its visible face, the one
 * towards the viewer: it is on the cut face iff the voxel in front of it was
 * in the object, i.e. the cut removed it. No tolerance. A projection's
 * pre-image keeps the depth only to a pixel unit and neither the voxel nor
 * the face, so there the entry point is tested against the plane instead
 * (bvox__cut_test, shared with the viewer's shading codes): within half a
 * voxel's extent plus half a depth step of the plane, which every face the
 * cut exposed satisfies (and a thin rim of the original surface beside it).
 */
#include "scene.h"

#include <math.h>
#include <string.h>

bvox_status bvox__scene_open(const bvox_volume *vol, const bvox_render_opts *opts,
                             bvox__scene *sc)
{
    memset(sc, 0, sizeof *sc);
    if (!vol) return bvox__fail(BVOX_EINVAL, "render: no volume");
    bvox_status st = bvox__render_opts_check(opts);
    if (st) return st;
    sc->opts = opts;
    sc->orig = sc->vol = vol;
    if (!opts->cut) return BVOX_OK;
    if ((st = bvox_volume_copy(vol, &sc->cut))) return st;
    const double *n = opts->plane;
    st = bvox_cut_plane(sc->cut, n[0], n[1], n[2], n[3], opts->keep_above, NULL);
    if (st) {
        bvox_volume_destroy(sc->cut);
        sc->cut = NULL;
        return st;
    }
    sc->vol = sc->cut;
    /* world = origin + D p: f = (D^T n) . p + (n . origin + d) */
    const bvox_geometry *g = &vol->geom;
    sc->e = n[3];
    for (int r = 0; r < 3; r++) sc->e += n[r] * g->origin[r];
    for (int a = 0; a < 3; a++) {
        sc->m[a] = 0;
        for (int r = 0; r < 3; r++) sc->m[a] += n[r] * g->direction[3 * r + a];
    }
    return BVOX_OK;
}

void bvox__scene_close(bvox__scene *sc)
{
    bvox_surface_destroy(sc->surf);
    bvox_volume_destroy(sc->cut);
    memset(sc, 0, sizeof *sc);
}

/* --------------------------------------------------------------- shading */

/* The binary+depth factor 1 - k t of a depth. */
static double depth_factor(const bvox_preimage *p, double k, int32_t d)
{
    return 1.0 - k * (p->depth_range > 1 ? (double)d / (p->depth_range - 1) : 0.0);
}

static bvox_status shade(const bvox__scene *sc, const bvox_preimage *p, const bvox_render_opts *o,
                         bvox_image **img)
{
    bvox_lut lut;
    bvox_status st;
    switch (o->shade) {
    case BVOX_SHADE_DEPTH: return bvox_shade_depth(p, &o->depth, img);
    case BVOX_SHADE_GRADIENT:
    case BVOX_SHADE_ENLARGED_GRADIENT: /* p is the enlarged pre-image then */
        return bvox_shade_gradient(p, BVOX_GRADIENT_SOBEL, &o->light, img);
    case BVOX_SHADE_SMOOTH:
    case BVOX_SHADE_PREIMAGE_BINARY:
        return bvox__shade_normals(sc->vol, p, o->shade, o->smooth_radius, &o->light, img);
    case BVOX_SHADE_BINARY:
        if ((st = bvox_lut_light(p, &o->light, &lut))) return st;
        return bvox_shade(p, &lut, img);
    default: break;
    }
    /* binary + depth: the normal's table without the 3-bit cue, then a
     * factor from the full depth, so the cue has no 8-level bands */
    bvox_light l = o->light;
    double k = l.depth_cue > 0 ? l.depth_cue : 0.5;
    l.depth_cue = 0;
    if ((st = bvox_lut_light(p, &l, &lut)) || (st = bvox_shade(p, &lut, img))) return st;
    const size_t n = (size_t)p->width * (size_t)p->height;
    uint8_t *px = (*img)->pixels;
    for (size_t i = 0; i < n; i++)
        if (p->depth[i] >= 0) px[i] = (uint8_t)(px[i] * depth_factor(p, k, p->depth[i]) + 0.5);
    return BVOX_OK;
}

/* ------------------------------------------------------------- cut face */

/* Axis views: the visible face of the hit voxel is the one towards the
 * viewer; it is on the cut face iff the voxel in front of it was in the
 * object (the cut removed it: it is empty now, the hit being the first). */
static int axis_cut_face(const bvox__scene *sc, bvox_view view, int32_t c, int32_t r, int32_t d)
{
    if (d == 0) return 0; /* the entry face of the volume: nothing was in front */
    const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
    const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
    const int32_t n[3] = {sc->vol->nx, sc->vol->ny, sc->vol->nz};
    int32_t q[3];
    q[cu] = c, q[cv] = r;
    q[axis] = dir > 0 ? d - 1 : n[axis] - d; /* one step back towards the viewer */
    return bvox_volume_get(sc->orig, q[0], q[1], q[2]);
}

/* The voxel hit at pixel (c, r), depth d, of a cast of vol: exact for an
 * axis view; for a projection (depth known to a pixel unit) the voxel whose
 * centre is nearest a point half a step behind the entry point, else the
 * first 1-voxel among its 26 neighbours. 0 if none is found. */
static int hit_voxel(const bvox_volume *vol, const bvox_preimage *p, int axis_cast, bvox_view view,
                     int32_t c, int32_t r, int32_t d, int32_t q[3])
{
    const int32_t n[3] = {vol->nx, vol->ny, vol->nz};
    if (axis_cast) {
        const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
        const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
        q[cu] = c, q[cv] = r;
        q[axis] = dir > 0 ? d : n[axis] - 1 - d;
        return 1;
    }
    int32_t g[3];
    for (int a = 0; a < 3; a++) {
        double x = p->origin[a] + c * p->pixel_size[0] * p->eye[a] +
                   r * p->pixel_size[1] * p->eye[3 + a] + (d + 0.5) * p->depth_step * p->eye[6 + a];
        g[a] = (int32_t)floor(x / p->spacing[a] + 0.5);
    }
    for (int k = 0; k < 27; k++) { /* the guess first (k = 13 is the centre) */
        int kk = k == 0 ? 13 : k == 13 ? 0 : k;
        for (int a = 0; a < 3; a++) q[a] = g[a] + (a == 0 ? kk / 9 : a == 1 ? kk / 3 % 3 : kk % 3) - 1;
        if (q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < n[0] && q[1] < n[1] && q[2] < n[2] &&
            bvox_volume_get(vol, q[0], q[1], q[2]))
            return 1;
    }
    return 0;
}

/* Turn the gray image into RGB (RGBA when transparent): the background in
 * its colour, the object's shades times its colour (per object through
 * colour_at), the cut face lit flat by the plane's normal and tinted: the
 * fixed cut_color for a plain object, a lighter tone of the object's colour
 * when colours were asked (so a cut organ stays recognisable). */
static bvox_status mark_cut(const bvox__scene *sc, const bvox_preimage *p, const bvox_render_opts *o,
                            int axis_cast, bvox_image **img)
{
    bvox_image *rgb;
    const int nch = o->transparent ? 4 : 3;
    bvox_status st = bvox_image_create(p->width, p->height, nch, 8, &rgb);
    if (st) return st;
    const int coloured = o->color_set || sc->colour_at;
    /* the cut face's normal in the eye frame, facing the viewer */
    double nrm[3] = {0, 0, -1}, l[3];
    if (sc->cut) bvox__cut_normal_eye(p, sc->m, nrm);
    /* projections: the plane oriented so that the kept side is >= 0 */
    const double ks = sc->opts->keep_above ? 1.0 : -1.0;
    const double mk[3] = {ks * sc->m[0], ks * sc->m[1], ks * sc->m[2]};
    bvox__cut_test test;
    memset(&test, 0, sizeof test);
    if (sc->cut) bvox__cut_test_init(&test, mk, ks * sc->e, p);
    bvox_light light = o->light;
    double k = light.depth_cue > 0 ? light.depth_cue : 0.5;
    if (o->shade == BVOX_SHADE_BINARY_DEPTH) light.depth_cue = 0;
    bvox__light_dir(&light, l);
    const uint8_t white[3] = {255, 255, 255};
    const uint8_t *gray = (*img)->pixels;
    for (int32_t r = 0; r < p->height; r++)
        for (int32_t c = 0; c < p->width; c++) {
            size_t i = (size_t)r * (size_t)p->width + (size_t)c;
            uint8_t *dst = rgb->pixels + (size_t)nch * i;
            int32_t d = p->depth[i];
            if (d < 0) {
                /* a black background keeps the shading's own (the light's) */
                const int bg = o->background[0] | o->background[1] | o->background[2];
                for (int ch = 0; ch < 3; ch++)
                    dst[ch] = o->transparent ? 0 : bg ? o->background[ch] : gray[i];
                if (nch == 4) dst[3] = 0;
                continue;
            }
            if (nch == 4) dst[3] = 255;
            const uint8_t *col = o->color_set ? o->color : white;
            uint8_t own[3];
            int32_t q[3];
            if (sc->colour_at && hit_voxel(sc->vol, p, axis_cast, o->view, c, r, d, q) &&
                sc->colour_at(sc->colour_ctx, q[0], q[1], q[2], own))
                col = own;
            int cut = sc->cut && (axis_cast ? axis_cut_face(sc, o->view, c, r, d)
                                            : bvox__cut_test_at(&test, p, c, r, d));
            if (!cut) {
                for (int ch = 0; ch < 3; ch++) dst[ch] = (uint8_t)((gray[i] * col[ch] + 127) / 255);
                continue;
            }
            uint8_t tint[3];
            for (int ch = 0; ch < 3; ch++)
                tint[ch] = coloured ? (uint8_t)(col[ch] + (255 - col[ch]) * 2 / 5) : sc->opts->cut_color[ch];
            double v = gray[i];
            if (o->shade != BVOX_SHADE_DEPTH) {
                v = bvox__phong(&light, l, nrm, BVOX_CODE_CUE(p->code[i]));
                if (o->shade == BVOX_SHADE_BINARY_DEPTH) v *= depth_factor(p, k, d);
            }
            for (int ch = 0; ch < 3; ch++) dst[ch] = (uint8_t)(v * tint[ch] / 255.0 + 0.5);
        }
    bvox_image_destroy(*img);
    *img = rgb;
    return BVOX_OK;
}

/* ------------------------------------------------------------- one view */

/* Replace *img by op(*img). */
static bvox_status then(bvox_status (*op)(const bvox_image *, int, bvox_image **), int arg,
                        bvox_image **img)
{
    bvox_image *next;
    bvox_status st = op(*img, arg, &next);
    if (st) return st;
    bvox_image_destroy(*img);
    *img = next;
    return BVOX_OK;
}
static bvox_status avg_op(const bvox_image *in, int arg, bvox_image **out)
{
    (void)arg;
    return bvox_image_zoom2_average(in, out);
}
static bvox_status filter_op(const bvox_image *in, int arg, bvox_image **out)
{
    return bvox_image_filter(in, (bvox_filter)arg, out);
}

bvox_status bvox__scene_render_one(bvox__scene *sc, const bvox_render_opts *o, bvox_image **out,
                                   bvox_preimage **pre)
{
    *out = NULL;
    if (pre) *pre = NULL;
    bvox_status st = bvox__render_opts_check(o);
    if (st) return st;
    const int ss = o->supersample > 1 ? o->supersample : 1;
    const int axis_cast = o->axis_view && !o->proj.width && !o->proj.height && ss == 1;
    bvox_preimage *p = NULL;
    if (axis_cast) {
        st = bvox_cast_axis(sc->vol, o->view, &p);
    } else {
        bvox_projection proj = o->proj;
        proj.use_matrix = 1;
        /* supersampling: N times the pixels over the same picture */
        proj.width = (proj.width ? proj.width : 512) * ss;
        proj.height = (proj.height ? proj.height : 512) * ss;
        proj.scale *= ss;
        if (proj.width > BVOX_IMAGE_MAX_DIM || proj.height > BVOX_IMAGE_MAX_DIM)
            return bvox__fail(BVOX_EINVAL, "render: %d x %d supersampled is over %d pixels a side",
                              (int)proj.width, (int)proj.height, BVOX_IMAGE_MAX_DIM);
        st = bvox__opts_frame(o, proj.matrix);
        if (!st && !sc->surf) st = bvox_surface_build(sc->vol, &sc->surf);
        if (!st) st = bvox_surface_cast(sc->surf, &proj, &p);
    }
    if (!st && o->shade == BVOX_SHADE_ENLARGED_GRADIENT) {
        bvox_preimage *big = NULL;
        st = bvox_preimage_enlarge(p, &big);
        bvox_preimage_destroy(p);
        p = big;
    }
    if (st) return st;
    bvox_image *img = NULL;
    st = shade(sc, p, o, &img);
    /* the enlarged pre-image's pixels are no voxel columns: the plane test */
    const int axis_face = axis_cast && o->shade != BVOX_SHADE_ENLARGED_GRADIENT;
    if (!st && (sc->cut || sc->colour_at || bvox__render_wants_colour(o)))
        st = mark_cut(sc, p, o, axis_face, &img);
    if (!st && (o->ao || o->shadows))
        st = bvox__apply_depth_cues(sc->vol, p, &o->light, o->smooth_radius, o->ao, o->shadows, img);
    if (!st && ss > 1) {
        bvox_image *small = NULL;
        st = bvox__image_shrink(img, ss, &small);
        bvox_image_destroy(img);
        img = small;
    }
    if (!st && o->zoom > 1) st = then(bvox_image_zoom, o->zoom, &img);
    if (!st && o->average) st = then(avg_op, 0, &img);
    if (!st && o->filter >= 0) st = then(filter_op, o->filter, &img);
    if (st) {
        bvox_image_destroy(img);
        bvox_preimage_destroy(p);
        return st;
    }
    *out = img;
    if (pre) *pre = p;
    else bvox_preimage_destroy(p);
    return BVOX_OK;
}

/* ---------------------------------------------------------------- stereo */

static inline uint8_t luma(const bvox_image *im, size_t i)
{
    if (im->channels == 1) return im->pixels[i];
    const uint8_t *p = im->pixels + 3 * i;
    return (uint8_t)((77u * p[0] + 150u * p[1] + 29u * p[2] + 128u) >> 8);
}

static bvox_status compose(const bvox_image *l, const bvox_image *r, bvox_stereo mode,
                           bvox_image **out)
{
    const int32_t w = l->width, h = l->height;
    if (mode == BVOX_STEREO_ANAGLYPH) {
        bvox_status st = bvox_image_create(w, h, 3, 8, out);
        if (st) return st;
        for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
            uint8_t *d = (*out)->pixels + 3 * i;
            d[0] = luma(l, i);
            d[1] = d[2] = luma(r, i);
        }
        return BVOX_OK;
    }
    if ((int64_t)w * 2 > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "stereo: a pair of %d pixels wide is too wide", (int)w);
    bvox_status st = bvox_image_create(2 * w, h, l->channels, 8, out);
    if (st) return st;
    const size_t row = (size_t)w * (size_t)l->channels;
    for (int32_t y = 0; y < h; y++) {
        uint8_t *d = (*out)->pixels + 2 * row * (size_t)y;
        memcpy(d, l->pixels + row * (size_t)y, row);
        memcpy(d + row, r->pixels + row * (size_t)y, row);
    }
    return BVOX_OK;
}

bvox_status bvox__scene_render(bvox__scene *sc, const bvox_render_opts *o, bvox_image **out,
                               bvox_preimage **pre)
{
    if (o->stereo == BVOX_STEREO_NONE) return bvox__scene_render_one(sc, o, out, pre);
    *out = NULL;
    if (pre) *pre = NULL;
    bvox_status st = bvox__render_opts_check(o);
    if (st) return st;
    bvox_render_opts eye[2] = {*o, *o};
    double f[9];
    if ((st = bvox__opts_frame(o, f))) return st;
    bvox_image *img[2] = {NULL, NULL};
    for (int k = 0; k < 2 && !st; k++) {
        eye[k].axis_view = 0;
        eye[k].stereo = BVOX_STEREO_NONE;
        eye[k].proj.use_matrix = 1;
        memcpy(eye[k].proj.matrix, f, sizeof f);
        bvox__frame_turn(eye[k].proj.matrix, k == 0 ? o->stereo_angle : -o->stereo_angle);
        st = bvox__scene_render_one(sc, &eye[k], &img[k], k == 0 ? pre : NULL);
    }
    if (!st) st = compose(img[0], img[1], o->stereo, out);
    bvox_image_destroy(img[0]);
    bvox_image_destroy(img[1]);
    if (st && pre) {
        bvox_preimage_destroy(*pre);
        *pre = NULL;
    }
    return st;
}

bvox_status bvox__render_coloured(const bvox_volume *vol, const bvox_render_opts *opts,
                                  int (*colour_at)(const void *, int32_t, int32_t, int32_t,
                                                   uint8_t[3]),
                                  const void *ctx, bvox_image **out, bvox_preimage **pre)
{
    *out = NULL;
    if (pre) *pre = NULL;
    bvox__scene sc;
    bvox_status st = bvox__scene_open(vol, opts, &sc);
    if (st) return st;
    sc.colour_at = colour_at;
    sc.colour_ctx = ctx;
    bvox__clear_error();
    /* the annotations need the pre-image (its pixel size) */
    const int note = opts->scale_bar || opts->axes || opts->title;
    bvox_preimage *p = NULL;
    st = bvox__scene_render(&sc, opts, out, pre || note ? &p : NULL);
    bvox__scene_close(&sc);
    if (!st && note) st = bvox__annotate(opts, p, vol->geom.unit, out);
    if (st) {
        bvox_image_destroy(*out);
        *out = NULL;
        bvox_preimage_destroy(p);
        return st;
    }
    BVOX_CHECK_IMAGE(*out);
    if (pre) *pre = p;
    else bvox_preimage_destroy(p);
    return BVOX_OK;
}

bvox_status bvox_render(const bvox_volume *vol, const bvox_render_opts *opts, bvox_image **out,
                        bvox_preimage **pre)
{
    BVOX_CHECK_VOLUME(vol);
    return bvox__render_coloured(vol, opts, NULL, NULL, out, pre);
}

bvox_status bvox_preimage_depth_map(const bvox_preimage *pre, bvox_image **out)
{
    *out = NULL;
    if (!pre || !pre->depth || pre->width < 1 || pre->height < 1)
        return bvox__fail(BVOX_EINVAL, "depth map: not a valid pre-image");
    bvox_status st = bvox_image_create(pre->width, pre->height, 1, 16, out);
    if (st) return st;
    const size_t n = (size_t)pre->width * (size_t)pre->height;
    for (size_t i = 0; i < n; i++) {
        int32_t d = pre->depth[i];
        (*out)->pixels16[i] = d < 0 ? 0 : d >= 65534 ? 65535 : (uint16_t)(d + 1);
    }
    return BVOX_OK;
}
