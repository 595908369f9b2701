/*
 * frame.c — draws the canvas: the 3D pane (cast -> per-mode code -> table ->
 * RGB), the three orthogonal slices, the mosaic, the overlay and the help.
 *
 * The 3D pane keeps the paper's split: a cast makes a pre-image (depth and
 * normal code per pixel, bvox_surface_cast of the displayed volume's
 * boundary voxels), cropped to the pane; the library's shading stage turns
 * it into a 16-bit code per pixel for the mode (bvox_shade_codes: depth
 * levels, the normal code, gradient bins, normal and depth, the cut face)
 * and a table of 8193 colours lights the codes (bvox_shade_table_build, the
 * same lighting as `bvox render`). Turning the light only rebuilds the
 * table and re-applies it (vw_apply_lut): no cast, no per-pixel lighting.
 *
 * Pan and the centre: bvox_surface_cast centres its image on the displayed
 * volume's bounding box; the pane is centred on the model's centre at load
 * plus the pan, so the cast is made larger by twice the offset and cropped.
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const uint8_t BG[3] = {22, 26, 34};

/* drawn over the 3D pane whenever its shading is applied (below) */
static void draw_ruler_3d(vw_state *s, vw_rect r);
static void draw_scale_bar(vw_state *s, vw_rect r);

double vw_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* ------------------------------------------------------------ display */

static const bvox_volume *displayed(const vw_state *s)
{
    return s->cut_copy ? s->cut_copy : s->model;
}

/* The centre bvox_surface_cast uses: the surface's box (the whole volume
 * when empty). */
static bvox_status set_disp_center(vw_state *s)
{
    bvox_box b;
    if (!bvox_surface_bbox(s->surf, &b)) b = (bvox_box){0, 0, 0, s->dims.nx, s->dims.ny, s->dims.nz};
    const int32_t *lo = &b.x0, *hi = &b.x1;
    for (int a = 0; a < 3; a++) s->disp_center[a] = (lo[a] + hi[a] - 1) * 0.5 * s->sp[a];
    return BVOX_OK;
}

static bvox_status update_display(vw_state *s)
{
    /* only edits inside a known box, no cut: update the surface in place,
     * and forget only the smooth normals the edit can reach */
    if (s->dirty_state == 1 && !s->cut && s->surf && !s->surf_of_cut &&
        bvox_surface_update(s->surf, s->model, s->dirty) == BVOX_OK) {
        s->dirty_state = 0;
        bvox_normal_cache_clear_box(s->normals, &s->dirty);
        return set_disp_center(s);
    }
    bvox_normal_cache_clear(s->normals); /* the displayed voxels change */
    s->dirty_state = 0;
    bvox_volume_destroy(s->cut_copy);
    s->cut_copy = NULL;
    bvox_status st;
    if (s->cut) {
        double pl[4];
        vw_cut_plane_world(s, pl);
        st = bvox_volume_copy(s->model, &s->cut_copy);
        if (!st) st = bvox_cut_plane(s->cut_copy, pl[0], pl[1], pl[2], pl[3], s->keep_above, NULL);
        if (st) {
            bvox_surface_destroy(s->surf);
            s->surf = NULL;
            return st;
        }
    }
    /* a rebuild reuses the old surface's memory: no fresh pages to fault in
     * and zero on every move of the cut (a tenth of a 1024^3 build) */
    st = s->surf ? bvox_surface_rebuild(s->surf, displayed(s))
                 : bvox_surface_build(displayed(s), &s->surf);
    if (st) {
        bvox_surface_destroy(s->surf);
        s->surf = NULL;
        return st;
    }
    s->surf_of_cut = s->cut_copy != NULL;
    return set_disp_center(s);
}

