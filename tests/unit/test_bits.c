/* test_bits.c — src/common/bits.h: the 64x64 bit transpose against the
 * definition (bit c of row r becomes bit r of row c), bit by bit. */
#include "harness.h"
#include "common/bits.h"

static int bit(const uint64_t m[64], int r, int c) { return (int)(m[r] >> c & 1); }

TEST(transpose_single_bits)
{
    /* one set bit at (r, c) must land at (c, r) and nowhere else */
    for (int r = 0; r < 64; r += 7)
        for (int c = 0; c < 64; c += 5) {
            uint64_t m[64] = {0};
            m[r] = 1ull << c;
            bvox__transpose64(m);
            for (int i = 0; i < 64; i++) CHECK_EQ(m[i], i == c ? 1ull << r : 0ull);
        }
    return 0;
}

TEST(transpose_random_against_definition_and_involution)
{
    for (int trial = 0; trial < 20; trial++) {
        uint64_t a[64], m[64];
        for (int i = 0; i < 64; i++) a[i] = m[i] = harness_rand();
        bvox__transpose64(m);
        for (int r = 0; r < 64; r++)
            for (int c = 0; c < 64; c++) CHECK_EQ(bit(m, r, c), bit(a, c, r));
        bvox__transpose64(m); /* twice is the identity */
        for (int i = 0; i < 64; i++) CHECK_EQ(m[i], a[i]);
    }
    return 0;
}

TEST(transpose_upper_triangle)
{
    /* row r holds bits r..63: afterwards row c holds bits 0..c */
    uint64_t m[64];
    for (int r = 0; r < 64; r++) m[r] = ~0ull << r;
    bvox__transpose64(m);
    for (int c = 0; c < 64; c++) CHECK_EQ(m[c], c == 63 ? ~0ull : (2ull << c) - 1);
    return 0;
}
