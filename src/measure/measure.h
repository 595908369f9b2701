/*
 * measure.h — private interfaces between the measure_*.c files.
 *
 *   measure_scan.c     one word-parallel pass over the volume: counts, sums
 *                      of coordinates (moments), bounding box, the cells of
 *                      the voxel complex (Euler number) and the 0/1
 *                      transitions along the 13 directions of the 2x2x2
 *                      neighbourhood (exposed faces, Crofton area);
 *   measure_crofton.c  the Crofton direction weights for a voxel spacing;
 *   measure.c          bvox_measure: the scan turned into physical measures,
 *                      plus the topology that needs labelling;
 *   measure_components.c  bvox_measure_components;
 *   measure_cavities.c  the cavities (6- and 26-connected) of bvox_measure:
 *                      measure_hull_runs.c, from the enclosed background's
 *                      runs; measure_enclosed.c, from its words labelled;
 *                      measure_cavities_sparse.c, the 26-cavities from runs;
 *   measure_flood.c    the background reached from the border, by sweeps
 *                      (measure_flood_avx512.c, _avx2.c: a row of them, a
 *                      column one or two vectors).
 */
#ifndef BVOX_MEASURE_H
#define BVOX_MEASURE_H

#include "internal.h"

/* Wide accumulators for the second-order sums: sum(x^2) over 2^37 voxels at
 * coordinates up to 65535 needs 69 bits. */
#ifdef __SIZEOF_INT128__
typedef __int128 bvox__wide;
#else
typedef long double bvox__wide;
#endif

/* The 13 directions of the 2x2x2 neighbourhood fall into 7 classes whose
 * members have the same length and the same Crofton weight for any
 * axis-aligned spacing (they are mirror images of each other). */
enum {
    BVOX__DIR_X = 0,   /* (1,0,0) */
    BVOX__DIR_Y = 1,   /* (0,1,0) */
    BVOX__DIR_Z = 2,   /* (0,0,1) */
    BVOX__DIR_XY = 3,  /* (1,+-1,0): 2 directions */
    BVOX__DIR_XZ = 4,  /* (1,0,+-1): 2 */
    BVOX__DIR_YZ = 5,  /* (0,1,+-1): 2 */
    BVOX__DIR_XYZ = 6, /* (1,+-1,+-1): 4 */
    BVOX__NDIR = 7
};

/* What one pass over the words gives (all exact integers). Voxel indices,
 * not physical units. */
typedef struct bvox__scan {
    int64_t count;
    bvox__wide s[3];  /* sum of x, y, z over the 1-voxels */
    bvox__wide ss[6]; /* sum of xx, yy, zz, xy, xz, yz */
    int32_t bbox[6];  /* x0 y0 z0 x1 y1 z1, half-open; meaningless if count == 0 */
    int64_t euler;    /* V - E + F - C of the union of closed voxel cubes (in a block
                       * of the scan: V - E only, measure_scan.c) */
    /* Pairs of voxels (p, p + d) with different values, summed over the
     * directions of each class; voxels outside the volume are 0. The three
     * axis classes are the exposed faces. */
    int64_t trans[BVOX__NDIR];
    /* The current row's sums (over its columns x: n, x n, x^2 n, sz, szz,
     * x sz), added into count, s and ss once a row (bvox__moments_row): a
     * 128-bit multiply-add per sum and column cost a sixth of the scan. All
     * are below 2^64, the dimensions being below 2^16. */
    uint64_t row[6];
    /* When not NULL, the current row's column hulls (bvox__measure_scan_hulls). */
    struct bvox__colhull *hull_row;
    bool boxed; /* bbox holds a voxel (count may lag: rows are added at their end) */
} bvox__scan;

/* Per column of a volume: the z range [lo, hi) strictly between its first
 * and last object voxel, which holds its enclosed background, and that
 * background's runs (the object's runs less one); all 0 in a column without
 * object. twin_row, the same in every column of a row: the row's words equal
 * those of the row before (an upsampled volume's rows repeat: 58 % of the
 * AAL atlas's inner rows at 512^3); the scan reuses that row's moments, the
 * cavities its runs. */
