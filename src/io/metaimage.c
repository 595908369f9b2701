/*
 * metaimage.c — MetaImage volumes (ITK's MetaIO): `.mha` (header and data in
 * one file, "ElementDataFile = LOCAL") and `.mhd` (header only; the data in
 * a .raw or zlib-compressed .zraw file beside it), read and written.
 *
 * The header is "Key = Value" lines ending with ElementDataFile, after which
 * a LOCAL file's data begin. Read: NDims 2 or 3, DimSize, ElementType
 * MET_CHAR..MET_DOUBLE (one channel), ElementSpacing (else ElementSize),
 * Offset (or Position, Origin), TransformMatrix (or Rotation, Orientation:
 * the direction of each axis in turn, as ITK writes it), BinaryDataByteOrderMSB
 * (or ElementByteOrderMSB), CompressedData (zlib), CompressedDataSize and
 * HeaderSize (-1: the data are the last bytes of the file). Positions are in
 * ITK's LPS frame, turned into bvox's RAS one (as the NRRD reader does); the
 * unit is mm, ITK's. ASCII data, several channels, LIST and numbered file
 * patterns are refused. Sizes are checked (bvox__check_dims, overflow-safe
 * products) before anything they drive is allocated, and a compressed
 * stream is inflated no further than the samples the header announces.
 *
 * Written: one byte per voxel (MET_UCHAR 0/1), zlib-compressed, the geometry
 * in LPS (a unit other than mm is warned about: the format cannot hold it); `.mhd` gets its data in BASE.zraw, written before the header.
 * Label volumes (labels_write.c) share the header with their own ElementType.
 */
#include "io.h"
#include "common/names.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct mha_header {
    int ndims;
    int64_t sizes[3];
    bvox_dtype dtype;
    bool have_type, have_sizes, big_endian, compressed, have_spacing, have_size, have_origin,
        have_matrix;
    double spacing[3], elsize[3], origin[3], matrix[9];
    int64_t header_size; /* bytes to skip in a separate data file; -1: data at the end */
    int64_t compressed_size; /* 0: to the end */
    char data_file[512];     /* "LOCAL" or a file name */
    size_t data_start;       /* offset of LOCAL data */
} mha_header;

static const char *const mha_keys[] = {"ObjectType", "NDims", "DimSize", "ElementType", NULL};

/* A MetaImage header starts with one of its usual first keys. */
static int mha_sniff(const uint8_t *d, size_t n)
{
    for (const char *const *k = mha_keys; *k; k++) {
        size_t len = strlen(*k);
        if (n > len + 1 && !memcmp(d, *k, len) && (d[len] == ' ' || d[len] == '='))
            return 1;
    }
    return 0;
}

static char *trim(char *s)
{
    while (*s && isspace((unsigned char)*s)) s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = '\0';
    return s;
}

static int parse_type(const char *v, bvox_dtype *t)
{
    static const struct {
        const char *name;
        bvox_dtype t;
    } types[] = {
        {"MET_CHAR", BVOX_DT_I8},       {"MET_UCHAR", BVOX_DT_U8},
        {"MET_SHORT", BVOX_DT_I16},     {"MET_USHORT", BVOX_DT_U16},
        {"MET_INT", BVOX_DT_I32},       {"MET_UINT", BVOX_DT_U32},
        {"MET_LONG", BVOX_DT_I32},      {"MET_ULONG", BVOX_DT_U32}, /* 4 bytes in MetaIO */
        {"MET_LONG_LONG", BVOX_DT_I64}, {"MET_ULONG_LONG", BVOX_DT_U64},
        {"MET_FLOAT", BVOX_DT_F32},     {"MET_DOUBLE", BVOX_DT_F64},
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcasecmp(v, types[i].name)) {
            *t = types[i].t;
            return 1;
        }
    return 0;
}

/* n finite numbers separated by spaces, nothing after them. */
static int parse_numbers(const char *v, int n, double *out)
{
    const char *p = v;
    for (int i = 0; i < n; i++) {
        char *e;
        out[i] = strtod(p, &e);
        if (e == p || !isfinite(out[i])) return 0;
        p = e;
    }
    while (*p && isspace((unsigned char)*p)) p++;
    return *p == '\0';
}

static int is_true(const char *v) { return !strcasecmp(v, "true") || !strcmp(v, "1"); }

