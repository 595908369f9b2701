/*
 * bench_ops.c — speed of the whole-word operations (count, union,
 * intersection, difference, complement) on n^3 volumes, against the memory
 * system (a memcpy of the same words, in the same run, with the same number
 * of threads) and against the byte-per-voxel reference of tests/ref.
 * One JSON line per case; bench/README.md explains every key.
 *
 *   bench_ops [--quick] [--runs N] [--sizes 256,512,1024] [--threads T | --threads-list L]
 *             [--simd generic|avx2|avx512] [--no-ref]
 */
#include "internal.h"
#include "bench_util.h"
#include "ref/voxref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { OP_COUNT, OP_UNION, OP_INTERSECTION, OP_DIFFERENCE, OP_COMPLEMENT, NOPS };
static const char *const op_names[NOPS] = {"count", "union", "intersection", "difference",
                                           "complement"};
/* streams of nwords*8 bytes each operation moves: reads + writes */
static const int op_streams[NOPS] = {1, 3, 3, 3, 2};

typedef struct options {
    int runs, threads, ref, nsizes;
    int sizes[8];
    int simd; /* -1: every supported level */
    thread_list tl; /* --threads-list (or --threads): the lines repeat per count */
} options;

static uint64_t rng_state = 0x243f6a8885a308d3ull;
static uint64_t rnd(void)
{
    uint64_t x = rng_state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return rng_state = x;
}

/* ---- specimens ---- */

/* random: every bit a coin toss; blocky: overlapping boxes and spheres (long
 * runs of equal words, as real segmentations have) */
static bvox_volume *make_volume(int n, int blocky)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    if (!blocky) {
        for (size_t i = 0; i < v->nwords; i++) v->words[i] = rnd();
        for (size_t c = v->wpc - 1; c < v->nwords; c += v->wpc) v->words[c] &= v->tail_mask;
        return v;
    }
    for (int i = 0; i < 24; i++) {
        int32_t c[3], h[3];
        for (int a = 0; a < 3; a++) {
            c[a] = (int32_t)(rnd() % (uint64_t)n);
            h[a] = (int32_t)(rnd() % (uint64_t)(n / 4 + 1)) + 1;
        }
        bvox_volume_fill_box(v, (bvox_box){c[0] - h[0], c[1] - h[1], c[2] - h[2],
                                           c[0] + h[0], c[1] + h[1], c[2] + h[2]},
                             (int)(rnd() % 3 != 0));
    }
    for (int i = 0; i < 8; i++) {
        bvox_shape s = {BVOX_SHAPE_SPHERE, {0}, {0}, {0}, 0, 0, 0};
        for (int a = 0; a < 3; a++) s.center[a] = (double)(rnd() % (uint64_t)n);
        s.radius = (double)(rnd() % (uint64_t)(n / 4 + 1)) + 2;
        bvox_shape_draw(v, &s, BVOX_CSG_XOR);
    }
    return v;
}

/* The same voxels one byte each. Unpacks 64 slices per column word so that
 * the writes stay sequential along x (a voxel-at-a-time copy through
 * bvox_volume_get would take minutes at 1024^3). */
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

static volatile int64_t sink; /* keeps the counts from being optimised away */

static void run_op(int op, bvox_volume *a, const bvox_volume *b, bvox_volume *d)
{
    switch (op) {
    case OP_COUNT: sink += bvox_volume_count(a); break;
    case OP_UNION: bvox_csg_apply(d, BVOX_CSG_UNION, b, NULL); break;
    case OP_INTERSECTION: bvox_csg_apply(d, BVOX_CSG_INTERSECTION, b, NULL); break;
    case OP_DIFFERENCE: bvox_csg_apply(d, BVOX_CSG_DIFFERENCE, b, NULL); break;
    case OP_COMPLEMENT: bvox_volume_complement(d); break;
    }
}

static void run_ref(int op, voxref *ra, const voxref *rb)
{
    static const int zero[3] = {0, 0, 0};
    switch (op) {
    case OP_COUNT: sink += voxref_count(ra); break;
    case OP_UNION: voxref_csg(ra, BVOX_CSG_UNION, rb, zero); break;
    case OP_INTERSECTION: voxref_csg(ra, BVOX_CSG_INTERSECTION, rb, zero); break;
    case OP_DIFFERENCE: voxref_csg(ra, BVOX_CSG_DIFFERENCE, rb, zero); break;
    case OP_COMPLEMENT: voxref_complement(ra); break;
    }
}

