/*
 * kernels_generic.c — portable word kernels, the reference every SIMD path is
 * compared with. Plain loops that any compiler can vectorise with the
 * baseline instruction set; popcount uses the bit-slicing formula because
 * baseline x86-64 has no POPCNT instruction.
 */
#include "internal.h"

static uint64_t popcount(const uint64_t *w, size_t n)
{
    uint64_t total = 0;
    for (size_t i = 0; i < n; i++) total += bvox__popcount64(w[i]);
    return total;
}

static uint64_t popcount_and(const uint64_t *a, const uint64_t *b, size_t n)
{
    uint64_t total = 0;
    for (size_t i = 0; i < n; i++) total += bvox__popcount64(a[i] & b[i]);
    return total;
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
