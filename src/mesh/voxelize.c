/*
 * voxelize.c — mesh -> volume.
 *
 * Grid: voxel size s (given, or the longest side of the bounding box / res);
 * n = ceil(extent / s) voxels per axis, centred on the box; voxel centres
 * at origin + i*s. For a box whose sides are multiples of s the voxel faces
 * fall on the mesh faces, so meshing the volume back lands on the original
 * coordinates.
 *
 * Solid: a voxel is in when its centre is inside. Rays along z through the
 * voxel centres; a triangle is crossed by the ray (i, j) when the point is
 * inside its projection. The projections are snapped to a fixed-point grid
 * (2^-20 voxel; a vertex always snaps the same way, so shared edges stay
 * shared) and the point-in-triangle test is exact (__int128 orientations).
 * Points ON an edge or vertex are decided by simulation of simplicity: the
 * ray is moved by (eps, eps^2), which makes the three orientation signs
 * never zero and consistent between the triangles sharing an edge, so a
 * closed surface is crossed an even number of times by every ray. Voxels
 * whose centre lies between the (2k)-th and (2k+1)-th crossing along z are
 * set as bit ranges of the column words. Rows of rays are split over the
 * threads (triangles bucketed by row).
 *
 * A mesh that is not closed (edges not on exactly two triangles) has no
 * inside; bvox casts the rays along x, y and z and keeps the voxels that at
 * least two of the three parities call inside.
 *
 * Shell: the voxels whose (closed) cube the surface meets, by the separating
 * axis test of a triangle and a box (Akenine-Moller), the box enlarged by
 * 1e-9 voxel so that touching counts.
 */
#include "mesh_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIX_BITS 20
#define FIX_ONE ((int64_t)1 << FIX_BITS)

typedef __int128 i128;

typedef struct cross {
    int32_t q; /* ray index within the row */
    double t;  /* position along the ray, voxel units */
} cross;

typedef struct vox {
    const bvox_mesh *m;
    bvox_volume *out;
    int32_t n[3];
    double origin[3], s;
    int a, r, q;         /* ray axis, row axis, in-row axis */
    int64_t *fq, *fr;    /* fixed-point projections */
    double *ga;          /* voxel-unit coordinate along the ray */
    int64_t *bstart;     /* triangles per row, CSR */
    int32_t *btri;
    size_t vbytes, bbytes; /* budgeted sizes of fq/fr/ga and btri */
    int shell;
    int failed;          /* an allocation failed in a worker */
} vox;

static inline int64_t floor_div(int64_t a, int64_t b)
{
    int64_t d = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? d - 1 : d;
}
static inline int64_t ceil_div(int64_t a, int64_t b) { return -floor_div(-a, b); }

static inline i128 orient(int64_t au, int64_t av, int64_t bu, int64_t bv, int64_t pu, int64_t pv)
{
    return (i128)(bu - au) * (pv - av) - (i128)(bv - av) * (pu - au);
}

/* Sign of the orientation of (e0, e1, p) with p moved by (eps, eps^2). */
static inline int sos_sign(int64_t au, int64_t av, int64_t bu, int64_t bv, int64_t pu, int64_t pv)
{
    i128 d = orient(au, av, bu, bv, pu, pv);
    if (d > 0) return 1;
    if (d < 0) return -1;
    int64_t du = bu - au, dv = bv - av;
    if (dv != 0) return dv < 0 ? 1 : -1;
    return du > 0 ? 1 : -1;
}

static double grid_coord(const vox *v, int axis, double x)
{
    return (x - v->origin[axis]) / v->s;
}

static int cross_cmp(const void *a, const void *b)
{
    const cross *x = a, *y = b;
    if (x->q != y->q) return x->q < y->q ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
}

static void set_voxel(vox *v, int32_t rowi, int32_t qi, int32_t k)
{
    int32_t xyz[3];
    xyz[v->a] = k;
    xyz[v->r] = rowi;
    xyz[v->q] = qi;
    uint64_t *c = bvox__column(v->out, xyz[0], xyz[1]);
    c[xyz[2] >> 6] |= 1ull << (xyz[2] & 63);
}

