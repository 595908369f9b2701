/*
 * zarr_write.c — an OME-Zarr group written chunk by chunk (the interface in
 * zarr.h): a folder NAME.zarr holding .zgroup, .zattrs (one "multiscales"
 * entry: axes z, y, x of type space with the unit, per level a scale of the
 * voxel size times 2^level and the translation that centres the coarse
 * voxels) and the arrays "0", "1", ... (.zarray and one file per chunk,
 * "kz.ky.kx"). Samples are uint8 0/1 ("|u1", fill_value 0, so all-zero
 * chunks are not written), each chunk compressed with zlib (numcodecs
 * "zlib") or Blosc lz4 with bit-shuffle (a 0/1 byte has one live bit plane,
 * so chunks come close to one bit per voxel). The coarser levels are made
 * at commit from the level below, read back chunk by chunk, so a writer
 * never holds more than a box and a few chunks. The whole folder is built
 * under a temporary name (bvox__dir_sink, kind zarr) and appears complete or
 * not at all.
 */
#include "zarr.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <blosc.h>
#include <zlib.h>

#define MAX_LEVELS 16

struct bvox__zarr_writer {
    bvox__dir_sink ds;
    char *name;                   /* the user's path, for messages */
    bool blosc;
    int32_t nlevels;
    int32_t n[MAX_LEVELS][3];     /* x, y, z per level */
    int64_t c[MAX_LEVELS][3];     /* chunk shape per level (capped by its dims) */
    size_t chunk_bytes, zbound;   /* of level 0, the largest */
    uint8_t *chunk, *zbuf;
};

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

static bvox_status write_group_meta(bvox__zarr_writer *w, const bvox_geometry *geom)
{
    bvox_status st = write_file(w->ds.tmp, ".zgroup", "{\n    \"zarr_format\": 2\n}\n", 25);
    if (st) return st;
    const char *unit = geom ? ngff_unit(geom->unit) : NULL;
    char ufield[64] = "";
    if (unit) snprintf(ufield, sizeof ufield, ", \"unit\": \"%s\"", unit);
    double sp[3] = {1, 1, 1}, org[3] = {0, 0, 0};
    if (geom)
        for (int a = 0; a < 3; a++) sp[a] = geom->spacing[a], org[a] = geom->origin[a];
    /* level 0 says its origin only when it has one: a plain volume's
     * metadata stays as before */
    bool moved = org[0] != 0 || org[1] != 0 || org[2] != 0;
    char buf[8192];
    size_t n = (size_t)snprintf(buf, sizeof buf,
                                "{\n    \"multiscales\": [\n        {\n"
                                "            \"version\": \"0.4\",\n            \"name\": \"bvox\",\n"
                                "            \"axes\": [\n"
                                "                {\"name\": \"z\", \"type\": \"space\"%s},\n"
                                "                {\"name\": \"y\", \"type\": \"space\"%s},\n"
                                "                {\"name\": \"x\", \"type\": \"space\"%s}\n"
                                "            ],\n            \"datasets\": [\n",
                                ufield, ufield, ufield);
    for (int32_t l = 0; l < w->nlevels; l++) {
        double f = (double)(1 << l), t = (f - 1) / 2;
        /* a coarse voxel covers 2^l fine ones: its centre moves by
         * (2^l - 1) / 2 fine voxels */
        n += (size_t)snprintf(buf + n, sizeof buf - n,
                              "                {\"path\": \"%d\", \"coordinateTransformations\": "
                              "[{\"type\": \"scale\", \"scale\": [%.17g, %.17g, %.17g]}%s",
                              (int)l, sp[2] * f, sp[1] * f, sp[0] * f,
                              l || moved ? ", " : "]}");
        if (l || moved)
            n += (size_t)snprintf(buf + n, sizeof buf - n,
                                  "{\"type\": \"translation\", \"translation\": "
                                  "[%.17g, %.17g, %.17g]}]}", org[2] + sp[2] * t,
                                  org[1] + sp[1] * t, org[0] + sp[0] * t);
        n += (size_t)snprintf(buf + n, sizeof buf - n, "%s\n", l + 1 < w->nlevels ? "," : "");
    }
    n += (size_t)snprintf(buf + n, sizeof buf - n, "            ]\n        }\n    ]\n}\n");
    return write_file(w->ds.tmp, ".zattrs", buf, n);
}

