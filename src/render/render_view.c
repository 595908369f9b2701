/*
 * render_view.c — the views of bvox_render: its options and their checks,
 * view names ("+z", "AZ,EL", "iso", "iso+x-y+z"), and the frames (rows right,
 * down, view) of axis views, isometric presets, stereo eyes and turntable
 * frames. Pure geometry: nothing here casts.
 */
#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double deg = 3.14159265358979323846 / 180.0;

static const char *const shade_names[] = {"depth", "binary", "gradient", "binary+depth",
                                           "smooth", "binary-preimage", "enlarged-gradient"};
#define NSHADES (int)(sizeof shade_names / sizeof shade_names[0])

const char *bvox_shade_mode_name(bvox_shade_mode mode)
{
    return (unsigned)mode < (unsigned)NSHADES ? shade_names[mode] : "unknown";
}

int bvox_shade_mode_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < NSHADES; i++)
        if (!strcmp(name, shade_names[i])) return i;
    return -1;
}

bvox_render_opts bvox_render_opts_default(void)
{
    bvox_render_opts o;
    memset(&o, 0, sizeof o);
    o.axis_view = 1;
    o.view = BVOX_VIEW_POS_Z;
    o.proj = (bvox_projection)BVOX_PROJECTION_INIT;
    o.shade = BVOX_SHADE_BINARY_DEPTH;
    o.light = (bvox_light)BVOX_LIGHT_INIT;
    o.depth = (bvox_depth_shading)BVOX_DEPTH_SHADING_INIT;
    o.zoom = 1;
    o.filter = -1;
    o.keep_above = 1;
    o.cut_color[0] = 255, o.cut_color[1] = 176, o.cut_color[2] = 96;
    o.stereo = BVOX_STEREO_NONE;
    o.stereo_angle = 3.0;
    return o;
}

bvox_status bvox__render_opts_check(const bvox_render_opts *o)
{
    if (!o) return bvox__fail(BVOX_EINVAL, "render: no options");
    if (o->axis_view && (unsigned)o->view >= 6u)
        return bvox__fail(BVOX_EINVAL, "render: unknown axis view %d", (int)o->view);
    if ((unsigned)o->shade >= (unsigned)NSHADES)
        return bvox__fail(BVOX_EINVAL, "render: unknown shading %d", (int)o->shade);
    if (o->zoom != 0 && o->zoom != 1 && o->zoom != 2 && o->zoom != 4 && o->zoom != 8)
        return bvox__fail(BVOX_EINVAL, "render: zoom %d is not 1, 2, 4 or 8", o->zoom);
    if (o->filter < -1 || o->filter > BVOX_FILTER_SOBEL)
        return bvox__fail(BVOX_EINVAL, "render: unknown filter %d", o->filter);
    if ((unsigned)o->stereo > (unsigned)BVOX_STEREO_ANAGLYPH)
        return bvox__fail(BVOX_EINVAL, "render: unknown stereo mode %d", (int)o->stereo);
    if (o->stereo && !(o->stereo_angle >= 0 && o->stereo_angle <= 45))
        return bvox__fail(BVOX_EINVAL, "render: stereo angle must be in 0..45 degrees");
    if (o->proj.width < 0 || o->proj.height < 0 || o->proj.width > BVOX_IMAGE_MAX_DIM ||
        o->proj.height > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "render: image size %d x %d is outside 0..%d",
                          (int)o->proj.width, (int)o->proj.height, BVOX_IMAGE_MAX_DIM);
    if (o->smooth_radius < 0 || o->smooth_radius > 3)
        return bvox__fail(BVOX_EINVAL, "render: smooth radius %d is not 1, 2 or 3 (0: 2)",
                          o->smooth_radius);
    if (o->supersample < 0 || o->supersample > 4)
        return bvox__fail(BVOX_EINVAL, "render: supersample %d is outside 1..4", o->supersample);
    if ((o->ao != 0 && o->ao != 1) || (o->shadows != 0 && o->shadows != 1))
        return bvox__fail(BVOX_EINVAL, "render: ao and shadows are 0 or 1");
    if (o->transparent && o->stereo == BVOX_STEREO_ANAGLYPH)
        return bvox__fail(BVOX_EINVAL, "render: an anaglyph cannot have a transparent background");
    if (o->title && strlen(o->title) > 200)
        return bvox__fail(BVOX_EINVAL, "render: a title of more than 200 characters");
    bvox_status st = bvox__light_check(&o->light);
    if (st) return st;
    if (o->cut) {
        for (int k = 0; k < 4; k++)
            if (!isfinite(o->plane[k]))
                return bvox__fail(BVOX_EINVAL, "render: the cut plane is not finite");
        if (!o->plane[0] && !o->plane[1] && !o->plane[2])
            return bvox__fail(BVOX_EINVAL, "render: the cut plane's normal is zero");
    }
    return BVOX_OK;
}

