/*
 * bench_manip.c — speed of the manipulation and measurement operations on
 * n^3 volumes: union with an offset (against a memcpy of the same words, in
 * the same run, with the same threads), dilation by the 26-neighbourhood and
 * by balls of radius 3 and 10 voxels, 26-connected labelling, the full measures
 * and a plane cut, each against a naive byte-per-voxel reference
 * (manip_ref.h, tests/ref/voxref.h) whose result must agree.
 * Two specimens: "aal", the AAL brain atlas of mricron-data read --nonzero
 * and resampled by nearest neighbour to n^3 (a real, smooth object; skipped
 * with a note when the file is missing), and "random" (every voxel a coin
 * toss). One JSON line per case; bench/README.md explains every key.
 *
 *   bench_manip [--quick] [--sizes 256,512] [--runs N] [--threads T | --threads-list L]
 *               [--no-ref] [--save DIR]
 *
 * --save DIR writes each specimen as DIR/<pattern>_<n>.nii (uint8 0/1) for
 * bench/compare_scipy.py.
 */
#include "internal.h"
#include "bench_util.h"
#include "manip_ref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define AAL_PATH "/usr/share/mricron/templates/aal.nii.gz"

typedef struct options {
    int runs, threads, ref, nsizes;
    int sizes[8];
    const char *save;
    thread_list tl;         /* --threads-list (or --threads): the lines repeat per count */
    const char *no_ref_why; /* why the reference is off, when it is */
} options;

/* The reference is slow: one run, no warm-up. */
#define TIME_ONCE(stmt)                                                                \
    ({                                                                                 \
        double s_ = now_ms();                                                          \
        stmt;                                                                          \
        now_ms() - s_;                                                                 \
    })

/* ---- specimens ---- */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint64_t rnd(void)
{
    uint64_t x = rng_state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return rng_state = x;
}

static bvox_volume *make_random(int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    for (size_t i = 0; i < v->nwords; i++) v->words[i] = rnd();
    for (size_t c = v->wpc - 1; c < v->nwords; c += v->wpc) v->words[c] &= v->tail_mask;
    return v;
}


/* The same voxels one byte each, unpacked a column word at a time. */
static voxref *to_ref(const bvox_volume *v)
{
    voxref *r = voxref_create(v->nx, v->ny, v->nz);
    if (!r) return NULL;
    size_t plane = (size_t)v->nx * (size_t)v->ny;
    for (size_t k = 0; k < v->wpc; k++) {
        int zn = v->nz - (int)k * 64 < 64 ? v->nz - (int)k * 64 : 64;
        for (size_t col = 0; col < plane; col++) {
            uint64_t w = v->words[col * v->wpc + k];
            uint8_t *dst = r->v + (k * 64) * plane + col;
            for (int b = 0; b < zn; b++) dst[(size_t)b * plane] = (uint8_t)((w >> b) & 1);
        }
    }
    return r;
}

/* 1 if vol holds exactly the voxels of r. */
static int same(const bvox_volume *vol, const voxref *r)
{
    voxref *c = to_ref(vol);
    int eq = c && memcmp(c->v, r->v, (size_t)r->nx * r->ny * r->nz) == 0;
    voxref_destroy(c);
    return eq;
}

/* ---- output ---- */

typedef struct result {
    const char *op, *pattern;
    int n, threads, runs;
    double ms, ref_ms; /* ref_ms < 0: none */
    int agree;         /* -1: not checked */
    char extra[512];   /* more "key":value pairs, each with a leading comma */
} result;

static void print(const result *r, const char *ref_note)
{
    double vox = (double)r->n * r->n * r->n;
    printf("{\"bench\":\"manip\",\"op\":\"%s\",\"n\":%d,\"pattern\":\"%s\",\"threads\":%d,"
           "\"runs\":%d,\"ms\":%.3f,\"Mvoxps\":%.1f",
           r->op, r->n, r->pattern, r->threads, r->runs, r->ms, vox / (r->ms * 1e3));
    if (r->ref_ms >= 0)
        printf(",\"ref_ms\":%.1f,\"speedup_ref\":%.1f,\"agree\":%s", r->ref_ms, r->ref_ms / r->ms,
               r->agree ? "true" : "false");
    else printf(",\"ref_ms\":null,\"speedup_ref\":null,\"ref_note\":\"%s\"", ref_note);
    printf("%s}\n", r->extra);
    fflush(stdout);
}

/* ---- the cases ---- */

static volatile int64_t sink;

