/*
 * shade_table.c — the lookup-table stage for interactive display: a
 * pre-image becomes a 16-bit shading code per pixel (one layout per mode,
 * the cut face and the background apart), and an RGB table of 8193 entries
 * lights every code at once. The viewer keeps the codes of its pane and, when
 * the light, the depth curve or a colour changes, rebuilds only the table:
 * that is the paper's output LUT, widened from 8 to 13 bits so that depth
 * shading has 256 levels and gradient shading 64 x 64 normal bins.
 *
 * The lighting itself is lut.c's (bvox__phong, bvox__light_dir, the 27
 * binary normals of bvox__normal_eye), the depth-map normal
 * shade_gradient.c's and the cut-face test render_pipeline.c's, so a still
 * picture (bvox render) and the window shade the same way.
 */
#include "normal_cache.h"
#include "occupancy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { GRAD_BINS = 64, DEPTH_LEVELS = 256, CUE_LEVELS = 16 };

static bvox_status opts_check(const bvox_shade_opts *o)
{
    if (!o) return bvox__fail(BVOX_EINVAL, "shade: no options");
    if ((unsigned)o->mode > (unsigned)BVOX_SHADE_ENLARGED_GRADIENT)
        return bvox__fail(BVOX_EINVAL, "shade: unknown shading %d", (int)o->mode);
    if (o->smooth_radius < 0 || o->smooth_radius > 3)
        return bvox__fail(BVOX_EINVAL, "shade: smooth radius %d is not 1, 2 or 3 (0: 2)",
                          o->smooth_radius);
    bvox_status st = bvox__light_check(&o->light);
    if (st) return st;
    if (o->mode == BVOX_SHADE_DEPTH && (st = bvox__depth_check(&o->depth))) return st;
    if (o->cut) {
        for (int k = 0; k < 4; k++)
            if (!isfinite(o->plane[k])) return bvox__fail(BVOX_EINVAL, "shade: the cut plane is not finite");
        if (!o->plane[0] && !o->plane[1] && !o->plane[2])
            return bvox__fail(BVOX_EINVAL, "shade: the cut plane's normal is zero");
    }
    return BVOX_OK;
}

/* ------------------------------------------------------------ cut face */

void bvox__cut_test_init(bvox__cut_test *t, const double m[3], double e, const bvox_preimage *p)
{
    /* A voxel the cut exposed has its centre c on the kept side and, across
     * the face the ray enters by, a removed neighbour q: f(q) < 0 <= f(c), so
     * f < f(c) / 2 < |m_a| s_a / 2 at the middle of that face, and anywhere
     * on the face f < sum_a |m_a| s_a / 2 ("half"). The pre-image keeps the
     * entry depth floored to a step: tested at the middle of the step, f is
     * off by at most |m . view| step / 2 (plus float rounding of the depth). */
    double half = 0, mv = 0;
    for (int a = 0; a < 3; a++) {
        t->m[a] = m[a];
        half += 0.5 * fabs(m[a]) * p->spacing[a];
        mv += m[a] * p->eye[6 + a];
    }
    t->e = e;
    const double mlen = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    t->limit = half + (0.5 * fabs(mv) + 1e-3 * mlen) * p->depth_step;
}

int bvox__cut_test_at(const bvox__cut_test *t, const bvox_preimage *p, int32_t c, int32_t r,
                      int32_t d)
{
    const double *e = p->eye;
    double f = t->e;
    for (int a = 0; a < 3; a++) {
        double x = p->origin[a] + c * p->pixel_size[0] * e[a] + r * p->pixel_size[1] * e[3 + a] +
                   (d + 0.5) * p->depth_step * e[6 + a];
        f += t->m[a] * x;
    }
    return f < t->limit; /* the solid lies on f >= 0: this close to the plane */
}

