/*
 * parallel.c — split a range of independent work over the worker threads.
 * The kernel is a pure function of its chunk (libvips' generate idea), so a
 * thread count change never touches the kernels. Threads are created per call:
 * the calls that use this move tens of megabytes, so the ~50 us of thread
 * start-up is noise, and no pool means no hidden global state.
 */
#include "internal.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#define MAX_THREADS BVOX__MAX_THREADS

static atomic_int configured_threads; /* 0 = not yet decided */

static int default_threads(void)
{
    const char *env = getenv("BVOX_THREADS");
    if (env && *env) {
        int n = atoi(env);
        if (n >= 1) return n > MAX_THREADS ? MAX_THREADS : n;
    }
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1) n = 1;
    return n > MAX_THREADS ? MAX_THREADS : (int)n;
}

void bvox_set_threads(int threads)
{
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    atomic_store(&configured_threads, threads < 1 ? 0 : threads);
}

int bvox_threads(void)
{
    int n = atomic_load(&configured_threads);
    if (n) return n;
    n = default_threads();
    atomic_store(&configured_threads, n);
    return n;
}

typedef struct job {
    bvox__range_fn fn;
    void *ctx;
    int64_t begin, end;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    j->fn(j->ctx, j->begin, j->end);
    return NULL;
}

void bvox__parallel_for(int64_t n, int64_t min_per_thread, bvox__range_fn fn, void *ctx)
{
    if (n <= 0) return;
    int threads = bvox_threads();
    if (min_per_thread < 1) min_per_thread = 1;
    if (threads > n / min_per_thread) threads = (int)(n / min_per_thread);
    if (threads <= 1) {
        fn(ctx, 0, n);
        return;
    }
    job jobs[MAX_THREADS];
    pthread_t tid[MAX_THREADS];
    bool started[MAX_THREADS] = {false};
    for (int t = 0; t < threads; t++) {
        jobs[t] = (job){fn, ctx, n * t / threads, n * (t + 1) / threads};
        /* Thread 0's chunk runs on the calling thread; a failed thread start
         * also falls back to running its chunk here, so the result never
         * depends on whether threads could be created. */
        if (t > 0) started[t] = pthread_create(&tid[t], NULL, run_job, &jobs[t]) == 0;
    }
    run_job(&jobs[0]);
    for (int t = 1; t < threads; t++) {
        if (started[t]) pthread_join(tid[t], NULL);
        else run_job(&jobs[t]);
    }
}
