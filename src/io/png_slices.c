/*
 * png_slices.c — folders of PNG slices (the "png" format), one file per z.
 *
 * Reading a folder lists its *.png files (any letter case; names starting
 * with '.' are skipped: macOS leaves "._s1.png" resource files on shared
 * drives), sorts them in natural order (s2 before s10) and decodes each into
 * one slice of a bvox__gray: 8 or 16-bit gray; gray+alpha, RGB(A) and palette
 * are reduced to gray by luminance, low bit depths expanded (so a 1-bit slice
 * reads 0/255). The first slice fixes size and sample depth; every other must
 * have the same size (the error names the file). A single .png file, or
 * read_memory, gives a volume with nz = 1. The voxel size comes from the
 * first slice's pHYs chunk when its unit is the metre (then in mm, z spacing
 * = x spacing, since PNG has no z).
 *
 * libpng reports errors by longjmp: each decode/encode owns its png structs
 * and frees them on both paths; our own buffers are allocated outside the
 * setjmp region, so nothing leaks and every libpng error is BVOX_EFORMAT.
 *
 * Writing makes a folder of slice_0000.png ... (more digits beyond 10000
 * slices), 8-bit gray 0/255 with pHYs when the unit is metric, inside a
 * temporary folder renamed over the target on success (bvox__dir_sink_*).
 */
#include "io.h"

#include <dirent.h>
#include <errno.h>
#include <png.h>
#include <zlib.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

typedef struct png_ctx {
    const uint8_t *data;
    size_t size, pos;
    char msg[200];
} png_ctx;

static void on_error(png_structp png, png_const_charp msg)
{
    png_ctx *c = png_get_error_ptr(png);
    snprintf(c->msg, sizeof c->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg) {}

static void read_cb(png_structp png, png_bytep out, size_t n)
{
    png_ctx *c = png_get_io_ptr(png);
    if (n > c->size - c->pos) png_error(png, "the file is truncated");
    memcpy(out, c->data + c->pos, n);
    c->pos += n;
}

static int png_sniff(const uint8_t *d, size_t n) { return n >= 8 && !png_sig_cmp(d, 0, 8); }

/* ----------------------------------------------------------------- decoding */

typedef struct slice_info {
    uint32_t w, h;
    int bytes;          /* 1 or 2 per sample */
    uint32_t ppm[2];    /* pixels per metre from pHYs, 0 if none */
} slice_info;

/* Decode one PNG. With dst NULL only the header is read into *info;
 * otherwise the image must be want->w x want->h (else an error naming both
 * files) and is written to dst as want->bytes-byte native samples. */
static bvox_status decode_with(png_ctx *ctx, const char *name, slice_info *info,
                               const slice_info *want, const char *first, uint8_t *dst)
{
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_read_struct(&png, NULL, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &pi, NULL);
        return bvox__fail(BVOX_EFORMAT, "%s: %s", name, ctx->msg);
    }
    png_set_read_fn(png, ctx, read_cb);
    png_set_user_limits(png, BVOX_MAX_DIM, BVOX_MAX_DIM);
    png_set_chunk_malloc_max(png, (png_alloc_size_t)8 << 20); /* text, ICC profiles */
    png_read_info(png, pi);
    png_uint_32 w, h, rx = 0, ry = 0;
    int depth, color, unit = -1;
    png_get_IHDR(png, pi, &w, &h, &depth, &color, NULL, NULL, NULL);
    memset(info, 0, sizeof *info);
    info->w = w;
    info->h = h;
    info->bytes = depth == 16 ? 2 : 1;
    if (png_get_pHYs(png, pi, &rx, &ry, &unit) && unit == PNG_RESOLUTION_METER && rx && ry) {
        info->ppm[0] = rx;
        info->ppm[1] = ry;
    }
    if (!dst) {
        png_destroy_read_struct(&png, &pi, NULL);
        return BVOX_OK;
    }
    if (w != want->w || h != want->h) {
        png_destroy_read_struct(&png, &pi, NULL);
        return bvox__fail(BVOX_EFORMAT, "%s is %u x %u pixels, but %s is %u x %u", name,
                          (unsigned)w, (unsigned)h, first, want->w, want->h);
    }
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if ((color & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, pi, PNG_INFO_tRNS))
        png_set_strip_alpha(png);
    if (color & PNG_COLOR_MASK_COLOR) png_set_rgb_to_gray_fixed(png, 1, -1, -1); /* luminance */
    if (want->bytes == 1 && depth == 16) png_set_scale_16(png);
    if (want->bytes == 2) {
        if (depth < 16) png_set_expand_16(png);
        const uint16_t probe = 1;
        if (*(const uint8_t *)&probe) png_set_swap(png); /* PNG is big-endian */
    }
    int passes = png_set_interlace_handling(png);
    png_read_update_info(png, pi);
    size_t row = (size_t)w * (size_t)want->bytes;
    if (png_get_channels(png, pi) != 1 || png_get_rowbytes(png, pi) != row)
        png_error(png, "unexpected sample layout after conversion to gray");
    for (int p = 0; p < passes; p++)
        for (png_uint_32 y = 0; y < h; y++) png_read_row(png, dst + (size_t)y * row, NULL);
    png_read_end(png, NULL); /* a file cut after its pixels is still truncated */
    png_destroy_read_struct(&png, &pi, NULL);
    return BVOX_OK;
}

