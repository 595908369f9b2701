/*
 * preimage_from_depth.c — a pre-image rebuilt from a 16-bit depth map (the
 * file `bvox render --depth` writes: 0 background, else depth + 1), so that
 * `bvox image` can run the paper's pre-image operators (enlarging, gradient
 * operators) on a picture alone, as the paper's image processor did on the
 * frame buffer without the voxels.
 */
#include "render.h"

#include <string.h>

bvox_status bvox_preimage_from_depth_map(const bvox_image *map, bvox_preimage **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(map, "depth map");
    if (st) return st;
    if (map->bits != 16 || map->channels != 1)
        return bvox__fail(BVOX_EINVAL, "depth map: needs a 16-bit gray image (render --depth), "
                                       "not %d-bit with %d channel%s",
                          (int)map->bits, (int)map->channels, map->channels == 1 ? "" : "s");
    bvox_preimage *p;
    if ((st = bvox__preimage_alloc(map->width, map->height, &p))) return st;
    const size_t n = (size_t)map->width * (size_t)map->height;
    int32_t top = 0;
    for (size_t i = 0; i < n; i++) {
        int32_t d = (int32_t)map->pixels16[i] - 1;
        p->depth[i] = d;
        p->code[i] = d < 0 ? BVOX_CODE_BACKGROUND : BVOX_NORMAL_NONE;
        top = d > top ? d : top;
    }
    p->depth_range = top + 1;
    p->depth_step = 1;
    p->pixel_size[0] = p->pixel_size[1] = 1;
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(p->eye, eye, sizeof eye);
    p->spacing[0] = p->spacing[1] = p->spacing[2] = 1;
    *out = p;
    return BVOX_OK;
}
