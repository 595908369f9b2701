/*
 * binarize_stream.c — binarisation fed one slice at a time, for readers
 * that decode a file slice by slice (a .nii.gz inflated in blocks, TIFF
 * pages, PNG slices): reading a volume then needs its bits plus a buffer of
 * a few slices, not the whole gray volume (8 to 64 times the bits) and,
 * for gzip, the compressed file beside it.
 *
 * The result is identical to bvox__binarize's: the same predicate and
 * compare kernels (bvox__binarize_setup). Each slice's rows are compared 64
 * samples at a time into masks (bits = x), stored so that the 64 masks of
 * one block of 64 columns over 64 slices lie together:
 *     m[((y * nxb + xb) * 64) + (z & 63)]
 * (the layout pack_item in binarize.c uses on the stack). When 64 slices
 * (or the last ones) are in, each such 64 x 64 bit matrix is transposed into
 * the 64 columns' words of that z block; slices beyond nz are zero rows, so
 * the tail bits come out zero. The mask buffer holds 64 slices of bits:
 * 8 bytes per (x, y) column, whatever the sample type.
 *
 * Otsu's threshold needs every sample before the first comparison; readers
 * use bvox__binarize on the whole gray volume for it (bvox__bin_stream_ok).
 */
#include "binarize_kernels.h"

#include <stdlib.h>
#include <string.h>

struct bvox__bin_stream {
    bvox_volume *v;
    bvox__binpred pred;
    bvox__bin_blocks_fn blocks;
    bool use_pred;
    size_t nx, ny, nz, nxb, size;
    uint64_t *m;   /* nxb * ny * 64 masks */
    size_t m_bytes;
    size_t z;      /* slices received */
    const void *slice; /* the slices being compared (compare_rows) */
    size_t nslices;
    char name[256];
};

bool bvox__bin_stream_ok(const bvox_binarize *how)
{
    return !how || how->mode != BVOX_BIN_OTSU;
}

bvox_status bvox__bin_stream_begin(const bvox__gray *g, const bvox_binarize *how,
                                   const char *name, bvox__bin_stream **out)
{
    *out = NULL;
    if (!name) name = "volume";
    if (!bvox__bin_stream_ok(how))
        return bvox__fail(BVOX_EINVAL, "%s: Otsu's threshold cannot be streamed", name);
    bvox__bin_stream *s = bvox__mem_zalloc(1, sizeof *s);
    if (!s) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    snprintf(s->name, sizeof s->name, "%s", name);
    bvox__gray shape = *g;
    shape.data = NULL;
    bvox_status st = bvox__binarize_setup(&shape, how, name, &s->pred, &s->use_pred,
                                          &s->blocks, &s->v);
    if (st) {
        free(s);
        return st;
    }
    s->nx = (size_t)g->dims.nx;
    s->ny = (size_t)g->dims.ny;
    s->nz = (size_t)g->dims.nz;
    s->nxb = (s->nx + 63) / 64;
    s->size = bvox_dtype_size(g->dtype);
    if (s->use_pred) {
        /* nxb * ny * 64 words <= (nx + 63) * ny words: no overflow after check_dims */
        s->m_bytes = s->nxb * s->ny * 64 * sizeof(uint64_t);
        s->m = bvox__alloc(s->m_bytes, false, "binarisation buffer", &st);
        if (!s->m) {
            bvox_volume_destroy(s->v);
            free(s);
            bvox__error_prefix(name);
            return st;
        }
    }
    *out = s;
    return BVOX_OK;
}

