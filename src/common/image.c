/*
 * image.c — the bvox_image type: create, copy, destroy. The public struct is
 * the first member of a private block that remembers the byte count given to
 * the budgeted allocator, so a caller who scribbles on width or height cannot
 * make the release miscount the budget.
 */
#include "image.h"

#include <stdlib.h>
#include <string.h>

typedef struct image_block {
    bvox_image pub; /* first: a bvox_image * is a image_block * */
    size_t bytes;
} image_block;

bvox_status bvox__image_check(const bvox_image *img, const char *what)
{
    if (!img) return bvox__fail(BVOX_EINVAL, "%s: no image", what);
    if (img->width < 1 || img->height < 1 || img->width > BVOX_IMAGE_MAX_DIM ||
        img->height > BVOX_IMAGE_MAX_DIM || (img->channels != 1 && img->channels != 3 && img->channels != 4) ||
        (img->bits == 8 ? !img->pixels : img->bits == 16 ? !img->pixels16 : 1))
        return bvox__fail(BVOX_EINVAL, "%s: not a valid image", what);
    return BVOX_OK;
}

bvox_status bvox_image_create(int32_t width, int32_t height, int32_t channels, int32_t bits,
                              bvox_image **out)
{
    *out = NULL;
    if (width < 1 || height < 1 || width > BVOX_IMAGE_MAX_DIM || height > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "image size %d x %d is outside 1..%d", (int)width,
                          (int)height, BVOX_IMAGE_MAX_DIM);
    if (channels != 1 && channels != 3 && channels != 4) /* 4: RGBA (issue 18, transparent) */
        return bvox__fail(BVOX_EINVAL, "an image has 1, 3 or 4 channels, not %d", (int)channels);
    if (bits != 8 && bits != 16)
        return bvox__fail(BVOX_EINVAL, "an image has 8 or 16 bits per sample, not %d",
                          (int)bits);
    size_t bytes;
    if (!bvox__mul_size((size_t)width * (size_t)height, (size_t)channels * (size_t)(bits / 8),
                        &bytes))
        return bvox__fail(BVOX_ETOOBIG, "image %d x %d overflows", (int)width, (int)height);
    image_block *b = bvox__mem_zalloc(1, sizeof *b);
    if (!b) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bvox_status st;
    void *px = bvox__alloc(bytes, true, "image", &st);
    if (!px) {
        free(b);
        return st;
    }
    b->bytes = bytes;
    b->pub.width = width;
    b->pub.height = height;
    b->pub.channels = channels;
    b->pub.bits = bits;
    if (bits == 8) b->pub.pixels = px;
    else b->pub.pixels16 = px;
    *out = &b->pub;
    return BVOX_OK;
}

void bvox_image_destroy(bvox_image *img)
{
    if (!img) return;
    image_block *b = (image_block *)img;
    bvox__free(img->bits == 8 ? (void *)img->pixels : (void *)img->pixels16, b->bytes);
    free(b);
}

bvox_status bvox_image_copy(const bvox_image *img, bvox_image **out)
{
    *out = NULL;
    bvox_status st = bvox__image_check(img, "image copy");
    if (st) return st;
    st = bvox_image_create(img->width, img->height, img->channels, img->bits, out);
    if (st) return st;
    memcpy(img->bits == 8 ? (void *)(*out)->pixels : (void *)(*out)->pixels16,
           img->bits == 8 ? (const void *)img->pixels : (const void *)img->pixels16,
           ((image_block *)*out)->bytes);
    return BVOX_OK;
}
