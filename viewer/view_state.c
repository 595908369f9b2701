/*
 * view_state.c — the viewer's state and the geometry every other part reads
 * from it: open/close, the camera (trackball, axis and isometric views), the
 * cut plane, the panes of the layout, the primitive's shape, the canvas as
 * an image, and the help text. It calls no other file of the viewer: edits.c,
 * frame.c and input.c build on it (input.c, the event handler, on all three),
 * so the files form layers, not a circle.
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const vw_help_lines[] = {
    "bvox view: keys and mouse (any key closes)",
    "left drag       rotate (trackball)",
    "right drag      pan          wheel, + -  zoom",
    "1 2 3 4 5 6     views +x -x +y -y +z -z",
    "i / I           isometric views    r  reset view",
    "arrows          turn the light (table only)",
    "shift+left drag turn the light (or middle drag)",
    "l               reset the light",
    "s / S           shading: depth, binary gradient,",
    "                gradient from depth, combined,",
    "                smooth (normals of the voxels)",
    "c               cut plane on/off (facing you)",
    "pageup pagedown move the plane (shift: 1 voxel)",
    "t T y Y         tilt the plane",
    "f               keep the other side",
    "a               apply the cut to the model",
    "o               orthogonal views xy xz yz",
    "click           move the cursor (any view)",
    "m               mosaic: 1..8 bit planes, n display",
    "e               brush on/off: click/drag edits",
    "x               brush adds / removes   [ ]  radius",
    "b / B           selection corner 1 / 2 at cursor",
    "                (its volume shows in the overlay)",
    "g               ruler: mark the cursor (twice)",
    "ctrl+drag       select a box in a slice (all depth)",
    "delete / k      remove / keep the selection box",
    "escape          drop the selection and primitive",
    "p               primitive: sphere, box, cylinder",
    ", .             its size   u union   d difference",
    "ctrl+z ctrl+y   undo / redo",
    "ctrl+s          save the model",
    "f12 ctrl+p      screenshot    v  overlay on/off",
    "drop a file     open it; drag a corner: resize",
    "h ? f1          this help     q  quit",
    NULL};

/* ---------------------------------------------------------------- math */

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void unit(double v[3])
{
    double l = sqrt(dot3(v, v));
    if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

void vw_orthonormalize(double R[9])
{
    double *r = R, *dn = R + 3, *v = R + 6;
    unit(v);
    double k = dot3(dn, v);
    for (int a = 0; a < 3; a++) dn[a] -= k * v[a];
    unit(dn);
    cross(dn, v, r); /* right = down x view */
}

/* R = Q(axis, angle) R: the object turns by angle about axis (eye frame). */
void vw_rotate(double R[9], const double axis_in[3], double angle)
{
    double a[3] = {axis_in[0], axis_in[1], axis_in[2]};
    unit(a);
    double c = cos(angle), s = sin(angle), t = 1 - c;
    double Q[9] = {t * a[0] * a[0] + c,        t * a[0] * a[1] - s * a[2], t * a[0] * a[2] + s * a[1],
                   t * a[0] * a[1] + s * a[2], t * a[1] * a[1] + c,        t * a[1] * a[2] - s * a[0],
                   t * a[0] * a[2] - s * a[1], t * a[1] * a[2] + s * a[0], t * a[2] * a[2] + c};
    double out[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i * 3 + j] = Q[i * 3] * R[j] + Q[i * 3 + 1] * R[3 + j] + Q[i * 3 + 2] * R[6 + j];
    memcpy(R, out, sizeof out);
    vw_orthonormalize(R);
}

/* A point of the pane on the trackball sphere (eye frame: right, down, view;
 * the sphere's front faces the viewer, so its view component is negative). */
static void ball(double x, double y, int w, int h, double p[3])
{
    double r = 0.5 * (w < h ? w : h);
    double a = (x - 0.5 * w) / r, b = (y - 0.5 * h) / r, d2 = a * a + b * b;
    p[0] = a;
    p[1] = b;
    p[2] = d2 <= 0.5 ? -sqrt(1 - d2) : -0.5 / sqrt(d2); /* sphere, then hyperbola */
    unit(p);
}

void vw_trackball(double R[9], double x0, double y0, double x1, double y1, int w, int h)
{
    double p0[3], p1[3], axis[3];
    ball(x0, y0, w, h, p0);
    ball(x1, y1, w, h, p1);
    cross(p0, p1, axis);
    double s = sqrt(dot3(axis, axis)), c = dot3(p0, p1);
    if (s < 1e-12) return;
    /* Turning the object by Q about axis maps p0 to p1: x_eye' = Q x_eye,
     * so the camera rows become Q R. */
    vw_rotate(R, axis, atan2(s, c));
}

/* down = d, view = v (world); right = down x view. */
static void set_frame(double R[9], const double down[3], const double view[3])
{
    memcpy(R + 3, down, 3 * sizeof(double));
    memcpy(R + 6, view, 3 * sizeof(double));
    vw_orthonormalize(R);
}

void vw_set_axis_view(vw_state *s, bvox_view view)
{
    double v[3] = {0, 0, 0}, down[3] = {0, 0, -1};
    int axis = view / 2, sign = view % 2 ? -1 : 1;
    v[axis] = sign;
    if (axis == 2) down[1] = 1, down[2] = 0; /* +-z: y down, as the axis images */
    set_frame(s->R, down, v);
    s->pan[0] = s->pan[1] = 0;
    s->need_cast = 1;
}

void vw_set_iso_view(vw_state *s, int corner)
{
    double v[3] = {corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1};
    for (int a = 0; a < 3; a++) v[a] = -v[a] / sqrt(3.0); /* from the corner to the centre */
    double down[3] = {0, 0, -1};                          /* z up */
    set_frame(s->R, down, v);
    s->pan[0] = s->pan[1] = 0;
    s->need_cast = 1;
}

void vw_cut_plane_local(const vw_state *s, double m[3], double *e)
{
    memcpy(m, s->cut_n, 3 * sizeof(double));
    double p0[3];
    for (int a = 0; a < 3; a++) p0[a] = s->center[a] + s->cut_s * m[a];
    *e = -dot3(m, p0);
}

void vw_cut_plane_world(const vw_state *s, double plane[4])
{
    double m[3], e;
    vw_cut_plane_local(s, m, &e);
    /* world = origin + D q: m . q + e = (D m) . w - (D m) . origin + e */
    const double *D = s->geom.direction, *o = s->geom.origin;
    double n[3];
    for (int i = 0; i < 3; i++) n[i] = D[i * 3] * m[0] + D[i * 3 + 1] * m[1] + D[i * 3 + 2] * m[2];
    plane[0] = n[0], plane[1] = n[1], plane[2] = n[2];
    plane[3] = e - dot3(n, o);
}

void vw_cut_tilt(vw_state *s, const double *axis_world, double angle)
{
    double a[3] = {axis_world[0], axis_world[1], axis_world[2]}, n[3];
    unit(a);
    double c = cos(angle), sn = sin(angle), k = dot3(a, s->cut_n), x[3];
    cross(a, s->cut_n, x);
    for (int i = 0; i < 3; i++) n[i] = s->cut_n[i] * c + x[i] * sn + a[i] * k * (1 - c);
    unit(n);
    memcpy(s->cut_n, n, sizeof n);
    s->need_surface = 1;
}

/* ------------------------------------------------- layout, shapes, canvas */

int vw_panes(const vw_state *s, vw_rect rects[4], vw_pane_kind kinds[4])
{
    int W = s->width, H = s->height, w2 = W / 2, h2 = H / 2;
    switch (s->layout) {
    case VW_LAYOUT_ORTHO:
        rects[0] = (vw_rect){0, 0, w2, h2}, kinds[0] = VW_PANE_3D;
        rects[1] = (vw_rect){w2, 0, W - w2, h2}, kinds[1] = VW_PANE_XY;
        rects[2] = (vw_rect){0, h2, w2, H - h2}, kinds[2] = VW_PANE_XZ;
        rects[3] = (vw_rect){w2, h2, W - w2, H - h2}, kinds[3] = VW_PANE_YZ;
        return 4;
    case VW_LAYOUT_MOSAIC:
        rects[0] = (vw_rect){0, 0, W, H}, kinds[0] = VW_PANE_MOSAIC;
        return 1;
    default:
        rects[0] = (vw_rect){0, 0, W, H}, kinds[0] = VW_PANE_3D;
        return 1;
    }
}

double vw_min_spacing(const vw_state *s)
{
    return fmin(s->sp[0], fmin(s->sp[1], s->sp[2]));
}

void vw_primitive_shape(const vw_state *s, bvox_shape *sh)
{
    memset(sh, 0, sizeof *sh);
    double r = s->prim_size * vw_min_spacing(s);
    for (int a = 0; a < 3; a++) sh->center[a] = s->geom.origin[a] + s->cursor[a] * s->sp[a];
    switch (s->prim) {
    case VW_PRIM_BOX:
        sh->kind = BVOX_SHAPE_BOX;
        sh->semi_axes[0] = sh->semi_axes[1] = sh->semi_axes[2] = r;
        break;
    case VW_PRIM_CYLINDER:
        sh->kind = BVOX_SHAPE_CYLINDER;
        sh->radius = r;
        sh->height = 4 * r;
        memcpy(sh->axis, s->R + 6, sizeof sh->axis); /* along the view: a drill */
        break;
    default:
        sh->kind = BVOX_SHAPE_SPHERE;
        sh->radius = r;
        break;
    }
}

bvox_status vw_canvas_image(const vw_state *s, bvox_image **out)
{
    bvox_status st = bvox_image_create(s->width, s->height, 3, 8, out);
    if (st) return st;
    memcpy((*out)->pixels, s->rgb, (size_t)s->width * (size_t)s->height * 3);
    return BVOX_OK;
}

/* ------------------------------------------------------------ invariants */

int vw_state_ok(const vw_state *s)
{
    if (!s || !s->model || !s->rgb || !s->journal || s->width < 64 || s->height < 64) return 0;
    for (int i = 0; i < 3; i++) /* the camera stays a rotation */
        for (int j = 0; j < 3; j++) {
            double d = s->R[i * 3] * s->R[j * 3] + s->R[i * 3 + 1] * s->R[j * 3 + 1] +
                       s->R[i * 3 + 2] * s->R[j * 3 + 2];
            if (!(fabs(d - (i == j)) < 1e-6)) return 0;
        }
    if (!(s->zoom > 0) || (unsigned)s->shade >= VW_NSHADE || (unsigned)s->layout > VW_LAYOUT_MOSAIC ||
        (unsigned)s->prim >= VW_NPRIM || s->sel_n < 0 || s->sel_n > 2 || s->ruler_n < 0 ||
        s->ruler_n > 2)
        return 0;
    const int32_t n[3] = {s->dims.nx, s->dims.ny, s->dims.nz};
    for (int a = 0; a < 3; a++)
        if (s->cursor[a] < 0 || s->cursor[a] >= n[a] || !(s->sp[a] > 0)) return 0;
    if (s->cut && !(fabs(dot3(s->cut_n, s->cut_n) - 1) < 1e-6)) return 0;
    const vw_3d *v = &s->view3d; /* the pane's arrays exist together, of w x h */
    if ((v->depth != NULL) != (v->w > 0) || (v->ncode != NULL) != (v->w > 0) ||
        (v->code != NULL) != (v->w > 0) || v->w < 0 || v->h < 0)
        return 0;
    return !v->valid || (v->depth && v->pixel > 0 && v->step > 0);
}

/* ------------------------------------------------------------ open/close */

/* Take model as the state's: its geometry, centre and size, the cursor at
 * its centre, a fresh journal; nothing else of s is touched. */
static bvox_status take_model(vw_state *s, bvox_volume *model)
{
    bvox_journal *j = NULL;
    bvox_dims d = bvox_volume_dims(model);
    bvox_status st = bvox_journal_create(d, bvox_memory_budget() / 4, &j);
    if (st) return st;
    bvox_journal_destroy(s->journal);
    s->journal = j;
    s->model = model;
    s->dims = d;
    s->geom = *bvox_volume_geometry(model);
    memcpy(s->sp, s->geom.spacing, sizeof s->sp);
    bvox_box b;
    if (!bvox_volume_bbox(model, &b)) b = (bvox_box){0, 0, 0, s->dims.nx, s->dims.ny, s->dims.nz};
    double ext2 = 0;
    const int32_t *lo = &b.x0, *hi = &b.x1;
    for (int a = 0; a < 3; a++) {
        s->center[a] = (lo[a] + hi[a] - 1) * 0.5 * s->sp[a];
        double e = (hi[a] - lo[a]) * s->sp[a];
        ext2 += e * e;
    }
    s->radius = 0.5 * sqrt(ext2);
    for (int a = 0; a < 3; a++) s->cursor[a] = (lo[a] + hi[a]) / 2;
    s->count = bvox_volume_count(model);
    return BVOX_OK;
}

bvox_status vw_open(bvox_volume *model, int width, int height, vw_state **out)
{
    *out = NULL;
    if (!model || width < 64 || height < 64 || width > 8192 || height > 8192) {
        bvox_volume_destroy(model);
        return BVOX_EINVAL;
    }
    vw_state *s = bvox__mem_zalloc(1, sizeof *s);
    if (!s) {
        bvox_volume_destroy(model);
        return BVOX_ENOMEM;
    }
    bvox_status st = take_model(s, model);
    if (st) {
        bvox_volume_destroy(model);
        free(s);
        return st;
    }
    s->width = width;
    s->height = height;
    s->rgb = bvox__mem_zalloc((size_t)width * (size_t)height, 3);
    if (!s->rgb) {
        vw_close(s);
        return BVOX_ENOMEM;
    }
    s->zoom = 1;
    s->iso = 7;
    vw_set_iso_view(s, s->iso);
    s->light = (bvox_light)BVOX_LIGHT_INIT;
    s->depth = (bvox_depth_shading)BVOX_DEPTH_SHADING_INIT;
    s->shade = VW_SHADE_COMBINED;
    s->overlay = 1;
    s->planes = 0xff;
    s->mosaic_display = BVOX_MOSAIC_COUNT;
    s->brush_radius = 3;
    s->prim_size = 8;
    s->fps = -1;
    s->coarse_ms = 25; /* below 40 fps of casts, drag at half resolution */
    s->drag_frame_ms = 1000.0 / 60; /* smooth mode: stand-in codes while turning */
    s->save_path = "bvox-view-model.nii.gz";
    s->need_surface = s->need_cast = s->need_code = s->need_lut = s->need_mosaic = 1;
    *out = s;
    return BVOX_OK;
}

bvox_status vw_replace_model(vw_state *s, bvox_volume *model)
{
    bvox_volume *old = s->model;
    bvox_status st = take_model(s, model);
    if (st) {
        bvox_volume_destroy(model);
        return st;
    }
    bvox_volume_destroy(old);
    bvox_volume_destroy(s->cut_copy);
    s->cut_copy = NULL;
    bvox_surface_destroy(s->surf);
    s->surf = NULL;
    bvox_image_destroy(s->mosaic);
    s->mosaic = NULL;
    vw_labels_free(s->labels);
    s->labels = NULL;
    s->cut = 0;
    s->sel_n = 0;
    s->ruler_n = 0;
    s->sel_count_ok = 0;
    s->dirty_state = 0;
    s->zoom = 1;
    s->pan[0] = s->pan[1] = 0;
    s->need_surface = s->need_cast = s->need_code = s->need_lut = s->need_mosaic = 1;
    return BVOX_OK;
}

bvox_status vw_resize(vw_state *s, int width, int height)
{
    if (width < 64 || height < 64 || width > 8192 || height > 8192) return BVOX_EINVAL;
    if (width == s->width && height == s->height) return BVOX_OK;
    uint8_t *rgb = bvox__mem_zalloc((size_t)width * (size_t)height, 3);
    if (!rgb) return BVOX_ENOMEM;
    free(s->rgb);
    s->rgb = rgb;
    s->width = width;
    s->height = height;
    s->need_cast = 1; /* the 3D pane's pre-image follows its new size */
    return BVOX_OK;
}

void vw_close(vw_state *s)
{
    if (!s) return;
    vw_labels_free(s->labels);
    bvox_volume_destroy(s->model);
    bvox_volume_destroy(s->cut_copy);
    bvox_surface_destroy(s->surf);
    bvox_normal_cache_destroy(s->normals);
    bvox_journal_destroy(s->journal);
    bvox_image_destroy(s->mosaic);
    free(s->view3d.depth);
    free(s->view3d.ncode);
    free(s->view3d.code);
    free(s->rgb);
    free(s);
}

/* The names the overlay's bench line, `bvox view --shade` and scripts use. */
static const char *const shade_names[VW_NSHADE] = {"depth", "binary", "gradient", "combined", "smooth"};

const char *vw_shade_name(vw_shade shade)
{
    return (unsigned)shade < VW_NSHADE ? shade_names[shade] : "?";
}

int vw_shade_parse(const char *name)
{
    for (int i = 0; i < VW_NSHADE; i++)
        if (!strcmp(name, shade_names[i])) return i;
    int m = bvox_shade_mode_parse(name); /* "binary+depth" */
    return m >= 0 && m < VW_NSHADE ? m : -1;
}
