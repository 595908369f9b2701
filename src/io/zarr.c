/*
 * zarr.c — OME-Zarr (NGFF 0.4 on Zarr v2) volumes, read and written.
 *
 * Written: a folder NAME.zarr holding .zgroup, .zattrs (one "multiscales"
 * entry: axes z, y, x of type space with the unit, a scale transform from the
 * voxel size) and the array "0" (.zarray and one file per chunk, "kz.ky.kx").
 * Samples are uint8 0/1 ("|u1"), chunk shape the caller's (opts->chunks) or
 * up to 64 per axis, each chunk compressed with zlib (numcodecs "zlib") or,
 * with opts->compressor "blosc", Blosc lz4 with bit-shuffle (a 0/1 byte
 * has one live bit plane, so chunks come close to one bit per voxel).
 * The whole folder is built under a temporary name and renamed on success
 * (bvox__dir_sink_*), so it appears complete or not at all.
 *
 * Read: the path is an array (has .zarray) or a group whose .zattrs names the
 * finest multiscales dataset (else "0"). Any integer/float dtype or bool, C
 * order, compressor none/zlib/gzip/blosc; the read options binarise (binarize.c).
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

/* ---------------------------------------------------------- reading */

typedef struct reader {
    const char *arr;    /* the array folder */
    const char *name;   /* the user's path, for messages */
    bvox__zarr_meta m;
    int32_t n[3];       /* x, y, z sizes */
    int64_t c[3];       /* chunk x, y, z */
    size_t elem, chunk_bytes;
    uint8_t *chunk;     /* chunk_bytes, decoded */
    uint8_t *samples;   /* the gray volume */
} reader;

/* Copy chunk (kx, ky, kz) from r->chunk (or the fill value) into samples. */
static void place(reader *r, int64_t kx, int64_t ky, int64_t kz, const uint8_t *fill)
{
    int64_t x0 = kx * r->c[0], y0 = ky * r->c[1], z0 = kz * r->c[2];
    int64_t wx = r->n[0] - x0 < r->c[0] ? r->n[0] - x0 : r->c[0];
    int64_t wy = r->n[1] - y0 < r->c[1] ? r->n[1] - y0 : r->c[1];
    int64_t wz = r->n[2] - z0 < r->c[2] ? r->n[2] - z0 : r->c[2];
    size_t e = r->elem;
    for (int64_t z = 0; z < wz; z++)
        for (int64_t y = 0; y < wy; y++) {
            uint8_t *dst = r->samples +
                           (((size_t)(z0 + z) * (size_t)r->n[1] + (size_t)(y0 + y)) *
                                (size_t)r->n[0] + (size_t)x0) * e;
            if (fill) {
                for (int64_t x = 0; x < wx; x++) memcpy(dst + (size_t)x * e, fill, e);
            } else {
                const uint8_t *src =
                    r->chunk + (((size_t)z * (size_t)r->c[1] + (size_t)y) * (size_t)r->c[0]) * e;
                memcpy(dst, src, (size_t)wx * e);
            }
        }
}

