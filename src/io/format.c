/*
 * format.c — the explicit table of file formats and the public entry points
 * bvox_read, bvox_read_memory and bvox_write that dispatch through it: by the
 * forced format name, else by extension, else (reading) by content.
 */
#include "io.h"
#include "common/names.h"

#include <string.h>
#include <strings.h>
#include <sys/stat.h>

static const bvox__format *const formats[] = {
    &bvox__format_nifti, &bvox__format_binvox, &bvox__format_tiff,
    &bvox__format_png,   &bvox__format_raw,    &bvox__format_nrrd,
    &bvox__format_zarr,
    &bvox__format_metaimage,
};
#define NFORMATS (sizeof formats / sizeof formats[0])

const char *bvox_format_list(void) { return "nifti, binvox, tiff, png, raw, nrrd, zarr, metaimage"; }

static const bvox__format *by_name(const char *name)
{
    for (size_t i = 0; i < NFORMATS; i++)
        if (!strcasecmp(formats[i]->name, name)) return formats[i];
    /* common aliases */
    if (!strcasecmp(name, "nii")) return &bvox__format_nifti;
    if (!strcasecmp(name, "tif")) return &bvox__format_tiff;
    if (!strcasecmp(name, "mha") || !strcasecmp(name, "mhd")) return &bvox__format_metaimage;
    return NULL;
}

static const bvox__format *by_extension(const char *path)
{
    size_t len = strlen(path);
    while (len > 1 && path[len - 1] == '/') len--;
    char trimmed[4096];
    if (len >= sizeof trimmed) return NULL;
    memcpy(trimmed, path, len);
    trimmed[len] = '\0';
    for (size_t i = 0; i < NFORMATS; i++)
        for (const char *const *e = formats[i]->extensions; e && *e; e++)
            if (bvox__ends_with_ci(trimmed, *e)) return formats[i];
    return NULL;
}

const char *bvox_format_for_path(const char *path)
{
    const bvox__format *f = by_extension(path);
    return f ? f->name : NULL;
}

static bvox_status resolve(const char *forced, const char *path, const bvox__format **out)
{
    *out = NULL;
    if (forced && *forced) {
        *out = by_name(forced);
        if (!*out)
            return bvox__fail(BVOX_EINVAL, "unknown format '%s' (known: %s)", forced,
                              bvox_format_list());
        return BVOX_OK;
    }
    if (path) *out = by_extension(path);
    return BVOX_OK;
}

static const bvox__format *sniff(const uint8_t *data, size_t size)
{
    for (size_t i = 0; i < NFORMATS; i++)
        if (formats[i]->sniff && formats[i]->sniff(data, size)) return formats[i];
    return NULL;
}

static bvox_status finish(bvox_status st, const bvox_read_opts *opts, bvox_volume **out)
{
    if (st == BVOX_OK && *out && (bvox__read_spacing_given(opts) || opts->unit)) {
        const double *s = bvox__read_spacing_given(opts) ? opts->spacing : (*out)->geom.spacing;
        st = bvox_volume_set_spacing(*out, s[0], s[1], s[2], opts->unit);
        if (st) {
            bvox_volume_destroy(*out);
            *out = NULL;
        }
    }
    if (st == BVOX_OK && *out) {
        /* every reader must leave the invariants intact */
        bvox_status chk = bvox_volume_check(*out);
        if (chk) {
            bvox_volume_destroy(*out);
            *out = NULL;
            return chk;
        }
    }
    return st;
}

/* The format of a buffer: the forced one, else by content. */
static bvox_status memory_format(const void *data, size_t size, const char *name,
                                 const char *forced, const bvox__format **f)
{
    bvox_status st = resolve(forced, NULL, f);
    if (st) return st;
    if (!*f) *f = sniff(data, size);
    if (!*f)
        return bvox__fail(BVOX_EFORMAT, "%s: unrecognised content (give the format: %s)", name,
                          bvox_format_list());
    return BVOX_OK;
}

