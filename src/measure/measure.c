/*
 * measure.c — bvox_measure: the integer sums of one scan (measure_scan.c)
 * turned into physical measures, plus the topology that needs labelling.
 *
 * Units: positions are origin + index * spacing (direction is not applied,
 * as for shapes, so a shape drawn at c measures its centroid at c). Moments
 * treat voxels as point masses at their centres; they are exact integer sums
 * until the central moments N*sum(xx) - sum(x)^2 are formed, so no
 * cancellation is lost however far the object is from the origin.
 *
 * Topology: the Euler number of the 26-connected object comes from the scan;
 * components (26) come from run labelling (components.c), cavities
 * (6-connected background components that do not reach the border, and the
 * 26-connected ones they make up) from measure_cavities.c.
 */
#include "measure/measure.h"

#include <math.h>
#include <string.h>

/* Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations:
 * on return val holds the eigenvalues and the columns of vec the unit
 * eigenvectors. Converges quadratically; 3x3 needs a handful of sweeps. */
static void jacobi3(const double in[9], double val[3], double vec[9])
{
    double a[3][3], v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    memcpy(a, in, sizeof a);
    for (int sweep = 0; sweep < 64; sweep++) {
        double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off == 0 || off <= 1e-36 * diag) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0) continue;
                /* rotation angle that zeroes a[p][q] (Numerical Recipes' form,
                 * the smaller root for stability) */
                double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                double t = fabs(theta) > 1e150 ? 0.5 / theta
                                               : (theta >= 0 ? 1 : -1) /
                                                     (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                /* a = R^T a R, v = v R with R the (p, q) rotation */
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                a[p][q] = a[q][p] = 0;
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < 3; i++) {
        val[i] = a[i][i];
        for (int k = 0; k < 3; k++) vec[k * 3 + i] = v[k][i];
    }
}

/* Principal axes (rows, largest eigenvalue first, largest component of each
 * made positive so that the result is deterministic) and moments. */
