/* bench_binarize.c — speed of gray -> binary (bvox__binarize) and binary ->
 * bytes (bvox__unpack_slices), one JSON line per case:
 *   {"bench":"binarize","case":"u8_512","mb_per_s":...,"median_ms":...,...}
 * mb_per_s counts the gray bytes read (binarize) or the bytes written
 * (unpack), in 10^6 bytes per second. Cases (names carry the cube side):
 * 512^3 u8 and 256^3 f32 with all threads and with one ("_1t"), per SIMD
 * path (suffix, none for the default path), Otsu on the u8 volume, 512^3
 * unpack (see below), and a naive per-voxel binarize (double arithmetic,
 * bvox_volume_set per voxel) for comparison, checked equal to the fast one.
 * Extra keys: threads, simd (the path used). Times are medians of the runs
 * after one untimed warm-up run.
 *   bench_binarize [--quick] [--runs N] [--threads-list 1,2,4,8,16]
 *   (--quick: 64^3 u8 and 32^3 f32, 3 runs; --threads-list: the threaded
 *   cases once per count instead of all threads and "_1t")
 * Needs src/ on the include path (private interface io/io.h). */
#include "io/io.h"
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void report(const char *name, double bytes, double *ms, int reps)
{
    qsort(ms, (size_t)reps, sizeof *ms, cmp_double);
    double med = ms[reps / 2];
    printf("{\"bench\":\"binarize\",\"case\":\"%s\",\"mb_per_s\":%.1f,\"median_ms\":%.3f,"
           "\"threads\":%d,\"simd\":\"%s\"}\n",
           name, bytes / 1e6 / (med / 1e3), med, bvox_threads(),
           bvox_simd_name(bvox_simd_active()));
    fflush(stdout);
}

#define MAX_RUNS 31

static int bench_binarize(const char *name, const bvox__gray *g, const bvox_binarize *how,
                          int reps)
{
    double ms[MAX_RUNS + 1];
    size_t bytes = (size_t)g->dims.nx * g->dims.ny * g->dims.nz *
                   (g->dtype == BVOX_DT_F32 ? 4 : 1);
    for (int r = -1; r < reps; r++) { /* r = -1: warm-up */
        bvox_volume *v;
        double t0 = now_ms();
        if (bvox__binarize(g, how, "bench", &v) != BVOX_OK) {
            fprintf(stderr, "%s: %s\n", name, bvox_errmsg());
            return 1;
        }
        if (r >= 0) ms[r] = now_ms() - t0;
        bvox_volume_destroy(v);
    }
    report(name, (double)bytes, ms, reps);
    return 0;
}

/* The obvious way: one voxel at a time, real value in doubles. */
static bvox_volume *naive_binarize(const uint8_t *d, int n, double threshold)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                double real = d[((size_t)z * n + y) * n + x] * 1.0 + 0.0;
                if (real >= threshold) bvox_volume_set(v, x, y, z, 1);
            }
    return v;
}

int main(int argc, char **argv)
{
    int n8 = 512, n32 = 256, runs = 7;
    thread_list tl = {0, {0}};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            n8 = 64;
            n32 = 32;
            runs = 3;
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = atoi(argv[++i]);
            if (runs < 1) runs = 1;
            if (runs > MAX_RUNS) runs = MAX_RUNS;
        } else if (!strcmp(argv[i], "--threads-list") && i + 1 < argc &&
                   thread_list_parse(argv[i + 1], &tl)) {
            i++;
        } else {
            fprintf(stderr, "usage: bench_binarize [--quick] [--runs N] [--threads-list 1,2,4,8,16]\n");
            return 2;
        }
    }
    size_t c8 = (size_t)n8 * n8 * n8, c32 = (size_t)n32 * n32 * n32;
    uint8_t *u8 = malloc(c8);
    float *f32 = malloc(c32 * sizeof(float));
    if (!u8 || !f32) return 1;
    /* a ball of bright voxels in noise: both outcomes everywhere */
    uint64_t s = 88172645463325252ull;
    for (size_t i = 0; i < c8; i++) {
        double x = (double)(i % n8), y = (double)(i / n8 % n8);
        double z = (double)(i / ((size_t)n8 * n8));
        double h = n8 / 2.0, r = sqrt((x - h) * (x - h) + (y - h) * (y - h) + (z - h) * (z - h));
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        u8[i] = (uint8_t)((r < 0.4 * n8 ? 160 : 60) + (int)(s % 64) - 32);
    }
    for (size_t i = 0; i < c32; i++) f32[i] = (float)u8[i * (c8 / c32)] * 0.25f - 10.0f;

    bvox__gray g8, g32;
    bvox__gray_init(&g8);
    g8.dims = (bvox_dims){n8, n8, n8};
    g8.dtype = BVOX_DT_U8;
    g8.data = u8;
    bvox__gray_init(&g32);
    g32.dims = (bvox_dims){n32, n32, n32};
    g32.dtype = BVOX_DT_F32;
    g32.data = f32;
    bvox_binarize th = {BVOX_BIN_THRESHOLD, 110, 0, 0, 0};
    bvox_binarize th32 = {BVOX_BIN_THRESHOLD, 17.5, 0, 0, 0};
    bvox_binarize otsu = {BVOX_BIN_OTSU, 0, 0, 0, 0};

    int all = bvox_threads();
    /* the counts to run at: all threads and one ("_1t"), or --threads-list
     * (no suffix: the lines differ by "threads") */
    const int listed = tl.n > 0;
    if (!listed) tl = (thread_list){2, {all, 1}};
