/*
 * bvox.h — public API of libbvox, a library for binary voxel models.
 *
 * Conventions (see docs/INTERNALS.md):
 *  - Every fallible function returns a bvox_status (BVOX_OK = 0). On failure a
 *    human-readable message is left in a thread-local buffer, read with
 *    bvox_errmsg(), and every out-parameter is set to NULL / left untouched:
 *    nothing leaks.
 *  - Whoever creates an object destroys it; destructors accept NULL.
 *    Out-parameters transfer ownership to the caller; inputs are borrowed for
 *    the duration of the call only.
 *  - Thread safety: there is no hidden mutable global state except the memory
 *    budget and the SIMD level, both set explicitly and read atomically.
 *    Different volumes may be used from different threads at once; functions
 *    taking a const volume may run concurrently on one volume; functions that
 *    modify a volume need exclusive access to it.
 *  - Voxel indices are (x, y, z) with 0 <= x < nx etc. Boxes are half-open.
 */
#ifndef BVOX_H
#define BVOX_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define BVOX_VERSION "0.1.0"

/* ---------------------------------------------------------------- status */

typedef enum bvox_status {
    BVOX_OK = 0,
    BVOX_EINVAL = 1,      /* misuse: bad argument, out-of-range value */
    BVOX_ENOMEM = 2,      /* an allocation failed */
    BVOX_EIO = 3,         /* the operating system refused a read or write */
    BVOX_EFORMAT = 4,     /* corrupt, truncated or unsupported input */
    BVOX_ETOOBIG = 5,     /* dimensions over the limits or the memory budget */
    BVOX_ENOTFOUND = 6,   /* a named file does not exist */
    BVOX_EUNSUPPORTED = 7 /* a feature this build or format does not have */
} bvox_status;

/* Stable token for a status ("BVOX_OK", "BVOX_EFORMAT", ...). Never NULL. */
const char *bvox_status_name(bvox_status status);

/* The message of the last failure in this thread ("" if none). The pointer is
 * valid until the next bvox call in this thread. */
const char *bvox_errmsg(void);

/* The library version, e.g. "0.1.0". */
const char *bvox_version(void);

/* ---------------------------------------------------------- memory budget */

/* The most bytes the library's large buffers (voxel words, decoded images) may
 * hold at once, process-wide. Default: half of physical memory. An allocation
 * that would exceed it fails with BVOX_ETOOBIG and a message naming the size.
 * 0 restores the default. Thread-safe. */
void bvox_set_memory_budget(size_t bytes);
size_t bvox_memory_budget(void);
/* Bytes currently held through the budgeted allocator. */
size_t bvox_memory_in_use(void);

/* Release a buffer the library returned (strings, arrays). Accepts NULL. */
void bvox_free(void *ptr);

/* ------------------------------------------------------------- SIMD level */

typedef enum bvox_simd {
    BVOX_SIMD_AUTO = 0,    /* best the CPU has (the default) */
    BVOX_SIMD_GENERIC = 1, /* portable C, the reference path */
    BVOX_SIMD_AVX2 = 2,
    BVOX_SIMD_AVX512 = 3   /* AVX-512 F + VPOPCNTDQ */
} bvox_simd;

/* Force a code path (tests compare every path with the generic one). Asking
 * for a level the CPU lacks returns BVOX_EUNSUPPORTED. The environment
 * variable BVOX_SIMD=generic|avx2|avx512 sets the initial level. */
bvox_status bvox_simd_set(bvox_simd level);
/* The level in use now (never BVOX_SIMD_AUTO) and its name. */
bvox_simd bvox_simd_active(void);
const char *bvox_simd_name(bvox_simd level);
/* Whether this CPU can run a level. */
int bvox_simd_supported(bvox_simd level);

/* Number of worker threads the library uses for large operations. Default:
 * the online CPU count, or the BVOX_THREADS environment variable. */
void bvox_set_threads(int threads);
int bvox_threads(void);

/* ----------------------------------------------------------- the model */

#define BVOX_MAX_DIM 65535

typedef struct bvox_dims {
    int32_t nx, ny, nz;
} bvox_dims;

