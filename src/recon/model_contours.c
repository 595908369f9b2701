/*
 * model_contours.c — bvox_volume_to_contours: the outlines of the 1-voxels
 * of every slice across an axis, as a contour stack.
 *
 * Crack following on pixel edges: a boundary edge is a side of a 1-pixel
 * whose neighbour across it is 0 (or outside the slice), directed so that
 * the 1-pixel is on its right as seen on screen (y down): top sides run +x,
 * right sides +y, bottom sides -x, left sides -y. Every such edge belongs to
 * exactly one closed loop. Walking a loop, at each corner the next edge is
 *     turn right if the pixel ahead-right is 0, else straight on if the
 *     pixel ahead-left is 0, else turn left,
 * which keeps each pixel's square closed: two pixels touching only at a
 * corner are in separate loops (4-connected objects, 8-connected
 * background), so the even-odd fill of the loops (bvox_stack_to_volume) is
 * exactly the slice again: pixel centres never lie on the integer lines the
 * loops run along. Vertices are emitted only where the direction changes.
 * Outer loops have positive bvox_polygon_signed_area, holes negative.
 * Loops start at the first unvisited top side in raster order. A hole's
 * parent is the smallest outer loop that holds the centre of the pixel the
 * hole's loop started on (a pixel of the component around the hole; outer
 * loops of components further out are larger). Only the box of the slice's
 * 1 pixels is visited. Slices are independent:
 * they are dealt round-robin to one task per thread (across z in blocks of
 * 64, unpacked by 64x64 bit transposes of the column words).
 * Non-square slice pixels (su != sv): v coordinates are multiplied by sv/su
 * so that points are in pixels of su and outlines keep their physical shape
 * (height = ceil(h sv/su)); only square pixels round-trip voxel for voxel.
 */
#include "contour_internal.h"
#include "common/bits.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

enum { E = 0, S = 1, W = 2, N = 3 };
static const int DX[4] = {1, 0, -1, 0}, DY[4] = {0, 1, 0, -1};

typedef struct outer_loop {
    double area, x0, y0, x1, y1;
    int32_t index;
} outer_loop;

static int cmp_outer(const void *a, const void *b)
{
    const outer_loop *p = a, *q = b;
    if (p->area != q->area) return p->area < q->area ? -1 : 1;
    return (p->index > q->index) - (p->index < q->index);
}

typedef struct slice_img {
    int32_t w, h;      /* pixels */
    int32_t bx0, bx1, by0, by1; /* the box holding every 1 pixel (half-open; empty: bx0 >= bx1) */
    size_t stride;     /* w + 2: a border of zeros all round */
    uint8_t *px;       /* (h + 2) * stride; px[(y + 1) * stride + x + 1] */
    uint8_t *top;      /* unvisited top sides, same layout */
    bvox_point2 *probe; /* per contour of the slice: its start pixel's centre */
    size_t probe_cap;
    struct outer_loop *outer; /* the slice's outer loops, by area */
    size_t outer_cap;
    bvox_point2 *pts;
    size_t npts, cap;
} slice_img;

static inline int P(const slice_img *s, int32_t x, int32_t y)
{
    return s->px[(size_t)(y + 1) * s->stride + (size_t)(x + 1)];
}

static bool push(slice_img *s, int32_t x, int32_t y)
{
    if (!bvox__grow((void **)&s->pts, sizeof *s->pts, s->npts + 1, &s->cap, "contour points"))
        return false;
    s->pts[s->npts++] = (bvox_point2){(double)x, (double)y};
    return true;
}

