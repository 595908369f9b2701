/*
 * preimage_enlarge.c — the paper's "enlarging a pre-image" (section 4.2,
 * Figure 5): zoom the depth pre-image x2 by replication, then run the pixel
 * averaging operator, so that the original depths stay where they were and
 * the replicated ones become interpolated; a gradient operator run over the
 * result (Picture 2's order) then sees slopes at twice the resolution.
 * Only foreground pixels are averaged: a depth averaged with the background
 * would be a cliff, not an interpolation (the paper's frame buffer had no
 * background value, its pictures a dark surround).
 */
#include "render.h"

#include <string.h>

bvox_status bvox_preimage_enlarge(const bvox_preimage *pre, bvox_preimage **out)
{
    *out = NULL;
    if (!pre || !pre->depth || !pre->code || pre->width < 1 || pre->height < 1)
        return bvox__fail(BVOX_EINVAL, "enlarge: not a valid pre-image");
    if ((int64_t)pre->width * 2 > BVOX_IMAGE_MAX_DIM || (int64_t)pre->height * 2 > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "enlarge: %d x %d doubled is over %d pixels a side",
                          (int)pre->width, (int)pre->height, BVOX_IMAGE_MAX_DIM);
    const int32_t w = pre->width, h = pre->height, W = 2 * w, H = 2 * h;
    bvox_preimage *p;
    bvox_status st = bvox__preimage_alloc(W, H, &p);
    if (st) return st;
    p->depth_range = pre->depth_range;
    p->depth_step = pre->depth_step;
    p->pixel_size[0] = pre->pixel_size[0] / 2;
    p->pixel_size[1] = pre->pixel_size[1] / 2;
    memcpy(p->eye, pre->eye, sizeof p->eye);
    memcpy(p->origin, pre->origin, sizeof p->origin);
    memcpy(p->spacing, pre->spacing, sizeof p->spacing);
    for (int32_t Y = 0; Y < H; Y++)
        for (int32_t X = 0; X < W; X++) {
            const int32_t i = X >> 1, j = Y >> 1;
            const size_t src = (size_t)j * (size_t)w + (size_t)i, dst = (size_t)Y * (size_t)W + (size_t)X;
            p->code[dst] = pre->code[src];
            if (pre->depth[src] < 0) {
                p->depth[dst] = -1;
                continue;
            }
            /* the 1, 2 or 4 original pixels around (X, Y), as Figure 5 */
            int64_t sum = 0, n = 0;
            for (int32_t b = j; b <= j + (Y & 1) && b < h; b++)
                for (int32_t a = i; a <= i + (X & 1) && a < w; a++) {
                    int32_t d = pre->depth[(size_t)b * (size_t)w + (size_t)a];
                    if (d >= 0) sum += d, n++;
                }
            p->depth[dst] = (int32_t)((2 * sum + n) / (2 * n)); /* rounded half up */
        }
    *out = p;
    return BVOX_OK;
}
