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
 * folder's voxel_size.txt ("SX SY SZ [UNIT]", '#' comments), else from the
 * first slice's pHYs chunk when its unit is the metre (then in mm, z spacing
 * = x spacing, since PNG has no z, with a warning: a liver read that way
 * came out at 46 % of its volume), else 1 x 1 x 1 without unit (warned too).
 * The read options' voxel size overrides both and silences the warnings.
 *
 * PNG decoding and encoding go through the libpng wrapper
 * (src/common/png.h): every libpng error while reading is BVOX_EFORMAT.
 *
 * Writing makes a folder of slice_0000.png ... (more digits beyond 10000
 * slices), 8-bit gray 0/255 with pHYs when the unit is metric, and the
 * voxel_size.txt that keeps the z spacing and unit, inside a
 * temporary folder renamed over the target on success (bvox__dir_sink_*).
 */
#include "io.h"
#include "common/names.h"
#include "common/png.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int png_sniff(const uint8_t *d, size_t n)
{
    return n >= 8 && !memcmp(d, "\x89PNG\r\n\x1a\n", 8);
}

/* ----------------------------------------------------------------- decoding */

typedef struct slice_info {
    uint32_t w, h;
    int bytes;          /* 1 or 2 per sample */
    uint32_t ppm[2];    /* pixels per metre from pHYs, 0 if none */
} slice_info;

typedef struct slice_dest {
    slice_info *info;
    const slice_info *want;
    const char *name, *first;
    uint8_t *dst;
} slice_dest;

static bvox_status slice_rows(void *ctx, const bvox__png_info *pi, uint8_t **rows)
{
    slice_dest *d = ctx;
    memset(d->info, 0, sizeof *d->info);
    d->info->w = pi->width;
    d->info->h = pi->height;
    d->info->bytes = pi->depth == 16 ? 2 : 1;
    memcpy(d->info->ppm, pi->ppm, sizeof d->info->ppm);
    if (d->dst && (pi->width != d->want->w || pi->height != d->want->h))
        return bvox__fail(BVOX_EFORMAT, "%s is %u x %u pixels, but %s is %u x %u", d->name,
                          (unsigned)pi->width, (unsigned)pi->height, d->first, d->want->w,
                          d->want->h);
    *rows = d->dst;
    return BVOX_OK;
}

/* Decode one PNG. With dst NULL only the header is read into *info;
 * otherwise the image must be want->w x want->h (else an error naming both
 * files) and is written to dst as want->bytes-byte native gray samples (RGB
 * by luminance). */
static bvox_status decode_png(const uint8_t *data, size_t size, const char *name,
                              slice_info *info, const slice_info *want, const char *first,
                              uint8_t *dst)
{
    const bvox__png_read_opts o = {BVOX_MAX_DIM, 1, dst ? want->bytes : 0};
    slice_dest d = {info, want, name, first, dst};
    return bvox__png_decode(data, size, name, &o, slice_rows, &d);
}

static void set_geometry(const slice_info *info, bvox_geometry *g)
{
    if (!info->ppm[0]) return;
    g->spacing[0] = 1000.0 / info->ppm[0];
    g->spacing[1] = 1000.0 / info->ppm[1];
    g->spacing[2] = g->spacing[0];
    strcpy(g->unit, "mm");
}

/* Allocate the gray volume for n slices of the first slice's size; with a
 * stream (bs not NULL) only one slice, and the stream is begun. */
static bvox_status gray_alloc(bvox__gray *g, const slice_info *info, int32_t n, const char *name,
                              const bvox_binarize *how, bvox__bin_stream **bs)
{
    if (info->w > BVOX_MAX_DIM || info->h > BVOX_MAX_DIM || !info->w || !info->h)
        return bvox__fail(BVOX_EFORMAT, "%s: bad size %u x %u", name, info->w, info->h);
    g->dims = (bvox_dims){(int32_t)info->w, (int32_t)info->h, n};
    g->dtype = info->bytes == 2 ? BVOX_DT_U16 : BVOX_DT_U8;
    set_geometry(info, &g->geom);
    size_t bits, bytes = (size_t)info->w * info->h * (size_t)info->bytes;
    bvox_status st = bvox__check_dims(g->dims, name, &bits);
    if (st) return st;
    if (bs) {
        st = bvox__bin_stream_begin(g, how, name, bs);
        if (st) return st;
        n = 1;
    }
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
    st = gray_alloc(&g, &info, 1, name, NULL, NULL);
    if (!st) st = decode_png(data, size, name, &info, &info, name, g.owned);
    if (!st) st = bvox__binarize(&g, opts ? &opts->binarize : NULL, name, out);
    bvox__gray_release(&g);
    return st;
}

