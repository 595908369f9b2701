/*
 * binarize_avx512.c — AVX-512 (F + BW) compare kernels of bvox__binarize,
 * chosen at run time. AVX-512 has unsigned compares at every width that
 * return a bit mask directly, so x - a <= w is one subtract and one compare,
 * and 64 bytes of u8 samples become a 64-bit mask in two instructions.
 */
#include "binarize_kernels.h"

#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512BW__)
#include <immintrin.h>

static inline __m512i swap_mask(int width)
{
    /* per 128-bit lane; _mm512_shuffle_epi8 works within lanes */
    __m128i l = width == 2   ? _mm_setr_epi8(1, 0, 3, 2, 5, 4, 7, 6, 9, 8, 11, 10, 13, 12, 15, 14)
                : width == 4 ? _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12)
                             : _mm_setr_epi8(7, 6, 5, 4, 3, 2, 1, 0, 15, 14, 13, 12, 11, 10, 9, 8);
    return _mm512_broadcast_i32x4(l);
}

static inline __m512i load(const unsigned char *s, int swap, __m512i shuf)
{
    __m512i x = _mm512_loadu_si512(s);
    return swap ? _mm512_shuffle_epi8(x, shuf) : x;
}

static void blocks_i8(const unsigned char *s, size_t nb, const bvox__binpred *p,
                      uint64_t *out, size_t stride)
{
    const __m512i a = _mm512_set1_epi8((char)p->a), w = _mm512_set1_epi8((char)p->w);
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 64)
        out[b * stride] =
            (uint64_t)_mm512_cmple_epu8_mask(_mm512_sub_epi8(_mm512_loadu_si512(s), a), w) ^ inv;
}

static void blocks_i16(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m512i a = _mm512_set1_epi16((short)p->a), w = _mm512_set1_epi16((short)p->w);
    const __m512i shuf = swap_mask(2);
    const int swap = p->swap;
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 128) {
        uint64_t m0 = _mm512_cmple_epu16_mask(_mm512_sub_epi16(load(s, swap, shuf), a), w);
        uint64_t m1 = _mm512_cmple_epu16_mask(_mm512_sub_epi16(load(s + 64, swap, shuf), a), w);
        out[b * stride] = (m0 | m1 << 32) ^ inv;
    }
}

static void blocks_i32(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m512i a = _mm512_set1_epi32((int)p->a), w = _mm512_set1_epi32((int)p->w);
    const __m512i shuf = swap_mask(4);
    const int swap = p->swap;
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 256) {
        uint64_t m = 0;
        for (int q = 0; q < 4; q++)
            m |= (uint64_t)_mm512_cmple_epu32_mask(
                     _mm512_sub_epi32(load(s + 64 * q, swap, shuf), a), w)
                 << (16 * q);
        out[b * stride] = m ^ inv;
    }
}

static void blocks_i64(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m512i a = _mm512_set1_epi64((long long)p->a), w = _mm512_set1_epi64((long long)p->w);
    const __m512i shuf = swap_mask(8);
    const int swap = p->swap;
    const uint64_t inv = p->invert ? ~0ull : 0;
    for (size_t b = 0; b < nb; b++, s += 512) {
        uint64_t m = 0;
        for (int q = 0; q < 8; q++)
            m |= (uint64_t)_mm512_cmple_epu64_mask(
                     _mm512_sub_epi64(load(s + 64 * q, swap, shuf), a), w)
                 << (8 * q);
        out[b * stride] = m ^ inv;
    }
}

static void blocks_f32(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m512 lo = _mm512_set1_ps(p->fa32), hi = _mm512_set1_ps(p->fb32);
    const __m512i shuf = swap_mask(4);
    const int swap = p->swap, invert = p->invert;
    for (size_t b = 0; b < nb; b++, s += 256) {
        uint64_t m = 0;
        for (int q = 0; q < 4; q++) {
            __m512 x = _mm512_castsi512_ps(load(s + 64 * q, swap, shuf));
            __mmask16 r = invert ? (__mmask16)(_mm512_cmp_ps_mask(x, lo, _CMP_LT_OQ) |
                                               _mm512_cmp_ps_mask(x, hi, _CMP_GT_OQ))
                                 : _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(x, lo, _CMP_GE_OQ),
                                                           x, hi, _CMP_LE_OQ);
            m |= (uint64_t)r << (16 * q);
        }
        out[b * stride] = m;
    }
}

static void blocks_f64(const unsigned char *s, size_t nb, const bvox__binpred *p,
                       uint64_t *out, size_t stride)
{
    const __m512d lo = _mm512_set1_pd(p->fa), hi = _mm512_set1_pd(p->fb);
    const __m512i shuf = swap_mask(8);
    const int swap = p->swap, invert = p->invert;
    for (size_t b = 0; b < nb; b++, s += 512) {
        uint64_t m = 0;
        for (int q = 0; q < 8; q++) {
            __m512d x = _mm512_castsi512_pd(load(s + 64 * q, swap, shuf));
            __mmask8 r = invert ? (__mmask8)(_mm512_cmp_pd_mask(x, lo, _CMP_LT_OQ) |
                                             _mm512_cmp_pd_mask(x, hi, _CMP_GT_OQ))
                                : _mm512_mask_cmp_pd_mask(_mm512_cmp_pd_mask(x, lo, _CMP_GE_OQ),
                                                          x, hi, _CMP_LE_OQ);
            m |= (uint64_t)r << (8 * q);
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

const bvox__bin_blocks_fn bvox__bin_blocks_avx512 = blocks;
#else
const bvox__bin_blocks_fn bvox__bin_blocks_avx512 = NULL;
#endif
