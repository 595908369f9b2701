/*
 * nifti.c — NIfTI-1 single files (.nii, .nii.gz): reading into a bvox__gray
 * (then binarised) and writing a binary volume as uint8 0/1.
 *
 * The 348-byte header is parsed by hand rather than through nifticlib: that
 * library prints to stderr, has no entry point for a buffer in memory, and
 * allocates from the sizes in the header before we could check them against
 * our budget. Here every field is read at its byte offset (no struct, so no
 * padding or alignment questions), in the byte order sizeof_hdr reveals.
 *
 * An uncompressed file is not copied: the gray volume points into the caller's
 * buffer (with a byteswap flag for the other byte order); the binariser reads
 * it in place. A .nii.gz is decompressed with a cap derived from its header,
 * so a "zip bomb" is refused instead of filling memory.
 *
 * World coordinates are kept as the file states them (NIfTI's RAS+ frame):
 * the sform when sform_code > 0, else the qform, else pixdim only.
 */
#include "io.h"
#include "common/names.h"

#include <fcntl.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#define HDR_SIZE 348
#define MIN_VOX_OFFSET BVOX__NIFTI_DATA_OFFSET /* header + the 4-byte extension flag */
/* A gzip stream may carry a little padding after the voxel data; more than
 * this beyond what the header promises is treated as a bomb. */
#define GZ_SLACK 65536

/* NIfTI-1 datatype codes (nifti1.h) */
enum {
    DT_BINARY = 1, DT_UINT8 = 2, DT_INT16 = 4, DT_INT32 = 8, DT_FLOAT32 = 16,
    DT_COMPLEX64 = 32, DT_FLOAT64 = 64, DT_RGB24 = 128, DT_INT8 = 256, DT_UINT16 = 512,
    DT_UINT32 = 768, DT_INT64 = 1024, DT_UINT64 = 1280, DT_FLOAT128 = 1536,
    DT_COMPLEX128 = 1792, DT_COMPLEX256 = 2048, DT_RGBA32 = 2304
};

static const struct {
    int code;
    bvox_dtype dtype;
    int bits;
} supported[] = {
    {DT_UINT8, BVOX_DT_U8, 8},     {DT_INT8, BVOX_DT_I8, 8},      {DT_UINT16, BVOX_DT_U16, 16},
    {DT_INT16, BVOX_DT_I16, 16},   {DT_UINT32, BVOX_DT_U32, 32},  {DT_INT32, BVOX_DT_I32, 32},
    {DT_UINT64, BVOX_DT_U64, 64},  {DT_INT64, BVOX_DT_I64, 64},   {DT_FLOAT32, BVOX_DT_F32, 32},
    {DT_FLOAT64, BVOX_DT_F64, 64},
};

static const char *unsupported_name(int code)
{
    switch (code) {
    case DT_BINARY: return "binary (1 bit per voxel)";
    case DT_COMPLEX64: return "complex64";
    case DT_COMPLEX128: return "complex128";
    case DT_COMPLEX256: return "complex256";
    case DT_RGB24: return "RGB24";
    case DT_RGBA32: return "RGBA32";
    case DT_FLOAT128: return "float128";
    default: return NULL;
    }
}

/* Length units of xyzt_units (bits 0..2), with the scale used when writing a
 * unit NIfTI cannot name (cm -> mm, nm -> um). */
static const struct {
    const char *name;
    int code;
    double scale;
} units[] = {
    {"m", 1, 1.0}, {"mm", 2, 1.0}, {"um", 3, 1.0}, {"\xc2\xb5m", 3, 1.0}, /* "µm" */
    {"cm", 2, 10.0}, {"nm", 3, 0.001},
};

/* ------------------------------------------------------------ header fields */

