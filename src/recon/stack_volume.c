/*
 * stack_volume.c — contour stack -> binary model (bvox_stack_to_volume):
 * scan conversion of every section, shape-based interpolation between
 * sections through signed distance maps, and the packing of the slices into
 * column words. The rules (extent, z range, tie rule, geometry) are in the
 * doc comment in include/bvox/contours.h.
 *
 *  1. every section is scan-converted into a bitmap (contour_scan.c),
 *     sections split over the threads;
 *  2. the distance maps (contour_edt.c) are computed only inside the box of
 *     all sections' 1-pixels grown by one pixel (clipped to the image): a
 *     point outside it is outside every section, and inside it the map is
 *     exact because the ring around the box is background (the nearest
 *     background pixel of any point of the box is never beyond the ring).
 *     Only sections next to an interpolated slice get a map; one task per
 *     thread with its own scratch, sections dealt round-robin;
 *  3. the output slices, 64 at a time: each slice is built as a bitmap
 *     (a copy of a section, or the blend (1 - t) d_a + t d_b <= 0 over the
 *     box), slices split over the threads; then per row y, the 64 slices'
 *     words of 64 columns are transposed (64x64 bit transpose) into the
 *     columns' z words, rows split over the threads.
 */
#include "contour_internal.h"
#include "common/bits.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bvox_stack_volume_opts bvox_stack_volume_opts_default(void)
{
    bvox_stack_volume_opts o = {0.0, 1, 1};
    return o;
}

typedef struct sv {
    const bvox_contour_stack *stack;
    int32_t nsec;
    int32_t *order;      /* sorted position -> section index */
    double *zs;          /* sorted z */
    int32_t x0, y0, nx, ny;
    size_t wpr, plane;   /* words per bitmap row, per bitmap */
    uint64_t *secbits;   /* nsec bitmaps, in sorted order */
    size_t secbits_bytes;
    int32_t rx0, ry0, rnx, rny; /* the distance-map box, window coordinates */
    size_t rarea;
    float cap;
    int32_t *map_of;     /* sorted position -> distance map slot, -1 none */
    int32_t nmaps;
    float *dist;
    size_t dist_bytes;
    double *scratch;     /* one per task */
    size_t scratch_doubles;
    int32_t ntasks;
    int32_t *mapped;     /* slot -> sorted position */
    /* output */
    int32_t nz;
    double zmid, dz;
    int interpolate;
    int32_t kb, kn;      /* current block of slices */
    uint64_t *slices;    /* 64 bitmaps */
    size_t slices_bytes;
    bvox_volume *vol;
} sv;

static double slice_z(const sv *s, int32_t k)
{
    return s->zmid + ((double)k - (s->nz - 1) / 2.0) * s->dz;
}

/* What slice k is made of: section a alone (b < 0) or the blend at t. */
static void slice_source(const sv *s, int32_t k, int32_t *a, int32_t *b, double *t)
{
    double z = slice_z(s, k);
    *b = -1;
    *t = 0;
    if (z <= s->zs[0]) {
        *a = 0;
        return;
    }
    if (z >= s->zs[s->nsec - 1]) {
        *a = s->nsec - 1;
        return;
    }
    int32_t lo = 0, hi = s->nsec - 1; /* zs[lo] < z < zs[hi] */
    while (hi - lo > 1) {
        int32_t mid = lo + (hi - lo) / 2;
        if (s->zs[mid] <= z) lo = mid;
        else hi = mid;
    }
    double za = s->zs[lo], zb = s->zs[hi], eps = 1e-9 * (zb - za);
    if (z - za <= eps) {
        *a = lo;
        return;
    }
    if (zb - z <= eps) {
        *a = hi;
        return;
    }
    if (!s->interpolate) { /* nearest; a tie goes to the lower section */
        *a = z - za <= zb - z ? lo : hi;
        return;
    }
    *a = lo;
    *b = hi;
    *t = (z - za) / (zb - za);
}

static void scan_task(void *ctx, int64_t begin, int64_t end)
{
    sv *s = ctx;
    for (int64_t i = begin; i < end; i++)
        bvox__scan_section(&s->stack->sections[s->order[i]], s->x0, s->y0, s->nx, s->ny, s->wpr,
                           s->secbits + (size_t)i * s->plane);
}

