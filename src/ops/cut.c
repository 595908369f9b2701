/*
 * cut.c — the half-space a*x + b*y + c*z + d >= 0 against a volume: the
 * plane cut (keep the part above or below a plane given in world
 * coordinates, the paper's reslicing) and the half-space primitive of CSG
 * (the shapes' axis-aligned frame).
 *
 * Both become a plane in voxel-index space, f(i, j, k) = base(i, j) + ck*k.
 * Along a column f is linear in k, so its "above" part (f >= 0) is a
 * half-line: its first (ck > 0) or last (ck < 0) index comes from solving
 * f = 0, and is then corrected by evaluating f itself at that index and its
 * neighbour, so the result is exactly the per-voxel predicate f >= 0 (f is
 * monotone in k in floating point too: rounding is monotone). ck == 0 puts
 * the whole column on one side. The run then changes the column with
 * whole-word masks; words the operation cannot change are not touched.
 */
#include "ops/edit.h"

#include <math.h>
#include <string.h>

typedef struct plane_job {
    bvox_volume *vol;
    double p[4]; /* ci, cj, ck, cd */
    bvox_csg_op op;
    bvox__change_shared shared;
} plane_job;

static inline bool above(double base, double ck, int64_t k)
{
    return base + ck * (double)k >= 0;
}

/* The run [*lo, *hi) of indices of the column with f = base + ck*k >= 0;
 * t estimates the root -base/ck (it is only a starting point: the predicate
 * itself decides, one or two evaluations when t is close). */
static inline void above_run(double base, double ck, double t, int64_t nz, int64_t *lo,
                             int64_t *hi)
{
    if (ck == 0) {
        *lo = 0;
        *hi = base >= 0 ? nz : 0;
        return;
    }
    /* clamp before converting (NaN goes to 0) */
    int64_t k = !(t > 0) ? 0 : t >= (double)nz ? nz : (int64_t)t;
    if (ck > 0) {
        /* first k with f >= 0 (nz if none) */
        while (k > 0 && above(base, ck, k - 1)) k--;
        while (k < nz && !above(base, ck, k)) k++;
        *lo = k;
        *hi = nz;
    } else {
        /* one past the last k with f >= 0 (0 if none) */
        while (k < nz && above(base, ck, k)) k++;
        while (k > 0 && !above(base, ck, k - 1)) k--;
        *lo = 0;
        *hi = k;
    }
}

static void plane_rows(void *ctx, int64_t begin, int64_t end)
{
    plane_job *j = ctx;
    bvox_volume *v = j->vol;
    const double ci = j->p[0], cj = j->p[1], ck = j->p[2], cd = j->p[3];
    /* the root moves by dt per column: no division per column */
    const double dt = ck != 0 ? -ci / ck : 0;
    int64_t nz = v->nz;
    bvox__change c;
    bvox__change_init(&c);
    for (int64_t y = begin; y < end; y++) {
        double row = cd + cj * (double)y, t0 = ck != 0 ? -row / ck : 0;
        for (int32_t x = 0; x < v->nx; x++) {
            int64_t lo, hi;
            above_run(row + ci * (double)x, ck, t0 + dt * (double)x, nz, &lo, &hi);
            uint64_t *col = bvox__column(v, x, (int32_t)y);
            switch (j->op) {
            case BVOX_CSG_UNION:
            case BVOX_CSG_REPLACE:
                bvox__run_apply(col, lo, hi, BVOX__RUN_SET, x, (int32_t)y, &c);
                break;
            case BVOX_CSG_DIFFERENCE:
                bvox__run_apply(col, lo, hi, BVOX__RUN_CLEAR, x, (int32_t)y, &c);
                break;
            case BVOX_CSG_XOR:
                bvox__run_apply(col, lo, hi, BVOX__RUN_FLIP, x, (int32_t)y, &c);
                break;
            case BVOX_CSG_INTERSECTION: /* clear what is not above */
                bvox__run_apply(col, 0, lo, BVOX__RUN_CLEAR, x, (int32_t)y, &c);
                bvox__run_apply(col, hi, nz, BVOX__RUN_CLEAR, x, (int32_t)y, &c);
                break;
            }
        }
    }
    bvox__change_merge(&j->shared, &c);
}

