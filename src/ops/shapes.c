/*
 * shapes.c — sphere, ellipsoid, box, cylinder, cone and torus drawn into a
 * volume with a set operation, in physical units (geometry in shapes_geom.c).
 *
 * Rasterisation is column by column: the line through the voxel centres of
 * column (x, y) meets a convex shape in one z interval, found analytically;
 * the interval becomes an index range with ceil/floor, its two end voxels are
 * checked (and moved) with the exact per-voxel-centre predicate so that the
 * result is exactly that predicate's despite rounding, and the range is
 * combined with the column's words as bit masks. A torus whose axis is not z
 * can meet a column twice: there the predicate is evaluated voxel by voxel,
 * but only within the column's candidate interval, and the bits are gathered
 * into whole words before they are combined. Only the shape's bounding box
 * is visited, except for INTERSECTION, which must clear everything else.
 */
#include "ops/shapes_geom.h"

#include <math.h>
#include <string.h>
#include <strings.h>

static const char *const kind_names[] = {"sphere", "ellipsoid", "box",
                                         "cylinder", "cone", "torus"};
#define NKINDS (int)(sizeof kind_names / sizeof kind_names[0])

const char *bvox_shape_kind_name(bvox_shape_kind kind)
{
    return (unsigned)kind < (unsigned)NKINDS ? kind_names[kind] : "unknown";
}

int bvox_shape_kind_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < NKINDS; i++)
        if (!strcasecmp(name, kind_names[i])) return i;
    return -1;
}

/* Volume of a spindle torus (tube radius rr > ring radius R), whose tube
 * overlaps itself around the axis: 4 pi * integral over u in [-R, rr] of
 * (u + R) sqrt(rr^2 - u^2) du. Equals 2 pi^2 R rr^2 when rr == R and the
 * sphere's 4/3 pi rr^3 when R == 0. */
static double spindle_torus_volume(double R, double rr)
{
    double root = sqrt(rr * rr - R * R);
    double first = rr * rr * rr * pow(1.0 - (R / rr) * (R / rr), 1.5) / 3.0;
    double second = M_PI * rr * rr / 4.0 + R * root / 2.0 + rr * rr / 2.0 * asin(R / rr);
    return 4.0 * M_PI * (first + R * second);
}

double bvox_shape_volume(const bvox_shape *shape)
{
    bvox__shape_geom g;
    if (bvox__shape_prepare(shape, &g) != BVOX_OK) return -1;
    switch (g.kind) {
    case BVOX_SHAPE_SPHERE: return 4.0 / 3.0 * M_PI * g.r * g.r * g.r;
    case BVOX_SHAPE_ELLIPSOID: return 4.0 / 3.0 * M_PI * g.a[0] * g.a[1] * g.a[2];
    case BVOX_SHAPE_BOX: return 8.0 * g.a[0] * g.a[1] * g.a[2];
    case BVOX_SHAPE_CYLINDER: return M_PI * g.r * g.r * (2.0 * g.h);
    case BVOX_SHAPE_CONE: return M_PI * g.r * g.r * g.h / 3.0;
    case BVOX_SHAPE_TORUS:
        if (g.rr <= g.r) return 2.0 * M_PI * M_PI * g.r * g.rr * g.rr;
        return spindle_torus_volume(g.r, g.rr);
    }
    return -1;
}

/* ---- combining a column's inside set with its words ---- */

/* Bits of word w that lie in [z0, z1). */
static uint64_t run_mask(size_t w, int64_t z0, int64_t z1)
{
    int64_t lo = z0 - (int64_t)w * 64, hi = z1 - (int64_t)w * 64;
    if (lo < 0) lo = 0;
    if (hi > 64) hi = 64;
    return lo < hi ? bvox__bit_range((unsigned)lo, (unsigned)hi) : 0;
}

static inline void combine(uint64_t *word, uint64_t bits, bvox_csg_op op)
{
    switch (op) {
    case BVOX_CSG_UNION:
    case BVOX_CSG_REPLACE: *word |= bits; break;
    case BVOX_CSG_DIFFERENCE: *word &= ~bits; break;
    case BVOX_CSG_XOR: *word ^= bits; break;
    case BVOX_CSG_INTERSECTION: *word &= bits; break;
    }
}

