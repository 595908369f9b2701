/*
 * align_contours.c — aligning a section by its content when its markers are
 * lost: a rigid registration (iterative closest point) of the section's
 * traced contours onto those of its already aligned neighbour. Marker
 * alignment stays the first choice (markers are what the sectioning
 * protocol put there to be exact); this only replaces the old fallback,
 * which gave the section its neighbour's transform and so was wrong as
 * soon as sections moved independently.
 *
 * Both outlines are sampled every half pixel along their edges (traced
 * pixel-edge contours have vertices only at corners, which would weigh
 * staircases), at most MAX_SAMPLES points, each with the normal of its
 * edge. Start: the centroids of the two samples on each other, no turn.
 * Each round pairs every moved source point with its nearest target point
 * (a grid of cells over the target), drops pairs farther than 3 x the
 * median distance (parts of the outline that really differ between
 * neighbouring sections), and solves the linearised point-to-line problem
 * (Chen and Medioni): minimise the sum of ((q' - p) . n)^2 over a small turn
 * about the moved points' centroid and a shift. Point-to-point ICP would
 * crawl: samples of two outlines never sit at the same places along them,
 * and sliding along the outline costs it almost nothing. Stops when the
 * step moves points less than 1e-5 pixel.
 */
#include "section_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SAMPLES 4000
#define MAX_ROUNDS 200
#define CELL 2.0
#define NORMAL_SPAN 4.0 /* pixels of outline that give a sample's normal */
#define MAX_TURN 0.02  /* radians per round (about 1.1 degrees) */
#define MAX_ANGLE 0.52 /* 30 degrees: more between neighbours is not believed */

typedef struct cloud {
    bvox_point2 *p;
    bvox_point2 *normal; /* unit normal of the edge each sample lies on */
    int32_t n;
} cloud;

static double perimeter(const bvox_contour *c, int32_t nc)
{
    double len = 0;
    for (int32_t k = 0; k < nc; k++)
        for (int32_t i = 0; i < c[k].npoints; i++) {
            bvox_point2 a = c[k].points[i], b = c[k].points[(i + 1) % c[k].npoints];
            len += hypot(b.x - a.x, b.y - a.y);
        }
    return len;
}

static bvox_status sample(const bvox_contour *c, int32_t nc, cloud *out)
{
    double len = perimeter(c, nc), step = 0.5;
    if (len / step > MAX_SAMPLES) step = len / MAX_SAMPLES;
    size_t cap = (size_t)(len / step) + 2 * (size_t)nc + 8;
    out->p = bvox__mem_alloc(cap * sizeof *out->p);
    out->normal = bvox__mem_alloc(cap * sizeof *out->normal);
    out->n = 0;
    if (!out->p || !out->normal) return bvox__fail(BVOX_ENOMEM, "out of memory aligning by contours");
    for (int32_t k = 0; k < nc; k++) {
        int32_t first = out->n;
        double carry = 0; /* distance into the next edge where the next sample falls */
        for (int32_t i = 0; i < c[k].npoints; i++) {
            bvox_point2 a = c[k].points[i], b = c[k].points[(i + 1) % c[k].npoints];
            double e = hypot(b.x - a.x, b.y - a.y);
            for (double t = carry; t < e && (size_t)out->n < cap; t += step)
                out->p[out->n++] = (bvox_point2){a.x + (b.x - a.x) * t / e, a.y + (b.y - a.y) * t / e};
            carry = e > carry ? step - fmod(e - carry, step) : carry - e;
            if (carry >= step) carry = 0;
        }
        /* Normals of the outline, not of its pixel edges: a traced contour
         * is a staircase whose edges are all horizontal or vertical, and
         * lines along those would hold a turn back (the fit drifts). The
         * tangent is the chord over NORMAL_SPAN pixels around the sample. */
        int32_t m = out->n - first, w = (int32_t)(NORMAL_SPAN / (2 * step)) + 1;
        for (int32_t i = 0; i < m; i++) {
            bvox_point2 a = out->p[first + (i - w % m + m) % m], b = out->p[first + (i + w) % m];
            double tx = b.x - a.x, ty = b.y - a.y, chord = hypot(tx, ty);
            out->normal[first + i] =
                chord > 0 ? (bvox_point2){-ty / chord, tx / chord} : (bvox_point2){0, 0};
        }
    }
    return BVOX_OK;
}

/* Nearest-point queries over the target: points bucketed in CELL cells. */
typedef struct grid {
    double x0, y0, cell;
    int32_t nx, ny;
    int32_t *start, *idx;
    const cloud *c;
} grid;