/* Half-open box of voxel indices: x0 <= x < x1 etc. */
typedef struct bvox_box {
    int32_t x0, y0, z0, x1, y1, z1;
} bvox_box;

/* Where the voxels are in the world. The physical position of the centre of
 * voxel (i, j, k) is origin + direction * (i*spacing[0], j*spacing[1],
 * k*spacing[2]); direction is a row-major 3x3 matrix whose columns are the
 * unit directions of the x, y and z axes (identity by default). unit names the
 * length unit of spacing and origin ("mm", "um", "" when unknown). */
typedef struct bvox_geometry {
    double spacing[3];
    double origin[3];
    double direction[9];
    char unit[16];
} bvox_geometry;

/* spacing 1, origin 0, identity direction, empty unit. */
bvox_geometry bvox_geometry_default(void);

/* A binary volume: nx*ny*nz bits plus its geometry. Opaque. */
typedef struct bvox_volume bvox_volume;

/* Create an all-zero volume with default geometry. Each dimension must be in
 * 1..BVOX_MAX_DIM and the words must fit in the memory budget.
 * Returns BVOX_EINVAL, BVOX_ETOOBIG or BVOX_ENOMEM on failure.
 * *out is owned by the caller (bvox_volume_destroy). */
bvox_status bvox_volume_create(bvox_dims dims, bvox_volume **out);
void bvox_volume_destroy(bvox_volume *vol);
/* Deep copy, geometry included. */
bvox_status bvox_volume_copy(const bvox_volume *vol, bvox_volume **out);

bvox_dims bvox_volume_dims(const bvox_volume *vol);
const bvox_geometry *bvox_volume_geometry(const bvox_volume *vol);
/* Validates (finite, spacing > 0, NUL-terminated unit) and copies. */
bvox_status bvox_volume_set_geometry(bvox_volume *vol, const bvox_geometry *geom);
/* Convenience: set spacing and unit only (unit may be NULL: unchanged). */
bvox_status bvox_volume_set_spacing(bvox_volume *vol, double sx, double sy, double sz,
                                    const char *unit);

/* Voxel access. get returns 0 outside the volume; set ignores nothing: an
 * out-of-range index is BVOX_EINVAL. value is treated as a boolean. */
int bvox_volume_get(const bvox_volume *vol, int32_t x, int32_t y, int32_t z);
bvox_status bvox_volume_set(bvox_volume *vol, int32_t x, int32_t y, int32_t z, int value);

/* Set (value != 0) or clear every voxel of box, clipped to the volume. */
void bvox_volume_fill_box(bvox_volume *vol, bvox_box box, int value);
/* Set or clear the whole volume. */
void bvox_volume_fill(bvox_volume *vol, int value);

/* New volume holding box of vol (box clipped to the volume; an empty result
 * is BVOX_EINVAL). The origin moves so that voxels keep their world position. */
bvox_status bvox_volume_crop(const bvox_volume *vol, bvox_box box, bvox_volume **out);
/* New volume with `before` zero voxels added before and `after` after on each
 * axis (x, y, z); the origin moves so that voxels keep their world position. */
bvox_status bvox_volume_pad(const bvox_volume *vol, const int32_t before[3],
                            const int32_t after[3], bvox_volume **out);

/* Number of 1-voxels (a popcount over the words). */
int64_t bvox_volume_count(const bvox_volume *vol);
/* Tight bounding box of the 1-voxels; returns 0 and a zero box if empty. */
int bvox_volume_bbox(const bvox_volume *vol, bvox_box *box);
/* 1 if both have the same dimensions and the same voxels (geometry ignored). */
int bvox_volume_equal(const bvox_volume *a, const bvox_volume *b);
/* Checks the invariants (sizes consistent, tail bits beyond nz zero).
 * Returns BVOX_OK or BVOX_EFORMAT with a message naming the first offence. */
bvox_status bvox_volume_check(const bvox_volume *vol);

/* Word-level view, read-only. Voxel (x, y, z) is bit (z % 64) of
 * words[((size_t)y * nx + x) * words_per_column + z / 64]. The bits of the
 * last word of a column beyond nz are zero. */
