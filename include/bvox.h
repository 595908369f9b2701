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

/* Warnings: the library never prints. Where it makes an assumption the user
 * should know about (a missing voxel size taken as 1, an SVG element skipped,
 * a self-crossing contour repaired), it formats one line without a trailing
 * newline ("section 3: contour 2 crosses itself at (10.5, 4); filled by ...")
 * and passes it to the handler set here; with no handler the warning is
 * dropped. The handler belongs to the calling thread (a thread-local setting:
 * set it in each thread that wants warnings); warnings are raised only in the
 * thread that called the library function. fn NULL removes the handler. */
typedef void (*bvox_warning_fn)(const char *message, void *user);
void bvox_set_warning_handler(bvox_warning_fn fn, void *user);
/* Number of warnings raised in this thread since it started (handler or not):
 * lets a caller tell whether a call warned. */
uint64_t bvox_warning_count(void);

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
    /* The space the origin and direction are in, as NIfTI's xform codes: 0
     * unknown (bvox writes scanner), 1 scanner, 2 aligned, 3 Talairach, 4
     * MNI-152. Read from NIfTI's sform (else qform) code and written back, so
     * an MNI atlas stays MNI through convert; other formats keep 0. */
    int32_t space;
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
                               "tiff", "png", "raw", "zarr" */
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
    int32_t chunks[3];  /* zarr only: chunk shape x, y, z (0: up to 64 per axis) */
    const char *compressor; /* zarr only: "zlib" (NULL: the default) or "blosc" */
} bvox_write_opts;

#define BVOX_WRITE_OPTS_INIT { NULL, 8, { 0, 0, 0 }, NULL }

/* Write a volume. The output is first written under a temporary name in the
 * target folder, synced and then renamed: a failure leaves no partial file
 * and an existing file unchanged. */
bvox_status bvox_write(const char *path, const bvox_volume *vol, const bvox_write_opts *opts);
/* Write size bytes as the file path the same way (temporary file in the
 * target folder, fsync, rename): for reports and other small outputs. */
bvox_status bvox_write_file_atomic(const char *path, const void *data, size_t size);

/* Write a label volume (e.g. from bvox_components_labels) as NIfTI-1, .nii
 * or .nii.gz by the path's suffix: labels holds nx*ny*nz values, x fastest
 * then y then z, for the dimensions and geometry of `like` (whose voxels are
 * not used; each dimension at most 32767). Samples are uint16 when the
 * largest label is at most 65535, else uint32; the header carries NIfTI's
 * label intent and the display range 0..largest label. Read one label back
 * as a binary volume with bvox_read and BVOX_BIN_LABEL. Written like
 * bvox_write (temporary file, renamed on success). BVOX_EUNSUPPORTED for a
 * dimension over 32767 or another extension, BVOX_EIO, BVOX_ETOOBIG. */
bvox_status bvox_write_labels_nifti(const char *path, const bvox_volume *like,
                                    const uint32_t *labels);

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

/* ---------------------------------------------------------------- measures */

/* Geometric and topological measures of the 1-voxels of a volume, in the
 * physical units of its geometry (spacing, unit; anisotropic voxels handled
 * everywhere). Positions are in the axis-aligned frame of the shapes:
 * voxel (i, j, k) has its centre at origin + (i*sx, j*sy, k*sz); direction is
 * not applied (multiply by it to get world coordinates; scalar measures do not
 * change). Each voxel is a point mass at its centre for the moments (as in
 * ITK and scikit-image) and a closed box sx*sy*sz for areas and topology; the
 * outside of the volume is background. All zero for an empty volume (axes:
 * the identity). */
typedef struct bvox_measures {
    int64_t count;          /* 1-voxels */
    double volume;          /* count * sx*sy*sz */
    bvox_box bbox;          /* tight, half-open, voxel indices */
    double extent_min[3];   /* physical extent of bbox: the outer faces of its */
    double extent_max[3];   /* voxels, origin + (index -+ 1/2) * spacing */
    /* Faces between a 1-voxel and a 0-voxel (or the outside), perpendicular to
     * x, y and z; area_faces = faces[0]*sy*sz + faces[1]*sx*sz + faces[2]*sx*sy,
     * the area of the voxel boundary (exact for the blocky object, too large
     * by up to 73% for an oblique smooth surface). */
    int64_t faces[3];
    double area_faces;
    /* Smooth surface area estimate: discrete Crofton formula over the 13
     * directions of the 2x2x2 neighbourhood, direction weights from the
     * spherical Voronoi cells of the voxel spacing (Lehmann and Legland; ITK's
     * label perimeter). Unbiased for isotropically oriented surfaces (a
     * sphere of radius 50 voxels: within 0.2%, cubic or 1:1:5 voxels); a
     * plane is off by -7.3%..+2.3% depending on its orientation with cubic
     * voxels (axis-aligned planes are the worst), -14%..+10% with 1:1:2.5. */
    double area;
    double centroid[3];
    double covariance[9];   /* central second moments sum((p-c)(p-c)^T)/count,
                               row-major, unit^2 */
    double inertia[9];      /* inertia tensor about the centroid for density 1
                               (mass = volume): volume * (trace(C) I - C), unit^5 */
    /* Eigen-decomposition of the covariance (Jacobi): rows of principal_axes
     * are unit vectors (largest component positive), principal_moments the
     * variances along them, largest first; principal_inertia the moments of
     * inertia about the same axes (so smallest first). */
    double principal_axes[9];
    double principal_moments[3];
    double principal_inertia[3];
    double equivalent_diameter; /* of the sphere of the same volume: (6V/pi)^(1/3) */
    /* pi^(1/3) (6V)^(2/3) / area: 1 for a ball, less otherwise. Never above 1:
     * the smooth area estimate is within about 0.5 % on round objects, so a
     * ball may come out a little above 1 and is reported as 1. NaN (JSON
     * null) below BVOX_SPHERICITY_MIN_VOXELS voxels, where the estimate errs
     * by 2-17 % (a 2x2x2 cube would read 1.17); 0 for an empty volume. */
    double sphericity;
    /* Topology with 26-connectivity for the object and 6-connectivity for the
     * background (scikit-image's euler_number(connectivity=3), the Euler
     * characteristic of the union of the closed voxel cubes):
     * euler = components - tunnels + cavities. */
    int64_t euler;
    int64_t components;     /* 26-connected components */
    int64_t cavities;       /* 6-connected background components not touching
                               the border of the volume */
    int64_t tunnels;        /* components + cavities - euler (the genus for
                               one component without cavities) */
    int64_t cavities_26;    /* the same cavities counted with 26-connectivity for the
                               background (the pairing of a 6-connected object): at
                               most cavities, since diagonal steps join more */
} bvox_measures;

