/*
 * surface_row.h — the row kernels of the surface build (surface.c, the
 * portable ones; surface_row_avx2.c), chosen at run time by the SIMD level.
 */
#ifndef BVOX_SURFACE_ROW_H
#define BVOX_SURFACE_ROW_H

#include <stddef.h>
#include <stdint.h>

/* b[i] = the boundary bits of word i of row cur for wpc <= i < n - wpc,
 * with prev and next the rows y - 1 and y + 1, the x neighbours wpc words
 * away and the z neighbours one word away (carries across the ends of
 * columns included: the caller redoes those words). */
typedef void (*bvox__surface_flat_fn)(const uint64_t *prev, const uint64_t *cur,
                                      const uint64_t *next, size_t n, size_t wpc, uint64_t *b);
/* Bit j of m[k]: b[64 k + j] != 0, for the n words of b. */
typedef void (*bvox__surface_nonzero_fn)(const uint64_t *b, size_t n, uint64_t *m);

/* The AVX2 kernels, NULL where the build has none; the caller checks the
 * CPU. */
extern const bvox__surface_flat_fn bvox__surface_flat_avx2;
extern const bvox__surface_nonzero_fn bvox__surface_nonzero_avx2;

/* The boundary bits of word c, given the x and y neighbours' words and the
 * words below and above along z. */
static inline uint64_t bvox__boundary_word(uint64_t c, uint64_t xm, uint64_t xp, uint64_t ym,
                                           uint64_t yp, uint64_t below, uint64_t above)
{
    uint64_t zm = c << 1 | below >> 63, zp = c >> 1 | above << 63;
    return c & ~(xm & xp & ym & yp & zm & zp);
}

#endif
