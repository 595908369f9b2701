/*
 * zoom.c — zoom by pixel replication (x1, x2, x4, x8, the frame grabber's
 * scan-out zoom), zoom x2 with pixel averaging (the paper's Figure 5) and pan
 * (the offset registers) on 8- or 16-bit images of any channel count.
 */
#include "render.h"

#include <string.h>

bvox_status bvox_image_zoom(const bvox_image *in, int factor, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(in, "zoom");
    if (st) return st;
    if (factor != 1 && factor != 2 && factor != 4 && factor != 8)
        return bvox__fail(BVOX_EINVAL, "zoom factor must be 1, 2, 4 or 8, not %d", factor);
    if ((int64_t)in->width * factor > BVOX_IMAGE_MAX_DIM ||
        (int64_t)in->height * factor > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_ETOOBIG, "zoom: the result would exceed %d pixels a side",
                          BVOX_IMAGE_MAX_DIM);
    st = bvox_image_create(in->width * factor, in->height * factor, in->channels, in->bits, out);
    if (st) return st;
    const size_t ch = (size_t)in->channels, bps = (size_t)in->bits / 8;
    const size_t px = ch * bps; /* bytes per pixel */
    const size_t in_row = (size_t)in->width * px, out_row = in_row * (size_t)factor;
    const uint8_t *src = in->bits == 8 ? in->pixels : (const uint8_t *)in->pixels16;
    uint8_t *dst = in->bits == 8 ? (*out)->pixels : (uint8_t *)(*out)->pixels16;
    for (int32_t y = 0; y < in->height; y++) {
        uint8_t *row = dst + (size_t)y * (size_t)factor * out_row;
        const uint8_t *s = src + (size_t)y * in_row;
        for (int32_t x = 0; x < in->width; x++)
            for (int k = 0; k < factor; k++)
                memcpy(row + ((size_t)x * (size_t)factor + (size_t)k) * px, s + (size_t)x * px, px);
        for (int k = 1; k < factor; k++) memcpy(row + (size_t)k * out_row, row, out_row);
    }
    return BVOX_OK;
}

bvox_status bvox_image_zoom2_average(const bvox_image *in, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(in, "zoom");
    if (st) return st;
    if ((int64_t)in->width * 2 > BVOX_IMAGE_MAX_DIM || (int64_t)in->height * 2 > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_ETOOBIG, "zoom: the result would exceed %d pixels a side",
                          BVOX_IMAGE_MAX_DIM);
    st = bvox_image_create(in->width * 2, in->height * 2, in->channels, in->bits, out);
    if (st) return st;
    bvox_image *o = *out;
    const int32_t w = in->width, h = in->height, ch = in->channels;
    /* p(i, j) with zeros beyond the edge, as the figure's zero-filled frame */
#define P(i, j, c) ((i) < h && (j) < w ? bvox__img_get(in, ((size_t)(i) * (size_t)w + (size_t)(j)) * (size_t)ch + (size_t)(c)) : 0u)
    for (int32_t i = 0; i < h; i++)
        for (int32_t j = 0; j < w; j++)
            for (int32_t c = 0; c < ch; c++) {
                uint32_t a = P(i, j, c), b = P(i, j + 1, c), d = P(i + 1, j, c),
                         e = P(i + 1, j + 1, c);
                size_t r0 = (size_t)(2 * i) * (size_t)(2 * w), r1 = r0 + (size_t)(2 * w);
                size_t x0 = (size_t)(2 * j), x1 = x0 + 1;
                /* averages rounded half up: (sum + n/2) / n */
                bvox__img_put(o, (r0 + x0) * (size_t)ch + (size_t)c, a);
                bvox__img_put(o, (r0 + x1) * (size_t)ch + (size_t)c, (a + b + 1) / 2);
                bvox__img_put(o, (r1 + x0) * (size_t)ch + (size_t)c, (a + d + 1) / 2);
                bvox__img_put(o, (r1 + x1) * (size_t)ch + (size_t)c, (a + b + d + e + 2) / 4);
            }
#undef P
    return BVOX_OK;
}

bvox_status bvox_image_pan(const bvox_image *in, int32_t dx, int32_t dy, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(in, "pan");
    if (st) return st;
    st = bvox_image_create(in->width, in->height, in->channels, in->bits, out);
    if (st) return st;
    const size_t px = (size_t)in->channels * (size_t)(in->bits / 8);
    const uint8_t *src = in->bits == 8 ? in->pixels : (const uint8_t *)in->pixels16;
    uint8_t *dst = in->bits == 8 ? (*out)->pixels : (uint8_t *)(*out)->pixels16;
    /* the source columns that land inside: x + dx in [0, width) */
    int64_t x0 = dx < 0 ? -(int64_t)dx : 0, x1 = (int64_t)in->width - (dx > 0 ? dx : 0);
    if (x1 <= x0) return BVOX_OK;
    for (int64_t y = 0; y < in->height; y++) {
        int64_t ty = y + dy;
        if (ty < 0 || ty >= in->height) continue;
        memcpy(dst + ((size_t)ty * (size_t)in->width + (size_t)(x0 + dx)) * px,
               src + ((size_t)y * (size_t)in->width + (size_t)x0) * px, (size_t)(x1 - x0) * px);
    }
    return BVOX_OK;
}
