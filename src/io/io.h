/*
 * io.h — private interface shared by the file readers and writers of src/io/.
 *
 *  - A reader decodes its file into a bvox__gray (typed samples, x fastest,
 *    then y, then z, as NIfTI, TIFF and raw store them) and hands it to
 *    bvox__binarize, which applies the user's read options and packs 64 voxels
 *    per word; binary formats (binvox) may build the volume directly.
 *  - Every reader has a memory entry point (fuzzing needs it); paths are read
 *    whole into memory with bvox__read_file first.
 *  - Every writer writes through a bvox__sink: a temporary file in the target
 *    folder, synced and renamed on commit, removed on abort.
 *  - Sizes from a file are checked (bvox__check_dims, overflow-safe products,
 *    the budget through bvox__alloc) before any allocation they drive.
 */
#ifndef BVOX_IO_H
#define BVOX_IO_H

#include "internal.h"

#include <stdio.h>

/* ---- gray volumes and binarisation (binarize.c) ---- */

typedef struct bvox__gray {
    bvox_dims dims;
    bvox_dtype dtype;
    const void *data;    /* nx*ny*nz samples, x fastest; may point into `owned`
                            or into a caller's buffer */
    void *owned;         /* from bvox__alloc, or NULL */
    size_t owned_bytes;
    bool byteswap;       /* samples are in the other byte order than the CPU's */
    bool z_fastest;      /* samples are z fastest, then y, then x (the C order of
                            an [x][y][z] array, NumPy's default) instead */
    double slope, inter; /* real value = raw * slope + inter; slope 0 means 1 */
    bvox_geometry geom;  /* given to the volume */
} bvox__gray;

/* Initialise: default geometry, slope 1, no data. */
void bvox__gray_init(bvox__gray *g);
/* Free `owned` (if any) and reset. */
void bvox__gray_release(bvox__gray *g);
/* Turn a gray volume into a binary one following `how` (NULL: nonzero).
 * name is the file name for messages. The volume gets g->geom. */
bvox_status bvox__binarize(const bvox__gray *g, const bvox_binarize *how, const char *name,
                           bvox_volume **out);

/* The same, fed a few slices at a time (binarize_stream.c), so that a reader
 * that decodes slice by slice holds only the bits and its slice buffer.
 * begin takes g's dims, dtype, byteswap, slope, inter and geom (not data);
 * slices() takes the next n whole slices (x fastest, then y), in order;
 * finish() after all nz returns the volume (the stream is released either
 * way); abort() releases it (accepts NULL). Not for Otsu's threshold, which
 * needs every sample first: bvox__bin_stream_ok(how) says when it applies. */
typedef struct bvox__bin_stream bvox__bin_stream;
bool bvox__bin_stream_ok(const bvox_binarize *how);
bvox_status bvox__bin_stream_begin(const bvox__gray *g, const bvox_binarize *how,
                                   const char *name, bvox__bin_stream **out);
void bvox__bin_stream_slices(bvox__bin_stream *s, const void *data, size_t n);
/* Bytes of one slice of samples (nx * ny * sample size). */
size_t bvox__bin_stream_slice_bytes(const bvox__bin_stream *s);
bvox_status bvox__bin_stream_finish(bvox__bin_stream *s, bvox_volume **out);
void bvox__bin_stream_abort(bvox__bin_stream *s);

/* ---- whole files in memory, gzip (stream.c) ---- */

typedef struct bvox__bytes {
    uint8_t *data; /* from bvox__alloc */
    size_t size;
    size_t alloc_bytes; /* what to pass to bvox__free */
} bvox__bytes;

/* Read a whole regular file. BVOX_ENOTFOUND if missing, BVOX_EIO if a
 * directory or unreadable, BVOX_ETOOBIG over the budget. Messages name path. */
