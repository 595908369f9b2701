/*
 * morph.c — binary dilation and erosion on whole words.
 *
 * A structuring element is described as a set of xy offsets (dx, dy), each
 * with a reach h along z: the element holds (dx, dy, dz) for |dz| <= h. Then
 *     dilate(A) = OR over (dx, dy) of shift_xy(Zdilate_h(A))
 *     erode(A)  = AND over (dx, dy) of shift_xy(Zerode_h(A))
 * where Zdilate_h ORs the column with itself shifted by -h..h bits (64 voxels
 * per operation) and shift_xy moves whole columns, so the xy part is a plain
 * word-array OR/AND. The 26-neighbourhood is a box and takes the separable
 * path (z, then x, then y: three 3-tap passes instead of nine); balls stream
 * through the cache in morph_ball.c. Voxels outside the volume are 0 for both
 * operations.
 */
#include "internal.h"
#include "morph_ball.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct offset {
    int dx, dy, h;
} offset;

#define MAX_OFFSETS 4096

typedef struct morph_job {
    const bvox_volume *in;
    bvox_volume *out;
    bool erode;
    int h;                    /* z pass: reach */
    const uint64_t *const *zs; /* per distinct reach: the z-processed volume words */
    const offset *offs;
    const int *zindex;        /* offs[i] uses zs[zindex[i]] */
    int noffs;
} morph_job;

/* z pass: every column OR (AND) its shifts by -h..h. */
static void z_range(void *ctx, int64_t begin, int64_t end)
{
    morph_job *j = ctx;
    const bvox_volume *v = j->in;
    size_t wpc = v->wpc;
    for (int64_t c = begin; c < end; c++) {
        const uint64_t *col = v->words + (size_t)c * wpc;
        uint64_t *dst = j->out->words + (size_t)c * wpc;
        for (size_t k = 0; k < wpc; k++) {
            uint64_t acc = col[k];
            int64_t base = (int64_t)k * 64;
            for (int s = 1; s <= j->h; s++) {
                uint64_t a = bvox__extract_bits(col, wpc, base - s);
                uint64_t b = bvox__extract_bits(col, wpc, base + s);
                acc = j->erode ? (acc & a & b) : (acc | a | b);
            }
            dst[k] = acc;
        }
        dst[wpc - 1] &= v->tail_mask;
    }
}

