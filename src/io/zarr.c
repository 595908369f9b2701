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
    uint8_t *samples;   /* the gray box: b1 - b0 samples per axis, x fastest */
    int64_t b0[3], b1[3]; /* the box being read (x, y, z, half-open) */
} reader;

/* Copy the part of chunk (kx, ky, kz) inside the box from r->chunk (or the
 * fill value) into samples. */
static void place(reader *r, int64_t kx, int64_t ky, int64_t kz, const uint8_t *fill)
{
    int64_t lo[3], hi[3], k[3] = {kx, ky, kz};
    for (int a = 0; a < 3; a++) {
        int64_t s = k[a] * r->c[a], e = s + r->c[a];
        lo[a] = s > r->b0[a] ? s : r->b0[a];
        hi[a] = e < r->b1[a] ? e : r->b1[a];
    }
    size_t e = r->elem, bx = (size_t)(r->b1[0] - r->b0[0]), by = (size_t)(r->b1[1] - r->b0[1]);
    size_t wx = (size_t)(hi[0] - lo[0]);
    for (int64_t z = lo[2]; z < hi[2]; z++)
        for (int64_t y = lo[1]; y < hi[1]; y++) {
            uint8_t *dst = r->samples + (((size_t)(z - r->b0[2]) * by + (size_t)(y - r->b0[1])) *
                                             bx + (size_t)(lo[0] - r->b0[0])) * e;
            if (fill) {
                for (size_t x = 0; x < wx; x++) memcpy(dst + x * e, fill, e);
            } else {
                const uint8_t *src =
                    r->chunk + ((((size_t)(z - kz * r->c[2])) * (size_t)r->c[1] +
                                 (size_t)(y - ky * r->c[1])) * (size_t)r->c[0] +
                                (size_t)(lo[0] - kx * r->c[0])) * e;
                memcpy(dst, src, wx * e);
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

bvox_status bvox__zarr_in_open(const char *path, bvox__zarr_in *zi)
{
    memset(zi, 0, sizeof *zi);
    bvox__zarr_attrs *attrs = &zi->attrs;
    attrs->spacing[0] = attrs->spacing[1] = attrs->spacing[2] = 1.0;
    if (snprintf(zi->name, sizeof zi->name, "%s", path) >= (int)sizeof zi->name)
        return bvox__fail(BVOX_EINVAL, "%s: path too long", path);
    char *arr = zi->arr;
    bvox_status st;
    if (exists(path, ".zarray")) {
        snprintf(arr, sizeof zi->arr, "%s", path);
    } else if (exists(path, ".zattrs") || exists(path, ".zgroup")) {
        if (exists(path, ".zattrs")) {
            bvox__bytes t;
            if ((st = read_text(path, ".zattrs", &t))) return st;
            char nm[4200];
            snprintf(nm, sizeof nm, "%s/.zattrs", path);
            st = bvox__zarr_attrs_parse((const char *)t.data, t.size, nm, attrs);
            bvox__bytes_release(&t);
            if (st) return st;
        }
        if (snprintf(arr, sizeof zi->arr, "%s/%s", path, attrs->path[0] ? attrs->path : "0") >=
            (int)sizeof zi->arr)
            return bvox__fail(BVOX_EINVAL, "%s: path too long", path);
        if (!exists(arr, ".zarray"))
            return bvox__fail(BVOX_EFORMAT, "%s: the group has no array %s (no .zarray)", path,
                              attrs->path[0] ? attrs->path : "0");
    } else {
        return bvox__fail(BVOX_EFORMAT, "%s: not a Zarr array or group (no .zarray, .zattrs "
                          "or .zgroup)", path);
    }
    {
        bvox__bytes t;
        if ((st = read_text(arr, ".zarray", &t))) return st;
        char nm[4300];
        snprintf(nm, sizeof nm, "%s/.zarray", arr);
        st = bvox__zarr_meta_parse((const char *)t.data, t.size, nm, &zi->m);
        bvox__bytes_release(&t);
        if (st) return st;
    }
    int32_t n[3];
    for (int a = 0; a < 3; a++) n[a] = (int32_t)zi->m.shape[2 - a];
    zi->dims = (bvox_dims){n[0], n[1], n[2]};
    size_t wb;
    if ((st = bvox__check_dims(zi->dims, path, &wb))) return st;
    size_t elem = bvox_dtype_size(zi->m.dtype), cb;
    if (!bvox__mul_size((size_t)zi->m.chunks[0] * (size_t)zi->m.chunks[1],
                        (size_t)zi->m.chunks[2], &cb) ||
        !bvox__mul_size(cb, elem, &cb))
        return bvox__fail(BVOX_ETOOBIG, "%s: array or chunk size overflows", path);
    const uint16_t probe = 1;
    bool host_big = *(const uint8_t *)&probe == 0;
    zi->swap = elem > 1 && zi->m.big_endian != host_big;
    if (zi->m.has_fill) {
        if (!fill_sample(zi->m.fill, zi->m.dtype, zi->swap, zi->fill))
            return bvox__fail(BVOX_EFORMAT, "%s: fill_value %g does not fit dtype %s", path,
                              zi->m.fill, bvox_dtype_name(zi->m.dtype));
    }
    zi->geom = bvox_geometry_default();
    for (int a = 0; a < 3; a++) zi->geom.spacing[a] = attrs->spacing[a];
    snprintf(zi->geom.unit, sizeof zi->geom.unit, "%s", attrs->unit);
    return BVOX_OK;
}

/* The samples of box b (x0 y0 z0 x1 y1 z1, inside the array) into a fresh
 * gray buffer: only the chunks the box touches are read. */
static bvox_status read_gray_box(const bvox__zarr_in *zi, const int64_t b[6], bvox__gray *g)
{
    reader r;
    memset(&r, 0, sizeof r);
    r.arr = zi->arr;
    r.name = zi->name;
    r.m = zi->m;
    r.n[0] = zi->dims.nx, r.n[1] = zi->dims.ny, r.n[2] = zi->dims.nz;
    for (int a = 0; a < 3; a++) {
        r.c[a] = zi->m.chunks[2 - a];
        r.b0[a] = b[a];
        r.b1[a] = b[a + 3];
    }
    r.elem = bvox_dtype_size(zi->m.dtype);
    r.chunk_bytes = (size_t)r.c[0] * (size_t)r.c[1] * (size_t)r.c[2] * r.elem; /* checked */
    size_t total;
    if (!bvox__mul_size((size_t)(b[3] - b[0]) * (size_t)(b[4] - b[1]), (size_t)(b[5] - b[2]),
                        &total) ||
        !bvox__mul_size(total, r.elem, &total))
        return bvox__fail(BVOX_ETOOBIG, "%s: array size overflows", zi->name);
    bvox_status st;
    r.chunk = bvox__alloc(r.chunk_bytes, false, "Zarr chunk", &st);
    if (!r.chunk) {
        bvox__error_prefix(zi->name);
        return st;
    }
    r.samples = bvox__alloc(total, false, "Zarr samples", &st);
    if (!r.samples) {
        bvox__error_prefix(zi->name);
        bvox__free(r.chunk, r.chunk_bytes);
        return st;
    }
    const uint8_t *fill = zi->m.has_fill ? zi->fill : NULL;
    int64_t k0[3], k1[3];
    for (int a = 0; a < 3; a++) {
        k0[a] = b[a] / r.c[a];
        k1[a] = (b[a + 3] + r.c[a] - 1) / r.c[a];
    }
    for (int64_t kz = k0[2]; kz < k1[2] && !st; kz++)
        for (int64_t ky = k0[1]; ky < k1[1] && !st; ky++)
            for (int64_t kx = k0[0]; kx < k1[0] && !st; kx++) st = read_chunk(&r, kx, ky, kz, fill);
    bvox__free(r.chunk, r.chunk_bytes);
    if (st) {
        bvox__free(r.samples, total);
        return st;
    }
    bvox__gray_init(g);
    g->dims = (bvox_dims){(int32_t)(b[3] - b[0]), (int32_t)(b[4] - b[1]), (int32_t)(b[5] - b[2])};
    g->dtype = zi->m.dtype;
    g->data = r.samples;
    g->owned = r.samples;
    g->owned_bytes = total;
    g->byteswap = zi->swap;
    g->geom = zi->geom;
    return BVOX_OK;
}

bvox_status bvox__zarr_in_read_box(const bvox__zarr_in *zi, bvox_box box,
                                   const bvox_binarize *how, bvox_volume **out)
{
    *out = NULL;
    const int32_t n[3] = {zi->dims.nx, zi->dims.ny, zi->dims.nz};
    const int32_t b[6] = {box.x0, box.y0, box.z0, box.x1, box.y1, box.z1};
    for (int a = 0; a < 3; a++)
        if (b[a] < 0 || b[a] >= b[a + 3] || b[a + 3] > n[a])
            return bvox__fail(BVOX_EINVAL, "%s: box outside the %dx%dx%d array", zi->name,
                              (int)n[0], (int)n[1], (int)n[2]);
    bool whole = !b[0] && !b[1] && !b[2] && b[3] == n[0] && b[4] == n[1] && b[5] == n[2];
    if (!whole && !bvox__bin_stream_ok(how))
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: Otsu's threshold needs the whole volume in "
                          "memory (give --threshold, or a larger --max-memory)", zi->name);
    /* one row of chunks along z at a time through the streaming binariser,
     * so only that row's samples are held beside the bits */
    int64_t c2 = zi->m.chunks[0], bb[6] = {b[0], b[1], b[2], b[3], b[4], b[5]};
    if (whole && !bvox__bin_stream_ok(how)) {
        bvox__gray g;
        bvox_status st = read_gray_box(zi, bb, &g);
        if (st) return st;
        st = bvox__binarize(&g, how, zi->name, out);
        bvox__gray_release(&g);
        return st;
    }
    bvox__gray shape;
    bvox__gray_init(&shape);
    shape.dims = (bvox_dims){b[3] - b[0], b[4] - b[1], b[5] - b[2]};
    shape.dtype = zi->m.dtype;
    shape.byteswap = zi->swap;
    shape.geom = zi->geom;
    bvox__bin_stream *bs = NULL;
    bvox_status st = bvox__bin_stream_begin(&shape, how, zi->name, &bs);
    for (int64_t z = b[2]; !st && z < b[5];) {
        int64_t ze = (z / c2 + 1) * c2;
        if (ze > b[5]) ze = b[5];
        bb[2] = z, bb[5] = ze;
        bvox__gray g;
        st = read_gray_box(zi, bb, &g);
        if (st) break;
        bvox__bin_stream_slices(bs, g.data, (size_t)(ze - z));
        bvox__gray_release(&g);
        z = ze;
    }
    if (st) {
        bvox__bin_stream_abort(bs);
        return st;
    }
    return bvox__bin_stream_finish(bs, out);
}

static bvox_status zarr_read_path(const char *path, const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    bvox__zarr_in zi;
    bvox_status st = bvox__zarr_in_open(path, &zi);
    if (st) return st;
    bvox_box all = {0, 0, 0, zi.dims.nx, zi.dims.ny, zi.dims.nz};
    return bvox__zarr_in_read_box(&zi, all, opts ? &opts->binarize : NULL, out);
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

static bvox_status write_meta(const char *tmp, const int32_t dim[3], const bvox_geometry *g,
                              const int64_t c[3], bool blosc)
{
    char buf[2048];
    bvox_status st = write_file(tmp, ".zgroup", "{\n    \"zarr_format\": 2\n}\n", 25);
    if (st) return st;
    const char *unit = ngff_unit(g->unit);
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
                     ufield, ufield, ufield, g->spacing[2], g->spacing[1], g->spacing[0]);
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
                 (int)dim[2], (int)dim[1], (int)dim[0]);
    return write_file(arr, ".zarray", buf, (size_t)n);
}

struct bvox__zarr_out {
    char *tmp;          /* the folder being built (dir sink), NULL once closed */
    char arr[4200];     /* tmp/0 */
    const char *path;   /* the final name, for messages */
    int32_t n[3];
    int64_t c[3];
    bool blosc;
    size_t page, chunk_bytes, slab_bytes, zbound;
    uint8_t *slab, *chunk, *z;
    int64_t next_z;     /* slices written so far (puts come in order) */
};

static void zarr_out_free(bvox__zarr_out *w)
{
    if (w->z) bvox__free(w->z, w->zbound);
    if (w->chunk) bvox__free(w->chunk, w->chunk_bytes);
    if (w->slab) bvox__free(w->slab, w->slab_bytes);
    w->z = w->chunk = w->slab = NULL;
}

void bvox__zarr_out_close(bvox__zarr_out *w, bool keep, bvox_status *st)
{
    if (!w) return;
    zarr_out_free(w);
    if (w->tmp) {
        if (!keep || *st) bvox__dir_sink_abort(w->tmp);
        else *st = bvox__dir_sink_commit(w->tmp, w->path);
        free(w->tmp);
    }
    free(w);
}

bvox_status bvox__zarr_out_open(const char *path, bvox_dims dims, const bvox_geometry *geom,
                                const bvox_write_opts *opts, bvox__zarr_out **out)
{
    *out = NULL;
    int32_t n[3] = {dims.nx, dims.ny, dims.nz};
    const char *codec = opts && opts->compressor ? opts->compressor : "zlib";
    bool blosc = !strcmp(codec, "blosc");
    if (!blosc && strcmp(codec, "zlib"))
        return bvox__fail(BVOX_EINVAL, "%s: unknown Zarr compressor '%s' (zlib or blosc)", path,
                          codec);
    int64_t c[3];
    for (int a = 0; a < 3; a++) {
        int32_t want = opts && opts->chunks[a] ? opts->chunks[a] : 64;
        if (want < 0 || want > BVOX_MAX_DIM)
            return bvox__fail(BVOX_EINVAL, "%s: chunk size %d must be in 1..%d", path,
                              (int)want, BVOX_MAX_DIM);
        c[a] = want < n[a] ? want : n[a];
    }
    bvox__zarr_out *w = bvox__mem_alloc(sizeof *w);
    if (!w) return bvox__fail(BVOX_ENOMEM, "out of memory");
    memset(w, 0, sizeof *w);
    w->path = path;
    w->blosc = blosc;
    memcpy(w->n, n, sizeof n);
    memcpy(w->c, c, sizeof c);
    w->page = (size_t)n[0] * (size_t)n[1];
    w->chunk_bytes = (size_t)c[0] * (size_t)c[1] * (size_t)c[2];
    /* slab: the 64-aligned z range covering one row of chunks */
    size_t slab_slices = (size_t)c[2] + 126 < (size_t)n[2] ? (size_t)c[2] + 126 : (size_t)n[2];
    w->zbound = blosc ? w->chunk_bytes + BLOSC_MAX_OVERHEAD : compressBound((uLong)w->chunk_bytes);
    bvox_status st = BVOX_OK;
    if (!bvox__mul_size(w->page, slab_slices, &w->slab_bytes))
        st = bvox__fail(BVOX_ETOOBIG, "%s: slices too large", path);
    if (!st) w->slab = bvox__alloc(w->slab_bytes, false, "Zarr slab", &st);
    if (!st) w->chunk = bvox__alloc(w->chunk_bytes, false, "Zarr chunk", &st);
    if (!st) w->z = bvox__alloc(w->zbound, false, "Zarr compressed chunk", &st);
    if (!st) st = bvox__dir_sink_open(path, &w->tmp);
    if (!st) st = write_meta(w->tmp, n, geom, c, blosc);
    if (!st) snprintf(w->arr, sizeof w->arr, "%s/0", w->tmp);
    if (st) {
        bvox__zarr_out_close(w, false, &st);
        return st;
    }
    *out = w;
    return BVOX_OK;
}

bvox_status bvox__zarr_out_put(bvox__zarr_out *w, const bvox_volume *v, int32_t z_at)
{
    const int32_t *n = w->n;
    const int64_t *c = w->c;
    if (v->nx != n[0] || v->ny != n[1] || z_at != w->next_z || z_at % c[2] ||
        z_at + v->nz > n[2] || (v->nz % c[2] && z_at + v->nz != n[2]))
        return bvox__fail(BVOX_EINVAL, "%s: slab z %d..%d does not continue the Zarr output "
                          "in whole rows of chunks", w->path, (int)z_at, (int)(z_at + v->nz));
    bvox_status st = BVOX_OK;
    const size_t page = w->page, chunk_bytes = w->chunk_bytes, zbound = w->zbound;
    uint8_t *slab = w->slab, *chunk = w->chunk, *z = w->z;
    const int32_t vz = v->nz;
    for (int64_t z0 = 0; !st && z0 < vz; z0 += c[2]) {
        int64_t z1 = z0 + c[2] < vz ? z0 + c[2] : vz;
        int64_t za = z0 & ~(int64_t)63;
        for (int64_t b = za; b < z1; b += 64) {
            int32_t cnt = vz - b < 64 ? (int32_t)(vz - b) : 64;
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
                if (w->blosc) {
                    /* bit-shuffled 0/1 bytes: 7 of every 8 bit planes are zero */
                    int k = blosc_compress_ctx(5, BLOSC_BITSHUFFLE, 1, chunk_bytes, chunk, z,
                                               zbound, "lz4", 0, 1);
                    if (k <= 0) { /* Blosc 1 takes at most 2 GiB per buffer */
                        st = bvox__fail(BVOX_ETOOBIG, "%s: Blosc could not compress a chunk of "
                                        "%zu bytes (use smaller --chunks)", w->path, chunk_bytes);
                        break;
                    }
                    zn = (uLongf)k;
                } else if (compress2(z, &zn, chunk, (uLong)chunk_bytes, 1) != Z_OK) {
                    st = bvox__fail(BVOX_ENOMEM, "%s: zlib failed", w->path);
                    break;
                }
                char key[64];
                snprintf(key, sizeof key, "%lld.%lld.%lld", (long long)((z_at + z0) / c[2]),
                         (long long)(y0 / c[1]), (long long)(x0 / c[0]));
                st = write_file(w->arr, key, z, zn);
            }
    }
    if (!st) w->next_z = z_at + vz;
    return st;
}

int32_t bvox__zarr_out_chunk_z(const bvox__zarr_out *w) { return (int32_t)w->c[2]; }

size_t bvox__zarr_out_bytes(const bvox__zarr_out *w)
{
    return w->slab_bytes + w->chunk_bytes + w->zbound;
}

static bvox_status zarr_write_path(const char *path, const bvox_volume *v,
                                   const bvox_write_opts *opts)
{
    bvox__zarr_out *w = NULL;
    bvox_status st = bvox__zarr_out_open(path, bvox_volume_dims(v), &v->geom, opts, &w);
    if (st) return st;
    st = bvox__zarr_out_put(w, v, 0);
    bvox__zarr_out_close(w, true, &st);
    return st;
}

static const char *const zarr_extensions[] = {".zarr", NULL};

const bvox__format bvox__format_zarr = {
    "zarr", zarr_extensions, NULL, zarr_read_memory, zarr_read_path, zarr_write_path, NULL, NULL,
};