bvox_status bvox__read_file(const char *path, bvox__bytes *out);
void bvox__bytes_release(bvox__bytes *b);
/* 1 if the buffer starts with the gzip magic. */
int bvox__is_gzip(const uint8_t *data, size_t size);
/* Decompress a gzip buffer (concatenated members allowed) into out. The
 * output is capped at max_bytes (0: the memory budget): a "zip bomb" gets
 * BVOX_ETOOBIG, a truncated or corrupt stream BVOX_EFORMAT. */
bvox_status bvox__gunzip(const uint8_t *data, size_t size, const char *name, size_t max_bytes,
                         bvox__bytes *out);

/* ---- output (stream.c) ---- */

typedef struct bvox__sink {
    FILE *file;
    char *tmp_path;
    char *final_path; /* where the rename goes: a symlink's final target */
    char *name;    /* the path as given, for messages */
    void *gz;      /* z_stream when compressing, else NULL */
    bool failed;   /* a write failed: commit will refuse */
    bvox_status status;
    int slot;      /* bvox__temp_register's slot, -1 if none */
} bvox__sink;

/* Open a temporary file next to path (".name.XXXXXX" in the same folder).
 * gzip != 0 compresses what is written: a gzip stream (for .nii.gz), or a
 * bare zlib stream when gzip is BVOX__SINK_ZLIB (MetaImage's CompressedData). Refused (BVOX_EIO):
 * a path that names a folder, a device, a FIFO or a socket. A symlink is
 * followed: the temporary file is made beside its final target, which the
 * rename replaces (the link stays a link). An existing file's permission
 * bits (and group, where allowed) are kept; a new file gets 0666 less the
 * umask. */
#define BVOX__SINK_ZLIB 2
bvox_status bvox__sink_open(const char *path, int gzip, bvox__sink *s);
bvox_status bvox__sink_write(bvox__sink *s, const void *data, size_t size);
/* Compress what is written from now on (mode 1 gzip, BVOX__SINK_ZLIB zlib):
 * a plain header before compressed data (.nrrd, .mha). No-op if already. */
bvox_status bvox__sink_compress(bvox__sink *s, int mode);
/* Flush, fsync, close, rename over path and fsync the folder. On failure
 * the temporary file is removed and an existing file at path is unchanged.
 * Always releases s. */
bvox_status bvox__sink_commit(bvox__sink *s);
/* Close and remove the temporary file; releases s. Safe after a failed open. */
void bvox__sink_abort(bvox__sink *s);
/* Overwrite size bytes at offset of what was written (an uncompressed sink):
 * a header whose counts are known only at the end (streamed meshes). */
bvox_status bvox__sink_pwrite(bvox__sink *s, uint64_t offset, const void *data, size_t size);
/* Test hook: make the n-th following bvox__sink_write fail (1: the next). */
void bvox__sink_fail_after(long n);
/* Test hook: how many times a folder was fsync'ed after a rename into it. */
long bvox__folder_syncs(void);
/* fsync the folder that holds path (after a rename into it). */
bool bvox__sync_parent(const char *path);
struct stat;
/* Follow path while it is a symlink (relative targets are relative to the
 * link's folder, at most 40 links). *out: the final path (free() it); *sb
 * its lstat, or *exists = false when nothing is there yet. false with errno
 * on failure (ELOOP, ENOMEM, ...). */
bool bvox__resolve_output(const char *path, char **out, struct stat *sb, bool *exists);

/* Folder outputs (PNG slices, SVG sections): the files are written into a
 * temporary folder beside the target (tmp), then
 *  - a target that does not exist: the temporary folder is renamed into place;
 *  - an empty target, or one holding only an earlier bvox output of the
 *    same kind (its manifest, MANIFEST_NAME, lists the files bvox wrote, and
 *    every name in it has the kind's pattern): the new files are renamed
 *    into it one by one, the listed files that are not written again are
 *    removed, and the manifest is rewritten; the folder itself is kept;
 *  - anything else is refused (BVOX_EIO, naming a file found there) before
 *    anything is written, and again at commit; with force, the new files
 *    replace files of the same names and nothing else is removed.
 * Nothing but the listed files is ever deleted. The temporary folder is
 * removed on every failure, and by bvox_cleanup_on_signals' handler.
 *
 * BVOX__DIR_ZARR is a whole tree (level folders of chunk files) and is put
 * in place whole: a new or empty target gets the temporary folder renamed
 * onto it; bvox's own earlier .zarr output (manifest of kind zarr naming
 * every entry at its top) is replaced only when forced (swapped, then the
 * old tree removed); a folder holding anything else is refused even when
 * forced, since replacing a Zarr tree means deleting it. */