/* Fewer voxels than this: sphericity is NaN (not estimated). */
#define BVOX_SPHERICITY_MIN_VOXELS 1000

/* All the measures of vol. Runs on whole words (split over the worker
 * threads) plus two labellings (the object, the complement) for the
 * components and the cavities; the complement takes a temporary copy of the
 * volume's size. Returns BVOX_ENOMEM / BVOX_ETOOBIG (the copy over the
 * budget). Thread-safe on a const volume. */
bvox_status bvox_measure(const bvox_volume *vol, bvox_measures *out);

/* The same measures for every conn-connected component (conn 6, 18 or 26),
 * in the order of bvox_components_find (largest first). Each component is
 * measured alone, cut out to its bounding box: bbox is in vol's voxel
 * indices, components is 1, cavities counts the cavities of that component.
 * *per_component (release with bvox_free) holds *n entries; NULL and 0 for an
 * empty volume. BVOX_EINVAL for another conn, BVOX_ENOMEM / BVOX_ETOOBIG. */
bvox_status bvox_measure_components(const bvox_volume *vol, int conn,
                                    bvox_measures **per_component, int64_t *n);

/* ------------------------------------------------------------------ render */

/* The display pipeline of the paper (section 4.2), in stages with their own
 * data: cast (volume -> pre-image: depth and normal code per pixel), shade
 * (pre-image + 256-entry lookup table -> image), image operations (zoom, pan,
 * convolution, colour maps) and PNG output. Changing the light rebuilds a
 * table and remaps the pre-image: it never re-casts. Everything here is
 * thread-safe on distinct outputs; inputs are only read. */

/* An image: 8-bit (pixels) or 16-bit (pixels16, native byte order) samples,
 * 1 (gray) or 3 (RGB, interleaved) channels, row-major, top row first, rows
 * not padded. Made and released by the library (bvox_image_destroy); samples
 * may be written, the other fields must not be changed. */
typedef struct bvox_image {
    int32_t width, height;
    int32_t channels;   /* 1 or 3 */
    int32_t bits;       /* 8 or 16 */
    uint8_t *pixels;    /* bits 8: width*height*channels samples; else NULL */
    uint16_t *pixels16; /* bits 16: width*height*channels samples; else NULL */
} bvox_image;

#define BVOX_IMAGE_MAX_DIM (1 << 20)

/* A zero image. width, height in 1..BVOX_IMAGE_MAX_DIM, channels 1 or 3, bits
 * 8 or 16 (else BVOX_EINVAL); BVOX_ETOOBIG/BVOX_ENOMEM over the budget. */
bvox_status bvox_image_create(int32_t width, int32_t height, int32_t channels, int32_t bits,
                              bvox_image **out);
void bvox_image_destroy(bvox_image *img);
bvox_status bvox_image_copy(const bvox_image *img, bvox_image **out);
/* Write as PNG (8/16-bit gray or RGB) through a temporary file renamed on
 * success: a failure leaves no partial file. */
bvox_status bvox_image_write_png(const bvox_image *img, const char *path);
/* Read a PNG: gray or RGB, 8 or 16 bits as stored (low bit depths expanded to
 * 8, palette to RGB, alpha dropped). BVOX_EFORMAT for a corrupt file. */
bvox_status bvox_image_read_png(const char *path, bvox_image **out);
bvox_status bvox_image_read_png_memory(const void *data, size_t size, const char *name,
                                       bvox_image **out);

/* The six axis views. Axes are the volume's index axes; +z looks along +z
 * (rays enter at z = 0). Image axes are the two other index axes in
 * increasing order, the same for both signs: for +-z column = x, row = y; for
 * +-x column = y, row = z; for +-y column = x, row = z. So pixel (c, r) of +v
 * and -v is the same ray seen from both ends (-v is +v seen through the
 * volume, a mirror image). */
typedef enum bvox_view {
    BVOX_VIEW_POS_X = 0, BVOX_VIEW_NEG_X = 1,
    BVOX_VIEW_POS_Y = 2, BVOX_VIEW_NEG_Y = 3,
    BVOX_VIEW_POS_Z = 4, BVOX_VIEW_NEG_Z = 5
} bvox_view;
/* "+x", "-x", "+y", "-y", "+z", "-z"; parse also takes "x" for "+x"; -1 if
 * unknown. */