typedef struct bvox__colhull {
    int32_t lo, hi;
    uint32_t runs : 31;
    uint32_t twin_row : 1;
} bvox__colhull;

/* One pass, split over the worker threads; the result does not depend on
 * the thread count. BVOX_ENOMEM if the scratch cannot be allocated. */
bvox_status bvox__measure_scan(const bvox_volume *vol, bvox__scan *out);

/* The same, with every column's hull written into hulls (nx * ny entries;
 * {0, 0, 0} for a column without object voxels): the cavities' first pass,
 * done while the scan has each column in cache. */
bvox_status bvox__measure_scan_hulls(const bvox_volume *vol, bvox__colhull *hulls,
                                     bvox__scan *out);

/* Crofton weights: the area estimate is sum over classes of
 * weight[c] * trans[c]. weight[c] = (solid angle of the spherical Voronoi
 * cell of one direction of c) / pi * (voxel volume) / (length of the
 * direction), the Voronoi cells taken among the 26 unit directions
 * +-(i sx, j sy, k sz) / |.|. */
void bvox__crofton_weights(const double spacing[3], double weight[BVOX__NDIR]);
/* Solid angles alone (one direction of each class); they sum, with the class
 * multiplicities 1,1,1,2,2,2,4 and both signs, to 4 pi. For tests. */
void bvox__crofton_solid_angles(const double spacing[3], double omega[BVOX__NDIR]);

/* bvox_measure with precomputed Crofton weights; bbox_shift is added to the
 * reported voxel box (a crop's offset in its parent), may be NULL. */
bvox_status bvox__measure_with(const bvox_volume *vol, const double weight[BVOX__NDIR],
                               const int32_t bbox_shift[3], bvox_measures *out);

/* The physical measures of one scan's sums (everything but the topology
 * that needs labelling: components, cavities, tunnels stay 0); geom gives
 * the spacing and origin. Used by bvox__measure_with and by the out-of-core
 * measure, which adds the scans of its slabs (src/stream/). */
void bvox__measure_from_scan(const bvox__scan *s, const bvox_geometry *geom,
                             const double weight[BVOX__NDIR], const int32_t bbox_shift[3],
                             bvox_measures *out);

/* A copy of vol without its repeated x- and y-slices and without the empty
 * ones outside bbox, the scan's box (not empty): the same components and
 * cavities (measure_collapse.c). hulls: the scan's records, whose twin
 * flags name the repeated rows. *out is NULL when the copy would keep more
 * than three quarters of the box's columns. BVOX_ENOMEM. */
bvox_status bvox__collapse_repeats(const bvox_volume *vol, const int32_t bbox[6],
                                   const bvox__colhull *hulls, bvox_volume **out);

/* Components (26) and cavities (6, 26) of vol into m, from its scan sc and
 * hulls, on its collapsed copy when there is one (its own scan then), or
 * on vol when the copy's way is over the memory budget; labelled (may be
 * NULL): the dims of the volume counted on. */
bvox_status bvox__measure_topology(const bvox_volume *vol, const bvox__scan *sc,
                                   const bvox__colhull *hulls, bvox_measures *m,
                                   bvox_dims *labelled);

/* Cavities of vol: 6-connected background components not reaching the
 * border (cav6), and the 26-connected ones (cav26); sc is vol's scan (the
 * object's voxel box, its count and z faces choose the route), the object
 * not empty; hulls, its columns' hulls from bvox__measure_scan_hulls, or
 * NULL (they are scanned for when the route needs them). BVOX_ENOMEM / BVOX_ETOOBIG,
 * or a progress cancel. */
bvox_status bvox__measure_cavities(const bvox_volume *vol, const bvox__scan *sc,
                                   const bvox__colhull *hulls, int64_t *cav6, int64_t *cav26);

/* Bits of word k of a column that lie in [lo, hi). */
static inline uint64_t bvox__range_bits(int32_t lo, int32_t hi, size_t k)
{
    int64_t base = (int64_t)k * 64, a = lo - base, b = hi - base;
    if (b <= 0 || a >= 64 || hi <= lo) return 0;
    uint64_t upto_b = b >= 64 ? ~0ull : (1ull << b) - 1;
    uint64_t below_a = a <= 0 ? 0 : (1ull << a) - 1;
    return upto_b & ~below_a;
}