static void fill_run(vox *v, int32_t rowi, int32_t qi, double t0, double t1)
{
    /* voxels k with t0 < k <= t1 */
    double lo = floor(t0) + 1, hi = floor(t1);
    int32_t na = v->n[v->a];
    if (lo < 0) lo = 0;
    if (hi > na - 1) hi = na - 1;
    if (lo > hi) return;
    int32_t k0 = (int32_t)lo, k1 = (int32_t)hi;
    if (v->a == 2) {
        bvox__column_fill(bvox__column(v->out, qi, rowi), k0, k1 + 1, 1);
        return;
    }
    for (int32_t k = k0; k <= k1; k++) set_voxel(v, rowi, qi, k);
}

static void ray_rows(void *ctx, int64_t begin, int64_t end)
{
    vox *v = ctx;
    const bvox_mesh *m = v->m;
    size_t cap = 1024, nc = 0;
    cross *cs = bvox__mem_alloc(cap * sizeof *cs);
    if (!cs) {
        __atomic_store_n(&v->failed, 1, __ATOMIC_RELAXED);
        return;
    }
    int32_t nq = v->n[v->q];
    for (int64_t row = begin; row < end; row++) {
        nc = 0;
        int64_t pr = row * FIX_ONE;
        for (int64_t bi = v->bstart[row]; bi < v->bstart[row + 1]; bi++) {
            const int32_t *t = m->triangles + 3 * (size_t)v->btri[bi];
            int64_t u0 = v->fq[t[0]], u1 = v->fq[t[1]], u2 = v->fq[t[2]];
            int64_t w0 = v->fr[t[0]], w1 = v->fr[t[1]], w2 = v->fr[t[2]];
            i128 area = orient(u0, w0, u1, w1, u2, w2);
            if (area == 0) continue;
            int sg = area > 0 ? 1 : -1;
            int64_t umin = u0 < u1 ? (u0 < u2 ? u0 : u2) : (u1 < u2 ? u1 : u2);
            int64_t umax = u0 > u1 ? (u0 > u2 ? u0 : u2) : (u1 > u2 ? u1 : u2);
            int64_t i0 = ceil_div(umin, FIX_ONE), i1 = floor_div(umax, FIX_ONE);
            if (i0 < 0) i0 = 0;
            if (i1 > nq - 1) i1 = nq - 1;
            for (int64_t i = i0; i <= i1; i++) {
                int64_t pu = i * FIX_ONE;
                if (sos_sign(u0, w0, u1, w1, pu, pr) != sg) continue;
                if (sos_sign(u1, w1, u2, w2, pu, pr) != sg) continue;
                if (sos_sign(u2, w2, u0, w0, pu, pr) != sg) continue;
                /* depth by barycentric weights (exact orientations) */
                double b0 = (double)orient(u1, w1, u2, w2, pu, pr);
                double b1 = (double)orient(u2, w2, u0, w0, pu, pr);
                double b2 = (double)orient(u0, w0, u1, w1, pu, pr);
                double tt = (b0 * v->ga[t[0]] + b1 * v->ga[t[1]] + b2 * v->ga[t[2]]) /
                            (b0 + b1 + b2);
                if (nc == cap) {
                    cross *g = bvox__mem_resize(cs, 2 * cap * sizeof *cs);
                    if (!g) {
                        __atomic_store_n(&v->failed, 1, __ATOMIC_RELAXED);
                        free(cs);
                        return;
                    }
                    cs = g;
                    cap *= 2;
                }
                cs[nc++] = (cross){(int32_t)i, tt};
            }
        }
        qsort(cs, nc, sizeof *cs, cross_cmp);
        for (size_t k = 0; k < nc;) {
            size_t e = k;
            while (e < nc && cs[e].q == cs[k].q) e++;
            for (size_t j = k; j + 1 < e; j += 2)
                fill_run(v, (int32_t)row, cs[k].q, cs[j].t, cs[j + 1].t);
            k = e;
        }
    }
    free(cs);
}

