/*
 * tiff.c — TIFF stacks (".tif", ".tiff"): every page is one z slice.
 *
 * Reading goes through libtiff on a memory buffer (TIFFClientOpenExt, see
 * bvox__tiff_open_memory in tiff_memory.c), so the memory entry point and
 * fuzzing work; libtiff's messages are captured per handle (never printed)
 * and the first one is quoted in our error. Pages must
 * all have one size and one sample type: 1, 8, 16, 32 or 64-bit grayscale
 * (unsigned, signed or float), strips or tiles, any codec libtiff has. They
 * are decoded into a bvox__gray and binarised with the user's options. Raw
 * sample values are used whatever the photometric (as ImageJ does: a
 * MinIsWhite image keeps its values and only its display is inverted).
 *
 * Voxel size follows ImageJ/Fiji: an ImageDescription starting "ImageJ="
 * gives unit=, spacing= (z) and xorigin= etc. (in pixels), and
 * XResolution/YResolution are pixels per unit. Without it, ResolutionUnit
 * inch or cm gives millimetres and z spacing = x spacing. ImageJ's layout
 * for stacks over 4 GiB (one IFD, "images=N", the N raw images back to back)
 * is read too.
 *
 * Writing is in tiff_write.c.
 */
#include "io.h"

#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <tiffio.h>
#include <unistd.h>

static int tiff_sniff(const uint8_t *d, size_t n)
{
    if (n < 4) return 0;
    return (d[0] == 'I' && d[1] == 'I' && (d[2] == 42 || d[2] == 43) && d[3] == 0) ||
           (d[0] == 'M' && d[1] == 'M' && d[2] == 0 && (d[3] == 42 || d[3] == 43));
}

/* ---------------------------------------------------------------- metadata */

typedef struct imagej {
    bool present;
    double spacing, origin[3];
    long images, channels, slices, frames;
    char unit[32];
} imagej;

static void parse_imagej(const char *desc, imagej *ij)
{
    memset(ij, 0, sizeof *ij);
    if (!desc || strncmp(desc, "ImageJ=", 7) != 0) return;
    ij->present = true;
    for (const char *p = desc; *p;) {
        const char *eol = strchr(p, '\n');
        size_t len = eol ? (size_t)(eol - p) : strlen(p);
        char line[128];
        if (len < sizeof line) {
            memcpy(line, p, len);
            line[len] = '\0';
            char *eq = strchr(line, '=');
            if (eq) {
                *eq = '\0';
                const char *key = line, *val = eq + 1;
                char *end;
                double v = strtod(val, &end);
                bool num = end != val && isfinite(v);
                if (!strcmp(key, "unit")) snprintf(ij->unit, sizeof ij->unit, "%s", val);
                else if (!strcmp(key, "spacing") && num) ij->spacing = fabs(v);
                else if (!strcmp(key, "xorigin") && num) ij->origin[0] = v;
                else if (!strcmp(key, "yorigin") && num) ij->origin[1] = v;
                else if (!strcmp(key, "zorigin") && num) ij->origin[2] = v;
                else if (!strcmp(key, "images") && num) ij->images = (long)fmin(v, 1e9);
                else if (!strcmp(key, "channels") && num) ij->channels = (long)fmin(v, 1e9);
                else if (!strcmp(key, "slices") && num) ij->slices = (long)fmin(v, 1e9);
                else if (!strcmp(key, "frames") && num) ij->frames = (long)fmin(v, 1e9);
            }
        }
        p += len + (eol != NULL);
    }
}

/* ImageJ unit names to ours ("" for pixels / unknown). */
static void map_unit(const char *u, char out[16])
{
    static const char *const micro[] = {"micron", "microns", "um", "\xc2\xb5m", "\xb5m",
                                        "\xce\xbcm", "\\u00B5m", "\\u00b5m", NULL};
    out[0] = '\0';
    for (int i = 0; micro[i]; i++)
        if (!strcmp(u, micro[i])) {
            strcpy(out, "um");
            return;
        }
    if (!strcmp(u, "pixel") || !strcmp(u, "pixels") || strlen(u) >= 16) return;
    for (const char *p = u; *p; p++)
        if (*p < 0x21 || *p > 0x7e) return;
    strcpy(out, u);
}