void bvox__cut_normal_eye(const bvox_preimage *p, const double m[3], double n[3])
{
    const double *e = p->eye;
    double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]), u[3];
    for (int a = 0; a < 3; a++) u[a] = len > 0 ? m[a] / len : 0;
    n[0] = n[1] = n[2] = 0;
    for (int a = 0; a < 3; a++) {
        n[0] += e[a] * u[a];
        n[1] -= e[3 + a] * u[a];
        n[2] -= e[6 + a] * u[a];
    }
    if (n[2] < 0) n[0] = -n[0], n[1] = -n[1], n[2] = -n[2]; /* the side we see */
}

/* --------------------------------------------------------------- codes */

/* d in 0..range-1 to 0..levels-1 over the whole range (the depth codes). */
static unsigned depth_level(int32_t d, int32_t range, unsigned levels)
{
    int64_t q = (int64_t)d * (levels - 1) / (range - 1);
    return q > (int64_t)levels - 1 ? levels - 1 : (unsigned)q;
}

/* The bin of an eye-frame normal's right and up components. */
static unsigned gradient_bin(const double n[3])
{
    int bx = (int)floor((n[0] + 1) * (GRAD_BINS / 2)), by = (int)floor((n[1] + 1) * (GRAD_BINS / 2));
    bx = bx < 0 ? 0 : bx > GRAD_BINS - 1 ? GRAD_BINS - 1 : bx;
    by = by < 0 ? 0 : by > GRAD_BINS - 1 ? GRAD_BINS - 1 : by;
    return (unsigned)(bx + GRAD_BINS * by);
}

typedef struct codes_ctx {
    const bvox_volume *vol;
    const bvox_preimage *pre;
    const bvox_shade_opts *opts;
    uint16_t *codes;
    bvox__cut_test cut;
    bvox_normal_cache *cache;
} codes_ctx;

static void codes_rows(void *arg, int64_t y0, int64_t y1)
{
    const codes_ctx *g = arg;
    const bvox_preimage *pre = g->pre;
    const bvox_shade_opts *opts = g->opts;
    uint16_t *codes = g->codes;
    const int32_t range = pre->depth_range > 1 ? pre->depth_range : 2;
    bvox__moment_cache *mc = opts->mode == BVOX_SHADE_SMOOTH ? bvox__moment_cache_new() : NULL;
    if (mc) mc->shared = g->cache;
    /* smooth: each row's cells are made a row ahead, their cached moments
     * asked of the memory then (without the scratch: per pixel, slower) */
    bvox__smooth_cell *cells = mc ? bvox__mem_alloc(2 * (size_t)pre->width * sizeof *cells) : NULL;
    if (cells) bvox__smooth_cells_row(g->vol, pre, (int32_t)y0, cells + (y0 & 1) * pre->width, mc);
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        const bvox__smooth_cell *row = cells ? cells + (size_t)(y & 1) * (size_t)pre->width : NULL;
        if (cells && y + 1 < y1)
            bvox__smooth_cells_row(g->vol, pre, y + 1, cells + (size_t)((y + 1) & 1) * (size_t)pre->width, mc);
        for (int32_t x = 0; x < pre->width; x++) {
            size_t i = (size_t)y * (size_t)pre->width + (size_t)x;
            int32_t d = pre->depth[i];
            if (d < 0) {
                codes[i] = BVOX_SCODE_BACKGROUND;
                continue;
            }
            unsigned c;
            if (opts->cut && bvox__cut_test_at(&g->cut, pre, x, y, d)) {
                codes[i] = (uint16_t)(BVOX_SCODE_CUT | depth_level(d, range, DEPTH_LEVELS));
                continue;
            }
            switch (opts->mode) {
            case BVOX_SHADE_DEPTH: c = depth_level(d, range, DEPTH_LEVELS); break;
            case BVOX_SHADE_BINARY: c = pre->code[i]; break;
            case BVOX_SHADE_GRADIENT:
            case BVOX_SHADE_SMOOTH:
            case BVOX_SHADE_PREIMAGE_BINARY:
            case BVOX_SHADE_ENLARGED_GRADIENT: {
                double n[3];
                if (row) bvox__smooth_normal_cell(g->vol, pre, opts->smooth_radius, x, y, &row[x], n, mc);
                else bvox__pixel_normal(g->vol, pre, opts->mode, opts->smooth_radius, x, y, n, mc);
                c = gradient_bin(n);
                break;
            }
            default: {
                int64_t t = (int64_t)d * CUE_LEVELS / range;
                c = BVOX_CODE_NORMAL(pre->code[i]) | (unsigned)(t > CUE_LEVELS - 1 ? CUE_LEVELS - 1 : t) << 5;
                break;
            }
            }
            BVOX_ASSERT(c < BVOX_SCODE_CUT);
            codes[i] = (uint16_t)c;
        }
    }
    free(cells);
    free(mc);
}

