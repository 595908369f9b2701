/*
 * alloc.c — the one allocation seam. Large buffers (voxel words, decoded
 * images) go through bvox__alloc, which enforces the process-wide memory
 * budget, so that a file header claiming 2^40 voxels gets a clear
 * BVOX_ETOOBIG instead of an abort or the OOM killer. Small things go through
 * the unbudgeted bvox__mem_* wrappers. Both kinds share one fault countdown,
 * so tests can fail any allocation of the library (see core/alloc.h).
 * This is the only file of src/ and viewer/ that calls libc's allocators.
 */
#include "internal.h"

#include "core/big_buffers.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static atomic_size_t budget_bytes;   /* 0 = not yet set: default */
static atomic_size_t in_use_bytes;
static atomic_long fail_countdown;  /* test hook, 0 = off */

static size_t default_budget(void)
{
    long pages = sysconf(_SC_PHYS_PAGES);
    long page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return (size_t)4 << 30;
    return (size_t)pages * (size_t)page / 2;
}

/* At most an eighth of the memory budget, and 1 GiB, stays cached. */
static size_t cache_limit(void)
{
    size_t b = bvox_memory_budget() / 8, most = (size_t)1 << 30;
    return b < most ? b : most;
}

void bvox_set_memory_budget(size_t bytes)
{
    atomic_store(&budget_bytes, bytes);
    bvox__big_fit(cache_limit());
}

size_t bvox_memory_budget(void)
{
    size_t b = atomic_load(&budget_bytes);
    if (b) return b;
    /* physical memory does not change: ask the system once */
    static atomic_size_t cached_default;
    b = atomic_load(&cached_default);
    if (!b) {
        b = default_budget();
        atomic_store(&cached_default, b);
    }
    return b;
}

size_t bvox_memory_in_use(void) { return atomic_load(&in_use_bytes); }

void bvox__alloc_fail_after(long n) { atomic_store(&fail_countdown, n); }

long bvox__alloc_fail_pending(void) { return atomic_load(&fail_countdown); }

/* True when the fault hook says this allocation must fail. The load first
 * keeps the common case (hook off) to one read: no shared write, so threads
 * allocating at once do not fight over a cache line. */
static bool injected_failure(void)
{
    long c = atomic_load(&fail_countdown);
    /* Decrement only while positive (compare-and-swap): a plain fetch_sub let
     * two threads that both saw 1 drive the countdown to -1, and the sweep then
     * thought the failed allocation was never reached. */
    while (c > 0) {
        if (atomic_compare_exchange_weak(&fail_countdown, &c, c - 1)) return c == 1;
    }
    return false;
}

void bvox__format_bytes(char *buf, size_t len, size_t bytes)
{
    const char *units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = (double)bytes;
    int u = 0;
    while (v >= 1024.0 && u < 6) { v /= 1024.0; u++; }
    snprintf(buf, len, u ? "%.1f %s" : "%.0f %s", v, units[u]);
}

bool bvox__budget_charge(size_t bytes, const char *what, bvox_status *status)
{
    if (!what) what = "buffer";
    size_t budget = bvox_memory_budget();
    size_t used = atomic_fetch_add(&in_use_bytes, bytes);
    if (bytes > budget || used > budget - bytes) {
        atomic_fetch_sub(&in_use_bytes, bytes);
        char need[32], lim[32], held[32];
        bvox__format_bytes(need, sizeof need, bytes);
        bvox__format_bytes(lim, sizeof lim, budget);
        bvox__format_bytes(held, sizeof held, used);
        /* say what else is held when the request alone would fit: "needs
         * 1.2 MiB, over the budget of 8 MiB" reads as a contradiction */
        if (bytes > budget)
            *status = bvox__fail(BVOX_ETOOBIG, "the %s needs %s, over the memory budget of %s",
                                 what, need, lim);
        else
            *status = bvox__fail(BVOX_ETOOBIG,
                                 "the %s needs %s with %s already in use, over the memory "
                                 "budget of %s",
                                 what, need, held, lim);
        return false;
    }
    *status = BVOX_OK;
    return true;
}

void bvox__budget_refund(size_t bytes) { atomic_fetch_sub(&in_use_bytes, bytes); }

/* Buffers from BVOX__BIG_MIN on are the library's own mappings, in huge
 * pages and cached for reuse (big_buffers.c says why); smaller ones come
 * from libc's heap. Which one a buffer is follows from its size alone, so
 * bvox__free, which is given the size, knows how to give it back. */
static bool is_big(size_t bytes) { return bytes >= BVOX__BIG_MIN; }

void *bvox__alloc(size_t bytes, bool zero, const char *what, bvox_status *status)
{
    if (!what) what = "buffer";
    if (injected_failure()) {
        *status = bvox__fail(BVOX_ENOMEM, "out of memory allocating the %s (injected)", what);
        return NULL;
    }
    if (!bvox__budget_charge(bytes, what, status)) return NULL;
    size_t rounded = (bytes + 63) & ~(size_t)63;
    if (rounded == 0) rounded = 64;
    bool fresh = false;
    void *p = is_big(bytes) ? bvox__big_get(bytes, &fresh) : aligned_alloc(64, rounded);
    if (!p) {
        atomic_fetch_sub(&in_use_bytes, bytes);
        char need[32];
        bvox__format_bytes(need, sizeof need, bytes);
        *status = bvox__fail(BVOX_ENOMEM, "out of memory allocating %s for the %s", need, what);
        return NULL;
    }
    if (zero && !fresh) memset(p, 0, rounded); /* fresh pages read as zeros */
    *status = BVOX_OK;
    return p;
}

void bvox__free(void *ptr, size_t bytes)
{
    if (!ptr) return;
    bvox__free_charged(ptr, bytes, bytes);
}

void bvox__free_charged(void *ptr, size_t bytes, size_t charged)
{
    if (!ptr) return;
    atomic_fetch_sub(&in_use_bytes, charged);
    if (is_big(bytes)) bvox__big_put(ptr, bytes, cache_limit());
    else free(ptr);
}

void bvox_free(void *ptr) { free(ptr); }

/* ---- small, unbudgeted allocations: libc semantics plus the fault hook ---- */

void *bvox__mem_alloc(size_t bytes)
{
    if (injected_failure()) return NULL;
    return malloc(bytes);
}

void *bvox__mem_zalloc(size_t count, size_t size)
{
    if (injected_failure()) return NULL;
    return calloc(count, size);
}

void *bvox__mem_resize(void *ptr, size_t bytes)
{
    if (injected_failure()) return NULL;
    return realloc(ptr, bytes);
}

char *bvox__mem_strndup(const char *s, size_t n)
{
    size_t len = strnlen(s, n);
    char *d = bvox__mem_alloc(len + 1);
    if (!d) return NULL;
    memcpy(d, s, len);
    d[len] = 0;
    return d;
}

char *bvox__mem_strdup(const char *s) { return bvox__mem_strndup(s, strlen(s)); }
