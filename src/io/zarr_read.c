/*
 * zarr_read.c — one Zarr v2 array opened for reading and read box by box
 * (the interface in zarr.h): only metadata at open, then each box read
 * decodes just the chunks it touches, one at a time into one buffer.
 *
 * Any integer/float dtype or bool, C order, compressor none/zlib/gzip/blosc.
 * Every chunk must decode to exactly the chunk's bytes (edge chunks are full
 * size, as Zarr writes them); a missing chunk is the fill value only when
 * the metadata gives one. Errors name the chunk file.
 */
#include "zarr.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <blosc.h>
#include <zlib.h>

/* Blosc chunk -> exactly n bytes: 0 ok, -1 corrupt, -2 wrong size. The
 * header is validated against the buffer before decoding (a lying header
 * must not make Blosc read or write out of bounds). */
static int unblosc_exact(const uint8_t *src, size_t size, uint8_t *dst, size_t n)
{
    size_t nbytes = 0;
    if (size < BLOSC_MIN_HEADER_LENGTH || blosc_cbuffer_validate(src, size, &nbytes) != 0)
        return -1;
    if (nbytes != n) return -2;
    if (n == 0) return 0;
    int got = blosc_decompress_ctx(src, dst, n, 1);
    return got < 0 ? -1 : (size_t)got != n ? -2 : 0;
}

/* ---------------------------------------------------------- helpers */

static bool exists(const char *dir, const char *file)
{
    char p[4200];
    if (snprintf(p, sizeof p, "%s/%s", dir, file) >= (int)sizeof p) return false;
    struct stat sb;
    return stat(p, &sb) == 0;
}

/* Inflate exactly n bytes (zlib or gzip by window_bits): 0 ok, -1 corrupt,
 * -2 the data decodes to more or fewer than n bytes. */
static int inflate_exact(const uint8_t *src, size_t size, int window_bits, uint8_t *dst, size_t n)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, window_bits) != Z_OK) return -1;
    z.next_in = (Bytef *)src;
    z.next_out = dst;
    size_t in_left = size, out_left = n;
    int rc = Z_OK;
    uint8_t extra;
    while (rc == Z_OK) {
        uInt in = in_left > (1u << 30) ? 1u << 30 : (uInt)in_left;
        uInt out = out_left > (1u << 30) ? 1u << 30 : (uInt)out_left;
        if (out == 0) { /* full: any more output means the chunk is too big */
            z.next_out = &extra;
            out = 1;
        }
        z.avail_in = in;
        z.avail_out = out;
        rc = inflate(&z, Z_NO_FLUSH);
        in_left -= in - z.avail_in;
        if (z.next_out == &extra + 1) {
            inflateEnd(&z);
            return -2;
        }
        if (out_left) out_left -= out - z.avail_out;
        if (rc == Z_BUF_ERROR && in_left == 0) break;
        if (rc == Z_BUF_ERROR) rc = Z_OK; /* no progress possible only when input is out */
    }
    inflateEnd(&z);
    if (rc != Z_STREAM_END) return rc == Z_BUF_ERROR ? (out_left ? -2 : -1) : -1;
    return out_left ? -2 : 0;
}

