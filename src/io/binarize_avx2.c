/*
 * binarize_avx2.c — AVX2 compare kernels of bvox__binarize (compiled with
 * -mavx2, chosen at run time). Same predicate as binarize_generic.c: AVX2 has
 * no unsigned compare, so x - a <= w is tested as min(x - a, w) == x - a
 * (8/16/32-bit) or with the sign bits flipped and a signed compare (64-bit);
 * movemask turns the lane results into bits.
 */
#include "binarize_kernels.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>

/* Byte shuffles that swap each 2-, 4- or 8-byte sample within a 128-bit lane. */
static inline __m256i swap_mask(int width)
{
    if (width == 2)
        return _mm256_setr_epi8(1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14, 1, 0, 3,
                                2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14);
    if (width == 4)
        return _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1,
                                0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    return _mm256_setr_epi8(7, 6, 5, 4, 3, 2, 1, 0, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4,
                            3, 2, 1, 0, 15, 14, 13, 12, 11, 10, 9, 8);
}

static inline __m256i load(const unsigned char *s, int swap, __m256i shuf)
{
    __m256i x = _mm256_loadu_si256((const __m256i *)s);
    return swap ? _mm256_shuffle_epi8(x, shuf) : x;
}

static void blocks_i8(const unsigned char *s, size_t nb, const bvox__binpred *p,
                      uint64_t *out, size_t stride)
{
    const __m256i a = _mm256_set1_epi8((char)p->a), w = _mm256_set1_epi8((char)p->w);
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 64) {
        uint64_t m = 0;
        for (int h = 0; h < 2; h++) {
            __m256i t = _mm256_sub_epi8(_mm256_loadu_si256((const __m256i *)(s + 32 * h)), a);
            __m256i le = _mm256_cmpeq_epi8(_mm256_min_epu8(t, w), t);
            m |= (uint64_t)(uint32_t)_mm256_movemask_epi8(le) << (32 * h);
        }
        out[b * stride] = m ^ inv;
    }
}

static void blocks_i16(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m256i a = _mm256_set1_epi16((short)p->a), w = _mm256_set1_epi16((short)p->w);
    const __m256i shuf = swap_mask(2);
    const int swap = p->swap;
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 128) {
        uint64_t m = 0;
        for (int h = 0; h < 2; h++) {
            __m256i t0 = _mm256_sub_epi16(load(s + 64 * h, swap, shuf), a);
            __m256i t1 = _mm256_sub_epi16(load(s + 64 * h + 32, swap, shuf), a);
            __m256i le0 = _mm256_cmpeq_epi16(_mm256_min_epu16(t0, w), t0);
            __m256i le1 = _mm256_cmpeq_epi16(_mm256_min_epu16(t1, w), t1);
            /* packs interleaves the 128-bit lanes; the permute restores order */
            __m256i pk = _mm256_permute4x64_epi64(_mm256_packs_epi16(le0, le1), 0xD8);
            m |= (uint64_t)(uint32_t)_mm256_movemask_epi8(pk) << (32 * h);
        }
        out[b * stride] = m ^ inv;
    }
}

static void blocks_i32(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m256i a = _mm256_set1_epi32((int)p->a), w = _mm256_set1_epi32((int)p->w);
    const __m256i shuf = swap_mask(4);
    const int swap = p->swap;
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 256) {
        uint64_t m = 0;
        for (int q = 0; q < 8; q++) {
            __m256i t = _mm256_sub_epi32(load(s + 32 * q, swap, shuf), a);
            __m256i le = _mm256_cmpeq_epi32(_mm256_min_epu32(t, w), t);
            m |= (uint64_t)(uint32_t)_mm256_movemask_ps(_mm256_castsi256_ps(le)) << (8 * q);
        }
        out[b * stride] = m ^ inv;
    }
}