/* ---- triangle / box overlap (separating axes) ---- */

static int axis_test(const double *v0, const double *v1, const double *v2, const double *ax,
                     const double *h)
{
    double p0 = v0[0] * ax[0] + v0[1] * ax[1] + v0[2] * ax[2];
    double p1 = v1[0] * ax[0] + v1[1] * ax[1] + v1[2] * ax[2];
    double p2 = v2[0] * ax[0] + v2[1] * ax[1] + v2[2] * ax[2];
    double mn = fmin(p0, fmin(p1, p2)), mx = fmax(p0, fmax(p1, p2));
    double rad = h[0] * fabs(ax[0]) + h[1] * fabs(ax[1]) + h[2] * fabs(ax[2]);
    return !(mn > rad || mx < -rad);
}

/* tri: vertices relative to the box centre; h: half sizes */
static int tri_box(const double tri[3][3], const double *h)
{
    for (int k = 0; k < 3; k++) {
        double mn = fmin(tri[0][k], fmin(tri[1][k], tri[2][k]));
        double mx = fmax(tri[0][k], fmax(tri[1][k], tri[2][k]));
        if (mn > h[k] || mx < -h[k]) return 0;
    }
    double e[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) e[i][k] = tri[(i + 1) % 3][k] - tri[i][k];
    double nrm[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                     e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    if (!axis_test(tri[0], tri[1], tri[2], nrm, h)) return 0;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            double unit[3] = {0, 0, 0}, ax[3];
            unit[k] = 1;
            ax[0] = e[i][1] * unit[2] - e[i][2] * unit[1];
            ax[1] = e[i][2] * unit[0] - e[i][0] * unit[2];
            ax[2] = e[i][0] * unit[1] - e[i][1] * unit[0];
            if (ax[0] == 0 && ax[1] == 0 && ax[2] == 0) continue;
            if (!axis_test(tri[0], tri[1], tri[2], ax, h)) return 0;
        }
    return 1;
}

static void shell_rows(void *ctx, int64_t begin, int64_t end)
{
    vox *v = ctx;
    const bvox_mesh *m = v->m;
    const double h[3] = {0.5 + 1e-9, 0.5 + 1e-9, 0.5 + 1e-9};
    for (int64_t y = begin; y < end; y++)
        for (int64_t bi = v->bstart[y]; bi < v->bstart[y + 1]; bi++) {
            const int32_t *t = m->triangles + 3 * (size_t)v->btri[bi];
            double g[3][3];
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 3; k++) g[i][k] = grid_coord(v, k, m->vertices[3 * t[i] + k]);
            int32_t lo[3], hi[3];
            for (int k = 0; k < 3; k++) {
                double mn = fmin(g[0][k], fmin(g[1][k], g[2][k]));
                double mx = fmax(g[0][k], fmax(g[1][k], g[2][k]));
                double a = ceil(mn - 0.5 - 1e-9), b = floor(mx + 0.5 + 1e-9);
                lo[k] = a < 0 ? 0 : (int32_t)a;
                hi[k] = b > v->n[k] - 1 ? v->n[k] - 1 : (int32_t)b;
            }
            for (int32_t x = lo[0]; x <= hi[0]; x++)
                for (int32_t z = lo[2]; z <= hi[2]; z++) {
                    double tri[3][3];
                    for (int i = 0; i < 3; i++) {
                        tri[i][0] = g[i][0] - x;
                        tri[i][1] = g[i][1] - (double)y;
                        tri[i][2] = g[i][2] - z;
                    }
                    if (tri_box(tri, h)) {
                        uint64_t *c = bvox__column(v->out, x, (int32_t)y);
                        c[z >> 6] |= 1ull << (z & 63);
                    }
                }
        }
}

