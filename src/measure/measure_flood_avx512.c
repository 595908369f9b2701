/*
 * measure_flood_avx512.c — one row of the flood's sweep (measure_flood.c)
 * with AVX-512F, for columns of at most eight words (nz <= 512): a column is
 * one vector, lanes past wpc zero.
 *
 * A visit is then a dozen instructions where the portable row spends one
 * or two per word: the test (R | R of the neighbours | the end voxels) & bg
 * against R, and, when it grew, the fill of the runs of bg holding a seed:
 * upwards within each lane by an addition (m + s carries from a run's
 * lowest seed through its top), downwards by a Kogge-Stone fill, the runs
 * that cross lanes by carrying between the eight lanes as a byte mask (a
 * lane passes a carry on when its bg is all ones). The result is the same
 * union of runs as the portable fill_column's (tests/unit/
 * test_measure_cavities.c runs the flood at every SIMD level).
 *
 * Threads: a column's neighbours in the rows beside it may belong to a row
 * another thread is storing. Each aligned 8-byte lane of a vector load is
 * read whole on x86-64, and a mix of a word's old and new bits would still
 * be a subset of R, which only grows; a stale read is caught by the stamps
 * (the column is due again in the next sweep).
 */
#include "measure/measure.h"

#if defined(__x86_64__) && defined(__AVX512F__)
#include <immintrin.h>

#define OR3(a, b, c) _mm512_ternarylogic_epi64(a, b, c, 0xfe)
/* a | (b & c) */
#define OR_AND(a, b, c) _mm512_ternarylogic_epi64(a, b, c, 0xf8)

/* Seeds x downwards through the bits of m, within each lane. */
static inline __m512i fill_down(__m512i x, __m512i m)
{
    __m512i p = m;
    x = OR_AND(x, p, _mm512_srli_epi64(x, 1)), p = _mm512_and_si512(p, _mm512_srli_epi64(p, 1));
    x = OR_AND(x, p, _mm512_srli_epi64(x, 2)), p = _mm512_and_si512(p, _mm512_srli_epi64(p, 2));
    x = OR_AND(x, p, _mm512_srli_epi64(x, 4)), p = _mm512_and_si512(p, _mm512_srli_epi64(p, 4));
    x = OR_AND(x, p, _mm512_srli_epi64(x, 8)), p = _mm512_and_si512(p, _mm512_srli_epi64(p, 8));
    x = OR_AND(x, p, _mm512_srli_epi64(x, 16)), p = _mm512_and_si512(p, _mm512_srli_epi64(p, 16));
    return OR_AND(x, p, _mm512_srli_epi64(x, 32));
}

/* Seeds s upwards through the bits of m within each lane, and the lanes
 * whose filled run reaches bit 63 (a carry out). */
static inline __m512i fill_up(__m512i s, __m512i m, __mmask8 *out)
{
    __m512i t = _mm512_add_epi64(m, s);
    *out = _mm512_cmplt_epu64_mask(t, m);
    return _mm512_ternarylogic_epi64(m, t, s, 0xba); /* (m & ~t) | s */
}

/* The runs of m holding a bit of s (s a subset of m). */
static inline __m512i fill_runs(__m512i s, __m512i m)
{
    const __m512i one = _mm512_set1_epi64(1), high = _mm512_set1_epi64((long long)(1ull << 63));
    unsigned full = _mm512_cmpeq_epi64_mask(m, _mm512_set1_epi64(-1));
    __mmask8 out;
    s = fill_up(s, m, &out);
    unsigned in = bvox__lane_carry_up(out, full);
    if (in) {
        s = _mm512_mask_or_epi64(s, (__mmask8)in, s, _mm512_and_si512(m, one));
        s = fill_up(s, m, &out);
    }
    s = fill_down(s, m);
    in = bvox__lane_carry_down(_mm512_test_epi64_mask(s, one), full);
    if (in) s = fill_down(_mm512_mask_or_epi64(s, (__mmask8)in, s, _mm512_and_si512(m, high)), m);
    return s;
}

static int sweep_row(const bvox__flood_row *w)
{
    size_t wpc = w->wpc, ystride = w->nx * wpc;
    __mmask8 lanes = (__mmask8)((1u << wpc) - 1);
    const __m512i flip = _mm512_set1_epi64((long long)w->flip);
    uint64_t tail[8], ends[8];
    bvox__flood_row_masks(w, tail, ends);
    const __m512i vtail = _mm512_loadu_si512(tail), vends = _mm512_loadu_si512(ends);
    int changed = 0;
    for (size_t xi = 1; xi + 1 < w->nx; xi++) {
        size_t x = w->backward ? w->nx - 1 - xi : xi;
        if (!bvox__flood_due(w, w->stamps + x)) continue;
        uint64_t *r = w->r + x * wpc;
        __m512i m = _mm512_maskz_loadu_epi64(lanes, w->bg + x * wpc);
        m = _mm512_ternarylogic_epi64(m, flip, vtail, 0x28); /* (m ^ flip) & tail */
        __m512i old = _mm512_maskz_loadu_epi64(lanes, r);
        __m512i nb = OR3(_mm512_maskz_loadu_epi64(lanes, r - wpc),
                         _mm512_maskz_loadu_epi64(lanes, r + wpc),
                         _mm512_maskz_loadu_epi64(lanes, r - ystride));
        nb = OR3(nb, _mm512_maskz_loadu_epi64(lanes, r + ystride), vends);
        __m512i t = _mm512_and_si512(_mm512_or_si512(old, nb), m);
        if (!_mm512_cmpneq_epu64_mask(t, old)) continue;
        _mm512_mask_storeu_epi64(r, lanes, fill_runs(t, m));
        __atomic_store_n(&w->stamps[x], w->sweep, __ATOMIC_RELAXED);
        changed = 1;
    }
    return changed;
}

const bvox__flood_row_fn bvox__flood_row_avx512 = sweep_row;
#else
const bvox__flood_row_fn bvox__flood_row_avx512 = NULL;
#endif
