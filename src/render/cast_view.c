/*
 * cast_view.c — arbitrary parallel projections by splatting the boundary
 * voxels of a bvox_surface into a z-buffer.
 *
 * Each candidate voxel (back faces culled: it needs a 0 neighbour on a side
 * the rays enter from) is a box of the voxel size centred on its voxel. Its
 * projection's bounding rectangle gives the candidate pixels; for each, the
 * pixel's centre ray is clipped against the box (slab test), which is exact:
 * a pixel is covered iff its ray meets the box, at the entry distance. So the
 * result is the exact first hit of every centre ray, whatever the scale
 * (no holes when zoomed in, no fat silhouettes), and thick sections project
 * thick because the boxes have the real voxel size.
 *
 * The z-buffer holds 64-bit keys (float depth bits << 32 | neighbour bits),
 * so the minimum is the nearest voxel with ties broken by the neighbour bits:
 * the result does not depend on the order of the splats. Threads own
 * disjoint bands of rows, never a whole z-buffer each (that cost one
 * image-sized buffer per thread to allocate, clear and merge every frame and
 * made views slower with more threads): the front-facing entries are first
 * bucketed by the bands their projection touches (a counting sort over fixed
 * chunks of entries, so the buckets do not depend on the thread count), then
 * each band is splatted alone, clipped to its rows, into a band-sized
 * z-buffer that stays in cache, and turned into depths and codes. One thread
 * has nothing to share: one band, the whole image, no bucketing.
 */
#include "render/cast_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double deg = 3.14159265358979323846 / 180.0;

static void normalize(double v[3], double *len)
{
    *len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (*len > 0) v[0] /= *len, v[1] /= *len, v[2] /= *len;
}

static bvox_status make_frame(const bvox_projection *p, frame *f)
{
    if (!p->use_matrix) {
        if (!isfinite(p->azimuth) || !isfinite(p->elevation))
            return bvox__fail(BVOX_EINVAL, "projection: angles must be finite");
        double az = p->azimuth * deg, el = p->elevation * deg;
        double d[3] = {sin(az) * cos(el), sin(el), cos(az) * cos(el)};
        double r[3] = {cos(az), 0, -sin(az)};
        memcpy(f->d, d, sizeof d);
        memcpy(f->r, r, sizeof r);
        f->dn[0] = d[1] * r[2] - d[2] * r[1]; /* down = view x right */
        f->dn[1] = d[2] * r[0] - d[0] * r[2];
        f->dn[2] = d[0] * r[1] - d[1] * r[0];
        return BVOX_OK;
    }
    for (int i = 0; i < 9; i++)
        if (!isfinite(p->matrix[i])) return bvox__fail(BVOX_EINVAL, "projection: matrix is not finite");
    double len[3];
    memcpy(f->r, p->matrix, sizeof f->r);
    memcpy(f->dn, p->matrix + 3, sizeof f->dn);
    memcpy(f->d, p->matrix + 6, sizeof f->d);
    normalize(f->r, &len[0]);
    double k = dot(f->dn, f->r);
    for (int a = 0; a < 3; a++) f->dn[a] -= k * f->r[a];
    normalize(f->dn, &len[1]);
    double k1 = dot(f->d, f->r), k2 = dot(f->d, f->dn);
    for (int a = 0; a < 3; a++) f->d[a] -= k1 * f->r[a] + k2 * f->dn[a];
    normalize(f->d, &len[2]);
    if (!(len[0] > 1e-9 && len[1] > 1e-9 && len[2] > 1e-9))
        return bvox__fail(BVOX_EINVAL, "projection: the matrix rows are not independent");
    return BVOX_OK;
}

/* The portable splat kernel (bvox__splat_fn, cast_view.h): per candidate
 * pixel of an entry's bounding box, the slab test of its centre ray. */
