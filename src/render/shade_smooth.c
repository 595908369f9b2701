/*
 * shade_smooth.c — still pictures for the shading modes whose normals are
 * computed per pixel rather than looked up by code (smooth, binary-preimage;
 * enlarged-gradient is bvox_shade_gradient on the enlarged pre-image), the
 * depth cues multiplied in after shading (ambient occlusion, cast shadows)
 * and the supersampling reduction (N x N pixels averaged into one).
 */
#include "render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct shade_ctx {
    const bvox_volume *vol;
    const bvox_preimage *pre;
    bvox_shade_mode mode;
    int radius;
    const bvox_light *light;
    double l[3];
    bvox_image *img;
} shade_ctx;

static void shade_rows(void *arg, int64_t y0, int64_t y1)
{
    const shade_ctx *g = arg;
    const bvox_preimage *p = g->pre;
    bvox__moment_cache *mc = g->mode == BVOX_SHADE_SMOOTH ? bvox__moment_cache_new() : NULL;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++)
        for (int32_t x = 0; x < p->width; x++) {
            size_t i = (size_t)y * (size_t)p->width + (size_t)x;
            if (p->depth[i] < 0) {
                g->img->pixels[i] = g->light->background;
                continue;
            }
            double n[3];
            bvox__pixel_normal(g->vol, p, g->mode, g->radius, x, y, n, mc);
            g->img->pixels[i] = (uint8_t)(bvox__phong(g->light, g->l, n, BVOX_CODE_CUE(p->code[i])) + 0.5);
        }
    free(mc);
}

bvox_status bvox__shade_normals(const bvox_volume *vol, const bvox_preimage *pre,
                                bvox_shade_mode mode, int radius, const bvox_light *light,
                                bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__light_check(light);
    if (st) return st;
    if ((st = bvox_image_create(pre->width, pre->height, 1, 8, out))) return st;
    shade_ctx g = {vol, pre, mode, radius, light, {0, 0, 0}, *out};
    bvox__light_dir(light, g.l);
    bvox__parallel_for(pre->height, 16, shade_rows, &g);
    return BVOX_OK;
}

bvox_status bvox__apply_depth_cues(const bvox_volume *vol, const bvox_preimage *pre,
                                   const bvox_light *light, int radius, int ao, int shadows,
                                   bvox_image *img)
{
    const size_t n = (size_t)pre->width * (size_t)pre->height;
    bvox_status st = BVOX_OK;
    uint8_t *f = bvox__alloc(n, false, "ambient occlusion", &st);
    uint8_t *lit = f ? bvox__alloc(n, false, "shadows", &st) : NULL;
    if (!lit) {
        bvox__free(f, n);
        return st;
    }
    if (ao) st = bvox_preimage_ao(vol, pre, radius, f);
    else memset(f, 255, n);
    if (!st && shadows) st = bvox_preimage_shadows(vol, pre, light, radius, lit);
    else if (!st) memset(lit, 1, n);
    if (!st) {
        double l[3];
        bvox__light_dir(light, l);
        const int ch = img->channels, nc = ch == 4 ? 3 : ch; /* alpha is coverage, not light */
        for (int32_t y = 0; y < pre->height; y++)
            for (int32_t x = 0; x < pre->width; x++) {
                size_t i = (size_t)y * (size_t)pre->width + (size_t)x;
                if (pre->depth[i] < 0) continue;
                double k = f[i] / 255.0;
                if (!lit[i]) { /* the direct light removed: ambient / (ambient + diffuse N.L) */
                    double nrm[3];
                    bvox__smooth_normal_eye(vol, pre, radius, x, y, nrm, NULL);
                    double nl = nrm[0] * l[0] + nrm[1] * l[1] + nrm[2] * l[2];
                    if (nl > 0 && light->ambient + light->diffuse * nl > 0)
                        k *= light->ambient / (light->ambient + light->diffuse * nl);
                }
                for (int c = 0; c < nc; c++) {
                    uint8_t *v = img->pixels + (size_t)ch * i + (size_t)c;
                    *v = (uint8_t)(*v * k + 0.5);
                }
            }
    }
    bvox__free(lit, n);
    bvox__free(f, n);
    return st;
}

bvox_status bvox__image_shrink(const bvox_image *in, int factor, bvox_image **out)
{
    *out = NULL;
    const int32_t w = in->width / factor, h = in->height / factor;
    const int ch = in->channels;
    bvox_status st = bvox_image_create(w, h, ch, 8, out);
    if (st) return st;
    const int area = factor * factor;
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++)
            for (int c = 0; c < ch; c++) {
                int sum = 0;
                for (int j = 0; j < factor; j++) {
                    const uint8_t *row = in->pixels + ((size_t)(y * factor + j) * (size_t)in->width +
                                                       (size_t)x * (size_t)factor) * (size_t)ch + (size_t)c;
                    for (int i = 0; i < factor; i++) sum += row[(size_t)i * (size_t)ch];
                }
                (*out)->pixels[((size_t)y * (size_t)w + (size_t)x) * (size_t)ch + (size_t)c] =
                    (uint8_t)((sum + area / 2) / area);
            }
    return BVOX_OK;
}

bvox_status bvox_shade_preimage(const bvox_volume *vol, const bvox_preimage *pre,
                                bvox_shade_mode mode, int radius, const bvox_light *light,
                                bvox_image **out)
{
    *out = NULL;
    if (!pre || !pre->depth || !pre->code || !light)
        return bvox__fail(BVOX_EINVAL, "shade: missing pre-image or light");
    if (radius < 0 || radius > 3)
        return bvox__fail(BVOX_EINVAL, "shade: smooth radius %d is not 1, 2 or 3 (0: 2)", radius);
    switch (mode) {
    case BVOX_SHADE_GRADIENT: return bvox_shade_gradient(pre, BVOX_GRADIENT_SOBEL, light, out);
    case BVOX_SHADE_ENLARGED_GRADIENT: {
        bvox_preimage *big;
        bvox_status st = bvox_preimage_enlarge(pre, &big);
        if (st) return st;
        st = bvox_shade_gradient(big, BVOX_GRADIENT_SOBEL, light, out);
        bvox_preimage_destroy(big);
        return st;
    }
    case BVOX_SHADE_SMOOTH:
        if (!vol) return bvox__fail(BVOX_EINVAL, "shade: smooth shading needs the volume");
        /* fall through */
    case BVOX_SHADE_PREIMAGE_BINARY: return bvox__shade_normals(vol, pre, mode, radius, light, out);
    default:
        return bvox__fail(BVOX_EINVAL, "shade: %s is not a per-pixel normal shading (smooth, "
                                       "binary-preimage, gradient, enlarged-gradient)",
                          bvox_shade_mode_name(mode));
    }
}
