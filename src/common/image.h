/*
 * image.h — private helpers of the bvox_image type (include/bvox.h; made in
 * src/common/image.c), for every room that handles images: render/ (pictures,
 * zoom, convolution, GIF), recon/ (section images), io/ (PNG files).
 */
#ifndef BVOX_COMMON_IMAGE_H
#define BVOX_COMMON_IMAGE_H

#include "internal.h"

/* Image sample access for ops that handle both depths. */
static inline uint32_t bvox__img_get(const bvox_image *im, size_t i)
{
    return im->bits == 8 ? im->pixels[i] : im->pixels16[i];
}
static inline void bvox__img_put(bvox_image *im, size_t i, uint32_t v)
{
    if (im->bits == 8) im->pixels[i] = (uint8_t)v;
    else im->pixels16[i] = (uint16_t)v;
}
/* BVOX_EINVAL unless img is a valid image (non-NULL, sane fields). */
bvox_status bvox__image_check(const bvox_image *img, const char *what);

#endif
