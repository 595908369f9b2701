/*
 * image_png.c — bvox_image to and from PNG, through the libpng wrapper of
 * src/common/png.h. Writing goes through the temp+rename sink, so a failure
 * leaves no partial file.
 */
#include "io.h"
#include "common/image.h"
#include "common/png.h"

#include <string.h>

static bvox_status sink_write(void *sink, const void *data, size_t n)
{
    return bvox__sink_write(sink, data, n);
}

bvox_status bvox_image_write_png(const bvox_image *img, const char *path)
{
    bvox_status st = bvox__image_check(img, path ? path : "PNG");
    if (st) return st;
    if (!path) return bvox__fail(BVOX_EINVAL, "no output path");
    if (img->width > 0x7fffffff / 8) return bvox__fail(BVOX_EINVAL, "%s: image too wide", path);
    bvox__sink sink;
    st = bvox__sink_open(path, 0, &sink);
    if (st) return st;
    const bvox__png_write_opts o = {img->channels, img->bits, {0, 0}, 0};
    const void *px = img->bits == 8 ? (const void *)img->pixels : (const void *)img->pixels16;
    st = bvox__png_encode((uint32_t)img->width, (uint32_t)img->height, px, &o, sink_write, &sink,
                          path);
    if (st) {
        bvox__sink_abort(&sink);
        return st;
    }
    return bvox__sink_commit(&sink);
}

/* The image is made once the header is known; it is the caller's to release
 * when a later libpng error stops the decode. */
typedef struct decoding {
    const char *name;
    bvox_image *img;
} decoding;

static bvox_status make_image(void *ctx, const bvox__png_info *info, uint8_t **rows)
{
    decoding *d = ctx;
    bvox_status st = bvox_image_create((int32_t)info->width, (int32_t)info->height,
                                       info->channels, info->bytes * 8, &d->img);
    if (st) {
        bvox__error_prefix(d->name);
        return st;
    }
    *rows = info->bytes == 1 ? d->img->pixels : (uint8_t *)d->img->pixels16;
    return BVOX_OK;
}

bvox_status bvox_image_read_png_memory(const void *data, size_t size, const char *name,
                                       bvox_image **out)
{
    *out = NULL;
    if (!name) name = "PNG";
    const bvox__png_read_opts o = {BVOX_IMAGE_MAX_DIM, 0, 0};
    decoding d = {name, NULL};
    bvox_status st = bvox__png_decode(data, size, name, &o, make_image, &d);
    if (st) {
        bvox_image_destroy(d.img);
        return st;
    }
    *out = d.img;
    return BVOX_OK;
}

bvox_status bvox_image_read_png(const char *path, bvox_image **out)
{
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "no input path");
    bvox__bytes b;
    bvox_status st = bvox__read_file(path, &b);
    if (st) return st;
    st = bvox_image_read_png_memory(b.data, b.size, path, out);
    bvox__bytes_release(&b);
    return st;
}