static double res_to_spacing(TIFF *tif, ttag_t tag, bool *have)
{
    float r = 0;
    *have = TIFFGetField(tif, tag, &r) && isfinite(r) && r > 0;
    if (!*have) return 1.0;
    /* libtiff hands the RATIONAL tag over as a float, so 1/0.1f gives
     * 9.99999985: keep only the 7 significant digits a float carries. */
    char buf[32];
    snprintf(buf, sizeof buf, "%.7g", 1.0 / (double)r);
    return strtod(buf, NULL);
}

static bvox_status read_geometry(TIFF *tif, const char *name, bvox_geometry *g, long *images)
{
    char *desc = NULL;
    imagej ij;
    if (!TIFFGetField(tif, TIFFTAG_IMAGEDESCRIPTION, &desc)) desc = NULL;
    parse_imagej(desc, &ij);
    *images = ij.images;
    if (ij.channels > 1)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: ImageJ hyperstack with %ld channels; split the channels first",
                          name, ij.channels);
    if (ij.slices > 1 && ij.frames > 1)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: ImageJ hyperstack with %ld time frames; extract one frame first",
                          name, ij.frames);
    bool hx, hy;
    double sx = res_to_spacing(tif, TIFFTAG_XRESOLUTION, &hx);
    double sy = res_to_spacing(tif, TIFFTAG_YRESOLUTION, &hy);
    if (hx && !hy) sy = sx;
    double ome_sp[3] = {0, 0, 0};
    bool ome_have[3];
    char ome_unit[16] = "";
    if (!ij.present && bvox__ome_parse(desc, ome_sp, ome_unit, ome_have) &&
        (ome_have[0] || ome_have[1] || ome_have[2])) {
        /* OME-TIFF: the physical sizes are the truth; an axis without one
         * takes x's (y) or 1 (z), as an ImageJ stack without spacing= */
        strcpy(g->unit, ome_unit);
        g->spacing[0] = ome_have[0] ? ome_sp[0] : ome_have[1] ? ome_sp[1] : 1.0;
        g->spacing[1] = ome_have[1] ? ome_sp[1] : g->spacing[0];
        g->spacing[2] = ome_have[2] ? ome_sp[2] : 1.0;
        if (!ome_have[2] && TIFFNumberOfDirectories(tif) > 1)
            bvox__warn("%s: the OME-XML gives no PhysicalSizeZ: z spacing 1 %s assumed", name,
                       g->unit);
        return BVOX_OK;
    }
    if (ij.present) {
        map_unit(ij.unit, g->unit);
        g->spacing[2] = ij.spacing > 0 ? ij.spacing : 1.0;
    } else {
        uint16_t ru = RESUNIT_INCH;
        TIFFGetFieldDefaulted(tif, TIFFTAG_RESOLUTIONUNIT, &ru);
        double f = ru == RESUNIT_INCH ? 25.4 : ru == RESUNIT_CENTIMETER ? 10.0 : 1.0;
        if (hx && f != 1.0) {
            sx *= f;
            sy *= f;
            strcpy(g->unit, "mm");
        }
        g->spacing[2] = sx;
    }
    g->spacing[0] = sx;
    g->spacing[1] = sy;
    for (int a = 0; a < 3; a++) {
        g->origin[a] = -ij.origin[a] * g->spacing[a];
        if (!isfinite(g->spacing[a]) || !(g->spacing[a] > 0) || !isfinite(g->origin[a]))
            return bvox__fail(BVOX_EFORMAT, "%s: unusable voxel size or origin", name);
    }
    return BVOX_OK;
}

/* ------------------------------------------------------------------ pixels */

