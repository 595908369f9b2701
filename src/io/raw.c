/*
 * raw.c — headerless voxel files (.raw): samples x fastest, then y, then z,
 * after an optional number of bytes to skip. Nothing in the file says what it
 * holds, so the read options must: dimensions, element type, byte order,
 * offset, spacing and unit. Writing produces one byte per voxel, 0 or 1.
 *
 * Like NIfTI, the samples are not copied: the gray volume points into the
 * caller's buffer and the binariser reads them in place.
 */
#include "io.h"

#include <math.h>
#include <string.h>

/* Decode into a gray volume pointing into data (no copy). */
static bvox_status raw_gray_memory(const uint8_t *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox__gray *gout)
{
    bvox__gray_init(gout);
    if (!name) name = "input";
    if (!opts || opts->raw_dims.nx == 0 || opts->raw_dims.ny == 0 || opts->raw_dims.nz == 0)
        return bvox__fail(BVOX_EINVAL, "%s: raw needs --dims NX,NY,NZ", name);
    bvox_dims d = opts->raw_dims;
    size_t words_bytes;
    bvox_status st = bvox__check_dims(d, name, &words_bytes);
    if (st) return st;
    size_t elem = bvox_dtype_size(opts->raw_dtype);
    if (elem == 0)
        return bvox__fail(BVOX_EINVAL, "%s: unknown raw element type %d", name,
                          (int)opts->raw_dtype);

    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = d;
    g.dtype = opts->raw_dtype;
    for (int i = 0; i < 3; i++) {
        double s = opts->raw_spacing[i];
        if (s == 0.0) s = 1.0; /* 0 means "not given" */
        if (!(s > 0) || !isfinite(s))
            return bvox__fail(BVOX_EINVAL, "%s: raw voxel size %g must be positive", name, s);
        g.geom.spacing[i] = s;
    }
    const char *unit = opts->raw_unit ? opts->raw_unit : "";
    if (strlen(unit) >= sizeof g.geom.unit)
        return bvox__fail(BVOX_EINVAL, "%s: unit name '%s' is too long", name, unit);
    strcpy(g.geom.unit, unit);

    /* n * elem cannot overflow with every axis <= 65535, but stay safe. */
    size_t n, need;
    if (!bvox__mul_size((size_t)d.nx, (size_t)d.ny, &n) || !bvox__mul_size(n, (size_t)d.nz, &n) ||
        !bvox__mul_size(n, elem, &need))
        return bvox__fail(BVOX_ETOOBIG, "%s: raw dimensions overflow", name);
    if (opts->raw_offset > size || need > size - opts->raw_offset)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: raw file is too small: %ld x %ld x %ld %s voxels after an offset "
                          "of %llu need %llu bytes, the file has %zu",
                          name, (long)d.nx, (long)d.ny, (long)d.nz,
                          bvox_dtype_name(opts->raw_dtype), (unsigned long long)opts->raw_offset,
                          (unsigned long long)opts->raw_offset + (unsigned long long)need, size);

    const uint16_t probe = 1;
    bool host_big = *(const uint8_t *)&probe == 0;
    g.data = data + opts->raw_offset;
    g.byteswap = elem > 1 && (opts->raw_big_endian != 0) != host_big;
    *gout = g;
    return BVOX_OK;
}

static bvox_status raw_read_memory(const uint8_t *data, size_t size, const char *name,
                                   const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "input";
    bvox__gray g;
    bvox_status st = raw_gray_memory(data, size, name, opts, &g);
    if (st) return st;
    st = bvox__binarize(&g, &opts->binarize, name, out);
    bvox__gray_release(&g);
    return st;
}

static bvox_status raw_write_path(const char *path, const bvox_volume *vol,
                                  const bvox_write_opts *opts)
{
    if (opts && opts->raw_bits != 8 && opts->raw_bits != 0)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: raw output is one byte per voxel (raw_bits 8), not %d", path,
                          opts->raw_bits);
    return bvox__write_byte_slices(path, vol, false, NULL, 0);
}

static const char *const raw_extensions[] = {".raw", NULL};

const bvox__format bvox__format_raw = {
    "raw", raw_extensions, NULL, raw_read_memory, NULL, raw_write_path, NULL, NULL,
    raw_gray_memory,
};