/* The fill value as one sample of dtype t, in file byte order (swap). */
static bool fill_sample(double v, bvox_dtype t, bool swap, uint8_t out[8])
{
    size_t e = bvox_dtype_size(t);
    bool is_float = t == BVOX_DT_F32 || t == BVOX_DT_F64;
    if (!is_float) {
        static const double lo[] = {0, -128, 0, -32768, 0, -2147483648.0, 0, -9223372036854775808.0};
        static const double hi[] = {255, 127, 65535, 32767, 4294967295.0, 2147483647.0,
                                    18446744073709551615.0, 9223372036854775807.0};
        if (!(v == floor(v)) || v < lo[t] || v > hi[t]) return false;
    }
    switch (t) {
    case BVOX_DT_U8: out[0] = (uint8_t)v; break;
    case BVOX_DT_I8: { int8_t x = (int8_t)v; memcpy(out, &x, 1); break; }
    case BVOX_DT_U16: { uint16_t x = (uint16_t)v; memcpy(out, &x, 2); break; }
    case BVOX_DT_I16: { int16_t x = (int16_t)v; memcpy(out, &x, 2); break; }
    case BVOX_DT_U32: { uint32_t x = (uint32_t)v; memcpy(out, &x, 4); break; }
    case BVOX_DT_I32: { int32_t x = (int32_t)v; memcpy(out, &x, 4); break; }
    case BVOX_DT_U64: { uint64_t x = v >= 18446744073709551615.0 ? UINT64_MAX : (uint64_t)v;
                        memcpy(out, &x, 8); break; }
    case BVOX_DT_I64: { int64_t x = v >= 9223372036854775807.0 ? INT64_MAX : (int64_t)v;
                        memcpy(out, &x, 8); break; }
    case BVOX_DT_F32: { float x = (float)v; memcpy(out, &x, 4); break; }
    default: memcpy(out, &v, 8); break;
    }
    if (swap)
        for (size_t i = 0; i < e / 2; i++) {
            uint8_t c = out[i];
            out[i] = out[e - 1 - i];
            out[e - 1 - i] = c;
        }
    return true;
}


/* ---------------------------------------------------------- the array */

struct bvox__zarr {
    char *arr;          /* the array folder */
    char *name;         /* the user's path, for messages */
    bvox__zarr_meta m;
    int32_t n[3];       /* x, y, z sizes */
    int64_t c[3];       /* chunk x, y, z */
    size_t elem, chunk_bytes;
    uint8_t *chunk;     /* chunk_bytes, decoded (allocated at the first read) */
    bool swap;          /* file byte order is not the CPU's */
    bool has_fill;
    uint8_t fill[8];    /* in file byte order */
    bvox_geometry geom;
    int32_t levels;
};

bool bvox__zarr_is_dir(const char *path)
{
    return exists(path, ".zarray") || exists(path, ".zgroup");
}

static bvox_status read_text(const char *dir, const char *file, bvox__bytes *out)
{
    char p[4200];
    if (snprintf(p, sizeof p, "%s/%s", dir, file) >= (int)sizeof p)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", dir);
    return bvox__read_file(p, out);
}

void bvox__zarr_close(bvox__zarr *z)
{
    if (!z) return;
    if (z->chunk) bvox__free(z->chunk, z->chunk_bytes);
    free(z->arr);
    free(z->name);
    free(z);
}

/* The array folder of path at level, the scale and unit into attrs. */
static bvox_status find_array(const char *path, int32_t level, char arr[4200],
                              bvox__zarr_attrs *attrs)
{
    memset(attrs, 0, sizeof *attrs);
    attrs->spacing[0] = attrs->spacing[1] = attrs->spacing[2] = 1.0;
    attrs->nlevels = 1;
    bvox_status st;
    if (exists(path, ".zarray")) {
        if (level != 0)
            return bvox__fail(BVOX_EINVAL, "%s: a single array has no resolution level %d", path,
                              (int)level);
        snprintf(arr, 4200, "%s", path);
        return BVOX_OK;
    }
    if (!exists(path, ".zattrs") && !exists(path, ".zgroup"))
        return bvox__fail(BVOX_EFORMAT, "%s: not a Zarr array or group (no .zarray, .zattrs "
                          "or .zgroup)", path);
    if (exists(path, ".zattrs")) {
        bvox__bytes t;
        if ((st = read_text(path, ".zattrs", &t))) return st;
        char nm[4200];
        snprintf(nm, sizeof nm, "%s/.zattrs", path);
        st = bvox__zarr_attrs_parse_level((const char *)t.data, t.size, nm, level, attrs);
        bvox__bytes_release(&t);
        if (st) return st;
        if (attrs->nlevels < 1) attrs->nlevels = 1;
    }
    if (level != 0 && !attrs->path[0])
        return bvox__fail(BVOX_EINVAL, "%s: no resolution level %d (no multiscales)", path,
                          (int)level);
    if (snprintf(arr, 4200, "%s/%s", path, attrs->path[0] ? attrs->path : "0") >= 4200)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", path);
    if (!exists(arr, ".zarray"))
        return bvox__fail(BVOX_EFORMAT, "%s: the group has no array %s (no .zarray)", path,
                          attrs->path[0] ? attrs->path : "0");
    return BVOX_OK;
}