static bvox_status parse_header(const uint8_t *data, size_t size, const char *name,
                                mha_header *h)
{
    memset(h, 0, sizeof *h);
    if (!mha_sniff(data, size)) return bvox__fail(BVOX_EFORMAT, "%s: not a MetaImage file", name);
    size_t pos = 0, lineno = 0;
    char line[1024];
    while (pos < size && !h->data_file[0]) {
        size_t end = pos;
        while (end < size && data[end] != '\n') end++;
        size_t n = end - pos;
        if (n >= sizeof line)
            return bvox__fail(BVOX_EFORMAT, "%s: MetaImage header line %zu is too long", name,
                              lineno + 1);
        memcpy(line, data + pos, n);
        line[n] = '\0';
        if (memchr(line, '\0', n))
            return bvox__fail(BVOX_EFORMAT, "%s: MetaImage header line %zu is not text", name,
                              lineno + 1);
        pos = end < size ? end + 1 : end;
        lineno++;
        char *eq = strchr(line, '=');
        if (!eq) {
            if (*trim(line)) /* blank lines are tolerated */
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage header line %zu is not 'Key = Value'",
                                  name, lineno);
            continue;
        }
        *eq = '\0';
        char *key = trim(line), *v = trim(eq + 1);
        int nd = h->ndims ? h->ndims : 3;
        if (!strcasecmp(key, "ObjectType")) {
            if (strcasecmp(v, "Image"))
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: MetaImage ObjectType '%s' (bvox reads Image)",
                                  name, v);
        } else if (!strcasecmp(key, "NDims")) {
            h->ndims = atoi(v);
            if (h->ndims < 2 || h->ndims > 3)
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: MetaImage NDims %s (bvox reads 2D and 3D images)", name, v);
        } else if (!strcasecmp(key, "DimSize")) {
            if (!h->ndims) return bvox__fail(BVOX_EFORMAT, "%s: DimSize before NDims", name);
            char *p = v;
            for (int i = 0; i < h->ndims; i++) {
                char *e;
                long long s = strtoll(p, &e, 10);
                if (e == p || s < 1 || s > BVOX_MAX_DIM)
                    return bvox__fail(BVOX_EFORMAT, "%s: MetaImage DimSize '%s' (each 1..%d)",
                                      name, v, BVOX_MAX_DIM);
                h->sizes[i] = s;
                p = e;
            }
            if (*trim(p)) return bvox__fail(BVOX_EFORMAT, "%s: MetaImage DimSize '%s'", name, v);
            h->have_sizes = true;
        } else if (!strcasecmp(key, "ElementType")) {
            if (!parse_type(v, &h->dtype))
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: MetaImage ElementType '%s' is not supported",
                                  name, v);
            h->have_type = true;
        } else if (!strcasecmp(key, "ElementNumberOfChannels")) {
            if (atoi(v) != 1)
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: MetaImage with %s channels (bvox reads scalar images)", name,
                                  v);
        } else if (!strcasecmp(key, "BinaryData")) {
            if (!is_true(v))
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: MetaImage ASCII data are not supported",
                                  name);
        } else if (!strcasecmp(key, "BinaryDataByteOrderMSB") ||
                   !strcasecmp(key, "ElementByteOrderMSB")) {
            h->big_endian = is_true(v);
        } else if (!strcasecmp(key, "CompressedData")) {
            h->compressed = is_true(v);
        } else if (!strcasecmp(key, "CompressedDataSize")) {
            h->compressed_size = atoll(v);
            if (h->compressed_size < 0)
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage CompressedDataSize %s", name, v);
        } else if (!strcasecmp(key, "HeaderSize")) {
            h->header_size = atoll(v);
            if (h->header_size < -1 || h->header_size > (int64_t)1 << 40)
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage HeaderSize %s", name, v);
        } else if (!strcasecmp(key, "ElementSpacing") || !strcasecmp(key, "ElementSize")) {
            double *dst = !strcasecmp(key, "ElementSpacing") ? h->spacing : h->elsize;
            if (!parse_numbers(v, nd, dst))
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage %s '%s'", name, key, v);
            for (int i = 0; i < nd; i++)
                if (!(dst[i] > 0))
                    return bvox__fail(BVOX_EFORMAT, "%s: MetaImage %s '%s' (must be > 0)", name,
                                      key, v);
            if (dst == h->spacing) h->have_spacing = true;
            else h->have_size = true;
        } else if (!strcasecmp(key, "Offset") || !strcasecmp(key, "Position") ||
                   !strcasecmp(key, "Origin")) {
            if (!parse_numbers(v, nd, h->origin))
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage %s '%s'", name, key, v);
            h->have_origin = true;
        } else if (!strcasecmp(key, "TransformMatrix") || !strcasecmp(key, "Rotation") ||
                   !strcasecmp(key, "Orientation")) {
            if (!parse_numbers(v, nd * nd, h->matrix))
                return bvox__fail(BVOX_EFORMAT, "%s: MetaImage %s '%s'", name, key, v);
            h->have_matrix = true;
        } else if (!strcasecmp(key, "ElementDataFile")) {
            if (!*v || !strncasecmp(v, "LIST", 4) || strchr(v, '%') ||
                strlen(v) >= sizeof h->data_file)
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: MetaImage ElementDataFile '%s' (bvox reads LOCAL or one "
                                  "data file)",
                                  name, v);
            strcpy(h->data_file, v);
        }
        /* other keys (AnatomicalOrientation, CenterOfRotation, ElementMin/Max,
           ...) do not change the voxels */
    }
    if (!h->ndims || !h->have_sizes || !h->have_type || !h->data_file[0])
        return bvox__fail(BVOX_EFORMAT, "%s: MetaImage header lacks %s", name,
                          !h->ndims        ? "NDims"
                          : !h->have_sizes ? "DimSize"
                          : !h->have_type  ? "ElementType"
                                           : "ElementDataFile");
    if (h->ndims == 2) h->sizes[2] = 1;
    h->data_start = pos;
    return BVOX_OK;
}

