/*
 * demo.h — the built-in specimen's shapes for the demo's other parts
 * (src/demo/: the simulated serial sections are cut from the same shapes,
 * not from the voxel model, so each section is a true plane through them).
 */
#ifndef BVOX_OPS_DEMO_H
#define BVOX_OPS_DEMO_H

#include "internal.h"

/* The specimen's grid: 256 x 256 x 128 voxels of 10 x 10 x 25 um. */
#define DEMO_NX 256
#define DEMO_NY 256
#define DEMO_NZ 128
#define DEMO_SXY 10.0 /* um */
#define DEMO_SZ 25.0  /* um: thick sections */

/* Add the specimen's shapes to v (union, hole bored), at their fixed
 * physical place in the frame of the built-in grid (um, origin at voxel
 * (0, 0, 0)): v's geometry says where its voxels are in that frame, so a
 * one-slice volume with origin z = Z gets the section at height Z. */
bvox_status bvox__demo_draw(bvox_volume *v);

#endif
