/*
 * tiff_memory.c — libtiff on a memory buffer, shared by the TIFF volume
 * reader (tiff.c) and the TIFF section reader (recon/section_tiff.c).
 *
 * TIFFClientOpenExt gets read/seek/size/map callbacks over the caller's
 * bytes (nothing is written; the "map" hands libtiff the buffer itself),
 * per-handle message handlers that keep libtiff's first error (never
 * printed: the library never prints) for the caller to quote, and a cap on
 * libtiff's single allocations at the memory budget.
 */
#include "io.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <tiffio.h>

static tmsize_t src_read(thandle_t h, void *buf, tmsize_t n)
{
    bvox__tiff_src *m = h;
    if (n <= 0 || m->pos >= m->size) return 0;
    uint64_t k = m->size - m->pos;
    if ((uint64_t)n < k) k = (uint64_t)n;
    memcpy(buf, m->data + m->pos, (size_t)k);
    m->pos += k;
    return (tmsize_t)k;
}

static tmsize_t src_write(thandle_t h, void *buf, tmsize_t n) { return -1; }

static toff_t src_seek(thandle_t h, toff_t off, int whence)
{
    bvox__tiff_src *m = h;
    if (whence == SEEK_SET) return m->pos = off;
    uint64_t base = whence == SEEK_CUR ? m->pos : m->size;
    int64_t d = (int64_t)off; /* SEEK_CUR / SEEK_END offsets may be negative */
    if (d < 0) {
        uint64_t back = (uint64_t)0 - (uint64_t)d;
        if (back > base) return (toff_t)-1;
        m->pos = base - back;
    } else if (__builtin_add_overflow(base, (uint64_t)d, &m->pos)) {
        return (toff_t)-1;
    }
    return m->pos;
}

static int src_close(thandle_t h) { return 0; }
static toff_t src_size(thandle_t h) { return ((bvox__tiff_src *)h)->size; }

static int src_map(thandle_t h, void **base, toff_t *size)
{
    bvox__tiff_src *m = h; /* libtiff only reads mapped data (files are mapped read-only) */
    *base = (void *)m->data;
    *size = m->size;
    return 1;
}

static void src_unmap(thandle_t h, void *base, toff_t size) {}

/* Keep libtiff's first error (usually the cause); returning 1 stops libtiff
 * from also calling the process-wide handlers, which print. */
static int on_error(TIFF *tif, void *user, const char *module, const char *fmt, va_list ap)
{
    bvox__tiff_src *e = user;
    if (!e->have_err) {
        vsnprintf(e->err, sizeof e->err, fmt, ap);
        e->have_err = true;
    }
    return 1;
}

static int on_warning(TIFF *tif, void *user, const char *module, const char *fmt, va_list ap)
{
    return 1;
}

const char *bvox__tiff_error(const bvox__tiff_src *src, const char *fallback)
{
    return src->have_err ? src->err : fallback;
}

bvox_status bvox__tiff_open_memory(const uint8_t *data, size_t size, const char *name,
                                   bvox__tiff_src *src, TIFF **out)
{
    *out = NULL;
    memset(src, 0, sizeof *src);
    src->data = data;
    src->size = size;
    TIFFOpenOptions *o = TIFFOpenOptionsAlloc();
    if (!o) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    TIFFOpenOptionsSetErrorHandlerExtR(o, on_error, src);
    TIFFOpenOptionsSetWarningHandlerExtR(o, on_warning, src);
    /* libtiff's own buffers (strip tables, codec state) stay within the budget. */
    size_t budget = bvox_memory_budget();
    TIFFOpenOptionsSetMaxSingleMemAlloc(o, (tmsize_t)(budget > ((size_t)1 << 62) ? (size_t)1 << 62
                                                                               : budget));
    TIFF *tif = TIFFClientOpenExt(name, "r", src, src_read, src_write, src_seek, src_close,
                                  src_size, src_map, src_unmap, o);
    TIFFOpenOptionsFree(o);
    if (!tif)
        return bvox__fail(BVOX_EFORMAT, "%s: not a readable TIFF file (%s)", name,
                          bvox__tiff_error(src, "bad header"));
    *out = tif;
    return BVOX_OK;
}