static uint16_t get16(const uint8_t *h, size_t off, bool swap)
{
    uint16_t v;
    memcpy(&v, h + off, 2);
    return swap ? __builtin_bswap16(v) : v;
}
static uint32_t get32(const uint8_t *h, size_t off, bool swap)
{
    uint32_t v;
    memcpy(&v, h + off, 4);
    return swap ? __builtin_bswap32(v) : v;
}
static int16_t geti16(const uint8_t *h, size_t off, bool swap)
{
    return (int16_t)get16(h, off, swap);
}
static float getf32(const uint8_t *h, size_t off, bool swap)
{
    uint32_t u = get32(h, off, swap);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

typedef struct header {
    bvox_dims dims;
    bvox_dtype dtype;
    size_t elem;
    uint64_t vox_offset;
    uint64_t data_bytes; /* of the first volume */
    bool swap;
    bool more_volumes; /* dim[4..7]: volumes after the first (never read) */
    double slope, inter;
    bvox_geometry geom;
} header;

/* Positive finite, else 1 (a missing or nonsensical pixdim must not fail the read). */
static double sane_spacing(double v)
{
    v = fabs(v);
    return (isfinite(v) && v > 0) ? v : 1.0;
}

/* Rotation from the qform quaternion (b, c, d; a implied), as nifti1_io's
 * nifti_quatern_to_mat44; qfac flips the third column. Row-major. */
static void quatern_to_rot(double b, double c, double d, double qfac, double r[9])
{
    double a = 1.0 - (b * b + c * c + d * d);
    if (a < 1.e-7) { /* special case: a 180-degree rotation, renormalise b,c,d */
        double n = sqrt(b * b + c * c + d * d);
        if (!(n > 0)) n = 1;
        b /= n, c /= n, d /= n;
        a = 0.0;
    } else {
        a = sqrt(a);
    }
    r[0] = a * a + b * b - c * c - d * d;
    r[1] = 2 * (b * c - a * d);
    r[2] = 2 * (b * d + a * c);
    r[3] = 2 * (b * c + a * d);
    r[4] = a * a + c * c - b * b - d * d;
    r[5] = 2 * (c * d - a * b);
    r[6] = 2 * (b * d - a * c);
    r[7] = 2 * (c * d + a * b);
    r[8] = a * a + d * d - c * c - b * b;
    for (int i = 0; i < 3; i++) r[i * 3 + 2] *= qfac;
}

/* Orientation: sform if given and usable, else qform, else pixdim only. */
static void read_geometry(const uint8_t *h, bool swap, header *hd)
{
    bvox_geometry *g = &hd->geom;
    *g = bvox_geometry_default();
    double pix[3];
    for (int i = 0; i < 3; i++) pix[i] = sane_spacing(getf32(h, 80 + 4 * (size_t)i, swap));
    memcpy(g->spacing, pix, sizeof pix);
    int code = h[123] & 7;
    for (size_t u = 0; u < sizeof units / sizeof units[0]; u++)
        if (units[u].code == code && units[u].scale == 1.0) {
            strcpy(g->unit, units[u].name);
            break;
        }

    if (geti16(h, 254, swap) > 0) {
        double a[12], dir[9], sp[3];
        bool ok = true;
        for (int i = 0; i < 12; i++) {
            a[i] = getf32(h, 280 + 4 * (size_t)i, swap);
            ok = ok && isfinite(a[i]);
        }
        for (int j = 0; j < 3 && ok; j++) {
            double n = sqrt(a[j] * a[j] + a[4 + j] * a[4 + j] + a[8 + j] * a[8 + j]);
            if (!(n > 0) || !isfinite(n)) ok = false;
            sp[j] = n;
            for (int i = 0; i < 3; i++) dir[i * 3 + j] = a[i * 4 + j] / n;
        }
        if (ok) { /* a degenerate sform falls through to the qform */
            g->space = geti16(h, 254, swap) <= 4 ? geti16(h, 254, swap) : 0;
            memcpy(g->spacing, sp, sizeof sp);
            memcpy(g->direction, dir, sizeof dir);
            for (int i = 0; i < 3; i++) g->origin[i] = a[i * 4 + 3];
            return;
        }
    }
    if (geti16(h, 252, swap) > 0) {
        double q[6], r[9];
        bool ok = true;
        for (int i = 0; i < 6; i++) {
            q[i] = getf32(h, 256 + 4 * (size_t)i, swap);
            ok = ok && isfinite(q[i]);
        }
        if (ok) {
            double qfac = getf32(h, 76, swap) < 0 ? -1.0 : 1.0;
            quatern_to_rot(q[0], q[1], q[2], qfac, r);
            g->space = geti16(h, 252, swap) <= 4 ? geti16(h, 252, swap) : 0;
            memcpy(g->direction, r, sizeof r);
            for (int i = 0; i < 3; i++) g->origin[i] = q[3 + i];
        }
    }
}

/* Parse and validate a header of `avail` bytes (the file size is checked by
 * the caller, which knows it). */
static bvox_status parse_header(const uint8_t *h, size_t avail, const char *name, header *hd)
{
    memset(hd, 0, sizeof *hd);
    if (avail < 4)
        return bvox__fail(BVOX_EFORMAT, "%s: truncated NIfTI header (%zu bytes, needs %d)", name,
                          avail, HDR_SIZE);
    uint32_t sz = get32(h, 0, false);
    bool swap;
    if (sz == HDR_SIZE)
        swap = false;
    else if (__builtin_bswap32(sz) == HDR_SIZE)
        swap = true;
    else if (sz == 540 || __builtin_bswap32(sz) == 540)
        return bvox__fail(BVOX_EFORMAT, "%s: NIfTI-2 files are not supported (only NIfTI-1)",
                          name);
    else
        return bvox__fail(BVOX_EFORMAT, "%s: not a NIfTI-1 file (sizeof_hdr is %u, not 348)",
                          name, (unsigned)sz);
    if (avail < HDR_SIZE)
        return bvox__fail(BVOX_EFORMAT, "%s: truncated NIfTI header (%zu bytes, needs %d)", name,
                          avail, HDR_SIZE);
    if (memcmp(h + 344, "ni1", 4) == 0)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: a NIfTI header/image pair (.hdr/.img) is not supported; "
                          "convert it to a single .nii file",
                          name);
    if (memcmp(h + 344, "n+1", 4) != 0)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: bad NIfTI-1 magic (expected \"n+1\"; an old Analyze 7.5 file?)",
                          name);
    hd->swap = swap;

    int16_t dim[8];
    for (int i = 0; i < 8; i++) dim[i] = geti16(h, 40 + 2 * (size_t)i, swap);
    if (dim[0] < 1 || dim[0] > 7)
        return bvox__fail(BVOX_EFORMAT, "%s: dim[0] is %d, must be 1..7", name, dim[0]);
    /* Axes beyond dim[0] are 1. Axes 4..7 (time, vectors) are not checked:
     * only the first 3D volume is read, whatever they say. */
    int32_t n[3];
    for (int i = 0; i < 3; i++) {
        n[i] = i < dim[0] ? dim[i + 1] : 1;
        if (n[i] < 1)
            return bvox__fail(BVOX_EFORMAT, "%s: dim[%d] is %d, must be at least 1", name, i + 1,
                              n[i]);
    }
    hd->dims = (bvox_dims){n[0], n[1], n[2]};
    hd->more_volumes = false;
    for (int i = 4; i <= dim[0]; i++) hd->more_volumes |= dim[i] > 1;

    int code = geti16(h, 70, swap), bitpix = geti16(h, 72, swap);
    size_t k = 0, nsup = sizeof supported / sizeof supported[0];
    while (k < nsup && supported[k].code != code) k++;
    if (k == nsup) {
        const char *what = unsupported_name(code);
        if (what)
            return bvox__fail(BVOX_EUNSUPPORTED,
                              "%s: NIfTI datatype %s is not supported (only integer and real "
                              "scalars)",
                              name, what);
        return bvox__fail(BVOX_EFORMAT, "%s: unknown NIfTI datatype code %d", name, code);
    }
    if (bitpix != supported[k].bits)
        return bvox__fail(BVOX_EFORMAT, "%s: bitpix %d does not match datatype %s (%d bits)",
                          name, bitpix, bvox_dtype_name(supported[k].dtype), supported[k].bits);
    hd->dtype = supported[k].dtype;
    hd->elem = (size_t)supported[k].bits / 8;

    /* The binary volume's size against the limits and the budget, before any
     * allocation (the data size below is checked against the file instead). */
    size_t words_bytes;
    bvox_status st = bvox__check_dims(hd->dims, name, &words_bytes);
    if (st) return st;
    size_t voxels, bytes;
    if (!bvox__mul_size((size_t)n[0], (size_t)n[1], &voxels) ||
        !bvox__mul_size(voxels, (size_t)n[2], &voxels) ||
        !bvox__mul_size(voxels, hd->elem, &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: header dimensions overflow", name);
    hd->data_bytes = bytes;

    float vo = getf32(h, 108, swap);
    if (!isfinite(vo) || vo < MIN_VOX_OFFSET || vo > 0x1p62f || vo != floorf(vo))
        return bvox__fail(BVOX_EFORMAT,
                          "%s: vox_offset %g is invalid (must be a whole number >= %d)", name,
                          (double)vo, MIN_VOX_OFFSET);
    hd->vox_offset = (uint64_t)vo;

    double slope = getf32(h, 112, swap), inter = getf32(h, 116, swap);
    if (!isfinite(slope) || slope == 0.0) slope = 1.0, inter = 0.0;
    if (!isfinite(inter)) inter = 0.0;
    hd->slope = slope;
    hd->inter = inter;
    read_geometry(h, swap, hd);
    return BVOX_OK;
}

/* Inflate just the start of a gzip stream (for the header): returns the
 * number of bytes produced, or -1 if the stream is corrupt. */
static long gunzip_head(const uint8_t *data, size_t size, uint8_t *out, size_t want)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 16) != Z_OK) return -1;
    z.next_in = (Bytef *)data;
    z.avail_in = size > UINT32_MAX ? UINT32_MAX : (uInt)size;
    z.next_out = out;
    z.avail_out = (uInt)want;
    int rc = Z_OK;
    while (z.avail_out > 0 && rc == Z_OK) {
        rc = inflate(&z, Z_SYNC_FLUSH);
        /* concatenated members (as bvox__gunzip accepts): go on to the next */
        if (rc == Z_STREAM_END && z.avail_out > 0 && bvox__is_gzip(z.next_in, z.avail_in))
            rc = inflateReset(&z);
    }
    long got = (long)(want - z.avail_out);
    inflateEnd(&z);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) return -1;
    return got;
}