bvox_status bvox_shade_codes(const bvox_preimage *pre, const bvox_shade_opts *opts, uint16_t *codes)
{
    return bvox_shade_codes_volume(NULL, pre, opts, codes);
}

bvox_status bvox_shade_codes_volume(const bvox_volume *vol, const bvox_preimage *pre,
                                    const bvox_shade_opts *opts, uint16_t *codes)
{
    return bvox_shade_codes_cached(vol, pre, opts, NULL, codes);
}

bvox_status bvox_shade_codes_cached(const bvox_volume *vol, const bvox_preimage *pre,
                                    const bvox_shade_opts *opts, bvox_normal_cache *cache,
                                    uint16_t *codes)
{
    if (!pre || !pre->depth || !pre->code || !codes)
        return bvox__fail(BVOX_EINVAL, "shade: missing pre-image or codes");
    bvox_status st = opts_check(opts);
    if (st) return st;
    if (opts->mode == BVOX_SHADE_SMOOTH && !vol)
        return bvox__fail(BVOX_EINVAL, "shade: smooth shading needs the volume "
                                       "(bvox_shade_codes_volume)");
    BVOX_ASSERT(bvox__preimage_ok(pre));
    codes_ctx g = {vol, pre, opts, codes, {{0, 0, 0}, 0, 0}, NULL};
    if (cache && opts->mode == BVOX_SHADE_SMOOTH) {
        bvox__normal_cache_bind(cache, vol, bvox__smooth_radius(opts->smooth_radius));
        g.cache = cache;
    }
    if (opts->cut) bvox__cut_test_init(&g.cut, opts->plane, opts->plane[3], pre);
    /* rows over the threads: smooth normals cost a few microseconds a pixel */
    bvox__parallel_for(pre->height, 16, codes_rows, &g);
    return BVOX_OK;
}

/* --------------------------------------------------------------- table */

static uint8_t round8(double v)
{
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v + 0.5);
}

/* The gray level of every code below BVOX_SCODE_CUT that the mode uses;
 * returns how many (-1: bvox_lut_light failed, its message set). */
static int gray_levels(const bvox_preimage *pre, const bvox_shade_opts *o, const double l[3],
                       uint8_t gray[BVOX_SCODE_CUT])
{
    const bvox_light *L = &o->light;
    bvox_lut lut;
    switch (o->mode) {
    case BVOX_SHADE_DEPTH:
        for (int c = 0; c < DEPTH_LEVELS; c++) gray[c] = bvox__depth_value(&o->depth, c / 255.0);
        return DEPTH_LEVELS;
    case BVOX_SHADE_BINARY: /* the paper's table itself */
        if (bvox_lut_light(pre, L, &lut)) return -1;
        memcpy(gray, lut.value, 256);
        return 256;
    case BVOX_SHADE_GRADIENT:
    case BVOX_SHADE_SMOOTH:
    case BVOX_SHADE_PREIMAGE_BINARY:
    case BVOX_SHADE_ENLARGED_GRADIENT:
        /* the bin's centre on the unit hemisphere facing the viewer */
        for (int by = 0; by < GRAD_BINS; by++)
            for (int bx = 0; bx < GRAD_BINS; bx++) {
                double v[3] = {(bx + 0.5) / (GRAD_BINS / 2) - 1, (by + 0.5) / (GRAD_BINS / 2) - 1, 0};
                double r2 = v[0] * v[0] + v[1] * v[1];
                if (r2 > 1) v[0] /= sqrt(r2), v[1] /= sqrt(r2), r2 = 1;
                v[2] = sqrt(1 - r2);
                gray[bx + GRAD_BINS * by] = round8(bvox__phong(L, l, v, 0));
            }
        return GRAD_BINS * GRAD_BINS;
    default: {
        /* binary + depth: the normal lit without the 3-bit cue, then the
         * depth factor of the level's middle */
        const double k = L->depth_cue > 0 ? L->depth_cue : 0.5;
        bvox_light flat = *L;
        flat.depth_cue = 0;
        if (bvox_lut_light(pre, &flat, &lut)) return -1;
        for (int t = 0; t < CUE_LEVELS; t++)
            for (int c = 0; c < 32; c++)
                gray[c | t << 5] = (uint8_t)(lut.value[c] * (1 - k * (t + 0.5) / CUE_LEVELS) + 0.5);
        return 32 * CUE_LEVELS;
    }
    }
}

