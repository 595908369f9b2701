/*
 * demo.h — the serial sections `bvox demo` cuts from the built-in specimen
 * (src/ops/demo.c): what a microscope would give of a physically sectioned
 * embryo, for bvox_reconstruct_images to rebuild the model from.
 *
 * Frames: a section image is the "block" (the specimen's x, y plane with a
 * margin of DEMO_MARGIN pixels of DEMO_SXY um around the 256 x 256 voxels:
 * block pixel u is specimen voxel u - DEMO_MARGIN) moved by the section's
 * random rigid transform; the middle section is not moved, so a model
 * aligned to it lies in the block frame.
 */
#ifndef BVOX_DEMO_DEMO_H
#define BVOX_DEMO_DEMO_H

#include "ops/demo.h"

#define DEMO_MARGIN 48                          /* pixels around the specimen */
#define DEMO_SIZE (DEMO_NX + 2 * DEMO_MARGIN)   /* section images are square */

typedef struct bvox__demo_cut {
    int32_t n;          /* sections */
    double z0, dz;      /* section k cuts the specimen at z = z0 + k dz (um) */
    uint64_t seed;      /* of the moves, the noise */
    bvox_sim2 *moves;   /* n: block pixels -> image pixels (n entries, owned) */
} bvox__demo_cut;

/* Choose the n sections' moves (up to +-6 degrees about the image centre
 * and +-12 pixels; none for section n / 2). */
bvox_status bvox__demo_cut_init(bvox__demo_cut *c, int32_t n, double z0, double dz, uint64_t seed);
void bvox__demo_cut_free(bvox__demo_cut *c);

/* Section k as an 8-bit gray image of DEMO_SIZE x DEMO_SIZE pixels: the
 * specimen's cut (textured, transmittance about 0.5) and three round dark
 * markers (embedding holes, the same block positions in every section) under
 * an uneven light (a gradient and a vignette fixed to the image, not the
 * block), with noise. */
bvox_status bvox__demo_section(const bvox__demo_cut *c, int32_t k, bvox_image **out);

#endif