/* The column's inside set is [z0, z1) (empty when z0 >= z1, always within
 * 0..nz so tail bits are never touched). Only INTERSECTION visits words
 * outside the run. */
static void apply_run(uint64_t *col, size_t wpc, int64_t z0, int64_t z1, bvox_csg_op op)
{
    if (op == BVOX_CSG_INTERSECTION) {
        for (size_t w = 0; w < wpc; w++) col[w] &= run_mask(w, z0, z1);
        return;
    }
    if (z0 >= z1) return;
    for (size_t w = (size_t)(z0 >> 6); w <= (size_t)((z1 - 1) >> 6); w++)
        combine(&col[w], run_mask(w, z0, z1), op);
}

/* ---- one column ---- */

typedef struct draw_job {
    bvox_volume *vol;
    const bvox__shape_geom *g;
    bvox_csg_op op;
    int32_t x0, x1, y0, y1; /* columns that may meet the shape (half-open) */
    double o[3], s[3];      /* origin and spacing */
} draw_job;

/* Clamp a double to [lo, hi] before converting it (NaN goes to lo). */
static int64_t to_index(double v, int64_t lo, int64_t hi)
{
    if (!(v >= (double)lo)) return lo;
    if (v > (double)hi) return hi;
    return (int64_t)v;
}

static bool inside_at(const draw_job *j, double x, double y, int64_t k)
{
    return bvox__shape_inside(j->g, x, y, j->o[2] + (double)k * j->s[2]);
}

/* Exact run [*k0, *k1] (inclusive) of a convex shape on the column, from its
 * candidate interval [a, b] in index units: the end voxels are moved inwards
 * while the exact predicate rejects them and outwards while it accepts their
 * neighbours. Returns 0 if the column has no inside voxel. */
static int exact_run(const draw_job *j, double x, double y, double a, double b, int64_t *k0,
                     int64_t *k1)
{
    int64_t last = j->vol->nz - 1;
    int64_t lo = to_index(ceil(a), 0, last), hi = to_index(floor(b), 0, last);
    if (lo > hi) {
        /* no centre in the candidate: one of its neighbours may still touch
         * the surface (a tangent line, rounding of the interval ends) */
        int64_t below = hi, above = lo; /* adjacent voxels, below < above */
        bool in_below = inside_at(j, x, y, below), in_above = inside_at(j, x, y, above);
        if (!in_below && !in_above) return 0;
        lo = in_below ? below : above;
        hi = in_above ? above : below;
    } else {
        while (lo <= hi && !inside_at(j, x, y, lo)) lo++;
        while (hi >= lo && !inside_at(j, x, y, hi)) hi--;
        if (lo > hi) return 0;
    }
    while (lo > 0 && inside_at(j, x, y, lo - 1)) lo--;
    while (hi < last && inside_at(j, x, y, hi + 1)) hi++;
    *k0 = lo;
    *k1 = hi;
    return 1;
}

