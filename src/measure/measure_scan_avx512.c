/*
 * measure_scan_avx512.c — the cells kernel of the measure scan with AVX-512
 * (F + VPOPCNTDQ; the build gives *_avx512.c files BW, VL, BMI2 and POPCNT
 * too), chosen at run time by measure_scan.c.
 *
 * Eight consecutive z-words of the four columns a, b, c, d are one vector
 * each; the "lo" words (voxels at z - 1) are the hi words shifted up by one
 * bit, each taking the top bit of the word below it: valignq of the vector
 * with the previous group's gives every lane its lower neighbour word. The
 * 17 popcounts of measure_scan.h's bvox__cells_word are counted eight words
 * at a time into nine vector accumulators, reduced once per vertex row;
 * windows whose columns x - 1 and x are equal in both rows (most of a
 * smooth or upsampled object's), or whose rows y - 1 and y are (an
 * upsampled object's rows repeat), take 6 (pair_equal).
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

/* windows() where two columns of each window are equal to the other two
 * (measure_scan.c's header), by 6 popcounts, not 17: p, q are the columns
 * that differ (hi and lo words), across the axis along which they differ.
 * b = a and d = c (columns x - 1 and x equal in both rows): p = a, q = c,
 * across y; V - E = -(a | c) - (c | c.lo) in popcounts, no x transitions,
 * and the xy, xz, xyz ones twice the y, z, yz ones. c = a and d = b (rows
 * y - 1 and y equal, in a row equal to the one before): the same with x and
 * y swapped, p = a, q = b, across x. */
static inline __attribute__((always_inline)) void
pair_equal(__m512i p, __m512i q, __m512i pl, __m512i ql, __m512i *vneg, __m512i t[BVOX__NDIR],
           int across, int across_z, int along_z)
{
    __m512i ta = PC(_mm512_xor_si512(p, q)), tz = PC(_mm512_xor_si512(q, ql));
    __m512i taz = _mm512_add_epi64(PC(_mm512_xor_si512(pl, q)), PC(_mm512_xor_si512(p, ql)));
    *vneg = _mm512_add_epi64(*vneg, PC(_mm512_or_si512(p, q)));
    *vneg = _mm512_add_epi64(*vneg, PC(_mm512_or_si512(q, ql)));
    t[across] = _mm512_add_epi64(t[across], ta);
    t[BVOX__DIR_Z] = _mm512_add_epi64(t[BVOX__DIR_Z], tz);
    t[BVOX__DIR_XY] = _mm512_add_epi64(t[BVOX__DIR_XY], _mm512_slli_epi64(ta, 1));
    t[along_z] = _mm512_add_epi64(t[along_z], _mm512_slli_epi64(tz, 1));
    t[across_z] = _mm512_add_epi64(t[across_z], taz);
    t[BVOX__DIR_XYZ] = _mm512_add_epi64(t[BVOX__DIR_XYZ], _mm512_slli_epi64(taz, 1));
}

/* The 8 x 64 windows of eight z-words of the columns a, b, c, d (hi words
 * ah..dh, lo words al..dl) added to the accumulators: V into vpos, E into
 * vneg (F - C comes from totals, measure_scan.c), the transitions into t;
 * eight words of all-1 windows only count in *full. */
