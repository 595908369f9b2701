/*
 * big_buffers.h — where bvox__alloc (alloc.c) gets its large buffers: the
 * library's own mappings, in whole huge pages, and a small cache of freed
 * ones handed to the next request (big_buffers.c).
 */
#ifndef BVOX_CORE_BIG_BUFFERS_H
#define BVOX_CORE_BIG_BUFFERS_H

#include <stdbool.h>
#include <stddef.h>

/* Requests of at least this many bytes come from here; smaller ones from
 * libc's heap. */
#define BVOX__BIG_MIN ((size_t)256 << 10)

/* A buffer of at least bytes (>= BVOX__BIG_MIN), page aligned; NULL when the
 * system has no memory left. *fresh: its pages have never been written
 * (they read as zeros). */
void *bvox__big_get(size_t bytes, bool *fresh);
/* Give back a buffer of bvox__big_get(bytes): kept for reuse while the cache
 * stays within limit bytes (older buffers go first), else unmapped. */
void bvox__big_put(void *p, size_t bytes, size_t limit);
/* The bytes the cache holds now. */
size_t bvox__big_cached(void);
/* Unmap the oldest cached buffers until the cache holds at most limit
 * bytes. */
void bvox__big_fit(size_t limit);

#endif
