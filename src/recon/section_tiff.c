/*
 * section_tiff.c — a TIFF section image (its first page) as an 8- or
 * 16-bit gray bvox_image, through libtiff on a memory buffer (the file is
 * read whole through the budget first). Unsigned 8/16-bit gray or RGB
 * strips are read as stored (min-is-white inverted); anything else libtiff
 * can decode (palette, tiles, other depths, YCbCr, ...) goes through
 * TIFFReadRGBAImageOriented as 8-bit RGB. RGB becomes luminance. libtiff's
 * messages are caught (the library never prints) and its single
 * allocations are bounded by the memory budget (bvox__tiff_open_memory,
 * shared with the TIFF volume reader: src/io/tiff_memory.c).
 */
#include "section_internal.h"
#include "io/io.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>

/* Strips of unsigned 8/16-bit gray or RGB, interleaved: as stored. */
static bvox_status read_plain(TIFF *tif, const char *name, const bvox__tiff_src *err,
                              uint32_t w, uint32_t h, uint16_t bps, uint16_t spp, int invert,
                              bvox_image **out)
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
    uint8_t *buf = bvox__mem_alloc((size_t)line);
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
                              bvox__tiff_error(err, "truncated or corrupt"));
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
static bvox_status read_rgba(TIFF *tif, const char *name, const bvox__tiff_src *err,
                             uint32_t w, uint32_t h, bvox_image **out)
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
                          bvox__tiff_error(err, "unsupported layout"));
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
    bvox__tiff_src src;
    TIFF *tif;
    bvox_status st = bvox__tiff_open_memory(data, size, name, &src, &tif);
    if (st) return st;
    uint32_t w = 0, h = 0;
    uint16_t bps = 1, spp = 1, photo = PHOTOMETRIC_MINISBLACK, planar = PLANARCONFIG_CONTIG,
             fmt = SAMPLEFORMAT_UINT;
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
        st = plain ? read_plain(tif, name, &src, w, h, bps, spp, photo == PHOTOMETRIC_MINISWHITE, &img)
                   : read_rgba(tif, name, &src, w, h, &img);
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