/* The context lives here, outside the function that calls setjmp, so that
 * its changes survive the longjmp (C11 7.13.2.1). */
static bvox_status decode_png(const uint8_t *data, size_t size, const char *name,
                              slice_info *info, const slice_info *want, const char *first,
                              uint8_t *dst)
{
    if (size < 8 || png_sig_cmp(data, 0, 8))
        return bvox__fail(BVOX_EFORMAT, "%s: not a PNG file", name);
    png_ctx ctx = {data, size, 0, {0}};
    return decode_with(&ctx, name, info, want, first, dst);
}

static void set_geometry(const slice_info *info, bvox_geometry *g)
{
    if (!info->ppm[0]) return;
    g->spacing[0] = 1000.0 / info->ppm[0];
    g->spacing[1] = 1000.0 / info->ppm[1];
    g->spacing[2] = g->spacing[0];
    strcpy(g->unit, "mm");
}

/* Allocate the gray volume for n slices of the first slice's size. */
static bvox_status gray_alloc(bvox__gray *g, const slice_info *info, int32_t n, const char *name)
{
    if (info->w > BVOX_MAX_DIM || info->h > BVOX_MAX_DIM || !info->w || !info->h)
        return bvox__fail(BVOX_EFORMAT, "%s: bad size %u x %u", name, info->w, info->h);
    g->dims = (bvox_dims){(int32_t)info->w, (int32_t)info->h, n};
    g->dtype = info->bytes == 2 ? BVOX_DT_U16 : BVOX_DT_U8;
    set_geometry(info, &g->geom);
    size_t bits, bytes = (size_t)info->w * info->h * (size_t)info->bytes;
    bvox_status st = bvox__check_dims(g->dims, name, &bits);
    if (st) return st;
    if (!bvox__mul_size(bytes, (size_t)n, &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: slices overflow the address space", name);
    g->owned = bvox__alloc(bytes, false, "PNG slices", &st);
    if (!g->owned) return st;
    g->owned_bytes = bytes;
    g->data = g->owned;
    return BVOX_OK;
}

static bvox_status png_read_memory(const uint8_t *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "PNG";
    slice_info info;
    bvox_status st = decode_png(data, size, name, &info, NULL, NULL, NULL);
    if (st) return st;
    bvox__gray g;
    bvox__gray_init(&g);
    st = gray_alloc(&g, &info, 1, name);
    if (!st) st = decode_png(data, size, name, &info, &info, name, g.owned);
    if (!st) st = bvox__binarize(&g, opts ? &opts->binarize : NULL, name, out);
    bvox__gray_release(&g);
    return st;
}

/* ------------------------------------------------------------------ folders */

static int cmp_names(const void *a, const void *b)
{
    return bvox__natural_compare(*(char *const *)a, *(char *const *)b);
}

static void free_names(char **names, size_t n)
{
    for (size_t i = 0; i < n; i++) free(names[i]);
    free(names);
}

static char *join(const char *dir, const char *file)
{
    size_t ld = strlen(dir), lf = strlen(file);
    char *p = bvox__mem_alloc(ld + lf + 2);
    if (!p) return NULL;
    memcpy(p, dir, ld);
    p[ld] = '/';
    memcpy(p + ld + 1, file, lf + 1);
    return p;
}

/* The *.png regular files of dir, in natural order. */
static bvox_status list_pngs(const char *dir, char ***out, size_t *count)
{
    DIR *d = opendir(dir);
    if (!d) return bvox__fail(BVOX_EIO, "%s: cannot open the folder: %s", dir, strerror(errno));
    char **names = NULL;
    size_t n = 0, cap = 0;
    bvox_status st = BVOX_OK;
    struct dirent *e;
    while (!st && (e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (e->d_name[0] == '.' || len < 5 || strcasecmp(e->d_name + len - 4, ".png") != 0)
            continue;
        char *full = join(dir, e->d_name);
        struct stat sb;
        bool regular = full && stat(full, &sb) == 0 && S_ISREG(sb.st_mode);
        free(full);
        if (!full) st = bvox__fail(BVOX_ENOMEM, "out of memory listing %s", dir);
        if (st || !regular) continue;
        if (n == BVOX_MAX_DIM) {
            st = bvox__fail(BVOX_ETOOBIG, "%s: more than %d PNG slices", dir, BVOX_MAX_DIM);
            break;
        }
        if (n == cap) {
            cap = cap ? cap * 2 : 64;
            char **grown = bvox__mem_resize(names, cap * sizeof *names);
            if (!grown) {
                st = bvox__fail(BVOX_ENOMEM, "out of memory listing %s", dir);
                break;
            }
            names = grown;
        }
        if (!(names[n] = bvox__mem_strdup(e->d_name)))
            st = bvox__fail(BVOX_ENOMEM, "out of memory listing %s", dir);
        else
            n++;
    }
    closedir(d);
    if (!st && n == 0) st = bvox__fail(BVOX_EFORMAT, "%s: the folder holds no .png files", dir);
    if (st) {
        free_names(names, n);
        return st;
    }
    qsort(names, n, sizeof *names, cmp_names);
    *out = names;
    *count = n;
    return BVOX_OK;
}

static bvox_status read_folder(const char *dir, const bvox_read_opts *opts, bvox_volume **out)
{
    char **names = NULL;
    size_t n = 0;
    bvox_status st = list_pngs(dir, &names, &n);
    if (st) return st;
    bvox__gray g;
    bvox__gray_init(&g);
    slice_info first;
    char *first_path = join(dir, names[0]);
    size_t slice_bytes = 0;
    if (!first_path) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    for (size_t i = 0; i < n && !st; i++) {
        char *path = i ? join(dir, names[i]) : first_path;
        if (!path) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            break;
        }
        bvox__bytes b;
        st = bvox__read_file(path, &b);
        if (!st) {
            slice_info info;
            if (i == 0) {
                st = decode_png(b.data, b.size, path, &first, NULL, NULL, NULL);
                if (!st) st = gray_alloc(&g, &first, (int32_t)n, dir);
                slice_bytes = (size_t)first.w * first.h * (size_t)first.bytes;
            }
            if (!st)
                st = decode_png(b.data, b.size, path, &info, &first, first_path,
                                (uint8_t *)g.owned + i * slice_bytes);
            bvox__bytes_release(&b);
        }
        if (i) free(path);
    }
    free(first_path);
    free_names(names, n);
    if (!st) st = bvox__binarize(&g, opts ? &opts->binarize : NULL, dir, out);
    bvox__gray_release(&g);
    return st;
}

static bvox_status png_read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    struct stat sb;
    if (stat(path, &sb) != 0)
        return bvox__fail(errno == ENOENT ? BVOX_ENOTFOUND : BVOX_EIO, "%s: %s", path,
                          strerror(errno));
    if (S_ISDIR(sb.st_mode)) return read_folder(path, opts, out);
    bvox__bytes b;
    bvox_status st = bvox__read_file(path, &b);
    if (st) return st;
    st = png_read_memory(b.data, b.size, path, opts, out);
    bvox__bytes_release(&b);
    return st;
}

/* ------------------------------------------------------------------ writing */

/* Metres per unit, 0 if the unit is not metric. */
static double metres_per_unit(const char *u)
{
    if (!strcmp(u, "mm")) return 1e-3;
    if (!strcmp(u, "um") || !strcmp(u, "\xc2\xb5m") || !strcmp(u, "micron")) return 1e-6;
    if (!strcmp(u, "nm")) return 1e-9;
    if (!strcmp(u, "cm")) return 1e-2;
    if (!strcmp(u, "m")) return 1.0;
    return 0;
}

static bvox_status write_with(png_ctx *ctx, FILE *f, const char *file, const uint8_t *pixels,
                              uint32_t w, uint32_t h, const uint32_t ppm[2])
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ctx, on_error, on_warning);
    png_infop pi = png ? png_create_info_struct(png) : NULL;
    if (!pi) {
        png_destroy_write_struct(&png, NULL);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", file);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &pi);
        return bvox__fail(BVOX_EIO, "%s: %s", file, ctx->msg);
    }
    png_init_io(png, f);
    png_set_IHDR(png, pi, w, h, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (ppm[0]) png_set_pHYs(png, pi, ppm[0], ppm[1], PNG_RESOLUTION_METER);
    /* Masks of 0/255 compress well unfiltered with run-length matching, and
     * filter search and deeper matching are slow for no gain. */
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_set_compression_strategy(png, Z_RLE);
    png_write_info(png, pi);
    for (uint32_t y = 0; y < h; y++) png_write_row(png, pixels + (size_t)y * w);
    png_write_end(png, pi);
    png_destroy_write_struct(&png, &pi);
    return BVOX_OK;
}

