/*
 * contourref.h — slow references for the contour code: even-odd point in
 * polygon per pixel centre in exact integer arithmetic (coordinates given in
 * quarter pixels), and a brute-force signed distance map. Share no code with
 * src/recon/.
 */
#ifndef BVOX_CONTOURREF_H
#define BVOX_CONTOURREF_H

#include <stdint.h>

/* A polygon with integer vertices in quarter pixels (x4 = 4 * x). */
typedef struct contourref_poly {
    const int64_t *x4, *y4;
    int n;
} contourref_poly;

/* 1 if the centre of pixel (i, j) is inside the even-odd union of the
 * polygons: a crossing of an edge with min y <= cy < max y counts when the
 * centre is strictly right of it. */
int contourref_inside(const contourref_poly *polys, int npolys, int64_t i, int64_t j);

/* Signed distance of pixel (x, y) of a bitmap (in[y * nx + x] 0/1) by
 * brute force: -(distance to the nearest 0) on 1 pixels, +(distance to the
 * nearest 1) on 0 pixels; cap when there is no such pixel. */
double contourref_signed_distance(const uint8_t *in, int nx, int ny, int x, int y, double cap);

#endif