static bvox_status cast_pane(vw_state *s, int w, int h)
{
    vw_3d *v = &s->view3d;
    if (v->w != w || v->h != h || !v->depth) {
        free(v->depth), free(v->ncode), free(v->code);
        size_t n = (size_t)w * (size_t)h;
        v->depth = bvox__mem_alloc(n * sizeof *v->depth);
        v->ncode = bvox__mem_alloc(n);
        v->code = bvox__mem_alloc(n * sizeof *v->code);
        v->w = w, v->h = h;
        if (!v->depth || !v->ncode || !v->code) {
            free(v->depth), free(v->ncode), free(v->code);
            v->depth = NULL, v->ncode = NULL, v->code = NULL;
            v->w = v->h = 0;
            return BVOX_ENOMEM;
        }
    }
    /* coarse (while dragging on a slow machine): cast at half the
     * resolution, each pixel shown as 2 x 2 */
    const int f = s->coarse ? 2 : 1;
    const int cw = (w + f - 1) / f, chh = (h + f - 1) / f;
    double full = s->zoom * (w < h ? w : h) / (2 * (s->radius > 0 ? s->radius : 1));
    double scale = full / f;
    double off[3];
    for (int a = 0; a < 3; a++) off[a] = s->disp_center[a] - s->center[a];
    long dx = lround((dot3(s->R, off) * full + s->pan[0]) / f);
    long dy = lround((dot3(s->R + 3, off) * full + s->pan[1]) / f);
    if (dx > 2L * cw) dx = 2L * cw;
    if (dx < -2L * cw) dx = -2L * cw;
    if (dy > 2L * chh) dy = 2L * chh;
    if (dy < -2L * chh) dy = -2L * chh;
    bvox_projection p = BVOX_PROJECTION_INIT;
    p.use_matrix = 1;
    memcpy(p.matrix, s->R, sizeof p.matrix);
    p.width = (int32_t)(cw + 2 * labs(dx));
    p.height = (int32_t)(chh + 2 * labs(dy));
    p.scale = scale;
    bvox_preimage *pre;
    bvox_status st = bvox_surface_cast(s->surf, &p, &pre);
    if (st) return st;
    long ox = labs(dx) - dx, oy = labs(dy) - dy;
    for (int y = 0; y < h; y++) {
        size_t src = (size_t)(y / f + oy) * (size_t)pre->width + (size_t)ox, dst = (size_t)y * (size_t)w;
        if (f == 1) {
            memcpy(v->depth + dst, pre->depth + src, (size_t)w * sizeof *v->depth);
            memcpy(v->ncode + dst, pre->code + src, (size_t)w);
            continue;
        }
        for (int x = 0; x < w; x++) {
            v->depth[dst + (size_t)x] = pre->depth[src + (size_t)(x / f)];
            v->ncode[dst + (size_t)x] = pre->code[src + (size_t)(x / f)];
        }
    }
    memcpy(v->eye, pre->eye, sizeof v->eye);
    double pc = pre->pixel_size[0];
    v->pixel = pc / f; /* pane pixels; depth stays in the cast's steps */
    v->step = pre->depth_step;
    v->depth_range = pre->depth_range;
    for (int a = 0; a < 3; a++)
        v->origin[a] = pre->origin[a] + ox * pc * v->eye[a] + oy * pc * v->eye[3 + a];
    v->coarse = f > 1;
    v->valid = 1;
    bvox_preimage_destroy(pre);
    return BVOX_OK;
}

/* The pane's pre-image: the cast cropped to the pane (and its pixels doubled
 * when coarse), over the pane's own arrays, for the library's shading stage. */
static void pane_preimage(const vw_state *s, bvox_preimage *p)
{
    const vw_3d *v = &s->view3d;
    memset(p, 0, sizeof *p);
    p->width = v->w, p->height = v->h;
    p->depth = v->depth, p->code = v->ncode;
    p->depth_range = v->depth_range;
    p->depth_step = v->step;
    p->pixel_size[0] = p->pixel_size[1] = v->pixel;
    memcpy(p->eye, v->eye, sizeof p->eye);
    memcpy(p->origin, v->origin, sizeof p->origin);
    memcpy(p->spacing, s->sp, sizeof p->spacing);
}

/* What the library's shading stage needs of the state: the mode, the light,
 * the depth curve, the cut plane (oriented so that the kept side is >= 0, in
 * the cast's frame), the tint and the background. */
static bvox_shade_opts shade_opts(const vw_state *s)
{
    bvox_shade_opts o = BVOX_SHADE_OPTS_INIT;
    o.mode = (bvox_shade_mode)s->shade;
    o.light = s->light;
    o.depth = s->depth;
    o.cut = s->cut;
    if (s->cut) {
        double m[3], e;
        vw_cut_plane_local(s, m, &e);
        const double k = s->keep_above ? 1 : -1;
        for (int a = 0; a < 3; a++) o.plane[a] = k * m[a];
        o.plane[3] = k * e;
    }
    memcpy(o.background, BG, 3);
    return o;
}

