/* morph_ball.h — the ball dilation/erosion kernel (morph_ball.c), called by
 * morph.c's bvox_morph_dilate_ball / bvox_morph_erode_ball. */
#ifndef BVOX_MORPH_BALL_H
#define BVOX_MORPH_BALL_H

#include "internal.h"

/* Dilate (erode) in by the ball of the given radius in world units (voxel
 * spacing from in's geometry): offsets (dx, dy, dz) with
 * (dx sx)^2 + (dy sy)^2 + (dz sz)^2 <= radius^2. Voxels outside the volume
 * are 0. *out is a new volume with in's geometry. radius must be finite and
 * >= 0; the caller checks the xy extent. */
bvox_status bvox__morph_ball(const bvox_volume *in, double radius, bool erode, bvox_volume **out);

/* The inner loops (morph_ball_kern.h), one set per SIMD level. */
#define BVOX__BALL_DECL(lv)                                                                  \
    void bvox__ball_gather_##lv(uint64_t *run, bool first, uint64_t *o1, uint64_t *o2,       \
                                const uint64_t *const *p, int np, size_t n, bool erode);      \
    void bvox__ball_step_##lv(uint64_t *dst, const uint64_t *src, size_t ncols, size_t wpc,   \
                              int s, uint64_t tail, bool erode);
BVOX__BALL_DECL(generic)
BVOX__BALL_DECL(avx2)
BVOX__BALL_DECL(avx512)

/* Tests only: when > 0, tiles are this many columns wide and small volumes
 * are split over threads as large ones are (so that tests reach the tile
 * and band edges on small volumes). Set from one thread between calls. */
extern int bvox__morph_ball_test_tile;

#endif