static bvox_status write_array_meta(bvox__zarr_writer *w, int32_t l)
{
    char arr[4200], buf[1024];
    snprintf(arr, sizeof arr, "%s/%d", w->ds.tmp, (int)l);
    if (mkdir(arr, 0777) != 0)
        return bvox__fail(BVOX_EIO, "%s: cannot create: %s", arr, strerror(errno));
    int n = snprintf(buf, sizeof buf,
                     "{\n    \"chunks\": [%lld, %lld, %lld],\n"
                     "    \"compressor\": %s,\n"
                     "    \"dimension_separator\": \".\",\n    \"dtype\": \"|u1\",\n"
                     "    \"fill_value\": 0,\n    \"filters\": null,\n    \"order\": \"C\",\n"
                     "    \"shape\": [%d, %d, %d],\n    \"zarr_format\": 2\n}\n",
                     (long long)w->c[l][2], (long long)w->c[l][1], (long long)w->c[l][0],
                     w->blosc ? "{\"id\": \"blosc\", \"cname\": \"lz4\", \"clevel\": 5, "
                                "\"shuffle\": 2, \"blocksize\": 0}"
                              : "{\"id\": \"zlib\", \"level\": 1}",
                     (int)w->n[l][2], (int)w->n[l][1], (int)w->n[l][0]);
    return write_file(arr, ".zarray", buf, (size_t)n);
}

static void writer_free(bvox__zarr_writer *w)
{
    if (w->zbuf) bvox__free(w->zbuf, w->zbound);
    if (w->chunk) bvox__free(w->chunk, w->chunk_bytes);
    free(w->name);
    free(w);
}

void bvox__zarr_abort(bvox__zarr_writer *w)
{
    if (!w) return;
    bvox__dir_sink_abort(&w->ds);
    writer_free(w);
}

