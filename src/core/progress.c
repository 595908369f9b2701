/*
 * progress.c — the progress callback (bvox_set_progress) and the checks long
 * operations make.
 *
 * Thread-local, like the warning handler: only the thread that called the
 * library reports, so workers never call user code and no lock is needed.
 * Operations nest (open = erode then dilate; reconstruct reads, thresholds,
 * ...): each public entry brackets its work with bvox__progress_begin/end,
 * and an outer operation gives an inner one a part of its own range with
 * bvox__progress_sub. Fractions are mapped through the current range
 * [base, base + span] of the outermost call and never go back: the caller
 * sees one bar from 0 to 1 per outermost call.
 *
 * Once the callback asks to stop, every later check of the same outermost
 * call fails too (sticky), so an operation that ignored one status still
 * stops at its next check.
 */
#include "internal.h"

#include <time.h>

static _Thread_local bvox_progress_fn cb;
static _Thread_local void *cb_user;
static _Thread_local int64_t interval_ns = 5000000;
static _Thread_local int depth;
static _Thread_local double base, span = 1, last;
static _Thread_local const char *stage = "";
static _Thread_local int64_t last_ns;
static _Thread_local int called, canceled;

void bvox_set_progress(bvox_progress_fn fn, void *user)
{
    cb = fn;
    cb_user = fn ? user : NULL;
}

void bvox_set_progress_interval(double seconds)
{
    interval_ns = seconds > 0 ? (int64_t)(seconds * 1e9) : 0;
}

int bvox__progress_active(void) { return cb != NULL; }

static int64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

static bvox_status canceled_status(void)
{
    return bvox__fail(BVOX_ECANCELED, "canceled (during %s)", stage[0] ? stage : "work");
}

/* Calls the callback with global fraction g (monotone); forced ignores the
 * interval. Returns non-zero when it asks to stop. */
static int report(double g, int forced)
{
    if (g < last) g = last;
    /* 1 is said once, by bvox__progress_end when the outermost call
     * succeeds: a stage that ends the range stays silent */
    if (g >= 1 && !forced) return 0;
    int64_t t = 0;
    if (interval_ns > 0) {
        t = now_ns();
        if (!forced && called && t - last_ns < interval_ns) return 0;
    }
    last = g;
    last_ns = t;
    called = 1;
    return cb(g, stage, cb_user) != 0;
}

void bvox__progress_begin(bvox__progress_scope *saved, const char *name)
{
    saved->base = base;
    saved->span = span;
    saved->stage = stage;
    if (depth++ == 0) {
        base = 0;
        span = 1;
        last = 0;
        called = 0;
        canceled = 0;
    }
    if (name) stage = name;
}

bvox_status bvox__progress_end(const bvox__progress_scope *saved, bvox_status st)
{
    if (--depth == 0 && cb && st == BVOX_OK && !canceled) (void)report(1, 1);
    base = saved->base;
    span = saved->span;
    stage = saved->stage;
    if (depth == 0) canceled = 0;
    return st;
}

void bvox__progress_sub(bvox__progress_scope *saved, double lo, double hi, const char *name)
{
    saved->base = base;
    saved->span = span;
    saved->stage = stage;
    base = base + span * lo;
    span = span * (hi - lo);
    if (name) stage = name;
}

void bvox__progress_restore(const bvox__progress_scope *saved)
{
    base = saved->base;
    span = saved->span;
    stage = saved->stage;
}

bvox_status bvox__progress(double fraction)
{
    if (canceled) return canceled_status();
    if (!cb) return BVOX_OK;
    if (fraction < 0) fraction = 0;
    if (fraction > 1) fraction = 1;
    if (report(base + span * fraction, 0)) {
        canceled = 1;
        return canceled_status();
    }
    return BVOX_OK;
}

bvox_status bvox__progress_steps(int64_t done, int64_t total)
{
    if (!cb && !canceled) return BVOX_OK;
    return bvox__progress(total > 0 ? (double)done / (double)total : 1);
}

/* Splitting [0, n) into blocks run one after the other gives the same result
 * as one call for kernels that are pure functions of their range (what
 * bvox__parallel_for asks of them); only the seams between threads move. */
#define PROGRESS_BLOCKS 32

/* Work per band with a callback: Ctrl-C answered within about this, and
 * the seams and thread start-ups of the bands lost in the noise (16 fixed
 * bands made `bvox morph dilate` measurably slower than the library call). */
#define BAND_NS 250000000

void bvox__bands_begin(bvox__bands *b, int64_t total, int64_t nfixed)
{
    b->total = total;
    b->nfixed = nfixed < 1 ? 1 : nfixed;
    b->i = 0;
    b->t0_ns = cb && interval_ns > 0 ? now_ns() : 0;
}

int64_t bvox__bands_next(bvox__bands *b, int64_t lo)
{
    int64_t total = b->total, n = b->nfixed, i = b->i++;
    if (!cb || lo >= total) return total;
    int64_t fixed_end = total * (i + 1) / n;
    if (interval_ns == 0 || lo == 0) return fixed_end > lo ? fixed_end : lo + 1;
    /* the rate so far gives the size of a band of BAND_NS, never smaller
     * than a fixed one */
    double per = (double)(now_ns() - b->t0_ns) / (double)lo;
    double size = per > 0 ? (double)BAND_NS / per : (double)total;
    double least = (double)total / (double)n;
    if (size < least) size = least;
    if (size >= (double)(total - lo)) return total;
    int64_t hi = lo + (int64_t)size;
    return hi > lo ? hi : lo + 1;
}

typedef struct offset_job {
    bvox__range_fn fn;
    void *ctx;
    int64_t lo;
} offset_job;

static void offset_range(void *ctx, int64_t begin, int64_t end)
{
    offset_job *j = ctx;
    j->fn(j->ctx, j->lo + begin, j->lo + end);
}

bvox_status bvox__parallel_for_progress(int64_t n, int64_t min_per_thread, bvox__range_fn fn,
                                        void *ctx)
{
    if (canceled) return canceled_status();
    if (!cb || n < 2 * PROGRESS_BLOCKS) {
        bvox__parallel_for(n, min_per_thread, fn, ctx);
        return bvox__progress(1);
    }
    bvox__bands b;
    bvox__bands_begin(&b, n, PROGRESS_BLOCKS);
    for (int64_t lo = 0, hi; lo < n; lo = hi) {
        hi = bvox__bands_next(&b, lo);
        offset_job j = {fn, ctx, lo};
        bvox__parallel_for(hi - lo, min_per_thread, offset_range, &j);
        bvox_status st = bvox__progress((double)hi / (double)n);
        if (st) return st;
    }
    return BVOX_OK;
}