/* Reference timings for one specimen, or a reason why there are none. */
static const char *time_reference(const options *o, int n, const bvox_volume *a,
                                  const bvox_volume *b, double ref_ms[NOPS])
{
    for (int op = 0; op < NOPS; op++) ref_ms[op] = -1;
    if (!o->ref) return "reference disabled (--no-ref)";
    double need = 2.0 * n * n * n + (512.0 * (1 << 20));
    double avail = (double)sysconf(_SC_AVPHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
    if (avail < need) return "reference skipped: not enough free memory for 2 byte volumes";
    voxref *ra = to_ref(a), *rb = to_ref(b);
    if (!ra || !rb) {
        voxref_destroy(ra);
        voxref_destroy(rb);
        return "reference skipped: allocation failed";
    }
    if (voxref_count(ra) != bvox_volume_count(a)) {
        fprintf(stderr, "bench_ops: reference count disagrees with bvox at n=%d\n", n);
        exit(1);
    }
    /* the reference is slow: fewer runs, and no warm-up at the largest sizes */
    int runs = n >= 1024 ? 1 : (o->runs < 3 ? o->runs : 3);
    for (int op = 0; op < NOPS; op++) {
        if (n >= 1024) {
            double s = now_ms();
            run_ref(op, ra, rb);
            ref_ms[op] = now_ms() - s;
        } else {
            ref_ms[op] = TIME_MEDIAN(runs, run_ref(op, ra, rb));
        }
    }
    voxref_destroy(ra);
    voxref_destroy(rb);
    return NULL;
}

static void usage(void)
{
    fprintf(stderr, "usage: bench_ops [--quick] [--runs N] [--sizes 256,512,1024] "
                    "[--threads T | --threads-list 1,2,4,8,16] [--simd generic|avx2|avx512] "
                    "[--no-ref]\n");
    exit(2);
}

static void parse(int argc, char **argv, options *o)
{
    *o = (options){7, bvox_threads(), 1, 3, {256, 512, 1024}, -1, thread_list_default()};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quick")) {
            o->runs = 3;
            o->nsizes = 2;
            o->sizes[0] = 64;
            o->sizes[1] = 96;
        } else if (!strcmp(a, "--no-ref")) {
            o->ref = 0;
        } else if (!strcmp(a, "--runs") && v) {
            o->runs = atoi(v), i++;
        } else if (!strcmp(a, "--threads") && v) {
            o->threads = atoi(v), i++;
            o->tl = (thread_list){1, {o->threads}};
        } else if (!strcmp(a, "--threads-list") && v) {
            if (!thread_list_parse(argv[++i], &o->tl)) usage();
        } else if (!strcmp(a, "--simd") && v) {
            o->simd = !strcmp(v, "generic") ? BVOX_SIMD_GENERIC
                      : !strcmp(v, "avx2")  ? BVOX_SIMD_AVX2
                      : !strcmp(v, "avx512") ? BVOX_SIMD_AVX512
                                             : -2;
            if (o->simd == -2) usage();
            i++;
        } else if (!strcmp(a, "--sizes") && v) {
            if (!parse_size_list(argv[++i], o->sizes, 8, &o->nsizes)) usage();
        } else {
            usage();
        }
    }
    if (o->runs < 1 || o->threads < 1 || o->nsizes < 1) usage();
    for (int i = 0; i < o->nsizes; i++)
        if (o->sizes[i] < 8 || o->sizes[i] > 4096) usage();
}

int main(int argc, char **argv)
{
    options o;
    parse(argc, argv, &o);
    static const char *const patterns[2] = {"random", "blocky"};
    for (int si = 0; si < o.nsizes; si++) {
        int n = o.sizes[si];
        for (int p = 0; p < 2; p++) {
            bvox_volume *a = make_volume(n, p), *b = make_volume(n, p), *d = NULL;
            if (!a || !b || bvox_volume_copy(a, &d) != BVOX_OK) {
                fprintf(stderr, "bench_ops: cannot allocate %d^3 volumes: %s\n", n,
                        bvox_errmsg());
                return 1;
            }
            size_t bytes = a->nwords * sizeof(uint64_t);
            double ref_ms[NOPS];
            const char *ref_note = time_reference(&o, n, a, b, ref_ms);
            for (int ti = 0; ti < o.tl.n; ti++) {
                const int threads = o.tl.t[ti];
                bvox_set_threads(threads);
                /* memcpy of one volume's words: bytes read + bytes written */
                double mc_ms = TIME_MEDIAN(o.runs, parallel_memcpy(d->words, a->words, bytes,
                                                                   threads));
                double mc1_ms = TIME_MEDIAN(o.runs, parallel_memcpy(d->words, a->words, bytes, 1));
                double mc_gbps = 2.0 * (double)bytes / (mc_ms * 1e6);
                printf("{\"bench\":\"ops\",\"op\":\"memcpy\",\"n\":%d,\"pattern\":\"%s\","
                       "\"threads\":%d,\"runs\":%d,\"ms\":%.3f,\"bytes\":%zu,\"GBps\":%.2f,"
                       "\"GBps_1thread\":%.2f}\n",
                       n, patterns[p], threads, o.runs, mc_ms, 2 * bytes, mc_gbps,
                       2.0 * (double)bytes / (mc1_ms * 1e6));
                fflush(stdout);
                for (int lv = BVOX_SIMD_GENERIC; lv <= BVOX_SIMD_AVX512; lv++) {
                    if ((o.simd >= 0 && lv != o.simd) || !bvox_simd_supported((bvox_simd)lv))
                        continue;
                    bvox_simd_set((bvox_simd)lv);
                    for (int op = 0; op < NOPS; op++) {
                        memcpy(d->words, a->words, bytes);
                        double ms = TIME_MEDIAN(o.runs, run_op(op, a, b, d));
                        double moved = (double)op_streams[op] * (double)bytes;
                        double gbps = moved / (ms * 1e6);
                        printf("{\"bench\":\"ops\",\"op\":\"%s\",\"n\":%d,\"pattern\":\"%s\","
                               "\"simd\":\"%s\",\"threads\":%d,\"runs\":%d,\"ms\":%.3f,"
                               "\"bytes\":%.0f,\"GBps\":%.2f,\"memcpy_GBps\":%.2f,"
                               "\"ratio_memcpy\":%.3f,",
                               op_names[op], n, patterns[p], bvox_simd_name((bvox_simd)lv),
                               threads, o.runs, ms, moved, gbps, mc_gbps, gbps / mc_gbps);
                        if (ref_note)
                            printf("\"ref_ms\":null,\"speedup_ref\":null,\"ref_note\":\"%s\"}\n",
                                   ref_note);
                        else
                            printf("\"ref_ms\":%.3f,\"speedup_ref\":%.1f}\n", ref_ms[op],
                                   ref_ms[op] / ms);
                        fflush(stdout);
                    }
                }
            }
            bvox_volume_destroy(a);
            bvox_volume_destroy(b);
            bvox_volume_destroy(d);
        }
    }
    return 0;
}