/* ------------------------------------------------------------------ folders */

/* The regular *.png files of the folder (not sub-folders named x.png). */
static bool keep_png(const char *dir, const char *name, void *ctx)
{
    (void)ctx;
    if (strlen(name) < 5 || !bvox__ends_with_ci(name, ".png")) return false;
    char full[4096];
    struct stat sb;
    int len = snprintf(full, sizeof full, "%s/%s", dir, name);
    return len > 0 && (size_t)len < sizeof full && stat(full, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* ------------------------------------------------------ voxel_size.txt */

typedef struct voxel_size {
    bool found;
    double s[3];
    char unit[16];
} voxel_size;

/* dir/voxel_size.txt when present: the first line that is not blank or a
 * '#' comment holds three sizes (spaces or commas between) and an optional
 * unit. A file that is there but wrong is an error, not a silent default. */
static bvox_status read_voxel_size(const char *dir, voxel_size *vs)
{
    memset(vs, 0, sizeof *vs);
    char path[4096];
    int len = snprintf(path, sizeof path, "%s/%s", dir, BVOX__VOXEL_SIZE_NAME);
    struct stat sb;
    if (len < 0 || (size_t)len >= sizeof path || stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return BVOX_OK;
    if (sb.st_size > 4096)
        return bvox__fail(BVOX_EFORMAT, "%s: %lld bytes, not a voxel size line", path,
                          (long long)sb.st_size);
    FILE *f = fopen(path, "r");
    if (!f) return bvox__fail(BVOX_EIO, "%s: %s", path, strerror(errno));
    char line[4100];
    bool got = false;
    while (!got && fgets(line, sizeof line, f)) {
        char *p = line + strspn(line, " \t\r\n");
        if (*p == '\0' || *p == '#') continue;
        got = true;
        for (char *c = p; *c; c++)
            if (*c == ',') *c = ' ';
        char unit[64] = "";
        int n = sscanf(p, "%lf %lf %lf %63s", &vs->s[0], &vs->s[1], &vs->s[2], unit);
        bool ok = n >= 3 && strlen(unit) < sizeof vs->unit;
        for (int a = 0; a < 3 && ok; a++) ok = isfinite(vs->s[a]) && vs->s[a] > 0;
        if (!ok) {
            fclose(f);
            return bvox__fail(BVOX_EFORMAT,
                              "%s: expected \"SX SY SZ [UNIT]\" (three sizes > 0, a unit of "
                              "at most 15 bytes)", path);
        }
        strcpy(vs->unit, unit);
    }
    fclose(f);
    if (!got) return bvox__fail(BVOX_EFORMAT, "%s: holds no voxel size line", path);
    vs->found = true;
    return BVOX_OK;
}

/* Give a folder's volume its voxel size; say what was assumed when neither
 * the caller, voxel_size.txt nor (for x and y) pHYs tells it. */
static bvox_status folder_geometry(const char *dir, const bvox_read_opts *opts,
                                   const voxel_size *vs, bvox_volume *v)
{
    if (vs->found) return bvox_volume_set_spacing(v, vs->s[0], vs->s[1], vs->s[2], vs->unit);
    if (bvox__read_spacing_given(opts) || v->nz < 2) return BVOX_OK;
    if (v->geom.unit[0])
        bvox__warn("%s: PNG slices hold no z spacing: %g %s (the x spacing) assumed; give it "
                   "with --voxel-size or in %s/%s (\"SX SY SZ UNIT\")", dir, v->geom.spacing[2],
                   v->geom.unit, dir, BVOX__VOXEL_SIZE_NAME);
    else
        bvox__warn("%s: no voxel size in the PNG slices (no pHYs) nor a %s: 1 x 1 x 1 voxels "
                   "without unit assumed; give it with --voxel-size and --unit", dir,
                   BVOX__VOXEL_SIZE_NAME);
    return BVOX_OK;
}

static bvox_status read_folder(const char *dir, const bvox_read_opts *opts, bvox_volume **out)
{
    voxel_size vs;
    bvox_status vst = read_voxel_size(dir, &vs);
    if (vst) return vst;
    char **paths = NULL;
    size_t n = 0;
    bvox_status st = bvox__list_dir(dir, keep_png, NULL, BVOX_MAX_DIM, "PNG slices", &paths, &n);
    if (!st && n == 0) st = bvox__fail(BVOX_EFORMAT, "%s: the folder holds no .png files", dir);
    if (st) return st;
    bvox__gray g;
    bvox__gray_init(&g);
    slice_info first;
    const char *first_path = paths[0];
    size_t slice_bytes = 0;
    /* slices binarised as they are decoded: the bits plus one slice (not
     * for Otsu, which needs every slice first) */
    const bvox_binarize *how = opts ? &opts->binarize : NULL;
    bvox__bin_stream *bs = NULL;
    bool stream = bvox__bin_stream_ok(how);
    for (size_t i = 0; i < n && !st; i++) {
        bvox__bytes b;
        st = bvox__read_file(paths[i], &b);
        if (!st) {
            slice_info info;
            if (i == 0) {
                st = decode_png(b.data, b.size, paths[i], &first, NULL, NULL, NULL);
                if (!st) st = gray_alloc(&g, &first, (int32_t)n, dir, how, stream ? &bs : NULL);
                slice_bytes = (size_t)first.w * first.h * (size_t)first.bytes;
            }
            if (!st)
                st = decode_png(b.data, b.size, paths[i], &info, &first, first_path,
                                (uint8_t *)g.owned + (bs ? 0 : i * slice_bytes));
            if (!st && bs) bvox__bin_stream_slices(bs, g.owned, 1);
            bvox__bytes_release(&b);
            if (!st) st = bvox__progress_steps((int64_t)i + 1, (int64_t)n);
        }
    }
    bvox__free_paths(paths, n);
    if (bs && st) bvox__bin_stream_abort(bs);
    else if (bs) st = bvox__bin_stream_finish(bs, out);
    else if (!st) st = bvox__binarize(&g, how, dir, out);
    bvox__gray_release(&g);
    if (!st) st = folder_geometry(dir, opts, &vs, *out);
    if (st && *out) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
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

/* Width and height from a PNG's IHDR (the chunk every PNG starts with). */
static bvox_status ihdr_dims(const char *path, uint32_t *w, uint32_t *h)
{
    uint8_t b[24];
    FILE *f = fopen(path, "rb");
    size_t got = f ? fread(b, 1, sizeof b, f) : 0;
    if (f) fclose(f);
    if (got < sizeof b || memcmp(b, "\x89PNG\r\n\x1a\n", 8) || memcmp(b + 12, "IHDR", 4))
        return bvox__fail(BVOX_EFORMAT, "%s: not a PNG file", path);
    *w = (uint32_t)b[16] << 24 | (uint32_t)b[17] << 16 | (uint32_t)b[18] << 8 | b[19];
    *h = (uint32_t)b[20] << 24 | (uint32_t)b[21] << 16 | (uint32_t)b[22] << 8 | b[23];
    if (!*w || !*h || *w > BVOX_MAX_DIM || *h > BVOX_MAX_DIM)
        return bvox__fail(*w && *h ? BVOX_ETOOBIG : BVOX_EFORMAT,
                          "%s: a slice of %u x %u pixels, outside 1..%d", path, *w, *h,
                          BVOX_MAX_DIM);
    return BVOX_OK;
}

/* A file: its IHDR, one slice. A folder: the first slice's IHDR and the
 * number of slices. Nothing is decoded. */
static bvox_status png_probe_dims(const char *path, const bvox_read_opts *opts,
                                  bvox_dims *dims)
{
    (void)opts;
    struct stat sb;
    uint32_t w, h;
    if (stat(path, &sb) != 0)
        return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
    if (!S_ISDIR(sb.st_mode)) {
        if (!S_ISREG(sb.st_mode))
            return bvox__fail(BVOX_EUNSUPPORTED, "%s: not a regular file", path);
        bvox_status st = ihdr_dims(path, &w, &h);
        if (!st) *dims = (bvox_dims){(int32_t)w, (int32_t)h, 1};
        return st;
    }
    char **paths = NULL;
    size_t n = 0;
    bvox_status st = bvox__list_dir(path, keep_png, NULL, BVOX_MAX_DIM, "PNG slices", &paths, &n);
    if (!st && n == 0) st = bvox__fail(BVOX_EFORMAT, "%s: the folder holds no .png files", path);
    if (st) return st;
    st = ihdr_dims(paths[0], &w, &h);
    bvox__free_paths(paths, n);
    if (!st) *dims = (bvox_dims){(int32_t)w, (int32_t)h, (int32_t)n};
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

static bvox_status file_write(void *f, const void *data, size_t n)
{
    return fwrite(data, 1, n, f) == n ? BVOX_OK : BVOX_EIO;
}

static bvox_status write_slice(const char *file, const uint8_t *pixels, uint32_t w, uint32_t h,
                               const uint32_t ppm[2])
{
    FILE *f = fopen(file, "wb");
    if (!f) return bvox__fail(BVOX_EIO, "%s: cannot create: %s", file, strerror(errno));
    const bvox__png_write_opts o = {1, 8, {ppm[0], ppm[1]}, 1};
    bvox_status st = bvox__png_encode(w, h, pixels, &o, file_write, f, file);
    if ((ferror(f) | fclose(f)) && !st)
        st = bvox__fail(BVOX_EIO, "%s: write failed: %s", file, strerror(errno));
    return st;
}

/* voxel_size.txt beside the slices: PNG keeps no z spacing (and pHYs no
 * unit but the metre), so without it a round trip would lose both. %.17g
 * prints each double so that it reads back to the same value. */
static bvox_status write_voxel_size(const char *tmp, char *file, size_t flen,
                                    const bvox_volume *v)
{
    snprintf(file, flen, "%s/%s", tmp, BVOX__VOXEL_SIZE_NAME);
    FILE *f = fopen(file, "w");
    if (!f) return bvox__fail(BVOX_EIO, "%s: cannot create: %s", file, strerror(errno));
    const double *s = v->geom.spacing;
    fprintf(f, "# voxel size of these slices (x y z unit), written by bvox\n%.17g %.17g %.17g%s%s\n",
            s[0], s[1], s[2], v->geom.unit[0] ? " " : "", v->geom.unit);
    if (ferror(f) | fclose(f))
        return bvox__fail(BVOX_EIO, "%s: write failed: %s", file, strerror(errno));
    return BVOX_OK;
}

static bvox_status png_write_path(const char *path, const bvox_volume *v,
                                  const bvox_write_opts *opts)
{
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
    bvox__dir_sink ds;
    st = bvox__dir_sink_open(path, BVOX__DIR_PNG_SLICES, opts->force != 0, &ds);
    const char *tmp = st ? NULL : ds.tmp;
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
            if (!st) st = bvox__progress_steps(z0 + k + 1, v->nz);
        }
    }
    if (!st) st = write_voxel_size(tmp, file, flen, v);
    free(file);
    bvox__free(slab, slab_bytes);
    if (tmp) {
        if (st) bvox__dir_sink_abort(&ds);
        else st = bvox__dir_sink_commit(&ds);
    }
    return st;
}

static const char *const png_extensions[] = {".png", NULL};

const bvox__format bvox__format_png = {
    "png", png_extensions, png_sniff, png_read_memory, png_read_path, png_write_path,
    png_probe_dims, NULL, NULL,
};
