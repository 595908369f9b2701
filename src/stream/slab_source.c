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
    bvox__zarr_in zi;
    bvox_binarize how;
    bool have_how;
} zarr_ctx;

static bvox_status zarr_read(const bvox__slab_source *s, int32_t z0, int32_t z1, bvox_volume **out)
{
    const zarr_ctx *z = s->ctx;
    bvox_box b = {0, 0, z0, s->dims.nx, s->dims.ny, z1};
    return bvox__zarr_in_read_box(&z->zi, b, z->have_how ? &z->how : NULL, out);
}

static void zarr_close(bvox__slab_source *s)
{
    free(s->ctx);
    s->ctx = NULL;
}

bool bvox__slab_source_is_zarr(const char *path) { return bvox__zarr_is_dir(path); }

bvox_status bvox__slab_source_zarr(const char *path, const bvox_binarize *how,
                                   bvox__slab_source *out)
{
    memset(out, 0, sizeof *out);
    if (how && !bvox__bin_stream_ok(how))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: Otsu's threshold needs the whole volume in "
                          "memory (give --threshold, or a larger --max-memory)", path);
    zarr_ctx *z = bvox__mem_alloc(sizeof *z);
    if (!z) return bvox__fail(BVOX_ENOMEM, "out of memory");
    memset(z, 0, sizeof *z);
    bvox_status st = bvox__zarr_in_open(path, &z->zi);
    if (st) {
        free(z);
        return st;
    }
    if (how) z->how = *how, z->have_how = true;
    out->dims = z->zi.dims;
    out->geom = z->zi.geom;
    out->chunk_z = (int32_t)z->zi.m.chunks[0];
    out->read_bytes = (size_t)z->zi.m.chunks[0] * (size_t)out->dims.nx * (size_t)out->dims.ny *
                          bvox_dtype_size(z->zi.m.dtype) +
                      (size_t)z->zi.m.chunks[0] * (size_t)z->zi.m.chunks[1] *
                          (size_t)z->zi.m.chunks[2] * bvox_dtype_size(z->zi.m.dtype);
    out->name = z->zi.name;
    out->read = zarr_read;
    out->close = zarr_close;
    out->ctx = z;
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

static bvox_status zarr_put(bvox__slab_sink *s, const bvox_volume *slab, int32_t z_at)
{
    return bvox__zarr_out_put(s->ctx, slab, z_at);
}

static void zarr_sink_close(bvox__slab_sink *s, bool keep, bvox_status *st)
{
    bvox__zarr_out_close(s->ctx, keep, st);
    s->ctx = NULL;
}

bvox_status bvox__slab_sink_zarr(const char *path, bvox_dims dims, const bvox_geometry *geom,
                                 const bvox_write_opts *opts, bvox__slab_sink *out)
{
    memset(out, 0, sizeof *out);
    bvox__zarr_out *w = NULL;
    bvox_status st = bvox__zarr_out_open(path, dims, geom, opts, &w);
    if (st) return st;
    out->align = bvox__zarr_out_chunk_z(w);
    out->bytes = bvox__zarr_out_bytes(w);
    out->put = zarr_put;
    out->close = zarr_sink_close;
    out->ctx = w;
    return BVOX_OK;
}
