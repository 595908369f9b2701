/*
 * big_buffers.c — large buffers (voxel words, label arrays, run lists) as
 * the library's own mappings, in whole 2 MiB huge pages, and a small cache
 * of freed ones for the next request.
 *
 * Why not libc's heap: a fresh buffer costs one page fault per 4 KiB page
 * written, and in a virtual machine a fault is dear. On the 2-vCPU EPYC VM
 * of 2026-12-07 writing a fresh 16 MiB took 43 ms in 4 KiB pages against
 * 1 ms in huge pages and 0.8 ms once mapped. glibc maps a request above its
 * mmap threshold afresh every time until a free raises the threshold, then
 * serves later ones from its heap; so a process's first few labellings of
 * the 512^3 atlas took 18-52 ms and the next ones 10 ms, and which calls
 * got which depended on the order of earlier frees. Here every buffer of
 * 1 MiB or more is whole huge pages (madvise: Debian's kernels give them
 * only on request), and a freed buffer is kept, up to a cap, and handed to
 * the next request it fits: a loop of the same operation touches fresh
 * memory once.
 *
 * The cache holds at most CACHE_SLOTS buffers and the limit alloc.c gives
 * (a share of the memory budget); beyond that the oldest go back to the
 * system. bvox_memory_trim() empties it. Cached bytes are not "in use"
 * (bvox_memory_in_use): no caller holds them.
 *
 * Under AddressSanitizer the part of a buffer past the request, and a whole
 * cached buffer, are poisoned, so overflows and uses after free are still
 * caught as with malloc's buffers.
 */
#include "core/big_buffers.h"

#include "bvox.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdint.h>
#include <sys/mman.h>

#if defined(__SANITIZE_ADDRESS__)
#define BIG_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define BIG_ASAN 1
#endif
#endif
#ifdef BIG_ASAN
#include <sanitizer/asan_interface.h>
#define POISON(p, n) ASAN_POISON_MEMORY_REGION((p), (n))
#define UNPOISON(p, n) ASAN_UNPOISON_MEMORY_REGION((p), (n))
#else
#define POISON(p, n) ((void)(p), (void)(n))
#define UNPOISON(p, n) ((void)(p), (void)(n))
#endif

#define HUGE_PAGE ((size_t)2 << 20)
#define SMALL_STEP ((size_t)64 << 10)
#define CACHE_SLOTS 16

typedef struct slot {
    void *p;
    size_t cap;
    uint64_t age; /* when it was cached: the oldest goes back first */
} slot;

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static slot cache[CACHE_SLOTS];
static int ncached;
static size_t cached_bytes;
static uint64_t clock_ticks;

/* The mapping's size for a request: whole huge pages from 1 MiB on (a huge
 * page half used costs less than the faults of 256 small ones), else 64 KiB
 * steps. Depends on bytes alone, so that put finds the size get mapped. */
static size_t capacity(size_t bytes)
{
    size_t step = bytes >= HUGE_PAGE / 2 ? HUGE_PAGE : SMALL_STEP;
    return (bytes + step - 1) / step * step;
}

/* The bytes a caller may touch: bvox__alloc's buffers are whole 64-byte
 * lines (vector kernels read a line at a time). */
static size_t usable(size_t bytes) { return (bytes + 63) & ~(size_t)63; }

/* A new mapping of cap bytes, aligned to a huge page when cap is whole
 * huge pages (the kernel can only back aligned 2 MiB with one). */
static void *map_new(size_t cap)
{
    size_t align = cap % HUGE_PAGE == 0 ? HUGE_PAGE : 0;
    size_t len = cap + align;
    if (len < cap) return NULL;
    char *m = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) return NULL;
    if (!align) return m;
    char *p = (char *)(((uintptr_t)m + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1));
    if (p > m) munmap(m, (size_t)(p - m));
    if (m + len > p + cap) munmap(p + cap, (size_t)(m + len - (p + cap)));
#ifdef MADV_HUGEPAGE
    (void)madvise(p, cap, MADV_HUGEPAGE); /* fails harmlessly where THP is off */
#endif
    return p;
}

/* Remove slot i (lock held); its buffer is the caller's. */
static slot take_slot(int i)
{
    slot s = cache[i];
    cache[i] = cache[--ncached];
    cached_bytes -= s.cap;
    return s;
}

/* Cached buffers out until the cache holds at most keep_bytes in at most
 * keep_slots slots, oldest first, into out[] (lock held); returns how many. */
static int evict(size_t keep_bytes, int keep_slots, slot out[CACHE_SLOTS])
{
    int n = 0;
    while (ncached > 0 && (cached_bytes > keep_bytes || ncached > keep_slots)) {
        int old = 0;
        for (int i = 1; i < ncached; i++)
            if (cache[i].age < cache[old].age) old = i;
        out[n++] = take_slot(old);
    }
    return n;
}

static void unmap_all(const slot *s, int n)
{
    for (int i = 0; i < n; i++) munmap(s[i].p, s[i].cap);
}

void *bvox__big_get(size_t bytes, bool *fresh)
{
    size_t cap = capacity(bytes);
    /* the smallest cached buffer of this exact size class first; a bigger
     * one only up to twice the size, so that a small request does not take
     * the buffer the next big one needs */
    pthread_mutex_lock(&lock);
    int best = -1;
    for (int i = 0; i < ncached; i++)
        if (cache[i].cap >= cap && cache[i].cap / 2 <= cap &&
            (best < 0 || cache[i].cap < cache[best].cap))
            best = i;
    if (best >= 0) {
        slot s = take_slot(best);
        pthread_mutex_unlock(&lock);
        POISON(s.p, s.cap);
        UNPOISON(s.p, usable(bytes));
        *fresh = false;
        return s.p;
    }
    pthread_mutex_unlock(&lock);
    void *p = map_new(cap);
    if (!p) {
        /* the cache's buffers may be what the system lacks */
        bvox_memory_trim();
        p = map_new(cap);
        if (!p) return NULL;
    }
    POISON(p, cap);
    UNPOISON(p, usable(bytes));
    *fresh = true;
    return p;
}

void bvox__big_put(void *p, size_t bytes, size_t limit)
{
    if ((uintptr_t)p % 4096) {
        /* not one of ours: bvox__free was given another size than
         * bvox__alloc (a bug of the caller); unmapping it would corrupt
         * the heap */
        fprintf(stderr, "bvox: internal error: a buffer freed with the wrong size\n");
        abort();
    }
    size_t cap = capacity(bytes);
    POISON(p, cap);
    if (cap > limit) {
        munmap(p, cap);
        return;
    }
    slot out[CACHE_SLOTS];
    pthread_mutex_lock(&lock);
    int n = evict(limit - cap, CACHE_SLOTS - 1, out);
    cache[ncached++] = (slot){p, cap, ++clock_ticks};
    cached_bytes += cap;
    pthread_mutex_unlock(&lock);
    unmap_all(out, n);
}

size_t bvox__big_cached(void)
{
    pthread_mutex_lock(&lock);
    size_t b = cached_bytes;
    pthread_mutex_unlock(&lock);
    return b;
}

void bvox_memory_trim(void)
{
    slot out[CACHE_SLOTS];
    pthread_mutex_lock(&lock);
    int n = evict(0, 0, out);
    pthread_mutex_unlock(&lock);
    unmap_all(out, n);
}

void bvox__big_fit(size_t limit)
{
    slot out[CACHE_SLOTS];
    pthread_mutex_lock(&lock);
    int n = evict(limit, CACHE_SLOTS, out);
    pthread_mutex_unlock(&lock);
    unmap_all(out, n);
}