bvox_status bvox__zarr_open_level(const char *path, int32_t level, bvox__zarr **out)
{
    *out = NULL;
    bvox__zarr_attrs attrs;
    char arr[4200];
    bvox_status st = find_array(path, level, arr, &attrs);
    if (st) return st;
    bvox__zarr *z = bvox__mem_zalloc(1, sizeof *z);
    if (!z) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    z->arr = bvox__mem_strdup(arr);
    z->name = bvox__mem_strdup(path);
    if (!z->arr || !z->name) {
        bvox__zarr_close(z);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    }
    bvox__bytes t;
    if ((st = read_text(arr, ".zarray", &t))) {
        bvox__zarr_close(z);
        return st;
    }
    char nm[4300];
    snprintf(nm, sizeof nm, "%s/.zarray", arr);
    st = bvox__zarr_meta_parse((const char *)t.data, t.size, nm, &z->m);
    bvox__bytes_release(&t);
    if (st) {
        bvox__zarr_close(z);
        return st;
    }
    for (int a = 0; a < 3; a++) {
        z->n[a] = (int32_t)z->m.shape[2 - a];
        z->c[a] = z->m.chunks[2 - a];
    }
    /* no memory budget here: an array larger than memory is read box by
     * box (the metadata parser already keeps each axis in 1..BVOX_MAX_DIM) */
    z->elem = bvox_dtype_size(z->m.dtype);
    if (!bvox__mul_size((size_t)z->c[0] * (size_t)z->c[1], (size_t)z->c[2], &z->chunk_bytes) ||
        !bvox__mul_size(z->chunk_bytes, z->elem, &z->chunk_bytes)) {
        bvox__zarr_close(z);
        return bvox__fail(BVOX_ETOOBIG, "%s: chunk size overflows", path);
    }
    const uint16_t probe = 1;
    bool host_big = *(const uint8_t *)&probe == 0;
    z->swap = z->elem > 1 && z->m.big_endian != host_big;
    if (z->m.has_fill) {
        if (!fill_sample(z->m.fill, z->m.dtype, z->swap, z->fill)) {
            st = bvox__fail(BVOX_EFORMAT, "%s: fill_value %g does not fit dtype %s", path,
                            z->m.fill, bvox_dtype_name(z->m.dtype));
            bvox__zarr_close(z);
            return st;
        }
        z->has_fill = true;
    }
    z->geom = bvox_geometry_default();
    for (int a = 0; a < 3; a++) {
        z->geom.spacing[a] = attrs.spacing[a];
        z->geom.origin[a] = attrs.origin[a];
    }
    snprintf(z->geom.unit, sizeof z->geom.unit, "%s", attrs.unit);
    z->levels = attrs.nlevels;
    *out = z;
    return BVOX_OK;
}

bvox_status bvox__zarr_open(const char *path, bvox__zarr **out)
{
    return bvox__zarr_open_level(path, 0, out);
}

bvox_dims bvox__zarr_dims(const bvox__zarr *z) { return (bvox_dims){z->n[0], z->n[1], z->n[2]}; }
const bvox_geometry *bvox__zarr_geometry(const bvox__zarr *z) { return &z->geom; }
bvox_dtype bvox__zarr_dtype(const bvox__zarr *z) { return z->m.dtype; }
int32_t bvox__zarr_levels(const bvox__zarr *z) { return z->levels; }

void bvox__zarr_chunk_shape(const bvox__zarr *z, int32_t chunks[3])
{
    for (int a = 0; a < 3; a++) chunks[a] = (int32_t)z->c[a];
}

/* Decode chunk (kx, ky, kz) into z->chunk: 0 done, 1 missing (the fill
 * value stands for it), else the failure. */
