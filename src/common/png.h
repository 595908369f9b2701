/*
 * png.h — the one libpng wrapper: decoding PNG data from memory and encoding
 * rows through a write callback, with libpng's longjmp errors turned into a
 * bvox_status and a message. Its users: the PNG slice folders
 * (io/png_slices.c) and bvox_image's PNG files (io/image_png.c; section
 * images and pictures go through those).
 */
#ifndef BVOX_COMMON_PNG_H
#define BVOX_COMMON_PNG_H

#include "internal.h"

/* What a decode found, after conversion. */
typedef struct bvox__png_info {
    uint32_t width, height;
    int depth;       /* bits per sample as stored: 1, 2, 4, 8 or 16 */
    int channels;    /* after conversion: 1 (gray) or 3 (RGB) */
    int bytes;       /* per sample after conversion: 1 or 2 (native byte order) */
    uint32_t ppm[2]; /* pixels per metre from pHYs in metres; 0 when none */
} bvox__png_info;

/* The conversion. Always: palette to RGB, gray below 8 bits to 8, alpha and
 * tRNS dropped. gray: RGB becomes luminance (libpng's default weights).
 * bytes: 0 keeps 8 or 16 bits as stored; 1 scales 16 bits down, 2 expands
 * to 16. Images wider or higher than max_dim are refused. */
typedef struct bvox__png_read_opts {
    uint32_t max_dim;
    int gray;
    int bytes;
} bvox__png_read_opts;

/* Called once the header is read and the conversion set up: *rows = where
 * the info->height rows of width * channels * bytes bytes go, one after the
 * other, or NULL to stop there (only the header was wanted). A status other
 * than BVOX_OK (message set by the callback) stops the decode with it. */
typedef bvox_status (*bvox__png_rows_fn)(void *ctx, const bvox__png_info *info, uint8_t **rows);

/* Decode the PNG in data. Not a PNG, or any libpng error (truncated, corrupt,
 * over max_dim): BVOX_EFORMAT "NAME: reason". libpng's own allocations for
 * text chunks are capped at 8 MiB. */
bvox_status bvox__png_decode(const void *data, size_t size, const char *name,
                             const bvox__png_read_opts *o, bvox__png_rows_fn rows, void *ctx);

typedef struct bvox__png_write_opts {
    int channels;    /* 1 or 3 */
    int bits;        /* 8 or 16 (samples in native byte order) */
    uint32_t ppm[2]; /* pHYs in pixels per metre when ppm[0] > 0 */
    int masks;       /* 0/255 masks: no row filter, run-length matching (fast, small) */
} bvox__png_write_opts;

/* Receives the encoded bytes; a non-OK status aborts the encode. */
typedef bvox_status (*bvox__png_write_fn)(void *ctx, const void *data, size_t n);

/* Encode width x height pixels (rows one after the other, width * channels
 * samples each) through write. A libpng or write failure: BVOX_EIO
 * "NAME: reason". */
bvox_status bvox__png_encode(uint32_t width, uint32_t height, const void *pixels,
                             const bvox__png_write_opts *o, bvox__png_write_fn write, void *ctx,
                             const char *name);

#endif
