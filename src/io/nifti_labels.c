/*
 * nifti_labels.c — label volumes (0 background, 1..N objects, as
 * bvox_components_labels makes them) written as NIfTI-1, the format atlases
 * and segmentation tools (ITK-SNAP, 3D Slicer, FSL) read label maps from.
 *
 * The header comes from nifti.c's builder (same geometry and units as a
 * binary volume written by bvox_write), with an integer datatype just wide
 * enough: uint16 covers 65535 labels at half the size of uint32. Samples are
 * converted (or copied) a chunk at a time into one small buffer and go
 * through the same temporary-file sink as every writer, so a failure leaves
 * no partial file.
 */
#include "io.h"

#include <string.h>

/* NIfTI-1 codes (nifti1.h) */
#define NIFTI_UINT16 512
#define NIFTI_UINT32 768
#define NIFTI_INTENT_LABEL 1002

#define CHUNK_SAMPLES ((size_t)1 << 18)

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
    if (like->nx > INT16_MAX || like->ny > INT16_MAX || like->nz > INT16_MAX)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: NIfTI-1 dimensions are at most 32767 per axis (volume is %ld x "
                          "%ld x %ld)",
                          path, (long)like->nx, (long)like->ny, (long)like->nz);
    /* nx*ny*nz fits: the volume itself was created with these dimensions. */
    size_t n = (size_t)like->nx * (size_t)like->ny * (size_t)like->nz;
    uint32_t max = 0;
    for (size_t i = 0; i < n; i++) max = labels[i] > max ? labels[i] : max;
    int wide = max > UINT16_MAX;
    size_t elem = wide ? 4 : 2;

    uint8_t h[BVOX__NIFTI_DATA_OFFSET];
    bvox__nifti_header(like, wide ? NIFTI_UINT32 : NIFTI_UINT16, (int)elem * 8, (double)max,
                       NIFTI_INTENT_LABEL, "label volume", h);
    size_t chunk = n < CHUNK_SAMPLES ? n : CHUNK_SAMPLES;
    bvox_status st;
    uint16_t *buf = NULL;
    if (!wide) {
        buf = bvox__alloc(chunk * sizeof *buf, false, "label buffer", &st);
        if (!buf) {
            bvox__error_prefix(path);
            return st;
        }
    }
    bvox__sink s;
    st = bvox__sink_open(path, bvox__path_has_gz(path), &s);
    if (st == BVOX_OK) st = bvox__sink_write(&s, h, sizeof h);
    for (size_t i = 0; st == BVOX_OK && i < n; i += chunk) {
        size_t m = n - i < chunk ? n - i : chunk;
        if (wide) { /* stored as they are, in this CPU's byte order like the header */
            st = bvox__sink_write(&s, labels + i, m * elem);
            continue;
        }
        for (size_t k = 0; k < m; k++) buf[k] = (uint16_t)labels[i + k];
        st = bvox__sink_write(&s, buf, m * elem);
    }
    if (buf) bvox__free(buf, chunk * sizeof *buf);
    if (st == BVOX_OK) return bvox__sink_commit(&s);
    bvox__sink_abort(&s);
    return st;
}