static bvox_status read_memory(const void *data, size_t size, const char *name,
                               const bvox_read_opts *opts, bvox_volume **out);
static bvox_status read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out);

bvox_status bvox_read_memory(const void *data, size_t size, const char *name,
                             const bvox_read_opts *opts, bvox_volume **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "read");
    return bvox__progress_end(&ps, read_memory(data, size, name, opts, out));
}

bvox_status bvox_read(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "read");
    return bvox__progress_end(&ps, read_path(path, opts, out));
}

static bvox_status read_memory(const void *data, size_t size, const char *name,
                               const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    bvox__clear_error();
    bvox_read_opts defaults = BVOX_READ_OPTS_INIT;
    if (!opts) opts = &defaults;
    if (!name) name = "input";
    const bvox__format *f;
    bvox_status st = memory_format(data, size, name, opts->format, &f);
    if (st) return st;
    st = f->read_memory(data, size, name, opts, out);
    return finish(st, opts, out);
}

/* Progress: reading the file is the first fifth, decoding the rest. */
static bvox_status read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    bvox__clear_error();
    bvox_read_opts defaults = BVOX_READ_OPTS_INIT;
    if (!opts) opts = &defaults;
    const bvox__format *f;
    bvox_status st = resolve(opts->format, path, &f);
    if (st) return st;
    struct stat sb;
    if (stat(path, &sb) != 0) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
    if (S_ISDIR(sb.st_mode) && !f)
        f = bvox__zarr_is_dir(path) ? &bvox__format_zarr : &bvox__format_png; /* else slices */
    if (f && f->read_path) return finish(f->read_path(path, opts, out), opts, out);
    bvox__bytes file;
    bvox__progress_scope ps;
    bvox__progress_sub(&ps, 0, 0.2, NULL);
    st = bvox__read_file(path, &file);
    bvox__progress_restore(&ps);
    if (st) return st;
    if (!f) f = sniff(file.data, file.size);
    if (!f) {
        bvox__bytes_release(&file);
        return bvox__fail(BVOX_EFORMAT,
                          "%s: unknown file type (extension not recognised and content not "
                          "identified; give --format, one of: %s)",
                          path, bvox_format_list());
    }
    bvox__progress_sub(&ps, 0.2, 1, NULL);
    st = f->read_memory(file.data, file.size, path, opts, out);
    bvox__progress_restore(&ps);
    bvox__bytes_release(&file);
    return finish(st, opts, out);
}

bvox_status bvox_read_dims(const char *path, const bvox_read_opts *opts, bvox_dims *dims)
{
    bvox__clear_error();
    bvox_read_opts defaults = BVOX_READ_OPTS_INIT;
    if (!opts) opts = &defaults;
    const bvox__format *f;
    bvox_status st = resolve(opts->format, path, &f);
    if (st) return st;
    struct stat sb;
    if (stat(path, &sb) != 0) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
    if (S_ISDIR(sb.st_mode) && !f) f = &bvox__format_png;
    if (!f || !f->probe_dims)
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: the size is known only by reading the file",
                          path);
    return f->probe_dims(path, opts, dims);
}

/* The format bvox_write would use for path. */
static bvox_status output_format(const char *path, const bvox_write_opts *opts,
                                 const bvox__format **out)
{
    const bvox__format *f;
    bvox_status st = resolve(opts->format, path, &f);
    if (st) return st;
    struct stat sb;
    size_t len = strlen(path);
    if (!f && ((len && path[len - 1] == '/') || (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))))
        f = &bvox__format_png; /* a folder: PNG slices */
    if (!f)
        return bvox__fail(BVOX_EINVAL,
                          "%s: cannot tell the output format from the extension (use one of "
                          ".nii .nii.gz .binvox .tif .tiff .raw .zarr .nrrd .nhdr .mha .mhd, a "
                          "folder with --format png)",
                          path);
    if (!f->write_path)
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: writing %s is not supported", path, f->name);
    *out = f;
    return BVOX_OK;
}