/* Rows [begin, end) of the slices in s->slice, compared into the masks. */
static void compare_rows(void *ctx, int64_t begin, int64_t end)
{
    const bvox__bin_stream *s = ctx;
    size_t nfull = s->nx / 64, tail = s->nx % 64, row_bytes = s->nx * s->size;
    _Alignas(64) unsigned char pad[64 * 8];
    for (size_t k = 0; k < s->nslices; k++) {
        size_t zz = (s->z + k) & 63;
        const unsigned char *slice = (const unsigned char *)s->slice + k * s->ny * row_bytes;
        for (size_t y = (size_t)begin; y < (size_t)end; y++) {
            const unsigned char *row = slice + y * row_bytes;
            uint64_t *m = s->m + y * s->nxb * 64 + zz;
            if (nfull) s->blocks(row, nfull, &s->pred, m, 64);
            if (tail) { /* bits beyond the row become columns that are never stored */
                memcpy(pad, row + nfull * 64 * s->size, tail * s->size);
                memset(pad + tail * s->size, 0, (64 - tail) * s->size);
                s->blocks(pad, 1, &s->pred, m + nfull * 64, 64);
            }
        }
    }
}

/* Rows [begin, end): transpose the masks of z block zb (the slices
 * received so far in it, zc of them) into the columns' words. */
typedef struct flush_ctx {
    bvox__bin_stream *s;
    size_t zb, zc;
} flush_ctx;

static void flush_rows(void *ctx, int64_t begin, int64_t end)
{
    const flush_ctx *f = ctx;
    const bvox__bin_stream *s = f->s;
    size_t wpc = s->v->wpc;
    for (size_t y = (size_t)begin; y < (size_t)end; y++)
        for (size_t xb = 0; xb < s->nxb; xb++) {
            uint64_t *t = s->m + (y * s->nxb + xb) * 64;
            if (f->zc < 64) memset(t + f->zc, 0, (64 - f->zc) * sizeof(uint64_t));
            bvox__transpose64(t);
            size_t n = s->nx - xb * 64 < 64 ? s->nx - xb * 64 : 64;
            uint64_t *dst = s->v->words + (y * s->nx + xb * 64) * wpc + f->zb;
            for (size_t i = 0; i < n; i++) dst[i * wpc] = t[i];
        }
}

static int64_t rows_per_thread(const bvox__bin_stream *s, size_t slices)
{
    /* a thread is worth starting for about a million samples */
    size_t per_row = s->nx * (slices ? slices : 1);
    return (int64_t)(((size_t)1 << 20) / per_row + 1);
}

void bvox__bin_stream_slices(bvox__bin_stream *s, const void *data, size_t n)
{
    const unsigned char *p = data;
    if (n > s->nz - s->z) n = s->nz - s->z; /* never beyond the volume */
    while (n > 0) {
        size_t zz = s->z & 63, k = 64 - zz < n ? 64 - zz : n;
        if (s->use_pred) {
            s->slice = p;
            s->nslices = k;
            bvox__parallel_for((int64_t)s->ny, rows_per_thread(s, k), compare_rows, s);
        }
        s->z += k;
        p += k * s->nx * s->ny * s->size;
        n -= k;
        if (s->use_pred && ((s->z & 63) == 0 || s->z == s->nz)) {
            flush_ctx f = {s, (s->z - 1) / 64, s->z - (s->z - 1) / 64 * 64};
            bvox__parallel_for((int64_t)s->ny, rows_per_thread(s, 64), flush_rows, &f);
        }
    }
}

size_t bvox__bin_stream_slice_bytes(const bvox__bin_stream *s)
{
    return s->nx * s->ny * s->size;
}

static void release(bvox__bin_stream *s)
{
    if (s->m) bvox__free(s->m, s->m_bytes);
    free(s);
}

bvox_status bvox__bin_stream_finish(bvox__bin_stream *s, bvox_volume **out)
{
    *out = NULL;
    if (s->z != s->nz) {
        bvox_status st = bvox__fail(BVOX_EINVAL, "%s: %zu of %zu slices given", s->name, s->z,
                                    s->nz);
        bvox__bin_stream_abort(s);
        return st;
    }
    *out = s->v;
    release(s);
    return BVOX_OK;
}

void bvox__bin_stream_abort(bvox__bin_stream *s)
{
    if (!s) return;
    bvox_volume_destroy(s->v);
    release(s);
}
