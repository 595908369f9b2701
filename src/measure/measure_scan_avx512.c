/*
 * measure_scan_avx512.c — the cells kernel of the measure scan with AVX-512
 * (F + VPOPCNTDQ; the build gives *_avx512.c files BW, VL, BMI2 and POPCNT
 * too), chosen at run time by measure_scan.c.
 *
 * Eight consecutive z-words of the four columns a, b, c, d are one vector
 * each; the "lo" words (voxels at z - 1) are the hi words shifted up by one
 * bit, each taking the top bit of the word below it: valignq of the vector
 * with the previous group's gives every lane its lower neighbour word. The
 * 21 popcounts of measure_scan.h's bvox__cells_word are counted eight words
 * at a time into nine vector accumulators, reduced once per vertex row.
 * Lanes past the column's end are zero in hi and lo, and all-zero windows
 * count nothing. The extra top word (nz a multiple of 64: hi = 0, lo = the
 * top voxels) is counted by the scalar formula. All sums are exact integers,
 * equal to the portable kernel's (tests/unit/test_measure.c).
 */
#include "measure/measure_scan.h"

#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512VPOPCNTDQ__)
#include <immintrin.h>

#define OR3(a, b, c) _mm512_ternarylogic_epi64(a, b, c, 0xfe)
#define AND3(a, b, c) _mm512_ternarylogic_epi64(a, b, c, 0x80)
#define PC(w) _mm512_popcnt_epi64(w)

/* lo words: lane i gets (h[i] << 1) | (h[i-1] >> 63), lane 0 taking the top
 * bit of the previous group's last word. */
static inline __m512i lo_of(__m512i h, __m512i prev, __mmask8 m)
{
    __m512i below = _mm512_alignr_epi64(h, prev, 7); /* below[i] = h[i-1], below[0] = prev[7] */
    return _mm512_maskz_or_epi64(m, _mm512_slli_epi64(h, 1), _mm512_srli_epi64(below, 63));
}

static void cells_row(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc,
                      bool extra, const uint64_t *zero, bvox__scan *s)
{
    const __m512i ones = _mm512_set1_epi64(-1);
    __m512i vpos = _mm512_setzero_si512(), vneg = _mm512_setzero_si512();
    __m512i t[BVOX__NDIR];
    for (int i = 0; i < BVOX__NDIR; i++) t[i] = _mm512_setzero_si512();
    int64_t eul = 0, ts[BVOX__NDIR] = {0}; /* the extra words, scalar */
    for (size_t x = 0; x <= nx; x++) {
        const uint64_t *col[4];
        bvox__cells_cols(prev, cur, x, nx, wpc, zero, col);
        const uint64_t *A = col[0], *B = col[1], *C = col[2], *D = col[3];
        __m512i pa = _mm512_setzero_si512(), pb = pa, pc = pa, pd = pa;
        for (size_t k = 0; k < wpc; k += 8) {
            __mmask8 m = wpc - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (wpc - k)) - 1);
            __m512i ah = _mm512_maskz_loadu_epi64(m, A + k), bh = _mm512_maskz_loadu_epi64(m, B + k);
            __m512i ch = _mm512_maskz_loadu_epi64(m, C + k), dh = _mm512_maskz_loadu_epi64(m, D + k);
            __m512i al = lo_of(ah, pa, m), bl = lo_of(bh, pb, m);
            __m512i cl = lo_of(ch, pc, m), dl = lo_of(dh, pd, m);
            pa = ah, pb = bh, pc = ch, pd = dh;
            __m512i hor = _mm512_or_si512(OR3(ah, bh, ch), dh);
            __m512i bdl = OR3(bh, bl, _mm512_or_si512(dh, dl));
            __m512i cdl = OR3(ch, cl, _mm512_or_si512(dh, dl));
            __m512i any = OR3(hor, bdl, cdl); /* a.lo is in neither */
            any = _mm512_or_si512(any, al);
            if (!_mm512_test_epi64_mask(any, any)) continue; /* all 0 */
            __m512i all = AND3(AND3(ah, bh, ch), AND3(dh, al, bl), _mm512_and_si512(cl, dl));
            if (!_mm512_cmpneq_epi64_mask(all, ones)) continue; /* all 1 */
            /* V - E + F - C */
            vpos = _mm512_add_epi64(vpos, PC(any));
            vpos = _mm512_add_epi64(vpos, PC(_mm512_or_si512(dl, dh)));
            vpos = _mm512_add_epi64(vpos, PC(_mm512_or_si512(ch, dh)));
            vpos = _mm512_add_epi64(vpos, PC(_mm512_or_si512(bh, dh)));
            vneg = _mm512_add_epi64(vneg, PC(hor));
            vneg = _mm512_add_epi64(vneg, PC(bdl));
            vneg = _mm512_add_epi64(vneg, PC(cdl));
            vneg = _mm512_add_epi64(vneg, PC(dh));
            /* transitions along the 13 directions */
            t[BVOX__DIR_X] = _mm512_add_epi64(t[BVOX__DIR_X], PC(_mm512_xor_si512(ch, dh)));
            t[BVOX__DIR_Y] = _mm512_add_epi64(t[BVOX__DIR_Y], PC(_mm512_xor_si512(bh, dh)));
            t[BVOX__DIR_Z] = _mm512_add_epi64(t[BVOX__DIR_Z], PC(_mm512_xor_si512(dl, dh)));
            t[BVOX__DIR_XY] = _mm512_add_epi64(t[BVOX__DIR_XY], PC(_mm512_xor_si512(ah, dh)));
            t[BVOX__DIR_XY] = _mm512_add_epi64(t[BVOX__DIR_XY], PC(_mm512_xor_si512(bh, ch)));
            t[BVOX__DIR_XZ] = _mm512_add_epi64(t[BVOX__DIR_XZ], PC(_mm512_xor_si512(cl, dh)));
            t[BVOX__DIR_XZ] = _mm512_add_epi64(t[BVOX__DIR_XZ], PC(_mm512_xor_si512(ch, dl)));
            t[BVOX__DIR_YZ] = _mm512_add_epi64(t[BVOX__DIR_YZ], PC(_mm512_xor_si512(bl, dh)));
            t[BVOX__DIR_YZ] = _mm512_add_epi64(t[BVOX__DIR_YZ], PC(_mm512_xor_si512(bh, dl)));
            t[BVOX__DIR_XYZ] = _mm512_add_epi64(t[BVOX__DIR_XYZ], PC(_mm512_xor_si512(al, dh)));
            t[BVOX__DIR_XYZ] = _mm512_add_epi64(t[BVOX__DIR_XYZ], PC(_mm512_xor_si512(bl, ch)));
            t[BVOX__DIR_XYZ] = _mm512_add_epi64(t[BVOX__DIR_XYZ], PC(_mm512_xor_si512(cl, bh)));
            t[BVOX__DIR_XYZ] = _mm512_add_epi64(t[BVOX__DIR_XYZ], PC(_mm512_xor_si512(dl, ah)));
        }
        if (extra)
            bvox__cells_word(0, 0, 0, 0, A[wpc - 1] >> 63, B[wpc - 1] >> 63, C[wpc - 1] >> 63,
                             D[wpc - 1] >> 63, &eul, ts, true);
    }
    s->euler += eul + _mm512_reduce_add_epi64(_mm512_sub_epi64(vpos, vneg));
    for (int i = 0; i < BVOX__NDIR; i++) s->trans[i] += ts[i] + _mm512_reduce_add_epi64(t[i]);
}