static int nifti_sniff(const uint8_t *data, size_t size)
{
    uint8_t head[HDR_SIZE];
    if (bvox__is_gzip(data, size)) {
        long got = gunzip_head(data, size, head, sizeof head);
        if (got < HDR_SIZE) return 0;
        data = head;
        size = sizeof head;
    }
    if (size < HDR_SIZE) return 0;
    uint32_t sz = get32(data, 0, false);
    return (sz == HDR_SIZE || __builtin_bswap32(sz) == HDR_SIZE) &&
           (memcmp(data + 344, "n+1", 4) == 0 || memcmp(data + 344, "ni1", 4) == 0);
}

/* ------------------------------------------------------------------ reading */

/* Where the streamed reader's bytes come from: a file (gzFile: inflates a
 * .nii.gz, passes a plain .nii through) or a gzip buffer in memory (a
 * z_stream; concatenated members allowed, as bvox__gunzip does). */
typedef struct nsrc {
    gzFile gz;
    const uint8_t *mem;
    size_t mem_size;
    z_stream z;
    bool zinit, zdone;
} nsrc;
static bvox_status read_streamed(nsrc *src, const char *name, uint64_t file_size,
                                 uint64_t gz_size, const bvox_read_opts *opts,
                                 bvox_volume **out);

static bvox_status decode_whole(const uint8_t *data, size_t size, const char *name,
                                const char *why, bvox__gray *g);