/* The runs of a column's words w[k0, k1) in z order (the words below k0
 * and from k1 on taken as 0): bvox__runs_begin, then bvox__runs_next until
 * it returns false. Each word's run starts and ends are found when the
 * iterator reaches it (from its bit 63 before and the next word's bit 0),
 * and a run it gives ends in that word, so the caller may clear the run
 * before asking for the next: no cleared bit is read again. */
typedef struct bvox__runs_iter {
    const uint64_t *w;
    size_t k, k1;
    uint64_t s, e, top; /* the word's starts and ends not yet passed; its bit 63 */
    int32_t z0;         /* the start of a run that goes on into later words */
} bvox__runs_iter;

static inline void bvox__runs_load(bvox__runs_iter *it, uint64_t below)
{
    uint64_t v = it->w[it->k], next = it->k + 1 < it->k1 ? it->w[it->k + 1] & 1 : 0;
    it->s = v & ~((v << 1) | below);
    it->e = v & ~((v >> 1) | (next << 63));
    it->top = v >> 63;
}

static inline bool bvox__runs_begin(bvox__runs_iter *it, const uint64_t *w, size_t k0, size_t k1)
{
    it->w = w, it->k = k0, it->k1 = k1, it->z0 = -1;
    if (k0 >= k1) return false;
    bvox__runs_load(it, 0);
    return true;
}

static inline bool bvox__runs_next(bvox__runs_iter *it, int32_t *z0, int32_t *z1)
{
    for (;;) {
        int32_t base = (int32_t)(it->k * 64);
        if (it->e) {
            /* a start at or below this end begins its run; else the run
             * began in an earlier word */
            if (it->s && __builtin_ctzll(it->s) <= __builtin_ctzll(it->e)) {
                it->z0 = base + __builtin_ctzll(it->s);
                it->s &= it->s - 1;
            }
            *z0 = it->z0;
            *z1 = base + __builtin_ctzll(it->e) + 1;
            it->e &= it->e - 1;
            return true;
        }
        if (it->s) it->z0 = base + __builtin_ctzll(it->s); /* goes on upwards */
        if (++it->k >= it->k1) return false;
        bvox__runs_load(it, it->top);
    }
}

/* The z range [lo, hi) strictly between the first and the last object voxel
 * of a column o of wpc words (lo = hi = 0 when it has none, or when ring:
 * the columns around a box are all outside it). */
static inline void bvox__column_hull(const uint64_t *o, size_t wpc, bool ring, int32_t *lo,
                                     int32_t *hi)
{
    size_t k0 = 0, k1 = wpc;
    while (k0 < wpc && !o[k0]) k0++;
    while (k1 > k0 && !o[k1 - 1]) k1--;
    *lo = *hi = 0;
    if (!ring && k0 < k1) {
        *lo = (int32_t)(k0 * 64) + __builtin_ctzll(o[k0]) + 1;
        *hi = (int32_t)((k1 - 1) * 64 + 63) - __builtin_clzll(o[k1 - 1]);
    }
}

/* Where a box's background is read from without a copy: box column (x, y)
 * is words + ((y0 + y) * nx + x0 + x) * wpc, each word XORed with flip (~0:
 * words holds the object, so a volume's complement is read in place; 0:
 * words holds the background itself), the last word of a column ANDed with
 * tail (the bits beyond nz). */
typedef struct bvox__bgsrc {
    const uint64_t *words;
    size_t nx, x0, y0;
    uint64_t flip, tail;
} bvox__bgsrc;

/* Word k (of wpc) of box column (x, y) of bg. */
static inline uint64_t bvox__bg_word(const bvox__bgsrc *bg, size_t x, size_t y, size_t wpc,
                                     size_t k)
{
    uint64_t w = bg->words[((bg->y0 + y) * bg->nx + bg->x0 + x) * wpc + k] ^ bg->flip;
    return k + 1 == wpc ? w & bg->tail : w;
}

/* Grows reached (zeroed, nx * ny columns of wpc words, the box's) to the
 * voxels of bg 6-connected to the border of the box (its ring of columns,
 * z = 0 and z = nz - 1) by at most max_sweeps sweeps; false when that was
 * not enough to settle (reached is then a subset). stamps: ny + nx * ny
 * entries of scratch. measure_flood.c. */