bvox_status bvox__zarr_create(const char *path, bvox_dims dims, const int32_t chunks[3],
                              const char *compressor, const bvox_geometry *geom, int32_t levels,
                              bool force, bvox__zarr_writer **out)
{
    *out = NULL;
    const char *codec = compressor ? compressor : "zlib";
    bool blosc = !strcmp(codec, "blosc");
    if (!blosc && strcmp(codec, "zlib"))
        return bvox__fail(BVOX_EINVAL, "%s: unknown Zarr compressor '%s' (zlib or blosc)", path,
                          codec);
    if (levels < 0 || levels > MAX_LEVELS)
        return bvox__fail(BVOX_EINVAL, "%s: %d resolution levels; 0 (automatic) to %d", path,
                          (int)levels, MAX_LEVELS);
    /* the axis limits only: a writer may write more than fits in memory */
    if (dims.nx < 1 || dims.ny < 1 || dims.nz < 1 || dims.nx > BVOX_MAX_DIM ||
        dims.ny > BVOX_MAX_DIM || dims.nz > BVOX_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "%s: dimensions %d x %d x %d are outside 1..%d per axis",
                          path, (int)dims.nx, (int)dims.ny, (int)dims.nz, BVOX_MAX_DIM);
    bvox_status st;
    bvox__zarr_writer *w = bvox__mem_zalloc(1, sizeof *w);
    if (!w) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    w->ds.slot = -1;
    w->blosc = blosc;
    w->name = bvox__mem_strdup(path);
    if (!w->name) {
        writer_free(w);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    }
    int32_t want[3];
    for (int a = 0; a < 3; a++) {
        want[a] = chunks && chunks[a] ? chunks[a] : 64;
        if (want[a] < 1 || want[a] > BVOX_MAX_DIM) {
            writer_free(w);
            return bvox__fail(BVOX_EINVAL, "%s: chunk size %d must be in 1..%d", path,
                              (int)want[a], BVOX_MAX_DIM);
        }
    }
    w->n[0][0] = dims.nx, w->n[0][1] = dims.ny, w->n[0][2] = dims.nz;
    /* automatic: halve while every side still spans at least one chunk and
     * something is left to halve, so the coarsest level has a side under
     * one chunk (or is a single voxel) */
    for (int32_t l = 0;; l++) {
        for (int a = 0; a < 3; a++) w->c[l][a] = want[a] < w->n[l][a] ? want[a] : w->n[l][a];
        w->nlevels = l + 1;
        bool more;
        if (levels) {
            more = w->nlevels < levels;
        } else {
            more = l + 1 < MAX_LEVELS;
            bool all_one = true;
            for (int a = 0; a < 3; a++) {
                if (w->n[l][a] < want[a]) more = false;
                if (w->n[l][a] > 1) all_one = false;
            }
            if (all_one) more = false;
        }
        if (!more) break;
        for (int a = 0; a < 3; a++) w->n[l + 1][a] = (w->n[l][a] + 1) / 2;
    }
    w->chunk_bytes = (size_t)w->c[0][0] * (size_t)w->c[0][1] * (size_t)w->c[0][2];
    w->zbound = blosc ? w->chunk_bytes + BLOSC_MAX_OVERHEAD : compressBound((uLong)w->chunk_bytes);
    w->chunk = bvox__alloc(w->chunk_bytes, false, "Zarr chunk", &st);
    w->zbuf = w->chunk ? bvox__alloc(w->zbound, false, "Zarr compressed chunk", &st) : NULL;
    if (!w->zbuf) {
        bvox__error_prefix(path);
        writer_free(w);
        return st;
    }
    st = bvox__dir_sink_open(path, BVOX__DIR_ZARR, force, &w->ds);
    if (st) {
        writer_free(w);
        return st;
    }
    st = write_group_meta(w, geom);
    for (int32_t l = 0; l < w->nlevels && !st; l++) st = write_array_meta(w, l);
    if (st) {
        bvox__zarr_abort(w);
        return st;
    }
    *out = w;
    return BVOX_OK;
}

void bvox__zarr_writer_chunk_shape(const bvox__zarr_writer *w, int32_t chunks[3])
{
    for (int a = 0; a < 3; a++) chunks[a] = (int32_t)w->c[0][a];
}

/* Compress w->chunk (chunk_bytes of level l) and write it as key, or
 * remove key when the chunk is all zeros (the fill value). */
static bvox_status put_chunk(bvox__zarr_writer *w, int32_t l, int64_t kx, int64_t ky, int64_t kz)
{
    char arr[4200], key[64];
    snprintf(arr, sizeof arr, "%s/%d", w->ds.tmp, (int)l);
    snprintf(key, sizeof key, "%lld.%lld.%lld", (long long)kz, (long long)ky, (long long)kx);
    size_t bytes = (size_t)w->c[l][0] * (size_t)w->c[l][1] * (size_t)w->c[l][2];
    bool zero = true;
    size_t i = 0;
    for (; i + 8 <= bytes && zero; i += 8) { /* 8 bytes at a time */
        uint64_t q;
        memcpy(&q, w->chunk + i, 8);
        zero = q == 0;
    }
    for (; i < bytes && zero; i++) zero = w->chunk[i] == 0;
    if (zero) {
        char p[4300];
        snprintf(p, sizeof p, "%s/%s", arr, key);
        if (unlink(p) != 0 && errno != ENOENT)
            return bvox__fail(BVOX_EIO, "%s: cannot remove: %s", p, strerror(errno));
        return BVOX_OK;
    }
    uLongf zn = (uLongf)w->zbound;
    if (w->blosc) {
        /* bit-shuffled 0/1 bytes: 7 of every 8 bit planes are zero */
        int k = blosc_compress_ctx(5, BLOSC_BITSHUFFLE, 1, bytes, w->chunk, w->zbuf, w->zbound,
                                   "lz4", 0, 1);
        if (k <= 0) /* Blosc 1 takes at most 2 GiB per buffer */
            return bvox__fail(BVOX_ETOOBIG, "%s: Blosc could not compress a chunk of %zu bytes "
                              "(use smaller --chunks)", w->name, bytes);
        zn = (uLongf)k;
    } else if (compress2(w->zbuf, &zn, w->chunk, (uLong)bytes, 1) != Z_OK) {
        return bvox__fail(BVOX_ENOMEM, "%s: zlib failed", w->name);
    }
    return write_file(arr, key, w->zbuf, zn);
}