static void splat_list(const splat_ctx *c, const uint64_t *list, int64_t n, int32_t row0,
                       int32_t row1, uint64_t *zb)
{
    const double *r = c->f.r, *dn = c->f.dn;
    const double inv = 1.0 / c->scale;
    const int any_parallel = c->parallel[0] | c->parallel[1] | c->parallel[2];
    for (int64_t i = 0; i < n; i++) {
        uint64_t e = list[i];
        double fu, fv, wc;
        int32_t box[4];
        if (!project(c, e, &fu, &fv, &wc, box)) continue;
        int32_t py0 = box[2] > row0 ? box[2] : row0, py1 = box[3] < row1 - 1 ? box[3] : row1 - 1;
        const uint64_t nb = SURF_NB(e);
        for (int32_t py = py0; py <= py1; py++) {
            double dv = py - fv;
            for (int32_t px = box[0]; px <= box[1]; px++) {
                double du = px - fu;
                double tmin = -INFINITY, tmax = INFINITY;
                for (int a = 0; a < 3; a++) {
                    double k = du * c->ku[a] + dv * c->kv[a];
                    double lo = -c->H[a] - k, hi = c->H[a] - k;
                    tmin = lo > tmin ? lo : tmin;
                    tmax = hi < tmax ? hi : tmax;
                }
                int hit = tmin <= tmax;
                if (any_parallel)
                    for (int a = 0; a < 3; a++)
                        if (c->parallel[a]) {
                            double q = (du * r[a] + dv * dn[a]) * inv;
                            hit &= q >= -c->h[a] && q < c->h[a];
                        }
                float df = (float)((wc + tmin) * c->scale);
                df = df > 0 ? df : 0;
                uint32_t bits;
                memcpy(&bits, &df, sizeof bits);
                /* ties of depth go to the smaller neighbour bits: the output
                 * (depth, code) is then the same in any splat order */
                uint64_t key = hit ? (uint64_t)bits << 32 | nb : ~0ull;
                size_t at = (size_t)(py - row0) * (size_t)c->stride + (size_t)px;
                zb[at] = key < zb[at] ? key : zb[at];
            }
        }
    }
}

/* The bands of entries list[0..n) (bvox__bands_fn, cast_view.h). */
static void bands_portable(const splat_ctx *c, const uint64_t *list, int n, int32_t *b0,
                           int32_t *b1)
{
    for (int i = 0; i < n; i++) entry_bands(c, list[i], &b0[i], &b1[i]);
}

static inline int64_t chunk_begin(const splat_ctx *c, int64_t k)
{
    return c->total * k / c->nchunks;
}

/* Chunk k's entries (of the front-facing ranges laid end to end), a block of
 * at most 256 at a time with their bands: into the per-band counts at
 * (first pass) or, with fill, copied into each band's place. */
static void chunk_blocks(splat_ctx *c, int64_t k, int fill)
{
    int64_t *at = c->bucket_at + k, g0 = chunk_begin(c, k), g1 = chunk_begin(c, k + 1);
    int32_t b0[256], b1[256];
    /* the first run that ends after g0 (there may be thousands of runs) */
    int64_t lo = 0, hi = c->nranges;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (c->range_end[mid] <= g0) lo = mid + 1;
        else hi = mid;
    }
    for (int64_t rg = lo; rg < c->nranges; rg++) {
        int64_t len = c->ranges[rg].n, off = c->range_end[rg] - len;
        if (off >= g1) break;
        int64_t a0 = g0 - off > 0 ? g0 - off : 0, a1 = g1 - off < len ? g1 - off : len;
        for (int64_t i = a0; i < a1; i += 256) {
            const uint64_t *list = c->ranges[rg].at + i;
            int m = a1 - i < 256 ? (int)(a1 - i) : 256;
            c->bands(c, list, m, b0, b1);
            for (int j = 0; j < m; j++)
                for (int32_t b = b0[j]; b <= b1[j]; b++) {
                    if (fill)
                        c->bucket[at[b * c->nchunks]++] = list[j];
                    else
                        at[b * c->nchunks]++;
                }
        }
    }
}

/* Bucketing, first pass: per chunk, how many entries touch each band. */
static void count_chunks(void *arg, int64_t k0, int64_t k1)
{
    for (int64_t k = k0; k < k1; k++) chunk_blocks(arg, k, 0);
}

/* Second pass: each chunk copies its entries into its place in each band. */
static void fill_chunks(void *arg, int64_t k0, int64_t k1)
{
    for (int64_t k = k0; k < k1; k++) chunk_blocks(arg, k, 1);
}

