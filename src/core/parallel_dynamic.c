/*
 * parallel_dynamic.c — bvox__parallel_for_dynamic (internal.h): a parallel
 * for whose blocks go to whichever thread asks next, for work whose cost per
 * item varies (marching cubes: an uneven surface). Built on
 * bvox__parallel_for, one task per thread, so that it follows whatever
 * parallel.c does with threads (thread count, fallbacks, a pool).
 */
#include "internal.h"

typedef struct dyn {
    bvox__range_fn fn;
    void *ctx;
    int64_t n, grain;
    int64_t next; /* atomic */
} dyn;

static void dyn_worker(void *ctx, int64_t begin, int64_t end)
{
    dyn *d = ctx;
    (void)begin;
    (void)end;
    for (;;) {
        int64_t b = __atomic_fetch_add(&d->next, d->grain, __ATOMIC_RELAXED);
        if (b >= d->n) return;
        d->fn(d->ctx, b, b + d->grain < d->n ? b + d->grain : d->n);
    }
}

void bvox__parallel_for_dynamic(int64_t n, int64_t grain, bvox__range_fn fn, void *ctx)
{
    if (grain < 1) grain = 1;
    int threads = bvox__parallelism();
    if (threads < 2 || n <= grain) {
        fn(ctx, 0, n);
        return;
    }
    dyn d = {fn, ctx, n, grain, 0};
    bvox__parallel_for(threads, 1, dyn_worker, &d);
}
