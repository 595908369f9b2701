/*
 * binvox.c — Patrick Min's binvox format (".binvox"), read and written
 * exactly as the reference read_binvox.cc and binvox_rw.py do:
 *
 *   #binvox 1\n  dim D0 D1 D2\n  translate tx ty tz\n  scale s\n  data\n
 *   then (value, count) byte pairs, value 0 or 1, count 1..255.
 *
 * The run-length stream walks index = x * (D1*D2) + z * D2 + y: y fastest,
 * then z, then x; so nx = D0, nz = D1, ny = D2. A voxel's world position is
 * translate + scale * (index + 0.5) / max(D0, D1, D2) on each axis, hence
 * spacing = scale / max(D) and origin (centre of voxel 0) = translate +
 * spacing / 2.
 *
 * Because binvox's fastest axis (y) is not our packing axis (z), both ways
 * go through a band of 64 z-rows, each row holding ny bits packed along y:
 * runs are filled into the band with whole-word bit-range fills, and the band
 * meets the volume's column words through 64x64 bit transposes. Everything is
 * O(voxels / 64 + runs).
 *
 * Choices: the header must hold "dim" and end with "data"; "translate" and
 * "scale" are optional (0 and 1, as in the reference reader); unknown or
 * repeated keywords, a value other than 0/1, a zero count, runs past the grid,
 * missing runs and bytes after the last run are all BVOX_EFORMAT.
 */
#include "io.h"
#include "common/bits.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_HEADER_LINE 256

static int binvox_sniff(const uint8_t *data, size_t size)
{
    return size >= 8 && memcmp(data, "#binvox ", 8) == 0;
}

/* ------------------------------------------------------------------ header */

typedef struct header {
    int64_t dim[3];
    double translate[3];
    double scale;
    size_t data_offset;
} header;

/* Next whitespace-separated token of a line; NULL at its end. */
static char *next_token(char **cursor)
{
    char *p = *cursor;
    while (*p == ' ' || *p == '\t') p++;
    if (!*p) return NULL;
    char *t = p;
    while (*p && *p != ' ' && *p != '\t') p++;
    if (*p) *p++ = '\0';
    *cursor = p;
    return t;
}

static bool parse_int(const char *t, int64_t *out)
{
    if (!t || !*t) return false;
    int64_t v = 0;
    for (const char *p = t; *p; p++) {
        if (*p < '0' || *p > '9') return false;
        if (v > 1000000000) return false; /* absurd: far beyond any limit */
        v = v * 10 + (*p - '0');
    }
    *out = v;
    return true;
}

static bool parse_real(const char *t, double *out)
{
    if (!t) return false;
    char *end;
    double v = strtod(t, &end);
    if (end == t || *end || !isfinite(v)) return false;
    *out = v;
    return true;
}

static bvox_status parse_header(const uint8_t *data, size_t size, const char *name,
                                header *h)
{
    bool have_dim = false, have_translate = false, have_scale = false;
    h->translate[0] = h->translate[1] = h->translate[2] = 0.0;
    h->scale = 1.0;
    size_t pos = 0;
    for (int line_no = 1;; line_no++) {
        if (pos >= size)
            return bvox__fail(BVOX_EFORMAT, "%s: binvox header ends without a 'data' line",
                              name);
        const uint8_t *nl = memchr(data + pos, '\n', size - pos);
        size_t len = nl ? (size_t)(nl - (data + pos)) : size - pos;
        if (len >= MAX_HEADER_LINE)
            return bvox__fail(BVOX_EFORMAT, "%s: binvox header line %d is too long", name,
                              line_no);
        if (memchr(data + pos, '\0', len))
            return bvox__fail(BVOX_EFORMAT, "%s: binvox header line %d holds a NUL byte",
                              name, line_no);
        char line[MAX_HEADER_LINE];
        memcpy(line, data + pos, len);
        line[len] = '\0';
        if (len && line[len - 1] == '\r') line[len - 1] = '\0';
        if (!nl)
            return bvox__fail(BVOX_EFORMAT, "%s: binvox header ends without a 'data' line",
                              name);
        pos += len + 1;

        char *cur = line;
        char *key = next_token(&cur);
        if (line_no == 1) {
            int64_t version;
            if (!key || strcmp(key, "#binvox") != 0)
                return bvox__fail(BVOX_EFORMAT, "%s: not a binvox file (no '#binvox' magic)",
                                  name);
            if (!parse_int(next_token(&cur), &version) || next_token(&cur))
                return bvox__fail(BVOX_EFORMAT, "%s: bad binvox version line", name);
            if (version != 1)
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: binvox version %lld (only 1 exists)",
                                  name, (long long)version);
            continue;
        }
        if (!key)
            return bvox__fail(BVOX_EFORMAT, "%s: empty binvox header line %d", name, line_no);
        if (strcmp(key, "data") == 0) {
            if (next_token(&cur))
                return bvox__fail(BVOX_EFORMAT, "%s: text after 'data' on line %d", name,
                                  line_no);
            if (!have_dim)
                return bvox__fail(BVOX_EFORMAT, "%s: binvox header has no 'dim' line", name);
            h->data_offset = pos;
            return BVOX_OK;
        }
        bool ok = true, *seen;
        if (strcmp(key, "dim") == 0) {
            seen = &have_dim;
            for (int a = 0; a < 3; a++) ok = ok && parse_int(next_token(&cur), &h->dim[a]);
        } else if (strcmp(key, "translate") == 0) {
            seen = &have_translate;
            for (int a = 0; a < 3; a++) ok = ok && parse_real(next_token(&cur), &h->translate[a]);
        } else if (strcmp(key, "scale") == 0) {
            seen = &have_scale;
            ok = parse_real(next_token(&cur), &h->scale) && h->scale > 0;
        } else {
            return bvox__fail(BVOX_EFORMAT, "%s: unknown binvox header keyword '%.32s'", name,
                              key);
        }
        if (!ok || next_token(&cur))
            return bvox__fail(BVOX_EFORMAT, "%s: bad '%s' line in the binvox header", name,
                              key);
        if (*seen)
            return bvox__fail(BVOX_EFORMAT, "%s: repeated '%s' line in the binvox header",
                              name, key);
        *seen = true;
    }
}

