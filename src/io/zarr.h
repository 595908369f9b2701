/*
 * zarr.h — private interface of the OME-Zarr (NGFF 0.4 on Zarr v2) reader and
 * writer: a small JSON tree (zarr_json.c), the metadata of one array and of
 * the multiscales group (zarr_meta.c), and the format itself (zarr.c).
 *
 * Array order: Zarr arrays are C order (last index fastest) and NGFF orders
 * the axes (z, y, x), so the array shape is [nz, ny, nx] and a chunk's bytes
 * run x fastest, then y, then z — the order bvox__gray holds its samples.
 */
#ifndef BVOX_IO_ZARR_H
#define BVOX_IO_ZARR_H

#include "io.h"

/* ---- zarr_json.c: a bounded JSON tree ---- */

typedef enum bvox__jtype {
    BVOX__JT_NULL, BVOX__JT_FALSE, BVOX__JT_TRUE, BVOX__JT_NUMBER,
    BVOX__JT_STRING, BVOX__JT_ARRAY, BVOX__JT_OBJECT
} bvox__jtype;

typedef struct bvox__jnode {
    bvox__jtype type;
    double num;          /* NUMBER */
    bool is_int;         /* NUMBER written without fraction or exponent */
    const char *str;     /* STRING: decoded, NUL-terminated (may hold NULs: len) */
    size_t len;
    const char *key;     /* member name when the parent is an OBJECT, else NULL */
    int32_t first_child; /* ARRAY/OBJECT: index of the first element, -1 none */
    int32_t next;        /* next sibling, -1 none */
    int32_t count;       /* ARRAY/OBJECT: number of elements */
} bvox__jnode;

typedef struct bvox__jtree {
    bvox__jnode *nodes; /* nodes[0] is the root */
    int32_t n, cap;
    char *text;             /* decoded copy of the input the strings point into */
} bvox__jtree;

/* Limits: metadata files are small; anything larger is refused. */
#define BVOX__JTREE_MAX_BYTES ((size_t)1 << 20)
#define BVOX__JTREE_MAX_DEPTH 64 /* (common/json.h is the writer; this is a reader) */

/* Parse strict JSON (RFC 8259). Errors are BVOX_EFORMAT "NAME: line L: what". */
bvox_status bvox__jtree_parse(const char *text, size_t size, const char *name, bvox__jtree *out);
void bvox__jtree_release(bvox__jtree *j);
/* Member `key` of object node i, or NULL (also when i is not an object). */
const bvox__jnode *bvox__jtree_get(const bvox__jtree *j, const bvox__jnode *obj,
                                      const char *key);
/* Element k of an array node, or NULL. */
const bvox__jnode *bvox__jtree_at(const bvox__jtree *j, const bvox__jnode *arr, int32_t k);

/* ---- zarr_meta.c ---- */

typedef enum bvox__zarr_codec {
    BVOX__ZARR_RAW = 0, BVOX__ZARR_ZLIB, BVOX__ZARR_GZIP, BVOX__ZARR_BLOSC
} bvox__zarr_codec;

typedef struct bvox__zarr_meta {
    int64_t shape[3];   /* z, y, x */
    int64_t chunks[3];  /* z, y, x */
    bvox_dtype dtype;
    bool big_endian;    /* dtype's byte order ('>') */
    bool is_bool;       /* "|b1": read as u8 */
    bvox__zarr_codec codec;
    bool has_fill;      /* fill_value is a number (missing chunks are it) */
    double fill;
    char sep;           /* '.' or '/' */
} bvox__zarr_meta;


/* Parse and validate a .zarray (3-D, C order, no filters, a known dtype and
 * compressor, chunks >= 1). name names the file in messages. */
bvox_status bvox__zarr_meta_parse(const char *text, size_t size, const char *name,
                                  bvox__zarr_meta *out);

/* From a group's .zattrs: the path of the first (finest) multiscales dataset
 * (path_cap bytes; "" if none), its scale (z, y, x order in the file, stored
 * here as x, y, z) and the unit of the space axes ("" if none). have_scale is
 * false when there is no scale transform. The dataset's translation (the
 * physical position of its voxel 0: a coarse level's is shifted to the
 * centre of the fine voxels it covers) is the origin, 0 when none. */
typedef struct bvox__zarr_attrs {
    char path[256];
    double spacing[3]; /* x, y, z */
    bool have_scale;
    double origin[3];  /* x, y, z */
    bool have_translation;
    char unit[16];
    int32_t nlevels;   /* datasets in the multiscales (0 when none) */
} bvox__zarr_attrs;
bvox_status bvox__zarr_attrs_parse(const char *text, size_t size, const char *name,
                                   bvox__zarr_attrs *out);