const char *bvox_view_name(bvox_view view);
int bvox_view_parse(const char *name);

/* Normal codes. A hit voxel's normal has a component in {-1, 0, 1} per axis,
 * pointing away from its 1-neighbours: n_x = (voxel at x-1) - (voxel at x+1),
 * so a component is 0 when both face neighbours along that axis are equal
 * (outside the volume counts as 0). Index = (n_x+1)*9 + (n_y+1)*3 + (n_z+1),
 * 0..26 (13: no normal). code = index | cue << 5, cue = depth * 8 /
 * depth_range (0 nearest .. 7 farthest); background pixels have code 31. */
#define BVOX_NORMAL_NONE 13
#define BVOX_CODE_BACKGROUND 31
#define BVOX_CODE_NORMAL(code) ((code) & 31)
#define BVOX_CODE_CUE(code) ((code) >> 5)

/* A pre-image: per pixel the depth of the first 1-voxel and its code. Made
 * and released by the library (bvox_preimage_destroy); depth and code may be
 * edited in place, the other fields must not be changed. A caller may also
 * fill one over its own arrays (a crop of a library-made pre-image, as the
 * viewer's pane) to pass to the shading calls; it then frees them itself. */
typedef struct bvox_preimage {
    int32_t width, height;
    int32_t *depth;       /* width*height, row-major; -1 for background */
    uint8_t *code;        /* width*height */
    int32_t depth_range;  /* depths are 0 .. depth_range-1 */
    double depth_step;    /* physical length of one depth step */
    double pixel_size[2]; /* physical width and height of a pixel */
    /* The eye frame in the volume's axis-aligned physical frame: unit rows
     * right (image +column), down (image +row) and view (into the screen). */
    double eye[9];
    /* Where pixel (c, r) at depth d is, in the same frame (voxel (i, j, k) at
     * (i sx, j sy, k sz)): origin + c pixel_size[0] right + r pixel_size[1]
     * down + d depth_step view. */
    double origin[3];
    double spacing[3];    /* the volume's voxel size (normals use it) */
} bvox_preimage;

/* Cast an axis view: one pixel per voxel column, depth = voxel steps from
 * the entry face. Rays along z test 64 voxels per word (count trailing /
 * leading zeros); along x and y a sweep advances 64 parallel rays per word.
 * *out is owned by the caller (bvox_preimage_destroy). */
bvox_status bvox_cast_axis(const bvox_volume *vol, bvox_view view, bvox_preimage **out);
void bvox_preimage_destroy(bvox_preimage *pre);
/* The depth map as a 16-bit gray image: depth, 65535 for background. */
bvox_status bvox_preimage_depth_image(const bvox_preimage *pre, bvox_image **out);

/* A lookup table from pre-image code to gray level. */
typedef struct bvox_lut {
    uint8_t value[256];
} bvox_lut;

/* Depth shading: intensity from depth t in 0..1 (0 nearest). Linear: near +
 * (far - near) t. Exponential: far + (near - far) exp(-decay t). */
typedef enum bvox_depth_curve { BVOX_DEPTH_LINEAR = 0, BVOX_DEPTH_EXP = 1 } bvox_depth_curve;
typedef struct bvox_depth_shading {
    bvox_depth_curve curve;
    double near_value, far_value; /* 0..255 */
    double decay;                 /* exponential only, > 0 */
    uint8_t background;
} bvox_depth_shading;
#define BVOX_DEPTH_SHADING_INIT { BVOX_DEPTH_LINEAR, 255.0, 40.0, 3.0, 0 }

/* Lighting (Phong) in the eye frame of a pre-image. The light comes from
 * azimuth degrees in the image plane (0 from the right, 90 from the top of
 * the image) at elevation degrees towards the viewer (90: from the viewer).
 * intensity = 255 (ambient + diffuse max(0, N.L) + specular max(0, R.V)^
 * shininess) (1 - depth_cue * cue / 7), clamped; V points to the viewer. */
typedef struct bvox_light {
    double azimuth, elevation;
    double ambient, diffuse, specular, shininess;
    double depth_cue; /* 0..1 */
    uint8_t background;
} bvox_light;
#define BVOX_LIGHT_INIT { 135.0, 45.0, 0.12, 0.78, 0.25, 16.0, 0.0, 0 }

/* Table for the 3-bit depth cue of the codes (the normal bits ignored). */
bvox_status bvox_lut_depth(const bvox_depth_shading *shading, bvox_lut *lut);
/* Table for binary gradient shading of pre's codes: the 27 normals (scaled by
 * 1/spacing, turned into the eye frame, normalised; "no normal" faces the
 * viewer) lit by light. Cheap (256 entries): rebuild it when the light moves. */
bvox_status bvox_lut_light(const bvox_preimage *pre, const bvox_light *light, bvox_lut *lut);
/* image = lut[code], an 8-bit gray image of pre's size. shade_into writes an
 * existing image of that size (1 channel, 8 bits), allocating nothing. */
bvox_status bvox_shade(const bvox_preimage *pre, const bvox_lut *lut, bvox_image **out);
bvox_status bvox_shade_into(const bvox_preimage *pre, const bvox_lut *lut, bvox_image *img);
/* Depth shading from the full depth (not the 3-bit cue): a table of
 * depth_range entries. */
bvox_status bvox_shade_depth(const bvox_preimage *pre, const bvox_depth_shading *shading,
                             bvox_image **out);

