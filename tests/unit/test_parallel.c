/* test_parallel.c — the worker pool of parallel.c: every index of [0, n) is
 * visited exactly once, in the chunks the documented split gives
 * ([n t / T, n (t + 1) / T), T = bvox__parallelism()), for many thread
 * counts (more than cores too)
 * and sizes, over thousands of back-to-back calls (a late worker must never
 * claim a chunk of a newer call); the pool keeps working after the thread
 * count changes, when called from several application threads at once, from
 * inside a chunk (nested), and in a forked child. */
#define _GNU_SOURCE /* sched_getaffinity */
#include "harness.h"
#include "internal.h"

#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct visit {
    int64_t n;
    _Atomic int *seen;     /* per index: times visited */
    _Atomic int chunks;    /* calls of the range function */
    _Atomic int bad_chunk; /* a chunk not on the documented boundaries */
    int threads;           /* expected chunk count */
} visit;

static void mark(void *arg, int64_t b, int64_t e)
{
    visit *v = arg;
    atomic_fetch_add(&v->chunks, 1);
    /* b must be n k / T for some k, and e the next boundary */
    int ok = 0;
    for (int k = 0; k < v->threads; k++)
        if (b == v->n * k / v->threads && e == v->n * (k + 1) / v->threads) ok = 1;
    if (!ok) atomic_store(&v->bad_chunk, 1);
    for (int64_t i = b; i < e; i++) atomic_fetch_add(&v->seen[i], 1);
}

/* One call; 0 if every index was seen once in the expected chunks. */
static int one_call(int64_t n, int64_t min_per)
{
    visit v = {n, calloc((size_t)n, sizeof(_Atomic int)), 0, 0, 0};
    if (!v.seen) return 1;
    int t = bvox__parallelism();
    if (t > n / min_per) t = (int)(n / min_per);
    v.threads = t < 1 ? 1 : t;
    bvox__parallel_for(n, min_per, mark, &v);
    int bad = atomic_load(&v.bad_chunk) || atomic_load(&v.chunks) != v.threads;
    for (int64_t i = 0; i < n; i++) bad |= atomic_load(&v.seen[i]) != 1;
    free(v.seen);
    return bad;
}

/* Work is split into at most as many pieces as CPUs: bvox_threads() capped
 * at the CPU count, which the tests' BVOX_CPUS=64 raises so that every
 * thread count up to 64 splits as asked. */
TEST(parallelism_is_threads_capped_by_cpus)
{
    const char *env = getenv("BVOX_CPUS");
    cpu_set_t set;
    int cpus = env && atoi(env) > 0 ? atoi(env)
               : sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
    for (int t = 1; t <= 64; t++) {
        bvox_set_threads(t);
        CHECK_EQ(bvox_threads(), t);
        CHECK_EQ(bvox__parallelism(), t < cpus ? t : cpus);
    }
    bvox_set_threads(0);
    return 0;
}

TEST(every_index_once_in_documented_chunks)
{
    static const int threads[] = {1, 2, 3, 4, 7, 16, 33, 64};
    static const int64_t sizes[] = {1, 2, 3, 15, 16, 17, 100, 1000, 4099};
    for (size_t ti = 0; ti < sizeof threads / sizeof *threads; ti++) {
        bvox_set_threads(threads[ti]);
        CHECK_EQ(bvox_threads(), threads[ti]);
        for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++)
            for (int64_t min_per = 1; min_per <= 4; min_per += 3)
                CHECK_EQ(one_call(sizes[si], min_per), 0);
    }
    bvox_set_threads(0);
    return 0;
}

/* Thousands of small calls in a row, alternating thread counts: a worker
 * that wakes late for one call must find nothing left of it and must not
 * touch the next one's chunks. */