static void set_geometry(const mha_header *h, bvox_geometry *g)
{
    *g = bvox_geometry_default();
    int nd = h->ndims;
    for (int i = 0; i < nd; i++) {
        if (h->have_spacing) g->spacing[i] = h->spacing[i];
        else if (h->have_size) g->spacing[i] = h->elsize[i];
        if (h->have_origin) g->origin[i] = h->origin[i];
    }
    if (h->have_matrix) {
        double d[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (int a = 0; a < nd; a++) { /* axis a's direction: matrix[a*nd .. a*nd+nd-1] */
            double n = 0;
            for (int r = 0; r < nd; r++) n += h->matrix[a * nd + r] * h->matrix[a * nd + r];
            n = sqrt(n);
            if (!(n > 0)) continue;
            for (int r = 0; r < 3; r++) d[r * 3 + a] = r < nd ? h->matrix[a * nd + r] / n : 0;
        }
        double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) +
                     d[2] * (d[3] * d[7] - d[4] * d[6]);
        if (fabs(det) > 1e-6) memcpy(g->direction, d, sizeof d);
    }
    bvox__geometry_flip_lps(g);
    strcpy(g->unit, "mm");
}

static bvox_status mha_gray_memory(const uint8_t *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox__gray *g)
{
    (void)opts;
    bvox__gray_init(g);
    if (!name) name = "input";
    mha_header h;
    bvox_status st = parse_header(data, size, name, &h);
    if (st) return st;
    bvox_dims d = {(int32_t)h.sizes[0], (int32_t)h.sizes[1], (int32_t)h.sizes[2]};
    size_t words_bytes, n, need, elem = bvox_dtype_size(h.dtype);
    st = bvox__check_dims(d, name, &words_bytes);
    if (st) return st;
    if (!bvox__mul_size((size_t)d.nx * (size_t)d.ny, (size_t)d.nz, &n) ||
        !bvox__mul_size(n, elem, &need))
        return bvox__fail(BVOX_ETOOBIG, "%s: MetaImage DimSize overflows", name);

    bvox__bytes detached = {0}, unz = {0};
    const uint8_t *src = data + h.data_start;
    size_t avail = size - h.data_start;
    bool local = !strcasecmp(h.data_file, "LOCAL");
    if (!local) {
        st = bvox__read_beside(name, h.data_file, &detached);
        if (st) return st;
        src = detached.data;
        avail = detached.size;
        size_t skip = 0;
        if (h.header_size == -1 && !h.compressed) skip = avail >= need ? avail - need : 0;
        else if (h.header_size > 0) skip = (uint64_t)h.header_size <= avail ? (size_t)h.header_size
                                                                         : avail;
        src += skip;
        avail -= skip;
    }
    if (h.compressed) {
        size_t csize = avail;
        if (h.compressed_size > 0 && (uint64_t)h.compressed_size < avail)
            csize = (size_t)h.compressed_size;
        st = bvox__gunzip(src, csize, name, need, &unz);
        if (st) goto fail;
        if (unz.size < need) {
            st = bvox__fail(BVOX_EFORMAT,
                            "%s: truncated: MetaImage DimSize needs %zu bytes of samples, the "
                            "compressed data hold %zu",
                            name, need, unz.size);
            goto fail;
        }
        g->data = unz.data;
        g->owned = unz.data;
        g->owned_bytes = unz.alloc_bytes;
        unz.data = NULL;
        if (detached.data) bvox__bytes_release(&detached);
    } else {
        if (need > avail) {
            st = bvox__fail(BVOX_EFORMAT,
                            "%s: truncated: MetaImage DimSize %ld x %ld x %ld of %s needs %zu "
                            "bytes of samples, %zu remain",
                            name, (long)d.nx, (long)d.ny, (long)d.nz, bvox_dtype_name(h.dtype),
                            need, avail);
            goto fail;
        }
        if (detached.data) { /* the gray keeps the data file */
            g->owned = detached.data;
            g->owned_bytes = detached.alloc_bytes;
        }
        g->data = src;
    }
    g->dims = d;
    g->dtype = h.dtype;
    {
        const uint16_t probe = 1;
        bool host_big = *(const uint8_t *)&probe == 0;
        g->byteswap = elem > 1 && h.big_endian != host_big;
    }
    set_geometry(&h, &g->geom);
    return BVOX_OK;
fail:
    if (unz.data) bvox__bytes_release(&unz);
    if (detached.data) bvox__bytes_release(&detached);
    bvox__gray_init(g);
    return st;
}