typedef struct page_fmt {
    uint32_t w, h;
    uint16_t bps;
    bvox_dtype dtype;
    size_t elem;
} page_fmt;

static bvox_status page_format(TIFF *tif, const char *name, uint32_t page, page_fmt *pf)
{
    uint32_t w = 0, h = 0;
    uint16_t bps = 1, spp = 1, sfmt = SAMPLEFORMAT_UINT, photo = PHOTOMETRIC_MINISBLACK,
             comp = COMPRESSION_NONE;
    if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h))
        return bvox__fail(BVOX_EFORMAT, "%s: page %u has no image size", name, page + 1);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bps);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &sfmt);
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &comp);
    if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photo)) photo = PHOTOMETRIC_MINISBLACK;
    if (w < 1 || h < 1 || w > BVOX_MAX_DIM || h > BVOX_MAX_DIM)
        return bvox__fail(w && h ? BVOX_ETOOBIG : BVOX_EFORMAT,
                          "%s: page %u is %u x %u pixels, outside 1..%d", name, page + 1, w, h,
                          BVOX_MAX_DIM);
    if (spp != 1)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: page %u has %u samples per pixel (colour or alpha); only "
                          "grayscale stacks are read",
                          name, page + 1, spp);
    if (photo != PHOTOMETRIC_MINISBLACK && photo != PHOTOMETRIC_MINISWHITE &&
        photo != PHOTOMETRIC_PALETTE)
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: page %u has photometric %u, not grayscale",
                          name, page + 1, photo);
    if (!TIFFIsCODECConfigured(comp))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: page %u uses compression %u, unavailable",
                          name, page + 1, comp);
    int kind = sfmt == SAMPLEFORMAT_INT ? 1 : sfmt == SAMPLEFORMAT_IEEEFP ? 2
               : (sfmt == SAMPLEFORMAT_UINT || sfmt == SAMPLEFORMAT_VOID) ? 0 : -1;
    int dt = -1;
    switch (bps) {
    case 1: dt = kind == 0 ? BVOX_DT_U8 : -1; break;
    case 8: dt = kind == 0 ? BVOX_DT_U8 : kind == 1 ? BVOX_DT_I8 : -1; break;
    case 16: dt = kind == 0 ? BVOX_DT_U16 : kind == 1 ? BVOX_DT_I16 : -1; break;
    case 32: dt = kind == 0 ? BVOX_DT_U32 : kind == 1 ? BVOX_DT_I32 : kind == 2 ? BVOX_DT_F32 : -1;
        break;
    case 64: dt = kind == 0 ? BVOX_DT_U64 : kind == 1 ? BVOX_DT_I64 : kind == 2 ? BVOX_DT_F64 : -1;
        break;
    }
    if (dt < 0)
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: page %u has %u-bit samples of format %u",
                          name, page + 1, bps, sfmt);
    pf->w = w;
    pf->h = h;
    pf->bps = bps;
    pf->dtype = (bvox_dtype)dt;
    pf->elem = bvox_dtype_size(pf->dtype);
    return BVOX_OK;
}

/* One row of n samples from libtiff's buffer to ours (1-bit rows expand to
 * one byte per sample, MSB first: libtiff has already applied FillOrder). */
static void copy_row(const page_fmt *pf, const uint8_t *src, uint32_t n, uint8_t *dst)
{
    if (pf->bps == 1)
        for (uint32_t x = 0; x < n; x++) dst[x] = (uint8_t)((src[x >> 3] >> (7 - (x & 7))) & 1);
    else
        memcpy(dst, src, (size_t)n * pf->elem);
}

static bvox_status decode_fail(const char *name, uint32_t page, const char *what,
                               const bvox__tiff_src *e)
{
    return bvox__fail(BVOX_EFORMAT, "%s: page %u: cannot decode %s (%s)", name, page + 1, what,
                      bvox__tiff_error(e, "truncated or corrupt"));
}