static bvox_status grid_build(const cloud *c, grid *g)
{
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    for (int32_t i = 0; i < c->n; i++) {
        x0 = fmin(x0, c->p[i].x), x1 = fmax(x1, c->p[i].x);
        y0 = fmin(y0, c->p[i].y), y1 = fmax(y1, c->p[i].y);
    }
    g->c = c;
    g->x0 = x0, g->y0 = y0;
    /* cells of 2 px, fewer over a huge outline (at most 2048 per side) */
    g->cell = fmax(CELL, fmax(x1 - x0, y1 - y0) / 2048);
    if (!isfinite(g->cell)) return bvox__fail(BVOX_EINVAL, "an outline point is not finite");
    g->nx = (int32_t)((x1 - x0) / g->cell) + 1;
    g->ny = (int32_t)((y1 - y0) / g->cell) + 1;
    size_t cells = (size_t)g->nx * (size_t)g->ny;
    g->start = bvox__mem_zalloc(cells + 1, sizeof *g->start);
    g->idx = bvox__mem_alloc((size_t)c->n * sizeof *g->idx);
    if (!g->start || !g->idx) return bvox__fail(BVOX_ENOMEM, "out of memory aligning by contours");
    for (int32_t i = 0; i < c->n; i++) {
        int32_t cx = (int32_t)((c->p[i].x - x0) / g->cell), cy = (int32_t)((c->p[i].y - y0) / g->cell);
        g->start[(size_t)cy * g->nx + cx + 1]++;
    }
    for (size_t k = 0; k < cells; k++) g->start[k + 1] += g->start[k];
    int32_t *fill = bvox__mem_alloc(cells * sizeof *fill);
    if (!fill) return bvox__fail(BVOX_ENOMEM, "out of memory aligning by contours");
    memcpy(fill, g->start, cells * sizeof *fill);
    for (int32_t i = 0; i < c->n; i++) {
        int32_t cx = (int32_t)((c->p[i].x - x0) / g->cell), cy = (int32_t)((c->p[i].y - y0) / g->cell);
        g->idx[fill[(size_t)cy * g->nx + cx]++] = i;
    }
    free(fill);
    return BVOX_OK;
}

/* Index of the target point nearest to q: rings of cells around q's cell,
 * until the ring is farther than the best distance found. */
