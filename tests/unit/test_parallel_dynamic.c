/* test_parallel_dynamic.c — src/core/parallel.c and parallel_dynamic.c: the static
 * and the dynamic parallel-for cover [0, n) exactly once, in blocks of the
 * promised size, for any thread count; the thread count is capped at
 * BVOX__MAX_THREADS. */
#include "harness.h"
#include "internal.h"

#include <stdlib.h>

typedef struct cover {
    int64_t n, grain;
    int *hits;   /* per index */
    int bad;     /* a block of the wrong shape */
} cover;

static void mark(void *ctx, int64_t b, int64_t e)
{
    cover *c = ctx;
    if (b < 0 || e > c->n || b > e) {
        __atomic_store_n(&c->bad, 1, __ATOMIC_RELAXED);
        return;
    }
    /* dynamic blocks start on a multiple of grain and are grain long but the last */
    if (c->grain && c->n > c->grain && (b % c->grain || (e - b != c->grain && e != c->n)))
        __atomic_store_n(&c->bad, 1, __ATOMIC_RELAXED);
    for (int64_t i = b; i < e; i++) __atomic_fetch_add(&c->hits[i], 1, __ATOMIC_RELAXED);
}

static int check_cover(int dynamic, int64_t n, int64_t grain)
{
    cover c = {n, dynamic ? grain : 0, calloc((size_t)n + 1, sizeof(int)), 0};
    CHECK(c.hits != NULL);
    if (dynamic) bvox__parallel_for_dynamic(n, grain, mark, &c);
    else bvox__parallel_for(n, grain, mark, &c);
    CHECK_EQ(c.bad, 0);
    for (int64_t i = 0; i < n; i++) CHECK_EQ(c.hits[i], 1);
    free(c.hits);
    return 0;
}

TEST(static_and_dynamic_cover_once)
{
    const int threads[] = {1, 2, 3, 7, 64};
    const int64_t ns[] = {1, 2, 5, 63, 64, 65, 1000, 4099};
    const int64_t grains[] = {1, 3, 64};
    for (int t = 0; t < 5; t++) {
        bvox_set_threads(threads[t]);
        for (int i = 0; i < 8; i++)
            for (int g = 0; g < 3; g++) {
                if (check_cover(0, ns[i], grains[g])) return 1;
                if (check_cover(1, ns[i], grains[g])) return 1;
            }
    }
    bvox_set_threads(0);
    return 0;
}

TEST(thread_cap)
{
    bvox_set_threads(BVOX__MAX_THREADS + 100);
    CHECK_EQ(bvox_threads(), BVOX__MAX_THREADS);
    bvox_set_threads(3);
    CHECK_EQ(bvox_threads(), 3);
    bvox_set_threads(0);
    CHECK(bvox_threads() >= 1 && bvox_threads() <= BVOX__MAX_THREADS);
    return 0;
}
