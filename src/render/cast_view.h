/*
 * cast_view.h — the state of one arbitrary-view cast (cast_view.c), shared
 * with its SIMD splat kernel (cast_view_avx2.c): both must give bit-identical
 * z-buffers, so they share the projection of an entry and do the per-pixel
 * arithmetic in the same order.
 */
#ifndef BVOX_RENDER_CAST_VIEW_H
#define BVOX_RENDER_CAST_VIEW_H

#include "render.h"

#include <math.h>
#include <stdatomic.h>
#include <stdint.h>

typedef struct frame {
    double r[3], dn[3], d[3]; /* right, down, view */
} frame;

static inline double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

struct splat_ctx;
typedef void (*bvox__splat_fn)(const struct splat_ctx *c, const uint64_t *list, int64_t n,
                               int32_t row0, int32_t row1, uint64_t *zb);

typedef void (*bvox__bands_fn)(const struct splat_ctx *c, const uint64_t *list, int n,
                               int32_t *b0, int32_t *b1);

typedef struct splat_ctx {
    const bvox_surface *s;
    frame f;
    double scale, half_w, half_h; /* pixel = eye * scale + half - 0.5 */
    double c[3], rho;             /* centre and radius of the fitting sphere */
    double hu, hv;                /* half size of a voxel's projection, pixels */
    double h[3];                  /* half voxel size */
    /* Slab test of a pixel ray offset (du, dv) pixels from a voxel's projected
     * centre, the same for every voxel: per axis a, k_a = du ku[a] + dv kv[a]
     * and the ray is inside the slab for t in [-H_a - k_a, H_a - k_a]
     * (t physical along the view from the voxel centre's depth). An axis the
     * view is parallel to has no t bounds: it is inside iff -h <= q < h with
     * q_a = (du r_a + dv dn_a) / scale. */
    double ku[3], kv[3], H[3];
    int parallel[3];
    unsigned facing;              /* neighbour bits whose emptiness makes a front face */
    const bvox__surface_run *ranges; /* the runs of the front-facing classes, in order */
    int64_t *range_end;           /* entries in ranges [0, i] */
    int64_t nranges;
    int64_t total;                /* entries in those ranges */
    int32_t w, hgt;
    int32_t stride;               /* keys from one z-buffer row to the next: w + 3 padding */
    int32_t band_rows, nbands;    /* the image in bands of band_rows rows */
    int band_shift;               /* band_rows = 1 << band_shift */
    int64_t nchunks;              /* the entries in chunks, for the bucketing */
    int64_t *bucket_at;           /* [band * nchunks + chunk]: count, then offset */
    uint64_t *bucket;             /* the entries of each band, band after band */
    bvox__splat_fn splat;         /* splat_list or a SIMD kernel giving the same keys */
    bvox__bands_fn bands;         /* the bands of entries, for the bucketing */
    bvox_preimage *pre;
    bvox__cue cue;
    uint64_t *scratch[64];         /* band z-buffers, one per concurrent task */
    atomic_int scratch_busy[64];
    int nscratch;
    double pu[4], pv[4], pw[4];   /* fu, fv, wc of a voxel from its indices (project_axis) */
} splat_ctx;

/* floor for values well inside the int32 range, without a libm call */
static inline int32_t ifloor(double x)
{
    int32_t i = (int32_t)x;
    return i - (x < (double)i);
}

/* x clamped to [lo, hi]; both comparisons as _mm256_max_pd / _mm256_min_pd
 * make them, so the SIMD kernel gets the same values. */
static inline double clamp_to(double x, double lo, double hi)
{
    x = x > lo ? x : lo;
    return x < hi ? x : hi;
}

/* ceil(x) and floor(x) clamped to 0..n-1 (empty ranges stay empty): x may be
 * far outside the int range when the scale is huge, so it is clamped first
 * (to -0.5: its ceil is 0, its floor -1), and no branch is taken. */
static inline int32_t ceil_in(double x, int32_t n) { return -ifloor(-clamp_to(x, -0.5, n)); }
static inline int32_t floor_in(double x, int32_t n) { return ifloor(clamp_to(x, -0.5, n - 1)); }

/* An entry's projected centre (fu, fv: pixels; wc: depth, physical) from its
 * voxel indices: ((x p[0] + y p[1]) + z p[2]) + p[3] with the coefficients
 * pu, pv, pw of splat_ctx, in that order in every kernel. */
static inline double project_axis(const double p[4], uint64_t e)
{
    return (SURF_X(e) * p[0] + SURF_Y(e) * p[1]) + SURF_Z(e) * p[2] + p[3];
}

/* The candidate pixels of entry e: its projection's bounding box, clipped to
 * the image; 0 if it is empty. fu, fv: projected centre; wc: its depth. */
static inline int project(const splat_ctx *c, uint64_t e, double *fu, double *fv, double *wc,
                          int32_t box[4])
{
    *fu = project_axis(c->pu, e);
    *fv = project_axis(c->pv, e);
    *wc = project_axis(c->pw, e);
    box[0] = ceil_in(*fu - c->hu, c->w), box[1] = floor_in(*fu + c->hu, c->w);
    box[2] = ceil_in(*fv - c->hv, c->hgt), box[3] = floor_in(*fv + c->hv, c->hgt);
    return box[0] <= box[1] && box[2] <= box[3];
}

/* The bands entry e may touch, [*b0, *b1] (*b1 < *b0 if none): project()'s
 * rows in a cheaper form, widened by a small margin so that rounding can
 * only add a band (where the exact test of the splat then finds nothing),
 * never lose one. */
static inline void entry_bands(const splat_ctx *c, uint64_t e, int32_t *b0, int32_t *b1)
{
    double fv = project_axis(c->pv, e);
    int32_t py0 = ceil_in(fv - c->hv - 1e-3, c->hgt), py1 = floor_in(fv + c->hv + 1e-3, c->hgt);
    *b0 = py0 >> c->band_shift;
    *b1 = py0 <= py1 ? py1 >> c->band_shift : -1;
}

/* The AVX2 kernel (cast_view_avx2.c); NULL where it is not built. Every
 * kernel reads and writes back 4 keys from any pixel of a z-buffer row: the
 * rows have 3 keys of padding (stride). */
extern const bvox__splat_fn bvox__splat_avx2;
extern const bvox__bands_fn bvox__bands_avx2;

#endif