typedef struct bvox_words_view {
    const uint64_t *words;
    size_t words_per_column;
    size_t word_count;
} bvox_words_view;
bvox_words_view bvox_volume_words(const bvox_volume *vol);

/* ------------------------------------------------------------ set operations */

typedef enum bvox_csg_op {
    BVOX_CSG_UNION = 0,        /* dst |= src */
    BVOX_CSG_INTERSECTION = 1, /* dst &= src */
    BVOX_CSG_DIFFERENCE = 2,   /* dst &= ~src */
    BVOX_CSG_XOR = 3,          /* dst ^= src */
    BVOX_CSG_REPLACE = 4       /* dst = src where src overlaps dst */
} bvox_csg_op;

/* dst = dst OP src, with src's voxel (x, y, z) placed on dst's voxel
 * (x + offset[0], y + offset[1], z + offset[2]); offset may be NULL (zero).
 * Voxels of dst outside src's footprint count as src = 0 (so intersection
 * clears them). The volumes may have any sizes. Works on whole words. */
bvox_status bvox_csg_apply(bvox_volume *dst, bvox_csg_op op, const bvox_volume *src,
                           const int32_t offset[3]);
/* Complement in place; bits beyond nz stay zero. */
void bvox_volume_complement(bvox_volume *vol);
/* Number of 1-voxels in (a AND b), same dimensions required (else -1). */
int64_t bvox_volume_count_and(const bvox_volume *a, const bvox_volume *b);

/* ------------------------------------------------------------------ shapes */

typedef enum bvox_shape_kind {
    BVOX_SHAPE_SPHERE = 0,    /* center, radius */
    BVOX_SHAPE_ELLIPSOID = 1, /* center, semi_axes (along x, y, z) */
    BVOX_SHAPE_BOX = 2,       /* center, semi_axes = half sizes (axis-aligned) */
    BVOX_SHAPE_CYLINDER = 3,  /* center, axis, radius, height (along axis) */
    BVOX_SHAPE_CONE = 4,      /* center of base, axis (towards apex), radius of base, height */
    BVOX_SHAPE_TORUS = 5      /* center, axis, radius (ring), minor_radius (tube) */
} bvox_shape_kind;

/* A primitive in physical units (the volume's spacing and origin; direction
 * is ignored: shapes live in the axis-aligned frame origin + index*spacing).
 * A voxel is inside when its centre is inside (boundary included). */
typedef struct bvox_shape {
    bvox_shape_kind kind;
    double center[3];
    double semi_axes[3];
    double axis[3]; /* need not be unit length; (0,0,0) means +z */
    double radius;
    double minor_radius;
    double height;
} bvox_shape;

/* Combine the shape into vol: UNION adds its voxels, DIFFERENCE removes them,
 * INTERSECTION keeps only them, XOR flips them. BVOX_EINVAL on a bad shape
 * (negative or non-finite sizes). */
bvox_status bvox_shape_draw(bvox_volume *vol, const bvox_shape *shape, bvox_csg_op op);
/* Analytic volume of the shape in physical units cubed (-1 if invalid). */
double bvox_shape_volume(const bvox_shape *shape);
/* Name of a kind ("sphere", ...) and parse of a name (-1 if unknown). */
const char *bvox_shape_kind_name(bvox_shape_kind kind);
int bvox_shape_kind_parse(const char *name);

/* --------------------------------------------------------------------- info */

typedef struct bvox_info {
    bvox_dims dims;
    bvox_geometry geometry;
    int64_t count;      /* 1-voxels */
    double volume;      /* count * spacing product, in unit^3 */
    int empty;          /* 1 if count == 0 (bbox is then all zero) */
    bvox_box bbox;      /* tight, half-open */
} bvox_info;

bvox_status bvox_info_compute(const bvox_volume *vol, bvox_info *info);

/* ------------------------------------------------------------------- files */

/* Element types of gray volumes (NIfTI, TIFF, raw). */
typedef enum bvox_dtype {
    BVOX_DT_U8 = 0, BVOX_DT_I8, BVOX_DT_U16, BVOX_DT_I16, BVOX_DT_U32, BVOX_DT_I32,
    BVOX_DT_U64, BVOX_DT_I64, BVOX_DT_F32, BVOX_DT_F64,
    BVOX_DT_COUNT
} bvox_dtype;
/* "u8", "i16", "f32", ...; parse also accepts "uint8", "int16", "float32", "float64"...
 * parse returns -1 if unknown. */