/* Gradient shading from the depth map (Gordon and Reynolds): the surface
 * normal from depth differences between neighbouring pixels, in physical
 * units (pixel_size, depth_step), lit like bvox_lut_light. Central: (d(x+1) -
 * d(x-1)) / 2; Sobel: the 3x3 Sobel pair / 8. A background neighbour is
 * replaced by the centre pixel (a one-sided difference). */
typedef enum bvox_gradient { BVOX_GRADIENT_CENTRAL = 0, BVOX_GRADIENT_SOBEL = 1 } bvox_gradient;
bvox_status bvox_shade_gradient(const bvox_preimage *pre, bvox_gradient op,
                                const bvox_light *light, bvox_image **out);

/* Colour maps for 8-bit gray images -> 8-bit RGB. */
typedef enum bvox_colormap {
    BVOX_CMAP_GRAY = 0, BVOX_CMAP_BONE = 1, BVOX_CMAP_HOT = 2, BVOX_CMAP_COPPER = 3,
    BVOX_CMAP_COOL = 4
} bvox_colormap;
const char *bvox_colormap_name(bvox_colormap map); /* "gray", "bone", ... */
int bvox_colormap_parse(const char *name);         /* -1 if unknown */
bvox_status bvox_image_colormap(const bvox_image *in, bvox_colormap map, bvox_image **out);

/* Image operations (8 or 16 bits, any channels, unless said). Zoom by pixel
 * replication, factor 1, 2, 4 or 8. */
bvox_status bvox_image_zoom(const bvox_image *in, int factor, bvox_image **out);
/* Zoom x2 with pixel averaging (the paper's Figure 5): output (2i, 2j) =
 * p(i, j); (2i, 2j+1) the average of p(i, j), p(i, j+1); (2i+1, 2j) of p(i, j),
 * p(i+1, j); (2i+1, 2j+1) of the four; averages rounded half up, zeros beyond
 * the edge. */
bvox_status bvox_image_zoom2_average(const bvox_image *in, bvox_image **out);
/* Translate by (dx, dy) pixels: out(x + dx, y + dy) = in(x, y), zeros where
 * nothing lands; same size. */
bvox_status bvox_image_pan(const bvox_image *in, int32_t dx, int32_t dy, bvox_image **out);

/* 3x3 convolution of 8-bit images (each channel), the edge pixels repeated
 * beyond the border: out = clamp(round_half_up(sum(k * p) / divisor) + bias,
 * 0, 255); kernel row-major, kernel[4] on the centre; divisor != 0. */
bvox_status bvox_image_convolve(const bvox_image *in, const int32_t kernel[9], int32_t divisor,
                                int32_t bias, bvox_image **out);
typedef enum bvox_filter {
    BVOX_FILTER_HIGHPASS = 0,  /* -1 -1 -1 / -1 9 -1 / -1 -1 -1 (sharpen) */
    BVOX_FILTER_SMOOTH = 1,    /* 1 2 1 / 2 4 2 / 1 2 1, divisor 16 */
    BVOX_FILTER_LAPLACIAN = 2, /* 0 -1 0 / -1 4 -1 / 0 -1 0 */
    BVOX_FILTER_SOBEL = 3      /* round(sqrt(gx^2 + gy^2)), saturated */
} bvox_filter;
const char *bvox_filter_name(bvox_filter filter);
int bvox_filter_parse(const char *name);
bvox_status bvox_image_filter(const bvox_image *in, bvox_filter filter, bvox_image **out);

/* Arbitrary parallel projections. The view is a rotation: with use_matrix 0,
 * from azimuth and elevation in degrees: view = (sin az cos el, sin el,
 * cos az cos el), right = (cos az, 0, -sin az), down = view x right. So
 * azimuth 0, elevation 0 is the +z view (right = +x, down = +y); azimuth 90
 * looks along +x; elevation 90 looks down along +y from the top of the +z
 * image. With use_matrix 1, matrix holds the rows right, down, view
 * (orthonormalised by the library, in that order). Voxels are boxes
 * of the volume's spacing, so thick sections look thick. The image is width x
 * height (0: 512) pixels; scale is pixels per physical unit, 0 to fit the
 * bounding sphere of the object's bounding box (no rotation clips it). Depth
 * is measured in pixel units from the front of that sphere. */
typedef struct bvox_projection {
    double azimuth, elevation;
    int use_matrix;
    double matrix[9];
    int32_t width, height;
    double scale;
} bvox_projection;
#define BVOX_PROJECTION_INIT { 0.0, 0.0, 0, { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, 0, 0, 0.0 }

/* The boundary voxels of a volume (those with a 0 face neighbour), with their
 * normal codes: built once (word-wise), then cast from any direction by
 * splatting into a z-buffer, fast enough to turn the object interactively. */
typedef struct bvox_surface bvox_surface;
bvox_status bvox_surface_build(const bvox_volume *vol, bvox_surface **out);
void bvox_surface_destroy(bvox_surface *surf);
int64_t bvox_surface_count(const bvox_surface *surf);
/* After vol (the volume surf was built from) changed only inside box
 * (half-open): recompute the boundary voxels of the box grown by one voxel,
 * keep the rest. The result is exactly what bvox_surface_build(vol) makes,
 * at the cost of the box plus one pass over the entries (interactive edits).
 * On failure surf is unchanged. BVOX_EINVAL for other dimensions. */
bvox_status bvox_surface_update(bvox_surface *surf, const bvox_volume *vol, bvox_box box);
/* The bounding box of the surface's voxels (the object's); 0 and a zero box
 * when empty. */