/* The moments of one column, eight words at a time by popcounts alone
 * (measure_scan.c's many-runs formula, whatever the runs): with k the word
 * index and c, t1, t2 a word's count, sum of bit indices t and of t^2,
 * sz = sum 64 k c + t1 and szz = sum 4096 k^2 c + 128 k t1 + t2. Every
 * lane product fits the 32 x 32 -> 64-bit multiply: k < 1024, c <= 64,
 * t1 < 2^11. */
static void moments(const uint64_t *col, size_t wpc, int32_t x, int32_t y, bvox__scan *s)
{
    __m512i vn = _mm512_setzero_si512(), vsz = vn, vszz = vn;
    __m512i idx = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
    const __m512i eight = _mm512_set1_epi64(8);
    int32_t zlo = -1, zhi = -1;
    for (size_t k = 0; k < wpc; k += 8, idx = _mm512_add_epi64(idx, eight)) {
        __mmask8 m = wpc - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (wpc - k)) - 1);
        __m512i w = _mm512_maskz_loadu_epi64(m, col + k);
        __mmask8 nz = _mm512_test_epi64_mask(w, w);
        if (!nz) continue;
        size_t first = k + (size_t)__builtin_ctz(nz), last = k + 31 - (size_t)__builtin_clz(nz);
        if (zlo < 0) zlo = (int32_t)(first * 64 + (size_t)__builtin_ctzll(col[first]));
        zhi = (int32_t)(last * 64 + 64 - (size_t)__builtin_clzll(col[last]));
        __m512i c = PC(w), t1 = _mm512_setzero_si512(), t2 = t1;
        __m512i wb[6];
        for (int b = 0; b < 6; b++) {
            wb[b] = _mm512_and_si512(w, _mm512_set1_epi64((long long)bvox__bit_of_index[b]));
            __m512i cb = PC(wb[b]);
            t1 = _mm512_add_epi64(t1, _mm512_sll_epi64(cb, _mm_cvtsi32_si128(b)));
            t2 = _mm512_add_epi64(t2, _mm512_sll_epi64(cb, _mm_cvtsi32_si128(2 * b)));
        }
        for (int b = 0; b < 6; b++)
            for (int d = b + 1; d < 6; d++)
                t2 = _mm512_add_epi64(t2, _mm512_sll_epi64(PC(_mm512_and_si512(wb[b], wb[d])),
                                                           _mm_cvtsi32_si128(b + d + 1)));
        __m512i kc = _mm512_mul_epu32(idx, c);
        __m512i kkc = _mm512_mul_epu32(_mm512_mul_epu32(idx, idx), c);
        __m512i kt1 = _mm512_mul_epu32(idx, t1);
        vn = _mm512_add_epi64(vn, c);
        vsz = _mm512_add_epi64(vsz, _mm512_add_epi64(_mm512_slli_epi64(kc, 6), t1));
        vszz = _mm512_add_epi64(vszz, _mm512_add_epi64(_mm512_slli_epi64(kkc, 12),
                                                       _mm512_add_epi64(_mm512_slli_epi64(kt1, 7), t2)));
    }
    if (zlo < 0) return;
    bvox__moments_add(s, x, y, _mm512_reduce_add_epi64(vn), _mm512_reduce_add_epi64(vsz),
                      _mm512_reduce_add_epi64(vszz), zlo, zhi);
    if (s->hull_row) bvox__hull_add(s, x, col, zlo, zhi, true);
}

const bvox__cells_row_fn bvox__cells_row_avx512 = cells_row;
const bvox__moments_fn bvox__moments_avx512 = moments;
#else
const bvox__cells_row_fn bvox__cells_row_avx512 = NULL;
const bvox__moments_fn bvox__moments_avx512 = NULL;
#endif