static inline __attribute__((always_inline)) void
windows(__m512i ah, __m512i bh, __m512i ch, __m512i dh, __m512i al, __m512i bl, __m512i cl,
        __m512i dl, __m512i *vpos, __m512i *vneg, __m512i t[BVOX__NDIR], int64_t *full)
{
    const __m512i ones = _mm512_set1_epi64(-1);
    __m512i hor = _mm512_or_si512(OR3(ah, bh, ch), dh);
    __m512i bdl = OR3(bh, bl, _mm512_or_si512(dh, dl));
    __m512i cdl = OR3(ch, cl, _mm512_or_si512(dh, dl));
    __m512i any = OR3(hor, bdl, cdl); /* a.lo is in neither */
    any = _mm512_or_si512(any, al);
    if (!_mm512_test_epi64_mask(any, any)) return; /* all 0 */
    __m512i xd = _mm512_ternarylogic_epi64(_mm512_xor_si512(ah, bh), ch, dh, 0xf6);
    xd = _mm512_or_si512(xd, _mm512_ternarylogic_epi64(_mm512_xor_si512(al, bl), cl, dl, 0xf6));
    if (!_mm512_test_epi64_mask(xd, xd)) {
        pair_equal(ah, ch, al, cl, vneg, t, BVOX__DIR_Y, BVOX__DIR_YZ, BVOX__DIR_XZ);
        return;
    }
    __m512i yd = _mm512_ternarylogic_epi64(_mm512_xor_si512(ah, ch), bh, dh, 0xf6);
    yd = _mm512_or_si512(yd, _mm512_ternarylogic_epi64(_mm512_xor_si512(al, cl), bl, dl, 0xf6));
    if (!_mm512_test_epi64_mask(yd, yd)) {
        pair_equal(ah, bh, al, bl, vneg, t, BVOX__DIR_X, BVOX__DIR_XZ, BVOX__DIR_YZ);
        return;
    }
    __m512i all = AND3(AND3(ah, bh, ch), AND3(dh, al, bl), _mm512_and_si512(cl, dl));
    if (!_mm512_cmpneq_epi64_mask(all, ones)) {
        (*full)++; /* all 1 */
        return;
    }
    /* V - E */
    *vpos = _mm512_add_epi64(*vpos, PC(any));
    *vneg = _mm512_add_epi64(*vneg, PC(hor));
    *vneg = _mm512_add_epi64(*vneg, PC(bdl));
    *vneg = _mm512_add_epi64(*vneg, PC(cdl));
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

static void cells_row(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc,
                      bool extra, const uint64_t *zero, bvox__scan *s)
{
    __m512i vpos = _mm512_setzero_si512(), vneg = _mm512_setzero_si512();
    __m512i t[BVOX__NDIR];
    for (int i = 0; i < BVOX__NDIR; i++) t[i] = _mm512_setzero_si512();
    int64_t eul = 0, ts[BVOX__NDIR] = {0}; /* the extra words, scalar */
    int64_t full = 0;                       /* vectors of all-1 windows */
    if (wpc <= 8) {
        /* one vector a column: vertex column x's a and c are x - 1's b and
         * d, so each column is loaded and shifted once, not twice */
        const __m512i z = _mm512_setzero_si512();
        __mmask8 m = wpc == 8 ? (__mmask8)0xff : (__mmask8)((1u << wpc) - 1);
        __m512i ah = z, al = z, ch = z, cl = z;
        uint64_t atop = 0, ctop = 0; /* the top voxels, for the extra word */
        for (size_t x = 0; x <= nx; x++) {
            const uint64_t *B = prev && x < nx ? prev + x * wpc : zero;
            const uint64_t *D = cur && x < nx ? cur + x * wpc : zero;
            __m512i bh = _mm512_maskz_loadu_epi64(m, B), dh = _mm512_maskz_loadu_epi64(m, D);
            __m512i bl = lo_of(bh, z, m), dl = lo_of(dh, z, m);
            windows(ah, bh, ch, dh, al, bl, cl, dl, &vpos, &vneg, t, &full);
            uint64_t btop = B[wpc - 1] >> 63, dtop = D[wpc - 1] >> 63;
            if (extra) bvox__cells_word(0, 0, 0, 0, atop, btop, ctop, dtop, &eul, ts, true);
            ah = bh, al = bl, ch = dh, cl = dl, atop = btop, ctop = dtop;
        }
    } else {
        for (size_t x = 0; x <= nx; x++) {
            const uint64_t *col[4];
            bvox__cells_cols(prev, cur, x, nx, wpc, zero, col);
            const uint64_t *A = col[0], *B = col[1], *C = col[2], *D = col[3];
            __m512i pa = _mm512_setzero_si512(), pb = pa, pc = pa, pd = pa;
            for (size_t k = 0; k < wpc; k += 8) {
                __mmask8 m = wpc - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (wpc - k)) - 1);
                __m512i ah = _mm512_maskz_loadu_epi64(m, A + k);
                __m512i bh = _mm512_maskz_loadu_epi64(m, B + k);
                __m512i ch = _mm512_maskz_loadu_epi64(m, C + k);
                __m512i dh = _mm512_maskz_loadu_epi64(m, D + k);
                __m512i al = lo_of(ah, pa, m), bl = lo_of(bh, pb, m);
                __m512i cl = lo_of(ch, pc, m), dl = lo_of(dh, pd, m);
                pa = ah, pb = bh, pc = ch, pd = dh;
                windows(ah, bh, ch, dh, al, bl, cl, dl, &vpos, &vneg, t, &full);
            }
            if (extra)
                bvox__cells_word(0, 0, 0, 0, A[wpc - 1] >> 63, B[wpc - 1] >> 63, C[wpc - 1] >> 63,
                                 D[wpc - 1] >> 63, &eul, ts, true);
        }
    }
    /* V - E of a full vector: 8 x 64 x (1 - 3) */
    s->euler += eul - full * 1024 + _mm512_reduce_add_epi64(_mm512_sub_epi64(vpos, vneg));
    for (int i = 0; i < BVOX__NDIR; i++) s->trans[i] += ts[i] + _mm512_reduce_add_epi64(t[i]);
}

