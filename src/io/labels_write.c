/*
 * labels_write.c — label volumes written in the formats segmentation tools
 * read label maps from (bvox_write_labels): NIfTI (nifti_labels.c), NRRD
 * (.nrrd: gzip data after the header; .nhdr: header + BASE.raw), 3D Slicer
 * segmentations (.seg.nrrd: NRRD plus the segments' names, colours and
 * extents, seg_nrrd_write.c) and MetaImage (.mha: zlib data after the header;
 * .mhd: header + BASE.zraw). Headers are the binary writers' own
 * (nrrd_write.c, metaimage.c) with the label type instead of uint8, so both
 * carry the same geometry the same way.
 *
 * Samples keep an integer type: the one asked for (the input's, so that an
 * int16 atlas stays int16) or the smallest unsigned one that holds the
 * largest label (label_samples.c). They go through the temporary-file
 * sink: a failure leaves no partial file, and a detached data file is
 * written before its header and removed if the header fails.
 */
#include "io.h"
#include "common/names.h"
#include "common/strbuf.h"

#include <string.h>

/* header (plain) then the samples, compressed by `compress` (0 none, 1
 * gzip, BVOX__SINK_ZLIB), into path: the whole file or nothing. */
static bvox_status write_file(const char *path, const void *header, size_t header_size,
                              int compress, const uint32_t *labels, size_t n, bvox_dtype t)
{
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, 0, &s);
    if (st) return st;
    if (header_size) st = bvox__sink_write(&s, header, header_size);
    if (!st && labels && compress) st = bvox__sink_compress(&s, compress);
    if (!st && labels) st = bvox__write_label_samples(&s, labels, n, t, false);
    if (st) {
        bvox__sink_abort(&s);
        return st;
    }
    return bvox__sink_commit(&s);
}

/* The data into data_path first, so that the header never names a missing
 * file, then the header into path; on failure neither is left behind. */
static bvox_status write_pair(const char *path, const char *data_path, const char *header,
                              size_t header_size, int compress, const uint32_t *labels,
                              size_t n, bvox_dtype t)
{
    bvox_status st = write_file(data_path, NULL, 0, compress, labels, n, t);
    if (st) return st;
    return bvox__write_header_after(path, data_path, header, header_size);
}

static const char *const nrrd_types[] = {"uint8",  "int8",  "uint16", "int16",
                                         "uint32", "int32", "uint64", "int64"};
static const char *const mha_types[] = {"MET_UCHAR", "MET_CHAR", "MET_USHORT",
                                        "MET_SHORT", "MET_UINT", "MET_INT",
                                        "MET_ULONG_LONG", "MET_LONG_LONG"};

static bvox_status write_nrrd(const char *path, const bvox_volume *like, const uint32_t *labels,
                              size_t n, bvox_dtype t, bool seg, const bvox_label_table *table)
{
    bool detached = bvox__ends_with_ci(path, ".nhdr");
    char data_path[4096];
    const char *base = NULL;
    bvox_status st = BVOX_OK;
    if (detached && (st = bvox__detached_name(path, 5, ".raw", data_path, sizeof data_path, &base)))
        return st;
    bvox__strbuf hdr = {0};
    bvox__nrrd_describe(like, nrrd_types[t], !detached, base, &hdr);
    if (seg) st = bvox__seg_nrrd_describe(like, labels, table, &hdr);
    bvox__sb_puts(&hdr, "\n");
    if (!st && hdr.failed) st = bvox__fail(BVOX_ENOMEM, "%s: NRRD header: out of memory", path);
    if (!st)
        st = detached ? write_pair(path, data_path, hdr.data, hdr.len, 0, labels, n, t)
                      : write_file(path, hdr.data, hdr.len, 1, labels, n, t);
    bvox__sb_free(&hdr);
    return st;
}

static bvox_status write_mha(const char *path, const bvox_volume *like, const uint32_t *labels,
                             size_t n, bvox_dtype t)
{
    const char *unit = bvox_volume_geometry(like)->unit;
    if (unit[0] && strcmp(unit, "mm"))
        bvox__warn("%s: MetaImage has no unit field (ITK reads mm); the voxel size is written "
                   "in %s",
                   path, unit);
    char hdr[2048];
    if (!bvox__ends_with_ci(path, ".mhd")) {
        int len = bvox__mha_describe(like, mha_types[t], "LOCAL", hdr, sizeof hdr);
        return write_file(path, hdr, (size_t)len, BVOX__SINK_ZLIB, labels, n, t);
    }
    char data_path[4096];
    const char *base;
    bvox_status st = bvox__detached_name(path, 4, ".zraw", data_path, sizeof data_path, &base);
    if (st) return st;
    int len = bvox__mha_describe(like, mha_types[t], base, hdr, sizeof hdr);
    return write_pair(path, data_path, hdr, (size_t)len, BVOX__SINK_ZLIB, labels, n, t);
}

bvox_status bvox_write_labels(const char *path, const bvox_volume *like, const uint32_t *labels,
                              int dtype, const bvox_label_table *table)
{
    bvox__clear_error();
    if (!path || !like || !labels)
        return bvox__fail(BVOX_EINVAL, "bvox_write_labels: NULL argument");
    const char *fmt = bvox_format_for_path(path);
    bool seg = bvox__ends_with_ci(path, ".seg.nrrd");
    bool nrrd = fmt && !strcmp(fmt, "nrrd"), mha = fmt && !strcmp(fmt, "metaimage");
    bool nifti = fmt && !strcmp(fmt, "nifti");
    if (!nrrd && !mha && !nifti)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: label volumes are written as NIfTI (.nii, .nii.gz), NRRD (.nrrd, "
                          ".nhdr, .seg.nrrd) or MetaImage (.mha, .mhd)",
                          path);
    size_t n = (size_t)like->nx * (size_t)like->ny * (size_t)like->nz;
    bvox_dtype t;
    uint32_t max;
    bvox_status st = bvox__label_dtype(path, labels, n, dtype, &t, &max);
    if (st) return st;
    if (nifti) return bvox__write_labels_nifti(path, like, labels, t, max);
    st = mha ? write_mha(path, like, labels, n, t) : write_nrrd(path, like, labels, n, t, seg, table);
    if (st) bvox__error_prefix(path);
    return st;
}
