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
 * false when there is no scale transform. */
typedef struct bvox__zarr_attrs {
    char path[256];
    double spacing[3]; /* x, y, z */
    bool have_scale;
    char unit[16];
} bvox__zarr_attrs;
bvox_status bvox__zarr_attrs_parse(const char *text, size_t size, const char *name,
                                   bvox__zarr_attrs *out);

/* ---- zarr.c: reading boxes and writing slab by slab (out of core) ---- */

/* An opened array: metadata parsed and checked, nothing else read. */
typedef struct bvox__zarr_in {
    char name[4200];    /* the user's path, for messages */
    char arr[4200];     /* the array folder */
    bvox__zarr_meta m;
    bvox__zarr_attrs attrs;
    bvox_dims dims;
    bvox_geometry geom; /* spacing and unit from the multiscales metadata */
    bool swap;          /* samples in the other byte order than the CPU's */
    uint8_t fill[8];    /* the fill value as one sample (m.has_fill) */
} bvox__zarr_in;
bvox_status bvox__zarr_in_open(const char *path, bvox__zarr_in *zi);
/* The voxels of box (inside the array) binarised by how (NULL: nonzero),
 * reading only the chunks the box touches, one row of chunks along z at a
 * time. Otsu's threshold needs the whole array (BVOX_EUNSUPPORTED for a
 * smaller box). The volume gets the array's spacing and unit, origin 0. */
bvox_status bvox__zarr_in_read_box(const bvox__zarr_in *zi, bvox_box box,
                                   const bvox_binarize *how, bvox_volume **out);

/* A .zarr folder written in slabs along z: open writes the metadata into a
 * temporary folder, each put adds the next slab (whole rows of chunks along z:
 * z_at and the slab's depth multiples of the chunk depth, except the last),
 * close(keep) renames the folder into place when keep and *st is BVOX_OK,
 * else removes it (*st gets the commit's status). */
typedef struct bvox__zarr_out bvox__zarr_out;
bvox_status bvox__zarr_out_open(const char *path, bvox_dims dims, const bvox_geometry *geom,
                                const bvox_write_opts *opts, bvox__zarr_out **out);
bvox_status bvox__zarr_out_put(bvox__zarr_out *w, const bvox_volume *slab, int32_t z_at);
void bvox__zarr_out_close(bvox__zarr_out *w, bool keep, bvox_status *st);
/* The chunk depth along z (slabs are multiples of it). */
int32_t bvox__zarr_out_chunk_z(const bvox__zarr_out *w);
/* The bytes its buffers hold (for the out-of-core planning). */
size_t bvox__zarr_out_bytes(const bvox__zarr_out *w);

#endif
