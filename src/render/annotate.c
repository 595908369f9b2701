/*
 * annotate.c — what bvox_render draws over the finished picture (issue 18):
 * a scale bar of a round length, an x/y/z triad turned as the view, and a
 * title, in the built-in 5x7 font (common/font5x7.c: why no FreeType is
 * said there). Drawn last, on the final pixels (after supersampling, zoom
 * and filters), so lines and text stay sharp and the bar's length is
 * measured in the picture's own pixels.
 */
#include "scene.h"
#include "common/font5x7.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int bvox__render_wants_colour(const bvox_render_opts *o)
{
    return o->color_set || o->transparent || o->scale_bar || o->axes || o->title ||
           (o->background[0] | o->background[1] | o->background[2]);
}

/* A gray picture becomes RGB so that the triad can be coloured. */
static bvox_status to_rgb(bvox_image **img)
{
    if ((*img)->channels != 1) return BVOX_OK;
    bvox_image *rgb;
    bvox_status st = bvox_image_create((*img)->width, (*img)->height, 3, 8, &rgb);
    if (st) return st;
    const size_t n = (size_t)(*img)->width * (size_t)(*img)->height;
    for (size_t i = 0; i < n; i++)
        rgb->pixels[3 * i] = rgb->pixels[3 * i + 1] = rgb->pixels[3 * i + 2] = (*img)->pixels[i];
    bvox_image_destroy(*img);
    *img = rgb;
    return BVOX_OK;
}

static void put(bvox_image *img, int32_t x, int32_t y, const uint8_t c[3])
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    const int ch = img->channels;
    uint8_t *p = img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)ch;
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
    if (ch == 4) p[3] = 255;
}

static void fill_rect(bvox_image *img, int32_t x, int32_t y, int32_t w, int32_t h,
                      const uint8_t c[3])
{
    for (int32_t j = 0; j < h; j++)
        for (int32_t i = 0; i < w; i++) put(img, x + i, y + j, c);
}

/* A line of thickness t (square brush), stepped one pixel along its longer
 * axis. */
static void line(bvox_image *img, double x0, double y0, double x1, double y1, int t,
                 const uint8_t c[3])
{
    double dx = x1 - x0, dy = y1 - y0;
    int n = (int)ceil(fmax(fabs(dx), fabs(dy)));
    for (int k = 0; k <= n; k++) {
        double f = n ? (double)k / n : 0;
        int32_t x = (int32_t)floor(x0 + f * dx + 0.5) - t / 2;
        int32_t y = (int32_t)floor(y0 + f * dy + 0.5) - t / 2;
        fill_rect(img, x, y, t, t, c);
    }
}

/* The largest 1, 2 or 5 x 10^k not over target (> 0). */
static double round_length(double target)
{
    double p = pow(10.0, floor(log10(target)));
    double m = target / p;
    /* guard the edges of floating point: 0.999999 x 10^k is 10^(k-1) x 9.99 */
    if (m >= 10 - 1e-9) p *= 10, m /= 10;
    return (m >= 5 - 1e-9 ? 5 : m >= 2 - 1e-9 ? 2 : 1) * p;
}

/* "2 mm", "0.5 mm", "200 um", "20" (no unit). */
static void length_label(double len, const char *unit, char *buf, size_t size)
{
    snprintf(buf, size, "%.6g%s%s", len, unit && *unit ? " " : "", unit ? unit : "");
}

/* Ink that stands out from the background: white on dark, black on light. */
static void ink_for(const bvox_render_opts *o, uint8_t ink[3])
{
    const uint8_t *b = o->background;
    unsigned luma = o->transparent ? 0 : (77u * b[0] + 150u * b[1] + 29u * b[2]) >> 8;
    memset(ink, luma > 128 ? 0 : 255, 3);
}

static void scale_bar(bvox_image *img, double px, const char *unit, int s, const uint8_t ink[3])
{
    const int32_t margin = 8 * s;
    double len = round_length(img->width * px / 5);
    int32_t bar = (int32_t)floor(len / px + 0.5);
    char label[64];
    length_label(len, unit, label, sizeof label);
    const int32_t thick = 2 * s;
    const int32_t y = img->height - margin - thick;
    fill_rect(img, margin, y, bar, thick, ink);
    /* end ticks, so the length reads without the label */
    fill_rect(img, margin, y - 3 * s, s, 3 * s, ink);
    fill_rect(img, margin + bar - s, y - 3 * s, s, 3 * s, ink);
    /* the label centred over the bar, but never cut by the left edge */
    int32_t tw = bvox__text_width(label, s), lx = margin + (bar - tw) / 2;
    bvox__text_draw(img, lx < 2 * s ? 2 * s : lx, y - 3 * s - 8 * s, s, label, ink);
}

/* The triad: the screen images (right, down components) of the index axes
 * x, y, z drawn from a common origin in the lower right corner, the axis
 * pointing away from the viewer first so the nearer ones cover it. */
static void axes(bvox_image *img, const double f[9], int s)
{
    static const uint8_t colour[3][3] = {{230, 50, 50}, {40, 200, 60}, {70, 120, 255}};
    static const char *const name[3] = {"x", "y", "z"};
    const double L = 20.0 * s;
    const double cx = img->width - 12.0 * s - L, cy = img->height - 12.0 * s - L;
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++) /* far (larger view component) first */
        for (int j = i + 1; j < 3; j++)
            if (f[6 + order[j]] > f[6 + order[i]]) {
                int t = order[i];
                order[i] = order[j], order[j] = t;
            }
    for (int k = 0; k < 3; k++) {
        int a = order[k];
        double ex = cx + L * f[a], ey = cy + L * f[3 + a];
        line(img, cx, cy, ex, ey, s > 1 ? s : 1, colour[a]);
        /* the letter beyond the tip, centred on the axis' direction */
        double lx = cx + (L + 6.0 * s) * f[a], ly = cy + (L + 6.0 * s) * f[3 + a];
        bvox__text_draw(img, (int32_t)floor(lx - 2.5 * s + 0.5), (int32_t)floor(ly - 3.5 * s + 0.5),
                        s, name[a], colour[a]);
    }
}

bvox_status bvox__annotate(const bvox_render_opts *o, const bvox_preimage *pre, const char *unit,
                           bvox_image **img)
{
    if (!o->scale_bar && !o->axes && !o->title) return BVOX_OK;
    bvox_status st = to_rgb(img);
    if (st) return st;
    bvox_image *im = *img;
    /* text and lines grow with the picture: 1 pixel per 256 of the shorter side */
    const int32_t side = im->width < im->height ? im->width : im->height;
    const int s = side >= 256 ? side / 256 : 1;
    uint8_t ink[3];
    ink_for(o, ink);
    if (o->scale_bar) {
        /* the picture's pixel: the pre-image's, times the rows it became
         * (supersampling, zoom, averaging, enlarging all scale both axes) */
        double px = pre->pixel_size[1] * pre->height / im->height;
        if (!(px > 0 && isfinite(px)))
            return bvox__fail(BVOX_EINVAL, "render: no pixel size for a scale bar");
        scale_bar(im, px, unit, s, ink);
    }
    if (o->axes) {
        double f[9];
        if ((st = bvox__opts_frame(o, f))) return st;
        axes(im, f, s);
    }
    if (o->title) {
        int32_t tw = bvox__text_width(o->title, s);
        bvox__text_draw(im, (im->width - tw) / 2, 6 * s, s, o->title, ink);
    }
    return BVOX_OK;
}
