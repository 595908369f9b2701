/*
 * section_trace.c — closed contours of a bitmap by crack following: every
 * boundary is walked along pixel edges with the object on the left (x
 * right, y down), so outer contours have negative shoelace area and hole
 * contours positive; the output reverses them (outer positive, holes
 * negative, as bvox_polygon_signed_area and bvox_volume_to_contours have it). At a vertex the walk turns right if the pixel ahead
 * right is object (so diagonal neighbours belong to one 8-connected
 * object), goes straight if the pixel ahead left is, else turns left. Starts
 * are the unvisited horizontal cracks, found a word at a time as the XOR of
 * two rows. Nesting: the parent of a contour is the smallest contour that
 * contains one pixel next to it on its inner side, found by a ray from that
 * pixel's centre to the left through a map of which contour owns each
 * vertical edge (odd crossings: enclosing; a pixel centre never lies on a
 * contour, so the test is exact). O(perimeter + contours x width).
 */
#include "section_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const int DX[4] = {1, 0, -1, 0}; /* E, S, W, N (turning right: +1) */
static const int DY[4] = {0, 1, 0, -1};

typedef struct poly {
    int32_t *xy; /* corner vertices x0, y0, x1, y1, ... */
    int32_t n, cap;
    double area; /* shoelace, signed */
    int32_t px, py; /* a pixel inside the polygon next to its boundary */
} poly;

static int fg(const bvox_bitmap *bm, int32_t x, int32_t y)
{
    return bvox_bitmap_get(bm, x, y);
}

/* Pixel whose centre is v + (ox, oy) / 2 for ox, oy in {-1, 1}. */
static inline int32_t pix(int32_t v, int o)
{
    return o > 0 ? v : v - 1;
}

static int push(poly *p, int32_t x, int32_t y)
{
    if (p->n == p->cap) {
        int32_t cap = p->cap ? p->cap * 2 : 16;
        int32_t *nxy = bvox__mem_resize(p->xy, (size_t)cap * 2 * sizeof *nxy);
        if (!nxy) return -1;
        p->xy = nxy;
        p->cap = cap;
    }
    p->xy[2 * p->n] = x;
    p->xy[2 * p->n + 1] = y;
    p->n++;
    return 0;
}

/* Walk from vertex (sx, sy) in direction sd; visited marks horizontal edges. */
static int trace_one(const bvox_bitmap *bm, uint64_t *visited, int32_t vwpr, int32_t *owner,
                     int32_t id, int32_t sx, int32_t sy, int sd, poly *p)
{
    int32_t x = sx, y = sy;
    int d = sd;
    memset(p, 0, sizeof *p);
    /* the pixel inside: left of the first edge for an outer contour, right for a hole;
     * decided after the area is known, so remember both */
    int32_t lx = pix(x, DX[d] + DY[d]), ly = pix(y, DY[d] - DX[d]);
    int32_t rx = pix(x, DX[d] - DY[d]), ry = pix(y, DY[d] + DX[d]);
    int64_t area2 = 0;
    for (;;) {
        if (DY[d] == 0) { /* horizontal edge: mark it */
            int32_t ex = d == 0 ? x : x - 1;
            visited[(size_t)y * (size_t)vwpr + (size_t)(ex >> 6)] |= 1ull << (ex & 63);
        } else { /* vertical edge on line x, row min(y, y + dy): its contour */
            int32_t ey = d == 1 ? y : y - 1;
            owner[(size_t)ey * (size_t)(bm->width + 1) + (size_t)x] = id;
        }
        int32_t nx = x + DX[d], ny = y + DY[d];
        area2 += (int64_t)x * ny - (int64_t)nx * y;
        x = nx;
        y = ny;
        /* left vector (DY, -DX); ahead-left d + l, ahead-right d - l */
        int lxv = DY[d], lyv = -DX[d];
        int ar = fg(bm, pix(x, DX[d] - lxv), pix(y, DY[d] - lyv));
        int al = fg(bm, pix(x, DX[d] + lxv), pix(y, DY[d] + lyv));
        int nd = ar ? (d + 1) & 3 : al ? d : (d + 3) & 3;
        if (nd != d && push(p, x, y)) return -1;
        d = nd;
        if (x == sx && y == sy && d == sd) break;
    }
    p->area = (double)area2 / 2;
    if (p->area < 0) {
        p->px = lx;
        p->py = ly;
    } else {
        p->px = rx;
        p->py = ry;
    }
    return 0;
}

void bvox_contours_free(bvox_contour *contours, int32_t count)
{
    if (!contours) return;
    for (int32_t i = 0; i < count; i++) free(contours[i].points);
    free(contours);
}

