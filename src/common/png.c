/*
 * png.c — the libpng wrapper of png.h. libpng reports errors by longjmp:
 * each call owns its png structs and frees them on both paths; the state
 * that must survive the jump lives in a context outside the function that
 * calls setjmp (C11 7.13.2.1), and buffers are the caller's (allocated by
 * its callback, released by the caller), so nothing leaks.
 */
#include "png.h"

#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <zlib.h>

typedef struct png_ctx {
    const uint8_t *data; /* reading */
    size_t size, pos;
    bvox__png_write_fn write; /* writing */
    void *write_ctx;
    char msg[200];
    bvox_status status; /* a callback's own failure: returned as it is */
} png_ctx;

static void on_error(png_structp png, png_const_charp msg)
{
    png_ctx *c = png_get_error_ptr(png);
    snprintf(c->msg, sizeof c->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void read_cb(png_structp png, png_bytep out, size_t n)
{
    png_ctx *c = png_get_io_ptr(png);
    if (n > c->size - c->pos) png_error(png, "the file is truncated");
    memcpy(out, c->data + c->pos, n);
    c->pos += n;
}

static int little_endian(void)
{
    const uint16_t probe = 1;
    return *(const uint8_t *)&probe;
}

static bvox_status decode_with(png_ctx *c, const char *name, const bvox__png_read_opts *o,
                               bvox__png_rows_fn rows, void *ctx)
{
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, c, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_read_struct(&png, NULL, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &pi, NULL);
        return bvox__fail(BVOX_EFORMAT, "%s: %s", name, c->msg);
    }
    png_set_read_fn(png, c, read_cb);
    png_set_user_limits(png, o->max_dim, o->max_dim);
    png_set_chunk_malloc_max(png, (png_alloc_size_t)8 << 20); /* text, ICC profiles */
    png_read_info(png, pi);
    png_uint_32 w, h, rx = 0, ry = 0;
    int depth, color, unit = -1;
    png_get_IHDR(png, pi, &w, &h, &depth, &color, NULL, NULL, NULL);
    bvox__png_info info = {w, h, depth, 0, 0, {0, 0}};
    if (png_get_pHYs(png, pi, &rx, &ry, &unit) && unit == PNG_RESOLUTION_METER && rx && ry) {
        info.ppm[0] = rx;
        info.ppm[1] = ry;
    }
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if ((color & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, pi, PNG_INFO_tRNS))
        png_set_strip_alpha(png);
    if (o->gray && (color & PNG_COLOR_MASK_COLOR))
        png_set_rgb_to_gray_fixed(png, 1, -1, -1); /* luminance */
    info.bytes = o->bytes ? o->bytes : depth == 16 ? 2 : 1;
    if (info.bytes == 1 && depth == 16) png_set_scale_16(png);
    if (info.bytes == 2 && depth < 16) png_set_expand_16(png);
    if (info.bytes == 2 && little_endian()) png_set_swap(png); /* PNG is big-endian */
    int passes = png_set_interlace_handling(png);
    png_read_update_info(png, pi);
    info.channels = png_get_channels(png, pi);
    size_t row = (size_t)w * (size_t)info.channels * (size_t)info.bytes;
    if ((info.channels != 1 && (o->gray || info.channels != 3)) || png_get_rowbytes(png, pi) != row)
        png_error(png, "unexpected sample layout after conversion");
    uint8_t *dst = NULL;
    c->status = rows(ctx, &info, &dst);
    if (c->status || !dst) {
        png_destroy_read_struct(&png, &pi, NULL);
        return c->status;
    }
    for (int p = 0; p < passes; p++)
        for (png_uint_32 y = 0; y < h; y++) png_read_row(png, dst + (size_t)y * row, NULL);
    png_read_end(png, NULL); /* a file cut after its pixels is still truncated */
    png_destroy_read_struct(&png, &pi, NULL);
    return BVOX_OK;
}

bvox_status bvox__png_decode(const void *data, size_t size, const char *name,
                             const bvox__png_read_opts *o, bvox__png_rows_fn rows, void *ctx)
{
    if (!data || size < 8 || png_sig_cmp(data, 0, 8))
        return bvox__fail(BVOX_EFORMAT, "%s: not a PNG file", name);
    png_ctx c = {data, size, 0, NULL, NULL, {0}, BVOX_OK};
    return decode_with(&c, name, o, rows, ctx);
}

static void write_cb(png_structp png, png_bytep data, size_t n)
{
    png_ctx *c = png_get_io_ptr(png);
    if ((c->status = c->write(c->write_ctx, data, n)) != BVOX_OK) png_error(png, "write failed");
}

static void flush_cb(png_structp png) { (void)png; }

static bvox_status encode_with(png_ctx *c, uint32_t w, uint32_t h, const void *pixels,
                               const bvox__png_write_opts *o, const char *name)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, c, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_write_struct(&png, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &pi);
        return bvox__fail(BVOX_EIO, "%s: %s", name, c->msg);
    }
    png_set_write_fn(png, c, write_cb, flush_cb);
    const int color = o->channels == 4   ? PNG_COLOR_TYPE_RGB_ALPHA
                      : o->channels == 3 ? PNG_COLOR_TYPE_RGB
                                         : PNG_COLOR_TYPE_GRAY;
    png_set_IHDR(png, pi, w, h, o->bits, color, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (o->ppm[0]) png_set_pHYs(png, pi, o->ppm[0], o->ppm[1], PNG_RESOLUTION_METER);
    if (o->masks) {
        /* Masks of 0/255 compress well unfiltered with run-length matching,
         * and filter search and deeper matching are slow for no gain. */
        png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
        png_set_compression_strategy(png, Z_RLE);
    }
    png_write_info(png, pi);
    if (o->bits == 16 && little_endian()) png_set_swap(png); /* PNG is big-endian */
    size_t row = (size_t)w * (size_t)o->channels * (size_t)(o->bits / 8);
    for (uint32_t y = 0; y < h; y++) png_write_row(png, (png_const_bytep)pixels + (size_t)y * row);
    png_write_end(png, pi);
    png_destroy_write_struct(&png, &pi);
    return BVOX_OK;
}

bvox_status bvox__png_encode(uint32_t width, uint32_t height, const void *pixels,
                             const bvox__png_write_opts *o, bvox__png_write_fn write, void *ctx,
                             const char *name)
{
    png_ctx c = {NULL, 0, 0, write, ctx, {0}, BVOX_OK};
    return encode_with(&c, width, height, pixels, o, name);
}
