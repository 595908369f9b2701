/*
 * nifti_ref.h — an independent, deliberately slow NIfTI-1 reader for tests:
 * zlib's gzopen/gzread (which also reads uncompressed files), header fields
 * read one by one at their offsets, every sample converted to a double with
 * scl_slope/scl_inter applied. Shares no code with src/io/nifti.c, so a test
 * comparing the two catches mistakes made twice the same way only if they were
 * made independently twice.
 */
#ifndef BVOX_NIFTI_REF_H
#define BVOX_NIFTI_REF_H

#include <stdint.h>

typedef struct nifti_ref {
    int dim[8];
    float pixdim[8];
    int datatype, bitpix;
    float vox_offset, slope, inter;
    int xyzt_units, qform_code, sform_code;
    float srow[3][4];
    int64_t nvox;   /* dim[1] * dim[2] * dim[3] (first volume) */
    double *values; /* nvox real values (slope/inter applied), x fastest */
} nifti_ref;

/* Read path; returns 0 on success, else -1 and prints why to stderr. */
int nifti_ref_read(const char *path, nifti_ref *out);
void nifti_ref_free(nifti_ref *r);
/* Number of values != 0. */
int64_t nifti_ref_count_nonzero(const nifti_ref *r);

#endif