const char *bvox_dtype_name(bvox_dtype dtype);
int bvox_dtype_parse(const char *name);
size_t bvox_dtype_size(bvox_dtype dtype);

/* How a gray or label volume becomes binary. The value compared is the real
 * value (NIfTI's scl_slope/scl_inter applied). */
typedef enum bvox_binarize_mode {
    BVOX_BIN_NONZERO = 0,   /* value != 0 (the default) */
    BVOX_BIN_THRESHOLD = 1, /* value >= threshold */
    BVOX_BIN_RANGE = 2,     /* lo <= value <= hi */
    BVOX_BIN_OTSU = 3,      /* value above Otsu's threshold */
    BVOX_BIN_LABEL = 4      /* value == label */
} bvox_binarize_mode;

typedef struct bvox_binarize {
    bvox_binarize_mode mode;
    double threshold;
    double lo, hi;
    double label;
} bvox_binarize;

typedef struct bvox_read_opts {
    const char *format;     /* NULL: by extension / content; else "nifti", "binvox",
                               "tiff", "png", "raw" */
    bvox_binarize binarize;
    /* raw only (required there): */
    bvox_dims raw_dims;
    bvox_dtype raw_dtype;
    int raw_big_endian;
    uint64_t raw_offset;    /* bytes to skip (a header) */
    double raw_spacing[3];  /* 0: 1.0 */
    const char *raw_unit;   /* NULL: "" */
} bvox_read_opts;

#define BVOX_READ_OPTS_INIT \
    { NULL, { BVOX_BIN_NONZERO, 0.0, 0.0, 0.0, 0.0 }, { 0, 0, 0 }, BVOX_DT_U8, 0, 0, \
      { 0.0, 0.0, 0.0 }, NULL }

/* Read a file (a folder for PNG slices). opts may be NULL (defaults). The
 * size claimed by a header is checked against the limits and the budget before
 * anything is allocated. */
bvox_status bvox_read(const char *path, const bvox_read_opts *opts, bvox_volume **out);
/* Read from memory; opts->format must name the format unless the content
 * identifies it (NIfTI, gzip-NIfTI, binvox, TIFF, PNG). name is used in
 * messages only (may be NULL). For "png" the buffer is one slice. */
bvox_status bvox_read_memory(const void *data, size_t size, const char *name,
                             const bvox_read_opts *opts, bvox_volume **out);

typedef struct bvox_write_opts {
    const char *format; /* NULL: by extension ("png" for a path ending in '/' or
                           without extension is not guessed: give it) */
    int raw_bits;       /* raw only: 8 (0/1 bytes, default) */
} bvox_write_opts;

#define BVOX_WRITE_OPTS_INIT { NULL, 8 }

/* Write a volume. The output is first written under a temporary name in the
 * target folder, synced and then renamed: a failure leaves no partial file
 * and an existing file unchanged. */
bvox_status bvox_write(const char *path, const bvox_volume *vol, const bvox_write_opts *opts);

/* The format bvox_read / bvox_write would use for a path ("nifti", "binvox",
 * "tiff", "png", "raw") or NULL if the extension is unknown. */
const char *bvox_format_for_path(const char *path);
/* Comma-separated list of format names. */
const char *bvox_format_list(void);

/* ------------------------------------------------------------------- demo */

/* The built-in sample specimen (src/demo.c), an "embryo"-like object made of
 * shapes, as a reconstruction from thick serial sections would give it:
 * 256 x 256 x 128 voxels of 10 x 10 x 25 um. Deterministic. *out is owned by
 * the caller (bvox_volume_destroy). Returns BVOX_ETOOBIG/BVOX_ENOMEM on
 * allocation failure. */
bvox_status bvox_demo_specimen(bvox_volume **out);

/* -------------------------------------------------------------- morphology */