static void report_failure(vw_state *s, bvox_status st, const char *what)
{
    if (st) snprintf(s->status, sizeof s->status, "%s failed: %.100s", what, bvox_errmsg());
}

/* Slots for the smooth normals' cache: about 8 per boundary voxel (the 8
 * voxels around each hit point reach one voxel around the surface), a power
 * of two from 2^16 up to 2^23 (64 MiB). */
static size_t normal_cache_entries(const vw_state *s)
{
    int64_t want = 8 * (s->surf ? bvox_surface_count(s->surf) : 0);
    size_t n = (size_t)1 << 16;
    while (n < ((size_t)1 << 23) && (int64_t)n < want) n <<= 1;
    return n;
}

/* The per-pixel shading codes of the pane (a new cast, mode or cut). The
 * smooth mode reads the occupancy around each hit voxel of the volume that
 * was cast (the cut copy when cut); the other modes ignore the volume. */
static void make_codes(vw_state *s)
{
    bvox_preimage p;
    pane_preimage(s, &p);
    bvox_shade_opts o = shade_opts(s);
    s->fast_codes = o.mode == BVOX_SHADE_SMOOTH && s->view_drag && s->coarse_ms > 0 &&
                    (s->last_smooth_ms > s->coarse_ms ||
                     s->last_smooth_ms + s->last_full_cast_ms > s->drag_frame_ms);
    if (s->fast_codes) o.mode = BVOX_SHADE_GRADIENT;
    double t = vw_now();
    /* the moments of the voxels earlier frames shaded are kept: a turn of
     * the view then mostly looks them up (without the cache: only slower) */
    if (o.mode == BVOX_SHADE_SMOOTH && !s->normals &&
        bvox_normal_cache_create(normal_cache_entries(s), &s->normals))
        s->normals = NULL;
    report_failure(s, bvox_shade_codes_cached(displayed(s), &p, &o, s->normals, s->view3d.code),
                   "shading");
    if (o.mode == BVOX_SHADE_SMOOTH) s->last_smooth_ms = (vw_now() - t) * 1e3;
}

/* The colour of every code (the light, the depth curve, the tint). */
static void build_lut(vw_state *s)
{
    bvox_preimage p;
    pane_preimage(s, &p);
    bvox_shade_opts o = shade_opts(s);
    report_failure(s, bvox_shade_table_build(&p, &o, &s->lut), "shading");
}

static void apply_pane(vw_state *s, vw_rect r)
{
    const vw_3d *v = &s->view3d;
    assert(r.x >= 0 && r.y >= 0 && r.x + r.w <= s->width && r.y + r.h <= s->height);
    bvox_shade_table_apply(&s->lut, v->code, v->w < r.w ? v->w : r.w, v->h < r.h ? v->h : r.h,
                           (size_t)v->w, s->rgb + ((size_t)r.y * (size_t)s->width + (size_t)r.x) * 3,
                           (size_t)s->width * 3);
}

void vw_apply_lut(vw_state *s)
{
    vw_rect rects[4];
    vw_pane_kind kinds[4];
    int n = vw_panes(s, rects, kinds);
    build_lut(s);
    for (int i = 0; i < n; i++)
        if (kinds[i] == VW_PANE_3D && s->view3d.valid) {
            apply_pane(s, rects[i]);
            vw_labels_tint(s, rects[i]);
            draw_ruler_3d(s, rects[i]);
            if (s->overlay) draw_scale_bar(s, rects[i]);
        }
    s->need_lut = 0;
}

/* The shared cursor in the 3D pane (with the linked slices): a cross at the
 * cursor voxel's projection, solid where the voxel is in front of what the
 * pane shows there, dotted where it is hidden. */
static void draw_cursor_3d(vw_state *s, vw_rect r)
{
    static const uint8_t cur[3] = {255, 220, 0};
    const vw_3d *v = &s->view3d;
    if (!v->valid || v->pixel <= 0) return;
    double d[3];
    for (int a = 0; a < 3; a++) d[a] = s->cursor[a] * s->sp[a] - v->origin[a];
    double u = dot3(d, v->eye) / v->pixel, w = dot3(d, v->eye + 3) / v->pixel;
    double depth = dot3(d, v->eye + 6) / v->step;
    int cu = (int)lround(u), cv = (int)lround(w);
    for (int k = -8; k <= 8; k++) {
        int pts[2][2] = {{cu + k, cv}, {cu, cv + k}};
        for (int j = 0; j < 2; j++) {
            int x = pts[j][0], y = pts[j][1];
            if (x < 0 || y < 0 || x >= v->w || y >= v->h || x >= r.w || y >= r.h || (k > -2 && k < 2)) continue;
            int32_t shown = v->depth[(size_t)y * (size_t)v->w + (size_t)x];
            if (shown >= 0 && depth > shown + 1.5 && (k & 1)) continue;
            memcpy(s->rgb + ((size_t)(r.y + y) * (size_t)s->width + (size_t)(r.x + x)) * 3, cur, 3);
        }
    }
}

