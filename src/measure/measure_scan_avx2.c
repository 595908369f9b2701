/*
 * measure_scan_avx2.c — the cells kernel of the measure scan with AVX2,
 * chosen at run time by measure_scan.c: measure_scan_avx512.c's kernel four
 * z-words at a time. AVX2 has no popcount instruction, so the bits are
 * counted per byte by two nibble look-ups (vpshufb); the byte counts of the
 * terms that go into one sum (at most 4 x 8 = 32 a byte) are added first and
 * widened to 64-bit lanes once (vpsadbw), 9 widenings for the 17 popcounts.
 * The lo words: each lane takes the top bit of the lane below, lane 0 that
 * of the previous group's last word (a qword rotation and a blend). The
 * extra top word is counted by the scalar formula; all sums are exact.
 * The moments kernel below counts by bytes the same way.
 */
#include "measure/measure_scan.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>

/* Bit counts of each byte of w (0..8). */
static inline __m256i pc8(__m256i w)
{
    const __m256i lut = _mm256_setr_epi8(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 0, 1, 1,
                                         2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
    const __m256i low = _mm256_set1_epi8(0x0f);
    __m256i lo = _mm256_shuffle_epi8(lut, _mm256_and_si256(w, low));
    __m256i hi = _mm256_shuffle_epi8(lut, _mm256_and_si256(_mm256_srli_epi16(w, 4), low));
    return _mm256_add_epi8(lo, hi);
}

/* acc += the byte counts summed per 64-bit lane. */
static inline __m256i widen(__m256i acc, __m256i bytes)
{
    return _mm256_add_epi64(acc, _mm256_sad_epu8(bytes, _mm256_setzero_si256()));
}

/* lo words: lane i gets (h[i] << 1) | (h[i-1] >> 63), lane 0 taking the top
 * bit of prev[3]. */
static inline __m256i lo_of(__m256i h, __m256i prev)
{
    __m256i rh = _mm256_permute4x64_epi64(h, 0x93);    /* h3 h0 h1 h2 */
    __m256i rp = _mm256_permute4x64_epi64(prev, 0x93); /* p3 ... */
    __m256i below = _mm256_blend_epi32(rh, rp, 0x03);  /* p3 h0 h1 h2 */
    return _mm256_or_si256(_mm256_slli_epi64(h, 1), _mm256_srli_epi64(below, 63));
}

#define OR(a, b) _mm256_or_si256(a, b)
#define XOR(a, b) _mm256_xor_si256(a, b)
#define ADD8(a, b) _mm256_add_epi8(a, b)

static inline __m256i load(const uint64_t *p, size_t n)
{
    if (n >= 4) return _mm256_loadu_si256((const __m256i *)p);
    const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
    __m256i m = _mm256_cmpgt_epi64(_mm256_set1_epi64x((long long)n), lane);
    return _mm256_maskload_epi64((const long long *)p, m);
}

static void cells_row(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc,
                      bool extra, const uint64_t *zero, bvox__scan *s)
{
    const __m256i ones = _mm256_set1_epi64x(-1), lane = _mm256_setr_epi64x(0, 1, 2, 3);
    __m256i vpos = _mm256_setzero_si256(), vneg = vpos;
    __m256i t[BVOX__NDIR];
    for (int i = 0; i < BVOX__NDIR; i++) t[i] = _mm256_setzero_si256();
    int64_t eul = 0, ts[BVOX__NDIR] = {0}; /* the extra words, scalar */
    for (size_t x = 0; x <= nx; x++) {
        const uint64_t *col[4];
        bvox__cells_cols(prev, cur, x, nx, wpc, zero, col);
        const uint64_t *A = col[0], *B = col[1], *C = col[2], *D = col[3];
        __m256i pa = _mm256_setzero_si256(), pb = pa, pc = pa, pd = pa;
        for (size_t k = 0; k < wpc; k += 4) {
            size_t n = wpc - k;
            __m256i ah = load(A + k, n), bh = load(B + k, n), ch = load(C + k, n),
                    dh = load(D + k, n);
            __m256i al = lo_of(ah, pa), bl = lo_of(bh, pb), cl = lo_of(ch, pc), dl = lo_of(dh, pd);
            if (n < 4) { /* lanes past the column's end: lo = 0 too */
                __m256i m = _mm256_cmpgt_epi64(_mm256_set1_epi64x((long long)n), lane);
                al = _mm256_and_si256(al, m), bl = _mm256_and_si256(bl, m);
                cl = _mm256_and_si256(cl, m), dl = _mm256_and_si256(dl, m);
            }
            pa = ah, pb = bh, pc = ch, pd = dh;
            __m256i hor = OR(OR(ah, bh), OR(ch, dh));
            __m256i ddl = OR(dh, dl);
            __m256i bdl = OR(OR(bh, bl), ddl), cdl = OR(OR(ch, cl), ddl);
            __m256i any = OR(OR(hor, bdl), OR(cdl, al));
            if (_mm256_testz_si256(any, any)) continue; /* all 0 */
            __m256i all = _mm256_and_si256(_mm256_and_si256(_mm256_and_si256(ah, bh),
                                                            _mm256_and_si256(ch, dh)),
                                           _mm256_and_si256(_mm256_and_si256(al, bl),
                                                            _mm256_and_si256(cl, dl)));
            if (_mm256_testc_si256(all, ones)) { /* all 1: V - E = 4 x 64 x (1 - 3) */
                eul -= 512;
                continue;
            }
            /* V - E (F - C comes from totals, measure_scan.c), at most 3 x 8 a byte */
            vpos = widen(vpos, pc8(any));
            vneg = widen(vneg, ADD8(ADD8(pc8(hor), pc8(bdl)), pc8(cdl)));
            t[BVOX__DIR_X] = widen(t[BVOX__DIR_X], pc8(XOR(ch, dh)));
            t[BVOX__DIR_Y] = widen(t[BVOX__DIR_Y], pc8(XOR(bh, dh)));
            t[BVOX__DIR_Z] = widen(t[BVOX__DIR_Z], pc8(XOR(dl, dh)));
            t[BVOX__DIR_XY] = widen(t[BVOX__DIR_XY], ADD8(pc8(XOR(ah, dh)), pc8(XOR(bh, ch))));
            t[BVOX__DIR_XZ] = widen(t[BVOX__DIR_XZ], ADD8(pc8(XOR(cl, dh)), pc8(XOR(ch, dl))));
            t[BVOX__DIR_YZ] = widen(t[BVOX__DIR_YZ], ADD8(pc8(XOR(bl, dh)), pc8(XOR(bh, dl))));
            t[BVOX__DIR_XYZ] =
                widen(t[BVOX__DIR_XYZ], ADD8(ADD8(pc8(XOR(al, dh)), pc8(XOR(bl, ch))),
                                             ADD8(pc8(XOR(cl, bh)), pc8(XOR(dl, ah)))));
        }
        if (extra)
            bvox__cells_word(0, 0, 0, 0, A[wpc - 1] >> 63, B[wpc - 1] >> 63, C[wpc - 1] >> 63,
                             D[wpc - 1] >> 63, &eul, ts, true);
    }
    int64_t lanes[4];
    _mm256_storeu_si256((__m256i *)lanes, _mm256_sub_epi64(vpos, vneg));
    s->euler += eul + lanes[0] + lanes[1] + lanes[2] + lanes[3];
    for (int i = 0; i < BVOX__NDIR; i++) {
        _mm256_storeu_si256((__m256i *)lanes, t[i]);
        s->trans[i] += ts[i] + lanes[0] + lanes[1] + lanes[2] + lanes[3];
    }
}

/* Nibble tables for the moments: bits set, sum of their indices i, sum of
 * i^2 (i = 0..3), twice over for the two 128-bit halves. */
#define NIB(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o, p)                                  \
    _mm256_setr_epi8(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o, p, a, b, c, d, e, f, g, h, i, \
                     j, k, l, m, n, o, p)

/* 16-bit pair sums of a maddubs result gathered into their 64-bit lanes. */
static inline __m256i lanes_of16(__m256i v)
{
    __m256i s32 = _mm256_madd_epi16(v, _mm256_set1_epi16(1));
    return _mm256_add_epi64(_mm256_and_si256(s32, _mm256_set1_epi64x(0xffffffff)),
                            _mm256_srli_epi64(s32, 32));
}

/* The four 64-bit lanes of v added. */
static inline int64_t sum4(__m256i v)
{
    __m128i h = _mm_add_epi64(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    return _mm_cvtsi128_si64(h) + _mm_extract_epi64(h, 1);
}

/* Whether the n words at a and b are equal. */
static inline bool same_words(const uint64_t *a, const uint64_t *b, size_t n)
{
    for (size_t k = 0; k < n; k += 4) {
        __m256i d = _mm256_xor_si256(load(a + k, n - k), load(b + k, n - k));
        if (!_mm256_testz_si256(d, d)) return false;
    }
    return true;
}

/* The moments of one row of columns, four words at a time (the many-runs
 * formula of measure_scan.c by bytes instead of bit masks): a byte j of a
 * word with count p, index sum s1 and square sum s2 (of its bits' indices
 * 0..7; by two nibble look-ups each) adds p to the word's count c, 8 j p + s1
 * to t1 and 64 j^2 p + 16 j s1 + s2 to t2; the j-weighted sums are
 * vpmaddubsw's, the plain ones vpsadbw's. Then per lane (word index k)
 * sz = 64 k c + t1 and szz = 4096 k^2 c + 128 k t1 + t2. The row's six sums
 * stay lane-wise in registers (x applied by multiplies) and are reduced once
 * a row, as in measure_scan_avx512.c, and a column equal to the one before
 * it reuses that one's sums; products fit 32 x 32 -> 64: k < 1024,
 * c <= 64, t1 < 2^11, a lane's sz over a column < 2^30, x < 2^16. */
static void row_moments(const uint64_t *row, size_t nx, size_t wpc, int32_t y, bvox__scan *s)
{
    const __m256i tp = NIB(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
    const __m256i ts1 = NIB(0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 4, 4, 5, 5, 6, 6);
    const __m256i ts2 = NIB(0, 0, 1, 1, 4, 4, 5, 5, 9, 9, 10, 10, 13, 13, 14, 14);
    const __m256i low = _mm256_set1_epi8(0x0f), zero = _mm256_setzero_si256();
    const __m256i w1 = _mm256_set1_epi64x(0x0706050403020100ll);
    const __m256i w2 = _mm256_set1_epi64x(0x3124191009040100ll);
    const __m256i four = _mm256_set1_epi64x(4), lanes = _mm256_setr_epi64x(0, 1, 2, 3);
    /* the row's n, x n, x^2 n, sz, szz, x sz (s->row's order), per lane */
    __m256i acc[6] = {zero, zero, zero, zero, zero, zero};
    /* the column's sums; one equal to the column before it keeps them */
    __m256i vn = zero, vsz = zero, vszz = zero, vruns = zero;
    int32_t zlo = -1, zhi = -1;
    for (size_t x = 0; x < nx; x++) {
        const uint64_t *col = row + x * wpc;
        if (x && same_words(col, col - wpc, wpc)) goto sums;
        vn = vsz = vszz = vruns = zero;
        zlo = zhi = -1;
        __m256i prev = zero, idx = lanes;
        for (size_t k = 0; k < wpc; k += 4, idx = _mm256_add_epi64(idx, four)) {
            __m256i w = load(col + k, wpc - k), below = prev;
            prev = w;
            __m256i isz = _mm256_cmpeq_epi64(w, zero);
            unsigned nz = ~(unsigned)_mm256_movemask_pd(_mm256_castsi256_pd(isz)) & 0xf;
            if (!nz) continue;
            size_t first = k + (size_t)__builtin_ctz(nz), last = k + 31 - (size_t)__builtin_clz(nz);
            if (zlo < 0) zlo = (int32_t)(first * 64 + (size_t)__builtin_ctzll(col[first]));
            zhi = (int32_t)(last * 64 + 64 - (size_t)__builtin_clzll(col[last]));
            /* runs: starts are 1-bits whose lower neighbour (lo_of) is 0 */
            vruns = widen(vruns, pc8(_mm256_andnot_si256(lo_of(w, below), w)));
            __m256i lo = _mm256_and_si256(w, low);
            __m256i hi = _mm256_and_si256(_mm256_srli_epi16(w, 4), low);
            __m256i plo = _mm256_shuffle_epi8(tp, lo), phi = _mm256_shuffle_epi8(tp, hi);
            __m256i s1hi = _mm256_shuffle_epi8(ts1, hi);
            __m256i p = _mm256_add_epi8(plo, phi);
            /* the high nibble's bits sit 4 higher: i + 4 */
            __m256i s1 = _mm256_add_epi8(_mm256_add_epi8(_mm256_shuffle_epi8(ts1, lo), s1hi),
                                         _mm256_slli_epi16(phi, 2));
            __m256i s2 = _mm256_add_epi8(
                _mm256_add_epi8(_mm256_shuffle_epi8(ts2, lo), _mm256_shuffle_epi8(ts2, hi)),
                _mm256_add_epi8(_mm256_slli_epi16(s1hi, 3), _mm256_slli_epi16(phi, 4)));
            __m256i c = _mm256_sad_epu8(p, zero);
            __m256i jp = lanes_of16(_mm256_maddubs_epi16(p, w1));
            __m256i jjp = lanes_of16(_mm256_maddubs_epi16(p, w2));
            __m256i js1 = lanes_of16(_mm256_maddubs_epi16(s1, w1));
            __m256i t1 = _mm256_add_epi64(_mm256_slli_epi64(jp, 3), _mm256_sad_epu8(s1, zero));
            __m256i t2 = _mm256_add_epi64(_mm256_add_epi64(_mm256_slli_epi64(jjp, 6),
                                                           _mm256_slli_epi64(js1, 4)),
                                          _mm256_sad_epu8(s2, zero));
            __m256i kc = _mm256_mul_epu32(idx, c);
            __m256i kkc = _mm256_mul_epu32(_mm256_mul_epu32(idx, idx), c);
            __m256i kt1 = _mm256_mul_epu32(idx, t1);
            vn = _mm256_add_epi64(vn, c);
            vsz = _mm256_add_epi64(vsz, _mm256_add_epi64(_mm256_slli_epi64(kc, 6), t1));
            vszz = _mm256_add_epi64(
                vszz, _mm256_add_epi64(_mm256_slli_epi64(kkc, 12),
                                       _mm256_add_epi64(_mm256_slli_epi64(kt1, 7), t2)));
        }
    sums:
        if (zlo < 0) {
            if (s->hull_row) s->hull_row[x] = (bvox__colhull){0, 0, 0, 0};
            continue;
        }
        __m256i X = _mm256_set1_epi64x((long long)x), XX = _mm256_set1_epi64x((long long)x * x);
        acc[0] = _mm256_add_epi64(acc[0], vn);
        acc[1] = _mm256_add_epi64(acc[1], _mm256_mul_epu32(X, vn));
        acc[2] = _mm256_add_epi64(acc[2], _mm256_mul_epu32(XX, vn));
        acc[3] = _mm256_add_epi64(acc[3], vsz);
        acc[4] = _mm256_add_epi64(acc[4], vszz);
        acc[5] = _mm256_add_epi64(acc[5], _mm256_mul_epu32(X, vsz));
        bvox__bbox_add(s, (int32_t)x, y, zlo, zhi);
        if (s->hull_row)
            s->hull_row[x] = (bvox__colhull){zlo + 1, zhi - 1, (uint32_t)sum4(vruns) - 1, 0};
    }
    for (int i = 0; i < 6; i++) s->row[i] += (uint64_t)sum4(acc[i]);
}

const bvox__cells_row_fn bvox__cells_row_avx2 = cells_row;
const bvox__row_moments_fn bvox__row_moments_avx2 = row_moments;
#else
const bvox__cells_row_fn bvox__cells_row_avx2 = NULL;
const bvox__row_moments_fn bvox__row_moments_avx2 = NULL;
#endif