static bvox_status read_page(TIFF *tif, const char *name, uint32_t page, const page_fmt *pf,
                             const bvox__tiff_src *err, uint8_t *dst)
{
    const size_t row_bytes = (size_t)pf->w * pf->elem;
    bool tiled = TIFFIsTiled(tif);
    uint32_t tw = pf->w, th = pf->h;
    uint64_t line, bufsize;
    if (tiled) {
        if (!TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw) ||
            !TIFFGetField(tif, TIFFTAG_TILELENGTH, &th) || tw == 0 || th == 0 || tw > 65536 ||
            th > 65536)
            return bvox__fail(BVOX_EFORMAT, "%s: page %u has bad tile sizes", name, page + 1);
        line = TIFFTileRowSize64(tif);
        bufsize = TIFFTileSize64(tif);
    } else {
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &th);
        if (th == 0 || th > pf->h) th = pf->h;
        line = TIFFScanlineSize64(tif);
        bufsize = line * th;
    }
    uint64_t want_line = pf->bps == 1 ? ((uint64_t)tw + 7) / 8 : (uint64_t)tw * pf->elem;
    if (line != want_line || bufsize < line * th) /* both < 2^35: no overflow */
        return bvox__fail(BVOX_EFORMAT, "%s: page %u has an inconsistent row size", name,
                          page + 1);
    bvox_status st;
    uint8_t *buf = bvox__alloc((size_t)bufsize, false, "TIFF strip buffer", &st);
    if (!buf) return st;
    for (uint32_t y0 = 0; y0 < pf->h && !st; y0 += th) {
        uint32_t rows = pf->h - y0 < th ? pf->h - y0 : th;
        for (uint32_t x0 = 0; x0 < pf->w && !st; x0 += tw) {
            uint32_t cols = pf->w - x0 < tw ? pf->w - x0 : tw;
            tmsize_t want = (tmsize_t)(tiled ? bufsize : rows * line);
            tmsize_t got = tiled ? TIFFReadEncodedTile(tif, TIFFComputeTile(tif, x0, y0, 0, 0),
                                                       buf, want)
                                 : TIFFReadEncodedStrip(tif, TIFFComputeStrip(tif, y0, 0), buf,
                                                        want);
            if (got < want) {
                st = decode_fail(name, page, tiled ? "a tile" : "a strip", err);
                break;
            }
            for (uint32_t r = 0; r < rows; r++)
                copy_row(pf, buf + (size_t)r * line, cols,
                         dst + (size_t)(y0 + r) * row_bytes + (size_t)x0 * pf->elem);
        }
    }
    bvox__free(buf, (size_t)bufsize);
    return st;
}

/* ImageJ writes stacks over 4 GiB with a single IFD whose description says
 * "images=N": the N uncompressed images lie back to back from the first strip.
 * Returns the offset of image 0 if this page is laid out so, 0 if not, and
 * UINT64_MAX if it is but the file ends before the last image. */
static uint64_t imagej_contiguous(TIFF *tif, const page_fmt *pf, long images,
                                  const bvox__tiff_src *src)
{
    uint16_t comp = COMPRESSION_NONE;
    uint64_t *off = NULL, *cnt = NULL;
    TIFFGetFieldDefaulted(tif, TIFFTAG_COMPRESSION, &comp);
    if (images < 2 || images > BVOX_MAX_DIM || comp != COMPRESSION_NONE || pf->bps < 8 ||
        TIFFIsTiled(tif) || !TIFFGetField(tif, TIFFTAG_STRIPOFFSETS, &off) ||
        !TIFFGetField(tif, TIFFTAG_STRIPBYTECOUNTS, &cnt) || !off || !cnt)
        return 0;
    uint64_t page = (uint64_t)pf->w * pf->h * pf->elem, at = off[0];
    uint32_t ns = TIFFNumberOfStrips(tif);
    for (uint32_t i = 0; i < ns; i++) { /* the strips themselves must be contiguous */
        if (off[i] != at || cnt[i] > page) return 0;
        at += cnt[i];
    }
    if (at - off[0] != page || off[0] == 0) return 0;
    if (off[0] > src->size || (src->size - off[0]) / page < (uint64_t)images) return UINT64_MAX;
    return off[0];
}