static bvox_status z_pass(const bvox_volume *in, int h, bool erode, bvox_volume **out)
{
    bvox_dims d = {in->nx, in->ny, in->nz};
    bvox_status st = bvox__volume_create_uninit(d, out);
    if (st) return st;
    (*out)->geom = in->geom;
    if (h == 0) {
        memcpy((*out)->words, in->words, in->nwords * sizeof(uint64_t));
        return BVOX_OK;
    }
    morph_job j = {.in = in, .out = *out, .erode = erode, .h = h};
    st = bvox__parallel_for_progress((int64_t)in->nx * in->ny, 4096, z_range, &j);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

/* The 26-neighbourhood, separable and fused: each output row y is the
 * OR (AND) of rows y-1, y, y+1 of zx, where zx = the x 3-tap of the z 3-tap
 * of the input. A thread walks its rows keeping zx of the last three rows
 * in a small ring (3 rows of words, in cache), so the input is read once and
 * the output written once: three separate passes over whole volumes moved
 * three times the memory. Loops have no data-dependent branches; dilation
 * and erosion are separate instantiations. */
typedef struct box26_job {
    const bvox_volume *in;
    bvox_volume *out;
    uint64_t *ring; /* per chunk: 3 rows of nx * wpc words */
    int64_t nchunks;
    int64_t y0, y1; /* the band of rows this call computes (all of them, or a
                     * band at a time when progress is reported) */
    size_t row_words;
} box26_job;

static inline __attribute__((always_inline)) uint64_t op3(uint64_t a, uint64_t b, uint64_t c,
                                                           bool erode)
{
    return erode ? (a & b & c) : (a | b | c);
}

/* zx of row y into dst (rows outside the volume: all 0). */
static inline __attribute__((always_inline)) void zx_row(const bvox_volume *v, int64_t y,
                                                          uint64_t *dst, bool erode)
{
    size_t wpc = v->wpc, nx = (size_t)v->nx, row = nx * wpc;
    if (y < 0 || y >= v->ny) {
        memset(dst, 0, row * sizeof *dst);
        return;
    }
    const uint64_t *src = v->words + (size_t)y * row;
    uint64_t tail = v->tail_mask;
    /* z pass into dst */
    for (size_t x = 0; x < nx; x++) {
        const uint64_t *c = src + x * wpc;
        uint64_t *d = dst + x * wpc;
        uint64_t prev_hi = 0;
        for (size_t k = 0; k < wpc; k++) {
            uint64_t w = c[k];
            uint64_t next_lo = k + 1 < wpc ? c[k + 1] << 63 : 0;
            d[k] = op3(w, (w << 1) | prev_hi, (w >> 1) | next_lo, erode);
            prev_hi = w >> 63;
        }
        d[wpc - 1] &= tail;
    }
    /* x pass in place: column x becomes op(x-1, x, x+1), keeping the old x-1 */
    uint64_t carry[64];
    for (size_t k0 = 0; k0 < wpc; k0 += 64) {
        size_t kn = wpc - k0 < 64 ? wpc - k0 : 64;
        for (size_t k = 0; k < kn; k++) carry[k] = 0; /* column -1 */
        for (size_t x = 0; x < nx; x++) {
            uint64_t *d = dst + x * wpc + k0;
            const uint64_t *r = x + 1 < nx ? d + wpc : NULL;
            for (size_t k = 0; k < kn; k++) {
                uint64_t mid = d[k], right = r ? r[k] : 0;
                d[k] = op3(carry[k], mid, right, erode);
                carry[k] = mid;
            }
        }
    }
}

static inline __attribute__((always_inline)) void box26_rows(const box26_job *j, int64_t s,
                                                              bool erode)
{
    const bvox_volume *v = j->in;
    int64_t band = j->y1 - j->y0;
    int64_t y0 = j->y0 + s * band / j->nchunks, y1 = j->y0 + (s + 1) * band / j->nchunks;
    size_t row = j->row_words;
    uint64_t *ring = j->ring + (size_t)s * 3 * row;
    /* ring slot of row r: (r + 1) mod 3 (r >= -1) */
    zx_row(v, y0 - 1, ring + (size_t)((y0) % 3) * row, erode);
    zx_row(v, y0, ring + (size_t)((y0 + 1) % 3) * row, erode);
    for (int64_t y = y0; y < y1; y++) {
        zx_row(v, y + 1, ring + (size_t)((y + 2) % 3) * row, erode);
        const uint64_t *a = ring + (size_t)(y % 3) * row;
        const uint64_t *b = ring + (size_t)((y + 1) % 3) * row;
        const uint64_t *c = ring + (size_t)((y + 2) % 3) * row;
        uint64_t *dst = j->out->words + (size_t)y * row;
        for (size_t i = 0; i < row; i++) dst[i] = op3(a[i], b[i], c[i], erode);
    }
}

static void box26_dilate_chunks(void *ctx, int64_t begin, int64_t end)
{
    for (int64_t s = begin; s < end; s++) box26_rows(ctx, s, false);
}

static void box26_erode_chunks(void *ctx, int64_t begin, int64_t end)
{
    for (int64_t s = begin; s < end; s++) box26_rows(ctx, s, true);
}

static bvox_status box26(const bvox_volume *in, bool erode, bvox_volume **out)
{
    bvox_dims d = {in->nx, in->ny, in->nz};
    bvox_status st = bvox__volume_create_uninit(d, out);
    if (st) return st;
    (*out)->geom = in->geom;
    box26_job j = {.in = in, .out = *out, .nchunks = 1, .row_words = (size_t)in->nx * in->wpc,
                   .y0 = 0, .y1 = in->ny};
    /* one chunk of rows per thread; each chunk recomputes 2 rows of zx */
    int threads = bvox__parallelism();
    j.nchunks = in->ny / 8 < threads ? in->ny / 8 : threads;
    if (j.nchunks < 1) j.nchunks = 1;
    size_t bytes;
    if (!bvox__mul_size(j.row_words * 3 * sizeof(uint64_t), (size_t)j.nchunks, &bytes)) {
        bvox_volume_destroy(*out);
        *out = NULL;
        return bvox__fail(BVOX_ETOOBIG, "rows too long for the dilation buffers");
    }
    j.ring = bvox__alloc(bytes, false, "dilation row buffers", &st);
    if (!j.ring) {
        bvox_volume_destroy(*out);
        *out = NULL;
        return st;
    }
    /* With a progress callback, bands of rows one after the other (each band
     * recomputes 2 rows of zx per chunk: a few per cent, only then; bands of
     * a quarter of a second, see bvox__bands, make that nothing). */
    int64_t maxchunks = j.nchunks;
    bvox__bands bands;
    bvox__bands_begin(&bands, in->ny, in->ny >= 256 ? 16 : 1);
    for (int64_t lo = 0, hi; !st && lo < in->ny; lo = hi) {
        hi = bvox__bands_next(&bands, lo);
        j.y0 = lo;
        j.y1 = hi;
        j.nchunks = (j.y1 - j.y0) / 8 < maxchunks ? (j.y1 - j.y0) / 8 : maxchunks;
        if (j.nchunks < 1) j.nchunks = 1;
        bvox__parallel_for(j.nchunks, 1, erode ? box26_erode_chunks : box26_dilate_chunks, &j);
        st = bvox__progress_steps(hi, in->ny);
    }
    bvox__free(j.ring, bytes);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

/* General element: one output row at a time, combining shifted rows of the
 * z-processed volumes. */
static void offsets_range(void *ctx, int64_t begin, int64_t end)
{
    morph_job *j = ctx;
    bvox_volume *o = j->out;
    size_t wpc = o->wpc, row = (size_t)o->nx * wpc;
    for (int64_t y = begin; y < end; y++) {
        uint64_t *dst = o->words + (size_t)y * row;
        memset(dst, j->erode ? 0xff : 0, row * sizeof(uint64_t));
        for (int n = 0; n < j->noffs; n++) {
            int64_t sy = y + j->offs[n].dy;
            int dx = j->offs[n].dx;
            if (sy < 0 || sy >= o->ny) { /* the whole source row is outside: 0 */
                if (j->erode) memset(dst, 0, row * sizeof(uint64_t));
                continue;
            }
            const uint64_t *src = j->zs[j->zindex[n]] + (size_t)sy * row;
            /* dst column x takes source column x + dx */
            int64_t x0 = dx < 0 ? -dx : 0, x1 = dx > 0 ? o->nx - dx : o->nx;
            if (x1 < x0) x1 = x0;
            if (j->erode) {
                memset(dst, 0, (size_t)x0 * wpc * sizeof(uint64_t));
                memset(dst + (size_t)x1 * wpc, 0, (size_t)(o->nx - x1) * wpc * sizeof(uint64_t));
            }
            const uint64_t *s = src + (int64_t)dx * (int64_t)wpc;
            for (size_t i = (size_t)x0 * wpc; i < (size_t)x1 * wpc; i++)
                dst[i] = j->erode ? (dst[i] & s[i]) : (dst[i] | s[i]);
        }
        if (j->erode && o->tail_mask != ~0ull)
            for (size_t c = wpc - 1; c < row; c += wpc) dst[c] &= o->tail_mask;
    }
}

static bvox_status general(const bvox_volume *in, const offset *offs, int noffs, bool erode,
                           bvox_volume **out)
{
    /* one z-processed volume per distinct reach */
    int maxh = 0;
    for (int i = 0; i < noffs; i++) maxh = offs[i].h > maxh ? offs[i].h : maxh;
    bvox_volume **zv = bvox__mem_zalloc((size_t)maxh + 1, sizeof *zv);
    const uint64_t **zs = bvox__mem_zalloc((size_t)maxh + 1, sizeof *zs);
    int *zindex = bvox__mem_alloc((size_t)noffs * sizeof *zindex);
    bvox_status st = BVOX_OK;
    if (!zv || !zs || !zindex) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    /* progress: the z passes share the first half, the rows the second */
    int nz_passes = 0; /* distinct reaches (zs, still all NULL, marks them) */
    for (int i = 0; !st && i < noffs; i++)
        if (!zs[offs[i].h]) zs[offs[i].h] = in->words, nz_passes++;
    for (int h = 0; !st && h <= maxh; h++) zs[h] = NULL;
    int done = 0;
    for (int i = 0; !st && i < noffs; i++) {
        int h = offs[i].h;
        zindex[i] = h;
        if (!zv[h]) {
            bvox__progress_scope ps;
            bvox__progress_sub(&ps, 0.5 * done / nz_passes, 0.5 * (done + 1) / nz_passes, NULL);
            st = z_pass(in, h, erode, &zv[h]);
            bvox__progress_restore(&ps);
            done++;
        }
        if (!st) zs[h] = zv[h]->words;
    }
    bvox_dims d = {in->nx, in->ny, in->nz};
    if (!st) st = bvox__volume_create_uninit(d, out);
    if (!st) {
        (*out)->geom = in->geom;
        morph_job j = {.in = in, .out = *out, .erode = erode, .zs = zs, .offs = offs,
                       .zindex = zindex, .noffs = noffs};
        bvox__progress_scope ps;
        bvox__progress_sub(&ps, 0.5, 1, NULL);
        st = bvox__parallel_for_progress(in->ny, 8, offsets_range, &j);
        bvox__progress_restore(&ps);
        if (st) {
            bvox_volume_destroy(*out);
            *out = NULL;
        }
    }
    for (int h = 0; zv && h <= maxh; h++) bvox_volume_destroy(zv[h]);
    free(zv);
    free(zs);
    free(zindex);
    return st;
}

static bvox_status neighbourhood(const bvox_volume *in, int conn, bool erode, bvox_volume **out)
{
    *out = NULL;
    if (conn == 26) return box26(in, erode, out);
    if (conn != 6 && conn != 18)
        return bvox__fail(BVOX_EINVAL, "connectivity must be 6, 18 or 26, not %d", conn);
    offset offs[9];
    int n = 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int k = abs(dx) + abs(dy);
            if (conn == 6 && k == 2) continue;
            /* z reach: 6 -> only the centre column reaches z +-1;
             * 18 -> every column with at most one xy step does */
            int h = conn == 6 ? (k == 0) : (k <= 1);
            offs[n++] = (offset){dx, dy, h};
        }
    return general(in, offs, n, erode, out);
}

static bvox_status ball(const bvox_volume *in, double radius, bool erode, bvox_volume **out)
{
    *out = NULL;
    if (!isfinite(radius) || radius < 0)
        return bvox__fail(BVOX_EINVAL, "ball radius must be a finite number >= 0, not %g", radius);
    const double *s = in->geom.spacing;
    int rx = (int)floor(radius / s[0]), ry = (int)floor(radius / s[1]);
    if ((2.0 * rx + 1) * (2.0 * ry + 1) > MAX_OFFSETS)
        return bvox__fail(BVOX_EINVAL, "ball radius %g is %d x %d voxels across: too large",
                          radius, 2 * rx + 1, 2 * ry + 1);
    return bvox__morph_ball(in, radius, erode, out);
}

bvox_status bvox_morph_dilate(const bvox_volume *in, int conn, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(in);
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "dilate");
    bvox_status st = bvox__progress_end(&ps, neighbourhood(in, conn, false, out));
    BVOX_RETURN_CHECKED(st, BVOX_CHECK_VOLUME, *out);
}
bvox_status bvox_morph_erode(const bvox_volume *in, int conn, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(in);
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "erode");
    bvox_status st = bvox__progress_end(&ps, neighbourhood(in, conn, true, out));
    BVOX_RETURN_CHECKED(st, BVOX_CHECK_VOLUME, *out);
}
bvox_status bvox_morph_dilate_ball(const bvox_volume *in, double radius, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(in);
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "dilate");
    bvox_status st = bvox__progress_end(&ps, ball(in, radius, false, out));
    BVOX_RETURN_CHECKED(st, BVOX_CHECK_VOLUME, *out);
}
bvox_status bvox_morph_erode_ball(const bvox_volume *in, double radius, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(in);
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "erode");
    bvox_status st = bvox__progress_end(&ps, ball(in, radius, true, out));
    BVOX_RETURN_CHECKED(st, BVOX_CHECK_VOLUME, *out);
}