static bvox_status read_chunk(reader *r, int64_t kx, int64_t ky, int64_t kz, const uint8_t *fill)
{
    char key[64], path[4200];
    snprintf(key, sizeof key, "%lld%c%lld%c%lld", (long long)kz, r->m.sep, (long long)ky,
             r->m.sep, (long long)kx);
    if (snprintf(path, sizeof path, "%s/%s", r->arr, key) >= (int)sizeof path)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", r->name);
    bvox__bytes f;
    bvox_status st = bvox__read_file(path, &f);
    if (st == BVOX_ENOTFOUND) {
        if (!fill)
            return bvox__fail(BVOX_EFORMAT,
                              "%s: chunk %s is missing and the array has no fill_value",
                              r->name, key);
        place(r, kx, ky, kz, fill);
        return BVOX_OK;
    }
    if (st) return st;
    int rc = 0;
    switch (r->m.codec) {
    case BVOX__ZARR_RAW:
        if (f.size != r->chunk_bytes) rc = -2;
        else memcpy(r->chunk, f.data, f.size);
        break;
    case BVOX__ZARR_ZLIB: rc = inflate_exact(f.data, f.size, 15, r->chunk, r->chunk_bytes); break;
    case BVOX__ZARR_GZIP: rc = inflate_exact(f.data, f.size, 31, r->chunk, r->chunk_bytes); break;
    case BVOX__ZARR_BLOSC: rc = unblosc_exact(f.data, f.size, r->chunk, r->chunk_bytes); break;
    default: rc = -1; break;
    }
    bvox__bytes_release(&f);
    if (rc == -1)
        return bvox__fail(BVOX_EFORMAT, "%s: chunk %s: corrupt compressed data", r->name, key);
    if (rc == -2)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: chunk %s does not hold %lld x %lld x %lld samples of %zu bytes "
                          "(%zu bytes) as the metadata says",
                          r->name, key, (long long)r->c[2], (long long)r->c[1],
                          (long long)r->c[0], r->elem, r->chunk_bytes);
    place(r, kx, ky, kz, NULL);
    return BVOX_OK;
}

static bvox_status read_text(const char *dir, const char *file, bvox__bytes *out)
{
    char p[4200];
    if (snprintf(p, sizeof p, "%s/%s", dir, file) >= (int)sizeof p)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", dir);
    return bvox__read_file(p, out);
}

static bvox_status zarr_read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    bvox__zarr_attrs attrs;
    memset(&attrs, 0, sizeof attrs);
    attrs.spacing[0] = attrs.spacing[1] = attrs.spacing[2] = 1.0;
    char arr[4200];
    bvox_status st;
    if (exists(path, ".zarray")) {
        snprintf(arr, sizeof arr, "%s", path);
    } else if (exists(path, ".zattrs") || exists(path, ".zgroup")) {
        if (exists(path, ".zattrs")) {
            bvox__bytes t;
            if ((st = read_text(path, ".zattrs", &t))) return st;
            char nm[4200];
            snprintf(nm, sizeof nm, "%s/.zattrs", path);
            st = bvox__zarr_attrs_parse((const char *)t.data, t.size, nm, &attrs);
            bvox__bytes_release(&t);
            if (st) return st;
        }
        if (snprintf(arr, sizeof arr, "%s/%s", path, attrs.path[0] ? attrs.path : "0") >=
            (int)sizeof arr)
            return bvox__fail(BVOX_EINVAL, "%s: path too long", path);
        if (!exists(arr, ".zarray"))
            return bvox__fail(BVOX_EFORMAT, "%s: the group has no array %s (no .zarray)", path,
                              attrs.path[0] ? attrs.path : "0");
    } else {
        return bvox__fail(BVOX_EFORMAT, "%s: not a Zarr array or group (no .zarray, .zattrs "
                          "or .zgroup)", path);
    }

    reader r;
    memset(&r, 0, sizeof r);
    r.arr = arr;
    r.name = path;
    {
        bvox__bytes t;
        if ((st = read_text(arr, ".zarray", &t))) return st;
        char nm[4300];
        snprintf(nm, sizeof nm, "%s/.zarray", arr);
        st = bvox__zarr_meta_parse((const char *)t.data, t.size, nm, &r.m);
        bvox__bytes_release(&t);
        if (st) return st;
    }
    for (int a = 0; a < 3; a++) {
        r.n[a] = (int32_t)r.m.shape[2 - a];
        r.c[a] = r.m.chunks[2 - a];
    }
    bvox_dims d = {r.n[0], r.n[1], r.n[2]};
    size_t wb;
    if ((st = bvox__check_dims(d, path, &wb))) return st;
    r.elem = bvox_dtype_size(r.m.dtype);
    size_t total;
    if (!bvox__mul_size((size_t)d.nx * (size_t)d.ny, (size_t)d.nz, &total) ||
        !bvox__mul_size(total, r.elem, &total) ||
        !bvox__mul_size((size_t)r.c[0] * (size_t)r.c[1], (size_t)r.c[2], &r.chunk_bytes) ||
        !bvox__mul_size(r.chunk_bytes, r.elem, &r.chunk_bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: array or chunk size overflows", path);
    const uint16_t probe = 1;
    bool host_big = *(const uint8_t *)&probe == 0;
    bool swap = r.elem > 1 && r.m.big_endian != host_big;
    uint8_t fillv[8], *fill = NULL;
    if (r.m.has_fill) {
        if (!fill_sample(r.m.fill, r.m.dtype, swap, fillv))
            return bvox__fail(BVOX_EFORMAT, "%s: fill_value %g does not fit dtype %s", path,
                              r.m.fill, bvox_dtype_name(r.m.dtype));
        fill = fillv;
    }
    r.chunk = bvox__alloc(r.chunk_bytes, false, "Zarr chunk", &st);
    if (!r.chunk) {
        bvox__error_prefix(path);
        return st;
    }
    r.samples = bvox__alloc(total, false, "Zarr samples", &st);
    if (!r.samples) {
        bvox__error_prefix(path);
        bvox__free(r.chunk, r.chunk_bytes);
        return st;
    }
    int64_t nk[3];
    for (int a = 0; a < 3; a++) nk[a] = (r.n[a] + r.c[a] - 1) / r.c[a];
    for (int64_t kz = 0; kz < nk[2] && !st; kz++)
        for (int64_t ky = 0; ky < nk[1] && !st; ky++)
            for (int64_t kx = 0; kx < nk[0] && !st; kx++) st = read_chunk(&r, kx, ky, kz, fill);
    bvox__free(r.chunk, r.chunk_bytes);
    if (st) {
        bvox__free(r.samples, total);
        return st;
    }
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = d;
    g.dtype = r.m.dtype;
    g.data = r.samples;
    g.owned = r.samples;
    g.owned_bytes = total;
    g.byteswap = swap;
    for (int a = 0; a < 3; a++) g.geom.spacing[a] = attrs.spacing[a];
    snprintf(g.geom.unit, sizeof g.geom.unit, "%s", attrs.unit);
    st = bvox__binarize(&g, opts ? &opts->binarize : NULL, path, out);
    bvox__gray_release(&g);
    return st;
}

static bvox_status zarr_read_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox_volume **out)
{
    (void)data, (void)size, (void)opts;
    *out = NULL;
    return bvox__fail(BVOX_EUNSUPPORTED, "%s: Zarr is a folder; read it by its path",
                      name ? name : "input");
}