static int decode_chunk(bvox__zarr *z, int64_t kx, int64_t ky, int64_t kz, bvox_status *st)
{
    char key[64], path[4300];
    snprintf(key, sizeof key, "%lld%c%lld%c%lld", (long long)kz, z->m.sep, (long long)ky,
             z->m.sep, (long long)kx);
    *st = BVOX_OK;
    if (snprintf(path, sizeof path, "%s/%s", z->arr, key) >= (int)sizeof path) {
        *st = bvox__fail(BVOX_EINVAL, "%s: path too long", z->name);
        return -1;
    }
    bvox__bytes f;
    *st = bvox__read_file(path, &f);
    if (*st == BVOX_ENOTFOUND) {
        if (z->has_fill) {
            *st = BVOX_OK;
            return 1;
        }
        *st = bvox__fail(BVOX_EFORMAT, "%s: chunk %s is missing and the array has no fill_value",
                         z->name, key);
        return -1;
    }
    if (*st) return -1;
    if (!z->chunk) {
        z->chunk = bvox__alloc(z->chunk_bytes, false, "Zarr chunk", st);
        if (!z->chunk) {
            bvox__bytes_release(&f);
            bvox__error_prefix(z->name);
            return -1;
        }
    }
    int rc = 0;
    switch (z->m.codec) {
    case BVOX__ZARR_RAW:
        if (f.size != z->chunk_bytes) rc = -2;
        else memcpy(z->chunk, f.data, f.size);
        break;
    case BVOX__ZARR_ZLIB: rc = inflate_exact(f.data, f.size, 15, z->chunk, z->chunk_bytes); break;
    case BVOX__ZARR_GZIP: rc = inflate_exact(f.data, f.size, 31, z->chunk, z->chunk_bytes); break;
    case BVOX__ZARR_BLOSC: rc = unblosc_exact(f.data, f.size, z->chunk, z->chunk_bytes); break;
    default: rc = -1; break;
    }
    bvox__bytes_release(&f);
    if (rc == -1)
        *st = bvox__fail(BVOX_EFORMAT, "%s: chunk %s: corrupt compressed data", z->name, key);
    else if (rc == -2)
        *st = bvox__fail(BVOX_EFORMAT,
                         "%s: chunk %s does not hold %lld x %lld x %lld samples of %zu bytes "
                         "(%zu bytes) as the metadata says",
                         z->name, key, (long long)z->c[2], (long long)z->c[1],
                         (long long)z->c[0], z->elem, z->chunk_bytes);
    return rc ? -1 : 0;
}

static void swap_samples(uint8_t *p, size_t count, size_t e)
{
    for (size_t i = 0; i < count; i++, p += e)
        for (size_t k = 0; k < e / 2; k++) {
            uint8_t c = p[k];
            p[k] = p[e - 1 - k];
            p[e - 1 - k] = c;
        }
}

/* n bytes of the sample fill (e bytes) repeated: memset when its bytes are
 * equal (0 above all), else doubling copies, never one call per sample. */
static void fill_run(uint8_t *d, size_t n, const uint8_t *fill, size_t e)
{
    bool same = true;
    for (size_t k = 1; k < e; k++) same = same && fill[k] == fill[0];
    if (same) {
        memset(d, fill[0], n);
        return;
    }
    memcpy(d, fill, e);
    for (size_t have = e; have < n; have *= 2)
        memcpy(d + have, d, have < n - have ? have : n - have);
}