void bvox__halfspace_index(bvox_volume *vol, const double p[4], bvox_csg_op op,
                           bvox_box *changed)
{
    plane_job j = {.vol = vol, .p = {p[0], p[1], p[2], p[3]}, .op = op};
    bvox__change_shared_init(&j.shared);
    bvox__parallel_for(vol->ny, 4, plane_rows, &j);
    bvox__change_to_box(&j.shared.c, changed);
    bvox__change_shared_done(&j.shared);
}

static bvox_status check_plane(const char *what, double a, double b, double c, double d)
{
    if (!isfinite(a) || !isfinite(b) || !isfinite(c) || !isfinite(d))
        return bvox__fail(BVOX_EINVAL, "%s: plane coefficients %g, %g, %g, %g are not all finite",
                          what, a, b, c, d);
    if (a == 0 && b == 0 && c == 0)
        return bvox__fail(BVOX_EINVAL, "%s: plane normal (a, b, c) is zero", what);
    return BVOX_OK;
}

static bvox_status check_index_plane(const char *what, const double p[4])
{
    /* bounded so that base + ck*k (indices < 2^16) can never overflow */
    for (int i = 0; i < 4; i++)
        if (!(fabs(p[i]) <= 1e290))
            return bvox__fail(BVOX_EINVAL,
                              "%s: plane coefficients too large for the volume's geometry",
                              what);
    return BVOX_OK;
}

bvox_status bvox_cut_plane(bvox_volume *vol, double a, double b, double c, double d,
                           int keep_above, bvox_box *changed)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__clear_error();
    if (changed) memset(changed, 0, sizeof *changed);
    if (!vol) return bvox__fail(BVOX_EINVAL, "cut: no volume");
    bvox_status st = check_plane("cut", a, b, c, d);
    if (st) return st;
    /* world p = origin + direction * (index * spacing), so
     * f = (n . origin + d) + sum_c (n . direction column c) * spacing_c * index_c */
    const bvox_geometry *g = &vol->geom;
    const double n[3] = {a, b, c};
    double p[4];
    for (int col = 0; col < 3; col++) {
        double dot = n[0] * g->direction[col] + n[1] * g->direction[3 + col] +
                     n[2] * g->direction[6 + col];
        p[col] = dot * g->spacing[col];
    }
    p[3] = (n[0] * g->origin[0] + n[1] * g->origin[1] + n[2] * g->origin[2]) + d;
    if ((st = check_index_plane("cut", p))) return st;
    bvox__halfspace_index(vol, p, keep_above ? BVOX_CSG_INTERSECTION : BVOX_CSG_DIFFERENCE,
                          changed);
    BVOX_CHECK_VOLUME(vol);
    return BVOX_OK;
}

bvox_status bvox_halfspace_draw(bvox_volume *vol, double a, double b, double c, double d,
                                bvox_csg_op op, bvox_box *changed)
{
    bvox__clear_error();
    if (changed) memset(changed, 0, sizeof *changed);
    if (!vol) return bvox__fail(BVOX_EINVAL, "halfspace: no volume");
    if ((unsigned)op > BVOX_CSG_REPLACE)
        return bvox__fail(BVOX_EINVAL, "halfspace: unknown set operation %d", (int)op);
    bvox_status st = check_plane("halfspace", a, b, c, d);
    if (st) return st;
    const double *s = vol->geom.spacing, *o = vol->geom.origin;
    double p[4] = {a * s[0], b * s[1], c * s[2], (a * o[0] + b * o[1] + c * o[2]) + d};
    if ((st = check_index_plane("halfspace", p))) return st;
    bvox__halfspace_index(vol, p, op, changed);
    return BVOX_OK;
}
