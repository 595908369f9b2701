/*
 * kernels_avx2.c — AVX2 word kernels (compiled with -mavx2, chosen at run time
 * by dispatch.c only on CPUs that have AVX2). Popcount uses the nibble lookup
 * with vpshufb and vpsadbw (Mula, Kurz and Lemire, "Faster population counts
 * using AVX2 instructions", 2018).
 */
#include "internal.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>

static inline __m256i popcnt256(__m256i v)
{
    const __m256i lookup = _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 0,
                                            1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
    const __m256i low = _mm256_set1_epi8(0x0f);
    __m256i lo = _mm256_shuffle_epi8(lookup, _mm256_and_si256(v, low));
    __m256i hi = _mm256_shuffle_epi8(lookup, _mm256_and_si256(_mm256_srli_epi16(v, 4), low));
    return _mm256_sad_epu8(_mm256_add_epi8(lo, hi), _mm256_setzero_si256());
}

static uint64_t hsum(__m256i acc)
{
    return (uint64_t)_mm256_extract_epi64(acc, 0) + (uint64_t)_mm256_extract_epi64(acc, 1) +
           (uint64_t)_mm256_extract_epi64(acc, 2) + (uint64_t)_mm256_extract_epi64(acc, 3);
}

static uint64_t popcount(const uint64_t *w, size_t n)
{
    __m256i acc = _mm256_setzero_si256();
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        acc = _mm256_add_epi64(acc, popcnt256(_mm256_loadu_si256((const __m256i *)(w + i))));
    uint64_t total = hsum(acc);
    for (; i < n; i++) total += (uint64_t)__builtin_popcountll(w[i]);
    return total;
}

static uint64_t popcount_and(const uint64_t *a, const uint64_t *b, size_t n)
{
    __m256i acc = _mm256_setzero_si256();
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        acc = _mm256_add_epi64(
            acc, popcnt256(_mm256_and_si256(_mm256_loadu_si256((const __m256i *)(a + i)),
                                            _mm256_loadu_si256((const __m256i *)(b + i)))));
    uint64_t total = hsum(acc);
    for (; i < n; i++) total += (uint64_t)__builtin_popcountll(a[i] & b[i]);
    return total;
}

#define BINARY_OP(name, expr, scalar)                                                     \
    static void name(uint64_t *restrict d, const uint64_t *restrict s, size_t n)          \
    {                                                                                      \
        size_t i = 0;                                                                      \
        for (; i + 4 <= n; i += 4) {                                                       \
            __m256i x = _mm256_loadu_si256((const __m256i *)(d + i));                      \
            __m256i y = _mm256_loadu_si256((const __m256i *)(s + i));                      \
            _mm256_storeu_si256((__m256i *)(d + i), expr);                                 \
        }                                                                                  \
        for (; i < n; i++) d[i] = scalar;                                                  \
    }

BINARY_OP(op_or, _mm256_or_si256(x, y), d[i] | s[i])
BINARY_OP(op_and, _mm256_and_si256(x, y), d[i] & s[i])
BINARY_OP(op_andnot, _mm256_andnot_si256(y, x), d[i] & ~s[i])
BINARY_OP(op_xor, _mm256_xor_si256(x, y), d[i] ^ s[i])

static void op_not(uint64_t *d, size_t n)
{
    const __m256i ones = _mm256_set1_epi64x(-1);
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        _mm256_storeu_si256((__m256i *)(d + i),
                            _mm256_xor_si256(_mm256_loadu_si256((const __m256i *)(d + i)), ones));
    for (; i < n; i++) d[i] = ~d[i];
}

const bvox__kernels bvox__kernels_avx2 = {popcount, popcount_and, op_or, op_and,
                                          op_andnot, op_xor, op_not};
#else
/* Not an x86-64 AVX2 build: dispatch.c never selects this table. */
const bvox__kernels bvox__kernels_avx2 = {0};
#endif