TEST(back_to_back_calls)
{
    for (int i = 0; i < 3000; i++) {
        int t = 1 + i % 16;
        bvox_set_threads(t);
        CHECK_EQ(one_call(16 + i % 5, 1), 0);
    }
    bvox_set_threads(0);
    return 0;
}

static void sum_range(void *arg, int64_t b, int64_t e)
{
    _Atomic int64_t *s = arg;
    int64_t x = 0;
    for (int64_t i = b; i < e; i++) x += i;
    atomic_fetch_add(s, x);
}

static void nested(void *arg, int64_t b, int64_t e)
{
    _Atomic int64_t *s = arg;
    for (int64_t i = b; i < e; i++) {
        _Atomic int64_t inner = 0;
        bvox__parallel_for(1000, 1, sum_range, &inner);
        atomic_fetch_add(s, atomic_load(&inner) == 999 * 1000 / 2);
    }
}

TEST(nested_calls_complete)
{
    bvox_set_threads(4);
    _Atomic int64_t ok = 0;
    bvox__parallel_for(12, 1, nested, &ok);
    CHECK_EQ(atomic_load(&ok), 12);
    bvox_set_threads(0);
    return 0;
}

static void *app_thread(void *arg)
{
    int *bad = arg;
    for (int i = 0; i < 300; i++) {
        _Atomic int64_t s = 0;
        int64_t n = 500 + i;
        bvox__parallel_for(n, 1, sum_range, &s);
        if (atomic_load(&s) != n * (n - 1) / 2) *bad = 1;
    }
    return NULL;
}

/* Several application threads using the library at once: one gets the pool,
 * the others fall back to their own threads; every answer is right. */
TEST(concurrent_callers)
{
    bvox_set_threads(3);
    pthread_t tid[4];
    int bad[4] = {0};
    for (int k = 0; k < 4; k++) CHECK_EQ(pthread_create(&tid[k], NULL, app_thread, &bad[k]), 0);
    for (int k = 0; k < 4; k++) pthread_join(tid[k], NULL);
    for (int k = 0; k < 4; k++) CHECK_EQ(bad[k], 0);
    bvox_set_threads(0);
    return 0;
}

typedef struct who {
    pthread_t tid[64];
    _Atomic int n;
} who;

/* Records which thread ran each chunk; slow enough that the caller alone
 * cannot claim every chunk before a live worker wakes. */
static void record_thread(void *arg, int64_t b, int64_t e)
{
    who *w = arg;
    (void)b, (void)e;
    usleep(20000);
    w->tid[atomic_fetch_add(&w->n, 1)] = pthread_self();
}

/* Chunks of a 4-thread call ran on more than one thread (where the process
 * may use more than one CPU: work is never split wider than that). */
static int spread_over_threads(void)
{
    if (bvox__parallelism() < 2) return 1; /* one CPU: nothing to spread over */
    who w = {{0}, 0};
    bvox__parallel_for(4, 1, record_thread, &w);
    int n = atomic_load(&w.n);
    if (n != (bvox__parallelism() < 4 ? bvox__parallelism() : 4)) return 0;
    for (int k = 1; k < n; k++)
        if (!pthread_equal(w.tid[k], w.tid[0])) return 1;
    return 0;
}

/* A child forked after the pool started has none of the parent's workers: it
 * must start its own (not believe it has them, and run every chunk alone). */
TEST(fork_child_uses_its_own_pool)
{
    bvox_set_threads(4);
    CHECK_EQ(one_call(1000, 1), 0); /* the pool exists now */
    CHECK(spread_over_threads());
    pid_t pid = fork();
    CHECK(pid >= 0);
    if (pid == 0) _exit(one_call(1000, 1) || one_call(77, 1) || !spread_over_threads() ? 1 : 0);
    int status = 0;
    CHECK_EQ(waitpid(pid, &status, 0), pid);
    CHECK(WIFEXITED(status));
    CHECK_EQ(WEXITSTATUS(status), 0);
    bvox_set_threads(0);
    return 0;
}