/* Trace every loop of the slice into sec. */
static bvox_status trace_slice(slice_img *s, bvox_section *sec, double vscale)
{
    /* top sides exist only inside the box; every one is cleared when its
     * loop is walked, so `top` is all zero between slices */
    if (s->bx0 >= s->bx1) return BVOX_OK;
    for (int32_t y = s->by0; y < s->by1; y++) {
        const uint8_t *row = s->px + (size_t)(y + 1) * s->stride + 1, *up = row - s->stride;
        uint8_t *top = s->top + (size_t)(y + 1) * s->stride + 1;
        for (int32_t x = s->bx0; x < s->bx1; x++) top[x] = row[x] & (uint8_t)!up[x];
    }
    int32_t first = sec->ncontours;
    for (int32_t y0 = s->by0; y0 < s->by1; y0++) {
        uint8_t *top = s->top + (size_t)(y0 + 1) * s->stride + 1;
        for (int32_t x0 = s->bx0; x0 < s->bx1; x0++) {
            if (!top[x0]) continue;
            s->npts = 0;
            if (!push(s, x0, y0)) return BVOX_ENOMEM;
            int32_t x = x0, y = y0;
            int d = E;
            for (;;) {
                if (d == E) s->top[(size_t)(y + 1) * s->stride + (size_t)(x + 1)] = 0;
                x += DX[d];
                y += DY[d];
                /* the pixels ahead-right and ahead-left of corner (x, y) */
                int ra, la;
                switch (d) {
                case E: ra = P(s, x, y), la = P(s, x, y - 1); break;
                case S: ra = P(s, x - 1, y), la = P(s, x, y); break;
                case W: ra = P(s, x - 1, y - 1), la = P(s, x - 1, y); break;
                default: ra = P(s, x, y - 1), la = P(s, x - 1, y - 1); break;
                }
                int nd = !ra ? (d + 1) & 3 : !la ? d : (d + 3) & 3;
                if (x == x0 && y == y0 && nd == E) break;
                if (nd != d && !push(s, x, y)) return BVOX_ENOMEM;
                d = nd;
            }
            if (vscale != 1)
                for (size_t k = 0; k < s->npts; k++) s->pts[k].y *= vscale;
            double area = bvox_polygon_signed_area(s->pts, (int32_t)s->npts);
            bvox_status st = bvox_section_add_contour(sec, s->pts, (int32_t)s->npts, area < 0, -1);
            if (st) return st;
            /* the centre of the pixel the loop started on: inside the loop's
             * own component, never on a boundary (for the parents below) */
            size_t i = (size_t)(sec->ncontours - 1 - first);
            if (!bvox__grow((void **)&s->probe, sizeof *s->probe, i + 1, &s->probe_cap, "contours"))
                return BVOX_ENOMEM;
            s->probe[i] = (bvox_point2){x0 + 0.5, (y0 + 0.5) * vscale};
        }
    }
    /* A hole's parent: the outer loop of its component, which is the
     * smallest outer loop holding the hole's start pixel (outer loops of
     * enclosing components hold it too, and are larger). Outer loops are
     * tried by increasing area (boxes first), so the first hit is it. */
    int32_t nloops = sec->ncontours - first, nouter = 0, nholes = 0;
    for (int32_t i = first; i < sec->ncontours; i++) nholes += sec->contours[i].hole;
    if (nholes == 0) return BVOX_OK;
    if (!bvox__grow((void **)&s->outer, sizeof *s->outer, (size_t)nloops, &s->outer_cap, "contours"))
        return BVOX_ENOMEM;
    for (int32_t i = first; i < sec->ncontours; i++) {
        const bvox_contour *c = &sec->contours[i];
        if (c->hole) continue;
        outer_loop *o = &s->outer[nouter++];
        o->index = i;
        o->area = bvox_polygon_signed_area(c->points, c->npoints);
        o->x0 = o->y0 = HUGE_VAL;
        o->x1 = o->y1 = -HUGE_VAL;
        for (int32_t k = 0; k < c->npoints; k++) {
            o->x0 = fmin(o->x0, c->points[k].x), o->x1 = fmax(o->x1, c->points[k].x);
            o->y0 = fmin(o->y0, c->points[k].y), o->y1 = fmax(o->y1, c->points[k].y);
        }
    }
    qsort(s->outer, (size_t)nouter, sizeof *s->outer, cmp_outer);
    for (int32_t h = first; h < sec->ncontours; h++) {
        if (!sec->contours[h].hole) continue;
        bvox_point2 p = s->probe[h - first];
        for (int32_t k = 0; k < nouter; k++) {
            const outer_loop *o = &s->outer[k];
            if (p.x < o->x0 || p.x > o->x1 || p.y < o->y0 || p.y > o->y1) continue;
            const bvox_contour *c = &sec->contours[o->index];
            if (!bvox_polygon_contains(c->points, c->npoints, p)) continue;
            sec->contours[h].parent = o->index;
            break;
        }
    }
    return BVOX_OK;
}