/* ----------------------------------------------------------------- reading */

/* A band: 64 rows (z = 64*w .. 64*w+63 of one x), each ny bits along y. */
typedef struct band {
    uint64_t *rows; /* 64 * nyw words */
    size_t nyw;
    int64_t x, w;   /* which band is held; -1: none */
    bool dirty;
} band;

/* Move the band's bits into the volume's column words and clear it. */
static void band_flush(band *b, bvox_volume *v)
{
    if (!b->dirty) return;
    uint64_t t[64];
    for (size_t k = 0; k < b->nyw; k++) {
        for (int zz = 0; zz < 64; zz++) t[zz] = b->rows[(size_t)zz * b->nyw + k];
        bvox__transpose64(t);
        int32_t y0 = (int32_t)(k * 64);
        int32_t n = v->ny - y0 < 64 ? v->ny - y0 : 64;
        for (int32_t i = 0; i < n; i++)
            bvox__column(v, (int32_t)b->x, y0 + i)[b->w] |= t[i];
    }
    memset(b->rows, 0, 64 * b->nyw * sizeof(uint64_t));
    b->dirty = false;
}

/* Set bits [y0, y1) of one band row. */
static void row_fill(uint64_t *row, int64_t y0, int64_t y1)
{
    int64_t w0 = y0 >> 6, w1 = (y1 - 1) >> 6;
    if (w0 == w1) {
        row[w0] |= bvox__bit_range((unsigned)(y0 & 63), (unsigned)(y1 - (w1 << 6)));
        return;
    }
    row[w0] |= bvox__bit_range((unsigned)(y0 & 63), 64);
    for (int64_t w = w0 + 1; w < w1; w++) row[w] = ~0ull;
    row[w1] |= bvox__bit_range(0, (unsigned)(y1 - (w1 << 6)));
}

/* Decoder cursor: the binvox row (fixed x, z) holding the current index. */
typedef struct cursor {
    uint64_t row_start; /* index of (x, z, y = 0) */
    int64_t x, z;
} cursor;

static void set_run(bvox_volume *v, band *b, cursor *c, uint64_t p, uint64_t count)
{
    const uint64_t ny = (uint64_t)v->ny, plane = ny * (uint64_t)v->nz;
    while (count) {
        if (p < c->row_start || p - c->row_start >= ny) {
            /* Left the cached row: locate it once with divisions. */
            c->x = (int64_t)(p / plane);
            c->z = (int64_t)((p % plane) / ny);
            c->row_start = p - (p % ny);
        }
        uint64_t y = p - c->row_start;
        uint64_t seg = ny - y < count ? ny - y : count;
        int64_t w = c->z >> 6;
        if (c->x != b->x || w != b->w) {
            band_flush(b, v);
            b->x = c->x;
            b->w = w;
        }
        row_fill(b->rows + (size_t)(c->z & 63) * b->nyw, (int64_t)y, (int64_t)(y + seg));
        b->dirty = true;
        p += seg;
        count -= seg;
    }
}