void bvox__axis_frame(bvox_view view, double f[9])
{
    /* as bvox_cast_axis: image axes the two other axes in increasing order */
    const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
    const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
    memset(f, 0, 9 * sizeof *f);
    f[0 + cu] = 1;
    f[3 + cv] = 1;
    f[6 + axis] = dir;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double normalize3(double *v)
{
    double n = sqrt(dot3(v, v));
    if (n > 0) v[0] /= n, v[1] /= n, v[2] /= n;
    return n;
}

bvox_status bvox__opts_frame(const bvox_render_opts *o, double f[9])
{
    if (o->axis_view) {
        bvox__axis_frame(o->view, f);
        return BVOX_OK;
    }
    const bvox_projection *p = &o->proj;
    if (!p->use_matrix) {
        if (!isfinite(p->azimuth) || !isfinite(p->elevation))
            return bvox__fail(BVOX_EINVAL, "render: view angles must be finite");
        /* bvox_projection's formulas */
        double az = p->azimuth * deg, el = p->elevation * deg;
        double r[3] = {cos(az), 0, -sin(az)}, d[3] = {sin(az) * cos(el), sin(el), cos(az) * cos(el)};
        memcpy(f, r, sizeof r);
        memcpy(f + 6, d, sizeof d);
        f[3] = d[1] * r[2] - d[2] * r[1];
        f[4] = d[2] * r[0] - d[0] * r[2];
        f[5] = d[0] * r[1] - d[1] * r[0];
        return BVOX_OK;
    }
    for (int i = 0; i < 9; i++)
        if (!isfinite(p->matrix[i])) return bvox__fail(BVOX_EINVAL, "render: matrix is not finite");
    memcpy(f, p->matrix, 9 * sizeof *f);
    /* Gram-Schmidt in the order right, down, view, as the caster does */
    double l0 = normalize3(f);
    double k = dot3(f + 3, f);
    for (int a = 0; a < 3; a++) f[3 + a] -= k * f[a];
    double l1 = normalize3(f + 3);
    double k1 = dot3(f + 6, f), k2 = dot3(f + 6, f + 3);
    for (int a = 0; a < 3; a++) f[6 + a] -= k1 * f[a] + k2 * f[3 + a];
    double l2 = normalize3(f + 6);
    if (!(l0 > 1e-9 && l1 > 1e-9 && l2 > 1e-9))
        return bvox__fail(BVOX_EINVAL, "render: the matrix rows are not independent");
    return BVOX_OK;
}

void bvox__frame_turn(double f[9], double degrees)
{
    /* right and view turn in their own plane; down (the vertical) stays */
    double c = cos(degrees * deg), s = sin(degrees * deg);
    for (int a = 0; a < 3; a++) {
        double r = f[a], v = f[6 + a];
        f[a] = r * c - v * s;
        f[6 + a] = v * c + r * s;
    }
}

/* The isometric frame looking from the corner (sx, sy, sz) (each +-1)
 * towards the centre, with +z up on the screen. */
static void iso_frame(const int sgn[3], double f[9])
{
    const double r3 = 1.0 / sqrt(3.0);
    double *right = f, *down = f + 3, *view = f + 6;
    for (int a = 0; a < 3; a++) view[a] = -sgn[a] * r3;
    /* down = -(ez minus its component along the view), normalised */
    for (int a = 0; a < 3; a++) down[a] = -((a == 2) - view[2] * view[a]);
    normalize3(down);
    /* right = down x view, so that right x down = view */
    right[0] = down[1] * view[2] - down[2] * view[1];
    right[1] = down[2] * view[0] - down[0] * view[2];
    right[2] = down[0] * view[1] - down[1] * view[0];
}

bvox_status bvox_render_parse_view(const char *text, bvox_render_opts *opts)
{
    if (!text || !opts) return bvox__fail(BVOX_EINVAL, "view: no text");
    int v = bvox_view_parse(text);
    if (v >= 0) {
        opts->axis_view = 1;
        opts->view = (bvox_view)v;
        return BVOX_OK;
    }
    if (!strncmp(text, "iso", 3)) {
        int sgn[3] = {1, 1, 1};
        const char *p = text + 3;
        if (*p) {
            for (int a = 0; a < 3; a++, p += 2) {
                if ((p[0] != '+' && p[0] != '-') || p[1] != "xyz"[a])
                    return bvox__fail(BVOX_EINVAL,
                                      "view '%s': write iso or iso with three signs, "
                                      "e.g. iso+x-y+z",
                                      text);
                sgn[a] = p[0] == '+' ? 1 : -1;
            }
            if (*p) return bvox__fail(BVOX_EINVAL, "view '%s': text after iso+x+y+z", text);
        }
        opts->axis_view = 0;
        opts->proj.use_matrix = 1;
        iso_frame(sgn, opts->proj.matrix);
        return BVOX_OK;
    }
    /* AZ,EL */
    const char *comma = strchr(text, ',');
    if (comma && !strchr(comma + 1, ',')) {
        char *end;
        double az = strtod(text, &end);
        if (end == comma && end != text) {
            double el = strtod(comma + 1, &end);
            if (*end == '\0' && end != comma + 1 && isfinite(az) && isfinite(el)) {
                opts->axis_view = 0;
                opts->proj.use_matrix = 0;
                opts->proj.azimuth = az;
                opts->proj.elevation = el;
                return BVOX_OK;
            }
        }
    }
    return bvox__fail(BVOX_EINVAL,
                      "view '%s' is not +x, -x, +y, -y, +z, -z, iso, iso+x+y+z (any signs) "
                      "or AZ,EL in degrees",
                      text);
}

bvox_status bvox_turntable_view(const bvox_render_opts *opts, int i, int n,
                                bvox_render_opts *frame_opts)
{
    bvox_status st = bvox__render_opts_check(opts);
    if (st) return st;
    if (n < 1 || i < 0 || i >= n)
        return bvox__fail(BVOX_EINVAL, "turntable: frame %d of %d", i, n);
    double f[9];
    if ((st = bvox__opts_frame(opts, f))) return st;
    /* spin about the volume axis nearest the image's vertical */
    int a = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(f[3 + k]) > fabs(f[3 + a])) a = k;
    const double t = 2 * 3.14159265358979323846 * i / n, c = cos(t), s = sin(t);
    const int b = (a + 1) % 3, e = (a + 2) % 3; /* (a, b, e) cyclic: right-handed */
    double g[9];
    for (int row = 0; row < 3; row++) {
        const double *v = f + 3 * row;
        double *w = g + 3 * row;
        w[a] = v[a];
        w[b] = v[b] * c - v[e] * s;
        w[e] = v[b] * s + v[e] * c;
    }
    *frame_opts = *opts;
    frame_opts->axis_view = 0;
    frame_opts->proj.use_matrix = 1;
    memcpy(frame_opts->proj.matrix, g, sizeof g);
    return BVOX_OK;
}