static bvox_status nifti_read_memory(const uint8_t *data, size_t size, const char *name,
                                     const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "input";
    bvox_status st;
    if (bvox__is_gzip(data, size) && bvox__bin_stream_ok(opts ? &opts->binarize : NULL)) {
        nsrc src;
        memset(&src, 0, sizeof src);
        src.mem = data;
        src.mem_size = size;
        st = read_streamed(&src, name, UINT64_MAX, size, opts, out);
        if (src.zinit) inflateEnd(&src.z);
        return st;
    }
    /* a plain buffer is binarised in place; a gzip one only for Otsu, which
     * needs every sample first */
    bvox__gray g;
    st = decode_whole(data, size, name, "Otsu's threshold needs", &g);
    if (!st) st = bvox__binarize(&g, opts ? &opts->binarize : NULL, name, out);
    bvox__gray_release(&g);
    return st;
}

/* The whole file decoded into a gray volume, not binarised: g->data points
 * into data, or into the inflated copy that g owns (.nii.gz, within the
 * memory budget; why names who needs it, for the refusal). */
static bvox_status decode_whole(const uint8_t *data, size_t size, const char *name,
                                const char *why, bvox__gray *g)
{
    bvox__gray_init(g);
    if (!name) name = "input";
    bvox__bytes unz = {0};
    header hd;
    bvox_status st;
    if (bvox__is_gzip(data, size)) {
        uint8_t head[HDR_SIZE];
        long got = gunzip_head(data, size, head, sizeof head);
        if (got < 0) return bvox__fail(BVOX_EFORMAT, "%s: corrupt gzip data", name);
        st = parse_header(head, (size_t)got, name, &hd);
        if (st) return st;
        uint64_t need = hd.vox_offset + hd.data_bytes;
        if (need + GZ_SLACK > bvox_memory_budget()) {
            char what[32], lim[32];
            bvox__format_bytes(what, sizeof what, (size_t)need);
            bvox__format_bytes(lim, sizeof lim, bvox_memory_budget());
            return bvox__fail(BVOX_ETOOBIG,
                              "%s: %s the whole inflated file (%s), over the memory budget "
                              "of %s",
                              name, why, what, lim);
        }
        st = bvox__gunzip(data, size, name, (size_t)need + GZ_SLACK, &unz);
        if (st) return st;
        data = unz.data;
        size = unz.size;
    }
    st = parse_header(data, size, name, &hd);
    if (st == BVOX_OK && hd.vox_offset > size)
        st = bvox__fail(BVOX_EFORMAT,
                        "%s: vox_offset %llu is beyond the end of the file (%zu bytes)", name,
                        (unsigned long long)hd.vox_offset, size);
    else if (st == BVOX_OK && hd.data_bytes > size - hd.vox_offset)
        st = bvox__fail(BVOX_EFORMAT,
                        "%s: truncated: header claims %llu bytes of voxel data, file has %llu",
                        name, (unsigned long long)hd.data_bytes,
                        (unsigned long long)(size - hd.vox_offset));
    if (st) {
        if (unz.data) bvox__bytes_release(&unz);
        return st;
    }
    g->dims = hd.dims;
    g->dtype = hd.dtype;
    g->data = data + hd.vox_offset;
    g->owned = unz.data;
    g->owned_bytes = unz.alloc_bytes;
    g->byteswap = hd.swap && hd.elem > 1;
    g->slope = hd.slope;
    g->inter = hd.inter;
    g->geom = hd.geom;
    return BVOX_OK;
}