/* Bucket the triangles by the rows (of axis v->r) they can touch. */
static bvox_status bucket(vox *v)
{
    const bvox_mesh *m = v->m;
    int32_t nrow = v->n[v->r];
    v->bstart = bvox__mem_zalloc((size_t)nrow + 2, sizeof(int64_t));
    if (!v->bstart) return bvox__fail(BVOX_ENOMEM, "out of memory (voxelize)");
    for (int pass = 0; pass < 2; pass++) {
        for (int64_t t = 0; t < m->ntriangles; t++) {
            const int32_t *tr = m->triangles + 3 * t;
            int64_t r0, r1;
            if (v->shell) {
                double mn = INFINITY, mx = -INFINITY;
                for (int i = 0; i < 3; i++) {
                    double g = grid_coord(v, v->r, m->vertices[3 * tr[i] + v->r]);
                    mn = fmin(mn, g);
                    mx = fmax(mx, g);
                }
                r0 = (int64_t)ceil(mn - 0.5 - 1e-9);
                r1 = (int64_t)floor(mx + 0.5 + 1e-9);
            } else {
                int64_t mn = v->fr[tr[0]], mx = mn;
                for (int i = 1; i < 3; i++) {
                    if (v->fr[tr[i]] < mn) mn = v->fr[tr[i]];
                    if (v->fr[tr[i]] > mx) mx = v->fr[tr[i]];
                }
                r0 = ceil_div(mn, FIX_ONE);
                r1 = floor_div(mx, FIX_ONE);
            }
            if (r0 < 0) r0 = 0;
            if (r1 > nrow - 1) r1 = nrow - 1;
            for (int64_t r = r0; r <= r1; r++) {
                if (pass == 0) v->bstart[r + 1]++;
                else v->btri[v->bstart[r]++] = (int32_t)t;
            }
        }
        if (pass == 0) {
            for (int32_t r = 0; r < nrow; r++) v->bstart[r + 1] += v->bstart[r];
            bvox_status st;
            v->bbytes = (size_t)v->bstart[nrow] * sizeof(int32_t) + 1;
            v->btri = bvox__alloc(v->bbytes, false, "voxelizer triangle lists", &st);
            if (!v->btri) return st;
        } else {
            for (int32_t r = nrow; r > 0; r--) v->bstart[r] = v->bstart[r - 1];
            v->bstart[0] = 0;
        }
    }
    return BVOX_OK;
}

static void vox_release(vox *v)
{
    if (v->fq) bvox__free(v->fq, v->vbytes);
    if (v->fr) bvox__free(v->fr, v->vbytes);
    if (v->ga) bvox__free(v->ga, v->vbytes);
    free(v->bstart);
    if (v->btri) bvox__free(v->btri, v->bbytes);
    v->fq = v->fr = NULL;
    v->ga = NULL;
    v->bstart = NULL;
    v->btri = NULL;
}

/* One pass: rays along axis a (or the shell) into v->out. */
static bvox_status run_axis(vox *v, int a)
{
    static const int rows[3] = {1, 0, 1}, inner[3] = {2, 2, 0};
    v->a = a;
    v->r = v->shell ? 1 : rows[a];
    v->q = inner[a];
    const bvox_mesh *m = v->m;
    size_t nv = (size_t)m->nvertices;
    if (!v->shell) {
        bvox_status st = BVOX_OK;
        v->vbytes = nv * sizeof(int64_t) + 1;
        v->fq = bvox__alloc(v->vbytes, false, "voxelizer vertices", &st);
        if (v->fq) v->fr = bvox__alloc(v->vbytes, false, "voxelizer vertices", &st);
        if (v->fr) v->ga = bvox__alloc(v->vbytes, false, "voxelizer vertices", &st);
        if (!v->ga) {
            vox_release(v);
            return st;
        }
        for (size_t i = 0; i < nv; i++) {
            const double *p = m->vertices + 3 * i;
            v->fq[i] = llround(grid_coord(v, v->q, p[v->q]) * (double)FIX_ONE);
            v->fr[i] = llround(grid_coord(v, v->r, p[v->r]) * (double)FIX_ONE);
            v->ga[i] = grid_coord(v, a, p[a]);
        }
    }
    bvox_status st = bucket(v);
    if (!st) {
        v->failed = 0;
        bvox__parallel_for(v->n[v->r], 8, v->shell ? shell_rows : ray_rows, v);
        if (v->failed) st = bvox__fail(BVOX_ENOMEM, "out of memory (voxelize)");
    }
    vox_release(v);
    return st;
}

