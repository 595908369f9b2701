/*
 * surface_row_avx2.c — the surface build's row kernels with AVX2, chosen at
 * run time by surface.c: four words of the row at a time. The words below
 * and above along z are the unaligned loads one word before and after, so
 * each lane does the portable formula; the results are the same bits.
 */
#include "render/surface_row.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>

static inline __m256i load(const uint64_t *p) { return _mm256_loadu_si256((const __m256i *)p); }

static void flat(const uint64_t *prev, const uint64_t *cur, const uint64_t *next, size_t n,
                 size_t wpc, uint64_t *b)
{
    size_t i = wpc;
    for (; i + 4 + wpc <= n; i += 4) {
        __m256i c = load(cur + i);
        __m256i below = load(cur + i - 1), above = load(cur + i + 1);
        __m256i zm = _mm256_or_si256(_mm256_slli_epi64(c, 1), _mm256_srli_epi64(below, 63));
        __m256i zp = _mm256_or_si256(_mm256_srli_epi64(c, 1), _mm256_slli_epi64(above, 63));
        __m256i in = _mm256_and_si256(_mm256_and_si256(load(cur + i - wpc), load(cur + i + wpc)),
                                      _mm256_and_si256(load(prev + i), load(next + i)));
        in = _mm256_and_si256(in, _mm256_and_si256(zm, zp));
        _mm256_storeu_si256((__m256i *)(b + i), _mm256_andnot_si256(in, c));
    }
    for (; i + wpc < n; i++)
        b[i] = bvox__boundary_word(cur[i], cur[i - wpc], cur[i + wpc], prev[i], next[i],
                                   cur[i - 1], cur[i + 1]);
}

static void nonzero(const uint64_t *b, size_t n, uint64_t *m)
{
    const __m256i zero = _mm256_setzero_si256();
    for (size_t i0 = 0; i0 < n; i0 += 64) {
        const size_t nw = n - i0 < 64 ? n - i0 : 64;
        uint64_t w = 0;
        size_t j = 0;
        for (; j + 4 <= nw; j += 4) {
            __m256i e = _mm256_cmpeq_epi64(load(b + i0 + j), zero);
            w |= (uint64_t)(_mm256_movemask_pd(_mm256_castsi256_pd(e)) ^ 0xf) << j;
        }
        for (; j < nw; j++) w |= (uint64_t)(b[i0 + j] != 0) << j;
        m[i0 / 64] = w;
    }
}

const bvox__surface_flat_fn bvox__surface_flat_avx2 = flat;
const bvox__surface_nonzero_fn bvox__surface_nonzero_avx2 = nonzero;
#else
const bvox__surface_flat_fn bvox__surface_flat_avx2 = NULL;
const bvox__surface_nonzero_fn bvox__surface_nonzero_avx2 = NULL;
#endif
