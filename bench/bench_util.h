/*
 * bench_util.h — pieces the benchmarks share: the monotonic clock in ms, the
 * median of the runs and the TIME_MEDIAN macros that time a statement with
 * one untimed warm-up run, the "--sizes 256,512" list parser, a memcpy
 * baseline split over threads the way the library splits its work, and the
 * nearest-neighbour resampling that turns the AAL atlas into an n^3 "real
 * object". Header-only (static functions): each benchmark is one .c file.
 */
#ifndef BVOX_BENCH_UTIL_H
#define BVOX_BENCH_UTIL_H

#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- timing ---- */

/* The process's CPU time (all threads), ms: what the load of other
 * processes disturbs much less than the wall clock. */
static inline double cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static inline double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static inline int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of t[0..n) (sorts t): the middle one, or the mean of the two. */
static inline double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    return n % 2 ? t[n / 2] : (t[n / 2 - 1] + t[n / 2]) / 2;
}

/* Median time in ms of `runs` runs (at most 64) of stmt after one untimed
 * warm-up run; prep runs before each, untimed. */
#define TIME_MEDIAN_PREP(runs, prep, stmt)                                             \
    ({                                                                                 \
        double t_[64];                                                                 \
        int n_ = (runs) > 64 ? 64 : (runs);                                            \
        prep;                                                                          \
        stmt;                                                                          \
        for (int i_ = 0; i_ < n_; i_++) {                                              \
            prep;                                                                      \
            double s_ = now_ms();                                                      \
            stmt;                                                                      \
            t_[i_] = now_ms() - s_;                                                    \
        }                                                                              \
        median(t_, n_);                                                                \
    })

/* The same without preparation. */
#define TIME_MEDIAN(runs, stmt) TIME_MEDIAN_PREP(runs, (void)0, stmt)

/* ---- options ---- */

/* "256,512,1024" into sizes[0..*n): at most max of them (the rest is not
 * read); 0 if something other than numbers and commas is met. */
static inline int parse_size_list(char *s, int *sizes, int max, int *n)
{
    *n = 0;
    while (*s && *n < max) {
        sizes[(*n)++] = (int)strtol(s, &s, 10);
        if (*s == ',') s++;
        else if (*s) return 0;
    }
    return 1;
}

/* "--threads-list 1,2,4,8,16": the thread counts a benchmark runs at, in
 * order (each at most 64, at most 16 of them). Every benchmark takes it and
 * prints its lines once per count, with that count as "threads", so one run
 * shows the scaling. Without it: the library's count (BVOX_THREADS or every
 * online CPU), or "--threads T" where a benchmark has that. */
typedef struct thread_list {
    int n, t[16];
} thread_list;

static inline thread_list thread_list_default(void)
{
    return (thread_list){1, {bvox_threads()}};
}

/* 0 if s is not a list of counts in 1..64. */
static inline int thread_list_parse(const char *s, thread_list *l)
{
    char buf[256];
    int n = 0;
    if (strlen(s) >= sizeof buf) return 0;
    strcpy(buf, s);
    if (!parse_size_list(buf, l->t, 16, &n) || n < 1) return 0;
    for (int i = 0; i < n; i++)
        if (l->t[i] < 1 || l->t[i] > 64) return 0;
    l->n = n;
    return 1;
}

/* For a benchmark whose cases are all in one main: takes "--threads-list L"
 * out of argv and runs main_fn once per count, after bvox_set_threads(count)
 * (main_fn's "threads" keys read bvox_threads()); without it, main_fn once.
 * 2 (usage) for a bad list. */
static inline int run_threads_list(int argc, char **argv, int (*main_fn)(int, char **),
                                   const char *name)
{
    thread_list tl = {0, {0}};
    char **args = malloc(((size_t)argc + 1) * sizeof *args);
    int n = 0;
    if (!args) return 1;
    for (int i = 0; i < argc; i++) {
        if (i > 0 && !strcmp(argv[i], "--threads-list")) {
            if (i + 1 >= argc || !thread_list_parse(argv[i + 1], &tl)) {
                fprintf(stderr, "%s: --threads-list takes counts in 1..64, e.g. 1,2,4,8,16\n",
                        name);
                free(args);
                return 2;
            }
            i++;
            continue;
        }
        args[n++] = argv[i];
    }
    args[n] = NULL;
    int rc = 0;
    if (!tl.n) rc = main_fn(n, args);
    for (int k = 0; k < tl.n && !rc; k++) {
        bvox_set_threads(tl.t[k]);
        rc = main_fn(n, args);
        fflush(stdout);
    }
    free(args);
    return rc;
}

/* ---- memcpy baseline ---- */

typedef struct copy_job {
    uint8_t *dst;
    const uint8_t *src;
    size_t n;
} copy_job;

static inline void copy_range(void *p, int64_t b, int64_t e)
{
    const copy_job *c = p;
    memcpy(c->dst + b, c->src + b, (size_t)(e - b));
}

/* memcpy of n bytes split over `threads` threads exactly as the library
 * splits its work (bvox__parallel_for: its pool, never wider than the CPUs),
 * so the baseline and the operations pay the same threading costs. */
static inline void parallel_memcpy(void *dst, const void *src, size_t n, int threads)
{
    int saved = bvox_threads();
    copy_job c = {dst, src, n};
    bvox_set_threads(threads);
    bvox__parallel_for((int64_t)n, 4096, copy_range, &c);
    bvox_set_threads(saved);
}

/* ---- specimens ---- */

/* Nearest-neighbour resampling of src to n^3: voxel i takes source voxel
 * floor((i + 1/2) * ns / n) on each axis. Built a word at a time. */
static inline bvox_volume *resample(const bvox_volume *src, int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    int32_t *zmap = malloc((size_t)n * sizeof *zmap);
    if (!zmap) {
        bvox_volume_destroy(v);
        return NULL;
    }
    for (int i = 0; i < n; i++) zmap[i] = (int32_t)(((double)i + 0.5) * src->nz / n);
    for (int y = 0; y < n; y++) {
        int32_t sy = (int32_t)(((double)y + 0.5) * src->ny / n);
        for (int x = 0; x < n; x++) {
            int32_t sx = (int32_t)(((double)x + 0.5) * src->nx / n);
            const uint64_t *sc = bvox__column_c(src, sx, sy);
            uint64_t *dc = bvox__column(v, x, y);
            for (size_t k = 0; k < v->wpc; k++) {
                uint64_t w = 0;
                for (int b = 0; b < 64 && (int)k * 64 + b < n; b++) {
                    int32_t sz = zmap[k * 64 + (size_t)b];
                    w |= ((sc[sz >> 6] >> (sz & 63)) & 1) << b;
                }
                dc[k] = w;
            }
        }
    }
    free(zmap);
    return v;
}

#endif