/* Typed samples without binarising (label volumes read them once,
 * labels_read.c). */
static bvox_status nifti_gray_memory(const uint8_t *data, size_t size, const char *name,
                                     const bvox_read_opts *opts, bvox__gray *g)
{
    (void)opts;
    return decode_whole(data, size, name ? name : "input", "the label samples need", g);
}

/* ---------------------------------------------------------- streamed reading */


/* Up to n bytes into buf: the count read (less at the end), or -1 if the
 * data is corrupt. */
static long long src_read(nsrc *s, void *buf, size_t n)
{
    size_t got = 0;
    if (s->gz) {
        while (got < n) {
            unsigned part = n - got > (1u << 30) ? 1u << 30 : (unsigned)(n - got);
            int k = gzread(s->gz, (char *)buf + got, part);
            if (k < 0) return -1;
            if (k == 0) break;
            got += (size_t)k;
        }
        int err;
        gzerror(s->gz, &err);
        return err == Z_OK || err == Z_BUF_ERROR ? (long long)got : -1;
    }
    if (!s->zinit) {
        if (inflateInit2(&s->z, 15 + 16) != Z_OK) return -1;
        s->zinit = true;
        s->z.next_in = (Bytef *)s->mem;
        s->z.avail_in = s->mem_size > UINT32_MAX ? UINT32_MAX : (uInt)s->mem_size;
    }
    while (got < n && !s->zdone) {
        size_t part = n - got > UINT32_MAX ? UINT32_MAX : n - got;
        s->z.next_out = (Bytef *)buf + got;
        s->z.avail_out = (uInt)part;
        int rc = inflate(&s->z, Z_NO_FLUSH);
        got += part - s->z.avail_out;
        /* refill avail_in from the buffer beyond the first 4 GiB */
        size_t used = (size_t)(s->z.next_in - s->mem);
        if (s->z.avail_in == 0 && used < s->mem_size)
            s->z.avail_in = s->mem_size - used > UINT32_MAX ? UINT32_MAX
                                                             : (uInt)(s->mem_size - used);
        if (rc == Z_STREAM_END) {
            if (bvox__is_gzip(s->z.next_in, s->z.avail_in) && inflateReset(&s->z) == Z_OK)
                continue;
            s->zdone = true;
        } else if (rc == Z_BUF_ERROR && s->z.avail_in == 0) {
            return -1; /* the stream ends mid-member: truncated */
        } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
            return -1;
        }
    }
    return (long long)got;
}

static bvox_status corrupt(const char *name)
{
    return bvox__fail(BVOX_EFORMAT, "%s: corrupt gzip data", name);
}

/* Read a NIfTI-1 file from src, slices inflated a few at a time into a
 * bounded buffer and binarised as they come (bvox__bin_stream): the volume's
 * bits plus at most 64 slices of samples, never the whole inflated file.
 * file_size is the size of a plain file (exact messages for a short one),
 * gz_size that of a gzip stream (the other is UINT64_MAX). */