static void blocks_i64(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m256i sign = _mm256_set1_epi64x((long long)0x8000000000000000ull);
    const __m256i a = _mm256_set1_epi64x((long long)p->a);
    const __m256i ws = _mm256_xor_si256(_mm256_set1_epi64x((long long)p->w), sign);
    const __m256i shuf = swap_mask(8);
    const int swap = p->swap;
    /* the compare gives "greater than", i.e. the complement of the interval */
    const uint64_t inv = p->invert ? 0 : ~0ull;
    for (size_t b = 0; b < nb; b++, s += 512) {
        uint64_t m = 0;
        for (int q = 0; q < 16; q++) {
            __m256i t = _mm256_xor_si256(_mm256_sub_epi64(load(s + 32 * q, swap, shuf), a), sign);
            __m256i gt = _mm256_cmpgt_epi64(t, ws);
            m |= (uint64_t)(uint32_t)_mm256_movemask_pd(_mm256_castsi256_pd(gt)) << (4 * q);
        }
        out[b * stride] = m ^ inv;
    }
}

static void blocks_f32(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m256 lo = _mm256_set1_ps(p->fa32), hi = _mm256_set1_ps(p->fb32);
    const __m256i shuf = swap_mask(4);
    const int swap = p->swap, invert = p->invert;
    for (size_t b = 0; b < nb; b++, s += 256) {
        uint64_t m = 0;
        for (int q = 0; q < 8; q++) {
            __m256 x = _mm256_castsi256_ps(load(s + 32 * q, swap, shuf));
            __m256 r = invert ? _mm256_or_ps(_mm256_cmp_ps(x, lo, _CMP_LT_OQ),
                                             _mm256_cmp_ps(x, hi, _CMP_GT_OQ))
                              : _mm256_and_ps(_mm256_cmp_ps(x, lo, _CMP_GE_OQ),
                                              _mm256_cmp_ps(x, hi, _CMP_LE_OQ));
            m |= (uint64_t)(uint32_t)_mm256_movemask_ps(r) << (8 * q);
        }
        out[b * stride] = m;
    }
}

static void blocks_f64(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m256d lo = _mm256_set1_pd(p->fa), hi = _mm256_set1_pd(p->fb);
    const __m256i shuf = swap_mask(8);
    const int swap = p->swap, invert = p->invert;
    for (size_t b = 0; b < nb; b++, s += 512) {
        uint64_t m = 0;
        for (int q = 0; q < 16; q++) {
            __m256d x = _mm256_castsi256_pd(load(s + 32 * q, swap, shuf));
            __m256d r = invert ? _mm256_or_pd(_mm256_cmp_pd(x, lo, _CMP_LT_OQ),
                                              _mm256_cmp_pd(x, hi, _CMP_GT_OQ))
                               : _mm256_and_pd(_mm256_cmp_pd(x, lo, _CMP_GE_OQ),
                                               _mm256_cmp_pd(x, hi, _CMP_LE_OQ));
            m |= (uint64_t)(uint32_t)_mm256_movemask_pd(r) << (4 * q);
        }
        out[b * stride] = m;
    }
}

static void blocks(const void *src, size_t nb, const bvox__binpred *p, uint64_t *out,
                   size_t stride)
{
    switch (p->kind) {
    case BVOX__BK_INT8: blocks_i8(src, nb, p, out, stride); break;
    case BVOX__BK_INT16: blocks_i16(src, nb, p, out, stride); break;
    case BVOX__BK_INT32: blocks_i32(src, nb, p, out, stride); break;
    case BVOX__BK_INT64: blocks_i64(src, nb, p, out, stride); break;
    case BVOX__BK_F32: blocks_f32(src, nb, p, out, stride); break;
    case BVOX__BK_F64: blocks_f64(src, nb, p, out, stride); break;
    }
}

const bvox__bin_blocks_fn bvox__bin_blocks_avx2 = blocks;
#else
const bvox__bin_blocks_fn bvox__bin_blocks_avx2 = NULL;
#endif