static bvox_status decode_runs(const uint8_t *data, size_t size, const char *name,
                               bvox_volume *v)
{
    band b = {NULL, ((size_t)v->ny + 63) / 64, -1, -1, false};
    b.rows = bvox__mem_zalloc(64 * b.nyw, sizeof(uint64_t));
    if (!b.rows) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    cursor c = {UINT64_MAX, 0, 0};
    const uint64_t total = (uint64_t)v->nx * (uint64_t)v->ny * (uint64_t)v->nz;
    uint64_t p = 0;
    size_t i = 0;
    bvox_status st = BVOX_OK;
    while (p < total) {
        if (size - i < 2) {
            st = bvox__fail(BVOX_EFORMAT,
                            "%s: binvox data is truncated (%llu of %llu voxels present)", name,
                            (unsigned long long)p, (unsigned long long)total);
            break;
        }
        uint8_t value = data[i], count = data[i + 1];
        if (value > 1 || count == 0) {
            st = bvox__fail(BVOX_EFORMAT, "%s: corrupt binvox run (value %u, count %u) at byte %zu",
                            name, value, count, i);
            break;
        }
        if (count > total - p) {
            st = bvox__fail(BVOX_EFORMAT, "%s: binvox runs overflow the %llu voxels of the grid",
                            name, (unsigned long long)total);
            break;
        }
        if (value) set_run(v, &b, &c, p, count);
        p += count;
        i += 2;
    }
    if (!st && i != size)
        st = bvox__fail(BVOX_EFORMAT, "%s: %zu unexpected bytes after the binvox voxel data",
                        name, size - i);
    if (!st) band_flush(&b, v);
    free(b.rows);
    return st;
}

static bvox_status binvox_read_memory(const uint8_t *data, size_t size, const char *name,
                                      const bvox_read_opts *opts, bvox_volume **out)
{
    (void)opts; /* binvox is binary already: binarisation options do not apply */
    *out = NULL;
    if (!name) name = "binvox";
    header h = {0};
    bvox_status st = parse_header(data, size, name, &h);
    if (st) return st;
    for (int a = 0; a < 3; a++) {
        if (h.dim[a] < 1)
            return bvox__fail(BVOX_EFORMAT, "%s: binvox dim %lld is not positive", name,
                              (long long)h.dim[a]);
        if (h.dim[a] > BVOX_MAX_DIM)
            return bvox__fail(BVOX_ETOOBIG, "%s: binvox dim %lld %lld %lld is over the limit "
                              "of %d per axis", name, (long long)h.dim[0],
                              (long long)h.dim[1], (long long)h.dim[2], BVOX_MAX_DIM);
    }
    bvox_dims dims = {(int32_t)h.dim[0], (int32_t)h.dim[2], (int32_t)h.dim[1]};
    size_t bytes;
    st = bvox__check_dims(dims, name, &bytes);
    if (st) return st;
    /* Each run pair covers at most 255 voxels: a file too short for its grid
     * is refused before the volume is allocated. */
    uint64_t total = (uint64_t)dims.nx * (uint64_t)dims.ny * (uint64_t)dims.nz;
    if ((size - h.data_offset) / 2 < (total + 254) / 255)
        return bvox__fail(BVOX_EFORMAT,
                          "%s: binvox data is truncated (%zu bytes cannot hold %llu voxels)",
                          name, size - h.data_offset, (unsigned long long)total);
    int64_t maxdim = h.dim[0] > h.dim[1] ? h.dim[0] : h.dim[1];
    if (h.dim[2] > maxdim) maxdim = h.dim[2];
    bvox_geometry geom = bvox_geometry_default();
    double s = h.scale / (double)maxdim;
    for (int a = 0; a < 3; a++) {
        geom.spacing[a] = s;
        geom.origin[a] = h.translate[a] + 0.5 * s;
        if (!(s > 0) || !isfinite(geom.origin[a]))
            return bvox__fail(BVOX_EFORMAT, "%s: binvox translate/scale out of range", name);
    }
    bvox_volume *v;
    st = bvox_volume_create(dims, &v);
    if (st) return st;
    st = decode_runs(data + h.data_offset, size - h.data_offset, name, v);
    if (st) {
        bvox_volume_destroy(v);
        return st;
    }
    v->geom = geom;
    *out = v;
    return BVOX_OK;
}

/* ----------------------------------------------------------------- writing */

typedef struct encoder {
    bvox__sink *sink;
    uint8_t buf[1 << 16];
    size_t used;
    bvox_status st;
    unsigned value;   /* value of the run being counted */
    uint64_t count;   /* its length so far */
} encoder;

static void enc_flush(encoder *e)
{
    if (e->used && !e->st) e->st = bvox__sink_write(e->sink, e->buf, e->used);
    e->used = 0;
}