/* Nibble tables for the moments: bits set, sum of their indices i, sum of
 * i^2 (i = 0..3), in each 128-bit quarter (vpshufb looks up within one). */
#define NIB(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o, p)                                  \
    _mm512_broadcast_i32x4(_mm_setr_epi8(a, b, c, d, e, f, g, h, i, j, k, l, m, n, o, p))

/* 16-bit pair sums of a maddubs result gathered into their 64-bit lanes. */
static inline __m512i lanes_of16(__m512i v)
{
    __m512i s32 = _mm512_madd_epi16(v, _mm512_set1_epi16(1));
    return _mm512_add_epi64(_mm512_and_si512(s32, _mm512_set1_epi64(0xffffffff)),
                            _mm512_srli_epi64(s32, 32));
}

/* Whether the n words at a and b are equal. */
static inline bool same_words(const uint64_t *a, const uint64_t *b, size_t n)
{
    for (size_t k = 0; k < n; k += 8) {
        __mmask8 m = n - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (n - k)) - 1);
        __m512i va = _mm512_maskz_loadu_epi64(m, a + k), vb = _mm512_maskz_loadu_epi64(m, b + k);
        if (_mm512_cmpneq_epi64_mask(va, vb)) return false;
    }
    return true;
}

/* The moments of one row of columns, eight words at a time, by bytes as in
 * measure_scan_avx2.c: a byte j of a word with count p, index sum s1 and
 * square sum s2 (of its bits' indices 0..7; by two nibble look-ups each)
 * adds p to the word's count c, 8 j p + s1 to t1 and 64 j^2 p + 16 j s1 + s2
 * to t2; the j-weighted sums are vpmaddubsw's, the plain ones vpsadbw's.
 * Per column the lanes' c, t1 and t2 are summed over its vectors (vector v
 * shifting its t1 and t2 to word index 8 v + lane); the row's sums of c,
 * x c, x^2 c, t1, t2 and x t1 stay lane-wise in registers, x applied by
 * multiplies, and the lane's own word index i only at the row's end:
 * sz = 64 i c + t1, szz = 4096 i^2 c + 128 i t1 + t2. Per column only its
 * z range and runs (for the hull) are reduced. A column equal to the one
 * before it (in a smooth object most are, in an upsampled one nearly all)
 * reuses that one's lane sums, z range and runs. Every product fits the
 * 32 x 32 -> 64-bit multiply: v < 128, c <= 64, t1 < 2^11, a lane's t1 over
 * a column < 2^30, x < 2^16. (The bit-mask formula of measure_scan.c, 22
 * popcounts a vector, and a reduction per column and sum took twice the
 * time: VPOPCNTQ has one port.) */