bvox_status bvox_shade_table_build(const bvox_preimage *pre, const bvox_shade_opts *opts,
                                   bvox_shade_table *table)
{
    if (!pre || !table) return bvox__fail(BVOX_EINVAL, "shade: no pre-image or table");
    bvox_status st = opts_check(opts);
    if (st) return st;
    const bvox_light *L = &opts->light;
    double l[3];
    bvox__light_dir(L, l);
    uint8_t gray[BVOX_SCODE_CUT];
    memset(gray, 0, sizeof gray);
    int n = gray_levels(pre, opts, l, gray);
    if (n < 0) return BVOX_EINVAL; /* bvox_lut_light said why */
    memset(table->rgb, 0, sizeof table->rgb);
    /* the object's colour; white keeps the gray exactly ((g 255 + 127) / 255 = g) */
    for (int c = 0; c < n; c++)
        for (int ch = 0; ch < 3; ch++) table->rgb[c][ch] = (uint8_t)((gray[c] * opts->color[ch] + 127) / 255);
    /* the cut face: lit flat by the plane's normal, depth by 256 levels */
    double pn[3] = {0, 0, 1};
    if (opts->cut) bvox__cut_normal_eye(pre, opts->plane, pn);
    const double flat = bvox__phong(L, l, pn, 0), k = L->depth_cue > 0 ? L->depth_cue : 0.5;
    for (int q = 0; q < DEPTH_LEVELS; q++) {
        double t = q / 255.0, g8;
        if (opts->mode == BVOX_SHADE_DEPTH) g8 = gray[q];
        else if (opts->mode == BVOX_SHADE_BINARY_DEPTH) g8 = flat * (1 - k * t);
        else g8 = flat;
        for (int ch = 0; ch < 3; ch++)
            table->rgb[BVOX_SCODE_CUT | q][ch] = (uint8_t)((g8 * opts->cut_color[ch] + 127.5) / 255);
    }
    memcpy(table->rgb[BVOX_SCODE_BACKGROUND], opts->background, 3);
    return BVOX_OK;
}

void bvox_shade_table_apply(const bvox_shade_table *table, const uint16_t *codes, int32_t width,
                            int32_t height, size_t code_stride, uint8_t *rgb, size_t rgb_stride)
{
    BVOX_ASSERT(table && (width <= 0 || height <= 0 || (codes && rgb)));
    BVOX_ASSERT(code_stride >= (size_t)(width > 0 ? width : 0) && rgb_stride >= 3 * (size_t)(width > 0 ? width : 0));
    for (int32_t y = 0; y < height; y++) {
        const uint16_t *c = codes + (size_t)y * code_stride;
        uint8_t *dst = rgb + (size_t)y * rgb_stride;
        for (int32_t x = 0; x < width; x++, dst += 3) {
            unsigned v = c[x] > BVOX_SCODE_BACKGROUND ? BVOX_SCODE_BACKGROUND : c[x];
            memcpy(dst, table->rgb[v], 3);
        }
    }
}
