/*
 * bvox/parts.h — measures of a volume seen one part (chunk) at a time, for
 * callers that split a volume themselves (bvox.dask: one Dask chunk per
 * call). Included by bvox.h; do not include it alone.
 *
 * The measure scan's sums (count, moments, Euler number of the cube complex,
 * 0/1 transitions of the 13 directions of the 2x2x2 neighbourhood) are sums
 * over voxels and 2x2x2 windows. A part handed in with a one-voxel overlap on
 * each high side that has a neighbour gives, by inclusion-exclusion over the
 * overlap planes, exactly what lies on its side of the border, so the parts'
 * sums add up to the whole volume's.
 */
#ifndef BVOX_PARTS_H
#define BVOX_PARTS_H

/* A signed 128-bit integer: hi * 2^64 + lo (second-order moments of large
 * volumes need more than 64 bits). */
typedef struct bvox_int128 {
    int64_t hi;
    uint64_t lo;
} bvox_int128;

/* The exact integer sums of the measure scan, in voxel indices of the whole
 * volume. bbox: x0 y0 z0 x1 y1 z1, half-open, meaningless when count == 0. */
typedef struct bvox_measure_sums {
    int64_t count;
    bvox_int128 s[3];  /* sums of x, y, z */
    bvox_int128 ss[6]; /* sums of xx, yy, zz, xy, xz, yz */
    int32_t bbox[6];
    int64_t euler;
    int64_t trans[7];  /* transitions per direction class: x y z xy xz yz xyz */
} bvox_measure_sums;

/* The sums of one part. part: the part's voxels, with one more voxel along
 * each axis a where core[a] < its size (the first plane of the neighbour on
 * the high side; core[a] must then be size - 1, else core[a] == size).
 * offset: where the part's voxel (0, 0, 0) lies in the whole volume; the
 * moments and bbox are given in the whole volume's indices. The sums of the
 * parts of a partition add up to the whole volume's (as signed 128-bit
 * integers; bbox by union). Returns BVOX_EINVAL for a bad core, BVOX_ENOMEM.
 * Thread-safe for different outputs. */
BVOX_API bvox_status bvox_measure_part(const bvox_volume *part, const int32_t core[3],
                                       const int32_t offset[3], bvox_measure_sums *out);

/* The physical measures (bvox_measure's fields but the topology: components,
 * cavities, cavities_26 and tunnels stay 0) of the whole volume's summed
 * sums, with its geometry (spacing, origin, direction). */
BVOX_API bvox_status bvox_measure_from_sums(const bvox_measure_sums *sums,
                                            const bvox_geometry *geom, bvox_measures *out);

#endif
