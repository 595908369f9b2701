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
 * path (z, then x, then y: three 3-tap passes instead of nine). Voxels outside
 * the volume are 0 for both operations.
 */
#include "internal.h"

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
    const uint64_t *src;      /* 3-tap passes: source words */
    int axis;                 /* 0 = x, 1 = y */
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
    bvox__parallel_for((int64_t)in->nx * in->ny, 4096, z_range, &j);
    return BVOX_OK;
}

/* 3-tap pass along x (neighbour columns) or y (neighbour rows), in a row. */
static void tap_range(void *ctx, int64_t begin, int64_t end)
{
    morph_job *j = ctx;
    const bvox_volume *v = j->out;
    size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    for (int64_t y = begin; y < end; y++) {
        uint64_t *dst = j->out->words + (size_t)y * row;
        const uint64_t *mid = j->src + (size_t)y * row;
        if (j->axis == 0) {
            for (size_t i = 0; i < row; i++) {
                uint64_t l = i >= wpc ? mid[i - wpc] : 0;
                uint64_t r = i + wpc < row ? mid[i + wpc] : 0;
                dst[i] = j->erode ? (mid[i] & l & r) : (mid[i] | l | r);
            }
        } else {
            const uint64_t *up = y > 0 ? mid - row : NULL;
            const uint64_t *dn = y + 1 < v->ny ? mid + row : NULL;
            for (size_t i = 0; i < row; i++) {
                uint64_t a = up ? up[i] : 0, b = dn ? dn[i] : 0;
                dst[i] = j->erode ? (mid[i] & a & b) : (mid[i] | a | b);
            }
        }
    }
}

/* The 26-neighbourhood: z, then x, then y, each a 3-tap pass. */
static bvox_status box26(const bvox_volume *in, bool erode, bvox_volume **out)
{
    bvox_volume *a, *b;
    bvox_status st = z_pass(in, 1, erode, &a);
    if (st) return st;
    st = bvox_volume_copy(a, &b);
    if (st) {
        bvox_volume_destroy(a);
        return st;
    }
    morph_job j = {.in = in, .out = b, .erode = erode, .src = a->words, .axis = 0};
    bvox__parallel_for(in->ny, 8, tap_range, &j); /* b = x pass of a */
    j = (morph_job){.in = in, .out = a, .erode = erode, .src = b->words, .axis = 1};
    bvox__parallel_for(in->ny, 8, tap_range, &j); /* a = y pass of b */
    bvox_volume_destroy(b);
    *out = a;
    return BVOX_OK;
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
    bvox_volume **zv = calloc((size_t)maxh + 1, sizeof *zv);
    const uint64_t **zs = calloc((size_t)maxh + 1, sizeof *zs);
    int *zindex = malloc((size_t)noffs * sizeof *zindex);
    bvox_status st = BVOX_OK;
    if (!zv || !zs || !zindex) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    for (int i = 0; !st && i < noffs; i++) {
        int h = offs[i].h;
        zindex[i] = h;
        if (!zv[h]) st = z_pass(in, h, erode, &zv[h]);
        if (!st) zs[h] = zv[h]->words;
    }
    bvox_dims d = {in->nx, in->ny, in->nz};
    if (!st) st = bvox__volume_create_uninit(d, out);
    if (!st) {
        (*out)->geom = in->geom;
        morph_job j = {.in = in, .out = *out, .erode = erode, .zs = zs, .offs = offs,
                       .zindex = zindex, .noffs = noffs};
        bvox__parallel_for(in->ny, 8, offsets_range, &j);
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
    offset *offs = malloc(MAX_OFFSETS * sizeof *offs);
    if (!offs) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int n = 0;
    double r2 = radius * radius;
    for (int dy = -ry; dy <= ry; dy++)
        for (int dx = -rx; dx <= rx; dx++) {
            double rest = r2 - (dx * s[0]) * (dx * s[0]) - (dy * s[1]) * (dy * s[1]);
            if (rest < 0) continue;
            int h = (int)floor(sqrt(rest) / s[2] + 1e-9);
            if (h > in->nz) h = in->nz;
            offs[n++] = (offset){dx, dy, h};
        }
    bvox_status st = general(in, offs, n, erode, out);
    free(offs);
    return st;
}

bvox_status bvox_morph_dilate(const bvox_volume *in, int conn, bvox_volume **out)
{
    return neighbourhood(in, conn, false, out);
}
bvox_status bvox_morph_erode(const bvox_volume *in, int conn, bvox_volume **out)
{
    return neighbourhood(in, conn, true, out);
}
bvox_status bvox_morph_dilate_ball(const bvox_volume *in, double radius, bvox_volume **out)
{
    return ball(in, radius, false, out);
}
bvox_status bvox_morph_erode_ball(const bvox_volume *in, double radius, bvox_volume **out)
{
    return ball(in, radius, true, out);
}