static int32_t nearest(const grid *g, bvox_point2 q, double *d2)
{
    double fx = floor((q.x - g->x0) / g->cell), fy = floor((q.y - g->y0) / g->cell);
    /* a point far outside the grid searches from the nearest border cell */
    int32_t cx = (int32_t)fmax(-1, fmin(g->nx, fx)), cy = (int32_t)fmax(-1, fmin(g->ny, fy));
    int32_t best = -1;
    double bd = HUGE_VAL;
    int32_t maxr = g->nx + g->ny + abs(cx) + abs(cy) + 2;
    for (int32_t r = 0; r <= maxr; r++) {
        double ring = (r - 1) * g->cell;
        if (best >= 0 && ring > 0 && ring * ring > bd) break;
        for (int32_t y = cy - r; y <= cy + r; y++) {
            if (y < 0 || y >= g->ny) continue;
            int32_t dx = (y == cy - r || y == cy + r) ? 1 : 2 * r;
            for (int32_t x = cx - r; x <= cx + r; x += dx ? dx : 1) {
                if (x < 0 || x >= g->nx) continue;
                size_t cell = (size_t)y * g->nx + x;
                for (int32_t k = g->start[cell]; k < g->start[cell + 1]; k++) {
                    bvox_point2 p = g->c->p[g->idx[k]];
                    double e = (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
                    if (e < bd) bd = e, best = g->idx[k];
                }
                if (r == 0) break;
            }
        }
    }
    *d2 = bd;
    return best;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static bvox_point2 mean(const cloud *c)
{
    double x = 0, y = 0;
    for (int32_t i = 0; i < c->n; i++) x += c->p[i].x, y += c->p[i].y;
    return (bvox_point2){x / c->n, y / c->n};
}

/* Solve the symmetric 3 x 3 system A x = b (Cramer); 0 when singular. */
static int solve3(const double A[9], const double b[3], double x[3])
{
    double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
                 A[2] * (A[3] * A[7] - A[4] * A[6]);
    if (!(fabs(det) > 1e-12)) return 0;
    for (int c = 0; c < 3; c++) {
        double M[9];
        memcpy(M, A, sizeof M);
        for (int r = 0; r < 3; r++) M[r * 3 + c] = b[r];
        x[c] = (M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                M[2] * (M[3] * M[7] - M[4] * M[6])) /
               det;
    }
    return 1;
}

bvox_status bvox__contours_register(const bvox_contour *src, int32_t ns, const bvox_contour *dst,
                                    int32_t nd, bvox_sim2 *step, double *rms)
{
    cloud a = {NULL, NULL, 0}, b = {NULL, NULL, 0};
    grid g;
    memset(&g, 0, sizeof g);
    int32_t *pair = NULL;
    double *dist = NULL, *sorted = NULL;
    bvox_status st = sample(src, ns, &a);
    if (!st) st = sample(dst, nd, &b);
    if (!st && (a.n < 8 || b.n < 8))
        st = bvox__fail(BVOX_ENOTFOUND, "too little outline to align by (%d and %d samples)",
                        (int)a.n, (int)b.n);
    if (!st) st = grid_build(&b, &g);
    if (!st) {
        pair = bvox__mem_alloc((size_t)a.n * sizeof *pair);
        dist = bvox__mem_alloc((size_t)a.n * sizeof *dist);
        sorted = bvox__mem_alloc((size_t)a.n * sizeof *sorted);
        if (!pair || !dist || !sorted)
            st = bvox__fail(BVOX_ENOMEM, "out of memory aligning by contours");
    }
    if (st) goto done;
    bvox_point2 ca = mean(&a), cb = mean(&b);
    bvox_sim2 t = {0, 1, cb.x - ca.x, cb.y - ca.y};
    double r = 0;
    for (int round = 0; round < MAX_ROUNDS; round++) {
        double gx = 0, gy = 0;
        for (int32_t i = 0; i < a.n; i++) {
            bvox_point2 q = bvox_sim2_apply(&t, a.p[i]);
            gx += q.x, gy += q.y;
            pair[i] = nearest(&g, q, &dist[i]);
        }
        gx /= a.n, gy /= a.n;
        memcpy(sorted, dist, (size_t)a.n * sizeof *sorted);
        qsort(sorted, (size_t)a.n, sizeof *sorted, cmp_double);
        double cut = fmax(9 * sorted[a.n / 2], 1.0); /* squared: 3 x the median, at least 1 px */
        double A[9] = {0}, rhs[3] = {0}, sum2 = 0, spread = 0;
        int32_t m = 0;
        for (int32_t i = 0; i < a.n; i++) {
            if (dist[i] > cut) continue;
            bvox_point2 q = bvox_sim2_apply(&t, a.p[i]), p = b.p[pair[i]], nv = b.normal[pair[i]];
            double r0 = (q.x - p.x) * nv.x + (q.y - p.y) * nv.y;
            double w[3] = {nv.y * (q.x - gx) - nv.x * (q.y - gy), nv.x, nv.y};
            for (int u = 0; u < 3; u++) {
                rhs[u] -= r0 * w[u];
                for (int v = 0; v < 3; v++) A[u * 3 + v] += w[u] * w[v];
            }
            sum2 += r0 * r0;
            spread += (q.x - gx) * (q.x - gx) + (q.y - gy) * (q.y - gy);
            m++;
        }
        r = m ? sqrt(sum2 / m) : 0;
        double x[3];
        /* A round outline says nothing about a turn (its normals point at
         * the centre): below 1 % of the stiffness of a straight-sided shape
         * only the shift is solved, the turn kept. */
        if (m >= 3 && A[0] < 0.01 * spread) {
            A[0] = 1, A[1] = A[2] = A[3] = A[6] = 0, rhs[0] = 0;
        }
        if (m < 3 || !solve3(A, rhs, x)) {
            st = bvox__fail(BVOX_ENOTFOUND, "the outlines do not pin a rigid alignment down");
            goto done;
        }
        /* the linearisation holds for small turns: a far-off pairing in the
         * first rounds must not spin the outline onto a symmetric twin (an
         * ellipse matches itself turned by 180 degrees) */
        if (fabs(x[0]) > MAX_TURN) {
            double f = MAX_TURN / fabs(x[0]);
            x[0] *= f, x[1] *= f, x[2] *= f;
        }
        /* the step: turn by x[0] about (gx, gy), then shift by (x[1], x[2]) */
        bvox_sim2 inc = {x[0], 1, 0, 0};
        bvox_point2 rg = bvox_sim2_apply(&inc, (bvox_point2){gx, gy});
        inc.tx = gx - rg.x + x[1];
        inc.ty = gy - rg.y + x[2];
        t = bvox_sim2_compose(&inc, &t);
        if (fabs(x[0]) * 1000 + hypot(x[1], x[2]) < 1e-5) break;
    }
    /* neighbouring sections turn by a few degrees; a registration that
     * wandered far is a shape that does not pin the turn down: not used */
    if (fabs(t.angle) > MAX_ANGLE) {
        st = bvox__fail(BVOX_ENOTFOUND, "the outlines give no reliable turn (%.0f degrees)",
                        t.angle * 180 / M_PI);
        goto done;
    }
    *step = t;
    if (rms) *rms = r;
done:
    free(a.p);
    free(a.normal);
    free(b.p);
    free(b.normal);
    free(g.start);
    free(g.idx);
    free(pair);
    free(dist);
    free(sorted);
    return st;
}
