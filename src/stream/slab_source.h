/*
 * slab_source.h — where the out-of-core operations (stream.h) get their
 * voxels and where they put them: a volume too large for the memory budget
 * is visited in slabs along z (the slowest axis of an OME-Zarr array, so a
 * slab is whole rows of chunks), each slab an ordinary bvox_volume that the
 * in-memory kernels take as they are.
 *
 * Sources: a .zarr folder (reading only the chunks a slab touches) and, for
 * the tests, a volume in memory. Sinks: a .zarr folder written slab by slab
 * (atomic: it appears only when complete) and a volume in memory.
 */
#ifndef BVOX_STREAM_SLAB_SOURCE_H
#define BVOX_STREAM_SLAB_SOURCE_H

#include "internal.h"

typedef struct bvox__slab_source bvox__slab_source;
struct bvox__slab_source {
    bvox_dims dims;
    bvox_geometry geom;  /* of the whole volume */
    int32_t chunk_z;     /* the natural slab depth multiple (a Zarr chunk's depth; 1 in memory) */
    const char *name;    /* for messages */
    size_t read_bytes;   /* what read() holds besides its result (a row of chunks) */
    /* Slices z0..z1-1 (0 <= z0 < z1 <= nz) as a new volume (nx, ny, z1 - z0),
     * default origin, the source's spacing and unit. */
    bvox_status (*read)(const bvox__slab_source *s, int32_t z0, int32_t z1, bvox_volume **out);
    void (*close)(bvox__slab_source *s);
    void *ctx;
};

/* The slabs of vol (borrowed: it must outlive the source). */
bvox_status bvox__slab_source_memory(const bvox_volume *vol, bvox__slab_source *out);
/* Whether path is a Zarr array or group folder. */
bool bvox__slab_source_is_zarr(const char *path);
/* The array of a .zarr folder, binarised by how (NULL: nonzero; not Otsu). */
bvox_status bvox__slab_source_zarr(const char *path, const bvox_binarize *how,
                                   bvox__slab_source *out);
/* The same for a multiscales level (0 the finest; --level). */
bvox_status bvox__slab_source_zarr_level(const char *path, int32_t level,
                                         const bvox_binarize *how, bvox__slab_source *out);
/* Accepts a source never opened (zeroed) or already closed. */
void bvox__slab_source_close(bvox__slab_source *s);

typedef struct bvox__slab_sink bvox__slab_sink;
struct bvox__slab_sink {
    int32_t align;       /* slabs start at multiples of it and are multiples of it deep
                            (but the last) */
    size_t bytes;        /* what the sink holds while open (its buffers) */
    /* Slices z_at.. z_at + slab->nz - 1, in order. */
    bvox_status (*put)(bvox__slab_sink *s, const bvox_volume *slab, int32_t z_at);
    /* keep: the output is complete (commit); else discard. *st gets the
     * commit's status when it was BVOX_OK. */
    void (*close)(bvox__slab_sink *s, bool keep, bvox_status *st);
    void *ctx;
};

/* Into *vol, a new volume of dims and geom (the caller owns it once closed
 * with keep; it is destroyed otherwise). */
bvox_status bvox__slab_sink_memory(bvox_dims dims, const bvox_geometry *geom, bvox_volume **vol,
                                   bvox__slab_sink *out);
/* Into a .zarr folder (opts: chunks and compressor). */
bvox_status bvox__slab_sink_zarr(const char *path, bvox_dims dims, const bvox_geometry *geom,
                                 const bvox_write_opts *opts, bvox__slab_sink *out);

#endif /* BVOX_STREAM_SLAB_SOURCE_H */
