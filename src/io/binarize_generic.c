/*
 * binarize_generic.c — the portable compare kernels of bvox__binarize (the
 * reference path that the AVX2 / AVX-512 kernels are tested against).
 *
 * Each block of 64 samples is compared into 64 flag bytes (a loop the
 * compiler vectorises: no branches, fixed trip count), and the flags are
 * packed eight at a time with one multiply (see pack64).
 */
#include "binarize_kernels.h"

#include <string.h>

/* 64 bytes that are each 0 or 1 -> 64 bits. For v = sum f_k << 8k, the
 * product v * 0x0102040810204080 puts f_k at bit 56 + k with no carries
 * (each partial product lands on its own bit), so >> 56 gives the 8 flags. */
static inline uint64_t pack64(const uint8_t f[64])
{
    uint64_t m = 0;
    for (unsigned j = 0; j < 8; j++) {
        uint64_t v;
        memcpy(&v, f + 8 * j, 8);
        m |= ((v * 0x0102040810204080ull) >> 56) << (8 * j);
    }
    return m;
}

static inline uint8_t ident8(uint8_t x) { return x; }

#define INT_KERNEL(NAME, T, SWAP)                                                          \
    static void NAME(const void *src, size_t nb, const bvox__binpred *p, uint64_t *out,   \
                     size_t stride)                                                       \
    {                                                                                     \
        const unsigned char *s = src;                                                     \
        const T a = (T)p->a, w = (T)p->w;                                                 \
        const uint64_t inv = p->invert ? ~0ull : 0;                                       \
        for (size_t b = 0; b < nb; b++, s += 64 * sizeof(T)) {                            \
            T x[64];                                                                      \
            uint8_t f[64];                                                                \
            memcpy(x, s, sizeof x);                                                       \
            if (p->swap)                                                                  \
                for (unsigned i = 0; i < 64; i++) x[i] = SWAP(x[i]);                      \
            for (unsigned i = 0; i < 64; i++) f[i] = (T)(x[i] - a) <= w;                  \
            out[b * stride] = pack64(f) ^ inv;                                            \
        }                                                                                 \
    }

INT_KERNEL(blocks_i8, uint8_t, ident8)
INT_KERNEL(blocks_i16, uint16_t, __builtin_bswap16)
INT_KERNEL(blocks_i32, uint32_t, __builtin_bswap32)
INT_KERNEL(blocks_i64, uint64_t, __builtin_bswap64)

/* Floats: the samples are read as unsigned integers of the same width (so a
 * byteswap is an integer swap), then reinterpreted. */
#define FLOAT_KERNEL(NAME, F, U, SWAP, LO, HI)                                            \
    static void NAME(const void *src, size_t nb, const bvox__binpred *p, uint64_t *out,   \
                     size_t stride)                                                       \
    {                                                                                     \
        const unsigned char *s = src;                                                     \
        const F lo = (F)p->LO, hi = (F)p->HI;                                             \
        for (size_t b = 0; b < nb; b++, s += 64 * sizeof(F)) {                            \
            U u[64];                                                                      \
            F x[64];                                                                      \
            uint8_t f[64];                                                                \
            memcpy(u, s, sizeof u);                                                       \
            if (p->swap)                                                                  \
                for (unsigned i = 0; i < 64; i++) u[i] = SWAP(u[i]);                      \
            memcpy(x, u, sizeof x);                                                       \
            if (p->invert)                                                                \
                for (unsigned i = 0; i < 64; i++) f[i] = (x[i] < lo) | (x[i] > hi);       \
            else                                                                          \
                for (unsigned i = 0; i < 64; i++) f[i] = (x[i] >= lo) & (x[i] <= hi);     \
            out[b * stride] = pack64(f);                                                  \
        }                                                                                 \
    }

FLOAT_KERNEL(blocks_f32, float, uint32_t, __builtin_bswap32, fa32, fb32)
FLOAT_KERNEL(blocks_f64, double, uint64_t, __builtin_bswap64, fa, fb)

void bvox__bin_blocks_generic(const void *src, size_t nblocks, const bvox__binpred *p,
                              uint64_t *out, size_t stride)
{
    switch (p->kind) {
    case BVOX__BK_INT8: blocks_i8(src, nblocks, p, out, stride); break;
    case BVOX__BK_INT16: blocks_i16(src, nblocks, p, out, stride); break;
    case BVOX__BK_INT32: blocks_i32(src, nblocks, p, out, stride); break;
    case BVOX__BK_INT64: blocks_i64(src, nblocks, p, out, stride); break;
    case BVOX__BK_F32: blocks_f32(src, nblocks, p, out, stride); break;
    case BVOX__BK_F64: blocks_f64(src, nblocks, p, out, stride); break;
    }
}