static bvox_status write_slice(const char *file, const uint8_t *pixels, uint32_t w, uint32_t h,
                               const uint32_t ppm[2])
{
    FILE *f = fopen(file, "wb");
    if (!f) return bvox__fail(BVOX_EIO, "%s: cannot create: %s", file, strerror(errno));
    png_ctx ctx = {NULL, 0, 0, {0}};
    bvox_status st = write_with(&ctx, f, file, pixels, w, h, ppm);
    if ((ferror(f) | fclose(f)) && !st)
        st = bvox__fail(BVOX_EIO, "%s: write failed: %s", file, strerror(errno));
    return st;
}

static bvox_status png_write_path(const char *path, const bvox_volume *v,
                                  const bvox_write_opts *opts)
{
    (void)opts;
    uint32_t ppm[2] = {0, 0};
    double mpu = metres_per_unit(v->geom.unit);
    for (int a = 0; a < 2 && mpu > 0; a++) {
        double p = 1.0 / (v->geom.spacing[a] * mpu) + 0.5;
        ppm[a] = p >= 1 && p <= 2147483647.0 ? (uint32_t)p : 0; /* PNG's 31-bit limit */
    }
    if (!ppm[0] || !ppm[1]) ppm[0] = ppm[1] = 0;
    int digits = 4;
    for (int64_t lim = 10000; v->nz - 1 >= lim; lim *= 10) digits++;

    const size_t page = (size_t)v->nx * (size_t)v->ny;
    size_t slab_bytes = (v->nz < 64 ? (size_t)v->nz : 64) * page;
    bvox_status st;
    uint8_t *slab = bvox__alloc(slab_bytes, false, "PNG slices", &st);
    if (!slab) return st;
    char *tmp = NULL;
    st = bvox__dir_sink_open(path, &tmp);
    size_t flen = tmp ? strlen(tmp) + 32 : 0;
    char *file = tmp ? bvox__mem_alloc(flen) : NULL;
    if (!st && !file) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    for (int32_t z0 = 0; z0 < v->nz && !st; z0 += 64) {
        int32_t n = v->nz - z0 < 64 ? v->nz - z0 : 64;
        bvox__unpack_slices(v, z0, n, 255, slab);
        for (int32_t k = 0; k < n && !st; k++) {
            snprintf(file, flen, "%s/slice_%0*d.png", tmp, digits & 15, (int)(z0 + k));
            st = write_slice(file, slab + (size_t)k * page, (uint32_t)v->nx, (uint32_t)v->ny,
                             ppm);
        }
    }
    free(file);
    bvox__free(slab, slab_bytes);
    if (tmp) {
        if (st) bvox__dir_sink_abort(tmp);
        else st = bvox__dir_sink_commit(tmp, path);
        free(tmp);
    }
    return st;
}

static const char *const png_extensions[] = {".png", NULL};

const bvox__format bvox__format_png = {
    "png", png_extensions, png_sniff, png_read_memory, png_read_path, png_write_path, NULL,
};