bool bvox__flood_border(const bvox__bgsrc *bg, size_t nx, size_t ny, size_t wpc, size_t nz,
                        int max_sweeps, uint64_t *reached, int32_t *stamps);

/* One row of a flood sweep (measure_flood.c): the columns x = 1 .. nx - 2,
 * backward or forward, each visited when bvox__flood_due and then grown to
 * fill_z(bg, R | R of its four neighbours | its two end voxels), its stamp
 * set to sweep when it grew. Pointers are to the row's column x = 0. */
typedef struct bvox__flood_row {
    const uint64_t *bg; /* the row's background columns, wpc words each */
    uint64_t *r;        /* reached; the rows beside it are r -+ nx * wpc */
    int32_t *stamps;    /* per column: the last sweep that grew it, or -1 */
    size_t nx, wpc;
    uint64_t flip, tail; /* bg's words are XORed with flip, the last ANDed with tail */
    uint64_t top;        /* bit of z = nz - 1 in a column's last word */
    int32_t sweep;
    int backward;
} bvox__flood_row;

/* 1 when the row grew anywhere. */
typedef int (*bvox__flood_row_fn)(const bvox__flood_row *row);
/* wpc <= 8, a column one vector (measure_flood_avx512.c) or two
 * (measure_flood_avx2.c); NULL when not built */
extern const bvox__flood_row_fn bvox__flood_row_avx512;
extern const bvox__flood_row_fn bvox__flood_row_avx2;

/* The SIMD rows' carries between the eight words of a column (bit i of a
 * mask: word i): word i passes a carry on to word i + 1 (up) or i - 1
 * (down) when it generates one (g) or receives one and propagates it (p,
 * its background all ones); the words that receive one. */
static inline unsigned bvox__lane_carry_up(unsigned g, unsigned p)
{
    g |= p & (g << 1), p &= p << 1;
    g |= p & (g << 2), p &= p << 2;
    g |= p & (g << 4);
    return (g << 1) & 0xff;
}

static inline unsigned bvox__lane_carry_down(unsigned g, unsigned p)
{
    g |= p & (g >> 1), p &= p >> 1;
    g |= p & (g >> 2), p &= p >> 2;
    g |= p & (g >> 4);
    return g >> 1;
}

/* The SIMD rows' per-word constants of a column (wpc <= 8, the words past
 * wpc 0): tail, ANDed with the background (the last word's bits beyond nz
 * cleared), and ends, the column's two end voxels (z = 0 and z = nz - 1),
 * which lie on the border. */
static inline void bvox__flood_row_masks(const bvox__flood_row *row, uint64_t tail[8],
                                         uint64_t ends[8])
{
    for (size_t k = 0; k < 8; k++) tail[k] = k < row->wpc ? ~0ull : 0, ends[k] = 0;
    tail[row->wpc - 1] = row->tail;
    ends[0] = 1;
    ends[row->wpc - 1] |= row->top;
}

/* Whether the column with stamp s is due in row->sweep: one of its four
 * neighbours grew since the sweep before began. Else its inputs are as at
 * its last visit, which left it settled. */
static inline int bvox__flood_due(const bvox__flood_row *row, const int32_t *s)
{
    size_t nx = row->nx;
    int32_t a = __atomic_load_n(&s[-1], __ATOMIC_RELAXED);
    int32_t b = __atomic_load_n(&s[1], __ATOMIC_RELAXED);
    int32_t c = __atomic_load_n(&s[-(ptrdiff_t)nx], __ATOMIC_RELAXED);
    int32_t d = __atomic_load_n(&s[nx], __ATOMIC_RELAXED);
    int32_t m = a > b ? a : b, n = c > d ? c : d;
    return (m > n ? m : n) >= row->sweep - 1;
}

/* Test hook of measure_cavities.c: -1 (default) chooses the route; 0 always
 * labels the background; n > 0 always floods first, at most n sweeps. */
extern int bvox__cavity_flood_sweeps;