/* Voxelize v.m into a volume of v.n voxels, the grid v.origin + i * v.s,
 * with geometry geo: parity along z for a closed mesh, a vote of x, y and z
 * for an open one, or the shell. */
static bvox_status run(vox *vp, const bvox_geometry *geom, bvox_volume **out,
                       bvox_voxelize_report *report)
{
    vox v = *vp;
    const bvox_mesh *m = v.m;
    int64_t edges, boundary, nonman, incons;
    bvox_status st = bvox__mesh_edge_stats(m, &edges, &boundary, &nonman, &incons);
    if (st) return st;
    int closed = boundary == 0 && nonman == 0;
    bvox_dims dims = {v.n[0], v.n[1], v.n[2]};
    /* An open mesh needs the result and one volume per axis at once: refuse
     * now rather than after voxelizing along two axes. */
    size_t bytes, nvol = v.shell || closed ? 1 : 4, in_use = bvox_memory_in_use();
    size_t room = bvox_memory_budget() > in_use ? bvox_memory_budget() - in_use : 0;
    st = bvox__check_dims(dims, NULL, &bytes);
    if (st) return st;
    if (bytes > room / nvol) {
        char need[32], lim[32];
        bvox__format_bytes(need, sizeof need, bytes * nvol);
        bvox__format_bytes(lim, sizeof lim, bvox_memory_budget());
        return bvox__fail(BVOX_ETOOBIG,
                          "voxelizing at %d x %d x %d needs %s (%zu volume%s), over the memory "
                          "budget of %s",
                          dims.nx, dims.ny, dims.nz, need, nvol, nvol > 1 ? "s: an open mesh "
                          "is voxelized along x, y and z" : "", lim);
    }
    bvox_volume *vol;
    st = bvox_volume_create(dims, &vol);
    if (st) return st;
    st = bvox_volume_set_geometry(vol, geom);
    const char *method = v.shell ? "shell" : closed ? "parity-z" : "vote-xyz";
    if (!st) {
        v.out = vol;
        if (v.shell || closed) {
            st = run_axis(&v, 2);
        } else {
            bvox_volume *ax[3] = {NULL, NULL, NULL};
            for (int a = 0; a < 3 && !st; a++) {
                st = bvox_volume_create(dims, &ax[a]);
                if (!st) {
                    v.out = ax[a];
                    st = run_axis(&v, a);
                }
            }
            if (!st) {
                size_t nw = vol->nwords;
                for (size_t i = 0; i < nw; i++) {
                    uint64_t x = ax[0]->words[i], y = ax[1]->words[i], z = ax[2]->words[i];
                    vol->words[i] = (x & y) | (x & z) | (y & z);
                }
            }
            for (int a = 0; a < 3; a++) bvox_volume_destroy(ax[a]);
        }
    }
    if (st) {
        bvox_volume_destroy(vol);
        return st;
    }
    if (report) {
        report->closed = closed;
        report->open_edges = boundary + nonman;
        report->method = method;
    }
    *out = vol;
    BVOX_CHECK_VOLUME(*out);
    return BVOX_OK;
}

/* A grid given by its geometry (or anisotropic voxels covering the box): the
 * mesh is mapped into the grid's index space, p -> D^T (p - origin) / s per
 * axis, where voxel centres sit on the integers; inside-ness and the surface
 * crossing a voxel are kept by any affine map, so the unit-voxel voxelizer
 * answers the question on the given grid exactly. */
