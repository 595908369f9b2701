/*
 * section_tiff.c — a TIFF section image (its first page) as an 8- or
 * 16-bit gray bvox_image, through libtiff on a memory buffer (the file is
 * read whole through the budget first). Unsigned 8/16-bit gray or RGB
 * strips are read as stored (min-is-white inverted); anything else libtiff
 * can decode (palette, tiles, other depths, YCbCr, ...) goes through
 * TIFFReadRGBAImageOriented as 8-bit RGB. RGB becomes luminance. libtiff's
 * messages are caught (the library never prints) and its single
 * allocations are bounded by the memory budget.
 */
#include "section_internal.h"
#include "io/io.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>

typedef struct memsrc {
    const uint8_t *data;
    uint64_t size, pos;
} memsrc;

static tmsize_t src_read(thandle_t h, void *buf, tmsize_t n)
{
    memsrc *m = h;
    if (n <= 0 || m->pos >= m->size) return 0;
    uint64_t k = m->size - m->pos;
    if ((uint64_t)n < k) k = (uint64_t)n;
    memcpy(buf, m->data + m->pos, (size_t)k);
    m->pos += k;
    return (tmsize_t)k;
}

static tmsize_t src_write(thandle_t h, void *buf, tmsize_t n) { return -1; }

static toff_t src_seek(thandle_t h, toff_t off, int whence)
{
    memsrc *m = h;
    if (whence == SEEK_SET) return m->pos = off;
    uint64_t base = whence == SEEK_CUR ? m->pos : m->size;
    int64_t d = (int64_t)off;
    if (d < 0) {
        uint64_t back = (uint64_t)0 - (uint64_t)d;
        if (back > base) return (toff_t)-1;
        m->pos = base - back;
    } else if (__builtin_add_overflow(base, (uint64_t)d, &m->pos)) {
        return (toff_t)-1;
    }
    return m->pos;
}

static int src_close(thandle_t h) { return 0; }
static toff_t src_size(thandle_t h) { return ((memsrc *)h)->size; }

static int src_map(thandle_t h, void **base, toff_t *size)
{
    memsrc *m = h;
    *base = (void *)m->data;
    *size = m->size;
    return 1;
}

static void src_unmap(thandle_t h, void *base, toff_t size) {}

typedef struct tiff_err {
    char msg[200];
    int have;
} tiff_err;

static int on_error(TIFF *tif, void *user, const char *module, const char *fmt, va_list ap)
{
    tiff_err *e = user;
    if (!e->have) {
        vsnprintf(e->msg, sizeof e->msg, fmt, ap);
        e->have = 1;
    }
    return 1; /* handled: libtiff's default handler (which prints) is not called */
}

static int on_warning(TIFF *tif, void *user, const char *module, const char *fmt, va_list ap)
{
    return 1;
}

