/*
 * zarr.c — OME-Zarr (NGFF 0.4 on Zarr v2) as one of bvox's formats: whole
 * volumes read and written through the box interface of zarr.h (reader in
 * zarr_read.c, writer in zarr_write.c, pyramid in zarr_pyramid.c).
 *
 * Read: the path is an array (has .zarray) or a group whose .zattrs names
 * the multiscales datasets (level 0, the finest, unless the read options
 * ask for another; else the array "0"); the read options binarise
 * (binarize.c); label volumes (bvox_labels_read) take the level's typed
 * samples unbinarised. Written: a group with a resolution pyramid (opts->levels),
 * uint8 0/1, chunk shape and compressor from the options.
 */
#include "zarr.h"

#include <stdio.h>
#include <string.h>

/* The level's samples, whole, as typed gray samples (the CPU's byte order)
 * with the level's geometry: label volumes read these (labels_read.c). */
bvox_status bvox__zarr_read_gray(const char *path, const bvox_read_opts *opts, bvox__gray *g)
{
    bvox__gray_init(g);
    bvox__zarr *z;
    bvox_status st = bvox__zarr_open_level(path, opts ? opts->zarr_level : 0, &z);
    if (st) return st;
    bvox_dims d = bvox__zarr_dims(z);
    size_t wb;
    if ((st = bvox__check_dims(d, path, &wb))) { /* the whole volume: within the budget */
        bvox__zarr_close(z);
        return st;
    }
    size_t total, elem = bvox_dtype_size(bvox__zarr_dtype(z));
    if (!bvox__mul_size((size_t)d.nx * (size_t)d.ny, (size_t)d.nz, &total) ||
        !bvox__mul_size(total, elem, &total)) {
        bvox__zarr_close(z);
        return bvox__fail(BVOX_ETOOBIG, "%s: array size overflows", path);
    }
    void *samples = bvox__alloc(total, false, "Zarr samples", &st);
    if (!samples) {
        bvox__error_prefix(path);
        bvox__zarr_close(z);
        return st;
    }
    st = bvox__zarr_read_box_samples(z, 0, 0, 0, d.nx, d.ny, d.nz, samples);
    if (st) {
        bvox__free(samples, total);
        bvox__zarr_close(z);
        return st;
    }
    g->dims = d;
    g->dtype = bvox__zarr_dtype(z);
    g->data = samples;
    g->owned = samples;
    g->owned_bytes = total;
    g->geom = *bvox__zarr_geometry(z);
    bvox__zarr_close(z);
    return BVOX_OK;
}

/* The binary volume read one row of chunks along z at a time through the
 * streaming binariser: besides the volume's words only a row of samples is
 * held (whole, the samples of a uint8 array take 8 times the words, so a
 * volume the out-of-core path judged small enough to read whole would not
 * fit the budget it was judged by). */
static bvox_status zarr_read_rows(const char *path, const bvox_read_opts *opts,
                                  bvox_volume **out)
{
    bvox__zarr *z;
    bvox_status st = bvox__zarr_open_level(path, opts ? opts->zarr_level : 0, &z);
    if (st) return st;
    bvox_dims d = bvox__zarr_dims(z);
    size_t wb;
    if ((st = bvox__check_dims(d, path, &wb))) {
        bvox__zarr_close(z);
        return st;
    }
    int32_t ch[3];
    bvox__zarr_chunk_shape(z, ch);
    bvox__gray shape;
    bvox__gray_init(&shape);
    shape.dims = d;
    shape.dtype = bvox__zarr_dtype(z);
    shape.geom = *bvox__zarr_geometry(z);
    bvox__bin_stream *bs = NULL;
    st = bvox__bin_stream_begin(&shape, opts ? &opts->binarize : NULL, path, &bs);
    size_t row_bytes = 0;
    void *row = NULL;
    if (!st && !bvox__mul_size(bvox__bin_stream_slice_bytes(bs), (size_t)ch[2], &row_bytes))
        st = bvox__fail(BVOX_ETOOBIG, "%s: array size overflows", path);
    if (!st) {
        row = bvox__alloc(row_bytes, false, "Zarr row samples", &st);
        if (!row) bvox__error_prefix(path);
    }
    for (int32_t k = 0; !st && k < d.nz;) {
        int32_t ke = (k / ch[2] + 1) * ch[2];
        if (ke > d.nz) ke = d.nz;
        st = bvox__zarr_read_box_samples(z, 0, 0, k, d.nx, d.ny, ke - k, row);
        if (!st) bvox__bin_stream_slices(bs, row, (size_t)(ke - k));
        k = ke;
    }
    if (row) bvox__free(row, row_bytes);
    bvox__zarr_close(z);
    if (st) {
        if (bs) bvox__bin_stream_abort(bs);
        return st;
    }
    return bvox__bin_stream_finish(bs, out);
}

static bvox_status zarr_read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (bvox__bin_stream_ok(opts ? &opts->binarize : NULL)) return zarr_read_rows(path, opts, out);
    /* Otsu's threshold needs every sample first */
    bvox__gray g;
    bvox_status st = bvox__zarr_read_gray(path, opts, &g);
    if (st) return st;
    st = bvox__binarize(&g, opts ? &opts->binarize : NULL, path, out);
    bvox__gray_release(&g);
    return st;
}

static bvox_status zarr_read_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox_volume **out)
{
    (void)data, (void)size, (void)opts;
    *out = NULL;
    return bvox__fail(BVOX_EUNSUPPORTED, "%s: Zarr is a folder; read it by its path",
                      name ? name : "input");
}

static bvox_status zarr_write_path(const char *path, const bvox_volume *v,
                                   const bvox_write_opts *opts)
{
    bvox__zarr_writer *w;
    bvox_status st = bvox__zarr_create(path, (bvox_dims){v->nx, v->ny, v->nz},
                                       opts ? opts->chunks : NULL, opts ? opts->compressor : NULL,
                                       &v->geom, opts ? opts->zarr_levels : 0,
                                       opts && opts->force, &w);
    if (st) return st;
    st = bvox__zarr_write_box(w, 0, 0, 0, v);
    if (st) {
        bvox__zarr_abort(w);
        return st;
    }
    return bvox__zarr_commit(w);
}

static bvox_status zarr_probe_dims(const char *path, const bvox_read_opts *opts, bvox_dims *dims)
{
    bvox__zarr *z;
    bvox_status st = bvox__zarr_open_level(path, opts ? opts->zarr_level : 0, &z);
    if (st) return st;
    *dims = bvox__zarr_dims(z);
    bvox__zarr_close(z);
    return BVOX_OK;
}

static const char *const zarr_extensions[] = {".zarr", NULL};

const bvox__format bvox__format_zarr = {
    "zarr", zarr_extensions, NULL, zarr_read_memory, zarr_read_path, zarr_write_path,
    zarr_probe_dims, NULL, NULL,
};
