/*
 * slab_source.c — slab sources and sinks (slab_source.h): a volume in memory
 * (for the tests: the same operations run in slabs on a volume whose
 * in-memory answer is known) and a .zarr folder (io/zarr.c's box reader and
 * slab writer).
 */
#include "stream/slab_source.h"

#include "io/zarr.h"

#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------- in memory */

static bvox_status memory_read(const bvox__slab_source *s, int32_t z0, int32_t z1,
                               bvox_volume **out)
{
    const bvox_volume *v = s->ctx;
    bvox_box b = {0, 0, z0, v->nx, v->ny, z1};
    bvox_status st = bvox_volume_crop(v, b, out);
    if (st) return st;
    bvox_geometry g = s->geom;
    memcpy(g.origin, (double[3]){0, 0, 0}, sizeof g.origin);
    return bvox_volume_set_geometry(*out, &g);
}

static void no_close(bvox__slab_source *s) { (void)s; }

bvox_status bvox__slab_source_memory(const bvox_volume *vol, bvox__slab_source *out)
{
    memset(out, 0, sizeof *out);
    out->dims = bvox_volume_dims(vol);
    out->geom = vol->geom;
    out->chunk_z = 1;
    out->name = "volume";
    out->read = memory_read;
    out->close = no_close;
    out->ctx = (void *)vol;
    return BVOX_OK;
}

/* ---------------------------------------------------------- .zarr */

typedef struct zarr_ctx {
    bvox__zarr *z;
    char *name;         /* a copy: the caller's string may not outlive the source */
    bvox_binarize how;
    bool have_how;
    int32_t chunk_z;
} zarr_ctx;

/* Slices z0..z1-1, one row of chunks along z at a time through the
 * streaming binariser: the row's samples are the only gray buffer. */
static bvox_status zarr_read(const bvox__slab_source *s, int32_t z0, int32_t z1, bvox_volume **out)
{
    zarr_ctx *c = s->ctx;
    *out = NULL;
    const int32_t nx = s->dims.nx, ny = s->dims.ny;
    bvox__gray shape;
    bvox__gray_init(&shape);
    shape.dims = (bvox_dims){nx, ny, z1 - z0};
    shape.dtype = bvox__zarr_dtype(c->z);
    shape.geom = s->geom;
    memset(shape.geom.origin, 0, sizeof shape.geom.origin);
    bvox__bin_stream *bs = NULL;
    bvox_status st = bvox__bin_stream_begin(&shape, c->have_how ? &c->how : NULL, c->name, &bs);
    size_t row_bytes = 0;
    void *row = NULL;
    if (!st) {
        row_bytes = bvox__bin_stream_slice_bytes(bs) * (size_t)c->chunk_z;
        row = bvox__alloc(row_bytes, false, "Zarr row samples", &st);
        if (!row) bvox__error_prefix(c->name);
    }
    for (int32_t z = z0; !st && z < z1;) {
        int32_t ze = (z / c->chunk_z + 1) * c->chunk_z;
        if (ze > z1) ze = z1;
        st = bvox__zarr_read_box_samples(c->z, 0, 0, z, nx, ny, ze - z, row);
        if (!st) bvox__bin_stream_slices(bs, row, (size_t)(ze - z));
        z = ze;
    }
    if (row) bvox__free(row, row_bytes);
    if (st) {
        bvox__bin_stream_abort(bs);
        return st;
    }
    return bvox__bin_stream_finish(bs, out);
}

static void zarr_close(bvox__slab_source *s)
{
    zarr_ctx *c = s->ctx;
    if (c) {
        bvox__zarr_close(c->z);
        free(c->name);
    }
    free(c);
    s->ctx = NULL;
}

bool bvox__slab_source_is_zarr(const char *path) { return bvox__zarr_is_dir(path); }

bvox_status bvox__slab_source_zarr(const char *path, const bvox_binarize *how,
                                   bvox__slab_source *out)
{
    return bvox__slab_source_zarr_level(path, 0, how, out);
}

bvox_status bvox__slab_source_zarr_level(const char *path, int32_t level,
                                         const bvox_binarize *how, bvox__slab_source *out)
{
    memset(out, 0, sizeof *out);
    if (how && !bvox__bin_stream_ok(how))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: Otsu's threshold needs the whole volume in "
                          "memory (give --threshold, or a larger --max-memory)", path);
    zarr_ctx *c = bvox__mem_zalloc(1, sizeof *c);
    char *name = c ? bvox__mem_strdup(path) : NULL;
    if (!name) {
        free(c);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    bvox_status st = bvox__zarr_open_level(path, level, &c->z);
    if (st) {
        free(name);
        free(c);
        return st;
    }
    if (how) c->how = *how, c->have_how = true;
    c->name = name;
    int32_t ch[3];
    bvox__zarr_chunk_shape(c->z, ch);
    c->chunk_z = ch[2];
    out->dims = bvox__zarr_dims(c->z);
    out->geom = *bvox__zarr_geometry(c->z);
    out->chunk_z = ch[2];
    out->name = name;
    size_t elem = bvox_dtype_size(bvox__zarr_dtype(c->z));
    /* a row of samples, and the reader's decoded chunk */
    out->read_bytes = ((size_t)ch[2] * (size_t)out->dims.nx * (size_t)out->dims.ny +
                       (size_t)ch[0] * (size_t)ch[1] * (size_t)ch[2]) * elem;
    out->read = zarr_read;
    out->close = zarr_close;
    out->ctx = c;
    return BVOX_OK;
}

