/*
 * image_png.c — bvox_image to and from PNG (libpng). Writing goes through the
 * temp+rename sink of src/io, so a failure leaves no partial file. libpng
 * reports errors by longjmp: each call owns its png structs and frees them on
 * both paths, and our own buffers are allocated outside the setjmp region
 * (or released on the error path from a variable that survives the jump).
 */
#include "io.h"
#include "common/image.h"

#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

typedef struct png_io {
    bvox__sink *sink;      /* writing */
    const uint8_t *data;   /* reading */
    size_t size, pos;
    char msg[200];
    bvox_status alloc_status; /* the image allocation failed with this */
} png_io;

static void on_error(png_structp png, png_const_charp msg)
{
    png_io *io = png_get_error_ptr(png);
    snprintf(io->msg, sizeof io->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg) {}

static void write_cb(png_structp png, png_bytep data, size_t n)
{
    png_io *io = png_get_io_ptr(png);
    if (bvox__sink_write(io->sink, data, n) != BVOX_OK) png_error(png, "write failed");
}

static void flush_cb(png_structp png) {}

static bvox_status encode(png_io *io, const bvox_image *img, const char *path)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, io, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_write_struct(&png, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &pi);
        return bvox__fail(BVOX_EIO, "%s: %s", path, io->msg);
    }
    png_set_write_fn(png, io, write_cb, flush_cb);
    png_set_IHDR(png, pi, (png_uint_32)img->width, (png_uint_32)img->height, img->bits,
                 img->channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, pi);
    const uint16_t probe = 1;
    if (img->bits == 16 && *(const uint8_t *)&probe) png_set_swap(png); /* PNG is big-endian */
    size_t row = (size_t)img->width * (size_t)img->channels;
    for (int32_t y = 0; y < img->height; y++) {
        png_const_bytep p = img->bits == 8 ? (png_const_bytep)(img->pixels + (size_t)y * row)
                                           : (png_const_bytep)(img->pixels16 + (size_t)y * row);
        png_write_row(png, p);
    }
    png_write_end(png, pi);
    png_destroy_write_struct(&png, &pi);
    return BVOX_OK;
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
    png_io io = {&sink, NULL, 0, 0, {0}, BVOX_OK};
    st = encode(&io, img, path);
    if (st) {
        bvox__sink_abort(&sink);
        return st;
    }
    return bvox__sink_commit(&sink);
}

static void read_cb(png_structp png, png_bytep out, size_t n)
{
    png_io *io = png_get_io_ptr(png);
    if (n > io->size - io->pos) png_error(png, "the file is truncated");
    memcpy(out, io->data + io->pos, n);
    io->pos += n;
}

/* The image is created inside the setjmp region, so it is kept in io-owned
 * storage (*slot) that survives the longjmp and is released on the error path. */
static bvox_status decode(png_io *io, const char *name, bvox_image **slot)
{
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, io, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_read_struct(&png, NULL, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &pi, NULL);
        bvox_image_destroy(*slot);
        *slot = NULL;
        if (io->alloc_status) return bvox__fail(io->alloc_status, "%s: %s", name, io->msg);
        return bvox__fail(BVOX_EFORMAT, "%s: %s", name, io->msg);
    }
    png_set_read_fn(png, io, read_cb);
    png_set_user_limits(png, BVOX_IMAGE_MAX_DIM, BVOX_IMAGE_MAX_DIM);
    png_set_chunk_malloc_max(png, (png_alloc_size_t)8 << 20);
    png_read_info(png, pi);
    png_uint_32 w, h;
    int depth, color;
    png_get_IHDR(png, pi, &w, &h, &depth, &color, NULL, NULL, NULL);
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if ((color & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, pi, PNG_INFO_tRNS))
        png_set_strip_alpha(png);
    const uint16_t probe = 1;
    if (depth == 16 && *(const uint8_t *)&probe) png_set_swap(png);
    int passes = png_set_interlace_handling(png);
    png_read_update_info(png, pi);
    int channels = png_get_channels(png, pi);
    int bits = depth == 16 ? 16 : 8;
    if (channels != 1 && channels != 3) png_error(png, "unexpected channel count");
    io->alloc_status = bvox_image_create((int32_t)w, (int32_t)h, channels, bits, slot);
    if (io->alloc_status) png_error(png, bvox_errmsg());
    size_t row = (size_t)w * (size_t)channels * (size_t)(bits / 8);
    if (png_get_rowbytes(png, pi) != row) png_error(png, "unexpected row size");
    uint8_t *base = bits == 8 ? (*slot)->pixels : (uint8_t *)(*slot)->pixels16;
    for (int p = 0; p < passes; p++)
        for (png_uint_32 y = 0; y < h; y++) png_read_row(png, base + (size_t)y * row, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &pi, NULL);
    return BVOX_OK;
}

bvox_status bvox_image_read_png_memory(const void *data, size_t size, const char *name,
                                       bvox_image **out)
{
    *out = NULL;
    if (!name) name = "PNG";
    if (!data || size < 8 || png_sig_cmp(data, 0, 8))
        return bvox__fail(BVOX_EFORMAT, "%s: not a PNG file", name);
    png_io io = {NULL, data, size, 0, {0}, BVOX_OK};
    bvox_image *slot = NULL; /* not a local of decode: survives its longjmp */
    bvox_status st = decode(&io, name, &slot);
    if (!st) *out = slot;
    return st;
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