static void slice_release(slice_img *s)
{
    size_t n = (size_t)(s->h + 2) * s->stride;
    bvox__free(s->px, n);
    bvox__free(s->top, n);
    free(s->probe);
    free(s->outer);
    free(s->pts);
}

/* The slice's pixel and visit maps, from the budget. */
static bvox_status slice_alloc(slice_img *si, int32_t w, int32_t h)
{
    memset(si, 0, sizeof *si);
    si->w = w;
    si->h = h;
    si->stride = (size_t)w + 2;
    size_t n = (size_t)(h + 2) * si->stride;
    bvox_status st;
    si->px = bvox__alloc(n, true, "slice map", &st);
    if (si->px) si->top = bvox__alloc(n, true, "slice map", &st);
    return st;
}

/* What a traced section holds: its points and contour records. */
static size_t section_bytes(const bvox_section *sec)
{
    size_t b = (size_t)sec->ncontours * sizeof(bvox_contour);
    for (int32_t i = 0; i < sec->ncontours; i++)
        b += (size_t)sec->contours[i].npoints * sizeof(bvox_point2);
    return b;
}

typedef struct mc_ctx {
    const bvox_volume *vol;
    int axis;
    int32_t w, h, nslices, ntasks;
    double vscale;
    bvox_contour_stack *stack;
    bvox_status *task_status;
    int32_t *task_slice; /* the slice a failed task was at */
    _Atomic size_t charged;  /* the sections' bytes, charged to the budget */
} mc_ctx;

/* Charge a traced section to the budget (the stack keeps the charge until
 * it is destroyed): a model with too many outlines stops at the budget. */
static bvox_status charge_section(mc_ctx *c, const bvox_section *sec)
{
    size_t b = section_bytes(sec);
    bvox_status st;
    if (!bvox__budget_charge(b, "contours", &st)) return st;
    atomic_fetch_add(&c->charged, b);
    return BVOX_OK;
}

/* Slices across x or y: pixel (u, v) is bit v (= z) of column (k, u) or
 * (u, k); every column is read once, by the slice it belongs to. */
static void fill_xy(const mc_ctx *c, slice_img *si, int32_t k)
{
    const bvox_volume *vol = c->vol;
    si->bx0 = c->w, si->bx1 = 0, si->by0 = c->h, si->by1 = 0;
    for (int32_t u = 0; u < c->w; u++) {
        const uint64_t *col = c->axis == 0 ? bvox__column_c(vol, k, u) : bvox__column_c(vol, u, k);
        for (size_t wd = 0; wd < vol->wpc; wd++) {
            uint64_t bits = col[wd];
            int32_t v0 = (int32_t)(wd * 64);
            if (bits) { /* tail bits are zero: the box stays inside the slice */
                if (u < si->bx0) si->bx0 = u;
                if (u + 1 > si->bx1) si->bx1 = u + 1;
                int32_t lo = v0 + __builtin_ctzll(bits), hi = v0 + 64 - __builtin_clzll(bits);
                if (lo < si->by0) si->by0 = lo;
                if (hi > si->by1) si->by1 = hi;
            }
            for (int32_t b = 0; b < 64 && v0 + b < c->h; b++)
                si->px[(size_t)(v0 + b + 1) * si->stride + (size_t)(u + 1)] = (uint8_t)((bits >> b) & 1);
        }
    }
}