/* Where physical point p falls in the 3D pane: pane pixel (u, v) and the
 * depth in the cast's steps. */
static void project(const vw_3d *v, const double p[3], double *u, double *w, double *depth)
{
    double d[3];
    for (int a = 0; a < 3; a++) d[a] = p[a] - v->origin[a];
    *u = dot3(d, v->eye) / v->pixel;
    *w = dot3(d, v->eye + 3) / v->pixel;
    *depth = dot3(d, v->eye + 6) / v->step;
}

/* A line of the canvas clipped to r (Bresenham), 2 pixels wide. */
static void draw_line(vw_state *s, vw_rect r, int x0, int y0, int x1, int y1, const uint8_t c[3])
{
    int dx = abs(x1 - x0), dy = -abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (int guard = 0; guard < 100000; guard++) {
        for (int k = 0; k < 2; k++) {
            int x = x0 + (dx > -dy ? 0 : k), y = y0 + (dx > -dy ? k : 0);
            if (x >= r.x && y >= r.y && x < r.x + r.w && y < r.y + r.h)
                memcpy(s->rgb + ((size_t)y * (size_t)s->width + (size_t)x) * 3, c, 3);
        }
        if (x0 == x1 && y0 == y1) break;
        int e2 = 2 * err;
        if (e2 >= dy) err += dy, x0 += sx;
        if (e2 <= dx) err += dx, y0 += sy;
    }
}

/* The ruler in the 3D pane: its points as small squares, the line between
 * them, and the length beside the middle. */
static void draw_ruler_3d(vw_state *s, vw_rect r)
{
    static const uint8_t col[3] = {80, 255, 160};
    const vw_3d *v = &s->view3d;
    if (!s->ruler_n || !v->valid || v->pixel <= 0) return;
    int px[2], py[2];
    for (int i = 0; i < s->ruler_n; i++) {
        double p[3], u, w, d;
        for (int a = 0; a < 3; a++) p[a] = s->ruler[i][a] * s->sp[a];
        project(v, p, &u, &w, &d);
        px[i] = r.x + (int)lround(u), py[i] = r.y + (int)lround(w);
        vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){px[i] - 3, py[i] - 3, 7, 7}, col, 255);
    }
    if (s->ruler_n < 2) return;
    draw_line(s, r, px[0], py[0], px[1], py[1], col);
    char text[64];
    snprintf(text, sizeof text, "%.4g %s", vw_ruler_length(s), s->geom.unit[0] ? s->geom.unit : "units");
    vw_text(s->rgb, s->width, s->height, (px[0] + px[1]) / 2 + 8, (py[0] + py[1]) / 2 - 20, 2, text, col);
}

/* A scale bar at the bottom left of the 3D pane: a round length in the
 * volume's unit, at most a quarter of the pane wide. */
static void draw_scale_bar(vw_state *s, vw_rect r)
{
    static const uint8_t col[3] = {240, 240, 235}, shade[3] = {0, 0, 0};
    const vw_3d *v = &s->view3d;
    if (!v->valid || v->pixel <= 0 || r.w < 120 || r.h < 80) return;
    double len = vw_scale_bar_length(v->pixel, r.w / 4);
    if (len <= 0) return;
    int n = (int)lround(len / v->pixel), sc = r.w >= 600 ? 2 : 1;
    char text[48];
    snprintf(text, sizeof text, "%g %s", len, s->geom.unit[0] ? s->geom.unit : "units");
    int x = r.x + 16, y = r.y + r.h - 16 - 4 * sc, tw = vw_text_width(text, sc);
    vw_fill_rect(s->rgb, s->width, s->height,
                 (vw_rect){x - 6, y - 9 * sc - 10, (n > tw ? n : tw) + 12, 9 * sc + 10 + 4 * sc + 6}, shade, 120);
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){x, y, n, 2 * sc}, col, 255);
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){x, y - 3 * sc, sc, 5 * sc}, col, 255);
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){x + n - sc, y - 3 * sc, sc, 5 * sc}, col, 255);
    vw_text(s->rgb, s->width, s->height, x, y - 9 * sc - 4, sc, text, col);
}

