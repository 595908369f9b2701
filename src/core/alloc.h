/*
 * alloc.h — the one allocation seam (alloc.c). Every heap allocation of the
 * library and of the viewer's core goes through it, so that a test can fail
 * the n-th one (bvox__alloc_fail_after) and check that every error path
 * returns a clean BVOX_ENOMEM, leaks nothing and leaves no output file.
 *
 * Two kinds:
 *  - bvox__alloc/bvox__free: large buffers (voxel words, decoded images,
 *    file contents). Budget-checked, counted in bvox_memory_in_use(),
 *    64-byte aligned; freed with bvox__free and the same byte count.
 *  - bvox__mem_*: small things (structs, lists, strings). Not budgeted or
 *    counted, but fault-injectable through the same countdown. They return
 *    NULL on failure like their libc namesakes and set no message (the
 *    caller knows what it was allocating); release with free() or bvox_free().
 *
 * This is the only header of src/ the viewer includes. tests/check_alloc.sh
 * fails the build's tests if a raw libc allocation appears anywhere else.
 */
#ifndef BVOX_CORE_ALLOC_H
#define BVOX_CORE_ALLOC_H

#include "bvox.h"

#include <stdbool.h>
#include <stddef.h>

/* Budget-checked, 64-byte aligned, zero-filled if zero != 0. On failure sets
 * the message (what names the buffer) and returns NULL with *status set. */
void *bvox__alloc(size_t bytes, bool zero, const char *what, bvox_status *status);
void bvox__free(void *ptr, size_t bytes);
/* Free a buffer of bvox__alloc(bytes) of which only `charged` bytes are
 * still counted against the budget (the rest was given back earlier with
 * bvox__budget_refund). bvox__free needs the size the buffer was allocated
 * with: it tells where the buffer came from. */
void bvox__free_charged(void *ptr, size_t bytes, size_t charged);

/* malloc/calloc/realloc/strdup/strndup through the fault hook. A failed
 * bvox__mem_resize leaves ptr allocated, as realloc does. */
void *bvox__mem_alloc(size_t bytes);
void *bvox__mem_zalloc(size_t count, size_t size);
void *bvox__mem_resize(void *ptr, size_t bytes);
char *bvox__mem_strdup(const char *s);
char *bvox__mem_strndup(const char *s, size_t n);

/* Test hook: make the n-th following allocation (of either kind) fail with
 * BVOX_ENOMEM (n = 1: the next one); 0 disables. */
void bvox__alloc_fail_after(long n);
/* Allocations still to go before the armed failure: 0 once it has
 * happened (or when off). Read before disarming, it tells a test whether the
 * call reached the failing allocation. */
long bvox__alloc_fail_pending(void);

#endif
