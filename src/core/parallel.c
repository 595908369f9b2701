/*
 * parallel.c — split a range of independent work over the worker threads.
 * The kernel is a pure function of its chunk (libvips' generate idea), so a
 * thread count change never touches the kernels.
 *
 * The workers are a pool that lives for the process: created on the first
 * call that needs them, grown when bvox_set_threads asks for more, never
 * joined. Starting threads per call cost ~50 us per thread, which made small
 * operations slower with more threads; a pooled call costs one wake-up.
 *
 * A call splits [0, n) into `tasks` chunks, chunk t = [n t / tasks,
 * n (t + 1) / tasks) exactly as before, and publishes them; the caller and
 * the woken workers claim chunks one at a time from one atomic counter until
 * none is left. So a worker that wakes late (more threads than cores) finds
 * nothing to do instead of holding up the call, and the chunk boundaries never
 * depend on who ran them.
 *
 * The counter holds the call's generation in its high 32 bits and the next
 * chunk in its low 32: a worker still holding an old generation can never
 * claim a chunk of a newer call. One call uses the pool at a time; a second
 * caller (another application thread, or a kernel calling back in from a
 * worker) is not made to wait: a nested call runs inline, a concurrent one
 * starts its own threads as this file did before the pool. After fork() the
 * child forgets the parent's workers (they do not exist there).
 */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include "internal.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>
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

/* ---- the pool ---- */

typedef struct pool {
    pthread_mutex_t lock;    /* guards everything below but `next` */
    pthread_cond_t wake;     /* a new call was published (or workers grow) */
    pthread_cond_t finished; /* the last chunk of the call completed */
    pthread_mutex_t submit;  /* held by the one call using the pool */
    int workers;             /* threads started so far */
    _Atomic uint32_t generation; /* of the call published last (written under lock) */
    int sleeping;            /* workers blocked on `wake` */
    bvox__range_fn fn;       /* the published call */
    void *ctx;
    int64_t n;
    uint32_t tasks;
    _Atomic uint32_t done;   /* chunks of the call completed */
    _Atomic uint64_t next;   /* generation << 32 | next chunk to claim */
} pool;

static pool the_pool = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER,
                        PTHREAD_COND_INITIALIZER, PTHREAD_MUTEX_INITIALIZER, 0, 0, 0, NULL,
                        NULL, 0, 0, 0, 0};
static pthread_once_t atfork_once = PTHREAD_ONCE_INIT;
static atomic_int cpus; /* CPUs this process may run on; 0 = not yet known */
static _Thread_local int in_worker; /* set in pool threads: nested calls run inline */

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* The CPUs this process may run on (or BVOX_CPUS, which tests set high so
 * that every thread count still splits the work as asked). */
static int cpu_count(void)
{
    int n = atomic_load(&cpus);
    if (n) return n;
    const char *env = getenv("BVOX_CPUS");
    if (env && *env) n = atoi(env);
    cpu_set_t set;
    if (n < 1 && sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    if (n < 1) n = (int)sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1) n = 1;
    if (n > MAX_THREADS) n = MAX_THREADS;
    atomic_store(&cpus, n);
    return n;
}

/* More threads than CPUs never run at once, so work is never split into
 * more pieces than that: BVOX_THREADS=16 on 2 cores costs what 2 threads
 * cost (a split into 16 would only add seams and per-piece scratch). */
int bvox__parallelism(void)
{
    int t = bvox_threads(), c = cpu_count();
    return t < c ? t : c;
}

/* Claims and runs chunks of generation gen until none is left; returns how
 * many it ran. */
static uint32_t run_chunks(pool *p, uint32_t gen, bvox__range_fn fn, void *ctx, int64_t n,
                           uint32_t tasks)
{
    uint32_t ran = 0;
    uint64_t v = atomic_load(&p->next);
    for (;;) {
        if ((uint32_t)(v >> 32) != gen || (uint32_t)v >= tasks) return ran;
        if (!atomic_compare_exchange_weak(&p->next, &v, v + 1)) continue;
        int64_t t = (int64_t)(uint32_t)v;
        fn(ctx, n * t / tasks, n * (t + 1) / tasks);
        ran++;
        v = atomic_load(&p->next);
    }
}

static void finish_chunks(pool *p, uint32_t ran, uint32_t tasks)
{
    if (!ran) return;
    /* tasks: the caller's own count, never p->tasks (a caller that sees the
     * last chunk done may already be publishing its next call) */
    if (atomic_fetch_add(&p->done, ran) + ran != tasks) return;
    pthread_mutex_lock(&p->lock); /* the caller may be about to sleep */
    pthread_cond_signal(&p->finished);
    pthread_mutex_unlock(&p->lock);
}

/* arg: the generation published before this worker was started (the call
 * that starts it publishes the next one, which the worker must not miss). */
static int64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

/* Returns when a call after `seen` is published or ~50 us have passed. The
 * worker yields while it watches: where it shares a CPU with the caller (a
 * loaded machine), spinning would hold the caller off for the whole watch. */
static void watch_for_call(pool *p, uint32_t seen)
{
    int64_t until = now_ns() + 50000;
    while (atomic_load(&p->generation) == seen && now_ns() < until) {
        for (int i = 0; i < 16; i++) cpu_relax();
        sched_yield();
    }
}

