/*
 * measure_flood_avx2.c — one row of the flood's sweep (measure_flood.c)
 * with AVX2, for columns of at most eight words (nz <= 512): a column is two
 * vectors, words 0-3 and 4-7, lanes past wpc zero. The same steps as
 * measure_flood_avx512.c (read it first), without its mask registers:
 * unsigned compares by flipping the sign bit, lane masks by movemask, and
 * the lanes that receive a carry spread back to a vector by comparing the
 * mask with each lane's bit.
 *
 * Threads: as in measure_flood_avx512.c, each aligned 8-byte lane of a
 * vector load is read whole, and R only grows.
 */
#include "measure/measure.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>

typedef struct col {
    __m256i lo, hi; /* words 0-3, 4-7 */
} col;

/* A column's words; masked unless it has all eight (masked stores are slow
 * on some AMD cores, and a 512^3 volume's columns are eight words). */
static inline col load(const uint64_t *p, col lanes, int eight)
{
    if (eight)
        return (col){_mm256_loadu_si256((const __m256i *)p),
                     _mm256_loadu_si256((const __m256i *)p + 1)};
    return (col){_mm256_maskload_epi64((const long long *)p, lanes.lo),
                 _mm256_maskload_epi64((const long long *)p + 4, lanes.hi)};
}

static inline void store(uint64_t *p, col lanes, int eight, col v)
{
    if (eight) {
        _mm256_storeu_si256((__m256i *)p, v.lo);
        _mm256_storeu_si256((__m256i *)p + 1, v.hi);
        return;
    }
    _mm256_maskstore_epi64((long long *)p, lanes.lo, v.lo);
    _mm256_maskstore_epi64((long long *)p + 4, lanes.hi, v.hi);
}

static inline col or2(col a, col b)
{
    return (col){_mm256_or_si256(a.lo, b.lo), _mm256_or_si256(a.hi, b.hi)};
}

static inline col and2(col a, col b)
{
    return (col){_mm256_and_si256(a.lo, b.lo), _mm256_and_si256(a.hi, b.hi)};
}

/* One bit per word (bit i: word i) of a compare's result. */
static inline unsigned mask8(__m256i lo, __m256i hi)
{
    return (unsigned)_mm256_movemask_pd(_mm256_castsi256_pd(lo)) |
           (unsigned)_mm256_movemask_pd(_mm256_castsi256_pd(hi)) << 4;
}

/* The words of mask m as all-ones lanes. */
static inline col lanes_of(unsigned m)
{
    const __m256i blo = _mm256_setr_epi64x(1, 2, 4, 8), bhi = _mm256_setr_epi64x(16, 32, 64, 128);
    __m256i v = _mm256_set1_epi64x((long long)m);
    return (col){_mm256_cmpeq_epi64(_mm256_and_si256(v, blo), blo),
                 _mm256_cmpeq_epi64(_mm256_and_si256(v, bhi), bhi)};
}

static inline __m256i fill_down1(__m256i x, __m256i p)
{
#define STEP(n)                                                                       \
    x = _mm256_or_si256(x, _mm256_and_si256(p, _mm256_srli_epi64(x, n)));             \
    p = _mm256_and_si256(p, _mm256_srli_epi64(p, n))
    STEP(1);
    STEP(2);
    STEP(4);
    STEP(8);
    STEP(16);
#undef STEP
    return _mm256_or_si256(x, _mm256_and_si256(p, _mm256_srli_epi64(x, 32)));
}

/* Seeds s downwards through the bits of m, within each word. */
static inline col fill_down(col s, col m)
{
    return (col){fill_down1(s.lo, m.lo), fill_down1(s.hi, m.hi)};
}

