/*
 * unpack.c — the inverse of bvox__binarize for writers: a block of up to 64
 * slices (one word per column) as bytes, x fastest, then y, then z.
 *
 * Per y and per 64 columns along x, the 64 words (rows = x, bits = z) are
 * transposed into rows = z, bits = x, and each row's bits are spread into
 * bytes eight at a time through a 256-entry table (byte b -> eight bytes 0/1,
 * times `one`: no carries since each byte is 0 or 1). Rows of y are
 * independent, so they are split over the worker threads.
 *
 * bvox__write_byte_slices: the whole volume as such bytes after a header,
 * through the sink (NIfTI and raw writers), 64 slices at a time.
 * bvox__unpack_columns is the z-fastest order (NumPy's): each column's words
 * expand straight into its run of nz bytes.
 */
#include "io.h"
#include "common/bits.h"

#include <string.h>

/* spread[b]: byte k is bit k of b */
#define E(b)                                                                               \
    ((((b) >> 0) & 1ull) | ((((b) >> 1) & 1ull) << 8) | ((((b) >> 2) & 1ull) << 16) |     \
     ((((b) >> 3) & 1ull) << 24) | ((((b) >> 4) & 1ull) << 32) |                           \
     ((((b) >> 5) & 1ull) << 40) | ((((b) >> 6) & 1ull) << 48) | ((((b) >> 7) & 1ull) << 56))
#define R4(b) E(b), E((b) + 1), E((b) + 2), E((b) + 3)
#define R16(b) R4(b), R4((b) + 4), R4((b) + 8), R4((b) + 12)
#define R64(b) R16(b), R16((b) + 16), R16((b) + 32), R16((b) + 48)
static const uint64_t spread[256] = {R64(0), R64(64), R64(128), R64(192)};

typedef struct unpack_ctx {
    const bvox_volume *vol;
    size_t zb, n;
    uint64_t one; /* the byte value, for the multiply */
    uint8_t *dst;
} unpack_ctx;

/* 64 bits -> `len` bytes (0 or one). */
static inline void expand(uint64_t bits, uint64_t one, size_t len, uint8_t *out)
{
    if (len == 64) {
        for (unsigned j = 0; j < 8; j++) {
            uint64_t v = spread[(bits >> (8 * j)) & 0xFF] * one;
            memcpy(out + 8 * j, &v, 8);
        }
        return;
    }
    uint8_t tmp[64];
    for (unsigned j = 0; j < 8; j++) {
        uint64_t v = spread[(bits >> (8 * j)) & 0xFF] * one;
        memcpy(tmp + 8 * j, &v, 8);
    }
    memcpy(out, tmp, len);
}

static void unpack_rows(void *ctx, int64_t begin, int64_t end)
{
    const unpack_ctx *c = ctx;
    const bvox_volume *v = c->vol;
    size_t nx = (size_t)v->nx, ny = (size_t)v->ny, wpc = v->wpc;
    _Alignas(64) uint64_t m[64];
    for (int64_t y = begin; y < end; y++) {
        for (size_t x0 = 0; x0 < nx; x0 += 64) {
            size_t width = nx - x0 < 64 ? nx - x0 : 64;
            const uint64_t *src = v->words + ((size_t)y * nx + x0) * wpc + c->zb;
            for (size_t i = 0; i < width; i++) m[i] = src[i * wpc];
            if (width < 64) memset(m + width, 0, (64 - width) * sizeof m[0]);
            bvox__transpose64(m);
            for (size_t z = 0; z < c->n; z++)
                expand(m[z], c->one, width, c->dst + (z * ny + (size_t)y) * nx + x0);
        }
    }
}

void bvox__unpack_slices(const bvox_volume *vol, int32_t z0, int32_t n, uint8_t one,
                         uint8_t *dst)
{
    BVOX_ASSERT(z0 >= 0 && z0 % 64 == 0 && n >= 1 && n <= 64 && z0 + n <= vol->nz);
    unpack_ctx c = {vol, (size_t)z0 / 64, (size_t)n, one, dst};
    /* a thread is worth starting for about a million voxels */
    int64_t per_row = (int64_t)vol->nx * n;
    bvox__parallel_for(vol->ny, ((int64_t)1 << 20) / per_row + 1, unpack_rows, &c);
}

bvox_status bvox__write_byte_slices(const char *path, const bvox_volume *vol, int gz,
                                    const void *header, size_t header_size)
{
    int32_t chunk = vol->nz < 64 ? vol->nz : 64;
    size_t slice = (size_t)vol->nx * (size_t)vol->ny, bytes;
    if (!bvox__mul_size(slice, (size_t)chunk, &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: slices too large", path);
    bvox_status st;
    uint8_t *buf = bvox__alloc(bytes, false, "slice buffer", &st);
    if (!buf) {
        bvox__error_prefix(path);
        return st;
    }
    bvox__sink s;
    int mode = gz & ~BVOX__SINK_PLAIN_HEADER;
    st = bvox__sink_open(path, gz & BVOX__SINK_PLAIN_HEADER ? 0 : mode, &s);
    if (st == BVOX_OK && header_size) st = bvox__sink_write(&s, header, header_size);
    if (st == BVOX_OK && mode) st = bvox__sink_compress(&s, mode);
    for (int32_t z0 = 0; st == BVOX_OK && z0 < vol->nz; z0 += 64) {
        int32_t n = vol->nz - z0 < 64 ? vol->nz - z0 : 64;
        bvox__unpack_slices(vol, z0, n, 1, buf);
        st = bvox__sink_write(&s, buf, slice * (size_t)n);
        if (st == BVOX_OK) st = bvox__progress_steps(z0 + n, vol->nz);
    }
    bvox__free(buf, bytes);
    if (st == BVOX_OK) return bvox__sink_commit(&s);
    bvox__sink_abort(&s);
    return st;
}

typedef struct columns_ctx {
    const bvox_volume *vol;
    uint8_t *dst;
} columns_ctx;

/* Columns in the destination's order: c = x * ny + y. */
static void unpack_column_range(void *ctx, int64_t begin, int64_t end)
{
    const columns_ctx *c = ctx;
    const bvox_volume *v = c->vol;
    size_t ny = (size_t)v->ny, nz = (size_t)v->nz, wpc = v->wpc;
    for (int64_t i = begin; i < end; i++) {
        size_t x = (size_t)i / ny, y = (size_t)i % ny;
        const uint64_t *col = v->words + (y * (size_t)v->nx + x) * wpc;
        uint8_t *out = c->dst + (size_t)i * nz;
        for (size_t w = 0; w < wpc; w++) {
            size_t len = nz - w * 64 < 64 ? nz - w * 64 : 64;
            expand(col[w], 1, len, out + w * 64);
        }
    }
}

void bvox__unpack_columns(const bvox_volume *vol, uint8_t *dst)
{
    columns_ctx c = {vol, dst};
    int64_t columns = (int64_t)vol->nx * vol->ny;
    bvox__parallel_for(columns, ((int64_t)1 << 20) / vol->nz + 1, unpack_column_range, &c);
}