static void *worker_main(void *arg)
{
    pool *p = &the_pool;
    in_worker = 1;
    uint32_t seen = (uint32_t)(uintptr_t)arg;
    for (;;) {
        /* Calls often come back to back: watch for the next one a little
         * (~50 us) before sleeping, so that it needs no wake-up (a futex
         * wake costs about as much as a small call's whole work). */
        watch_for_call(p, seen);
        pthread_mutex_lock(&p->lock);
        while (atomic_load(&p->generation) == seen) {
            p->sleeping++;
            pthread_cond_wait(&p->wake, &p->lock);
            p->sleeping--;
        }
        seen = atomic_load(&p->generation);
        bvox__range_fn fn = p->fn;
        void *ctx = p->ctx;
        int64_t n = p->n;
        uint32_t tasks = p->tasks;
        pthread_mutex_unlock(&p->lock);
        finish_chunks(p, run_chunks(p, seen, fn, ctx, n, tasks), tasks);
    }
    return NULL;
}

/* In the child of a fork only the forking thread exists: start afresh. */
static void atfork_child(void)
{
    pool fresh = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER,
                  PTHREAD_COND_INITIALIZER, PTHREAD_MUTEX_INITIALIZER, 0, 0, 0, NULL,
                  NULL, 0, 0, 0, 0};
    the_pool = fresh;
}

static void register_atfork(void)
{
    pthread_atfork(NULL, NULL, atfork_child);
}

/* Starts workers until there are `want` (with p->lock held); returns how
 * many there are (fewer if the system refuses threads). */
static int grow(pool *p, int want)
{
    while (p->workers < want) {
        pthread_t tid;
        pthread_attr_t attr;
        pthread_attr_init(&attr);
        pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
        int err = pthread_create(&tid, &attr, worker_main, (void *)(uintptr_t)p->generation);
        pthread_attr_destroy(&attr);
        if (err) break;
        p->workers++;
    }
    return p->workers;
}

/* ---- the old way, for a call made while the pool is busy ---- */

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

static void spawn_for(int64_t n, int threads, bvox__range_fn fn, void *ctx)
{
    job jobs[MAX_THREADS];
    pthread_t tid[MAX_THREADS];
    bool started[MAX_THREADS] = {false};
    for (int t = 0; t < threads; t++) {
        jobs[t] = (job){fn, ctx, n * t / threads, n * (t + 1) / threads};
        /* a failed thread start runs its chunk here: the result never
         * depends on whether threads could be created */
        if (t > 0) started[t] = pthread_create(&tid[t], NULL, run_job, &jobs[t]) == 0;
    }
    run_job(&jobs[0]);
    for (int t = 1; t < threads; t++) {
        if (started[t]) pthread_join(tid[t], NULL);
        else run_job(&jobs[t]);
    }
}

void bvox__parallel_for(int64_t n, int64_t min_per_thread, bvox__range_fn fn, void *ctx)
{
    if (n <= 0) return;
    int threads = bvox__parallelism();
    if (min_per_thread < 1) min_per_thread = 1;
    if (threads > n / min_per_thread) threads = (int)(n / min_per_thread);
    if (threads <= 1) {
        fn(ctx, 0, n);
        return;
    }
    if (in_worker) { /* called from inside a chunk: the other workers are busy */
        for (int t = 0; t < threads; t++) fn(ctx, n * t / threads, n * (t + 1) / threads);
        return;
    }
    pool *p = &the_pool;
    pthread_once(&atfork_once, register_atfork);
    if (pthread_mutex_trylock(&p->submit) != 0) {
        spawn_for(n, threads, fn, ctx);
        return;
    }
    pthread_mutex_lock(&p->lock);
    grow(p, threads - 1);
    p->fn = fn, p->ctx = ctx, p->n = n;
    p->tasks = (uint32_t)threads;
    atomic_store(&p->done, 0);
    uint32_t gen = atomic_load(&p->generation) + 1;
    atomic_store(&p->next, (uint64_t)gen << 32);
    atomic_store(&p->generation, gen); /* watching workers start here */
    /* wake sleeping workers, no more than the chunks besides the caller's */
    for (int t = 1; t < threads && t <= p->sleeping; t++) pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);

    /* the caller works too; with no workers at all it runs every chunk */
    finish_chunks(p, run_chunks(p, gen, fn, ctx, n, (uint32_t)threads), (uint32_t)threads);
    /* A worker is finishing its last chunk: watch for it a little (~20 us;
     * a sleep and wake-up costs more than a small call's whole work), then
     * sleep. Not sched_yield: on a loaded machine that gives the CPU away
     * for a whole time slice. */
    int64_t until = now_ns() + 20000;
    for (int i = 1; atomic_load(&p->done) < (uint32_t)threads; i++) {
        cpu_relax();
        if (i % 64 == 0 && now_ns() > until) break;
    }
    if (atomic_load(&p->done) < (uint32_t)threads) {
        pthread_mutex_lock(&p->lock);
        while (atomic_load(&p->done) < (uint32_t)threads)
            pthread_cond_wait(&p->finished, &p->lock);
        pthread_mutex_unlock(&p->lock);
    }
    pthread_mutex_unlock(&p->submit);
}
