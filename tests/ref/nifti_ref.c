/* nifti_ref.c — the slow reference NIfTI-1 reader (see nifti_ref.h). One
 * field, one sample at a time; clarity over speed. */
#include "nifti_ref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static int swap_needed;

static void flip(unsigned char *p, int n)
{
    for (int i = 0; i < n / 2; i++) {
        unsigned char t = p[i];
        p[i] = p[n - 1 - i];
        p[n - 1 - i] = t;
    }
}

static int16_t field_i16(const unsigned char *h, int off)
{
    unsigned char b[2] = {h[off], h[off + 1]};
    if (swap_needed) flip(b, 2);
    int16_t v;
    memcpy(&v, b, 2);
    return v;
}

static int32_t field_i32(const unsigned char *h, int off)
{
    unsigned char b[4] = {h[off], h[off + 1], h[off + 2], h[off + 3]};
    if (swap_needed) flip(b, 4);
    int32_t v;
    memcpy(&v, b, 4);
    return v;
}

static float field_f32(const unsigned char *h, int off)
{
    unsigned char b[4] = {h[off], h[off + 1], h[off + 2], h[off + 3]};
    if (swap_needed) flip(b, 4);
    float v;
    memcpy(&v, b, 4);
    return v;
}

/* One sample of the given NIfTI datatype as a double. */
static int sample(const unsigned char *p, int datatype, double *v)
{
    unsigned char b[8];
    int n;
    switch (datatype) {
    case 2: case 256: n = 1; break;
    case 4: case 512: n = 2; break;
    case 8: case 768: case 16: n = 4; break;
    case 64: case 1024: case 1280: n = 8; break;
    default: return -1;
    }
    memcpy(b, p, (size_t)n);
    if (swap_needed) flip(b, n);
    switch (datatype) {
    case 2: *v = b[0]; break;
    case 256: *v = (int8_t)b[0]; break;
    case 4: { int16_t x; memcpy(&x, b, 2); *v = x; } break;
    case 512: { uint16_t x; memcpy(&x, b, 2); *v = x; } break;
    case 8: { int32_t x; memcpy(&x, b, 4); *v = x; } break;
    case 768: { uint32_t x; memcpy(&x, b, 4); *v = x; } break;
    case 16: { float x; memcpy(&x, b, 4); *v = x; } break;
    case 64: { double x; memcpy(&x, b, 8); *v = x; } break;
    case 1024: { int64_t x; memcpy(&x, b, 8); *v = (double)x; } break;
    case 1280: { uint64_t x; memcpy(&x, b, 8); *v = (double)x; } break;
    }
    return 0;
}

int nifti_ref_read(const char *path, nifti_ref *r)
{
    memset(r, 0, sizeof *r);
    gzFile f = gzopen(path, "rb");
    if (!f) {
        fprintf(stderr, "nifti_ref: cannot open %s\n", path);
        return -1;
    }
    unsigned char h[348];
    if (gzread(f, h, 348) != 348) {
        fprintf(stderr, "nifti_ref: short header in %s\n", path);
        gzclose(f);
        return -1;
    }
    int32_t sz;
    memcpy(&sz, h, 4);
    swap_needed = sz != 348;
    if (field_i32(h, 0) != 348 || memcmp(h + 344, "n+1", 4) != 0) {
        fprintf(stderr, "nifti_ref: %s is not a single-file NIfTI-1\n", path);
        gzclose(f);
        return -1;
    }
    for (int i = 0; i < 8; i++) r->dim[i] = field_i16(h, 40 + 2 * i);
    r->datatype = field_i16(h, 70);
    r->bitpix = field_i16(h, 72);
    for (int i = 0; i < 8; i++) r->pixdim[i] = field_f32(h, 76 + 4 * i);
    r->vox_offset = field_f32(h, 108);
    r->slope = field_f32(h, 112);
    r->inter = field_f32(h, 116);
    r->xyzt_units = h[123];
    r->qform_code = field_i16(h, 252);
    r->sform_code = field_i16(h, 254);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) r->srow[i][j] = field_f32(h, 280 + 16 * i + 4 * j);
    int nx = r->dim[1], ny = r->dim[0] >= 2 ? r->dim[2] : 1, nz = r->dim[0] >= 3 ? r->dim[3] : 1;
    r->nvox = (int64_t)nx * ny * nz;
    int bytes = r->bitpix / 8;
    double slope = r->slope, inter = r->inter;
    if (slope == 0) slope = 1, inter = 0;

    /* skip to the data */
    for (long skip = (long)r->vox_offset - 348; skip > 0; skip--) {
        unsigned char c;
        if (gzread(f, &c, 1) != 1) goto short_data;
    }
    r->values = malloc((size_t)r->nvox * sizeof(double));
    if (!r->values) {
        gzclose(f);
        return -1;
    }
    for (int64_t i = 0; i < r->nvox; i++) {
        unsigned char b[8];
        if (gzread(f, b, (unsigned)bytes) != bytes) goto short_data;
        double v = 0;
        if (sample(b, r->datatype, &v) != 0) {
            fprintf(stderr, "nifti_ref: datatype %d not handled\n", r->datatype);
            nifti_ref_free(r);
            gzclose(f);
            return -1;
        }
        r->values[i] = v * slope + inter;
    }
    gzclose(f);
    return 0;
short_data:
    fprintf(stderr, "nifti_ref: short data in %s\n", path);
    nifti_ref_free(r);
    gzclose(f);
    return -1;
}

void nifti_ref_free(nifti_ref *r)
{
    free(r->values);
    r->values = NULL;
}

int64_t nifti_ref_count_nonzero(const nifti_ref *r)
{
    int64_t n = 0;
    for (int64_t i = 0; i < r->nvox; i++)
        if (r->values[i] != 0.0) n++;
    return n;
}