bvox_status bvox_bitmap_trace(const bvox_bitmap *bm, bvox_contour **contours, int32_t *count)
{
    *contours = NULL;
    *count = 0;
    int32_t w = bm->width, h = bm->height, nw = bm->words_per_row;
    uint64_t *visited = bvox__mem_zalloc((size_t)(h + 1) * (size_t)nw, sizeof *visited);
    int32_t *owner = bvox__mem_alloc((size_t)h * ((size_t)w + 1) * sizeof *owner);
    poly *polys = NULL;
    int32_t np = 0, cap = 0;
    bvox_status st = BVOX_OK;
    if (!visited || !owner) {
        free(visited);
        free(owner);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    memset(owner, 0xff, (size_t)h * ((size_t)w + 1) * sizeof *owner); /* -1: no contour */
    for (int32_t y = 0; y <= h && !st; y++) {
        const uint64_t *top = y > 0 ? bvox__bm_row_c(bm, y - 1) : NULL;
        const uint64_t *bot = y < h ? bvox__bm_row_c(bm, y) : NULL;
        for (int32_t k = 0; k < nw && !st; k++) {
            uint64_t t = top ? top[k] : 0, b = bot ? bot[k] : 0;
            uint64_t cracks = (t ^ b) & ~visited[(size_t)y * (size_t)nw + (size_t)k];
            while (cracks) {
                int bit = __builtin_ctzll(cracks);
                cracks &= cracks - 1;
                int32_t x = k * 64 + bit;
                if ((visited[(size_t)y * (size_t)nw + (size_t)k] >> bit) & 1) continue;
                if (np == cap) {
                    int32_t ncap = cap ? cap * 2 : 16;
                    poly *n2 = bvox__mem_resize(polys, (size_t)ncap * sizeof *polys);
                    if (!n2) {
                        st = bvox__fail(BVOX_ENOMEM, "out of memory");
                        break;
                    }
                    polys = n2;
                    cap = ncap;
                }
                /* object below: walk west from (x+1, y); object above: east from (x, y) */
                int below = (int)((b >> bit) & 1);
                if (trace_one(bm, visited, nw, owner, np, below ? x + 1 : x, y, below ? 2 : 0,
                              &polys[np])) {
                    free(polys[np].xy);
                    st = bvox__fail(BVOX_ENOMEM, "out of memory");
                    break;
                }
                np++;
            }
        }
    }
    free(visited);
    bvox_contour *out = NULL;
    uint8_t *parity = NULL;
    int32_t *touched = NULL;
    if (!st && np > 0) {
        out = bvox__mem_zalloc((size_t)np, sizeof *out);
        parity = bvox__mem_zalloc((size_t)np, 1);
        touched = bvox__mem_alloc(((size_t)w + 1) * sizeof *touched);
        if (!out || !parity || !touched) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    for (int32_t i = 0; i < np && !st; i++) {
        out[i].points = bvox__mem_alloc((size_t)polys[i].n * sizeof *out[i].points);
        if (!out[i].points) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            break;
        }
        /* reversed: outer contours positive (bvox_polygon_signed_area), holes negative */
        for (int32_t j = 0, m = polys[i].n; j < m; j++)
            out[i].points[j] = (bvox_point2){polys[i].xy[2 * (m - 1 - j)], polys[i].xy[2 * (m - 1 - j) + 1]};
        out[i].npoints = polys[i].n;
        out[i].hole = polys[i].area > 0;
        /* parent: the smallest contour (by |area|) containing the inner
         * pixel: a ray from its centre to the left crosses the vertical
         * edges of each enclosing contour an odd number of times */
        int32_t parent = -1, nt = 0, px = polys[i].px, py = polys[i].py;
        const int32_t *row = owner + (size_t)py * ((size_t)w + 1);
        for (int32_t x = px; x >= 0; x--) {
            int32_t id = row[x];
            if (id < 0 || id == i) continue;
            if (!parity[id]) touched[nt++] = id;
            parity[id] ^= 1;
        }
        double best = INFINITY;
        for (int32_t t = 0; t < nt; t++) {
            int32_t id = touched[t];
            if (parity[id] && fabs(polys[id].area) < best) {
                best = fabs(polys[id].area);
                parent = id;
            }
            parity[id] = 0;
        }
        out[i].parent = parent;
    }
    for (int32_t i = 0; i < np; i++) free(polys[i].xy);
    free(polys);
    free(owner);
    free(parity);
    free(touched);
    if (st) {
        bvox_contours_free(out, np);
        return st;
    }
    *contours = out;
    *count = np;
    return BVOX_OK;
}