#define SUFFIX_1T(t) (!listed && (t) == 1 ? "_1t" : "")
    bvox_simd best = bvox_simd_active();
    const bvox_simd levels[] = {BVOX_SIMD_AVX512, BVOX_SIMD_AVX2, BVOX_SIMD_GENERIC};
    char name[64];
    int rc = 0;
    /* names: <case>[_1t][_<path>], the path left out for the default one */
    for (int t = 0; t < tl.n; t++) {
        bvox_set_threads(tl.t[t]);
        for (int l = 0; l < 3; l++) {
            if (!bvox_simd_supported(levels[l])) continue;
            bvox_simd_set(levels[l]);
            char suffix[32];
            snprintf(suffix, sizeof suffix, "%s%s%s", SUFFIX_1T(t),
                     levels[l] == best ? "" : "_", levels[l] == best ? "" : bvox_simd_name(levels[l]));
            snprintf(name, sizeof name, "u8_%d%s", n8, suffix);
            rc |= bench_binarize(name, &g8, &th, runs);
            snprintf(name, sizeof name, "f32_%d%s", n32, suffix);
            rc |= bench_binarize(name, &g32, &th32, runs);
        }
        bvox_simd_set(best);
    }
    bvox_set_threads(all);
    snprintf(name, sizeof name, "u8_%d_otsu", n8);
    rc |= bench_binarize(name, &g8, &otsu, runs);

    /* unpack the whole 512^3 volume, 64 slices at a time: "unpack_512" into
     * one reused 64-slice buffer, as writers do (it stays in the L3 cache on
     * big machines), "unpack_512_full" into one 128 MiB buffer (every byte
     * goes to main memory) */
    bvox_volume *v;
    if (bvox__binarize(&g8, &th, "bench", &v) != BVOX_OK) return 1;
    uint8_t *out = malloc(c8);
    if (!out) return 1;
    memset(out, 0, c8); /* fault the pages in outside the timing */
    size_t slab = (size_t)64 * n8 * n8;
    double ms[MAX_RUNS + 1];
    for (int full = 0; full < 2; full++)
        for (int t = 0; t < tl.n; t++) {
            bvox_set_threads(tl.t[t]);
            for (int r = -1; r < runs; r++) {
                double t0 = now_ms();
                for (int z0 = 0; z0 < n8; z0 += 64)
                    bvox__unpack_slices(v, z0, 64, 1, out + (full ? (size_t)z0 / 64 * slab : 0));
                if (r >= 0) ms[r] = now_ms() - t0;
            }
            snprintf(name, sizeof name, "unpack_%d%s%s", n8, full ? "_full" : "",
                     SUFFIX_1T(t));
            report(name, (double)c8, ms, runs);
        }
    bvox_set_threads(all);

    for (int r = 0; r < 3; r++) {
        double t0 = now_ms();
        bvox_volume *nv = naive_binarize(u8, n8, th.threshold);
        ms[r] = now_ms() - t0;
        if (!nv || !bvox_volume_equal(nv, v)) {
            fprintf(stderr, "naive and fast binarize disagree\n");
            rc = 1;
        }
        bvox_volume_destroy(nv);
    }
    snprintf(name, sizeof name, "u8_%d_naive", n8);
    report(name, (double)c8, ms, 3);
    bvox_volume_destroy(v);
    free(out);
    free(u8);
    free(f32);
    return rc;
}