/* m + s, the words carrying out of bit 63 (m + s < m, unsigned) in *out. */
static inline __m256i up1(__m256i s, __m256i m, __m256i *carry)
{
    const __m256i sign = _mm256_set1_epi64x((long long)(1ull << 63));
    __m256i t = _mm256_add_epi64(m, s);
    *carry = _mm256_cmpgt_epi64(_mm256_xor_si256(m, sign), _mm256_xor_si256(t, sign));
    return _mm256_or_si256(_mm256_andnot_si256(t, m), s); /* (m & ~t) | s */
}

/* Seeds s upwards through the bits of m within each word; the words whose
 * filled run reaches bit 63. */
static inline col fill_up(col s, col m, unsigned *out)
{
    __m256i clo, chi;
    col r = {up1(s.lo, m.lo, &clo), up1(s.hi, m.hi, &chi)};
    *out = mask8(clo, chi);
    return r;
}

/* The runs of m holding a bit of s (s a subset of m). */
static inline col fill_runs(col s, col m)
{
    const __m256i ones = _mm256_set1_epi64x(-1), one = _mm256_set1_epi64x(1);
    const __m256i high = _mm256_set1_epi64x((long long)(1ull << 63));
    unsigned full = mask8(_mm256_cmpeq_epi64(m.lo, ones), _mm256_cmpeq_epi64(m.hi, ones)), out;
    s = fill_up(s, m, &out);
    unsigned in = bvox__lane_carry_up(out, full);
    if (in) s = fill_up(or2(s, and2(and2(lanes_of(in), m), (col){one, one})), m, &out);
    s = fill_down(s, m);
    unsigned bit0 = mask8(_mm256_slli_epi64(s.lo, 63), _mm256_slli_epi64(s.hi, 63));
    in = bvox__lane_carry_down(bit0, full);
    if (in) s = fill_down(or2(s, and2(and2(lanes_of(in), m), (col){high, high})), m);
    return s;
}

/* eight: wpc == 8, a constant in each of sweep_row's two calls */
static inline __attribute__((always_inline)) int row(const bvox__flood_row *w, int eight)
{
    size_t wpc = w->wpc, ystride = w->nx * wpc;
    col lanes = lanes_of((1u << wpc) - 1);
    const __m256i flip = _mm256_set1_epi64x((long long)w->flip);
    uint64_t tail[8], ends[8];
    bvox__flood_row_masks(w, tail, ends);
    const col vtail = {_mm256_loadu_si256((const __m256i *)tail),
                       _mm256_loadu_si256((const __m256i *)(tail + 4))};
    const col vends = {_mm256_loadu_si256((const __m256i *)ends),
                       _mm256_loadu_si256((const __m256i *)(ends + 4))};
    int changed = 0;
    for (size_t xi = 1; xi + 1 < w->nx; xi++) {
        size_t x = w->backward ? w->nx - 1 - xi : xi;
        if (!bvox__flood_due(w, w->stamps + x)) continue;
        uint64_t *r = w->r + x * wpc;
        col m = load(w->bg + x * wpc, lanes, eight);
        m = and2((col){_mm256_xor_si256(m.lo, flip), _mm256_xor_si256(m.hi, flip)}, vtail);
        col old = load(r, lanes, eight);
        col nb = or2(or2(load(r - wpc, lanes, eight), load(r + wpc, lanes, eight)),
                     or2(load(r - ystride, lanes, eight), load(r + ystride, lanes, eight)));
        col t = and2(or2(or2(old, nb), vends), m);
        if (mask8(_mm256_cmpeq_epi64(t.lo, old.lo), _mm256_cmpeq_epi64(t.hi, old.hi)) == 0xff)
            continue;
        store(r, lanes, eight, fill_runs(t, m));
        __atomic_store_n(&w->stamps[x], w->sweep, __ATOMIC_RELAXED);
        changed = 1;
    }
    return changed;
}

static int sweep_row(const bvox__flood_row *w) { return w->wpc == 8 ? row(w, 1) : row(w, 0); }

const bvox__flood_row_fn bvox__flood_row_avx2 = sweep_row;
#else
const bvox__flood_row_fn bvox__flood_row_avx2 = NULL;
#endif