static bvox_status read_streamed(nsrc *src, const char *name, uint64_t file_size,
                                 uint64_t gz_size, const bvox_read_opts *opts,
                                 bvox_volume **out)
{
    *out = NULL;
    uint8_t head[MIN_VOX_OFFSET];
    long long got = src_read(src, head, sizeof head);
    if (got < 0) return corrupt(name);
    header hd;
    bvox_status st = parse_header(head, (size_t)got, name, &hd);
    if (st) return st;
    if (file_size != UINT64_MAX && hd.vox_offset > file_size)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: vox_offset %llu is beyond the end of the file (%llu bytes)", name,
                          (unsigned long long)hd.vox_offset, (unsigned long long)file_size);
    if (file_size != UINT64_MAX && hd.data_bytes > file_size - hd.vox_offset)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: truncated: header claims %llu bytes of voxel data, file has %llu",
                          name, (unsigned long long)hd.data_bytes,
                          (unsigned long long)(file_size - hd.vox_offset));
    /* deflate compresses at most 1032:1, so a short stream is found out
     * before anything is allocated */
    uint64_t most = gz_size > UINT64_MAX / 1032 - 65536 ? UINT64_MAX : gz_size * 1032 + 65536;
    if (gz_size != UINT64_MAX && hd.data_bytes > most - hd.vox_offset)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: truncated: header claims %llu bytes of voxel data, a gzip "
                          "stream of %llu bytes holds at most %llu",
                          name, (unsigned long long)hd.data_bytes, (unsigned long long)gz_size,
                          (unsigned long long)(most - hd.vox_offset));
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = hd.dims;
    g.dtype = hd.dtype;
    g.byteswap = hd.swap && hd.elem > 1;
    g.slope = hd.slope;
    g.inter = hd.inter;
    g.geom = hd.geom;
    bvox__bin_stream *bs;
    st = bvox__bin_stream_begin(&g, opts ? &opts->binarize : NULL, name, &bs);
    if (st) return st;
    /* a few slices per read: at least 1 MiB when slices are small, at most 64 */
    size_t slice = bvox__bin_stream_slice_bytes(bs);
    size_t k = ((size_t)1 << 20) / slice;
    k = k < 1 ? 1 : k > 64 ? 64 : k;
    size_t buf_bytes = k * slice;
    uint8_t *buf = bvox__alloc(buf_bytes, false, "slice buffer", &st);
    if (!buf) {
        bvox__bin_stream_abort(bs);
        bvox__error_prefix(name);
        return st;
    }
    /* skip the extensions between the header and vox_offset */
    uint64_t at = (uint64_t)got, data_got = 0;
    while (!st && at < hd.vox_offset) {
        size_t want = hd.vox_offset - at < buf_bytes ? (size_t)(hd.vox_offset - at) : buf_bytes;
        long long r = src_read(src, buf, want);
        if (r < 0) st = corrupt(name);
        else if ((size_t)r < want)
            st = bvox__fail(BVOX_EFORMAT, "%s: vox_offset %llu is beyond the end of the file "
                            "(%llu bytes)", name, (unsigned long long)hd.vox_offset,
                            (unsigned long long)(at + (uint64_t)r));
        at += r > 0 ? (uint64_t)r : 0;
    }
    for (size_t z = 0; !st && z < (size_t)hd.dims.nz; z += k) {
        size_t n = (size_t)hd.dims.nz - z < k ? (size_t)hd.dims.nz - z : k;
        long long r = src_read(src, buf, n * slice);
        if (r >= 0) data_got += (uint64_t)r;
        if (r < 0) st = corrupt(name);
        else if ((size_t)r < n * slice)
            st = bvox__fail(BVOX_EFORMAT,
                            "%s: truncated: header claims %llu bytes of voxel data, file has "
                            "%llu",
                            name, (unsigned long long)hd.data_bytes,
                            (unsigned long long)data_got);
        else bvox__bin_stream_slices(bs, buf, n);
        if (!st) st = bvox__progress_steps((int64_t)(z + n), hd.dims.nz);
    }
    /* A single volume's stream may carry a little padding after the data;
     * much more is a "zip bomb" (inflated only this far: bounded work). */
    if (!st && gz_size != UINT64_MAX && !hd.more_volumes) {
        uint64_t extra = 0;
        while (!st && extra <= GZ_SLACK) {
            long long r = src_read(src, buf, buf_bytes < GZ_SLACK + 1 ? buf_bytes : GZ_SLACK + 1);
            if (r < 0) st = corrupt(name);
            if (r <= 0) break;
            extra += (uint64_t)r;
        }
        if (!st && extra > GZ_SLACK)
            st = bvox__fail(BVOX_ETOOBIG, "%s: the gzip stream holds far more than the %llu "
                            "bytes of voxel data its header claims", name,
                            (unsigned long long)hd.data_bytes);
    }
    bvox__free(buf, buf_bytes);
    if (st) {
        bvox__bin_stream_abort(bs);
        return st;
    }
    return bvox__bin_stream_finish(bs, out);
}

static bvox_status nifti_read_path(const char *path, const bvox_read_opts *opts,
                                   bvox_volume **out)
{
    *out = NULL;
    int fd = -1;
    struct stat sb;
    /* Otsu (every sample before the first comparison) and anything that is
     * not a regular file go the whole-file way */
    if (bvox__bin_stream_ok(opts ? &opts->binarize : NULL)) {
        fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK); /* a FIFO must not block here */
        if (fd >= 0 && (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode))) {
            close(fd);
            fd = -1;
        }
    }
    if (fd < 0) {
        bvox__bytes file;
        bvox_status st = bvox__read_file(path, &file);
        if (st) return st;
        st = nifti_read_memory(file.data, file.size, path, opts, out);
        bvox__bytes_release(&file);
        return st;
    }
    uint8_t magic[2] = {0, 0};
    bool gzip = pread(fd, magic, 2, 0) == 2 && bvox__is_gzip(magic, 2);
    nsrc src;
    memset(&src, 0, sizeof src);
    src.gz = gzdopen(fd, "rb");
    if (!src.gz) {
        close(fd);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory opening the file", path);
    }
    gzbuffer(src.gz, 1u << 17);
    uint64_t size = (uint64_t)sb.st_size;
    bvox_status st = read_streamed(&src, path, gzip ? UINT64_MAX : size,
                                   gzip ? size : UINT64_MAX, opts, out);
    gzclose_r(src.gz);
    return st;
}

/* ------------------------------------------------------------------ writing */

