/*
 * count.c — measures that are whole-word reductions: count (popcount),
 * count of an intersection, bounding box, equality, and bvox_info.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct count_job {
    const uint64_t *a, *b;
    const bvox__kernels *k;
    uint64_t total; /* summed atomically by the threads */
    int64_t nwords;
} count_job;

#define COUNT_CHUNK 65536 /* words per unit of work: 512 KiB */

static void count_range(void *ctx, int64_t begin, int64_t end)
{
    count_job *j = ctx;
    uint64_t total = 0;
    for (int64_t c = begin; c < end; c++) {
        size_t w0 = (size_t)c * COUNT_CHUNK;
        size_t left = (size_t)j->nwords - w0;
        size_t n = left < COUNT_CHUNK ? left : COUNT_CHUNK;
        total += j->b ? j->k->popcount_and(j->a + w0, j->b + w0, n) : j->k->popcount(j->a + w0, n);
    }
    __atomic_fetch_add(&j->total, total, __ATOMIC_RELAXED);
}

static int64_t count_words(const uint64_t *a, const uint64_t *b, size_t n)
{
    count_job j = {a, b, bvox__simd(), 0, (int64_t)n};
    int64_t chunks = (int64_t)((n + COUNT_CHUNK - 1) / COUNT_CHUNK);
    bvox__parallel_for(chunks, 4, count_range, &j);
    return (int64_t)j.total;
}

int64_t bvox_volume_count(const bvox_volume *vol)
{
    return count_words(vol->words, NULL, vol->nwords);
}

int64_t bvox_volume_count_and(const bvox_volume *a, const bvox_volume *b)
{
    if (a->nx != b->nx || a->ny != b->ny || a->nz != b->nz) return -1;
    return count_words(a->words, b->words, a->nwords);
}

int bvox_volume_bbox(const bvox_volume *vol, bvox_box *box)
{
    memset(box, 0, sizeof *box);
    /* One pass: columns with any bit give the x/y range, and the OR of all
     * columns (a z profile of wpc words) gives the z range. */
    uint64_t profile_small[64];
    uint64_t *profile = profile_small;
    size_t wpc = vol->wpc;
    uint64_t *heap = NULL;
    if (wpc > 64) {
        heap = bvox__mem_zalloc(wpc, sizeof *heap);
        if (!heap) return -1;
        profile = heap;
    } else {
        memset(profile_small, 0, sizeof profile_small);
    }
    int32_t x0 = vol->nx, x1 = -1, y0 = vol->ny, y1 = -1;
    for (int32_t y = 0; y < vol->ny; y++) {
        for (int32_t x = 0; x < vol->nx; x++) {
            const uint64_t *c = bvox__column_c(vol, x, y);
            uint64_t any = 0;
            for (size_t k = 0; k < wpc; k++) {
                any |= c[k];
                profile[k] |= c[k];
            }
            if (!any) continue;
            if (x < x0) x0 = x;
            if (x > x1) x1 = x;
            if (y < y0) y0 = y;
            y1 = y;
        }
    }
    int found = x1 >= 0;
    if (found) {
        size_t k0 = 0, k1 = wpc - 1;
        while (!profile[k0]) k0++;
        while (!profile[k1]) k1--;
        *box = (bvox_box){x0, y0, (int32_t)(k0 * 64 + (size_t)__builtin_ctzll(profile[k0])),
                          x1 + 1, y1 + 1,
                          (int32_t)(k1 * 64 + 64 - (size_t)__builtin_clzll(profile[k1]))};
    }
    free(heap);
    return found;
}

int bvox_volume_equal(const bvox_volume *a, const bvox_volume *b)
{
    return a->nx == b->nx && a->ny == b->ny && a->nz == b->nz &&
           memcmp(a->words, b->words, a->nwords * sizeof(uint64_t)) == 0;
}

bvox_status bvox_info_compute(const bvox_volume *vol, bvox_info *info)
{
    memset(info, 0, sizeof *info);
    info->dims = bvox_volume_dims(vol);
    info->geometry = vol->geom;
    info->count = bvox_volume_count(vol);
    const double *s = vol->geom.spacing;
    info->volume = (double)info->count * s[0] * s[1] * s[2];
    int found = bvox_volume_bbox(vol, &info->bbox);
    if (found < 0) return bvox__fail(BVOX_ENOMEM, "out of memory computing the bounding box");
    info->empty = !found;
    return BVOX_OK;
}