static bvox_status voxelize_on_grid(const bvox_mesh *m, const bvox_voxelize_opts *opts,
                                    const double mn[3], const double ext[3], bvox_volume **out,
                                    bvox_voxelize_report *report, bvox_dims *dims_only)
{
    bvox_geometry geo = bvox_geometry_default();
    int32_t n[3];
    if (opts->grid) {
        geo = *opts->grid;
        n[0] = opts->grid_dims.nx, n[1] = opts->grid_dims.ny, n[2] = opts->grid_dims.nz;
        for (int k = 0; k < 3; k++) {
            if (n[k] < 1 || n[k] > BVOX_MAX_DIM)
                return bvox__fail(BVOX_EINVAL, "grid dimension %c is %d, not 1..%d", "xyz"[k],
                                  (int)n[k], BVOX_MAX_DIM);
            if (!(geo.spacing[k] > 0) || !isfinite(geo.spacing[k]) || !isfinite(geo.origin[k]))
                return bvox__fail(BVOX_EINVAL, "the grid's voxel size and origin must be finite "
                                               "and the voxel size > 0");
        }
        for (int k = 0; k < 9; k++)
            if (!isfinite(geo.direction[k]))
                return bvox__fail(BVOX_EINVAL, "the grid's direction is not finite");
    } else {
        for (int k = 0; k < 3; k++) {
            double sk = opts->spacing[k];
            if (!(sk > 0) || !isfinite(sk))
                return bvox__fail(BVOX_EINVAL, "voxel size %c must be finite and > 0 (it is %g)",
                                  "xyz"[k], sk);
            double nk = ceil(ext[k] / sk - 1e-9);
            if (nk < 1) nk = 1;
            if (!(nk <= BVOX_MAX_DIM)) /* also NaN: never converted to int */
                return bvox__fail(BVOX_ETOOBIG,
                                  "the mesh spans %.3g voxels along %c (at most %d); use a larger "
                                  "voxel size",
                                  nk, "xyz"[k], BVOX_MAX_DIM);
            n[k] = (int32_t)nk;
            geo.spacing[k] = sk;
            geo.origin[k] = mn[k] + 0.5 * (ext[k] - nk * sk) + 0.5 * sk;
        }
    }
    if (dims_only) {
        *dims_only = (bvox_dims){n[0], n[1], n[2]};
        return BVOX_OK;
    }
    if (opts->unit[0] || !opts->grid) snprintf(geo.unit, sizeof geo.unit, "%.15s", opts->unit);
    bvox_status st;
    size_t bytes = (size_t)m->nvertices * 3 * sizeof(double);
    double *iv = bvox__alloc(bytes, false, "voxelizer vertices in grid space", &st);
    if (!iv) return st;
    const double *D = geo.direction;
    for (int64_t i = 0; i < m->nvertices; i++) {
        const double *p = m->vertices + 3 * i;
        double d[3] = {p[0] - geo.origin[0], p[1] - geo.origin[1], p[2] - geo.origin[2]};
        for (int c = 0; c < 3; c++)
            iv[3 * i + c] = (D[c] * d[0] + D[3 + c] * d[1] + D[6 + c] * d[2]) / geo.spacing[c];
    }
    bvox_mesh grid_mesh = *m;
    grid_mesh.vertices = iv;
    vox v;
    memset(&v, 0, sizeof v);
    v.m = &grid_mesh;
    v.shell = opts->shell != 0;
    v.s = 1;
    for (int k = 0; k < 3; k++) v.n[k] = n[k];
    st = run(&v, &geo, out, report);
    bvox__free(iv, bytes);
    return st;
}

/* Checks, the grid, then the work; with dims_only, the grid's dimensions
 * alone (nothing allocated). */