static void bench_specimen(const options *o, const char *pattern, int n, bvox_volume *a)
{
    const char *note = o->ref ? NULL : o->no_ref_why;
    voxref *ra = o->ref ? to_ref(a) : NULL;
    voxref *rr = o->ref ? voxref_create(n, n, n) : NULL;
    if (o->ref && (!ra || !rr)) note = "reference skipped: allocation failed";
    int ref = note == NULL;
    result r = {.pattern = pattern, .n = n, .threads = o->threads, .runs = o->runs};
    size_t bytes = a->nwords * sizeof(uint64_t);
    bvox_volume *b = NULL, *d = NULL, *out = NULL;
    if (bvox_volume_copy(a, &b) || bvox_volume_copy(a, &d)) {
        fprintf(stderr, "bench_manip: %s\n", bvox_errmsg());
        exit(1);
    }

    /* memcpy of one volume's words: read + write */
    double mc_ms = TIME_MEDIAN(o->runs,
                               parallel_memcpy(d->words, a->words, bytes, o->threads));
    double mc_gbps = 2.0 * (double)bytes / (mc_ms * 1e6);
    r.op = "memcpy";
    r.ms = mc_ms;
    r.ref_ms = -1;
    snprintf(r.extra, sizeof r.extra, ",\"bytes\":%zu,\"GBps\":%.2f", 2 * bytes, mc_gbps);
    print(&r, "none: this is the baseline");

    /* union with an offset: reads dst and src, writes dst (3 streams) */
    const int32_t off[3] = {3, 5, 7};
    const int ioff[3] = {3, 5, 7};
    r.op = "union_offset";
    r.ms = TIME_MEDIAN(o->runs, bvox_csg_apply(d, BVOX_CSG_UNION, b, off));
    r.ref_ms = -1;
    if (ref) {
        memcpy(rr->v, ra->v, (size_t)n * n * n);
        r.ref_ms = TIME_ONCE(voxref_csg(rr, BVOX_CSG_UNION, ra, ioff));
        r.agree = same(d, rr);
    }
    double gbps = 3.0 * (double)bytes / (r.ms * 1e6);
    snprintf(r.extra, sizeof r.extra,
             ",\"offset\":[3,5,7],\"bytes\":%zu,\"GBps\":%.2f,\"memcpy_ms\":%.3f,"
             "\"memcpy_GBps\":%.2f,\"ratio_memcpy\":%.3f,\"time_ratio_memcpy\":%.3f",
             3 * bytes, gbps, mc_ms, mc_gbps, gbps / mc_gbps, mc_ms / r.ms);
    print(&r, note);

    /* dilation: the 26-neighbourhood, and balls of radius 3 and 10 voxels
     * (ratio_dilate26: the ball's time over the 26-neighbourhood's) */
    static ref_offset offs[8192];
    static const double ball_r[3] = {0, 3.0, 10.0};
    static const char *const ball_op[3] = {"dilate26", "dilate_ball3", "dilate_ball10"};
    double d26_ms = 0;
    for (int ball = 0; ball <= 2; ball++) {
        r.op = ball_op[ball];
        r.ms = TIME_MEDIAN_PREP(o->runs, (bvox_volume_destroy(out), out = NULL),
                           ball ? bvox_morph_dilate_ball(a, ball_r[ball], &out)
                                : bvox_morph_dilate(a, 26, &out));
        if (!ball) d26_ms = r.ms;
        r.ref_ms = -1;
        /* radius 10 is 4169 offsets per voxel: the reference only on small cubes */
        int ref_here = ref && (ball < 2 || n <= 96);
        if (ref_here) {
            int k = ref_offsets(!ball, ball ? ball_r[ball] : 3.0, offs);
            r.ref_ms = TIME_ONCE(ref_dilate(ra, offs, k, rr));
            r.agree = same(out, rr);
        }
        int m = snprintf(r.extra, sizeof r.extra, ",\"count_in\":%lld,\"count_out\":%lld",
                         (long long)bvox_volume_count(a), (long long)bvox_volume_count(out));
        if (ball)
            snprintf(r.extra + m, sizeof r.extra - (size_t)m, ",\"ratio_dilate26\":%.2f",
                     r.ms / d26_ms);
        bvox_volume_destroy(out);
        out = NULL;
        print(&r, ref_here || !ref ? note : "reference of radius 10 only up to 96^3 (4169 offsets per voxel)");
    }

    /* 26-connected components */
    bvox_components *comps = NULL;
    r.op = "label26";
    r.ms = TIME_MEDIAN_PREP(o->runs, (bvox_components_destroy(comps), comps = NULL),
                       bvox_components_find(a, 26, &comps));
    int64_t ncomp = comps ? bvox_components_count(comps) : -1;
    bvox_components_destroy(comps);
    r.ref_ms = -1;
    if (ref) {
        int32_t *parent = malloc((size_t)n * n * n * sizeof *parent);
        if (parent) {
            int64_t k = 0;
            r.ref_ms = TIME_ONCE(k = ref_label26(ra, parent));
            r.agree = k == ncomp;
            free(parent);
        }
    }
    snprintf(r.extra, sizeof r.extra, ",\"components\":%lld", (long long)ncomp);
    print(&r, note);

    /* the full measures (area, moments, topology: two labellings) */
    bvox_measures m;
    r.op = "measure";
    r.ms = TIME_MEDIAN(o->runs, bvox_measure(a, &m));
    r.ref_ms = -1;
    if (ref) {
        ref_measures rm;
        r.ref_ms = TIME_ONCE(ref_measure(ra, &rm));
        r.agree = rm.count == m.count && rm.faces[0] == m.faces[0] &&
                  rm.faces[1] == m.faces[1] && rm.faces[2] == m.faces[2];
        for (int k = 0; k < 3; k++)
            r.agree = r.agree && fabs(rm.centroid[k] - m.centroid[k]) < 1e-6 * n;
    }
    snprintf(r.extra, sizeof r.extra,
             ",\"ref_covers\":\"count, faces, centroid, covariance (not area, topology)\","
             "\"components\":%lld,\"euler\":%lld",
             (long long)m.components, (long long)m.euler);
    print(&r, note);

    /* a plane cut through the centre, normal (1, 2, 3): in place, so each
     * run starts from a fresh copy (not timed) */
    double pd = -3.0 * (n - 1);
    r.op = "cut_plane";
    r.ms = TIME_MEDIAN_PREP(o->runs, memcpy(d->words, a->words, bytes),
                       bvox_cut_plane(d, 1, 2, 3, pd, 1, NULL));
    r.ref_ms = -1;
    if (ref) {
        memcpy(rr->v, ra->v, (size_t)n * n * n);
        r.ref_ms = TIME_ONCE(ref_cut_plane(rr, 1, 2, 3, pd));
        r.agree = same(d, rr);
    }
    snprintf(r.extra, sizeof r.extra, ",\"plane\":[1,2,3,%g]", pd);
    print(&r, note);

    bvox_volume_destroy(b);
    bvox_volume_destroy(d);
    voxref_destroy(ra);
    voxref_destroy(rr);
}