static void edt_task(void *ctx, int64_t begin, int64_t end)
{
    sv *s = ctx;
    for (int64_t task = begin; task < end; task++) {
        double *tmp = s->scratch + (size_t)task * s->scratch_doubles;
        for (int32_t slot = (int32_t)task; slot < s->nmaps; slot += s->ntasks) {
            int32_t pos = s->mapped[slot];
            /* the box of this section's bitmap: rows ry0.., words from rx0's word */
            const uint64_t *bits = s->secbits + (size_t)pos * s->plane + (size_t)s->ry0 * s->wpr;
            float *out = s->dist + (size_t)slot * s->rarea;
            if (s->rx0 % 64 == 0) {
                bvox__signed_edt(bits + s->rx0 / 64, s->wpr, s->rnx, s->rny, s->cap, tmp, out);
            } else {
                /* shift the box's rows to start at bit 0: a small copy */
                size_t bw = ((size_t)s->rnx + 63) / 64;
                uint64_t *shifted = (uint64_t *)(tmp + bvox__edt_scratch_doubles(s->rnx, s->rny));
                unsigned sh = (unsigned)(s->rx0 % 64);
                for (int32_t y = 0; y < s->rny; y++) {
                    const uint64_t *row = bits + (size_t)y * s->wpr + s->rx0 / 64;
                    size_t avail = s->wpr - (size_t)(s->rx0 / 64);
                    for (size_t w = 0; w < bw; w++) {
                        uint64_t lo = row[w] >> sh;
                        uint64_t hi = w + 1 < avail ? row[w + 1] << (64 - sh) : 0;
                        shifted[(size_t)y * bw + w] = lo | hi;
                    }
                }
                bvox__signed_edt(shifted, bw, s->rnx, s->rny, s->cap, tmp, out);
            }
        }
    }
}

/* Build slice k's bitmap into dst. */
static void make_slice(const sv *s, int32_t k, uint64_t *dst)
{
    int32_t a, b;
    double t;
    slice_source(s, k, &a, &b, &t);
    if (b < 0) {
        memcpy(dst, s->secbits + (size_t)a * s->plane, s->plane * sizeof *dst);
        return;
    }
    memset(dst, 0, s->plane * sizeof *dst);
    if (s->map_of[a] < 0 || s->map_of[b] < 0) return; /* every section is empty */
    const float *da = s->dist + (size_t)s->map_of[a] * s->rarea;
    const float *db = s->dist + (size_t)s->map_of[b] * s->rarea;
    const float ta = (float)(1.0 - t), tb = (float)t;
    for (int32_t y = 0; y < s->rny; y++) {
        const float *ra = da + (size_t)y * s->rnx, *rb = db + (size_t)y * s->rnx;
        uint64_t *row = dst + (size_t)(s->ry0 + y) * s->wpr;
        int32_t x = 0;
        while (x < s->rnx) {
            int32_t gx = s->rx0 + x;           /* window column */
            int32_t n = 64 - (gx & 63);        /* up to the end of this word */
            if (n > s->rnx - x) n = s->rnx - x;
            uint64_t m = 0;
            for (int32_t i = 0; i < n; i++)
                m |= (uint64_t)(ta * ra[x + i] + tb * rb[x + i] <= 0.0f) << i;
            row[gx >> 6] |= m << (gx & 63);
            x += n;
        }
    }
}

static void slice_task(void *ctx, int64_t begin, int64_t end)
{
    sv *s = ctx;
    for (int64_t i = begin; i < end; i++) make_slice(s, s->kb + (int32_t)i, s->slices + (size_t)i * s->plane);
}

static void pack_task(void *ctx, int64_t begin, int64_t end)
{
    sv *s = ctx;
    bvox_volume *v = s->vol;
    size_t zw = (size_t)s->kb / 64;
    _Alignas(64) uint64_t m[64];
    for (int64_t y = begin; y < end; y++) {
        for (size_t w = 0; w < s->wpr; w++) {
            for (int32_t i = 0; i < 64; i++)
                m[i] = i < s->kn ? s->slices[(size_t)i * s->plane + (size_t)y * s->wpr + w] : 0;
            bvox__transpose64(m);
            size_t x0 = w * 64;
            size_t width = (size_t)s->nx - x0 < 64 ? (size_t)s->nx - x0 : 64;
            uint64_t *col = v->words + ((size_t)y * (size_t)s->nx + x0) * v->wpc + zw;
            for (size_t i = 0; i < width; i++) col[i * v->wpc] = m[i];
        }
    }
}

