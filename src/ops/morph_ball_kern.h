/* morph_ball_kern.h — the inner loops of morph_ball.c, written once in plain
 * C and compiled three times: in morph_ball.c (portable), morph_ball_avx2.c
 * and morph_ball_avx512.c (with those instruction sets on, so the compiler
 * vectorises them with wider registers); morph_ball.c picks one at run time
 * from bvox_simd_active(). Include with BALL_KERN(name) defined. */
#include "internal.h"

#include <stdbool.h>

/* The vector the file's flags allow: one zmm (8 words), one ymm (4) or
 * one xmm (2) as a GCC vector, loaded and stored at 8-byte alignment.
 * (A wider vector than the registers is split badly by the compiler.) */
#if defined(__AVX512F__)
#define BALL_VW 8
#elif defined(__AVX2__)
#define BALL_VW 4
#else
#define BALL_VW 2
#endif
#define BALL_NACC (16 / BALL_VW)

/* Words are gathered 16 at a time: the accumulators stay in registers
 * while every term of a slice is loaded once. */
static inline __attribute__((always_inline)) void
BALL_KERN(gather_op)(uint64_t *restrict run, bool first, uint64_t *restrict o1,
                     uint64_t *restrict o2, const uint64_t *const *p, int np, size_t n,
                     bool erode)
{
    typedef uint64_t vec __attribute__((vector_size(BALL_VW * 8), aligned(8), may_alias));
    size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        vec a[BALL_NACC];
        for (int q = 0; q < BALL_NACC; q++)
            a[q] = *(const vec *)((first ? p[0] : run) + i + q * BALL_VW);
        for (int t = first ? 1 : 0; t < np; t++) {
            const uint64_t *s = p[t] + i;
            for (int q = 0; q < BALL_NACC; q++) {
                vec x = *(const vec *)(s + q * BALL_VW);
                a[q] = erode ? a[q] & x : a[q] | x;
            }
        }
        for (int q = 0; q < BALL_NACC; q++) {
            *(vec *)(run + i + q * BALL_VW) = a[q];
            if (!o1) continue;
            vec *d = (vec *)(o1 + i + q * BALL_VW);
            *d = erode ? *d & a[q] : *d | a[q];
            if (o2) {
                d = (vec *)(o2 + i + q * BALL_VW);
                *d = erode ? *d & a[q] : *d | a[q];
            }
        }
    }
    for (; i < n; i++) {
        uint64_t acc = first ? p[0][i] : run[i];
        for (int t = first ? 1 : 0; t < np; t++) acc = erode ? acc & p[t][i] : acc | p[t][i];
        run[i] = acc;
        if (!o1) continue;
        o1[i] = erode ? o1[i] & acc : o1[i] | acc;
        if (o2) o2[i] = erode ? o2[i] & acc : o2[i] | acc;
    }
}

/* run = the OR (AND when erode) of the np arrays p[t][0 .. n), and of run
 * itself unless first (np >= 1 when first); then o1 and o2 (each unless
 * NULL) OR= (AND=) run. */
void BALL_KERN(gather)(uint64_t *run, bool first, uint64_t *o1, uint64_t *o2,
                       const uint64_t *const *p, int np, size_t n, bool erode)
{
    if (erode) {
        if (first) BALL_KERN(gather_op)(run, true, o1, o2, p, np, n, true);
        else BALL_KERN(gather_op)(run, false, o1, o2, p, np, n, true);
    } else {
        if (first) BALL_KERN(gather_op)(run, true, o1, o2, p, np, n, false);
        else BALL_KERN(gather_op)(run, false, o1, o2, p, np, n, false);
    }
}

static inline __attribute__((always_inline)) uint64_t BALL_KERN(op3)(uint64_t a, uint64_t b,
                                                                     uint64_t c, bool erode)
{
    return erode ? (a & b & c) : (a | b | c);
}

static inline __attribute__((always_inline)) void
BALL_KERN(step_op)(uint64_t *restrict dst, const uint64_t *restrict src, size_t ncols, size_t wpc,
                   int s, uint64_t tail, bool erode)
{
    if (wpc == 1) {
        for (size_t c = 0; c < ncols; c++) {
            uint64_t x = src[c];
            dst[c] = BALL_KERN(op3)(x, x << s, x >> s, erode) & tail;
        }
        return;
    }
    size_t n = ncols * wpc;
    int r = 64 - s;
    for (size_t i = 1; i + 1 < n; i++) {
        uint64_t x = src[i];
        dst[i] = BALL_KERN(op3)(x, (x << s) | (src[i - 1] >> r), (x >> s) | (src[i + 1] << r), erode);
    }
    for (size_t i = 0; i < n; i += wpc) {
        uint64_t x = src[i], y = src[i + wpc - 1];
        dst[i] = BALL_KERN(op3)(x, x << s, (x >> s) | (src[i + 1] << r), erode);
        dst[i + wpc - 1] = BALL_KERN(op3)(y, (y << s) | (src[i + wpc - 2] >> r), y >> s, erode) & tail;
    }
}

/* dst = every column of src (ncols columns of wpc words) op'ed with itself
 * shifted by -s and +s bits, 1 <= s <= 63; bits shifted in from outside are
 * 0. The words are one flat array: the loop over it reads both neighbours
 * unconditionally (no carried dependency, so it vectorises), then the first
 * and last word of each column are redone without their neighbours in
 * other columns. */
void BALL_KERN(step)(uint64_t *dst, const uint64_t *src, size_t ncols, size_t wpc, int s,
                     uint64_t tail, bool erode)
{
    if (erode) BALL_KERN(step_op)(dst, src, ncols, wpc, s, tail, true);
    else BALL_KERN(step_op)(dst, src, ncols, wpc, s, tail, false);
}
