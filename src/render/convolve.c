/*
 * convolve.c — 3x3 convolution of 8-bit images (the frame processor's
 * convolution hardware): any kernel with a divisor and a bias, and presets
 * (high pass, smooth, Laplacian, Sobel magnitude). Pixels beyond the border
 * repeat the edge pixel, so a flat image stays flat under every kernel whose
 * weights sum to the divisor. Results saturate to 0..255.
 */
#include "render.h"

#include <math.h>
#include <strings.h>

static const char *const names[] = {"highpass", "smooth", "laplacian", "sobel"};
#define NFILTERS (int)(sizeof names / sizeof names[0])

static const int32_t presets[3][9] = {
    {-1, -1, -1, -1, 9, -1, -1, -1, -1},
    {1, 2, 1, 2, 4, 2, 1, 2, 1},
    {0, -1, 0, -1, 4, -1, 0, -1, 0},
};
static const int32_t preset_div[3] = {1, 16, 1};

const char *bvox_filter_name(bvox_filter filter)
{
    return (unsigned)filter < (unsigned)NFILTERS ? names[filter] : "unknown";
}

int bvox_filter_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < NFILTERS; i++)
        if (!strcasecmp(name, names[i])) return i;
    return -1;
}

static inline uint8_t sat(int64_t v) { return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v); }

/* floor(a / b) for b > 0 */
static inline int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/* The 3x3 neighbourhood of (x, y), channel c, edge pixels repeated. */
static inline void gather(const bvox_image *in, int32_t x, int32_t y, int32_t c, int32_t p[9])
{
    const int32_t w = in->width, h = in->height, ch = in->channels;
    for (int dy = -1; dy <= 1; dy++) {
        int32_t yy = y + dy < 0 ? 0 : y + dy >= h ? h - 1 : y + dy;
        for (int dx = -1; dx <= 1; dx++) {
            int32_t xx = x + dx < 0 ? 0 : x + dx >= w ? w - 1 : x + dx;
            p[(dy + 1) * 3 + dx + 1] = in->pixels[((size_t)yy * (size_t)w + (size_t)xx) *
                                                      (size_t)ch + (size_t)c];
        }
    }
}

static bvox_status prepare(const bvox_image *in, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(in, "convolve");
    if (st) return st;
    if (in->bits != 8) return bvox__fail(BVOX_EINVAL, "convolve: the image must be 8-bit");
    return bvox_image_create(in->width, in->height, in->channels, 8, out);
}

bvox_status bvox_image_convolve(const bvox_image *in, const int32_t kernel[9], int32_t divisor,
                                int32_t bias, bvox_image **out)
{
    *out = NULL;
    if (!kernel) return bvox__fail(BVOX_EINVAL, "convolve: no kernel");
    if (divisor == 0) return bvox__fail(BVOX_EINVAL, "convolve: the divisor must not be 0");
    bvox_status st = prepare(in, out);
    if (st) return st;
    int64_t k[9], div = divisor;
    for (int i = 0; i < 9; i++) k[i] = divisor < 0 ? -(int64_t)kernel[i] : kernel[i];
    if (div < 0) div = -div;
    for (int32_t y = 0; y < in->height; y++)
        for (int32_t x = 0; x < in->width; x++)
            for (int32_t c = 0; c < in->channels; c++) {
                int32_t p[9];
                gather(in, x, y, c, p);
                int64_t s = 0;
                for (int i = 0; i < 9; i++) s += k[i] * p[i];
                /* round half up: floor(s / div + 1/2) */
                int64_t v = floor_div(2 * s + div, 2 * div) + bias;
                (*out)->pixels[((size_t)y * (size_t)in->width + (size_t)x) *
                                   (size_t)in->channels + (size_t)c] = sat(v);
            }
    return BVOX_OK;
}

bvox_status bvox_image_filter(const bvox_image *in, bvox_filter filter, bvox_image **out)
{
    *out = NULL;
    if ((unsigned)filter >= (unsigned)NFILTERS)
        return bvox__fail(BVOX_EINVAL, "unknown filter %d", (int)filter);
    if (filter != BVOX_FILTER_SOBEL)
        return bvox_image_convolve(in, presets[filter], preset_div[filter], 0, out);
    bvox_status st = prepare(in, out);
    if (st) return st;
    for (int32_t y = 0; y < in->height; y++)
        for (int32_t x = 0; x < in->width; x++)
            for (int32_t c = 0; c < in->channels; c++) {
                int32_t p[9];
                gather(in, x, y, c, p);
                int64_t gx = (p[2] + 2 * p[5] + p[8]) - (p[0] + 2 * p[3] + p[6]);
                int64_t gy = (p[6] + 2 * p[7] + p[8]) - (p[0] + 2 * p[1] + p[2]);
                double m = sqrt((double)(gx * gx + gy * gy));
                (*out)->pixels[((size_t)y * (size_t)in->width + (size_t)x) *
                                   (size_t)in->channels + (size_t)c] = sat((int64_t)(m + 0.5));
            }
    return BVOX_OK;
}