static void draw_column(const draw_job *j, int32_t xi, int32_t yi)
{
    bvox_volume *v = j->vol;
    uint64_t *col = bvox__column(v, xi, yi);
    double x = j->o[0] + (double)xi * j->s[0], y = j->o[1] + (double)yi * j->s[1];
    double zlo, zhi;
    if (!bvox__shape_column(j->g, x, y, &zlo, &zhi)) {
        if (j->op == BVOX_CSG_INTERSECTION) memset(col, 0, v->wpc * sizeof *col);
        return;
    }
    double a = (zlo - j->o[2]) / j->s[2], b = (zhi - j->o[2]) / j->s[2];
    if (bvox__shape_one_interval(j->g)) {
        int64_t k0 = 0, k1 = -1;
        if (!exact_run(j, x, y, a, b, &k0, &k1)) k1 = k0 - 1;
        apply_run(col, v->wpc, k0, k1 + 1, j->op);
        return;
    }
    /* a torus across the column: test each voxel of the candidate range
     * (widened by one voxel), gather the bits of a word, combine the word */
    int64_t last = v->nz - 1;
    int64_t k0 = to_index(floor(a) - 1, 0, last), k1 = to_index(ceil(b) + 1, 0, last);
    size_t w0 = (size_t)(k0 >> 6), w1 = (size_t)(k1 >> 6);
    for (size_t w = w0; w <= w1; w++) {
        int64_t first = (int64_t)w * 64 > k0 ? (int64_t)w * 64 : k0;
        int64_t end = (int64_t)w * 64 + 63 < k1 ? (int64_t)w * 64 + 63 : k1;
        uint64_t bits = 0;
        for (int64_t k = first; k <= end; k++)
            if (inside_at(j, x, y, k)) bits |= 1ull << (k & 63);
        combine(&col[w], bits, j->op);
    }
    if (j->op == BVOX_CSG_INTERSECTION) {
        memset(col, 0, w0 * sizeof *col);
        memset(col + w1 + 1, 0, (v->wpc - w1 - 1) * sizeof *col);
    }
}

/* Rows are independent: each thread takes a range of them. For INTERSECTION
 * the range covers every row, and columns outside the bounding box are
 * cleared whole (a row is nx*wpc contiguous words). */
static void draw_rows(void *ctx, int64_t begin, int64_t end)
{
    const draw_job *j = ctx;
    bvox_volume *v = j->vol;
    bool clear = j->op == BVOX_CSG_INTERSECTION;
    int32_t first_row = clear ? 0 : j->y0;
    for (int64_t r = begin; r < end; r++) {
        int32_t y = (int32_t)(first_row + r);
        uint64_t *row = bvox__column(v, 0, y);
        bool in_box = y >= j->y0 && y < j->y1 && j->x0 < j->x1;
        if (!in_box) {
            if (clear) memset(row, 0, (size_t)v->nx * v->wpc * sizeof *row);
            continue;
        }
        if (clear) {
            memset(row, 0, (size_t)j->x0 * v->wpc * sizeof *row);
            memset(bvox__column(v, j->x1, y), 0,
                   (size_t)(v->nx - j->x1) * v->wpc * sizeof *row);
        }
        for (int32_t x = j->x0; x < j->x1; x++) draw_column(j, x, y);
    }
}

bvox_status bvox_shape_draw(bvox_volume *vol, const bvox_shape *shape, bvox_csg_op op)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__clear_error();
    if (!vol) return bvox__fail(BVOX_EINVAL, "no volume to draw into");
    if ((unsigned)op > BVOX_CSG_REPLACE)
        return bvox__fail(BVOX_EINVAL, "unknown set operation %d", (int)op);
    bvox__shape_geom g;
    bvox_status st = bvox__shape_prepare(shape, &g);
    if (st) return st;
    draw_job j = {vol, &g, op, 0, 0, 0, 0, {0}, {0}};
    const int32_t n[3] = {vol->nx, vol->ny, vol->nz};
    int32_t lo[3], hi[3];
    for (int i = 0; i < 3; i++) {
        j.o[i] = vol->geom.origin[i];
        j.s[i] = vol->geom.spacing[i];
        /* voxel range of the bounding box, one voxel wider on each side for
         * rounding: the exact test decides anyway */
        lo[i] = (int32_t)to_index(floor((g.lo[i] - j.o[i]) / j.s[i]) - 1, 0, n[i]);
        hi[i] = (int32_t)to_index(ceil((g.hi[i] - j.o[i]) / j.s[i]) + 2, 0, n[i]);
    }
    bool empty = lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2];
    if (!empty) {
        j.x0 = lo[0];
        j.x1 = hi[0];
        j.y0 = lo[1];
        j.y1 = hi[1];
    }
    int64_t rows = op == BVOX_CSG_INTERSECTION ? vol->ny : (int64_t)j.y1 - j.y0;
    bvox__parallel_for(rows, 8, draw_rows, &j);
    BVOX_CHECK_VOLUME(vol);
    return BVOX_OK;
}
