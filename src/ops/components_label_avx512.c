/*
 * components_label_avx512.c — the labeller's first pass for 2 x 2 groups
 * (26-connectivity, components_label.c) eight words at a time: the OR of
 * the group's four columns stored, and its runs counted as the popcount of
 * its run starts (a 1 whose lower neighbour is 0; lane 0's lower neighbour
 * is the previous vector's lane 7, as in measure_scan_avx512.c). The scalar
 * loop it replaces spent half of a 26-labelling of the atlas's 512^3 on this
 * pass. Chosen at run time by components_label.c; the build gives
 * *_avx512.c files F, BW, VL, VPOPCNTDQ (cmake/simd.cmake).
 */
#include "ops/components_label.h"

#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512VPOPCNTDQ__)
#include <immintrin.h>

/* Words of column c (NULL: outside the volume, all 0) at k, mask m. */
static inline __m512i column_words(const uint64_t *c, size_t k, __mmask8 m)
{
    return c ? _mm512_maskz_loadu_epi64(m, c + k) : _mm512_setzero_si512();
}

static uint32_t group_runs(const uint64_t *c00, const uint64_t *c10, const uint64_t *c01,
                           const uint64_t *c11, size_t wpc, uint64_t *dst)
{
    __m512i prev = _mm512_setzero_si512(), runs = prev;
    for (size_t k = 0; k < wpc; k += 8) {
        __mmask8 m = wpc - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (wpc - k)) - 1);
        __m512i u = _mm512_ternarylogic_epi64(column_words(c00, k, m), column_words(c10, k, m),
                                              column_words(c01, k, m), 0xfe); /* a | b | c */
        u = _mm512_or_si512(u, column_words(c11, k, m));
        _mm512_mask_storeu_epi64(dst + k, m, u);
        __m512i below = _mm512_alignr_epi64(u, prev, 7); /* below[i] = u[i-1] */
        __m512i lo = _mm512_or_si512(_mm512_slli_epi64(u, 1), _mm512_srli_epi64(below, 63));
        runs = _mm512_add_epi64(runs, _mm512_popcnt_epi64(_mm512_andnot_si512(lo, u)));
        prev = u;
    }
    return (uint32_t)_mm512_reduce_add_epi64(runs);
}

const bvox__group_runs_fn bvox__group_runs_avx512 = group_runs;
#else
const bvox__group_runs_fn bvox__group_runs_avx512 = NULL;
#endif