static void usage(void)
{
    fprintf(stderr, "usage: bench_manip [--quick] [--sizes 256,512] [--runs N] "
                    "[--threads T | --threads-list 1,2,4,8,16] [--no-ref] [--save DIR]\n");
    exit(2);
}

static void parse(int argc, char **argv, options *o)
{
    *o = (options){5, bvox_threads(), 1, 2, {256, 512}, NULL, thread_list_default(),
                   "reference disabled (--no-ref)"};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quick")) {
            o->runs = 2;
            o->nsizes = 2;
            o->sizes[0] = 40;
            o->sizes[1] = 70;
        } else if (!strcmp(a, "--no-ref")) {
            o->ref = 0;
        } else if (!strcmp(a, "--runs") && v) {
            o->runs = atoi(v), i++;
        } else if (!strcmp(a, "--threads") && v) {
            o->threads = atoi(v), i++;
            o->tl = (thread_list){1, {o->threads}};
        } else if (!strcmp(a, "--threads-list") && v) {
            if (!thread_list_parse(argv[++i], &o->tl)) usage();
        } else if (!strcmp(a, "--save") && v) {
            o->save = v, i++;
        } else if (!strcmp(a, "--sizes") && v) {
            if (!parse_size_list(argv[++i], o->sizes, 8, &o->nsizes)) usage();
        } else {
            usage();
        }
    }
    if (o->runs < 1 || o->threads < 1 || o->nsizes < 1) usage();
    for (int i = 0; i < o->nsizes; i++)
        if (o->sizes[i] < 8 || o->sizes[i] > 2048) usage();
}

int main(int argc, char **argv)
{
    options o;
    parse(argc, argv, &o);
    bvox_volume *aal = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT; /* --nonzero: every labelled region */
    const char *aal_note = NULL;
    if (bvox_read(AAL_PATH, &ro, &aal) != BVOX_OK)
        aal_note = "skipped: " AAL_PATH " is missing or unreadable (install mricron-data)";
    for (int si = 0; si < o.nsizes; si++) {
        int n = o.sizes[si];
        for (int p = 0; p < 2; p++) {
            const char *pattern = p ? "random" : "aal";
            if (!p && !aal) {
                printf("{\"bench\":\"manip\",\"n\":%d,\"pattern\":\"aal\",\"skipped\":\"%s\"}\n",
                       n, aal_note);
                continue;
            }
            bvox_volume *a = p ? make_random(n) : resample(aal, n);
            if (!a) {
                fprintf(stderr, "bench_manip: cannot make %s at %d^3: %s\n", pattern, n,
                        bvox_errmsg());
                return 1;
            }
            if (o.save) {
                char path[4096];
                snprintf(path, sizeof path, "%s/%s_%d.nii", o.save, pattern, n);
                if (bvox_write(path, a, NULL) != BVOX_OK) {
                    fprintf(stderr, "bench_manip: %s\n", bvox_errmsg());
                    return 1;
                }
            }
            for (int ti = 0; ti < o.tl.n; ti++) { /* the slow reference once */
                options ot = o;
                ot.threads = o.tl.t[ti];
                if (ti && o.ref) {
                    ot.ref = 0;
                    ot.no_ref_why = "reference timed on the first thread count's line only";
                }
                bvox_set_threads(ot.threads);
                bench_specimen(&ot, pattern, n, a);
            }
            bvox_volume_destroy(a);
        }
    }
    bvox_volume_destroy(aal);
    return 0;
}
