/*
 * nifti_labels.c — label volumes (0 background, 1..N objects, as
 * bvox_components_labels makes them) written as NIfTI-1, the format atlases
 * and segmentation tools (ITK-SNAP, 3D Slicer, FSL) read label maps from.
 *
 * The header comes from nifti.c's builder (same geometry and units as a
 * binary volume written by bvox_write), with an integer datatype just wide
 * enough: uint16 covers 65535 labels at half the size of uint32; or, through
 * bvox_write_labels, the integer type asked for. Samples are converted a
 * chunk at a time into one small buffer (labels_write.c) and go through the
 * same temporary-file sink as every writer, so a failure leaves no partial
 * file.
 */
#include "io.h"

#include <string.h>

/* NIfTI-1 datatype codes (nifti1.h) by bvox_dtype, integers only */
static const int nifti_codes[] = {2, 256, 512, 4, 768, 8, 1280, 1024};
#define NIFTI_INTENT_LABEL 1002

bvox_status bvox__write_labels_nifti(const char *path, const bvox_volume *like,
                                     const uint32_t *labels, bvox_dtype dtype, uint32_t max)
{
    if (like->nx > INT16_MAX || like->ny > INT16_MAX || like->nz > INT16_MAX)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: NIfTI-1 dimensions are at most 32767 per axis (volume is %ld x "
                          "%ld x %ld)",
                          path, (long)like->nx, (long)like->ny, (long)like->nz);
    /* nx*ny*nz fits: the volume itself was created with these dimensions. */
    size_t n = (size_t)like->nx * (size_t)like->ny * (size_t)like->nz;
    size_t elem = bvox_dtype_size(dtype);
    uint8_t h[BVOX__NIFTI_DATA_OFFSET];
    bvox__nifti_header(like, nifti_codes[dtype], (int)elem * 8, (double)max, NIFTI_INTENT_LABEL,
                       "label volume", h);
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, bvox__path_has_gz(path), &s);
    if (st == BVOX_OK) st = bvox__sink_write(&s, h, sizeof h);
    /* in this CPU's byte order, like the header */
    if (st == BVOX_OK) st = bvox__write_label_samples(&s, labels, n, dtype, true);
    if (st == BVOX_OK) return bvox__sink_commit(&s);
    bvox__sink_abort(&s);
    bvox__error_prefix(path);
    return st;
}

bvox_status bvox_write_labels_nifti(const char *path, const bvox_volume *like,
                                    const uint32_t *labels)
{
    bvox__clear_error();
    if (!path || !like || !labels)
        return bvox__fail(BVOX_EINVAL, "bvox_write_labels_nifti: NULL argument");
    const char *fmt = bvox_format_for_path(path);
    if (!fmt || strcmp(fmt, "nifti") != 0)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: label volumes are written as NIfTI only (.nii or .nii.gz)", path);
    size_t n = (size_t)like->nx * (size_t)like->ny * (size_t)like->nz;
    uint32_t max = 0;
    for (size_t i = 0; i < n; i++) max = labels[i] > max ? labels[i] : max;
    /* uint16 covers 65535 labels at half the size of uint32 (no uint8: files
     * written so far keep their type) */
    return bvox__write_labels_nifti(path, like, labels, max > UINT16_MAX ? BVOX_DT_U32 : BVOX_DT_U16,
                                    max);
}