/* Pages decoded one at a time into a one-page buffer and binarised as they
 * come (bvox__bin_stream): the bits plus one page, not every decoded page. */
static bvox_status read_pages(TIFF *tif, const bvox__tiff_src *src, const char *name,
                              bvox__gray *g, const bvox_binarize *how, bvox_volume **out)
{
    tdir_t n = TIFFNumberOfDirectories(tif);
    if (n == 0) return bvox__fail(BVOX_EFORMAT, "%s: TIFF has no pages", name);
    if (n > BVOX_MAX_DIM)
        return bvox__fail(BVOX_ETOOBIG, "%s: %lu pages, over the limit of %d", name,
                          (unsigned long)n, BVOX_MAX_DIM);
    page_fmt first;
    bvox_status st = page_format(tif, name, 0, &first);
    if (st) return st;
    long images;
    st = read_geometry(tif, name, &g->geom, &images);
    if (st) return st;
    uint64_t contig = n == 1 ? imagej_contiguous(tif, &first, images, src) : 0;
    if (contig == UINT64_MAX)
        return bvox__fail(BVOX_EFORMAT, "%s: the ImageJ stack of %ld images is truncated",
                          name, images);
    int32_t nz = contig ? (int32_t)images : (int32_t)n;
    g->dims = (bvox_dims){(int32_t)first.w, (int32_t)first.h, nz};
    g->dtype = first.dtype;
    size_t bits_bytes, page_bytes = (size_t)first.w * first.h * first.elem, bytes;
    st = bvox__check_dims(g->dims, name, &bits_bytes);
    if (st) return st;
    if (contig) {
        /* Raw samples in the file's byte order; used in place when aligned. */
        const uint8_t *raw = src->data + contig;
        g->byteswap = TIFFIsByteSwapped(tif) && first.elem > 1;
        if ((uintptr_t)raw % first.elem == 0) {
            g->data = raw;
            return BVOX_OK;
        }
        bytes = page_bytes * (size_t)images;
        g->owned = bvox__alloc(bytes, false, "TIFF pixels", &st);
        if (!g->owned) return st;
        g->owned_bytes = bytes;
        g->data = g->owned;
        memcpy(g->owned, raw, bytes);
        return BVOX_OK;
    }
    if (!bvox__mul_size(page_bytes, n, &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: pixel data overflows the address space", name);
    bvox__bin_stream *bs = NULL;
    uint8_t *page = NULL;
    if (out && bvox__bin_stream_ok(how)) { /* no out: the samples are wanted */
        st = bvox__bin_stream_begin(g, how, name, &bs);
        if (st) return st;
        page = bvox__alloc(page_bytes, false, "TIFF page", &st);
        if (!page) {
            bvox__bin_stream_abort(bs);
            return st;
        }
    } else { /* Otsu: every page first */
        g->owned = bvox__alloc(bytes, false, "TIFF pixels", &st);
        if (!g->owned) return st;
        g->owned_bytes = bytes;
        g->data = g->owned;
    }
    for (tdir_t z = 0; z < n && !st; z++) {
        page_fmt pf;
        if (z > 0 && !TIFFReadDirectory(tif))
            st = bvox__fail(BVOX_EFORMAT, "%s: cannot read page %lu (%s)", name,
                            (unsigned long)z + 1, bvox__tiff_error(src, "truncated"));
        if (!st) st = page_format(tif, name, z, &pf);
        if (st) break;
        if (pf.w != first.w || pf.h != first.h)
            st = bvox__fail(BVOX_EFORMAT, "%s: page %lu is %u x %u pixels, page 1 is %u x %u",
                            name, (unsigned long)z + 1, pf.w, pf.h, first.w, first.h);
        else if (pf.dtype != first.dtype || pf.bps != first.bps)
            st = bvox__fail(BVOX_EFORMAT, "%s: page %lu has %u-bit %s samples, page 1 %u-bit %s",
                            name, (unsigned long)z + 1, pf.bps, bvox_dtype_name(pf.dtype),
                            first.bps, bvox_dtype_name(first.dtype));
        else
            st = read_page(tif, name, z, &pf, src,
                           bs ? page : (uint8_t *)g->owned + (size_t)z * page_bytes);
        if (!st && bs) bvox__bin_stream_slices(bs, page, 1);
        if (!st) st = bvox__progress_steps((int64_t)z + 1, (int64_t)n);
    }
    /* The page count stops at the first unreadable IFD: a chain that goes on
     * past the last page read means a truncated or corrupt file. */
    if (!st && !TIFFLastDirectory(tif))
        st = bvox__fail(BVOX_EFORMAT, "%s: page %lu cannot be read (%s)", name,
                        (unsigned long)n + 1, bvox__tiff_error(src, "truncated or corrupt"));
    if (!bs) return st;
    bvox__free(page, page_bytes);
    if (st) {
        bvox__bin_stream_abort(bs);
        return st;
    }
    return bvox__bin_stream_finish(bs, out);
}

/* Decode every page into a gray volume that owns its samples (no
 * binarising: label volumes read the typed samples, labels_read.c). */
static bvox_status tiff_gray_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox__gray *g)
{
    (void)opts;
    bvox__gray_init(g);
    if (!name) name = "TIFF";
    bvox__tiff_src src;
    TIFF *tif;
    bvox_status st = bvox__tiff_open_memory(data, size, name, &src, &tif);
    if (st) return st;
    st = read_pages(tif, &src, name, g, NULL, NULL);
    TIFFClose(tif);
    if (st) bvox__gray_release(g);
    return st;
}

static bvox_status tiff_read_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "TIFF";
    bvox__tiff_src src;
    TIFF *tif;
    bvox_status st = bvox__tiff_open_memory(data, size, name, &src, &tif);
    if (st) return st;
    bvox__gray g;
    bvox__gray_init(&g);
    const bvox_binarize *how = opts ? &opts->binarize : NULL;
    st = read_pages(tif, &src, name, &g, how, out);
    TIFFClose(tif);
    if (!st && !*out) st = bvox__binarize(&g, how, name, out);
    bvox__gray_release(&g);
    return st;
}

