/*
 * bits.h — the 64x64 bit transpose: the step between 64 rows of 64 pixels
 * (images, slices, contour bitmaps) and 64 columns of 64 z voxels (the
 * volume's packing). Used by the binariser, the writers' unpacker, binvox,
 * and the contour stacks in both directions.
 */
#ifndef BVOX_COMMON_BITS_H
#define BVOX_COMMON_BITS_H

#include <stdint.h>

/* In-place transpose of a 64x64 bit matrix: afterwards bit c of m[r] is what
 * bit r of m[c] was (bit 0 = least significant). Six rounds of masked swaps
 * of ever smaller sub-blocks (Hacker's Delight, 2nd ed., 7-3), each round
 * written with a constant shift so that the compiler unrolls it and runs the
 * wide rounds on vector registers. */
#define BVOX__TRANSPOSE_ROUND(m, J, MASK)                                                  \
    for (unsigned k_ = 0; k_ < 64; k_ += 2 * (J))                                          \
        for (unsigned i_ = k_; i_ < k_ + (J); i_++) {                                      \
            uint64_t t_ = ((m[i_] >> (J)) ^ m[i_ + (J)]) & (MASK);                         \
            m[i_] ^= t_ << (J);                                                            \
            m[i_ + (J)] ^= t_;                                                             \
        }
static inline void bvox__transpose64(uint64_t m[64])
{
    BVOX__TRANSPOSE_ROUND(m, 32, 0x00000000FFFFFFFFull)
    BVOX__TRANSPOSE_ROUND(m, 16, 0x0000FFFF0000FFFFull)
    BVOX__TRANSPOSE_ROUND(m, 8, 0x00FF00FF00FF00FFull)
    BVOX__TRANSPOSE_ROUND(m, 4, 0x0F0F0F0F0F0F0F0Full)
    BVOX__TRANSPOSE_ROUND(m, 2, 0x3333333333333333ull)
    BVOX__TRANSPOSE_ROUND(m, 1, 0x5555555555555555ull)
}

#endif