int bvox_surface_bbox(const bvox_surface *surf, bvox_box *box);
/* Cast a parallel projection of the prepared surface. Each pixel gets the
 * exact first voxel box its centre ray meets (the ray clipped against each
 * candidate box; equal depths go to the smaller neighbour code, so the
 * result does not depend on the thread count). Thread-safe on one surface. */
bvox_status bvox_surface_cast(const bvox_surface *surf, const bvox_projection *proj,
                              bvox_preimage **out);
/* Convenience: build the surface, cast, destroy. */
bvox_status bvox_cast_projection(const bvox_volume *vol, const bvox_projection *proj,
                                 bvox_preimage **out);

/* ------------------------------------------------- render: the pictures */

/* Picture 4 of the paper: the data set as the frame buffer held it. Slices
 * are packed 8 to a byte, as the volume packs them 64 to a word: section s
 * holds slices 8s .. 8s+7, slice 8s+b in bit b of its byte pixels, and
 * pixel (x, y) of section s is the byte of voxel column (x, y). Sections are
 * laid out row by row, section s at grid cell (s % columns, s / columns), so
 * a 128^3 volume gives the paper's 512 x 512 image of 4 x 4 sections of
 * 128 x 128. Slices beyond nz read as 0; unused cells are 0.
 * The bytes are shown through a 256-entry table, as the paper's output LUT
 * enabled or disabled bit planes: planes selects the slices shown (bit b:
 * slice 8s+b of every section) and display maps byte & planes to gray. */
typedef enum bvox_mosaic_display {
    BVOX_MOSAIC_COUNT = 0, /* 255 * set selected planes / selected planes, rounded
                              (the default: an outline shows how the 8 slices differ) */
    BVOX_MOSAIC_ANY = 1,   /* 255 where any selected plane is set, else 0 */
    BVOX_MOSAIC_BYTES = 2  /* byte & planes itself: the frame buffer as stored */
} bvox_mosaic_display;
typedef struct bvox_mosaic_opts {
    uint8_t planes;              /* 0xff: all 8 slices of each section */
    bvox_mosaic_display display;
    int32_t columns;             /* sections per row; 0: ceil(sqrt(sections)) */
} bvox_mosaic_opts;
#define BVOX_MOSAIC_OPTS_INIT { 0xff, BVOX_MOSAIC_COUNT, 0 }
/* An 8-bit gray image of columns*nx x rows*ny pixels (rows = ceil(sections /
 * columns)), made from whole words (8 bytes of a column's word at a time).
 * opts may be NULL (defaults). BVOX_EINVAL for a bad option or an image over
 * BVOX_IMAGE_MAX_DIM, BVOX_ETOOBIG/BVOX_ENOMEM. *out owned by the caller. */
bvox_status bvox_mosaic(const bvox_volume *vol, const bvox_mosaic_opts *opts, bvox_image **out);
/* The display table of a plane mask and mode (byte -> gray). */
bvox_status bvox_mosaic_lut(uint8_t planes, bvox_mosaic_display display, bvox_lut *lut);
const char *bvox_mosaic_display_name(bvox_mosaic_display display); /* "count", "any", "bytes" */
int bvox_mosaic_display_parse(const char *name);                    /* -1 if unknown */

/* How bvox_render shades a pre-image. */
typedef enum bvox_shade_mode {
    BVOX_SHADE_DEPTH = 0,       /* depth shading from the full depth (opts.depth) */
    BVOX_SHADE_BINARY = 1,      /* binary gradient shading of the normal codes (opts.light) */
    BVOX_SHADE_GRADIENT = 2,    /* gradient shading of the depth map (Sobel, opts.light) */
    BVOX_SHADE_BINARY_DEPTH = 3 /* binary gradient times a depth cue from the full depth:
                                   1 - k t, t = depth / (depth_range - 1), k =
                                   light.depth_cue, or 0.5 when that is 0 */
} bvox_shade_mode;
const char *bvox_shade_mode_name(bvox_shade_mode mode); /* "depth", "binary", "gradient",
                                                           "binary+depth" */
int bvox_shade_mode_parse(const char *name);            /* -1 if unknown */

/* Shading codes and colour tables: the paper's split kept for interactive
 * display. A pre-image is turned once into a 16-bit shading code per pixel
 * (bvox_shade_codes, for one mode); a colour table of BVOX_SCODES entries
 * (bvox_shade_table_build) maps codes to RGB (bvox_shade_table_apply). A new
 * light, depth curve, tint or colour rebuilds only the table (8193 entries),
 * never the codes; a new view or mode remakes the codes. The codes by mode:
 *   depth:        d * 255 / (depth_range - 1), 0..255 (256 depth levels)
 *   binary:       the pre-image's code (normal index | 3-bit cue << 5)
 *   gradient:     the Sobel normal of the depth map (physical units, as
 *                 bvox_shade_gradient), its right and up components (-1..1)
 *                 in 64 bins each: bx + 64 by, 0..4095
 *   binary+depth: normal index | min(15, d * 16 / depth_range) << 5, 0..511;
 *                 the table darkens level t by 1 - k (t + 0.5) / 16, k =
 *                 light.depth_cue or 0.5 when that is 0
 *   cut face:     BVOX_SCODE_CUT | d * 255 / (depth_range - 1): pixels whose
 *                 entry point lies within half a voxel's extent plus half a
 *                 depth step of the plane, counted into the kept side (as
 *                 bvox_render's projections: every face the cut exposed,
 *                 and a thin rim of the old surface beside it); lit flat by the plane's normal (depth mode:
 *                 its depth shade, binary+depth: times its depth factor) and
 *                 tinted with cut_color
 *   background:   BVOX_SCODE_BACKGROUND
 * Later modes and per-object colours plug in here: a mode adds its code
 * layout below BVOX_SCODE_CUT and its table entries; an object's colour is
 * `color` (one table per colour; white keeps the gray shades exactly). */
