/*
 * lut.c — shading through a 256-entry lookup table, the paper's output LUT:
 * a pre-image code (5-bit normal index, 3-bit depth cue) indexes the table.
 * Depth shading uses the cue bits, binary gradient shading the normal bits
 * (Phong, the light in the pre-image's eye frame) and optionally the cue.
 * A new light or lighting model rebuilds only the table (256 entries, a few
 * microseconds) and remaps the codes: nothing is re-cast.
 */
#include "render.h"

#include <math.h>

static const double deg = 3.14159265358979323846 / 180.0;

bvox_status bvox__light_check(const bvox_light *l)
{
    if (!l) return bvox__fail(BVOX_EINVAL, "no light given");
    const double v[] = {l->azimuth, l->elevation, l->ambient, l->diffuse, l->specular,
                        l->shininess, l->depth_cue};
    for (int i = 0; i < 7; i++)
        if (!isfinite(v[i])) return bvox__fail(BVOX_EINVAL, "light: a value is not finite");
    if (l->ambient < 0 || l->diffuse < 0 || l->specular < 0 || l->shininess < 0)
        return bvox__fail(BVOX_EINVAL, "light: ambient, diffuse, specular and shininess "
                                       "must not be negative");
    if (l->depth_cue < 0 || l->depth_cue > 1)
        return bvox__fail(BVOX_EINVAL, "light: depth_cue %g is outside 0..1", l->depth_cue);
    return BVOX_OK;
}

void bvox__light_dir(const bvox_light *light, double l[3])
{
    double az = light->azimuth * deg, el = light->elevation * deg;
    l[0] = cos(el) * cos(az);
    l[1] = cos(el) * sin(az);
    l[2] = sin(el);
}

double bvox__phong(const bvox_light *light, const double l[3], const double n[3], unsigned cue)
{
    double nl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    double i = light->ambient;
    if (nl > 0) {
        i += light->diffuse * nl;
        double rv = 2 * nl * n[2] - l[2]; /* R = 2 (N.L) N - L, V = (0, 0, 1) */
        if (rv > 0 && light->specular > 0) i += light->specular * pow(rv, light->shininess);
    }
    i *= 1.0 - light->depth_cue * (double)cue / 7.0;
    i *= 255.0;
    return i < 0 ? 0 : i > 255 ? 255 : i;
}

bvox_status bvox__depth_check(const bvox_depth_shading *s)
{
    if (!s) return bvox__fail(BVOX_EINVAL, "no depth shading given");
    if (!(s->near_value >= 0 && s->near_value <= 255 && s->far_value >= 0 &&
          s->far_value <= 255))
        return bvox__fail(BVOX_EINVAL, "depth shading: near and far values must be in 0..255");
    if (s->curve != BVOX_DEPTH_LINEAR && s->curve != BVOX_DEPTH_EXP)
        return bvox__fail(BVOX_EINVAL, "depth shading: unknown curve %d", (int)s->curve);
    if (s->curve == BVOX_DEPTH_EXP && !(s->decay > 0 && isfinite(s->decay)))
        return bvox__fail(BVOX_EINVAL, "depth shading: decay must be > 0");
    return BVOX_OK;
}

uint8_t bvox__depth_value(const bvox_depth_shading *s, double t)
{
    double i = s->curve == BVOX_DEPTH_LINEAR
                   ? s->near_value + (s->far_value - s->near_value) * t
                   : s->far_value + (s->near_value - s->far_value) * exp(-s->decay * t);
    return (uint8_t)(i < 0 ? 0 : i > 255 ? 255 : i + 0.5);
}

bvox_status bvox_lut_depth(const bvox_depth_shading *shading, bvox_lut *lut)
{
    bvox_status st = bvox__depth_check(shading);
    if (st) return st;
    for (unsigned c = 0; c < 256; c++)
        lut->value[c] = BVOX_CODE_NORMAL(c) >= 27 ? shading->background
                                                  : bvox__depth_value(shading, BVOX_CODE_CUE(c) / 7.0);
    return BVOX_OK;
}

bvox_status bvox_lut_light(const bvox_preimage *pre, const bvox_light *light, bvox_lut *lut)
{
    if (!pre || !lut) return bvox__fail(BVOX_EINVAL, "lut: no pre-image or table");
    bvox_status st = bvox__light_check(light);
    if (st) return st;
    double l[3], n[27][3];
    bvox__light_dir(light, l);
    for (unsigned i = 0; i < 27; i++) bvox__normal_eye(pre, i, n[i]);
    for (unsigned c = 0; c < 256; c++) {
        unsigned idx = BVOX_CODE_NORMAL(c);
        lut->value[c] = idx >= 27 ? light->background
                                  : (uint8_t)(bvox__phong(light, l, n[idx], BVOX_CODE_CUE(c)) + 0.5);
    }
    return BVOX_OK;
}

bvox_status bvox_shade_into(const bvox_preimage *pre, const bvox_lut *lut, bvox_image *img)
{
    if (!pre || !pre->code || !lut) return bvox__fail(BVOX_EINVAL, "shade: missing input");
    bvox_status st = bvox__image_check(img, "shade");
    if (st) return st;
    if (img->width != pre->width || img->height != pre->height || img->channels != 1 ||
        img->bits != 8)
        return bvox__fail(BVOX_EINVAL, "shade: the image must be %d x %d, 1 channel, 8 bits",
                          (int)pre->width, (int)pre->height);
    const size_t n = (size_t)pre->width * (size_t)pre->height;
    const uint8_t *restrict code = pre->code;
    uint8_t *restrict dst = img->pixels;
    const uint8_t *restrict t = lut->value;
    for (size_t i = 0; i < n; i++) dst[i] = t[code[i]];
    return BVOX_OK;
}

bvox_status bvox_shade(const bvox_preimage *pre, const bvox_lut *lut, bvox_image **out)
{
    *out = NULL;
    if (!pre || !pre->code || !lut) return bvox__fail(BVOX_EINVAL, "shade: missing input");
    bvox_status st = bvox_image_create(pre->width, pre->height, 1, 8, out);
    if (!st) st = bvox_shade_into(pre, lut, *out);
    if (st) {
        bvox_image_destroy(*out);
        *out = NULL;
    }
    return st;
}

bvox_status bvox_shade_depth(const bvox_preimage *pre, const bvox_depth_shading *shading,
                             bvox_image **out)
{
    *out = NULL;
    if (!pre || !pre->depth) return bvox__fail(BVOX_EINVAL, "shade: missing pre-image");
    bvox_status st = bvox__depth_check(shading);
    if (st) return st;
    int32_t range = pre->depth_range > 0 ? pre->depth_range : 1;
    /* the paper's table over every depth value, not only the 3-bit cue */
    size_t tbytes = (size_t)range;
    uint8_t *table = bvox__alloc(tbytes, false, "depth table", &st);
    if (!table) return st;
    for (int32_t d = 0; d < range; d++)
        table[d] = bvox__depth_value(shading, range > 1 ? (double)d / (range - 1) : 0.0);
    st = bvox_image_create(pre->width, pre->height, 1, 8, out);
    if (!st) {
        const size_t n = (size_t)pre->width * (size_t)pre->height;
        for (size_t i = 0; i < n; i++) {
            int32_t d = pre->depth[i];
            (*out)->pixels[i] = d < 0 ? shading->background : table[d < range ? d : range - 1];
        }
    }
    bvox__free(table, tbytes);
    return st;
}