/* Per band: splat its entries into a band z-buffer, then write its rows of
 * the pre-image. The z-buffer is one of the scratch set: at most nscratch
 * calls of this run at once (one per task), so one is always free. */
static void splat_bands(void *arg, int64_t b0, int64_t b1)
{
    splat_ctx *c = arg;
    int k = 0;
    for (;; k = (k + 1) % c->nscratch)
        if (!atomic_exchange(&c->scratch_busy[k], 1)) break;
    uint64_t *zb = c->scratch[k];
    const int32_t range = c->pre->depth_range;
    for (int64_t b = b0; b < b1; b++) {
        /* after fill_chunks, bucket_at[b * nchunks + k] is the end of chunk k's
         * entries in band b: band b is [end of band b - 1, end of its last chunk) */
        int32_t row0 = (int32_t)b * c->band_rows;
        int32_t row1 = row0 + c->band_rows < c->hgt ? row0 + c->band_rows : c->hgt;
        size_t nkeys = (size_t)(row1 - row0) * (size_t)c->stride;
        memset(zb, 0xff, nkeys * sizeof *zb);
        if (c->bucket) {
            int64_t lo = b ? c->bucket_at[b * c->nchunks - 1] : 0;
            int64_t hi = c->bucket_at[(b + 1) * c->nchunks - 1];
            c->splat(c, c->bucket + lo, hi - lo, row0, row1, zb);
        } else { /* one band, the whole image: every front-facing entry */
            for (int64_t rg = 0; rg < c->nranges; rg++)
                c->splat(c, c->ranges[rg].at, c->ranges[rg].n, row0, row1, zb);
        }
        for (int32_t py = row0; py < row1; py++) {
            const uint64_t *keys = zb + (size_t)(py - row0) * (size_t)c->stride;
            size_t base = (size_t)py * (size_t)c->w;
            /* every pixel is written: the pre-image comes unset */
            int32_t *depth_row = c->pre->depth + base;
            uint8_t *code_row = c->pre->code + base;
            for (int32_t px = 0; px < c->w; px++) {
                uint64_t key = keys[px];
                if (key == ~0ull) { /* no hit: -1, background code */
                    depth_row[px] = -1;
                    code_row[px] = BVOX_CODE_BACKGROUND;
                    continue;
                }
                uint32_t bits = (uint32_t)(key >> 32);
                float depth;
                memcpy(&depth, &bits, sizeof depth);
                int32_t di = depth < (float)range ? (int32_t)depth : range - 1;
                depth_row[px] = di;
                code_row[px] = bvox__code((unsigned)key & 63, di, &c->cue);
            }
        }
    }
    atomic_store(&c->scratch_busy[k], 0);
}

/* The AVX2 kernels where they are built, the CPU has them and the SIMD
 * level allows them (tests force each level and compare). */
static int use_avx2(void)
{
#if defined(__x86_64__)
    return bvox__splat_avx2 && bvox_simd_active() >= BVOX_SIMD_AVX2 &&
           __builtin_cpu_supports("avx2");
#else
    return 0;
#endif
}