#define BVOX_SCODE_CUT 4096
#define BVOX_SCODE_BACKGROUND 8192
#define BVOX_SCODES 8193
typedef struct bvox_shade_opts {
    bvox_shade_mode mode;
    bvox_light light;           /* binary, gradient, binary+depth, cut face */
    bvox_depth_shading depth;   /* depth mode (its background is not used) */
    int cut;                    /* 1: mark and light the cut face */
    /* The cut plane m . p + e = 0, p in the pre-image's frame (voxel (i, j, k)
     * at (i sx, j sy, k sz)), m = plane[0..2] (not zero), e = plane[3]; the
     * kept side is m . p + e >= 0. */
    double plane[4];
    uint8_t cut_color[3];       /* tint of the cut face */
    uint8_t color[3];           /* the object's colour: shade * color / 255 */
    uint8_t background[3];
} bvox_shade_opts;
#define BVOX_SHADE_OPTS_INIT                                                           \
    { BVOX_SHADE_BINARY_DEPTH, BVOX_LIGHT_INIT, BVOX_DEPTH_SHADING_INIT, 0,            \
      { 0, 0, 1, 0 }, { 255, 176, 96 }, { 255, 255, 255 }, { 0, 0, 0 } }
/* RGB per shading code. */
typedef struct bvox_shade_table {
    uint8_t rgb[BVOX_SCODES][3];
} bvox_shade_table;
/* The shading codes of pre for opts->mode (and the cut face when opts->cut):
 * codes has width * height entries, row-major. BVOX_EINVAL for a missing
 * input, an unknown mode or a bad light or plane. Thread-safe. */
bvox_status bvox_shade_codes(const bvox_preimage *pre, const bvox_shade_opts *opts,
                             uint16_t *codes);
/* The colour table of opts for codes made from a pre-image with pre's eye
 * frame and spacing (only those fields of pre are read). Cheap (8193
 * entries, the 27 normals and 4096 gradient bins lit once): rebuild it when
 * the light moves. BVOX_EINVAL for a missing input or bad options. */
bvox_status bvox_shade_table_build(const bvox_preimage *pre, const bvox_shade_opts *opts,
                                   bvox_shade_table *table);
/* rgb (3 bytes a pixel, rows rgb_stride bytes apart) = table[codes] for a
 * width x height block of codes (rows code_stride entries apart); a code
 * beyond BVOX_SCODE_BACKGROUND shows as the background. Allocates nothing. */
void bvox_shade_table_apply(const bvox_shade_table *table, const uint16_t *codes,
                            int32_t width, int32_t height, size_t code_stride, uint8_t *rgb,
                            size_t rgb_stride);

typedef enum bvox_stereo {
    BVOX_STEREO_NONE = 0,
    BVOX_STEREO_SBS = 1,     /* left eye's image on the left (parallel viewing) */
    BVOX_STEREO_ANAGLYPH = 2 /* RGB: red = left eye, green and blue = right eye */
} bvox_stereo;

/* Everything bvox_render does, in order: cut (a copy of the volume by the
 * plane, keeping a side, as bvox_cut_plane), cast (the axis view on whole
 * words, or a parallel projection), shade, mark the cut face, zoom by
 * replication, zoom x2 with averaging, filter; for stereo, two casts with
 * the view turned by -+stereo_angle about the image's vertical axis, then
 * side by side or as an anaglyph.
 * The view: axis_view 1 casts `view` with one pixel per voxel column (as
 * bvox_cast_axis) unless proj.width or proj.height is set or stereo is
 * asked; then, and with axis_view 0, it is the projection proj (size 0: 512,
 * scale 0: fit), an axis view becoming the projection with the same image
 * axes (rows right, down, view of its eye frame).
 * The cut face: for an axis view, the pixels whose hit voxel is seen through
 * a face the cut exposed (the voxel in front of it was in the object); for a
 * projection, whose pre-image keeps depth only to a pixel unit, those whose
 * hit point lies within half a voxel's extent plus half a depth step (along
 * the plane's normal) of the plane, counted into the kept side: every face
 * the cut exposed, and a thin rim of the old surface. They are lit flat with the plane's
 * own normal (depth shading: their depth shade) and tinted
 * with cut_color, and the image is RGB; without a cut it is gray (anaglyphs
 * are RGB). */
typedef struct bvox_render_opts {
    int axis_view;            /* 1: the axis view `view` */
    bvox_view view;
    bvox_projection proj;     /* the rotation (axis_view 0) and the image size */
    bvox_shade_mode shade;
    bvox_light light;
    bvox_depth_shading depth;
    int zoom;                 /* 1, 2, 4 or 8 (0: 1): pixel replication */
    int average;              /* then zoom x2 with pixel averaging (Figure 5) */
    int filter;               /* -1: none, else a bvox_filter, applied last */
    int cut;                  /* 1: cut by plane: a x + b y + c z + d = 0 (world) */
    double plane[4];
    int keep_above;           /* the side kept: 1 above (>= 0), 0 below */
    uint8_t cut_color[3];     /* tint of the cut face */
    bvox_stereo stereo;
    double stereo_angle;      /* degrees each way (default 3) */
} bvox_render_opts;
/* +z axis view, binary+depth shading, BVOX_LIGHT_INIT, BVOX_DEPTH_SHADING_INIT,
 * zoom 1, no filter, no cut (keep above, tint 255, 176, 96), no stereo (3 degrees). */