static bvox_status mha_read_memory(const uint8_t *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "input";
    bvox__gray g;
    bvox_status st = mha_gray_memory(data, size, name, opts, &g);
    if (st) return st;
    st = bvox__binarize(&g, opts ? &opts->binarize : NULL, name, out);
    bvox__gray_release(&g);
    return st;
}

/* ---------------------------------------------------------------- writer */

int bvox__mha_describe(const bvox_volume *vol, const char *element_type, const char *data_file,
                       char *buf, size_t cap)
{
    bvox_geometry g = *bvox_volume_geometry(vol);
    bvox__geometry_flip_lps(&g);
    const double *m = g.direction;
    bvox_dims d = bvox_volume_dims(vol);
    return snprintf(buf, cap,
                    "ObjectType = Image\nNDims = 3\nBinaryData = True\n"
                    "BinaryDataByteOrderMSB = False\nCompressedData = True\n"
                    "TransformMatrix = %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n"
                    "Offset = %.17g %.17g %.17g\nCenterOfRotation = 0 0 0\n"
                    "ElementSpacing = %.17g %.17g %.17g\nDimSize = %ld %ld %ld\n"
                    "ElementType = %s\nElementDataFile = %s\n",
                    m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8], g.origin[0],
                    g.origin[1], g.origin[2], g.spacing[0], g.spacing[1], g.spacing[2],
                    (long)d.nx, (long)d.ny, (long)d.nz, element_type, data_file);
}

static bvox_status mha_write_path(const char *path, const bvox_volume *vol,
                                  const bvox_write_opts *opts)
{
    (void)opts;
    const char *unit = bvox_volume_geometry(vol)->unit;
    if (unit[0] && strcmp(unit, "mm"))
        bvox__warn("%s: MetaImage has no unit field (ITK reads mm); the voxel size is written "
                   "in %s",
                   path, unit);
    char hdr[2048];
    if (!bvox__ends_with_ci(path, ".mhd")) {
        int n = bvox__mha_describe(vol, "MET_UCHAR", "LOCAL", hdr, sizeof hdr);
        return bvox__write_byte_slices(path, vol, BVOX__SINK_ZLIB | BVOX__SINK_PLAIN_HEADER, hdr,
                                       (size_t)n);
    }
    char data_path[4096];
    const char *base;
    bvox_status st = bvox__detached_name(path, 4, ".zraw", data_path, sizeof data_path, &base);
    if (st) return st;
    int n = bvox__mha_describe(vol, "MET_UCHAR", base, hdr, sizeof hdr);
    return bvox__write_detached(path, data_path, vol, BVOX__SINK_ZLIB, hdr, (size_t)n);
}

static const char *const mha_extensions[] = {".mha", ".mhd", NULL};

const bvox__format bvox__format_metaimage = {
    "metaimage", mha_extensions, mha_sniff, mha_read_memory, NULL, mha_write_path, NULL, NULL,
    mha_gray_memory,
};
