/*
 * section_gray.c — bvox_section_gray: a gray or RGB section image as gray
 * (luminance, Rec. 601 weights, rounded). On its own so that both section
 * readers (PNG in section_image.c, TIFF in section_tiff.c) can use it
 * without calling each other.
 */
#include "section_internal.h"

bvox_status bvox_section_gray(const bvox_image *img, bvox_image **out)
{
    *out = NULL;
    if (!img || (img->channels != 1 && img->channels != 3))
        return bvox__fail(BVOX_EINVAL, "a section image must be gray or RGB");
    if (img->channels == 1) return bvox_image_copy(img, out);
    bvox_status st = bvox_image_create(img->width, img->height, 1, img->bits, out);
    if (st) return st;
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++) {
        double r, g, b;
        if (img->bits == 8) {
            r = img->pixels[3 * i], g = img->pixels[3 * i + 1], b = img->pixels[3 * i + 2];
            (*out)->pixels[i] = (uint8_t)(0.299 * r + 0.587 * g + 0.114 * b + 0.5);
        } else {
            r = img->pixels16[3 * i], g = img->pixels16[3 * i + 1], b = img->pixels16[3 * i + 2];
            (*out)->pixels16[i] = (uint16_t)(0.299 * r + 0.587 * g + 0.114 * b + 0.5);
        }
    }
    return BVOX_OK;
}