bvox_render_opts bvox_render_opts_default(void);
/* Set the view of opts from text: "+z", "-z", "+x", "-x", "+y", "-y" (axis
 * views), "AZ,EL" (degrees, see bvox_projection), "iso" (looking from the
 * corner (+1, +1, +1) towards the centre, z up on the screen) or "iso" with
 * three signs, "iso+x-y+z" (from (+1, -1, +1)): the 8 isometric directions.
 * BVOX_EINVAL if the text is none of these. */
bvox_status bvox_render_parse_view(const char *text, bvox_render_opts *opts);

/* Render vol as opts say into *out (8-bit gray, or RGB as said above). pre,
 * if not NULL, receives the pre-image of the (left eye's) cast. Owned by the
 * caller. BVOX_EINVAL for bad options, BVOX_ETOOBIG/BVOX_ENOMEM. */
bvox_status bvox_render(const bvox_volume *vol, const bvox_render_opts *opts, bvox_image **out,
                        bvox_preimage **pre);
/* The depth map for files: 16-bit, 0 for background, else depth + 1 (depth
 * in steps from the entry face along the view: voxels for an axis view,
 * pixel units from the front of the fitting sphere for a projection),
 * saturated at 65535. */
bvox_status bvox_preimage_depth_map(const bvox_preimage *pre, bvox_image **out);

/* A sheet of four views in a 2 x 2 grid, each cell rendered as opts say (no
 * stereo) as a projection of proj's size (0: 256 x 256) fitted alike, so all
 * cells share one scale: top left +z, top right +x, bottom left -y (the axis
 * views whose image axes make a true, unmirrored picture), bottom right iso.
 * BVOX_EINVAL with stereo. */
bvox_status bvox_render_sheet(const bvox_volume *vol, const bvox_render_opts *opts,
                              bvox_image **out);

/* Frame i of a turntable of n: opts' view (an axis view taken as its
 * projection) turned by 360 i / n degrees about the volume axis (x, y or z)
 * closest to the image's vertical, so the object spins about an upright axis.
 * Fills *frame_opts (axis_view 0, a matrix). */
bvox_status bvox_turntable_view(const bvox_render_opts *opts, int i, int n,
                                bvox_render_opts *frame_opts);
/* Render n frames (1..3600) of a turntable and write them: an animated GIF
 * (looping, a turn in about 4 s) when path ends in ".gif", else n PNG files
 * named after path without its ".png": "spin.png" -> spin_000.png, spin_001.png
 * ... (4 digits from 1001 frames). Each file goes through a temporary file
 * renamed on success. Gray frames use a gray palette; RGB frames (a cut,
 * anaglyphs) one palette per frame (median cut). */
bvox_status bvox_render_turntable(const bvox_volume *vol, const bvox_render_opts *opts, int n,
                                  const char *path);

/* The paper's four pictures of a volume (the built-in specimen in `bvox
 * demo`), k = 1..4: 1 binary gradient and depth shaded; 2 depth shaded,
 * zoomed x2 with averaging and high-pass filtered; 3 "the same" (as 2), the
 * object resliced by a plane, its cut face tinted; 4 the data set as the frame buffer held it (the
 * mosaic, of every other column in x and y when nx or ny exceeds 128, so the
 * 256 x 256 x 128 specimen gives the paper's 512 x 512 layout). */
bvox_status bvox_demo_picture(const bvox_volume *vol, int k, bvox_image **out);
/* Write picture1.png .. picture4.png into the existing folder dir. */
bvox_status bvox_demo_pictures(const bvox_volume *vol, const char *dir);

/* ------------------------------------------------------------ editing, cut */

/* In-place edits that report which region changed, so that a display can
 * redo only that part. changed may be NULL; otherwise *changed receives the
 * tight bounding box (half-open) of exactly the voxels whose value changed,
 * or an all-zero (empty) box when nothing changed. Boxes and half-spaces are
 * a bit run per column, changed with whole-word masks, rows split over the
 * worker threads. They modify vol: exclusive access needed. */

/* Set (value != 0) or clear voxel (x, y, z); BVOX_EINVAL outside the volume. */
bvox_status bvox_edit_voxel(bvox_volume *vol, int32_t x, int32_t y, int32_t z, int value,
                            bvox_box *changed);
/* Set (value != 0) or clear every voxel of box (half-open, clipped to the
 * volume; a box outside it changes nothing). */
bvox_status bvox_edit_fill_box(bvox_volume *vol, bvox_box box, int value, bvox_box *changed);
/* The paper's spatial selection: clear every voxel outside box (half-open,
 * clipped; a box outside the volume clears everything). */
bvox_status bvox_edit_keep_box(bvox_volume *vol, bvox_box box, bvox_box *changed);

/* Cut by the plane a*x + b*y + c*z + d = 0 in world coordinates: (x, y, z) is
 * the centre of a voxel, origin + direction * (index * spacing) (the full
 * geometry). "Above" is a*x + b*y + c*z + d >= 0, so a centre on the plane is
 * above, and "below" is < 0: keeping above and keeping below split the
 * 1-voxels exactly. keep_above != 0 clears the voxels below, else those
 * above. The test is evaluated in index space as
 * f = ((e + cj*j) + ci*i) + ck*k with the plane's coefficients carried into
 * index space; it is exact when those are exactly representable (e.g.
 * identity direction, spacing and plane given in binary fractions), otherwise
 * a centre within rounding of the plane may fall on either side.
 * BVOX_EINVAL for non-finite coefficients, a zero normal, or coefficients so
 * large that the index-space plane overflows. */
