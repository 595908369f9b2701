/*
 * measref.h — slow per-voxel references for the measures (test_measure*.c):
 * neighbour-by-neighbour transition counts, moments summed voxel by voxel,
 * the Euler number as V - E + F - C of the closed-cube complex enumerated
 * cell by cell, and breadth-first flood fills for components and cavities.
 * Shares no code with src/.
 */
#ifndef BVOX_MEASREF_H
#define BVOX_MEASREF_H

#include "voxref.h"

#include <stdint.h>

/* Direction classes of trans[], in the order of src/measure.h:
 * x, y, z, (1,+-1,0), (1,0,+-1), (0,1,+-1), (1,+-1,+-1). */
#define MEASREF_NCLASS 7

typedef struct measref {
    int64_t count, faces[3], trans[MEASREF_NCLASS], euler, components, cavities;
    int64_t cavities_26; /* 26-connected background components not reaching the border */
    double centroid[3], cov[9]; /* physical, origin 0 */
} measref;

/* All of the above for r with voxel spacing sp (outside the volume is 0;
 * components 26-connected, cavities 6-connected background not reaching the
 * border). */
void measref_compute(const voxref *r, const double sp[3], measref *out);

#endif