/* Test hook of measure_cavities.c, on the flood's route: 0 (default) the
 * 26-cavities by labelling only the cavity voxels that no dilation of the
 * reached background covers; 1 by labelling all of them. */
extern int bvox__cavity_label_k;

/* Test hook of measure_cavities.c: -1 (default), the labelling route lists
 * and joins the runs of the background enclosed along z
 * (measure_hull_runs.c); 1, it labels that background's words
 * (measure_enclosed.c); 0, all of the box's background. */
extern int bvox__cavity_hull;

/* Test hook of measure_hull_runs.c: 1 (default), rows equal to the row
 * before own no runs (they stand on their streak's first row's); 0, every
 * row is listed and joined on its own. */
extern int bvox__cavity_twin_rows;

/* Both cavity counts of vol from the runs of the background enclosed along z
 * in the columns [x0, x0 + nx) x [y0, y0 + ny) (the object's x-y box grown
 * by one, so its ring of columns is background), hulls the volume's columns'
 * from bvox__measure_scan_hulls. measure_hull_runs.c.
 * BVOX_ENOMEM / BVOX_ETOOBIG. */
bvox_status bvox__cavities_from_hull_runs(const bvox_volume *vol, const bvox__colhull *hulls,
                                          size_t x0, size_t y0, size_t nx, size_t ny,
                                          int64_t *cav6, int64_t *cav26);

/* U: the background of vol's columns [x0, x0 + nx) x [y0, y0 + ny) strictly
 * between the first and the last object voxel of each column (none in the
 * box's ring of columns), nx * ny * wpc words; zr: per column that z range
 * [lo, hi), 2 int32 each. measure_enclosed.c. */
void bvox__enclosed_background(const bvox_volume *vol, size_t x0, size_t y0, size_t nx,
                               size_t ny, uint64_t *u, int32_t *zr);

/* touched[root] = 1 for the component of every run of r, the 6-labelling
 * of U above (box at x0, y0, parents flattened), holding a 6-neighbour of
 * the rest of the background. */
struct bvox__labelruns;
void bvox__enclosed_mark_exterior(const struct bvox__labelruns *r, const bvox_volume *vol,
                                  size_t x0, size_t y0, const int32_t *zr, uint8_t *touched);

/* A run of a column along z, [z0, z1). */
typedef struct bvox__zrun {
    int32_t z0, z1;
} bvox__zrun;

/* Unites the runs a[0, na) (union-find indices ia..) with the runs b[0, nb)
 * (ib..) of a neighbour column that they touch: faces when reach is 0,
 * z-diagonals too when it is 1 ([z0, z1) and [z0', z1') with
 * z0 < z1' + reach and z0' < z1 + reach). Both lists in z order, their runs
 * disjoint, so one merge finds every pair. measure_cavities_sparse.c. */
void bvox__zruns_join(uint32_t *parent, const bvox__zrun *a, uint32_t ia, uint32_t na,
                      const bvox__zrun *b, uint32_t ib, uint32_t nb, int32_t reach);

/* The 26-cavities of K, given as runs kr (column by column of the box of
 * nx * ny columns at x0, y0 in vol, in z order; first: per column the index
 * of its first run, ncol + 1 entries), none in the box's ring: the
 * 26-components of K with no voxel 26-adjacent to the rest of the
 * background. measure_cavities_sparse.c. BVOX_ENOMEM. */
bvox_status bvox__cavities_26_runs(const bvox__zrun *kr, const uint32_t *first, size_t nx,
                                   size_t ny, const bvox_volume *vol, size_t x0, size_t y0,
                                   int64_t *out);

/* The same from r, the flattened 6-labelling of words (the box's columns)
 * whose runs not in the component of parent[nruns] are K; first counts
 * those per column as above. */
bvox_status bvox__cavities_26_sparse(const struct bvox__labelruns *r, const uint64_t *words,
                                     const bvox_volume *vol, size_t x0, size_t y0,
                                     const uint32_t *first, int64_t *out);

/* Test hook of measure_cavities.c: -1 (default) chooses; 0, the
 * 26-cavities of the labelling routes by relabelling K's box; 1, from K's
 * runs (bvox__cavities_26_sparse). */
extern int bvox__cavity_sparse_26;

#endif /* BVOX_MEASURE_H */