bool bvox__zarr_is_dir(const char *path)
{
    return exists(path, ".zarray") || exists(path, ".zgroup");
}

/* ---------------------------------------------------------- writing */

static bvox_status write_file(const char *dir, const char *file, const void *data, size_t size)
{
    char p[4200];
    if (snprintf(p, sizeof p, "%s/%s", dir, file) >= (int)sizeof p)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", dir);
    FILE *f = fopen(p, "wb");
    if (!f) return bvox__fail(BVOX_EIO, "%s: cannot create: %s", p, strerror(errno));
    bool ok = fwrite(data, 1, size, f) == size;
    ok = (fclose(f) == 0) && ok;
    if (!ok) return bvox__fail(BVOX_EIO, "%s: write failed", p);
    return BVOX_OK;
}

static const char *ngff_unit(const char *u)
{
    static const char *const map[][2] = {
        {"um", "micrometer"}, {"µm", "micrometer"}, {"micron", "micrometer"},
        {"mm", "millimeter"}, {"nm", "nanometer"},  {"cm", "centimeter"},
        {"m", "meter"},       {"micrometer", "micrometer"}, {"millimeter", "millimeter"},
        {"nanometer", "nanometer"},
    };
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (!strcmp(u, map[i][0])) return map[i][1];
    return NULL;
}

