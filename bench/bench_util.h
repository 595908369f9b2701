/*
 * bench_util.h — pieces the benchmarks share: a memcpy baseline split over
 * threads the way the library splits its work, and the nearest-neighbour
 * resampling that turns the AAL atlas into an n^3 "real object".
 * Header-only (static functions): each benchmark is one .c file.
 */
#ifndef BVOX_BENCH_UTIL_H
#define BVOX_BENCH_UTIL_H

#include "internal.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

typedef struct copy_part {
    uint8_t *dst;
    const uint8_t *src;
    size_t n;
} copy_part;

static inline void *copy_run(void *p)
{
    copy_part *c = p;
    memcpy(c->dst, c->src, c->n);
    return NULL;
}

static inline void parallel_memcpy(void *dst, const void *src, size_t n, int threads)
{
    copy_part parts[64];
    pthread_t tid[64];
    if (threads > 64) threads = 64;
    for (int t = 0; t < threads; t++) {
        size_t a = n * (size_t)t / (size_t)threads, b = n * (size_t)(t + 1) / (size_t)threads;
        parts[t] = (copy_part){(uint8_t *)dst + a, (const uint8_t *)src + a, b - a};
    }
    for (int t = 1; t < threads; t++) pthread_create(&tid[t], NULL, copy_run, &parts[t]);
    copy_run(&parts[0]);
    for (int t = 1; t < threads; t++) pthread_join(tid[t], NULL);
}

/* Nearest-neighbour resampling of src to n^3: voxel i takes source voxel
 * floor((i + 1/2) * ns / n) on each axis. Built a word at a time. */
static inline bvox_volume *resample(const bvox_volume *src, int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    int32_t *zmap = malloc((size_t)n * sizeof *zmap);
    if (!zmap) {
        bvox_volume_destroy(v);
        return NULL;
    }
    for (int i = 0; i < n; i++) zmap[i] = (int32_t)(((double)i + 0.5) * src->nz / n);
    for (int y = 0; y < n; y++) {
        int32_t sy = (int32_t)(((double)y + 0.5) * src->ny / n);
        for (int x = 0; x < n; x++) {
            int32_t sx = (int32_t)(((double)x + 0.5) * src->nx / n);
            const uint64_t *sc = bvox__column_c(src, sx, sy);
            uint64_t *dc = bvox__column(v, x, y);
            for (size_t k = 0; k < v->wpc; k++) {
                uint64_t w = 0;
                for (int b = 0; b < 64 && (int)k * 64 + b < n; b++) {
                    int32_t sz = zmap[k * 64 + (size_t)b];
                    w |= ((sc[sz >> 6] >> (sz & 63)) & 1) << b;
                }
                dc[k] = w;
            }
        }
    }
    free(zmap);
    return v;
}

#endif