void bvox__slab_source_close(bvox__slab_source *s)
{
    if (s->close) s->close(s);
    memset(s, 0, sizeof *s);
}

/* ---------------------------------------------------------- sinks */

typedef struct memory_sink {
    bvox_volume *v;
    bvox_volume **dst;
} memory_sink;

static bvox_status memory_put(bvox__slab_sink *s, const bvox_volume *slab, int32_t z_at)
{
    memory_sink *m = s->ctx;
    return bvox_csg_apply(m->v, BVOX_CSG_REPLACE, slab, (int32_t[3]){0, 0, z_at});
}

static void memory_sink_close(bvox__slab_sink *s, bool keep, bvox_status *st)
{
    memory_sink *m = s->ctx;
    if (keep && !*st) *m->dst = m->v;
    else bvox_volume_destroy(m->v);
    free(m);
    s->ctx = NULL;
}

bvox_status bvox__slab_sink_memory(bvox_dims dims, const bvox_geometry *geom, bvox_volume **vol,
                                   bvox__slab_sink *out)
{
    memset(out, 0, sizeof *out);
    *vol = NULL;
    memory_sink *m = bvox__mem_alloc(sizeof *m);
    if (!m) return bvox__fail(BVOX_ENOMEM, "out of memory");
    m->dst = vol;
    bvox_status st = bvox_volume_create(dims, &m->v);
    if (!st) st = bvox_volume_set_geometry(m->v, geom);
    if (st) {
        bvox_volume_destroy(m->v);
        free(m);
        return st;
    }
    out->align = 1;
    out->put = memory_put;
    out->close = memory_sink_close;
    out->ctx = m;
    return BVOX_OK;
}

typedef struct zarr_sink {
    bvox__zarr_writer *w;
    int32_t chunk_z;
} zarr_sink;

/* One row of chunks at a time: the writer unpacks what it is given to bytes. */
static bvox_status zarr_put(bvox__slab_sink *s, const bvox_volume *slab, int32_t z_at)
{
    zarr_sink *k = s->ctx;
    bvox_status st = BVOX_OK;
    for (int32_t z = 0; !st && z < slab->nz; z += k->chunk_z) {
        int32_t ze = z + k->chunk_z < slab->nz ? z + k->chunk_z : slab->nz;
        if (z == 0 && ze == slab->nz) return bvox__zarr_write_box(k->w, 0, 0, z_at, slab);
        bvox_volume *row = NULL;
        st = bvox_volume_crop(slab, (bvox_box){0, 0, z, slab->nx, slab->ny, ze}, &row);
        if (!st) st = bvox__zarr_write_box(k->w, 0, 0, z_at + z, row);
        bvox_volume_destroy(row);
    }
    return st;
}

static void zarr_sink_close(bvox__slab_sink *s, bool keep, bvox_status *st)
{
    zarr_sink *k = s->ctx;
    if (keep && !*st) *st = bvox__zarr_commit(k->w);
    else bvox__zarr_abort(k->w);
    free(k);
    s->ctx = NULL;
}

bvox_status bvox__slab_sink_zarr(const char *path, bvox_dims dims, const bvox_geometry *geom,
                                 const bvox_write_opts *opts, bvox__slab_sink *out)
{
    memset(out, 0, sizeof *out);
    const char *f = opts && opts->format ? opts->format : "zarr";
    if (strcmp(f, "zarr"))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: slabs are written as .zarr only", path);
    zarr_sink *k = bvox__mem_zalloc(1, sizeof *k);
    if (!k) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bvox_status st = bvox__zarr_create(path, dims, opts ? opts->chunks : (int32_t[3]){0, 0, 0},
                                       opts ? opts->compressor : NULL, geom,
                                       opts ? opts->zarr_levels : 0, opts && opts->force, &k->w);
    if (st) {
        free(k);
        return st;
    }
    int32_t ch[3];
    bvox__zarr_writer_chunk_shape(k->w, ch);
    k->chunk_z = ch[2];
    out->align = ch[2];
    /* the writer's byte copy of one row of chunks, the crop, a chunk and its
     * compressed copy */
    out->bytes = (size_t)ch[2] * (size_t)dims.nx * (size_t)dims.ny * 2 +
                 (size_t)ch[0] * (size_t)ch[1] * (size_t)ch[2] * 3;
    out->put = zarr_put;
    out->close = zarr_sink_close;
    out->ctx = k;
    return BVOX_OK;
}