static bvox_status write_meta(const char *tmp, const bvox_volume *v, const int64_t c[3], bool blosc)
{
    char buf[2048];
    bvox_status st = write_file(tmp, ".zgroup", "{\n    \"zarr_format\": 2\n}\n", 25);
    if (st) return st;
    const char *unit = ngff_unit(v->geom.unit);
    char ufield[64] = "";
    if (unit) snprintf(ufield, sizeof ufield, ", \"unit\": \"%s\"", unit);
    int n = snprintf(buf, sizeof buf,
                     "{\n    \"multiscales\": [\n        {\n"
                     "            \"version\": \"0.4\",\n            \"name\": \"bvox\",\n"
                     "            \"axes\": [\n"
                     "                {\"name\": \"z\", \"type\": \"space\"%s},\n"
                     "                {\"name\": \"y\", \"type\": \"space\"%s},\n"
                     "                {\"name\": \"x\", \"type\": \"space\"%s}\n"
                     "            ],\n"
                     "            \"datasets\": [\n                {\"path\": \"0\", "
                     "\"coordinateTransformations\": [{\"type\": \"scale\", \"scale\": "
                     "[%.17g, %.17g, %.17g]}]}\n            ]\n        }\n    ]\n}\n",
                     ufield, ufield, ufield, v->geom.spacing[2], v->geom.spacing[1],
                     v->geom.spacing[0]);
    if ((st = write_file(tmp, ".zattrs", buf, (size_t)n))) return st;
    char arr[4200];
    snprintf(arr, sizeof arr, "%s/0", tmp);
    if (mkdir(arr, 0777) != 0) return bvox__fail(BVOX_EIO, "%s: cannot create: %s", arr,
                                                 strerror(errno));
    n = snprintf(buf, sizeof buf,
                 "{\n    \"chunks\": [%lld, %lld, %lld],\n"
                 "    \"compressor\": %s,\n"
                 "    \"dimension_separator\": \".\",\n    \"dtype\": \"|u1\",\n"
                 "    \"fill_value\": 0,\n    \"filters\": null,\n    \"order\": \"C\",\n"
                 "    \"shape\": [%d, %d, %d],\n    \"zarr_format\": 2\n}\n",
                 (long long)c[2], (long long)c[1], (long long)c[0],
                 blosc ? "{\"id\": \"blosc\", \"cname\": \"lz4\", \"clevel\": 5, "
                         "\"shuffle\": 2, \"blocksize\": 0}"
                       : "{\"id\": \"zlib\", \"level\": 1}",
                 (int)v->nz, (int)v->ny,
                 (int)v->nx);
    return write_file(arr, ".zarray", buf, (size_t)n);
}