bvox_status bvox_write_check(const char *path, bvox_dims dims, const bvox_write_opts *opts)
{
    bvox__clear_error();
    bvox_write_opts defaults = BVOX_WRITE_OPTS_INIT;
    if (!opts) opts = &defaults;
    const bvox__format *f = NULL;
    bvox_status st = output_format(path, opts, &f);
    size_t bytes;
    if (!st && f->write_limits) st = f->write_limits(path, dims);
    if (!st) st = bvox__check_dims(dims, path, &bytes);
    return st;
}

static bvox_status write_path(const char *path, const bvox_volume *vol,
                              const bvox_write_opts *opts);

bvox_status bvox_write(const char *path, const bvox_volume *vol, const bvox_write_opts *opts)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "write");
    return bvox__progress_end(&ps, write_path(path, vol, opts));
}

static bvox_status write_path(const char *path, const bvox_volume *vol,
                              const bvox_write_opts *opts)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__clear_error();
    bvox_write_opts defaults = BVOX_WRITE_OPTS_INIT;
    if (!opts) opts = &defaults;
    const bvox__format *f = NULL;
    bvox_status st = output_format(path, opts, &f);
    if (st) return st;
    if (f->write_limits) {
        st = f->write_limits(path, bvox_volume_dims(vol));
        if (st) return st;
    }
    return f->write_path(path, vol, opts);
}

/* ---------------------------------------------- typed samples (label volumes) */

static bvox_status no_samples(const bvox__format *f, const char *name)
{
    return bvox__fail(BVOX_EUNSUPPORTED,
                      "%s: %s files hold binary voxels, not labels (label volumes are read "
                      "from nifti, tiff, raw, nrrd, metaimage or zarr)",
                      name, f->name);
}

bvox_status bvox__read_gray_memory(const void *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox__gray *g)
{
    bvox__gray_init(g);
    bvox_read_opts defaults = BVOX_READ_OPTS_INIT;
    if (!opts) opts = &defaults;
    if (!name) name = "input";
    const bvox__format *f;
    bvox_status st = memory_format(data, size, name, opts->format, &f);
    if (st) return st;
    if (!f->gray_memory) return no_samples(f, name);
    return f->gray_memory(data, size, name, opts, g);
}

bvox_status bvox__read_gray(const char *path, const bvox_read_opts *opts, bvox__bytes *file,
                            bvox__gray *g)
{
    bvox__gray_init(g);
    memset(file, 0, sizeof *file);
    bvox_read_opts defaults = BVOX_READ_OPTS_INIT;
    if (!opts) opts = &defaults;
    const bvox__format *f;
    bvox_status st = resolve(opts->format, path, &f);
    if (st) return st;
    struct stat sb;
    if (stat(path, &sb) != 0) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
    if (S_ISDIR(sb.st_mode) && !f)
        f = bvox__zarr_is_dir(path) ? &bvox__format_zarr : &bvox__format_png;
    if (f == &bvox__format_zarr) return bvox__zarr_read_gray(path, opts, g); /* a folder */
    if (f && !f->gray_memory) return no_samples(f, path);
    st = bvox__read_file(path, file);
    if (st) return st;
    if (!f) f = sniff(file->data, file->size);
    if (!f || !f->gray_memory) {
        bvox__bytes_release(file);
        memset(file, 0, sizeof *file);
        if (f) return no_samples(f, path);
        return bvox__fail(BVOX_EFORMAT,
                          "%s: unknown file type (extension not recognised and content not "
                          "identified; give --format, one of: %s)",
                          path, bvox_format_list());
    }
    st = f->gray_memory(file->data, file->size, path, opts, g);
    if (st) {
        bvox__bytes_release(file);
        memset(file, 0, sizeof *file);
    }
    return st;
}