bvox_status bvox_cut_plane(bvox_volume *vol, double a, double b, double c, double d,
                           int keep_above, bvox_box *changed);
/* The half-space a*x + b*y + c*z + d >= 0 as a primitive, combined into vol
 * like bvox_shape_draw (UNION/REPLACE set it, DIFFERENCE clears it,
 * INTERSECTION keeps only it, XOR flips it), in the shapes' frame: (x, y, z) =
 * origin + index*spacing, direction ignored. Same errors as bvox_cut_plane. */
bvox_status bvox_halfspace_draw(bvox_volume *vol, double a, double b, double c, double d,
                                bvox_csg_op op, bvox_box *changed);

/* --------------------------------------------------------- CSG expressions */

/* bvox_csg_eval evaluates a small set-operation language:
 *
 *   expr    := term (('+' | '-' | '^') term)*      union, difference, xor
 *   term    := unary ('*' unary)*                   intersection
 *   unary   := '~' unary | primary                  complement (in the output grid)
 *   primary := '(' expr ')' | FILE [place] | NAME '(' [param (',' param)*] ')'
 *   place   := '@' I ',' J ',' K                    offset in voxels (integers)
 *            | '@' '(' X ',' Y ',' Z ')'            offset in physical units, rounded
 *   param   := KEY '=' NUMBER (',' NUMBER)*         to voxels of the output grid
 *
 * '*' binds tighter than '+', '-', '^', which have equal precedence and group
 * left to right: "a + b * c - d" is "(a + (b * c)) - d". Whitespace is free.
 * FILE is a run of characters other than whitespace and ( ) + * ^ ~ @ , = " '
 * not starting with '-' ("my-file.nii" is one name, so put spaces around a
 * '-' operator), or any text in double or single quotes.
 * Primitives, in physical units (the output grid's unit), drawn exactly as
 * bvox_shape_draw / bvox_halfspace_draw draw them (the shapes' frame);
 * "at" defaults to the centre of the output grid, "axis" to 0,0,1:
 *   sphere(r=R, at=X,Y,Z)          ellipsoid(r=RX,RY,RZ, at=...)
 *   box(size=SX,SY,SZ, at=...)     box(min=X0,Y0,Z0, max=X1,Y1,Z1)
 *   cylinder(r=R, h=H, at=..., axis=AX,AY,AZ)   (at: centre, h: full height)
 *   cone(r=R, h=H, at=..., axis=...)            (at: centre of the base)
 *   torus(R=RING, r=TUBE, at=..., axis=...)
 *   halfspace(n=A,B,C, d=D)        A*x + B*y + C*z + D >= 0
 * (a single value for ellipsoid r or box size means all three).
 *
 * The output grid (dimensions and geometry) is that of the first FILE in the
 * text; without one, opts->dims and opts->geometry. Files are combined index
 * to index (their own origin is ignored) after the placement offset, with
 * bvox_csg_apply semantics: outside a file's footprint it counts as 0. A file
 * whose voxel size differs (relative 1e-4) from the grid's is refused.
 * Errors are BVOX_EINVAL with "csg: <what> at column N" (1-based), plus the
 * loader's status and message (prefixed with the column) for files. */

#define BVOX_CSG_MAX_LENGTH 65536 /* bytes of expression text */
#define BVOX_CSG_MAX_DEPTH 256    /* nesting of parentheses and '~' */

/* Loads file operand name into a new volume (*out owned by the caller). */
typedef bvox_status (*bvox_csg_loader)(void *ctx, const char *name, bvox_volume **out);

typedef struct bvox_csg_eval_opts {
    bvox_dims dims;          /* grid without a file operand; {0,0,0}: none given */
    bvox_geometry geometry;  /* its geometry (bvox_geometry_default()) */
    const bvox_read_opts *read_opts; /* for bvox_read of files (NULL: defaults) */
    bvox_csg_loader load;    /* NULL: bvox_read(name, read_opts) */
    void *load_ctx;
    int parse_only;          /* check syntax and parameters only: no file is
                                read, nothing built, *out stays NULL */
} bvox_csg_eval_opts;

/* dims {0,0,0}, default geometry, no read options, bvox_read, parse_only 0. */
bvox_csg_eval_opts bvox_csg_eval_opts_default(void);

/* Evaluate expr (see above) into a new volume *out (owned by the caller).
 * opts may be NULL (defaults). Each distinct file is loaded once. Nesting
 * and length are bounded (BVOX_CSG_MAX_DEPTH/LENGTH), so no input can exhaust
 * the stack. Returns BVOX_EINVAL for a bad expression or a missing grid,
 * the loader's status for a file, BVOX_ETOOBIG/BVOX_ENOMEM for memory. */
bvox_status bvox_csg_eval(const char *expr, const bvox_csg_eval_opts *opts, bvox_volume **out);

/* Later subsystems, one header each (they rely on the types above). */
#include "bvox/contours.h" /* section outlines: the reconstruction data model */
#include "bvox/recon.h"    /* images of serial sections -> aligned contour stack -> model */
#include "bvox/mesh.h"     /* volume <-> triangle meshes */
#include "bvox/journal.h"  /* undo/redo of in-place edits (the viewer) */

#ifdef __cplusplus
}
#endif

#endif /* BVOX_H */