static bvox_status zarr_write_path(const char *path, const bvox_volume *v,
                                   const bvox_write_opts *opts)
{
    int32_t n[3] = {v->nx, v->ny, v->nz};
    int64_t c[3];
    const char *codec = opts && opts->compressor ? opts->compressor : "zlib";
    bool blosc = !strcmp(codec, "blosc");
    if (!blosc && strcmp(codec, "zlib"))
        return bvox__fail(BVOX_EINVAL, "%s: unknown Zarr compressor '%s' (zlib or blosc)", path,
                          codec);
    for (int a = 0; a < 3; a++) {
        int32_t want = opts && opts->chunks[a] ? opts->chunks[a] : 64;
        if (want < 0 || want > BVOX_MAX_DIM)
            return bvox__fail(BVOX_EINVAL, "%s: chunk size %d must be in 1..%d", path,
                              (int)want, BVOX_MAX_DIM);
        c[a] = want < n[a] ? want : n[a];
    }
    const size_t page = (size_t)n[0] * (size_t)n[1];
    size_t chunk_bytes = (size_t)c[0] * (size_t)c[1] * (size_t)c[2];
    /* slab: the 64-aligned z range covering one row of chunks */
    size_t slab_slices = (size_t)c[2] + 126 < (size_t)n[2] ? (size_t)c[2] + 126 : (size_t)n[2];
    size_t slab_bytes, zbound = blosc ? chunk_bytes + BLOSC_MAX_OVERHEAD
                                     : compressBound((uLong)chunk_bytes);
    if (!bvox__mul_size(page, slab_slices, &slab_bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: slices too large", path);
    bvox_status st;
    uint8_t *slab = bvox__alloc(slab_bytes, false, "Zarr slab", &st);
    uint8_t *chunk = slab ? bvox__alloc(chunk_bytes, false, "Zarr chunk", &st) : NULL;
    uint8_t *z = chunk ? bvox__alloc(zbound, false, "Zarr compressed chunk", &st) : NULL;
    char *tmp = NULL;
    if (z) st = bvox__dir_sink_open(path, &tmp);
    if (!st) st = write_meta(tmp, v, c, blosc);
    char arr[4200];
    if (tmp) snprintf(arr, sizeof arr, "%s/0", tmp);
    for (int64_t z0 = 0; !st && z0 < n[2]; z0 += c[2]) {
        int64_t z1 = z0 + c[2] < n[2] ? z0 + c[2] : n[2];
        int64_t za = z0 & ~(int64_t)63;
        for (int64_t b = za; b < z1; b += 64) {
            int32_t cnt = n[2] - b < 64 ? (int32_t)(n[2] - b) : 64;
            bvox__unpack_slices(v, (int32_t)b, cnt, 1, slab + (size_t)(b - za) * page);
        }
        for (int64_t y0 = 0; !st && y0 < n[1]; y0 += c[1])
            for (int64_t x0 = 0; !st && x0 < n[0]; x0 += c[0]) {
                int64_t wx = n[0] - x0 < c[0] ? n[0] - x0 : c[0];
                int64_t wy = n[1] - y0 < c[1] ? n[1] - y0 : c[1];
                if (wx < c[0] || wy < c[1] || z1 - z0 < c[2]) memset(chunk, 0, chunk_bytes);
                for (int64_t k = 0; k < z1 - z0; k++)
                    for (int64_t y = 0; y < wy; y++)
                        memcpy(chunk + ((size_t)k * (size_t)c[1] + (size_t)y) * (size_t)c[0],
                               slab + (size_t)(z0 - za + k) * page +
                                   (size_t)(y0 + y) * (size_t)n[0] + (size_t)x0,
                               (size_t)wx);
                uLongf zn = (uLongf)zbound;
                if (blosc) {
                    /* bit-shuffled 0/1 bytes: 7 of every 8 bit planes are zero */
                    int k = blosc_compress_ctx(5, BLOSC_BITSHUFFLE, 1, chunk_bytes, chunk, z,
                                               zbound, "lz4", 0, 1);
                    if (k <= 0) { /* Blosc 1 takes at most 2 GiB per buffer */
                        st = bvox__fail(BVOX_ETOOBIG, "%s: Blosc could not compress a chunk of "
                                        "%zu bytes (use smaller --chunks)", path, chunk_bytes);
                        break;
                    }
                    zn = (uLongf)k;
                } else if (compress2(z, &zn, chunk, (uLong)chunk_bytes, 1) != Z_OK) {
                    st = bvox__fail(BVOX_ENOMEM, "%s: zlib failed", path);
                    break;
                }
                char key[64];
                snprintf(key, sizeof key, "%lld.%lld.%lld", (long long)(z0 / c[2]),
                         (long long)(y0 / c[1]), (long long)(x0 / c[0]));
                st = write_file(arr, key, z, zn);
            }
    }
    if (z) bvox__free(z, zbound);
    if (chunk) bvox__free(chunk, chunk_bytes);
    if (slab) bvox__free(slab, slab_bytes);
    if (tmp) {
        if (st) bvox__dir_sink_abort(tmp);
        else st = bvox__dir_sink_commit(tmp, path);
        free(tmp);
    }
    return st;
}

static const char *const zarr_extensions[] = {".zarr", NULL};

const bvox__format bvox__format_zarr = {
    "zarr", zarr_extensions, NULL, zarr_read_memory, zarr_read_path, zarr_write_path, NULL, NULL,
};