/* -------------------------------------------------------------- slices */

typedef struct slice_geom {
    int u, v, flip;         /* image axes (0 x, 1 y, 2 z); flip: v grows upwards */
    int32_t nu, nv;
    double pu, pv;          /* pixels per voxel along u and v */
    double ox, oy;          /* canvas position of the image's corner */
} slice_geom;

static void slice_geometry(const vw_state *s, vw_pane_kind kind, vw_rect r, slice_geom *g)
{
    const int32_t n[3] = {s->dims.nx, s->dims.ny, s->dims.nz};
    g->u = kind == VW_PANE_YZ ? 1 : 0;
    g->v = kind == VW_PANE_XY ? 1 : 2;
    g->flip = kind != VW_PANE_XY;
    g->nu = n[g->u], g->nv = n[g->v];
    double wu = g->nu * s->sp[g->u], wv = g->nv * s->sp[g->v];
    double sc = fmin((r.w - 8) / wu, (r.h - 24) / wv);
    g->pu = sc * s->sp[g->u], g->pv = sc * s->sp[g->v];
    g->ox = r.x + (r.w - g->nu * g->pu) * 0.5;
    g->oy = r.y + 16 + (r.h - 16 - g->nv * g->pv) * 0.5;
}

/* The voxel under canvas pixel (x, y) of a slice pane; 0 outside the image. */
static int slice_voxel(const vw_state *s, vw_pane_kind kind, vw_rect r, int x, int y, int32_t out[3])
{
    slice_geom g;
    slice_geometry(s, kind, r, &g);
    double fu = (x + 0.5 - g.ox) / g.pu, fv = (y + 0.5 - g.oy) / g.pv;
    if (fu < 0 || fv < 0 || fu >= g.nu || fv >= g.nv) return 0;
    memcpy(out, s->cursor, 3 * sizeof(int32_t));
    out[g.u] = (int32_t)fu;
    out[g.v] = g.flip ? g.nv - 1 - (int32_t)fv : (int32_t)fv;
    return 1;
}

static int inside_shape(const bvox_shape *sh, const double p[3])
{
    double d[3] = {p[0] - sh->center[0], p[1] - sh->center[1], p[2] - sh->center[2]};
    switch (sh->kind) {
    case BVOX_SHAPE_SPHERE: return dot3(d, d) <= sh->radius * sh->radius;
    case BVOX_SHAPE_BOX:
        return fabs(d[0]) <= sh->semi_axes[0] && fabs(d[1]) <= sh->semi_axes[1] &&
               fabs(d[2]) <= sh->semi_axes[2];
    case BVOX_SHAPE_CYLINDER: {
        double a[3] = {sh->axis[0], sh->axis[1], sh->axis[2]}, l = sqrt(dot3(a, a));
        if (l == 0) a[0] = a[1] = 0, a[2] = 1, l = 1;
        for (int k = 0; k < 3; k++) a[k] /= l;
        double hh = dot3(d, a), r2 = dot3(d, d) - hh * hh;
        return fabs(hh) <= sh->height / 2 && r2 <= sh->radius * sh->radius;
    }
    default: return 0;
    }
}