static bvox_status voxelize(const bvox_mesh *m, const bvox_voxelize_opts *opts,
                            bvox_volume **out, bvox_voxelize_report *report,
                            bvox_dims *dims_only)
{
    if (!m || !opts) return bvox__fail(BVOX_EINVAL, "bvox_mesh_voxelize: NULL argument");
    int aniso = opts->spacing[0] > 0 || opts->spacing[1] > 0 || opts->spacing[2] > 0;
    if ((opts->res > 0) + (opts->voxel_size > 0) + aniso + (opts->grid != NULL) != 1)
        return bvox__fail(BVOX_EINVAL, "voxelize needs exactly one of a resolution (voxels along "
                                       "the longest side), a voxel size, or a grid");
    if (opts->voxel_size > 0 && !isfinite(opts->voxel_size))
        return bvox__fail(BVOX_EINVAL, "the voxel size must be finite");
    if (m->ntriangles == 0) return bvox__fail(BVOX_EINVAL, "the mesh has no triangles");
    for (int64_t i = 0; i < 3 * m->ntriangles; i++)
        if (m->triangles[i] < 0 || m->triangles[i] >= m->nvertices)
            return bvox__fail(BVOX_EINVAL, "triangle index out of range");
    for (int64_t i = 0; i < 3 * m->nvertices; i++)
        if (!isfinite(m->vertices[i]))
            return bvox__fail(BVOX_EINVAL, "a vertex coordinate is not finite");
    double mn[3], mx[3];
    for (int k = 0; k < 3; k++) mn[k] = mx[k] = m->vertices[k];
    for (int64_t i = 1; i < m->nvertices; i++)
        for (int k = 0; k < 3; k++) {
            mn[k] = fmin(mn[k], m->vertices[3 * i + k]);
            mx[k] = fmax(mx[k], m->vertices[3 * i + k]);
        }
    double ext[3] = {mx[0] - mn[0], mx[1] - mn[1], mx[2] - mn[2]};
    for (int k = 0; k < 3; k++)
        if (!isfinite(ext[k])) /* e.g. vertices at -1e308 and 1e308 */
            return bvox__fail(BVOX_EINVAL,
                              "the mesh's bounding box (%g to %g along %c) is too large",
                              mn[k], mx[k], "xyz"[k]);
    double longest = fmax(ext[0], fmax(ext[1], ext[2]));
    if (opts->grid || aniso) return voxelize_on_grid(m, opts, mn, ext, out, report, dims_only);
    vox v;
    memset(&v, 0, sizeof v);
    v.m = m;
    v.shell = opts->shell != 0;
    if (opts->res > 0) {
        if (opts->res > BVOX_MAX_DIM)
            return bvox__fail(BVOX_EINVAL, "resolution %d over the limit %d", opts->res,
                              BVOX_MAX_DIM);
        if (!(longest > 0)) return bvox__fail(BVOX_EINVAL, "the mesh has no extent");
        v.s = longest / opts->res;
    } else {
        v.s = opts->voxel_size;
    }
    for (int k = 0; k < 3; k++) {
        double nk = ceil(ext[k] / v.s - 1e-9);
        if (nk < 1) nk = 1;
        if (!(nk <= BVOX_MAX_DIM)) /* also NaN: never converted to int */
            return bvox__fail(BVOX_ETOOBIG,
                              "the mesh spans %.6g voxels along %c (at most %d); use a larger "
                              "voxel size",
                              nk, "xyz"[k], BVOX_MAX_DIM);
        v.n[k] = (int32_t)nk;
        v.origin[k] = mn[k] + 0.5 * (ext[k] - nk * v.s) + 0.5 * v.s;
    }
    if (dims_only) {
        *dims_only = (bvox_dims){v.n[0], v.n[1], v.n[2]};
        return BVOX_OK;
    }
    bvox_geometry geo = bvox_geometry_default();
    for (int k = 0; k < 3; k++) {
        geo.spacing[k] = v.s;
        geo.origin[k] = v.origin[k];
    }
    snprintf(geo.unit, sizeof geo.unit, "%.15s", opts->unit);
    return run(&v, &geo, out, report);
}

bvox_status bvox_mesh_voxelize(const bvox_mesh *m, const bvox_voxelize_opts *opts,
                               bvox_volume **out, bvox_voxelize_report *report)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_voxelize: out is NULL");
    *out = NULL;
    return voxelize(m, opts, out, report, NULL);
}

bvox_status bvox_mesh_voxelize_dims(const bvox_mesh *m, const bvox_voxelize_opts *opts,
                                    bvox_dims *dims)
{
    bvox__clear_error();
    if (!dims) return bvox__fail(BVOX_EINVAL, "bvox_mesh_voxelize_dims: dims is NULL");
    return voxelize(m, opts, NULL, NULL, dims);
}