static void enc_emit(encoder *e)
{
    uint64_t n = e->count;
    while (n) {
        unsigned c = n > 255 ? 255 : (unsigned)n;
        if (e->used + 2 > sizeof e->buf) enc_flush(e);
        e->buf[e->used++] = (uint8_t)e->value;
        e->buf[e->used++] = (uint8_t)c;
        n -= c;
    }
    e->count = 0;
}

/* Append one binvox row of n bits (y = 0..n-1), extending or ending runs. */
static void enc_row(encoder *e, const uint64_t *row, uint64_t n)
{
    uint64_t pos = 0;
    while (pos < n) {
        uint64_t k = pos >> 6, limit = (k + 1) * 64 < n ? (k + 1) * 64 : n;
        uint64_t diff = (row[k] ^ (e->value ? ~0ull : 0)) & (~0ull << (pos & 63));
        uint64_t q = diff ? k * 64 + (uint64_t)__builtin_ctzll(diff) : limit;
        if (q >= limit) {
            e->count += limit - pos;
            pos = limit;
            continue;
        }
        e->count += q - pos;
        pos = q;
        enc_emit(e);
        e->value ^= 1;
    }
}

static bvox_status binvox_write_path(const char *path, const bvox_volume *vol,
                                     const bvox_write_opts *opts)
{
    (void)opts;
    const bvox_geometry *g = &vol->geom;
    int32_t maxdim = vol->nx > vol->ny ? vol->nx : vol->ny;
    if (vol->nz > maxdim) maxdim = vol->nz;
    /* binvox has one voxel size: x's is used when the volume's are not equal,
     * and no unit; what cannot be kept is said (the translate and scale are) */
    double s = g->spacing[0];
    if (g->spacing[1] != s || g->spacing[2] != s)
        bvox__warn("%s: binvox has one voxel size: %g x %g x %g %s voxels are written as %g "
                   "(the anisotropy is lost)",
                   path, g->spacing[0], g->spacing[1], g->spacing[2], g->unit, s);
    if (g->unit[0])
        bvox__warn("%s: binvox stores no unit: the voxel size is in %s", path, g->unit);
    char head[512];
    int hl = snprintf(head, sizeof head,
                      "#binvox 1\ndim %d %d %d\ntranslate %.17g %.17g %.17g\nscale %.17g\n"
                      "data\n",
                      (int)vol->nx, (int)vol->nz, (int)vol->ny, g->origin[0] - 0.5 * s,
                      g->origin[1] - 0.5 * s, g->origin[2] - 0.5 * s, s * (double)maxdim);
    if (hl < 0 || (size_t)hl >= sizeof head)
        return bvox__fail(BVOX_EINVAL, "%s: cannot format the binvox header", path);

    size_t nyw = ((size_t)vol->ny + 63) / 64;
    uint64_t *rows = bvox__mem_alloc(64 * nyw * sizeof(uint64_t));
    encoder *e = bvox__mem_alloc(sizeof *e);
    if (!rows || !e) {
        free(rows);
        free(e);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    }
    bvox__sink sink;
    bvox_status st = bvox__sink_open(path, 0, &sink);
    if (st) {
        free(rows);
        free(e);
        return st;
    }
    e->sink = &sink;
    e->used = 0;
    e->st = bvox__sink_write(&sink, head, (size_t)hl);
    e->value = 0;
    e->count = 0;
    uint64_t t[64];
    for (int32_t x = 0; x < vol->nx && !e->st; x++) {
        for (size_t w = 0; w < vol->wpc; w++) {
            /* Transpose the band of 64 z-slices of this x into rows along y. */
            for (size_t k = 0; k < nyw; k++) {
                int32_t y0 = (int32_t)(k * 64);
                int32_t n = vol->ny - y0 < 64 ? vol->ny - y0 : 64;
                for (int32_t i = 0; i < n; i++) t[i] = bvox__column_c(vol, x, y0 + i)[w];
                for (int32_t i = n; i < 64; i++) t[i] = 0;
                bvox__transpose64(t);
                for (int zz = 0; zz < 64; zz++) rows[(size_t)zz * nyw + k] = t[zz];
            }
            int32_t nz = vol->nz - (int32_t)(w * 64) < 64 ? vol->nz - (int32_t)(w * 64) : 64;
            for (int32_t zz = 0; zz < nz; zz++)
                enc_row(e, rows + (size_t)zz * nyw, (uint64_t)vol->ny);
        }
    }
    enc_emit(e);
    enc_flush(e);
    st = e->st;
    free(rows);
    free(e);
    if (st) {
        bvox__sink_abort(&sink);
        return st;
    }
    return bvox__sink_commit(&sink);
}

static const char *const binvox_extensions[] = {".binvox", NULL};

const bvox__format bvox__format_binvox = {
    "binvox", binvox_extensions, binvox_sniff, binvox_read_memory, NULL, binvox_write_path,
    NULL, NULL, NULL,
};