static void draw_slice(vw_state *s, vw_pane_kind kind, vw_rect r)
{
    static const uint8_t frame_bg[3] = {12, 12, 14}, on[3] = {205, 205, 200}, off[3] = {34, 36, 46},
                         cur[3] = {255, 220, 0}, label[3] = {230, 230, 230};
    slice_geom g;
    slice_geometry(s, kind, r, &g);
    const bvox_volume *vol = displayed(s);
    bvox_shape sh;
    vw_primitive_shape(s, &sh);
    int32_t lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
    if (s->sel_n)
        for (int a = 0; a < 3; a++) {
            lo[a] = s->sel[0][a] < s->sel[1][a] ? s->sel[0][a] : s->sel[1][a];
            hi[a] = s->sel[0][a] > s->sel[1][a] ? s->sel[0][a] : s->sel[1][a];
        }
    for (int y = r.y; y < r.y + r.h; y++)
        for (int x = r.x; x < r.x + r.w; x++) {
            uint8_t *p = s->rgb + ((size_t)y * (size_t)s->width + (size_t)x) * 3;
            int32_t vx[3];
            if (!slice_voxel(s, kind, r, x, y, vx)) {
                memcpy(p, frame_bg, 3);
                continue;
            }
            const int set = bvox_volume_get(vol, vx[0], vx[1], vx[2]);
            uint8_t lab[3];
            const uint8_t *c = set ? on : off;
            if (set && s->labels && vw_label_at(s, vx, NULL, lab)) c = lab; /* its label's colour */
            int col[3] = {c[0], c[1], c[2]};
            if (vx[g.u] == s->cursor[g.u] || vx[g.v] == s->cursor[g.v])
                for (int k = 0; k < 3; k++) col[k] = (col[k] + cur[k]) / 2;
            if (s->sel_n && vx[0] >= lo[0] && vx[0] <= hi[0] && vx[1] >= lo[1] && vx[1] <= hi[1] &&
                vx[2] >= lo[2] && vx[2] <= hi[2])
                col[0] = col[0] / 2, col[1] = (col[1] + 255) / 2, col[2] = (col[2] + 255) / 2;
            if (s->prim) {
                double q[3];
                for (int a = 0; a < 3; a++) q[a] = s->geom.origin[a] + vx[a] * s->sp[a];
                if (inside_shape(&sh, q)) col[0] = (col[0] + 255) / 2, col[1] = col[1] / 2, col[2] = (col[2] + 255) / 2;
            }
            p[0] = (uint8_t)col[0], p[1] = (uint8_t)col[1], p[2] = (uint8_t)col[2];
        }
    char text[64];
    static const char *const names[] = {"3d", "xy", "xz", "yz"};
    const char ax = "xyz"[kind == VW_PANE_XY ? 2 : kind == VW_PANE_XZ ? 1 : 0];
    snprintf(text, sizeof text, "%s  %c=%d", names[kind], ax, (int)s->cursor[ax - 'x']);
    vw_text(s->rgb, s->width, s->height, r.x + 4, r.y + 4, 1, text, label);
    /* a thin border between panes */
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){r.x, r.y, 1, r.h}, label, 80);
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){r.x, r.y, r.w, 1}, label, 80);
}

int vw_pick(vw_state *s, int x, int y, int32_t hit[3])
{
    vw_rect rects[4];
    vw_pane_kind kinds[4];
    int n = vw_panes(s, rects, kinds);
    for (int i = 0; i < n; i++) {
        vw_rect r = rects[i];
        if (x < r.x || y < r.y || x >= r.x + r.w || y >= r.y + r.h) continue;
        if (kinds[i] == VW_PANE_3D) {
            if (!s->view3d.valid) return 0;
            double p0[3], dir[3];
            vw_pixel_ray(&s->view3d, x - r.x, y - r.y, p0, dir);
            return vw_pick_ray(displayed(s), s->sp, p0, dir, hit);
        }
        if (kinds[i] == VW_PANE_MOSAIC) return 0;
        return slice_voxel(s, kinds[i], r, x, y, hit);
    }
    return 0;
}

/* -------------------------------------------------------------- mosaic */

static void draw_mosaic(vw_state *s, vw_rect r)
{
    static const uint8_t label[3] = {255, 220, 0};
    if (s->need_mosaic || !s->mosaic) {
        bvox_image_destroy(s->mosaic);
        s->mosaic = NULL;
        bvox_mosaic_opts o = BVOX_MOSAIC_OPTS_INIT;
        o.planes = s->planes;
        o.display = s->mosaic_display;
        if (bvox_mosaic(s->model, &o, &s->mosaic)) s->mosaic = NULL;
        s->need_mosaic = 0;
    }
    vw_fill_rect(s->rgb, s->width, s->height, r, BG, 255);
    const bvox_image *m = s->mosaic;
    if (m) {
        double sc = fmin((double)r.w / m->width, (double)(r.h - 20) / m->height);
        int iw = (int)(m->width * sc), ih = (int)(m->height * sc);
        int ox = r.x + (r.w - iw) / 2, oy = r.y + (r.h - 20 - ih) / 2;
        for (int y = 0; y < ih; y++) {
            int sy = (int)((y + 0.5) / sc);
            sy = sy >= m->height ? m->height - 1 : sy;
            uint8_t *dst = s->rgb + ((size_t)(oy + y) * (size_t)s->width + (size_t)ox) * 3;
            for (int x = 0; x < iw; x++, dst += 3) {
                int sx = (int)((x + 0.5) / sc);
                sx = sx >= m->width ? m->width - 1 : sx;
                uint8_t g8 = m->pixels[((size_t)sy * (size_t)m->width + (size_t)sx) * (size_t)m->channels];
                dst[0] = dst[1] = dst[2] = g8;
            }
        }
    }
    char text[96], bits[9];
    for (int b = 0; b < 8; b++) bits[b] = s->planes >> b & 1 ? (char)('1' + b) : '-';
    bits[8] = 0;
    snprintf(text, sizeof text, "mosaic  planes %s  %s", bits, bvox_mosaic_display_name(s->mosaic_display));
    vw_text(s->rgb, s->width, s->height, r.x + 6, r.y + r.h - 20, 2, text, label);
}