static void principal(bvox_measures *m)
{
    double val[3], vec[9];
    jacobi3(m->covariance, val, vec);
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (val[order[j]] > val[order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    double trace = m->covariance[0] + m->covariance[4] + m->covariance[8];
    for (int i = 0; i < 3; i++) {
        int e = order[i];
        double *axis = &m->principal_axes[i * 3];
        int big = 0;
        for (int k = 0; k < 3; k++) {
            axis[k] = vec[k * 3 + e];
            if (fabs(axis[k]) > fabs(axis[big])) big = k;
        }
        if (axis[big] < 0)
            for (int k = 0; k < 3; k++) axis[k] = -axis[k];
        m->principal_moments[i] = val[e] > 0 ? val[e] : 0; /* rounding of a flat object */
        m->principal_inertia[i] = m->volume * (trace - m->principal_moments[i]);
    }
}

/* 26-components of vol and the cavities (measure_cavities.c, which takes
 * the object's voxel box and its faces along z from the scan sc, and the
 * columns' hulls from the scan too). */
static bvox_status topology(const bvox_volume *vol, const bvox__scan *sc,
                            const bvox__colhull *hulls, bvox_measures *m)
{
    bvox_status st = bvox__components_count(vol, 26, 0, &m->components);
    if (!st) st = bvox__progress(0.6);
    if (st) return st;
    if (sc->count == (int64_t)vol->nx * vol->ny * vol->nz) return BVOX_OK; /* no background */
    return bvox__measure_cavities(vol, sc, hulls, &m->cavities, &m->cavities_26);
}

/* topology() of a collapsed copy, with its own scan: its box, z faces and
 * hulls choose the cavities' route (a tenth of the volume's on the atlas). */
static bvox_status topology_of_copy(const bvox_volume *copy, bvox_measures *m)
{
    bvox_status st = BVOX_OK;
    size_t bytes = (size_t)copy->nx * (size_t)copy->ny * sizeof(bvox__colhull);
    bvox__colhull *own = bvox__alloc(bytes, false, "column hulls", &st);
    if (!own) return st;
    bvox__scan sc;
    st = bvox__measure_scan_hulls(copy, own, &sc);
    if (!st) st = topology(copy, &sc, own, m);
    bvox__free(own, bytes);
    return st;
}

bvox_status bvox__measure_topology(const bvox_volume *vol, const bvox__scan *sc,
                                   const bvox__colhull *hulls, bvox_measures *m,
                                   bvox_dims *labelled)
{
    bvox_volume *copy = NULL;
    bvox_status st = bvox__collapse_repeats(vol, sc->bbox, hulls, &copy);
    if (copy) {
        st = topology_of_copy(copy, m);
        if (!st && labelled) *labelled = bvox_volume_dims(copy);
        bvox_volume_destroy(copy);
        if (st != BVOX_ETOOBIG) return st;
    }
    if (st && st != BVOX_ETOOBIG) return st;
    if (st) {
        /* the copy's way can need more than the volume's own labelling (a
         * copy of three quarters of a volume): a saving of time, not worth
         * failing a measure over the memory budget */
        bvox__clear_error();
        m->components = m->cavities = m->cavities_26 = 0;
    }
    if (labelled) *labelled = bvox_volume_dims(vol);
    return topology(vol, sc, hulls, m);
}

void bvox__measure_from_scan(const bvox__scan *sc, const bvox_geometry *geom,
                             const double weight[BVOX__NDIR], const int32_t bbox_shift[3],
                             bvox_measures *out)
{
    bvox_measures m;
    memset(&m, 0, sizeof m);
    m.principal_axes[0] = m.principal_axes[4] = m.principal_axes[8] = 1;
    const bvox__scan s = *sc;
    const double *sp = geom->spacing, *org = geom->origin;
    m.count = s.count;
    m.volume = (double)s.count * sp[0] * sp[1] * sp[2];
    m.euler = s.euler;
    for (int a = 0; a < 3; a++) m.faces[a] = s.trans[a];
    m.area_faces = (double)s.trans[0] * sp[1] * sp[2] + (double)s.trans[1] * sp[0] * sp[2] +
                   (double)s.trans[2] * sp[0] * sp[1];
    for (int c = 0; c < BVOX__NDIR; c++) m.area += weight[c] * (double)s.trans[c];
    if (s.count) {
        const int32_t *b = s.bbox;
        int32_t sh[3] = {0, 0, 0};
        if (bbox_shift) memcpy(sh, bbox_shift, sizeof sh);
        m.bbox = (bvox_box){b[0] + sh[0], b[1] + sh[1], b[2] + sh[2],
                            b[3] + sh[0], b[4] + sh[1], b[5] + sh[2]};
        double n = (double)s.count;
        for (int a = 0; a < 3; a++) {
            m.extent_min[a] = org[a] + (b[a] - 0.5) * sp[a];
            m.extent_max[a] = org[a] + (b[a + 3] - 0.5) * sp[a];
            m.centroid[a] = org[a] + sp[a] * ((double)s.s[a] / n);
        }
        /* ss order: xx yy zz xy xz yz */
        static const int pair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
        for (int k = 0; k < 6; k++) {
            int i = pair[k][0], j = pair[k][1];
            bvox__wide num = (bvox__wide)s.count * s.ss[k] - s.s[i] * s.s[j];
            double c = (double)num / n / n * sp[i] * sp[j];
            m.covariance[i * 3 + j] = m.covariance[j * 3 + i] = c;
        }
        double trace = m.covariance[0] + m.covariance[4] + m.covariance[8];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                m.inertia[i * 3 + j] = m.volume * ((i == j ? trace : 0) - m.covariance[i * 3 + j]);
        principal(&m);
        m.equivalent_diameter = cbrt(6 * m.volume / M_PI);
        if (s.count < BVOX_SPHERICITY_MIN_VOXELS) {
            m.sphericity = NAN;
        } else if (m.area > 0) {
            m.sphericity = cbrt(M_PI) * pow(6 * m.volume, 2.0 / 3.0) / m.area;
            if (m.sphericity > 1) m.sphericity = 1;
        }
    }
    *out = m;
}

bvox_status bvox__measure_with(const bvox_volume *vol, const double weight[BVOX__NDIR],
                               const int32_t bbox_shift[3], bvox_measures *out)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__scan s;
    bvox_status st = BVOX_OK;
    size_t hull_bytes = (size_t)vol->nx * (size_t)vol->ny * sizeof(bvox__colhull);
    bvox__colhull *hulls = bvox__alloc(hull_bytes, false, "column hulls", &st);
    if (!hulls) return st;
    st = bvox__measure_scan_hulls(vol, hulls, &s);
    if (!st) st = bvox__progress(0.4); /* then the labellings of topology() */
    bvox_measures m;
    if (!st) {
        bvox__measure_from_scan(&s, &vol->geom, weight, bbox_shift, &m);
        if (s.count) st = bvox__measure_topology(vol, &s, hulls, &m, NULL);
    }
    bvox__free(hulls, hull_bytes);
    if (st) return st;
    m.tunnels = m.components + m.cavities - m.euler;
    *out = m;
    return BVOX_OK;
}

bvox_status bvox_measure(const bvox_volume *vol, bvox_measures *out)
{
    memset(out, 0, sizeof *out);
    bvox__clear_error();
    double weight[BVOX__NDIR];
    bvox__crofton_weights(vol->geom.spacing, weight);
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "measure");
    return bvox__progress_end(&ps, bvox__measure_with(vol, weight, NULL, out));
}
