/*
 * kernels_generic.c — portable word kernels, the reference every SIMD path is
 * compared with. Plain loops that any compiler can vectorise with the
 * baseline instruction set; popcount uses the bit-slicing formula (through a
 * carry-save adder tree, 32 words at a time) because baseline x86-64 has no
 * POPCNT instruction.
 */
#include "internal.h"

/* Two words as one GCC vector: SSE2 on baseline x86-64, whatever the
 * target has elsewhere. */
typedef uint64_t v2 __attribute__((vector_size(16), aligned(8), may_alias));

/* Popcount of each lane (the bit-slicing formula, summed by shifts: SSE2
 * has no 64-bit multiply). */
static inline v2 lane_popcount(v2 x)
{
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
    x += x >> 8;
    x += x >> 16;
    x += x >> 32;
    return x & 0x7f;
}

/* Carry-save adder: h:l = a + b + c, bit by bit. */
#define CSA(h, l, a, b, c)                                                                  \
    do {                                                                                    \
        v2 u_ = (a) ^ (b);                                                                  \
        h = ((a) & (b)) | (u_ & (c));                                                       \
        l = u_ ^ (c);                                                                       \
    } while (0)

/* Harley-Seal (Lemire, Kurz and Mula, "Faster population counts using AVX2
 * instructions", 2018) on two-word vectors: 32 words go through a tree of
 * carry-save adders and only the sixteens are counted, so the slow
 * bit-slicing count runs once per 32 words instead of once per word (about
 * 3x the per-word formula, which kept the portable count at a third of
 * memcpy's speed at 1024^3). With b, counts a & b. */
static inline __attribute__((always_inline)) uint64_t popcount_hs(const uint64_t *a,
                                                                   const uint64_t *b, size_t n)
{
    v2 total = {0, 0}, ones = {0, 0}, twos = {0, 0}, fours = {0, 0}, eights = {0, 0};
    v2 twos_a, twos_b, fours_a, fours_b, eights_a, eights_b, sixteens;
    size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        v2 p[16];
        for (int q = 0; q < 16; q++) {
            p[q] = *(const v2 *)(a + i + 2 * q);
            if (b) p[q] &= *(const v2 *)(b + i + 2 * q);
        }
        CSA(twos_a, ones, ones, p[0], p[1]);
        CSA(twos_b, ones, ones, p[2], p[3]);
        CSA(fours_a, twos, twos, twos_a, twos_b);
        CSA(twos_a, ones, ones, p[4], p[5]);
        CSA(twos_b, ones, ones, p[6], p[7]);
        CSA(fours_b, twos, twos, twos_a, twos_b);
        CSA(eights_a, fours, fours, fours_a, fours_b);
        CSA(twos_a, ones, ones, p[8], p[9]);
        CSA(twos_b, ones, ones, p[10], p[11]);
        CSA(fours_a, twos, twos, twos_a, twos_b);
        CSA(twos_a, ones, ones, p[12], p[13]);
        CSA(twos_b, ones, ones, p[14], p[15]);
        CSA(fours_b, twos, twos, twos_a, twos_b);
        CSA(eights_b, fours, fours, fours_a, fours_b);
        CSA(sixteens, eights, eights, eights_a, eights_b);
        total += lane_popcount(sixteens);
    }
    total = 16 * total + 8 * lane_popcount(eights) + 4 * lane_popcount(fours) +
            2 * lane_popcount(twos) + lane_popcount(ones);
    uint64_t sum = total[0] + total[1];
    for (; i < n; i++) sum += bvox__popcount64(b ? a[i] & b[i] : a[i]);
    return sum;
}

static uint64_t popcount(const uint64_t *w, size_t n) { return popcount_hs(w, NULL, n); }

static uint64_t popcount_and(const uint64_t *a, const uint64_t *b, size_t n)
{
    return popcount_hs(a, b, n);
}

static void op_or(uint64_t *restrict d, const uint64_t *restrict s, size_t n)
{
    for (size_t i = 0; i < n; i++) d[i] |= s[i];
}
static void op_and(uint64_t *restrict d, const uint64_t *restrict s, size_t n)
{
    for (size_t i = 0; i < n; i++) d[i] &= s[i];
}
static void op_andnot(uint64_t *restrict d, const uint64_t *restrict s, size_t n)
{
    for (size_t i = 0; i < n; i++) d[i] &= ~s[i];
}
static void op_xor(uint64_t *restrict d, const uint64_t *restrict s, size_t n)
{
    for (size_t i = 0; i < n; i++) d[i] ^= s[i];
}
static void op_not(uint64_t *d, size_t n)
{
    for (size_t i = 0; i < n; i++) d[i] = ~d[i];
}

const bvox__kernels bvox__kernels_generic = {popcount, popcount_and, op_or, op_and,
                                             op_andnot, op_xor, op_not};
