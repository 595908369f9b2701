/*
 * zarr_pyramid.c — one step of the OME-Zarr resolution pyramid: a volume
 * halved along every axis, a coarse voxel set when any of its (up to)
 * 2x2x2 fine voxels is. The four fine columns are ORed a word at a time,
 * then each pair of bits along z is ORed and the odd positions squeezed
 * out, 64 fine voxels into 32 coarse ones per word.
 */
#include "zarr.h"

/* The even bits of x (after x | x >> 1: each pair's OR) packed into the low
 * 32 bits. */
static uint64_t squeeze_pairs(uint64_t x)
{
    x = (x | (x >> 1)) & 0x5555555555555555u;
    x = (x | (x >> 1)) & 0x3333333333333333u;
    x = (x | (x >> 2)) & 0x0f0f0f0f0f0f0f0fu;
    x = (x | (x >> 4)) & 0x00ff00ff00ff00ffu;
    x = (x | (x >> 8)) & 0x0000ffff0000ffffu;
    x = (x | (x >> 16)) & 0x00000000ffffffffu;
    return x;
}

void bvox__downsample_or(const bvox_volume *src, bvox_volume *dst)
{
    BVOX_ASSERT(dst->nx == (src->nx + 1) / 2 && dst->ny == (src->ny + 1) / 2 &&
                dst->nz == (src->nz + 1) / 2);
    const size_t sw = src->wpc, dw = dst->wpc;
    for (int32_t y = 0; y < dst->ny; y++)
        for (int32_t x = 0; x < dst->nx; x++) {
            uint64_t *out = dst->words + ((size_t)y * (size_t)dst->nx + (size_t)x) * dw;
            for (size_t k = 0; k < dw; k++) out[k] = 0;
            for (size_t k = 0; k < sw; k++) {
                uint64_t v = 0;
                for (int32_t dy = 0; dy < 2; dy++)
                    for (int32_t dx = 0; dx < 2; dx++) {
                        int32_t sx = 2 * x + dx, sy = 2 * y + dy;
                        if (sx < src->nx && sy < src->ny)
                            v |= src->words[((size_t)sy * (size_t)src->nx + (size_t)sx) * sw + k];
                    }
                /* fine word k holds coarse voxels 32k .. 32k+31 */
                out[k / 2] |= squeeze_pairs(v) << (32 * (k & 1));
            }
        }
}