static void put16(uint8_t *h, size_t off, int16_t v) { memcpy(h + off, &v, 2); }
static void put32(uint8_t *h, size_t off, int32_t v) { memcpy(h + off, &v, 4); }
static void putf(uint8_t *h, size_t off, double v)
{
    float f = (float)v;
    memcpy(h + off, &f, 4);
}

/* Quaternion (b, c, d) and qfac of the rotation part of a direction matrix, as
 * nifti1_io's nifti_mat44_to_quatern: the columns are made orthonormal first
 * (Gram-Schmidt) and a negative determinant goes into qfac (third column
 * flipped), since a quaternion can only express a proper rotation. */
static void rot_to_quatern(const double dir[9], double q[3], double *qfac)
{
    double c[3][3]; /* c[j] = column j */
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) c[j][i] = dir[i * 3 + j];
    for (int j = 0; j < 3; j++) {
        for (int k = 0; k < j; k++) {
            double d = c[j][0] * c[k][0] + c[j][1] * c[k][1] + c[j][2] * c[k][2];
            for (int i = 0; i < 3; i++) c[j][i] -= d * c[k][i];
        }
        double n = sqrt(c[j][0] * c[j][0] + c[j][1] * c[j][1] + c[j][2] * c[j][2]);
        if (!(n > 1e-12)) { /* degenerate: fall back to the identity */
            q[0] = q[1] = q[2] = 0;
            *qfac = 1;
            return;
        }
        for (int i = 0; i < 3; i++) c[j][i] /= n;
    }
    double det = c[0][0] * (c[1][1] * c[2][2] - c[2][1] * c[1][2]) -
                 c[1][0] * (c[0][1] * c[2][2] - c[2][1] * c[0][2]) +
                 c[2][0] * (c[0][1] * c[1][2] - c[1][1] * c[0][2]);
    *qfac = det < 0 ? -1.0 : 1.0;
    if (det < 0)
        for (int i = 0; i < 3; i++) c[2][i] = -c[2][i];
#define R(i, j) c[(j)][(i)]
    double a = R(0, 0) + R(1, 1) + R(2, 2) + 1.0, b, cc, d;
    if (a > 0.5) {
        a = 0.5 * sqrt(a);
        b = 0.25 * (R(2, 1) - R(1, 2)) / a;
        cc = 0.25 * (R(0, 2) - R(2, 0)) / a;
        d = 0.25 * (R(1, 0) - R(0, 1)) / a;
    } else {
        double xd = 1.0 + R(0, 0) - (R(1, 1) + R(2, 2));
        double yd = 1.0 + R(1, 1) - (R(0, 0) + R(2, 2));
        double zd = 1.0 + R(2, 2) - (R(0, 0) + R(1, 1));
        if (xd > 1.0) {
            b = 0.5 * sqrt(xd);
            cc = 0.25 * (R(0, 1) + R(1, 0)) / b;
            d = 0.25 * (R(0, 2) + R(2, 0)) / b;
            a = 0.25 * (R(2, 1) - R(1, 2)) / b;
        } else if (yd > 1.0) {
            cc = 0.5 * sqrt(yd);
            b = 0.25 * (R(0, 1) + R(1, 0)) / cc;
            d = 0.25 * (R(1, 2) + R(2, 1)) / cc;
            a = 0.25 * (R(0, 2) - R(2, 0)) / cc;
        } else {
            d = 0.5 * sqrt(zd);
            b = 0.25 * (R(0, 2) + R(2, 0)) / d;
            cc = 0.25 * (R(1, 2) + R(2, 1)) / d;
            a = 0.25 * (R(1, 0) - R(0, 1)) / d;
        }
        if (a < 0.0) b = -b, cc = -cc, d = -d;
    }
#undef R
    q[0] = b, q[1] = cc, q[2] = d;
}