static bvox_status write_level_box(bvox__zarr_writer *w, int32_t l, int32_t x0, int32_t y0,
                                   int32_t z0, const bvox_volume *box)
{
    const int32_t b0[3] = {x0, y0, z0}, bn[3] = {box->nx, box->ny, box->nz};
    const int64_t *c = w->c[l];
    for (int a = 0; a < 3; a++)
        if (b0[a] < 0 || b0[a] % c[a] || b0[a] > w->n[l][a] - bn[a] ||
            (bn[a] % c[a] && b0[a] + bn[a] != w->n[l][a]))
            return bvox__fail(BVOX_EINVAL, "%s: box %d,%d,%d + %d,%d,%d is not on the chunk grid "
                              "(%lld x %lld x %lld) of the %d x %d x %d array", w->name, x0, y0,
                              z0, bn[0], bn[1], bn[2], (long long)c[0], (long long)c[1],
                              (long long)c[2], w->n[l][0], w->n[l][1], w->n[l][2]);
    const size_t page = (size_t)bn[0] * (size_t)bn[1];
    /* whole 64-slice blocks from the one holding the chunk row's first slice
     * (up to 63 before it) to past its last (up to 63 after) */
    size_t slab_slices = (size_t)c[2] + 126 < (size_t)bn[2] ? (size_t)c[2] + 126 : (size_t)bn[2];
    size_t slab_bytes;
    if (!bvox__mul_size(page, slab_slices, &slab_bytes))
        return bvox__fail(BVOX_ETOOBIG, "%s: box slices too large", w->name);
    bvox_status st;
    uint8_t *slab = bvox__alloc(slab_bytes, false, "Zarr slab", &st);
    if (!slab) {
        bvox__error_prefix(w->name);
        return st;
    }
    st = BVOX_OK;
    for (int64_t zb = 0; !st && zb < bn[2]; zb += c[2]) {
        int64_t z1 = zb + c[2] < bn[2] ? zb + c[2] : bn[2];
        int64_t za = zb & ~(int64_t)63;
        for (int64_t b = za; b < z1; b += 64) {
            int32_t cnt = bn[2] - b < 64 ? (int32_t)(bn[2] - b) : 64;
            bvox__unpack_slices(box, (int32_t)b, cnt, 1, slab + (size_t)(b - za) * page);
        }
        for (int64_t yb = 0; !st && yb < bn[1]; yb += c[1])
            for (int64_t xb = 0; !st && xb < bn[0]; xb += c[0]) {
                int64_t wx = bn[0] - xb < c[0] ? bn[0] - xb : c[0];
                int64_t wy = bn[1] - yb < c[1] ? bn[1] - yb : c[1];
                size_t bytes = (size_t)c[0] * (size_t)c[1] * (size_t)c[2];
                if (wx < c[0] || wy < c[1] || z1 - zb < c[2]) memset(w->chunk, 0, bytes);
                for (int64_t k = 0; k < z1 - zb; k++)
                    for (int64_t y = 0; y < wy; y++)
                        memcpy(w->chunk + ((size_t)k * (size_t)c[1] + (size_t)y) * (size_t)c[0],
                               slab + (size_t)(zb - za + k) * page + (size_t)(yb + y) * (size_t)bn[0] +
                                   (size_t)xb,
                               (size_t)wx);
                st = put_chunk(w, l, (x0 + xb) / c[0], (y0 + yb) / c[1], (z0 + zb) / c[2]);
            }
    }
    bvox__free(slab, slab_bytes);
    return st;
}