typedef struct zkey {
    double z;
    int32_t index;
} zkey;

static int cmp_zkey(const void *pa, const void *pb)
{
    const zkey *a = pa, *b = pb;
    if (a->z != b->z) return a->z < b->z ? -1 : 1;
    return (a->index > b->index) - (a->index < b->index);
}

static void sv_release(sv *s)
{
    free(s->order);
    free(s->zs);
    free(s->map_of);
    free(s->mapped);
    bvox__free(s->secbits, s->secbits_bytes);
    bvox__free(s->dist, s->dist_bytes);
    if (s->scratch)
        bvox__free(s->scratch, (size_t)s->ntasks * s->scratch_doubles * sizeof(double));
    bvox__free(s->slices, s->slices_bytes);
}

/* The window (x0, y0, nx, ny) in section pixels. */
static bvox_status extent(const bvox_contour_stack *st, int32_t margin, sv *s)
{
    if (st->width > 0 && st->height > 0) {
        s->x0 = s->y0 = 0;
        s->nx = st->width;
        s->ny = st->height;
    } else {
        double xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
        for (int32_t i = 0; i < st->nsections; i++)
            for (int32_t c = 0; c < st->sections[i].ncontours; c++) {
                const bvox_contour *ct = &st->sections[i].contours[c];
                for (int32_t k = 0; k < ct->npoints; k++) {
                    bvox_point2 p = ct->points[k];
                    if (p.x < xmin) xmin = p.x;
                    if (p.x > xmax) xmax = p.x;
                    if (p.y < ymin) ymin = p.y;
                    if (p.y > ymax) ymax = p.y;
                }
            }
        if (xmin > xmax)
            return bvox__fail(BVOX_EINVAL,
                              "the contour stack has no contours and no width/height: no extent");
        double fx0 = floor(xmin) - margin, fx1 = ceil(xmax) + margin;
        double fy0 = floor(ymin) - margin, fy1 = ceil(ymax) + margin;
        if (fx1 - fx0 > BVOX_MAX_DIM || fy1 - fy0 > BVOX_MAX_DIM)
            return bvox__fail(BVOX_ETOOBIG, "the contours span %.6g x %.6g pixels (at most %d)",
                              fx1 - fx0, fy1 - fy0, BVOX_MAX_DIM);
        s->x0 = (int32_t)fx0;
        s->y0 = (int32_t)fy0;
        s->nx = (int32_t)(fx1 - fx0);
        s->ny = (int32_t)(fy1 - fy0);
        if (s->nx < 1) s->nx = 1;
        if (s->ny < 1) s->ny = 1;
    }
    if (s->nx > BVOX_MAX_DIM || s->ny > BVOX_MAX_DIM)
        return bvox__fail(BVOX_ETOOBIG, "image of %d x %d pixels (at most %d)", (int)s->nx,
                          (int)s->ny, BVOX_MAX_DIM);
    return BVOX_OK;
}