void bvox__nifti_header(const bvox_volume *vol, int datatype, int bitpix, double cal_max,
                        int intent, const char *descrip, uint8_t h[BVOX__NIFTI_DATA_OFFSET])
{
    const bvox_geometry *g = &vol->geom;
    memset(h, 0, MIN_VOX_OFFSET);
    int code = 0;
    double scale = 1.0;
    for (size_t u = 0; u < sizeof units / sizeof units[0]; u++)
        if (!strcmp(g->unit, units[u].name)) {
            code = units[u].code;
            scale = units[u].scale;
            break;
        }
    double sp[3], org[3], q[3], qfac;
    for (int i = 0; i < 3; i++) sp[i] = g->spacing[i] * scale, org[i] = g->origin[i] * scale;
    rot_to_quatern(g->direction, q, &qfac);

    put32(h, 0, HDR_SIZE);
    h[38] = 'r'; /* "regular", as Analyze wanted */
    int16_t dim[8] = {3, (int16_t)vol->nx, (int16_t)vol->ny, (int16_t)vol->nz, 1, 1, 1, 1};
    for (int i = 0; i < 8; i++) put16(h, 40 + 2 * (size_t)i, dim[i]);
    put16(h, 68, (int16_t)intent);
    put16(h, 70, (int16_t)datatype);
    put16(h, 72, (int16_t)bitpix);
    putf(h, 76, qfac);
    for (int i = 0; i < 3; i++) putf(h, 80 + 4 * (size_t)i, sp[i]);
    for (int i = 3; i < 7; i++) putf(h, 80 + 4 * (size_t)i, 1.0);
    putf(h, 108, MIN_VOX_OFFSET);
    putf(h, 112, 1.0); /* scl_slope: values are stored exactly */
    putf(h, 116, 0.0);
    h[123] = (uint8_t)code;
    putf(h, 124, cal_max); /* cal_max / cal_min: a viewer's display range */
    putf(h, 128, 0.0);
    put32(h, 140, 1);
    snprintf((char *)h + 148, 80, "bvox %s %s", BVOX_VERSION, descrip);
    /* the volume's space (an MNI atlas stays MNI), else 1 (scanner-based);
     * the same code for both, so readers that prefer either agree */
    int16_t space = g->space >= 1 && g->space <= 4 ? (int16_t)g->space : 1;
    put16(h, 252, space);
    put16(h, 254, space);
    for (int i = 0; i < 3; i++) putf(h, 256 + 4 * (size_t)i, q[i]);
    for (int i = 0; i < 3; i++) putf(h, 268 + 4 * (size_t)i, org[i]);
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++)
            putf(h, 280 + 16 * (size_t)r + 4 * (size_t)c, g->direction[r * 3 + c] * sp[c]);
        putf(h, 280 + 16 * (size_t)r + 12, org[r]);
    }
    memcpy(h + 344, "n+1", 4);
    /* bytes 348..351: no extensions */
}

bool bvox__path_has_gz(const char *path)
{
    return bvox__ends_with_ci(path, ".gz");
}

static bvox_status nifti_write_limits(const char *path, bvox_dims d)
{
    if (d.nx > INT16_MAX || d.ny > INT16_MAX || d.nz > INT16_MAX)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: NIfTI-1 dimensions are at most 32767 per axis (volume is %ld x "
                          "%ld x %ld)",
                          path, (long)d.nx, (long)d.ny, (long)d.nz);
    return BVOX_OK;
}

/* The header of a .nii or .nii.gz: its first 348 bytes, inflated if need be. */
static bvox_status nifti_probe_dims(const char *path, const bvox_read_opts *opts,
                                    bvox_dims *dims)
{
    (void)opts;
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK); /* a FIFO must not block here */
    struct stat sb;
    if (fd < 0 || fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        if (fd >= 0) close(fd);
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: not a regular file", path);
    }
    gzFile gz = gzdopen(fd, "rb");
    if (!gz) {
        close(fd);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory opening the file", path);
    }
    uint8_t head[HDR_SIZE];
    int got = gzread(gz, head, sizeof head);
    gzclose_r(gz);
    header hd;
    bvox_status st = parse_header(head, got > 0 ? (size_t)got : 0, path, &hd);
    if (!st) *dims = hd.dims;
    return st;
}

static bvox_status nifti_write_path(const char *path, const bvox_volume *vol,
                                    const bvox_write_opts *opts)
{
    (void)opts;
    bvox_status lim = nifti_write_limits(path, bvox_volume_dims(vol));
    if (lim) return lim;
    /* the header stores sizes and positions as 32-bit floats: one that does
     * not fit would be read back as 1 (or inf), silently */
    const bvox_geometry *g = &vol->geom;
    for (int i = 0; i < 3; i++) {
        float sp = (float)g->spacing[i], org = (float)g->origin[i];
        if (!isfinite(sp) || !(sp > 0) || !isfinite(org))
            return bvox__fail(BVOX_EUNSUPPORTED,
                              "%s: NIfTI-1 stores voxel size and origin as 32-bit floats; "
                              "%s %g along %c does not fit",
                              path, !isfinite(sp) || !(sp > 0) ? "a voxel size of" : "an origin of",
                              !isfinite(sp) || !(sp > 0) ? g->spacing[i] : g->origin[i], "xyz"[i]);
    }
    uint8_t h[MIN_VOX_OFFSET];
    bvox__nifti_header(vol, DT_UINT8, 8, 1.0, 0, "binary volume", h);
    return bvox__write_byte_slices(path, vol, bvox__path_has_gz(path), h, sizeof h);
}

static const char *const nifti_extensions[] = {".nii.gz", ".nii", NULL};

const bvox__format bvox__format_nifti = {
    "nifti", nifti_extensions, nifti_sniff, nifti_read_memory, nifti_read_path,
    nifti_write_path, nifti_probe_dims, nifti_write_limits, nifti_gray_memory,
};