typedef enum {
    BVOX__DIR_PNG_SLICES,   /* slice_NNNN.png */
    BVOX__DIR_SVG_SECTIONS, /* section_NNNN.svg */
    BVOX__DIR_LABEL_MESHES, /* LABEL[_NAME].stl|ply|obj|off (bvox mesh --labels) */
    BVOX__DIR_ZARR,         /* .zgroup, .zattrs, level folders 0, 1, ... (zarr.c) */
    BVOX__DIR_DEMO          /* bvox demo -o: section_NNNN.png and the names of
                               bvox__demo_file_names */
} bvox__dir_kind;
#define BVOX__MANIFEST_NAME ".bvox-manifest"
/* The voxel size of a PNG slice folder (PNG has no z): "SX SY SZ [UNIT]". */
#define BVOX__VOXEL_SIZE_NAME "voxel_size.txt"
/* True when the read options give the voxel size (all three axes > 0). */
static inline bool bvox__read_spacing_given(const bvox_read_opts *opts)
{
    return opts && opts->spacing[0] > 0 && opts->spacing[1] > 0 && opts->spacing[2] > 0;
}
typedef struct bvox__dir_sink {
    char *target;  /* trailing slashes removed, a symlink resolved */
    char *tmp;     /* the temporary folder: writers put their files here */
    const char *name; /* the path as given, for messages */
    bvox__dir_kind kind;
    bool force;
    int slot;
} bvox__dir_sink;
/* The fixed file names of BVOX__DIR_DEMO, NULL-terminated. */
extern const char *const bvox__demo_file_names[];
bvox_status bvox__dir_sink_open(const char *path, bvox__dir_kind kind, bool force,
                                bvox__dir_sink *d);
/* Put the files in place as described above; always releases d. */
bvox_status bvox__dir_sink_commit(bvox__dir_sink *d);
/* Remove the temporary folder; releases d. Safe after a failed open. */
void bvox__dir_sink_abort(bvox__dir_sink *d);

/* ---- temporary names and signal cleanup (temp_files.c) ---- */

/* "DIR/.BASE.XXXXXX" for path "DIR/BASE" (malloc'ed; NULL when out of memory). */
char *bvox__temp_name(const char *path);
/* Make a unique file (returns an open fd, mode 0666 less the umask) or
 * folder (returns 0, mode 0777 less the umask) from templ, whose last six
 * characters are replaced. -1 with errno on failure. */
int bvox__temp_create(char *templ, bool is_dir);
/* Track a temporary path so that a signal removes it; returns the slot for
 * bvox__temp_unregister (-1: not tracked, which unregister accepts). */
int bvox__temp_register(const char *path, bool is_dir);
void bvox__temp_unregister(int slot);
/* Remove every tracked temporary (what the signal handler does). */
void bvox__temp_remove_all_signal_safe(void);

/* ---- the format table (format.c) ---- */