/* Dilation and erosion with the 6-, 18- or 26-neighbourhood (conn), out of
 * place: *out gets the same geometry. Voxels outside the volume count as 0, so
 * erosion removes 1-voxels on the border (as scipy.ndimage does by default).
 * Works on whole words: shifts along z within a word, whole-column ORs (ANDs)
 * along x and whole-row ones along y. BVOX_EINVAL for another conn. */
bvox_status bvox_morph_dilate(const bvox_volume *in, int conn, bvox_volume **out);
bvox_status bvox_morph_erode(const bvox_volume *in, int conn, bvox_volume **out);
/* With a ball (an ellipsoid in voxels when the voxels are anisotropic) of the
 * given radius in physical units; a voxel offset (i, j, k) is in the ball when
 * (i*sx)^2 + (j*sy)^2 + (k*sz)^2 <= radius^2. */
bvox_status bvox_morph_dilate_ball(const bvox_volume *in, double radius, bvox_volume **out);
bvox_status bvox_morph_erode_ball(const bvox_volume *in, double radius, bvox_volume **out);

/* ------------------------------------------------------ connected components */

typedef struct bvox_component {
    int64_t voxels;
    double volume;  /* voxels * voxel volume, in unit^3 */
    bvox_box bbox;  /* tight, half-open */
} bvox_component;

/* The components of a volume: found by labelling runs of set bits along z
 * (never single voxels) with a union-find over overlapping runs of
 * neighbouring columns. Opaque; destroy with bvox_components_destroy. */
typedef struct bvox_components bvox_components;

/* conn is 6, 18 or 26. Components are sorted largest first (ties: the one
 * whose first voxel comes first in column order). */
bvox_status bvox_components_find(const bvox_volume *vol, int conn, bvox_components **out);
void bvox_components_destroy(bvox_components *comps);
int64_t bvox_components_count(const bvox_components *comps);
/* Component i (0 = largest), or NULL when out of range. */
const bvox_component *bvox_components_get(const bvox_components *comps, int64_t i);
/* A volume (same dims and geometry as the one labelled) holding the n
 * largest components (all if n >= count). */
bvox_status bvox_components_keep(const bvox_components *comps, int64_t n, bvox_volume **out);
/* Labels as x-fastest uint32 samples (nx*ny*nz of them): 0 background,
 * i + 1 for component i. dst must hold nx*ny*nz values. */
void bvox_components_labels(const bvox_components *comps, uint32_t *dst);
/* Index (0 = largest) of the component holding voxel (x, y, z), or -1 if
 * that voxel is 0 or outside. */
int64_t bvox_components_index_at(const bvox_components *comps, int32_t x, int32_t y, int32_t z);
/* A volume holding the components for which keep(component, index, ctx)
 * returns non-zero. */
bvox_status bvox_components_keep_if(const bvox_components *comps,
                                    int (*keep)(const bvox_component *c, int64_t index,
                                                void *ctx),
                                    void *ctx, bvox_volume **out);

/* -------------------------------------------------- derived morphology */

/* Opening (erode then dilate) and closing (dilate then erode). radius > 0
 * uses a ball of that physical radius, otherwise the conn neighbourhood.
 * Closing works on a padded copy so that the volume's border does not eat
 * into the object (ITK's "safe border"); opening erodes at the border. */
bvox_status bvox_morph_open(const bvox_volume *in, int conn, double radius, bvox_volume **out);
bvox_status bvox_morph_close(const bvox_volume *in, int conn, double radius, bvox_volume **out);
/* Fill cavities: 0-voxels not 6-connected to the border become 1. */
bvox_status bvox_morph_fill_holes(const bvox_volume *in, bvox_volume **out);
/* The shell of the object: its voxels within `thickness` (physical units) of
 * the background, i.e. in minus its erosion by a ball of that radius; the
 * outside of the volume counts as background. */
bvox_status bvox_morph_hollow(const bvox_volume *in, double thickness, bvox_volume **out);
/* Remove components (conn-connected) of fewer than min_voxels voxels. */
bvox_status bvox_morph_remove_islands(const bvox_volume *in, int conn, int64_t min_voxels,
                                      bvox_volume **out);

#ifdef __cplusplus
}
#endif

#endif /* BVOX_H */