/* A TIFF file is mapped, not read into a buffer: libtiff reads it through
 * memory (bvox__tiff_open_memory) either way, and clean file-backed pages
 * cost no budget (the kernel can drop them), so a stack is read with its
 * bits and one decoded page. Anything that cannot be mapped is read whole. */
static bvox_status tiff_read_path(const char *path, const bvox_read_opts *opts,
                                  bvox_volume **out)
{
    *out = NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK); /* a FIFO must not block here */
    struct stat sb;
    void *map = MAP_FAILED;
    if (fd >= 0 && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size > 0)
        map = mmap(NULL, (size_t)sb.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (fd >= 0) close(fd);
    if (map == MAP_FAILED) {
        bvox__bytes file;
        bvox_status st = bvox__read_file(path, &file);
        if (st) return st;
        st = tiff_read_memory(file.data, file.size, path, opts, out);
        bvox__bytes_release(&file);
        return st;
    }
    bvox_status st = tiff_read_memory(map, (size_t)sb.st_size, path, opts, out);
    munmap(map, (size_t)sb.st_size);
    return st;
}

static const char *const tiff_extensions[] = {".tif", ".tiff", NULL};

const bvox__format bvox__format_tiff = {
    "tiff", tiff_extensions, tiff_sniff, tiff_read_memory, tiff_read_path, bvox__tiff_write,
    NULL, NULL, tiff_gray_memory,
};