static void row_moments(const uint64_t *row, size_t nx, size_t wpc, int32_t y, bvox__scan *s)
{
    const __m512i tp = NIB(0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4);
    const __m512i ts1 = NIB(0, 0, 1, 1, 2, 2, 3, 3, 3, 3, 4, 4, 5, 5, 6, 6);
    const __m512i ts2 = NIB(0, 0, 1, 1, 4, 4, 5, 5, 9, 9, 10, 10, 13, 13, 14, 14);
    const __m512i low = _mm512_set1_epi8(0x0f), zero = _mm512_setzero_si512();
    const __m512i w1 = _mm512_set1_epi64(0x0706050403020100ll);
    const __m512i w2 = _mm512_set1_epi64(0x3124191009040100ll);
    /* the row's c, x c, x^2 c, t1, t2, x t1 per lane (word index mod 8) */
    __m512i acc[6] = {zero, zero, zero, zero, zero, zero};
    /* the column's sums; one equal to the column before it keeps them */
    __m512i vn = zero, vt1 = zero, vt2 = zero, vruns = zero;
    int32_t zlo = -1, zhi = -1;
    for (size_t x = 0; x < nx; x++) {
        const uint64_t *col = row + x * wpc;
        if (x && same_words(col, col - wpc, wpc)) goto sums;
        vn = vt1 = vt2 = vruns = zero;
        zlo = zhi = -1;
        __m512i prev = zero;
        for (size_t k = 0; k < wpc; k += 8) {
            __mmask8 m = wpc - k >= 8 ? (__mmask8)0xff : (__mmask8)((1u << (wpc - k)) - 1);
            __m512i w = _mm512_maskz_loadu_epi64(m, col + k), below = prev;
            prev = w;
            __mmask8 nz = _mm512_test_epi64_mask(w, w);
            if (!nz) continue;
            size_t first = k + (size_t)__builtin_ctz(nz), last = k + 31 - (size_t)__builtin_clz(nz);
            if (zlo < 0) zlo = (int32_t)(first * 64 + (size_t)__builtin_ctzll(col[first]));
            zhi = (int32_t)(last * 64 + 64 - (size_t)__builtin_clzll(col[last]));
            /* runs: starts are 1-bits whose lower neighbour (lo_of) is 0 */
            __m512i starts = _mm512_andnot_si512(lo_of(w, below, m), w);
            vruns = _mm512_add_epi64(vruns, PC(starts));
            __m512i lo = _mm512_and_si512(w, low);
            __m512i hi = _mm512_and_si512(_mm512_srli_epi16(w, 4), low);
            __m512i plo = _mm512_shuffle_epi8(tp, lo), phi = _mm512_shuffle_epi8(tp, hi);
            __m512i s1hi = _mm512_shuffle_epi8(ts1, hi);
            __m512i p = _mm512_add_epi8(plo, phi);
            /* the high nibble's bits sit 4 higher: i + 4 */
            __m512i s1 = _mm512_add_epi8(_mm512_add_epi8(_mm512_shuffle_epi8(ts1, lo), s1hi),
                                         _mm512_slli_epi16(phi, 2));
            __m512i s2 = _mm512_add_epi8(
                _mm512_add_epi8(_mm512_shuffle_epi8(ts2, lo), _mm512_shuffle_epi8(ts2, hi)),
                _mm512_add_epi8(_mm512_slli_epi16(s1hi, 3), _mm512_slli_epi16(phi, 4)));
            __m512i c = _mm512_sad_epu8(p, zero);
            __m512i jp = lanes_of16(_mm512_maddubs_epi16(p, w1));
            __m512i jjp = lanes_of16(_mm512_maddubs_epi16(p, w2));
            __m512i js1 = lanes_of16(_mm512_maddubs_epi16(s1, w1));
            __m512i t1 = _mm512_add_epi64(_mm512_slli_epi64(jp, 3), _mm512_sad_epu8(s1, zero));
            __m512i t2 = _mm512_add_epi64(_mm512_add_epi64(_mm512_slli_epi64(jjp, 6),
                                                           _mm512_slli_epi64(js1, 4)),
                                          _mm512_sad_epu8(s2, zero));
            if (k) {
                /* vector v = k / 8: its lanes' word index is 8 v + lane, so
                 * t1 += 512 v c, t2 += 1024 v t1 + 2^18 v^2 c (v < 128) */
                __m512i v = _mm512_set1_epi64((long long)(k / 8));
                __m512i vv = _mm512_set1_epi64((long long)(k / 8 * (k / 8)));
                t2 = _mm512_add_epi64(t2, _mm512_slli_epi64(_mm512_mul_epu32(v, t1), 10));
                t2 = _mm512_add_epi64(t2, _mm512_slli_epi64(_mm512_mul_epu32(vv, c), 18));
                t1 = _mm512_add_epi64(t1, _mm512_slli_epi64(_mm512_mul_epu32(v, c), 9));
            }
            vn = _mm512_add_epi64(vn, c);
            vt1 = _mm512_add_epi64(vt1, t1);
            vt2 = _mm512_add_epi64(vt2, t2);
        }
    sums:
        if (zlo < 0) {
            if (s->hull_row) s->hull_row[x] = (bvox__colhull){0, 0, 0, 0};
            continue;
        }
        __m512i X = _mm512_set1_epi64((long long)x), XX = _mm512_set1_epi64((long long)x * x);
        acc[0] = _mm512_add_epi64(acc[0], vn);
        acc[1] = _mm512_add_epi64(acc[1], _mm512_mul_epu32(X, vn));
        acc[2] = _mm512_add_epi64(acc[2], _mm512_mul_epu32(XX, vn));
        acc[3] = _mm512_add_epi64(acc[3], vt1);
        acc[4] = _mm512_add_epi64(acc[4], vt2);
        acc[5] = _mm512_add_epi64(acc[5], _mm512_mul_epu32(X, vt1));
        bvox__bbox_add(s, (int32_t)x, y, zlo, zhi);
        if (s->hull_row)
            s->hull_row[x] = (bvox__colhull){zlo + 1, zhi - 1,
                                             (uint32_t)_mm512_reduce_add_epi64(vruns) - 1, 0};
    }
    /* the lanes' word index i applied: sz = 64 i c + t1, szz = 4096 i^2 c +
     * 128 i t1 + t2 (and x sz likewise from x c and x t1) */
    uint64_t a[6][8];
    for (int i = 0; i < 6; i++) _mm512_storeu_si512(a[i], acc[i]);
    for (uint64_t i = 0; i < 8; i++) {
        s->row[0] += a[0][i], s->row[1] += a[1][i], s->row[2] += a[2][i];
        s->row[3] += 64 * i * a[0][i] + a[3][i];
        s->row[4] += 4096 * i * i * a[0][i] + 128 * i * a[3][i] + a[4][i];
        s->row[5] += 64 * i * a[1][i] + a[5][i];
    }
}

const bvox__cells_row_fn bvox__cells_row_avx512 = cells_row;
const bvox__row_moments_fn bvox__row_moments_avx512 = row_moments;
#else
const bvox__cells_row_fn bvox__cells_row_avx512 = NULL;
const bvox__row_moments_fn bvox__row_moments_avx512 = NULL;
#endif
