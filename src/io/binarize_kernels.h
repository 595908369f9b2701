/*
 * binarize_kernels.h — private interface between binarize.c, unpack.c and the
 * compare kernels (generic in binarize_generic.c, binarize_avx2.c,
 * binarize_avx512.c).
 *
 * binarize.c turns every read mode into one predicate on the RAW samples, so
 * a kernel only ever does one of two things per sample:
 *   integers: in = (uint_w)(x - a) <= w      (x in [a, a+w], modulo 2^width,
 *                                             which works for signed types too)
 *   floats:   in = fa <= x <= fb             (ordered: NaN is never in)
 * and `invert` turns `in` into its complement (for floats: x < fa || x > fb,
 * so NaN stays 0). Kernels handle whole blocks of 64 samples; binarize.c pads
 * a row's tail into a stack buffer.
 */
#ifndef BVOX_BINARIZE_KERNELS_H
#define BVOX_BINARIZE_KERNELS_H

#include "io.h"
#include "common/bits.h" /* bvox__transpose64 */

/* Sample class: the integer width, or the float type. */
typedef enum bvox__bin_kind {
    BVOX__BK_INT8 = 0,
    BVOX__BK_INT16,
    BVOX__BK_INT32,
    BVOX__BK_INT64,
    BVOX__BK_F32,
    BVOX__BK_F64
} bvox__bin_kind;

typedef struct bvox__binpred {
    bvox__bin_kind kind;
    bool swap;    /* byteswap each sample before comparing */
    bool invert;  /* complement of the interval (NaN still 0) */
    uint64_t a, w; /* integers, truncated to the sample width */
    double fa, fb; /* f64 bounds */
    float fa32, fb32; /* the same bounds for f32 (exactly representable) */
} bvox__binpred;

/* For each block b < nblocks of 64 samples starting at src + b*64 samples:
 * out[b * stride] = the 64 predicate bits (bit i = sample i). src need not be
 * aligned. */
typedef void (*bvox__bin_blocks_fn)(const void *src, size_t nblocks, const bvox__binpred *p,
                                    uint64_t *out, size_t stride);

void bvox__bin_blocks_generic(const void *src, size_t nblocks, const bvox__binpred *p,
                              uint64_t *out, size_t stride);
/* NULL when this build has no such path (not x86-64). */
extern const bvox__bin_blocks_fn bvox__bin_blocks_avx2;
extern const bvox__bin_blocks_fn bvox__bin_blocks_avx512;

/* The real value of a raw sample, exactly as documented in io.h (slope is
 * already "0 means 1"-resolved). Written once so that every caller rounds the
 * same way: the predicates are derived from this very function. */
static inline double bvox__real_value(double raw, double slope, double inter)
{
    return raw * slope + inter;
}

/* The start of every binarisation (binarize.c): validate g (dims, scaling;
 * g->data may be NULL unless how is Otsu), derive the predicate and the
 * compare kernel, and make the volume with g's dims and geometry: zero or
 * all ones when the predicate is constant (*use_pred false: the volume is
 * the answer), else uninitialised, for the caller to pack every word. */
bvox_status bvox__binarize_setup(const bvox__gray *g, const bvox_binarize *how,
                                 const char *name, bvox__binpred *pred, bool *use_pred,
                                 bvox__bin_blocks_fn *blocks, bvox_volume **out);

/* Otsu's threshold of g, as a real value (binarize_otsu.c). slope is the
 * resolved slope (nonzero). *found = false when the samples hold fewer than two
 * distinct histogram bins (nothing to split: the result is all zero). */
bvox_status bvox__otsu_threshold(const bvox__gray *g, double slope, double inter,
                                 const char *name, bool *found, double *threshold);

#endif
