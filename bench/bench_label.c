/*
 * bench_label.c — 26-connected labelling (bvox_components_find) and the full
 * measures (bvox_measure: scan, components, cavities) of the same volume,
 * with their ratio, the "measure <= 1.3 x one labelling". Two
 * specimens as in bench_manip: the AAL atlas resampled to n^3 (skipped with
 * a note when mricron-data is missing) and a coin toss per voxel. Besides the
 * wall-clock median (ms) each line has the median process CPU time per call
 * (cpu_ms, all threads): on a shared machine the wall clock also counts the
 * time other processes hold the cores, the CPU time much less so. The
 * measure's three parts are also timed alone (wall ms): scan_ms (the one
 * pass: counts, moments, Euler number, faces), collapse_ms (the copy
 * without repeated slices, when that pays, and its scan: measure_collapse.c;
 * "labelled" gives the x by y columns counted on, the copy's or the
 * volume's), components_ms (the 26-count) and cavities_ms
 * (measure_cavities.c, its route chosen as in bvox_measure), both on what
 * "labelled" says. A
 * third specimen has no repeated slices: a sphere of radius 0.39 n at
 * native resolution, a torus-shaped cavity inside.
 *
 *   bench_label [--quick] [--sizes 512] [--runs N] [--threads-list L]
 */
#include "bench_util.h"
#include "measure/measure.h"

#include <stdio.h>

#define AAL_PATH "/usr/share/mricron/templates/aal.nii.gz"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static bvox_volume *coin_toss(int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    for (size_t i = 0; i < v->nwords; i++) {
        rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
        v->words[i] = rng;
    }
    for (size_t c = v->wpc - 1; c < v->nwords; c += v->wpc) v->words[c] &= v->tail_mask;
    return v;
}

/* Median wall and CPU ms of runs calls of stmt, after one warm-up call. */
#define TIME_BOTH(runs, wall, cpu, stmt)                                               \
    do {                                                                               \
        double w_[64], c_[64];                                                         \
        int n_ = (runs) > 64 ? 64 : (runs);                                            \
        stmt;                                                                          \
        for (int i_ = 0; i_ < n_; i_++) {                                              \
            double s_ = now_ms(), u_ = cpu_ms();                                       \
            stmt;                                                                      \
            w_[i_] = now_ms() - s_;                                                    \
            c_[i_] = cpu_ms() - u_;                                                    \
        }                                                                              \
        wall = median(w_, n_);                                                         \
        cpu = median(c_, n_);                                                          \
    } while (0)