/* Strips of unsigned 8/16-bit gray or RGB, interleaved: as stored. */
static bvox_status read_plain(TIFF *tif, const char *name, tiff_err *err, uint32_t w, uint32_t h,
                              uint16_t bps, uint16_t spp, int invert, bvox_image **out)
{
    bvox_status st = bvox_image_create((int32_t)w, (int32_t)h, spp, bps, out);
    if (st) return st;
    tmsize_t line = TIFFScanlineSize(tif);
    size_t need = (size_t)w * spp * (bps / 8);
    if (line <= 0 || (size_t)line < need) {
        bvox_image_destroy(*out);
        *out = NULL;
        return bvox__fail(BVOX_EFORMAT, "%s: bad scanline size", name);
    }
    uint8_t *buf = malloc((size_t)line);
    if (!buf) {
        bvox_image_destroy(*out);
        *out = NULL;
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    for (uint32_t y = 0; y < h; y++) {
        if (TIFFReadScanline(tif, buf, y, 0) < 0) {
            free(buf);
            bvox_image_destroy(*out);
            *out = NULL;
            return bvox__fail(BVOX_EFORMAT, "%s: row %u: %s", name, (unsigned)y,
                              err->have ? err->msg : "truncated or corrupt");
        }
        if (bps == 8) {
            uint8_t *dst = (*out)->pixels + (size_t)y * need;
            memcpy(dst, buf, need);
            if (invert)
                for (size_t i = 0; i < need; i++) dst[i] = (uint8_t)(255 - dst[i]);
        } else {
            uint16_t *dst = (*out)->pixels16 + (size_t)y * (need / 2);
            memcpy(dst, buf, need);
            if (invert)
                for (size_t i = 0; i < need / 2; i++) dst[i] = (uint16_t)(65535 - dst[i]);
        }
    }
    free(buf);
    return BVOX_OK;
}

/* Anything else libtiff decodes: 8-bit RGB(A) through its RGBA interface. */
static bvox_status read_rgba(TIFF *tif, const char *name, tiff_err *err, uint32_t w, uint32_t h,
                             bvox_image **out)
{
    size_t n = (size_t)w * (size_t)h, bytes;
    if (!bvox__mul_size(n, sizeof(uint32_t), &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: %u x %u pixels overflow", name, (unsigned)w, (unsigned)h);
    bvox_status st;
    uint32_t *raster = bvox__alloc(bytes, false, "TIFF raster", &st);
    if (!raster) return st;
    if (!TIFFReadRGBAImageOriented(tif, w, h, raster, ORIENTATION_TOPLEFT, 0)) {
        bvox__free(raster, bytes);
        return bvox__fail(BVOX_EFORMAT, "%s: cannot decode the image (%s)", name,
                          err->have ? err->msg : "unsupported layout");
    }
    st = bvox_image_create((int32_t)w, (int32_t)h, 3, 8, out);
    if (!st)
        for (size_t i = 0; i < n; i++) {
            (*out)->pixels[3 * i] = (uint8_t)TIFFGetR(raster[i]);
            (*out)->pixels[3 * i + 1] = (uint8_t)TIFFGetG(raster[i]);
            (*out)->pixels[3 * i + 2] = (uint8_t)TIFFGetB(raster[i]);
        }
    bvox__free(raster, bytes);
    return st;
}

bvox_status bvox__section_tiff_decode(const uint8_t *data, size_t size, const char *name,
                                      bvox_image **out)
{
    *out = NULL;
    if (!name) name = "TIFF";
    memsrc src = {data, size, 0};
    tiff_err err = {{0}, 0};
    TIFFOpenOptions *o = TIFFOpenOptionsAlloc();
    if (!o) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    TIFFOpenOptionsSetErrorHandlerExtR(o, on_error, &err);
    TIFFOpenOptionsSetWarningHandlerExtR(o, on_warning, &err);
    size_t budget = bvox_memory_budget();
    TIFFOpenOptionsSetMaxSingleMemAlloc(o, (tmsize_t)(budget > ((size_t)1 << 62) ? (size_t)1 << 62
                                                                               : budget));
    TIFF *tif = TIFFClientOpenExt(name, "r", &src, src_read, src_write, src_seek, src_close,
                                  src_size, src_map, src_unmap, o);
    TIFFOpenOptionsFree(o);
    if (!tif)
        return bvox__fail(BVOX_EFORMAT, "%s: not a readable TIFF file (%s)", name,
                          err.have ? err.msg : "bad header");
    uint32_t w = 0, h = 0;
    uint16_t bps = 1, spp = 1, photo = PHOTOMETRIC_MINISBLACK, planar = PLANARCONFIG_CONTIG,
             fmt = SAMPLEFORMAT_UINT;
    bvox_status st = BVOX_OK;
    TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
    TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bps);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
    TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &fmt);
    if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photo)) photo = PHOTOMETRIC_MINISBLACK;
    size_t px;
    if (w < 1 || h < 1 || w > BVOX_IMAGE_MAX_DIM || h > BVOX_IMAGE_MAX_DIM) {
        st = bvox__fail(BVOX_EFORMAT, "%s: image size %u x %u is outside 1..%d", name,
                        (unsigned)w, (unsigned)h, BVOX_IMAGE_MAX_DIM);
    } else if (!bvox__mul_size((size_t)w * h, 4, &px) || px > bvox_memory_budget()) {
        st = bvox__fail(BVOX_ETOOBIG, "%s: %u x %u pixels are over the memory budget", name,
                        (unsigned)w, (unsigned)h);
    } else {
        int gray = photo == PHOTOMETRIC_MINISBLACK || photo == PHOTOMETRIC_MINISWHITE;
        int plain = (bps == 8 || bps == 16) && fmt == SAMPLEFORMAT_UINT && !TIFFIsTiled(tif) &&
                    ((gray && spp == 1) ||
                     (photo == PHOTOMETRIC_RGB && spp == 3 && planar == PLANARCONFIG_CONTIG));
        bvox_image *img = NULL;
        st = plain ? read_plain(tif, name, &err, w, h, bps, spp, photo == PHOTOMETRIC_MINISWHITE, &img)
                   : read_rgba(tif, name, &err, w, h, &img);
        if (!st && img->channels == 3) {
            st = bvox_section_gray(img, out);
            bvox_image_destroy(img);
        } else if (!st) {
            *out = img;
        }
    }
    TIFFClose(tif);
    return st;
}

bvox_status bvox__section_tiff_read(const char *path, bvox_image **out)
{
    *out = NULL;
    bvox__bytes b;
    bvox_status st = bvox__read_file(path, &b);
    if (st) return st;
    st = bvox__section_tiff_decode(b.data, b.size, path, out);
    bvox__bytes_release(&b);
    return st;
}