bvox_status bvox__zarr_write_box(bvox__zarr_writer *w, int32_t x0, int32_t y0, int32_t z0,
                                 const bvox_volume *box)
{
    return write_level_box(w, 0, x0, y0, z0, box);
}

/* Whether any chunk file of level l under the box at (x0, y0, z0) of size d
 * exists (put_chunk writes no all-zero chunk). */
static bool any_chunk(const bvox__zarr_writer *w, int32_t l, int64_t x0, int64_t y0, int64_t z0,
                      bvox_dims d)
{
    const int64_t *c = w->c[l];
    for (int64_t kz = z0 / c[2]; kz <= (z0 + d.nz - 1) / c[2]; kz++)
        for (int64_t ky = y0 / c[1]; ky <= (y0 + d.ny - 1) / c[1]; ky++)
            for (int64_t kx = x0 / c[0]; kx <= (x0 + d.nx - 1) / c[0]; kx++) {
                char p[4300];
                struct stat sb;
                snprintf(p, sizeof p, "%s/%d/%lld.%lld.%lld", w->ds.tmp, (int)l, (long long)kz,
                         (long long)ky, (long long)kx);
                if (stat(p, &sb) == 0) return true;
            }
    return false;
}

/* Level l from level l - 1, one coarse chunk at a time: the fine box it
 * covers is read back (at most 8 chunks), halved, written. */
static bvox_status build_level(bvox__zarr_writer *w, int32_t l)
{
    char arr[4200];
    snprintf(arr, sizeof arr, "%s/%d", w->ds.tmp, (int)(l - 1));
    bvox__zarr *fine;
    bvox_status st = bvox__zarr_open(arr, &fine);
    if (st) return st;
    const int64_t *c = w->c[l];
    const int32_t *nf = w->n[l - 1], *nc = w->n[l];
    for (int64_t z0 = 0; !st && z0 < nc[2]; z0 += c[2])
        for (int64_t y0 = 0; !st && y0 < nc[1]; y0 += c[1])
            for (int64_t x0 = 0; !st && x0 < nc[0]; x0 += c[0]) {
                int64_t o[3] = {x0, y0, z0};
                bvox_dims fd, cd;
                int32_t *fp = &fd.nx, *cp = &cd.nx;
                for (int a = 0; a < 3; a++) {
                    int64_t f = 2 * c[a] < nf[a] - 2 * o[a] ? 2 * c[a] : nf[a] - 2 * o[a];
                    fp[a] = (int32_t)f;
                    cp[a] = (int32_t)((f + 1) / 2);
                }
                /* no fine chunk written (all zeros): the coarse chunk is zeros too */
                if (!any_chunk(w, l - 1, 2 * x0, 2 * y0, 2 * z0, fd)) continue;
                bvox_volume *fv = NULL, *cv = NULL;
                st = bvox_volume_create(fd, &fv);
                if (!st) st = bvox_volume_create(cd, &cv);
                if (!st) st = bvox__zarr_read_box(fine, (int32_t)(2 * x0), (int32_t)(2 * y0),
                                                  (int32_t)(2 * z0), fd.nx, fd.ny, fd.nz, NULL, fv);
                if (!st) {
                    bvox__downsample_or(fv, cv);
                    st = write_level_box(w, l, (int32_t)x0, (int32_t)y0, (int32_t)z0, cv);
                }
                bvox_volume_destroy(fv);
                bvox_volume_destroy(cv);
            }
    bvox__zarr_close(fine);
    return st;
}

bvox_status bvox__zarr_commit(bvox__zarr_writer *w)
{
    bvox_status st = BVOX_OK;
    for (int32_t l = 1; l < w->nlevels && !st; l++) st = build_level(w, l);
    if (st) {
        bvox__zarr_abort(w);
        return st;
    }
    st = bvox__dir_sink_commit(&w->ds);
    writer_free(w);
    return st;
}
