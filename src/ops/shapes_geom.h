/*
 * shapes_geom.h — private interface between shapes.c (the public calls, the
 * rasteriser and the word operations) and shapes_geom.c (the geometry of each
 * primitive: validation, the exact inside predicate, the bounding box and the
 * analytic intersection of a line parallel to z with the shape).
 *
 * Everything here is in physical units of the volume's frame: the centre of
 * voxel (i, j, k) is origin + (i*sx, j*sy, k*sz), the direction matrix is
 * ignored (as bvox.h documents for shapes).
 */
#ifndef BVOX_SHAPES_GEOM_H
#define BVOX_SHAPES_GEOM_H

#include "internal.h"

/* A validated shape with the derived quantities the hot paths need. */
typedef struct bvox__shape_geom {
    bvox_shape_kind kind;
    double c[3];          /* centre (cone: centre of the base) */
    double a[3];          /* semi-axes (ellipsoid, box) */
    double u[3];          /* unit axis (cylinder, cone, torus) */
    double r;             /* radius (sphere, cylinder, cone base, torus ring) */
    double rr;            /* tube radius (torus) */
    double h;             /* cylinder: half height; cone: height */
    double lo[3], hi[3];  /* physical axis-aligned bounding box */
    double eps;           /* how far candidate intervals are widened (physical) */
} bvox__shape_geom;

/* Validate and prepare. BVOX_EINVAL with a message on a bad shape: unknown
 * kind, non-finite or negative sizes, a zero ellipsoid semi-axis or cone
 * height, values so large that their squares overflow. A zero axis is +z. */
bvox_status bvox__shape_prepare(const bvox_shape *shape, bvox__shape_geom *g);

/* The exact per-voxel-centre test (boundary included): the definition the
 * rasteriser must reproduce. */
bool bvox__shape_inside(const bvox__shape_geom *g, double x, double y, double z);

/* The line (x, y, z) for all z: a candidate z interval [*zlo, *zhi]
 * (physical, may be +-inf). Returns 0 when the line certainly misses the
 * shape. For convex shapes the candidate is the analytic intersection widened
 * by g->eps, so that the caller needs only to verify the end voxels with
 * bvox__shape_inside; for the torus it is a superset (bounding sphere and
 * slab) inside which the caller tests voxel by voxel. */
int bvox__shape_column(const bvox__shape_geom *g, double x, double y, double *zlo,
                       double *zhi);

/* Whether every column meets the shape in one interval (convex shapes, and a
 * torus whose axis is z); otherwise the caller tests voxel by voxel within
 * the candidate interval. */
static inline bool bvox__shape_one_interval(const bvox__shape_geom *g)
{
    return g->kind != BVOX_SHAPE_TORUS || (g->u[0] == 0 && g->u[1] == 0);
}

#endif
