/*
 * label_samples.c — the samples of a label volume as a writer stores them
 * (labels_write.c, nifti_labels.c): the integer type they are written with
 * (the one asked for, checked against the largest label, or the smallest
 * unsigned one that holds it) and the conversion from bvox's uint32 labels,
 * a chunk at a time into one small buffer, never a second copy of the
 * volume, in little-endian or this CPU's byte order.
 */
#include "io.h"

#include <string.h>

#define CHUNK_SAMPLES ((size_t)1 << 16)

static bool host_big_endian(void)
{
    const uint16_t probe = 1;
    return *(const uint8_t *)&probe == 0;
}

bvox_status bvox__write_label_samples(bvox__sink *s, const uint32_t *labels, size_t n,
                                      bvox_dtype dtype, bool host_order)
{
    size_t elem = bvox_dtype_size(dtype);
    bool swap = !host_order && elem > 1 && host_big_endian();
    size_t chunk = n < CHUNK_SAMPLES ? n : CHUNK_SAMPLES, bytes = (chunk ? chunk : 1) * elem;
    bvox_status st;
    uint8_t *buf = bvox__alloc(bytes, false, "label samples", &st);
    if (!buf) return st;
    for (size_t i = 0; st == BVOX_OK && i < n; i += chunk) {
        size_t m = n - i < chunk ? n - i : chunk;
        for (size_t k = 0; k < m; k++) {
            uint64_t v = labels[i + k]; /* non-negative: the same bits in every integer type */
            uint8_t *p = buf + k * elem;
            switch (elem) {
            case 1: p[0] = (uint8_t)v; break;
            case 2: { uint16_t w = (uint16_t)v; memcpy(p, &w, 2); break; }
            case 4: { uint32_t w = (uint32_t)v; memcpy(p, &w, 4); break; }
            default: memcpy(p, &v, 8); break;
            }
            if (swap)
                for (size_t a = 0, b = elem - 1; a < b; a++, b--) {
                    uint8_t t = p[a];
                    p[a] = p[b];
                    p[b] = t;
                }
        }
        st = bvox__sink_write(s, buf, m * elem);
    }
    bvox__free(buf, bytes);
    return st;
}

bvox_status bvox__label_dtype(const char *path, const uint32_t *labels, size_t n, int dtype,
                              bvox_dtype *out, uint32_t *max_out)
{
    uint32_t max = 0;
    for (size_t i = 0; i < n; i++) max = labels[i] > max ? labels[i] : max;
    *max_out = max;
    if (dtype < 0) {
        *out = max <= UINT8_MAX ? BVOX_DT_U8 : max <= UINT16_MAX ? BVOX_DT_U16 : BVOX_DT_U32;
        return BVOX_OK;
    }
    if (dtype >= BVOX_DT_F32)
        return bvox__fail(BVOX_EINVAL, "%s: labels are written as integers, not %s", path,
                          dtype < BVOX_DT_COUNT ? bvox_dtype_name((bvox_dtype)dtype) : "?");
    static const uint64_t top[] = {UINT8_MAX,  INT8_MAX,   UINT16_MAX, INT16_MAX,
                                   UINT32_MAX, INT32_MAX,  UINT64_MAX, INT64_MAX};
    if (max > top[dtype])
        return bvox__fail(BVOX_EINVAL, "%s: label %lu does not fit %s samples", path,
                          (unsigned long)max, bvox_dtype_name((bvox_dtype)dtype));
    *out = (bvox_dtype)dtype;
    return BVOX_OK;
}