static bvox_volume *sphere_with_cavity(int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    double c = (n - 1) / 2.0;
    bvox_shape ball = {BVOX_SHAPE_SPHERE, {c, c, c}, {0}, {0}, 0.39 * n, 0, 0};
    bvox_shape ring = {BVOX_SHAPE_TORUS, {c, c, c}, {0}, {0, 0, 1}, 0.2 * n, 0.06 * n, 0};
    if (bvox_shape_draw(v, &ball, BVOX_CSG_UNION) ||
        bvox_shape_draw(v, &ring, BVOX_CSG_DIFFERENCE)) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

static int bench_one(const char *pattern, int n, const bvox_volume *a, int runs)
{
    bvox_components *c = NULL;
    int bad = 0;
    double lw, lc, mw, mc;
    TIME_BOTH(runs, lw, lc, {
        bvox_components_destroy(c);
        c = NULL;
        bad |= bvox_components_find(a, 26, &c) != BVOX_OK;
    });
    int64_t ncomp = c ? bvox_components_count(c) : -1;
    bvox_components_destroy(c);
    bvox_measures m;
    TIME_BOTH(runs, mw, mc, bad |= bvox_measure(a, &m) != BVOX_OK);
    bvox__scan sc;
    int64_t count = 0, cav6 = 0, cav26 = 0;
    double sw, sc_cpu, xw = 0, xc, kw = 0, kc, cw = 0, cc;
    /* the scan as bvox_measure runs it: with the columns' hulls */
    size_t nhull = (size_t)a->nx * (size_t)a->ny;
    bvox__colhull *hulls = calloc(nhull, sizeof *hulls), *own = NULL;
    if (!hulls) return 1;
    TIME_BOTH(runs, sw, sc_cpu, bad |= bvox__measure_scan_hulls(a, hulls, &sc) != BVOX_OK);
    /* the topology's steps as bvox__measure_topology takes them: the copy
     * without repeated slices and its scan, then the counts on it */
    bvox_volume *copy = NULL;
    bvox__scan csc = sc;
    const bvox__colhull *th = hulls;
    if (!bad && sc.count) {
        TIME_BOTH(runs, xw, xc, {
            bvox_volume_destroy(copy);
            free(own);
            copy = NULL;
            own = NULL;
            bad |= bvox__collapse_repeats(a, sc.bbox, hulls, &copy) != BVOX_OK;
            if (copy && (own = calloc((size_t)copy->nx * (size_t)copy->ny, sizeof *own)))
                bad |= bvox__measure_scan_hulls(copy, own, &csc) != BVOX_OK;
        });
    }
    const bvox_volume *t = copy ? copy : a;
    if (copy) th = own;
    bad |= copy && !own;
    if (!bad && sc.count) {
        TIME_BOTH(runs, kw, kc, bad |= bvox__components_count(t, 26, 0, &count) != BVOX_OK);
        TIME_BOTH(runs, cw, cc, bad |= bvox__measure_cavities(t, &csc, th, &cav6, &cav26) != BVOX_OK);
    }
    bvox_dims kept = bvox_volume_dims(t);
    if (copy) free(own);
    bvox_volume_destroy(copy);
    free(hulls);
    (void)sc_cpu, (void)xc, (void)kc, (void)cc;
    if (!bad && (count != m.components || cav6 != m.cavities || cav26 != m.cavities_26)) {
        fprintf(stderr, "bench_label: measure's parts alone disagree with bvox_measure\n");
        return 1;
    }
    if (bad) {
        fprintf(stderr, "bench_label: %s\n", bvox_errmsg());
        return 1;
    }
    printf("{\"bench\":\"label\",\"n\":%d,\"pattern\":\"%s\",\"threads\":%d,\"runs\":%d,"
           "\"label26_ms\":%.3f,\"label26_cpu_ms\":%.3f,\"measure_ms\":%.3f,"
           "\"measure_cpu_ms\":%.3f,\"ratio\":%.2f,\"ratio_cpu\":%.2f,\"components\":%lld,"
           "\"cavities\":%lld,\"cavities_26\":%lld,\"euler\":%lld,\"scan_ms\":%.3f,"
           "\"collapse_ms\":%.3f,\"components_ms\":%.3f,\"cavities_ms\":%.3f,"
           "\"labelled\":\"%dx%d\"}\n",
           n, pattern, bvox_threads(), runs, lw, lc, mw, mc, mw / lw, mc / lc,
           (long long)ncomp, (long long)m.cavities, (long long)m.cavities_26,
           (long long)m.euler, sw, xw, kw, cw, kept.nx, kept.ny);
    return 0;
}

static int bench_main(int argc, char **argv)
{
    int runs = 7, sizes[8] = {512}, nsizes = 1;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) runs = 2, sizes[0] = 40, sizes[1] = 70, nsizes = 2;
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) {
            if (!parse_size_list(argv[++i], sizes, 8, &nsizes)) nsizes = 0;
        } else nsizes = 0;
        if (!nsizes) break;
    }
    for (int i = 0; i < nsizes; i++)
        if (sizes[i] < 8 || sizes[i] > 2048) nsizes = 0;
    if (nsizes < 1 || runs < 1) {
        fprintf(stderr, "usage: bench_label [--quick] [--sizes 512] [--runs N] "
                        "[--threads-list 1,2,16]\n");
        return 2;
    }
    rng = 0x9e3779b97f4a7c15ull; /* the same coin tosses at every thread count */
    bvox_volume *aal = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    if (bvox_read(AAL_PATH, &ro, &aal) != BVOX_OK) aal = NULL;
    int rc = 0;
    for (int i = 0; i < nsizes && !rc; i++) {
        int n = sizes[i];
        if (!aal) {
            printf("{\"bench\":\"label\",\"n\":%d,\"pattern\":\"aal\",\"threads\":%d,\"skipped\":"
                   "\"" AAL_PATH " is missing (install mricron-data)\"}\n",
                   n, bvox_threads());
        } else {
            bvox_volume *a = resample(aal, n);
            rc = a ? bench_one("aal", n, a, runs) : 1;
            bvox_volume_destroy(a);
        }
        if (rc) break;
        bvox_volume *r = coin_toss(n);
        rc = r ? bench_one("random", n, r, runs) : 1;
        bvox_volume_destroy(r);
        if (rc) break;
        bvox_volume *sp = sphere_with_cavity(n);
        rc = sp ? bench_one("sphere", n, sp, runs) : 1;
        bvox_volume_destroy(sp);
    }
    bvox_volume_destroy(aal);
    return rc;
}

int main(int argc, char **argv) { return run_threads_list(argc, argv, bench_main, "bench_label"); }