static void mc_task(void *ctx, int64_t begin, int64_t end)
{
    mc_ctx *c = ctx;
    for (int64_t t = begin; t < end; t++) {
        slice_img si;
        bvox_status st = BVOX_OK;
        int32_t at = -1;
        uint64_t *rows = NULL; /* axis z: 64 slices x h rows x wpr words */
        size_t wpr = ((size_t)c->w + 63) / 64;
        size_t rows_bytes = (size_t)64 * (size_t)c->h * wpr * sizeof *rows;
        st = slice_alloc(&si, c->w, c->h);
        if (!st && c->axis == 2) rows = bvox__alloc(rows_bytes, false, "slice rows", &st);
        if (c->axis == 2) {
            /* blocks of 64 slices dealt round-robin: one transpose per 64
             * columns gives 64 slices' rows */
            int32_t nblocks = (c->nslices + 63) / 64;
            const bvox_volume *vol = c->vol;
            for (int32_t blk = (int32_t)t; blk < nblocks && !st; blk += c->ntasks) {
                int32_t k0 = blk * 64, kn = c->nslices - k0 < 64 ? c->nslices - k0 : 64;
                _Alignas(64) uint64_t m[64];
                for (int32_t y = 0; y < c->h; y++)
                    for (size_t wd = 0; wd < wpr; wd++) {
                        size_t x0 = wd * 64, width = (size_t)c->w - x0 < 64 ? (size_t)c->w - x0 : 64;
                        const uint64_t *col = bvox__column_c(vol, (int32_t)x0, y) + (size_t)blk;
                        for (size_t i = 0; i < width; i++) m[i] = col[i * vol->wpc];
                        for (size_t i = width; i < 64; i++) m[i] = 0;
                        bvox__transpose64(m);
                        for (int32_t k = 0; k < kn; k++)
                            rows[((size_t)k * (size_t)c->h + (size_t)y) * wpr + wd] = m[k];
                    }
                for (int32_t k = 0; k < kn && !st; k++) {
                    /* clear the last slice's box, find and fill this one's */
                    for (int32_t y = si.by0; y < si.by1; y++)
                        memset(si.px + (size_t)(y + 1) * si.stride + 1 + si.bx0, 0,
                               (size_t)(si.bx1 - si.bx0));
                    si.bx0 = c->w, si.bx1 = 0, si.by0 = c->h, si.by1 = 0;
                    for (int32_t y = 0; y < c->h; y++) {
                        const uint64_t *r = rows + ((size_t)k * (size_t)c->h + (size_t)y) * wpr;
                        for (size_t wd = 0; wd < wpr; wd++) {
                            if (!r[wd]) continue;
                            int32_t lo = (int32_t)(wd * 64) + __builtin_ctzll(r[wd]);
                            int32_t hi = (int32_t)(wd * 64) + 64 - __builtin_clzll(r[wd]);
                            if (lo < si.bx0) si.bx0 = lo;
                            if (hi > si.bx1) si.bx1 = hi;
                            if (y < si.by0) si.by0 = y;
                            si.by1 = y + 1;
                        }
                    }
                    for (int32_t y = si.by0; y < si.by1; y++) {
                        const uint64_t *r = rows + ((size_t)k * (size_t)c->h + (size_t)y) * wpr;
                        uint8_t *dst = si.px + (size_t)(y + 1) * si.stride + 1;
                        for (int32_t x = si.bx0; x < si.bx1; x++)
                            dst[x] = (uint8_t)((r[x >> 6] >> (x & 63)) & 1);
                    }
                    at = k0 + k;
                    st = trace_slice(&si, &c->stack->sections[at], c->vscale);
                    if (!st) st = charge_section(c, &c->stack->sections[at]);
                }
            }
        } else {
            for (int32_t k = (int32_t)t; k < c->nslices && !st; k += c->ntasks) {
                fill_xy(c, &si, k);
                at = k;
                st = trace_slice(&si, &c->stack->sections[k], c->vscale);
                if (!st) st = charge_section(c, &c->stack->sections[k]);
            }
        }
        bvox__free(rows, rows_bytes);
        slice_release(&si);
        c->task_status[t] = st;
        c->task_slice[t] = at;
    }
}