/* The same for dataset `level` (0 finest); BVOX_EINVAL when there is none. */
bvox_status bvox__zarr_attrs_parse_level(const char *text, size_t size, const char *name,
                                         int32_t level, bvox__zarr_attrs *out);

/* ---- zarr.c: arrays read box by box and written chunk by chunk ----
 *
 * The interface the out-of-core code builds on; keep it stable. Boxes are
 * in voxels, x/y/z order (bvox's), inside the array's dims. */

/* An array open for reading: a group path (its multiscales level, 0 the
 * finest) or an array folder (.zarray; level must be 0). Only metadata is
 * read here; chunks are decoded by the box reads, only those a box touches.
 * A handle holds one chunk buffer: use one handle per thread. No chunk is
 * cached, so boxes that share chunks (halos) decode them again. */
typedef struct bvox__zarr bvox__zarr;
bvox_status bvox__zarr_open(const char *path, bvox__zarr **out);
bvox_status bvox__zarr_open_level(const char *path, int32_t level, bvox__zarr **out);
void bvox__zarr_close(bvox__zarr *z);
bvox_dims bvox__zarr_dims(const bvox__zarr *z);
/* spacing (the level's scale), origin (its translation) and unit; the rest
 * default */
const bvox_geometry *bvox__zarr_geometry(const bvox__zarr *z);
void bvox__zarr_chunk_shape(const bvox__zarr *z, int32_t chunks[3]); /* x, y, z */
bvox_dtype bvox__zarr_dtype(const bvox__zarr *z);
int32_t bvox__zarr_levels(const bvox__zarr *z); /* datasets of the group (1 for an array) */
/* The box's samples into dst (nx*ny*nz samples of bvox__zarr_dtype, x
 * fastest, the CPU's byte order). */
bvox_status bvox__zarr_read_box_samples(bvox__zarr *z, int32_t x0, int32_t y0, int32_t z0,
                                        int32_t nx, int32_t ny, int32_t nz, void *dst);
/* The box as bits into out, whose dims must be exactly nx, ny, nz, by the
 * read options' rule how (threshold, label, range...; NULL: a voxel is set
 * when its sample is nonzero), as a whole-volume read binarises. Otsu's
 * threshold needs every sample of the volume: refused. out's geometry is
 * left as it is. */
bvox_status bvox__zarr_read_box(bvox__zarr *z, int32_t x0, int32_t y0, int32_t z0, int32_t nx,
                                int32_t ny, int32_t nz, const bvox_binarize *how,
                                bvox_volume *out);

/* A new OME-Zarr group written chunk by chunk into a temporary folder:
 * uint8 0/1, fill_value 0 (a chunk never written reads as zeros).
 * chunks: x, y, z (0: up to 64), capped by the dims; compressor "zlib"
 * (NULL) or "blosc"; geom: spacing and unit (NULL: 1, none); levels: the
 * resolution levels (0: automatic, halving until the smallest side is
 * under one chunk; 1: no pyramid); force: replace bvox's own earlier
 * .zarr (a folder holding anything else is refused). */
typedef struct bvox__zarr_writer bvox__zarr_writer;
bvox_status bvox__zarr_create(const char *path, bvox_dims dims, const int32_t chunks[3],
                              const char *compressor, const bvox_geometry *geom, int32_t levels,
                              bool force, bvox__zarr_writer **out);
void bvox__zarr_writer_chunk_shape(const bvox__zarr_writer *w, int32_t chunks[3]);
/* Write the chunks covered by box placed at (x0, y0, z0) of level 0: x0, y0,
 * z0 multiples of the chunk shape, and each side of box a multiple of it or
 * reaching the array's end. A chunk written twice is rewritten. */
bvox_status bvox__zarr_write_box(bvox__zarr_writer *w, int32_t x0, int32_t y0, int32_t z0,
                                 const bvox_volume *box);
/* Build the coarser levels from level 0 (read back chunk by chunk; a
 * coarse voxel is set when any of its 2x2x2 fine voxels is), write the
 * metadata and put the folder in place. Always frees w. */
bvox_status bvox__zarr_commit(bvox__zarr_writer *w);
/* Remove everything written; frees w. */
void bvox__zarr_abort(bvox__zarr_writer *w);

/* ---- zarr_pyramid.c ---- */
/* dst (dims ceil(src / 2) per axis) = src halved: a voxel is set when any
 * of its (up to) 2x2x2 source voxels is; whole words along z. */
void bvox__downsample_or(const bvox_volume *src, bvox_volume *dst);

#endif