bvox_status bvox_surface_cast(const bvox_surface *surf, const bvox_projection *proj,
                              bvox_preimage **out)
{
    *out = NULL;
    if (!surf || !proj) return bvox__fail(BVOX_EINVAL, "projection: missing input");
    bvox__clear_error();
    splat_ctx c;
    memset(&c, 0, sizeof c);
    c.s = surf;
    bvox_status st = make_frame(proj, &c.f);
    if (st) return st;
    c.w = proj->width ? proj->width : 512;
    c.hgt = proj->height ? proj->height : 512;
    if (c.w < 1 || c.hgt < 1 || c.w > BVOX_IMAGE_MAX_DIM || c.hgt > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "projection: image size %d x %d is outside 1..%d",
                          (int)c.w, (int)c.hgt, BVOX_IMAGE_MAX_DIM);
    if (!(proj->scale >= 0 && isfinite(proj->scale)))
        return bvox__fail(BVOX_EINVAL, "projection: scale must be >= 0 (0: fit)");
    const double *sp = surf->spacing;
    /* the sphere around the object's bounding box (the voxels' outer faces) */
    bvox_box b = surf->empty ? (bvox_box){0, 0, 0, surf->dims.nx, surf->dims.ny, surf->dims.nz}
                             : surf->bbox;
    double ext2 = 0;
    for (int a = 0; a < 3; a++) {
        const int32_t *lo = &b.x0, *hi = &b.x1;
        c.c[a] = (lo[a] + hi[a] - 1) * 0.5 * sp[a];
        double e = (hi[a] - lo[a]) * sp[a];
        ext2 += e * e;
        c.h[a] = 0.5 * sp[a];
    }
    c.rho = 0.5 * sqrt(ext2);
    c.scale = proj->scale > 0 ? proj->scale : (c.w < c.hgt ? c.w : c.hgt) / (2 * c.rho);
    c.half_w = c.w * 0.5;
    c.half_h = c.hgt * 0.5;
    for (int a = 0; a < 3; a++) {
        c.hu += fabs(c.f.r[a]) * c.h[a] * c.scale;
        c.hv += fabs(c.f.dn[a]) * c.h[a] * c.scale;
    }
    for (int a = 0; a < 3; a++) {
        /* |d_a| tiny: the slab bounds in t would overflow; test inclusion */
        c.parallel[a] = fabs(c.f.d[a]) < 1e-12;
        if (c.parallel[a]) { /* no bound in t from this axis */
            c.ku[a] = c.kv[a] = 0;
            c.H[a] = INFINITY;
            continue;
        }
        double sa = 1.0 / c.f.d[a];
        c.ku[a] = c.f.r[a] * sa / c.scale;
        c.kv[a] = c.f.dn[a] * sa / c.scale;
        c.H[a] = c.h[a] * fabs(sa);
    }
    const unsigned m_[3] = {NB_XM, NB_YM, NB_ZM}, p_[3] = {NB_XP, NB_YP, NB_ZP};
    for (int a = 0; a < 3; a++) {
        if (c.f.d[a] > 1e-12) c.facing |= m_[a];
        if (c.f.d[a] < -1e-12) c.facing |= p_[a];
    }
    /* a voxel can be a first hit only through a face the rays enter: it needs
     * a 0 neighbour on such a side (whole classes skipped, no test per voxel) */
    int64_t nruns = 0;
    for (unsigned k = 0; k < 64; k++)
        if (~k & c.facing) nruns += surf->class_run[k + 1] - surf->class_run[k];
    bvox__surface_run *ranges = bvox__mem_alloc((size_t)(nruns ? nruns : 1) * sizeof *ranges);
    c.range_end = bvox__mem_alloc((size_t)(nruns ? nruns : 1) * sizeof *c.range_end);
    c.ranges = ranges;
    if (!ranges || !c.range_end) {
        free(ranges);
        free(c.range_end);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    for (unsigned k = 0; k < 64; k++) {
        if (!(~k & c.facing)) continue;
        for (int64_t r = surf->class_run[k]; r < surf->class_run[k + 1]; r++) {
            ranges[c.nranges] = surf->runs[r];
            c.total += surf->runs[r].n;
            c.range_end[c.nranges++] = c.total;
        }
    }

    bvox_preimage *pre;
    st = bvox__preimage_alloc_unset(c.w, c.hgt, &pre);
    if (st) {
        free(ranges);
        free(c.range_end);
        return st;
    }
    double range = ceil(2 * c.rho * c.scale) + 1;
    pre->depth_range = range < 2147483647.0 ? (int32_t)range : 2147483647;
    pre->depth_step = 1.0 / c.scale;
    pre->pixel_size[0] = pre->pixel_size[1] = 1.0 / c.scale;
    memcpy(pre->eye, c.f.r, sizeof c.f.r);
    memcpy(pre->eye + 3, c.f.dn, sizeof c.f.dn);
    memcpy(pre->eye + 6, c.f.d, sizeof c.f.d);
    memcpy(pre->spacing, sp, sizeof pre->spacing);
    for (int a = 0; a < 3; a++)
        pre->origin[a] = c.c[a] + (0.5 - c.half_w) / c.scale * c.f.r[a] +
                         (0.5 - c.half_h) / c.scale * c.f.dn[a] - c.rho * c.f.d[a];

    /* Bands of about 16 K pixels (a band's keys stay in cache while it is
     * splatted); chunks of about 16 K entries; both independent of the thread
     * count. An entry's projection is at most 2 hv + 1 rows high, so it lands
     * in a few bands; the bucket array is counted exactly before it is made.
     * With one thread (or few entries) there is nothing to share: one band,
     * the whole image, and no bucketing. */
    c.pre = pre;
    c.splat = use_avx2() ? bvox__splat_avx2 : splat_list;
    c.bands = use_avx2() ? bvox__bands_avx2 : bands_portable;
    for (int a = 0; a < 3; a++) {
        c.pu[a] = c.f.r[a] * sp[a] * c.scale;
        c.pv[a] = c.f.dn[a] * sp[a] * c.scale;
        c.pw[a] = c.f.d[a] * sp[a];
    }
    c.pu[3] = c.half_w - 0.5 - dot(c.f.r, c.c) * c.scale;
    c.pv[3] = c.half_h - 0.5 - dot(c.f.dn, c.c) * c.scale;
    c.pw[3] = c.rho - dot(c.f.d, c.c);
    bvox__cue_init(&c.cue, pre->depth_range);
    const int threads = bvox__parallelism();
    const int bucketed = threads > 1 && c.total >= 16384;
    while (bucketed && c.band_shift < 14 && (c.w << (c.band_shift + 1)) <= 16384) c.band_shift++;
    c.band_rows = bucketed ? 1 << c.band_shift : c.hgt;
    c.nbands = (c.hgt + c.band_rows - 1) / c.band_rows;
    c.nchunks = c.total / 16384 + 1;
    if (c.nchunks > 1024) c.nchunks = 1024;
    size_t at_bytes = (size_t)c.nbands * (size_t)c.nchunks * sizeof(int64_t), bucket_bytes = 0;
    st = BVOX_OK;
    if (bucketed) {
        c.bucket_at = bvox__alloc(at_bytes, true, "view bands", &st);
        if (c.bucket_at) {
            bvox__parallel_for(c.nchunks, 1, count_chunks, &c);
            int64_t sum = 0; /* counts into starts: band-major, chunks in order */
            for (size_t k = 0; k < (size_t)c.nbands * (size_t)c.nchunks; k++) {
                int64_t n = c.bucket_at[k];
                c.bucket_at[k] = sum;
                sum += n;
            }
            bucket_bytes = (size_t)(sum ? sum : 1) * sizeof(uint64_t);
            c.bucket = bvox__alloc(bucket_bytes, false, "view buckets", &st);
        }
    }
    c.stride = c.w + 3;
    size_t zb_bytes = (size_t)c.band_rows * (size_t)c.stride * sizeof(uint64_t);
    int want = threads < c.nbands ? threads : c.nbands;
    if (!st)
        for (c.nscratch = 0; c.nscratch < want; c.nscratch++) {
            c.scratch[c.nscratch] = bvox__alloc(zb_bytes, false, "view z-buffer", &st);
            if (!c.scratch[c.nscratch]) break;
        }
    if (!st) {
        if (c.bucket) bvox__parallel_for(c.nchunks, 1, fill_chunks, &c); /* starts become ends */
        bvox__parallel_for(c.nbands, 1, splat_bands, &c);
    }
    for (int k = 0; k < c.nscratch; k++) bvox__free(c.scratch[k], zb_bytes);
    bvox__free(c.bucket, bucket_bytes);
    bvox__free(c.bucket_at, at_bytes);
    free(ranges);
    free(c.range_end);
    if (st) {
        bvox_preimage_destroy(pre);
        return st;
    }
    bvox__render_count_cast();
    *out = pre;
    return BVOX_OK;
}

bvox_status bvox_cast_projection(const bvox_volume *vol, const bvox_projection *proj,
                                 bvox_preimage **out)
{
    *out = NULL;
    bvox_surface *s;
    bvox_status st = bvox_surface_build(vol, &s);
    if (st) return st;
    st = bvox_surface_cast(s, proj, out);
    bvox_surface_destroy(s);
    return st;
}