typedef struct bvox__format {
    const char *name;               /* "nifti", ... */
    const char *const *extensions;  /* NULL-terminated, lower case, with dot: ".nii.gz" */
    /* 1 if the first bytes identify the format (NULL: cannot tell) */
    int (*sniff)(const uint8_t *data, size_t size);
    bvox_status (*read_memory)(const uint8_t *data, size_t size, const char *name,
                               const bvox_read_opts *opts, bvox_volume **out);
    /* NULL: format.c reads the file whole and calls read_memory */
    bvox_status (*read_path)(const char *path, const bvox_read_opts *opts, bvox_volume **out);
    bvox_status (*write_path)(const char *path, const bvox_volume *vol,
                              const bvox_write_opts *opts);
    /* the dimensions a read would give, from the header alone (NULL: the
     * format cannot tell cheaply) */
    bvox_status (*probe_dims)(const char *path, const bvox_read_opts *opts, bvox_dims *dims);
    /* the writer's own limits on dimensions (NULL: none beyond BVOX_MAX_DIM) */
    bvox_status (*write_limits)(const char *path, bvox_dims dims);
    /* Decode to typed samples without binarising (label volumes read them
     * once, labels.c); NULL for formats that hold only binary voxels. On
     * success g->data points into data or into g->owned. */
    bvox_status (*gray_memory)(const uint8_t *data, size_t size, const char *name,
                               const bvox_read_opts *opts, bvox__gray *g);
} bvox__format;

extern const bvox__format bvox__format_nifti;
extern const bvox__format bvox__format_binvox;
extern const bvox__format bvox__format_tiff;
extern const bvox__format bvox__format_png;
extern const bvox__format bvox__format_raw;
extern const bvox__format bvox__format_nrrd; /* nrrd.c, nrrd_write.c */
extern const bvox__format bvox__format_zarr;
/* A folder holding .zarray or .zgroup (zarr.c). */
bool bvox__zarr_is_dir(const char *path);
/* A .zarr's level (opts->zarr_level) as typed samples, unbinarised, with its
 * geometry (label volumes: labels_read.c); g->data points into g->owned. */
bvox_status bvox__zarr_read_gray(const char *path, const bvox_read_opts *opts, bvox__gray *g);
extern const bvox__format bvox__format_metaimage; /* metaimage.c */

/* Headers with a separate data file (detached.c): read `file` (relative to
 * the folder of header_path, or absolute) whole. */
bvox_status bvox__read_beside(const char *header_path, const char *file, bvox__bytes *out);
/* The data file of a header path: path less its last `strip` characters,
 * plus ext, into out; *base points at its file name within out. */
bvox_status bvox__detached_name(const char *path, size_t strip, const char *ext, char *out,
                                size_t cap, const char **base);
/* vol's bytes 0/1 into data_path (gz as bvox__write_byte_slices), then the
 * header into path; on failure neither is left behind. */
bvox_status bvox__write_detached(const char *path, const char *data_path, const bvox_volume *vol,
                                 int gz, const char *header, size_t header_size);
/* The header into path (whole or not at all) after its data file was
 * written; on failure the data file is removed too. */
bvox_status bvox__write_header_after(const char *path, const char *data_path, const char *header,
                                     size_t header_size);
/* The NRRD writer (nrrd_write.c), for the format table in nrrd.c. */
bvox_status bvox__nrrd_write(const char *path, const bvox_volume *vol,
                             const bvox_write_opts *opts);
/* Label-volume writers (labels_write.c, seg_nrrd_write.c) share the headers
 * of the binary writers. NRRD: the header lines of vol's dimensions and
 * geometry with samples of NRRD `type` ("uint8", "int16", ...), "gzip" or
 * "raw" encoding and "data file" when data_file is not NULL, appended to sb
 * without the blank line that ends a header (key/value pairs may follow).
 * MetaImage: the whole header, ElementType element_type ("MET_UCHAR", ...),
 * zlib-compressed little-endian data in data_file ("LOCAL": after it);
 * returns snprintf's count. */
struct bvox__strbuf;
/* label_samples.c: the n labels as samples of integer type dtype into s, a
 * chunk at a time (little-endian, or this CPU's order when host_order). */
bvox_status bvox__write_label_samples(bvox__sink *s, const uint32_t *labels, size_t n,
                                      bvox_dtype dtype, bool host_order);