/* ------------------------------------------------------ overlay, help */

static void draw_overlay(vw_state *s)
{
    static const uint8_t shade[3] = {0, 0, 0}, fg[3] = {235, 235, 225}, hi[3] = {255, 210, 80};
    static const char *const shades[] = {"depth", "binary gradient", "gradient from depth", "combined",
                                           "smooth"};
    static const char *const prims[] = {"", "sphere", "box", "cylinder"};
    int sc = s->layout != VW_LAYOUT_ORTHO && s->width >= 700 ? 2 : 1;
    char l[7][160];
    double vox = s->sp[0] * s->sp[1] * s->sp[2];
    const char *unit = s->geom.unit[0] ? s->geom.unit : "units";
    snprintf(l[0], sizeof l[0], "%dx%dx%d  %lld voxels  %.6g %s^3", (int)s->dims.nx, (int)s->dims.ny,
             (int)s->dims.nz, (long long)s->count, (double)s->count * vox, unit);
    char fps[32];
    if (s->fps >= 0) snprintf(fps, sizeof fps, "%.1f fps", s->fps);
    else snprintf(fps, sizeof fps, "script");
    snprintf(l[1], sizeof l[1], "%s  %s  light %.0f/%.0f  zoom %.2f", fps, shades[s->shade],
             s->light.azimuth, s->light.elevation, s->zoom);
    int k = 0;
    char *t = l[2];
    size_t cap = sizeof l[2];
    k += snprintf(t + k, cap - (size_t)k, "cursor %d,%d,%d", (int)s->cursor[0], (int)s->cursor[1],
                  (int)s->cursor[2]);
    if (s->brush)
        k += snprintf(t + k, cap - (size_t)k, "  brush %s r=%d", s->brush_add ? "add" : "remove", s->brush_radius);
    if (s->cut) k += snprintf(t + k, cap - (size_t)k, "  cut keeps %s", s->keep_above ? "far" : "near");
    if (s->prim && k < (int)cap)
        k += snprintf(t + k, cap - (size_t)k, "  %s %d", prims[s->prim], s->prim_size);
    if (s->labels && k < (int)cap) {
        const char *name;
        int64_t lab = vw_label_at(s, s->cursor, &name, NULL);
        if (lab) k += snprintf(t + k, cap - (size_t)k, "  label %lld %s", (long long)lab, name);
    }
    int extra = 0;
    char *m = l[4];
    if (s->sel_n) {
        bvox_box b;
        int64_t cnt = 0;
        double vol = 0;
        vw_selection_box(s, &b);
        if (vw_selection_volume(s, &cnt, &vol) == BVOX_OK)
            snprintf(m, sizeof l[4], "box %dx%dx%d: %lld voxels = %.6g %s^3", (int)(b.x1 - b.x0),
                     (int)(b.y1 - b.y0), (int)(b.z1 - b.z0), (long long)cnt, vol, unit);
        else snprintf(m, sizeof l[4], "box: cannot count (%.80s)", bvox_errmsg());
        m = l[4 + ++extra];
    }
    if (s->ruler_n == 2)
        snprintf(m, sizeof l[4], "ruler %.6g %s  (%d,%d,%d to %d,%d,%d)", vw_ruler_length(s), unit,
                 (int)s->ruler[0][0], (int)s->ruler[0][1], (int)s->ruler[0][2], (int)s->ruler[1][0],
                 (int)s->ruler[1][1], (int)s->ruler[1][2]), extra++;
    else if (s->ruler_n == 1)
        snprintf(m, sizeof l[4], "ruler from %d,%d,%d: g at the second point", (int)s->ruler[0][0],
                 (int)s->ruler[0][1], (int)s->ruler[0][2]), extra++;
    snprintf(l[3], sizeof l[3], "undo %d (%.1f KiB)   h: help", bvox_journal_steps(s->journal),
             bvox_journal_bytes(s->journal) / 1024.0);
    snprintf(l[4 + extra], sizeof l[4], "%s", s->status);
    int lines = 4 + extra + (s->status[0] ? 1 : 0), wmax = 0;
    for (int i = 0; i < lines; i++) {
        int w = vw_text_width(l[i], sc);
        wmax = w > wmax ? w : wmax;
    }
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){0, 0, wmax + 12 * sc / 2 + 8, lines * 9 * sc + 8},
                 shade, 150);
    for (int i = 0; i < lines; i++)
        vw_text(s->rgb, s->width, s->height, 6, 5 + i * 9 * sc, sc, l[i], i == 4 + extra ? hi : fg);
}