bvox_status bvox_volume_to_contours(const bvox_volume *vol, int axis, bvox_contour_stack **out)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_volume_to_contours: out is NULL");
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "bvox_volume_to_contours: volume is NULL");
    if (axis < 0 || axis > 2) return bvox__fail(BVOX_EINVAL, "axis %d is not 0 (x), 1 (y) or 2 (z)", axis);
    const bvox_geometry *g = &vol->geom;
    int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2; /* the slice plane's axes */
    const int32_t dims[3] = {vol->nx, vol->ny, vol->nz};
    int32_t w = dims[ua], h = dims[va], nslices = dims[axis];
    size_t n = (size_t)(h + 2) * ((size_t)w + 2);
    if (n > INT32_MAX)
        return bvox__fail(BVOX_ETOOBIG, "slices of %d x %d pixels are too large to trace", (int)w, (int)h);
    bvox_contour_stack *s = NULL;
    bvox_status st = bvox_stack_create(&s);
    if (st) return st;
    memcpy(s->unit, g->unit, sizeof s->unit);
    s->unit[sizeof s->unit - 1] = '\0';
    s->pixel = g->spacing[ua];
    s->spacing = g->spacing[axis];
    s->origin[0] = g->origin[ua] - 0.5 * g->spacing[ua];
    s->origin[1] = g->origin[va] - 0.5 * g->spacing[va];
    /* non-square pixels: v is scaled to pixels of u, so the outlines keep
     * their physical shape (the slice's height grows or shrinks with it) */
    double vscale = g->spacing[va] / g->spacing[ua];
    s->width = w;
    double fh = ceil(h * vscale);
    s->height = fh < 1 ? 1 : fh > BVOX_MAX_DIM ? BVOX_MAX_DIM : (int32_t)fh;
    for (int32_t k = 0; k < nslices && !st; k++)
        st = bvox_stack_add_section(s, g->origin[axis] + k * g->spacing[axis], NULL, NULL);
    mc_ctx c = {vol, axis, w, h, nslices, 1, vscale, s, NULL, NULL, 0};
    int32_t units = axis == 2 ? (nslices + 63) / 64 : nslices;
    c.ntasks = bvox__parallelism();
    if (c.ntasks > units) c.ntasks = units;
    /* a thread is worth it for about a million pixels */
    if ((int64_t)w * h * nslices < ((int64_t)1 << 20)) c.ntasks = 1;
    if (!st) {
        c.task_status = bvox__mem_zalloc((size_t)c.ntasks, sizeof *c.task_status);
        c.task_slice = bvox__mem_zalloc((size_t)c.ntasks, sizeof *c.task_slice);
        if (!c.task_status || !c.task_slice) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    if (!st) {
        bvox__parallel_for(c.ntasks, 1, mc_task, &c);
        /* the workers' messages are in their own threads: say it again here */
        char lim[32];
        bvox__format_bytes(lim, sizeof lim, bvox_memory_budget());
        for (int32_t t = 0; t < c.ntasks && !st; t++)
            if (c.task_status[t] == BVOX_ETOOBIG && c.task_slice[t] >= 0)
                st = bvox__fail(BVOX_ETOOBIG,
                                "tracing slice %d across %c: the contours and their buffers "
                                "reach the memory budget of %s",
                                (int)c.task_slice[t], "xyz"[axis], lim);
            else if (c.task_status[t] == BVOX_ETOOBIG)
                st = bvox__fail(BVOX_ETOOBIG,
                                "tracing across %c: the buffers for slices of %d x %d pixels "
                                "are over the memory budget of %s",
                                "xyz"[axis], (int)w, (int)h, lim);
            else if (c.task_status[t])
                st = bvox__fail(c.task_status[t],
                                "tracing slice %d across %c: %s (a slice of %d x %d pixels)",
                                (int)c.task_slice[t], "xyz"[axis],
                                c.task_status[t] == BVOX_ENOMEM ? "out of memory" : "too many contours or points",
                                (int)w, (int)h);
    }
    bvox__stack_charged(s, atomic_load(&c.charged));
    free(c.task_status);
    free(c.task_slice);
    if (st) {
        bvox_stack_destroy(s);
        return st;
    }
    *out = s;
    BVOX_CHECK_STACK(*out);
    return BVOX_OK;
}