/* The type labels are written with: dtype (an integer bvox_dtype every label
 * fits, else BVOX_EINVAL naming path) or, dtype < 0, the smallest unsigned
 * one; *max the largest label. */
bvox_status bvox__label_dtype(const char *path, const uint32_t *labels, size_t n, int dtype,
                              bvox_dtype *out, uint32_t *max);
/* nifti_labels.c: NIfTI label volume of samples dtype, display range 0..max. */
bvox_status bvox__write_labels_nifti(const char *path, const bvox_volume *like,
                                     const uint32_t *labels, bvox_dtype dtype, uint32_t max);
void bvox__nrrd_describe(const bvox_volume *vol, const char *type, bool gzip,
                         const char *data_file, struct bvox__strbuf *sb);
int bvox__mha_describe(const bvox_volume *vol, const char *element_type, const char *data_file,
                       char *buf, size_t cap);
/* The Segment<N>_ and Segmentation_ key/value lines of a 3D Slicer
 * segmentation holding `labels` (nx*ny*nz, x fastest, each <= 65535) as one
 * layer, one segment per label present, named and coloured by table (NULL
 * or a label it lacks: "Segment_<label>" and bvox__label_color), appended
 * to sb. BVOX_EUNSUPPORTED for a label over 65535; BVOX_ENOMEM. */
bvox_status bvox__seg_nrrd_describe(const bvox_volume *like, const uint32_t *labels,
                                    const bvox_label_table *table, struct bvox__strbuf *sb);

/* LPS (ITK, 3D Slicer: NRRD, MetaImage) <-> RAS (bvox): negate the first two
 * world axes of origin and direction, in place. */
void bvox__geometry_flip_lps(bvox_geometry *g);

/* 3D Slicer segmentations (seg_nrrd.c): the Segment<N>_ keys of a NRRD
 * header, segment N at seg[N] (present: it had a key). */
typedef struct bvox__segment {
    char name[96];
    unsigned char rgb[3];
    bool present, has_color, has_value, has_layer;
    int64_t label_value;
    long layer;
} bvox__segment;
typedef struct bvox__segs {
    bvox__segment *seg;
    long n, cap;
} bvox__segs;
bvox_status bvox__segs_parse(const uint8_t *header, size_t size, const char *name,
                             bvox__segs *out);
void bvox__segs_release(bvox__segs *s);
/* The label segment i gets: its LabelValue in a 3D file, i + 1 in a
 * layered (4D) one. */
int64_t bvox__segs_label(const bvox__segs *s, long i, bool layered);
/* The segments as a label table (names, colours); BVOX_EFORMAT without any. */
bvox_status bvox__segs_table(const uint8_t *header, size_t size, const char *name, bool layered,
                             bvox_label_table **out);
/* g holds `layers` samples per voxel (layer fastest): replace them by one
 * uint16 label per voxel as described in seg_nrrd.c. */
bvox_status bvox__segs_flatten(bvox__gray *g, int64_t layers, const uint8_t *header,
                               size_t header_size, const char *name);
/* 1 if data is a NRRD header with a first "list" axis of layers (a
 * segmentation with overlapping segments). For label_table.c. */
bool bvox__nrrd_layered(const uint8_t *data, size_t size);

/* The typed samples of a file or buffer, for readers of label volumes: the
 * format resolved as bvox_read does (forced, extension, content). On success
 * g->data may point into *file (released by the caller after g) or into
 * g->owned. BVOX_EUNSUPPORTED for formats without samples (binvox, png). */
bvox_status bvox__read_gray(const char *path, const bvox_read_opts *opts, bvox__bytes *file,
                            bvox__gray *g);
bvox_status bvox__read_gray_memory(const void *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox__gray *g);

/* The TIFF writer, in its own file (tiff_write.c) beside the reader (tiff.c). */
bvox_status bvox__tiff_write(const char *path, const bvox_volume *vol,
                             const bvox_write_opts *opts);