static void draw_help(vw_state *s)
{
    static const uint8_t shade[3] = {0, 0, 0}, fg[3] = {240, 240, 230}, title[3] = {255, 210, 80};
    int longest = 0;
    for (int i = 0; vw_help_lines[i]; i++) {
        int w = vw_text_width(vw_help_lines[i], 1);
        longest = w > longest ? w : longest;
    }
    int n = 0;
    while (vw_help_lines[n]) n++;
    int sc = longest * 2 + 24 <= s->width && n * 20 + 24 <= s->height ? 2 : 1;
    vw_fill_rect(s->rgb, s->width, s->height, (vw_rect){0, 0, s->width, s->height}, shade, 215);
    for (int i = 0; i < n; i++)
        vw_text(s->rgb, s->width, s->height, 12, 12 + i * 10 * sc, sc, vw_help_lines[i], i ? fg : title);
}

/* --------------------------------------------------------------- frame */

bvox_status vw_render(vw_state *s)
{
    assert(vw_state_ok(s));
    double t0 = vw_now(), t;
    bvox_status st;
    memset(&s->times, 0, sizeof s->times);
    if (s->need_surface || !s->surf) {
        st = update_display(s);
        if (st) return st;
        s->need_surface = 0;
        s->need_cast = 1;
    }
    t = vw_now();
    s->times.surface = (t - t0) * 1e3;
    vw_rect rects[4];
    vw_pane_kind kinds[4];
    int n = vw_panes(s, rects, kinds);
    for (int i = 0; i < n; i++) {
        if (kinds[i] != VW_PANE_3D) continue;
        double a = vw_now();
        if (s->need_cast || s->view3d.w != rects[i].w || s->view3d.h != rects[i].h) {
            st = cast_pane(s, rects[i].w, rects[i].h);
            if (st) return st;
            s->need_cast = 0;
            s->need_code = 1;
        }
        double b = vw_now();
        if (s->need_code) {
            make_codes(s);
            vw_labels_pixels(s); /* the label each pixel shows, once per cast */
            s->need_code = 0;
            s->need_lut = 1;
        }
        double c = vw_now();
        build_lut(s); /* the light may have changed: tables are cheap */
        apply_pane(s, rects[i]);
        vw_labels_tint(s, rects[i]);
        if (s->layout == VW_LAYOUT_ORTHO) draw_cursor_3d(s, rects[i]);
        draw_ruler_3d(s, rects[i]);
        if (s->overlay) draw_scale_bar(s, rects[i]);
        s->need_lut = 0;
        double d = vw_now();
        s->times.cast = (b - a) * 1e3;
        if (b > a && !s->view3d.coarse && s->times.cast > 0.001) s->last_full_cast_ms = s->times.cast;
        s->times.code = (c - b) * 1e3;
        s->times.lut = (d - c) * 1e3;
    }
    double c0 = vw_now();
    for (int i = 0; i < n; i++) {
        if (kinds[i] == VW_PANE_XY || kinds[i] == VW_PANE_XZ || kinds[i] == VW_PANE_YZ)
            draw_slice(s, kinds[i], rects[i]);
        else if (kinds[i] == VW_PANE_MOSAIC) draw_mosaic(s, rects[i]);
    }
    if (s->overlay) draw_overlay(s);
    if (s->help) draw_help(s);
    double end = vw_now();
    s->times.compose = (end - c0) * 1e3;
    s->times.total = (end - t0) * 1e3;
    assert(vw_state_ok(s));
    return BVOX_OK;
}