bvox_status bvox_stack_to_volume(const bvox_contour_stack *stack, const bvox_stack_volume_opts *opts,
                                 bvox_volume **out)
{
    BVOX_CHECK_STACK(stack);
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_to_volume: out is NULL");
    *out = NULL;
    if (!stack) return bvox__fail(BVOX_EINVAL, "bvox_stack_to_volume: stack is NULL");
    bvox_stack_volume_opts o = opts ? *opts : bvox_stack_volume_opts_default();
    if (stack->nsections < 1) return bvox__fail(BVOX_EINVAL, "the contour stack has no sections");
    if (!(stack->pixel > 0) || !isfinite(stack->pixel) || !(stack->spacing > 0) ||
        !isfinite(stack->spacing))
        return bvox__fail(BVOX_EINVAL, "pixel size %g and section spacing %g must be > 0",
                          stack->pixel, stack->spacing);
    if (!(o.z_spacing >= 0) || !isfinite(o.z_spacing))
        return bvox__fail(BVOX_EINVAL, "z spacing %g must be >= 0", o.z_spacing);
    if (o.margin < 0 || o.margin > 4096)
        return bvox__fail(BVOX_EINVAL, "margin %d must be in 0..4096", (int)o.margin);
    double dz = o.z_spacing > 0 ? o.z_spacing : stack->pixel;

    sv s;
    memset(&s, 0, sizeof s);
    s.stack = stack;
    s.nsec = stack->nsections;
    s.interpolate = o.interpolate != 0;
    bvox_status st = extent(stack, o.margin, &s);
    if (st) return st;
    s.wpr = ((size_t)s.nx + 63) / 64;
    s.plane = s.wpr * (size_t)s.ny;

    /* sort the sections by z; equal z is an error */
    s.order = bvox__mem_alloc((size_t)s.nsec * sizeof *s.order);
    s.zs = bvox__mem_alloc((size_t)s.nsec * sizeof *s.zs);
    s.map_of = bvox__mem_alloc((size_t)s.nsec * sizeof *s.map_of);
    s.mapped = bvox__mem_alloc((size_t)s.nsec * sizeof *s.mapped);
    if (!s.order || !s.zs || !s.map_of || !s.mapped) {
        sv_release(&s);
        return bvox__fail(BVOX_ENOMEM, "out of memory for the section order");
    }
    zkey *keys = bvox__mem_alloc((size_t)s.nsec * sizeof *keys);
    if (!keys) {
        sv_release(&s);
        return bvox__fail(BVOX_ENOMEM, "out of memory for the section order");
    }
    for (int32_t i = 0; i < s.nsec; i++) keys[i] = (zkey){stack->sections[i].z, i};
    qsort(keys, (size_t)s.nsec, sizeof *keys, cmp_zkey);
    for (int32_t i = 0; i < s.nsec; i++) s.order[i] = keys[i].index;
    free(keys);
    for (int32_t i = 0; i < s.nsec; i++) {
        s.zs[i] = stack->sections[s.order[i]].z;
        s.map_of[i] = -1;
        if (i > 0 && s.zs[i] == s.zs[i - 1]) {
            char l1[160], l2[160];
            bvox__section_label(&stack->sections[s.order[i - 1]], s.order[i - 1], l1, sizeof l1);
            bvox__section_label(&stack->sections[s.order[i]], s.order[i], l2, sizeof l2);
            sv_release(&s);
            return bvox__fail(BVOX_EINVAL, "%s and %s are at the same z", l1, l2);
        }
    }

    /* z extent */
    double length = (s.zs[s.nsec - 1] - s.zs[0]) + stack->spacing;
    double fnz = floor(length / dz + 0.5);
    if (!(fnz <= BVOX_MAX_DIM)) {
        sv_release(&s);
        return bvox__fail(BVOX_ETOOBIG, "%.6g slices of %g %s over %g (at most %d)", fnz, dz,
                          stack->unit, length, BVOX_MAX_DIM);
    }
    s.nz = fnz < 1 ? 1 : (int32_t)fnz;
    s.dz = dz;
    s.zmid = (s.zs[0] + s.zs[s.nsec - 1]) / 2;

    bvox_dims dims = {s.nx, s.ny, s.nz};
    st = bvox_volume_create(dims, &s.vol);
    if (st) {
        sv_release(&s);
        return st;
    }

    if (!bvox__mul_size(s.plane * sizeof(uint64_t), (size_t)s.nsec, &s.secbits_bytes)) {
        sv_release(&s);
        bvox_volume_destroy(s.vol);
        return bvox__fail(BVOX_ETOOBIG, "the section bitmaps are too large");
    }
    s.secbits = bvox__alloc(s.secbits_bytes, false, "section bitmaps", &st);
    if (!s.secbits) goto fail;
    bvox__parallel_for(s.nsec, 4, scan_task, &s);

    /* box of all 1-pixels, grown by one pixel, clipped */
    int32_t bx0 = s.nx, bx1 = -1, by0 = s.ny, by1 = -1;
    for (int32_t y = 0; y < s.ny; y++) {
        for (size_t w = 0; w < s.wpr; w++) {
            uint64_t any = 0;
            for (int32_t i = 0; i < s.nsec; i++) any |= s.secbits[(size_t)i * s.plane + (size_t)y * s.wpr + w];
            if (!any) continue;
            int32_t lo = (int32_t)(w * 64) + __builtin_ctzll(any);
            int32_t hi = (int32_t)(w * 64) + 63 - __builtin_clzll(any);
            if (lo < bx0) bx0 = lo;
            if (hi > bx1) bx1 = hi;
            if (y < by0) by0 = y;
            if (y > by1) by1 = y;
        }
    }

    /* which sections need a distance map */
    s.nmaps = 0;
    if (s.interpolate && bx1 >= 0) {
        for (int32_t k = 0; k < s.nz; k++) {
            int32_t a, b;
            double t;
            slice_source(&s, k, &a, &b, &t);
            if (b < 0) continue;
            if (s.map_of[a] < 0) { s.mapped[s.nmaps] = a; s.map_of[a] = s.nmaps++; }
            if (s.map_of[b] < 0) { s.mapped[s.nmaps] = b; s.map_of[b] = s.nmaps++; }
        }
    }
    if (s.nmaps > 0) {
        s.rx0 = bx0 > 0 ? bx0 - 1 : 0;
        s.ry0 = by0 > 0 ? by0 - 1 : 0;
        s.rnx = (bx1 + 1 < s.nx ? bx1 + 2 : s.nx) - s.rx0;
        s.rny = (by1 + 1 < s.ny ? by1 + 2 : s.ny) - s.ry0;
        s.rarea = (size_t)s.rnx * (size_t)s.rny;
        s.cap = (float)(s.rnx + s.rny + 2);
        if (!bvox__mul_size(s.rarea * sizeof(float), (size_t)s.nmaps, &s.dist_bytes)) {
            st = bvox__fail(BVOX_ETOOBIG, "the distance maps are too large");
            goto fail;
        }
        s.dist = bvox__alloc(s.dist_bytes, false, "distance maps", &st);
        if (!s.dist) goto fail;
        s.ntasks = bvox__parallelism();
        if (s.ntasks > s.nmaps) s.ntasks = s.nmaps;
        /* EDT scratch plus room for a shifted copy of the box's bits */
        s.scratch_doubles = bvox__edt_scratch_doubles(s.rnx, s.rny) +
                            ((size_t)s.rnx + 63) / 64 * (size_t)s.rny + 8;
        size_t sbytes;
        if (!bvox__mul_size(s.scratch_doubles * sizeof(double), (size_t)s.ntasks, &sbytes)) {
            st = bvox__fail(BVOX_ETOOBIG, "the distance scratch is too large");
            goto fail;
        }
        s.scratch = bvox__alloc(sbytes, false, "distance map scratch", &st);
        if (!s.scratch) goto fail;
        bvox__parallel_for(s.ntasks, 1, edt_task, &s);
    }

    /* the slices, 64 at a time */
    s.slices_bytes = s.plane * 64 * sizeof(uint64_t);
    s.slices = bvox__alloc(s.slices_bytes, false, "slice bitmaps", &st);
    if (!s.slices) goto fail;
    int64_t per_row_min = ((int64_t)1 << 16) / ((int64_t)s.wpr * 64) + 1;
    for (s.kb = 0; s.kb < s.nz; s.kb += 64) {
        s.kn = s.nz - s.kb < 64 ? s.nz - s.kb : 64;
        bvox__parallel_for(s.kn, 1, slice_task, &s);
        bvox__parallel_for(s.ny, per_row_min, pack_task, &s);
    }

    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = g.spacing[1] = stack->pixel;
    g.spacing[2] = dz;
    g.origin[0] = stack->origin[0] + (s.x0 + 0.5) * stack->pixel;
    g.origin[1] = stack->origin[1] + (s.y0 + 0.5) * stack->pixel;
    g.origin[2] = slice_z(&s, 0);
    memcpy(g.unit, stack->unit, sizeof g.unit);
    g.unit[sizeof g.unit - 1] = '\0';
    st = bvox_volume_set_geometry(s.vol, &g);
    if (st) goto fail;
    sv_release(&s);
    *out = s.vol;
    BVOX_CHECK_VOLUME(*out);
    return BVOX_OK;
fail:
    sv_release(&s);
    bvox_volume_destroy(s.vol);
    return st;
}
