/*
 * shade_gradient.c — gradient shading computed from the depth map itself
 * (Gordon and Reynolds, 1985; the paper's "general gradient shading": a
 * gradient operator run over the depth-shaded pre-image). The normal of the
 * surface depth D(u, v) is (dD/du, dD/dv, 1) in (right, down, towards the
 * viewer), with the differences taken in physical units (pixel size, depth
 * step), then lit by the same Phong model as the binary normals.
 * A background or out-of-image neighbour takes the centre's depth, which
 * makes the difference one-sided at silhouettes instead of a cliff.
 */
#include "render.h"

#include <math.h>

typedef struct grad_ctx {
    const bvox_preimage *pre;
    bvox_gradient op;
    const bvox_light *light;
    double l[3];
    bvox_image *img;
} grad_ctx;

static inline double depth_or(const bvox_preimage *p, int32_t x, int32_t y, double centre)
{
    if (x < 0 || y < 0 || x >= p->width || y >= p->height) return centre;
    int32_t d = p->depth[(size_t)y * (size_t)p->width + (size_t)x];
    return d < 0 ? centre : (double)d;
}

void bvox__depth_normal(const bvox_preimage *p, bvox_gradient op, int32_t x, int32_t y, double n[3])
{
    const double su = p->depth_step / (p->pixel_size[0] > 0 ? p->pixel_size[0] : 1.0);
    const double sv = p->depth_step / (p->pixel_size[1] > 0 ? p->pixel_size[1] : 1.0);
    double c = p->depth[(size_t)y * (size_t)p->width + (size_t)x], gx, gy;
    if (op == BVOX_GRADIENT_CENTRAL) {
        gx = (depth_or(p, x + 1, y, c) - depth_or(p, x - 1, y, c)) / 2;
        gy = (depth_or(p, x, y + 1, c) - depth_or(p, x, y - 1, c)) / 2;
    } else {
        double a = depth_or(p, x - 1, y - 1, c), b = depth_or(p, x, y - 1, c),
               e = depth_or(p, x + 1, y - 1, c), f = depth_or(p, x - 1, y, c),
               h = depth_or(p, x + 1, y, c), k = depth_or(p, x - 1, y + 1, c),
               m = depth_or(p, x, y + 1, c), q = depth_or(p, x + 1, y + 1, c);
        gx = ((e + 2 * h + q) - (a + 2 * f + k)) / 8;
        gy = ((k + 2 * m + q) - (a + 2 * b + e)) / 8;
    }
    n[0] = gx * su, n[1] = -gy * sv, n[2] = 1.0; /* (right, up, towards the viewer) */
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + 1.0);
    n[0] /= len, n[1] /= len, n[2] /= len;
}

static void grad_rows(void *arg, int64_t y0, int64_t y1)
{
    const grad_ctx *g = arg;
    const bvox_preimage *p = g->pre;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        for (int32_t x = 0; x < p->width; x++) {
            size_t i = (size_t)y * (size_t)p->width + (size_t)x;
            if (p->depth[i] < 0) {
                g->img->pixels[i] = g->light->background;
                continue;
            }
            double n[3];
            bvox__depth_normal(p, g->op, x, y, n);
            double v = bvox__phong(g->light, g->l, n, BVOX_CODE_CUE(p->code[i]));
            g->img->pixels[i] = (uint8_t)(v + 0.5);
        }
    }
}

bvox_status bvox_shade_gradient(const bvox_preimage *pre, bvox_gradient op,
                                const bvox_light *light, bvox_image **out)
{
    *out = NULL;
    if (!pre || !pre->depth || !pre->code) return bvox__fail(BVOX_EINVAL, "shade: missing pre-image");
    if (op != BVOX_GRADIENT_CENTRAL && op != BVOX_GRADIENT_SOBEL)
        return bvox__fail(BVOX_EINVAL, "shade: unknown gradient operator %d", (int)op);
    bvox_status st = bvox__light_check(light);
    if (st) return st;
    st = bvox_image_create(pre->width, pre->height, 1, 8, out);
    if (st) return st;
    grad_ctx g = {pre, op, light, {0, 0, 0}, *out};
    bvox__light_dir(light, g.l);
    bvox__parallel_for(pre->height, 64, grad_rows, &g);
    return BVOX_OK;
}
