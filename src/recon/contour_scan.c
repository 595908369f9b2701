/*
 * contour_scan.c — even-odd scan conversion of a section's contours into a
 * bitmap (one bit per pixel, 64 pixels per word along x).
 *
 * Pixel (i, j) is inside when its centre (i + 0.5, j + 0.5) is inside the
 * union-by-parity of all contours (holes are just more contours). Rule at the
 * boundaries (half-open, so that two polygons sharing an edge never both own
 * a centre on it and the rule is exact for vertices on scanlines):
 *   - an edge p -> q crosses row j when min(py, qy) <= cy < max(py, qy);
 *     horizontal edges never cross;
 *   - the crossing toggles every centre strictly to its right (cx > x).
 * Each crossing is located with floating point and then confirmed with the
 * orientation predicate (cx - px) * dy - (cy - py) * dx, which is exact when
 * the coordinates have few significant bits (integers, halves, quarters: what
 * tests use); for general doubles it is as good as double rounding allows.
 *
 * Edge-major: every edge walks only the rows it spans and flips one "toggle"
 * bit per row; then each row is turned into fill by a prefix XOR over its
 * words (six shift-XORs per word plus the carried parity). No sorting.
 */
#include "contour_internal.h"

#include <math.h>
#include <string.h>

/* (cx, cy) strictly right of the edge p -> q on that row (dy != 0). */
static inline bool right_of(double cx, double cy, bvox_point2 p, bvox_point2 q)
{
    double dx = q.x - p.x, dy = q.y - p.y;
    double d = (cx - p.x) * dy - (cy - p.y) * dx;
    return dy > 0 ? d > 0 : d < 0;
}

static void scan_edge(bvox_point2 p, bvox_point2 q, int32_t x0, int32_t y0, int32_t nx,
                      int32_t ny, size_t wpr, uint64_t *bits)
{
    if (p.y == q.y) return;
    double ymin = p.y < q.y ? p.y : q.y, ymax = p.y < q.y ? q.y : p.y;
    /* rows j (window) with ymin <= y0 + j + 0.5 < ymax */
    double fl = ceil(ymin - y0 - 0.5), fh = ceil(ymax - y0 - 0.5);
    if (fl < -1) fl = -1;
    if (fh > ny + 1) fh = ny + 1;
    if (fl > ny + 1 || fh < -1) return;
    int64_t jlo = (int64_t)fl, jhi = (int64_t)fh;
    while ((double)(y0 + jlo - 1) + 0.5 >= ymin && jlo > -1) jlo--;
    while ((double)(y0 + jlo) + 0.5 < ymin) jlo++;
    while ((double)(y0 + jhi - 1) + 0.5 >= ymax && jhi > -1) jhi--;
    while ((double)(y0 + jhi) + 0.5 < ymax) jhi++;
    if (jlo < 0) jlo = 0;
    if (jhi > ny) jhi = ny;
    double slope = (q.x - p.x) / (q.y - p.y);
    for (int64_t j = jlo; j < jhi; j++) {
        double cy = (double)(y0 + j) + 0.5;
        double xc = p.x + (cy - p.y) * slope;
        /* first window column whose centre is right of xc */
        double fi = floor(xc - x0 - 0.5) + 1;
        if (fi < 0) fi = 0;
        if (fi > nx) fi = nx;
        int64_t i = (int64_t)fi;
        while (i > 0 && right_of((double)(x0 + i - 1) + 0.5, cy, p, q)) i--;
        while (i < nx && !right_of((double)(x0 + i) + 0.5, cy, p, q)) i++;
        if (i >= nx) continue;
        bits[(size_t)j * wpr + ((size_t)i >> 6)] ^= 1ull << (i & 63);
    }
}

void bvox__scan_section(const bvox_section *sec, int32_t x0, int32_t y0, int32_t nx, int32_t ny,
                        size_t wpr, uint64_t *bits)
{
    memset(bits, 0, (size_t)ny * wpr * sizeof *bits);
    for (int32_t c = 0; c < sec->ncontours; c++) {
        const bvox_contour *ct = &sec->contours[c];
        for (int32_t k = 0; k < ct->npoints; k++) {
            bvox_point2 p = ct->points[k], q = ct->points[k + 1 < ct->npoints ? k + 1 : 0];
            scan_edge(p, q, x0, y0, nx, ny, wpr, bits);
        }
    }
    /* toggles -> fill: prefix XOR along each row */
    size_t full = (size_t)nx / 64, rem = (size_t)nx % 64;
    uint64_t last_mask = rem ? (1ull << rem) - 1 : ~0ull;
    for (int32_t j = 0; j < ny; j++) {
        uint64_t *row = bits + (size_t)j * wpr;
        uint64_t carry = 0;
        for (size_t w = 0; w < wpr; w++) {
            uint64_t x = row[w];
            x ^= x << 1;
            x ^= x << 2;
            x ^= x << 4;
            x ^= x << 8;
            x ^= x << 16;
            x ^= x << 32;
            x ^= carry;
            carry = (uint64_t)0 - (x >> 63);
            row[w] = x;
        }
        if (rem && full < wpr) row[full] &= last_mask;
        for (size_t w = full + (rem ? 1 : 0); w < wpr; w++) row[w] = 0;
    }
}