/* libtiff on a memory buffer (tiff_memory.c), for the TIFF volume reader
 * (tiff.c) and the TIFF section reader (recon/section_tiff.c). The source
 * is the handle libtiff reads through and where its first error message is
 * kept (never printed); it must outlive the TIFF. */
struct tiff; /* libtiff's TIFF (tiffio.h) */
typedef struct bvox__tiff_src {
    const uint8_t *data;
    uint64_t size, pos;
    char err[200]; /* libtiff's first error, if have_err */
    bool have_err;
} bvox__tiff_src;
/* Open data[0..size) read-only (TIFFClientOpenExt) with libtiff's single
 * allocations capped at the memory budget; *out is NULL on failure
 * ("NAME: not a readable TIFF file (libtiff's reason)"). TIFFClose it. */
bvox_status bvox__tiff_open_memory(const uint8_t *data, size_t size, const char *name,
                                   bvox__tiff_src *src, struct tiff **out);
/* libtiff's first error message, or fallback when it gave none. */
const char *bvox__tiff_error(const bvox__tiff_src *src, const char *fallback);

/* NIfTI-1 output (nifti.c), shared with the label writer (nifti_labels.c):
 * the header and empty extension flag before the voxel data, for vol's
 * dimensions (each <= 32767: the caller checks) and geometry, samples of
 * NIfTI datatype code `datatype` of `bitpix` bits in this CPU's byte order,
 * display range 0..cal_max, NIfTI intent code `intent` (0: none), and
 * "bvox VERSION descrip" as the description. */
#define BVOX__NIFTI_DATA_OFFSET 352
void bvox__nifti_header(const bvox_volume *vol, int datatype, int bitpix, double cal_max,
                        int intent, const char *descrip, uint8_t h[BVOX__NIFTI_DATA_OFFSET]);
/* 1 if path ends in ".gz" (any case): the writer compresses. */
bool bvox__path_has_gz(const char *path);

/* OME-XML (ome_xml.c). Parse: 1 if desc is OME-XML; then the axes that give
 * a physical size in a known unit get spacing[a] (all in one unit, the
 * first axis's; have[a] true) and unit is set. Describe: a minimal OME
 * document for vol (uint8 planes, XYZCT, one IFD per plane from IFD 0, the
 * voxel size when the unit is a length); returns snprintf's count. */
int bvox__ome_parse(const char *desc, double spacing[3], char unit[16], bool have[3]);
int bvox__ome_describe(const bvox_volume *vol, char *buf, size_t cap);

/* For writers (unpack.c): slices z0 .. z0+n-1 (z0 a multiple of 64, 1 <= n
 * <= 64, z0 + n <= nz) as bytes, x fastest, then y, then z:
 * dst[((z - z0) * ny + y) * nx + x] = voxel ? one : 0. Word-wise, through
 * 64x64 bit transposes; dst holds n * nx * ny bytes. */
void bvox__unpack_slices(const bvox_volume *vol, int32_t z0, int32_t n, uint8_t one,
                         uint8_t *dst);
/* Write header (header_size bytes; none when 0), then every slice as bytes
 * 0/1 in that order, to path through a sink (gz as bvox__sink_open's gzip:
 * 0 plain, 1 gzip, BVOX__SINK_ZLIB zlib; plus BVOX__SINK_PLAIN_HEADER: the
 * header is written plain, only the slices compressed): the whole file or,
 * on failure, nothing. */
#define BVOX__SINK_PLAIN_HEADER 8
bvox_status bvox__write_byte_slices(const char *path, const bvox_volume *vol, int gz,
                                    const void *header, size_t header_size);
/* The whole volume as bytes 0/1, z fastest, then y, then x:
 * dst[((size_t)x * ny + y) * nz + z] = voxel. Each column's words expand in
 * place (no transpose); columns are split over the worker threads. */
void bvox__unpack_columns(const bvox_volume *vol, uint8_t *dst);

#endif