bvox_status bvox__zarr_read_box_samples(bvox__zarr *z, int32_t x0, int32_t y0, int32_t z0,
                                        int32_t nx, int32_t ny, int32_t nz, void *dst)
{
    const int32_t b0[3] = {x0, y0, z0}, bn[3] = {nx, ny, nz};
    for (int a = 0; a < 3; a++)
        if (b0[a] < 0 || bn[a] < 1 || b0[a] > z->n[a] - bn[a])
            return bvox__fail(BVOX_EINVAL, "%s: box %d,%d,%d + %d,%d,%d is outside the array's "
                              "%d x %d x %d", z->name, x0, y0, z0, nx, ny, nz, z->n[0], z->n[1],
                              z->n[2]);
    int64_t k0[3], k1[3];
    for (int a = 0; a < 3; a++) {
        k0[a] = b0[a] / z->c[a];
        k1[a] = ((int64_t)b0[a] + bn[a] - 1) / z->c[a];
    }
    const size_t e = z->elem;
    uint8_t *out = dst;
    bvox_status st = BVOX_OK;
    for (int64_t kz = k0[2]; kz <= k1[2] && !st; kz++)
        for (int64_t ky = k0[1]; ky <= k1[1] && !st; ky++)
            for (int64_t kx = k0[0]; kx <= k1[0] && !st; kx++) {
                int rc = decode_chunk(z, kx, ky, kz, &st);
                if (rc < 0) break;
                /* the part of the chunk inside the box, in box coordinates */
                int64_t lo[3], hi[3], k[3] = {kx, ky, kz};
                for (int a = 0; a < 3; a++) {
                    int64_t c0 = k[a] * z->c[a], c1 = c0 + z->c[a];
                    lo[a] = c0 > b0[a] ? c0 : b0[a];
                    hi[a] = c1 < (int64_t)b0[a] + bn[a] ? c1 : (int64_t)b0[a] + bn[a];
                }
                size_t run = (size_t)(hi[0] - lo[0]) * e;
                for (int64_t zz = lo[2]; zz < hi[2]; zz++)
                    for (int64_t yy = lo[1]; yy < hi[1]; yy++) {
                        uint8_t *d = out + (((size_t)(zz - z0) * (size_t)ny + (size_t)(yy - y0)) *
                                                (size_t)nx + (size_t)(lo[0] - x0)) * e;
                        if (rc == 1) {
                            fill_run(d, run, z->fill, e);
                        } else {
                            const uint8_t *s =
                                z->chunk + ((((size_t)(zz - kz * z->c[2]) * (size_t)z->c[1]) +
                                             (size_t)(yy - ky * z->c[1])) * (size_t)z->c[0] +
                                            (size_t)(lo[0] - kx * z->c[0])) * e;
                            memcpy(d, s, run);
                        }
                    }
            }
    if (!st && z->swap) swap_samples(out, (size_t)nx * (size_t)ny * (size_t)nz, e);
    return st;
}

bvox_status bvox__zarr_read_box(bvox__zarr *z, int32_t x0, int32_t y0, int32_t z0, int32_t nx,
                                int32_t ny, int32_t nz, const bvox_binarize *how,
                                bvox_volume *out)
{
    if (out->nx != nx || out->ny != ny || out->nz != nz)
        return bvox__fail(BVOX_EINVAL, "%s: the box is %d x %d x %d, the volume %d x %d x %d",
                          z->name, nx, ny, nz, out->nx, out->ny, out->nz);
    /* a box's own Otsu threshold would differ from the volume's */
    if (!bvox__bin_stream_ok(how))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: Otsu's threshold needs the whole volume; a "
                          "box is read with a given threshold", z->name);
    size_t bytes;
    if (!bvox__mul_size((size_t)nx * (size_t)ny, (size_t)nz, &bytes) ||
        !bvox__mul_size(bytes, z->elem, &bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: box too large", z->name);
    bvox_status st;
    void *samples = bvox__alloc(bytes, false, "Zarr box samples", &st);
    if (!samples) {
        bvox__error_prefix(z->name);
        return st;
    }
    st = bvox__zarr_read_box_samples(z, x0, y0, z0, nx, ny, nz, samples);
    bvox_volume *v = NULL;
    if (!st) {
        bvox__gray g;
        bvox__gray_init(&g);
        g.dims = (bvox_dims){nx, ny, nz};
        g.dtype = z->m.dtype;
        g.data = samples;
        st = bvox__binarize(&g, how, z->name, &v);
    }
    bvox__free(samples, bytes);
    if (!st) memcpy(out->words, v->words, out->nwords * sizeof *out->words);
    bvox_volume_destroy(v);
    return st;
}
