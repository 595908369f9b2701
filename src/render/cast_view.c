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
 * The z-buffer holds 64-bit keys (float depth bits << 32 | voxel number), so
 * the minimum is the nearest voxel with ties broken by voxel order: the
 * result does not depend on the order of the splats, which lets each worker
 * thread splat a share of the voxels into its own z-buffer and the buffers be
 * merged by a minimum at the end.
 */
#include "render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double deg = 3.14159265358979323846 / 180.0;

typedef struct frame {
    double r[3], dn[3], d[3]; /* right, down, view */
} frame;

static void normalize(double v[3], double *len)
{
    *len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (*len > 0) v[0] /= *len, v[1] /= *len, v[2] /= *len;
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
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

typedef struct splat_ctx {
    const bvox_surface *s;
    frame f;
    double scale, half_w, half_h; /* pixel = eye * scale + half - 0.5 */
    double c[3], rho;             /* centre and radius of the fitting sphere */
    double hu, hv;                /* half size of a voxel's projection, pixels */
    double h[3];                  /* half voxel size */
    /* Slab test of a pixel ray offset (du, dv) pixels from a voxel's projected
     * centre, the same for every voxel: per axis a, k_a = du ku[a] + dv kv[a]
     * and the ray is inside the slab for t in [-H_a - k_a, H_a - k_a]
     * (t physical along the view from the voxel centre's depth). An axis the
     * view is parallel to has no t bounds: it is inside iff -h <= q < h with
     * q_a = (du r_a + dv dn_a) / scale. */
    double ku[3], kv[3], H[3];
    int parallel[3];
    unsigned facing;              /* neighbour bits whose emptiness makes a front face */
    int64_t range_lo[64], range_hi[64]; /* entry ranges of the front-facing classes */
    int nranges;
    int64_t total;                /* entries in those ranges */
    int32_t w, hgt;
    uint64_t **zbuf;              /* one per share */
    int shares;
} splat_ctx;

/* floor for values well inside the int32 range, without a libm call */
static inline int32_t ifloor(double x)
{
    int32_t i = (int32_t)x;
    return i - (x < (double)i);
}

/* ceil(x) and floor(x) clamped to 0..n-1 (empty ranges stay empty): x may be
 * far outside the int range when the scale is huge. */
static inline int32_t ceil_in(double x, int32_t n)
{
    return x <= 0 ? 0 : x >= n ? n : -ifloor(-x);
}
static inline int32_t floor_in(double x, int32_t n)
{
    return x < 0 ? -1 : x >= n - 1 ? n - 1 : ifloor(x);
}

/* Splat voxel entries [i0, i1) into the z-buffer zb. */
static void splat_range(const splat_ctx *c, uint64_t *zb, int64_t i0, int64_t i1)
{
    const bvox_surface *s = c->s;
    const double *r = c->f.r, *dn = c->f.dn, *d = c->f.d;
    const double inv = 1.0 / c->scale;
    const int any_parallel = c->parallel[0] | c->parallel[1] | c->parallel[2];
    for (int64_t i = i0; i < i1; i++) {
        uint64_t e = s->entries[i];
        double p[3] = {SURF_X(e) * s->spacing[0] - c->c[0], SURF_Y(e) * s->spacing[1] - c->c[1],
                       SURF_Z(e) * s->spacing[2] - c->c[2]};
        double fu = dot(r, p) * c->scale + c->half_w - 0.5;
        double fv = dot(dn, p) * c->scale + c->half_h - 0.5;
        double wc = dot(d, p) + c->rho;
        /* candidate pixels: centres within the projection's bounding box */
        int32_t px0 = ceil_in(fu - c->hu, c->w), px1 = floor_in(fu + c->hu, c->w);
        int32_t py0 = ceil_in(fv - c->hv, c->hgt), py1 = floor_in(fv + c->hv, c->hgt);
        const uint64_t nb = SURF_NB(e);
        for (int32_t py = py0; py <= py1; py++) {
            double dv = py - fv;
            for (int32_t px = px0; px <= px1; px++) {
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
                float depth = (float)((wc + tmin) * c->scale);
                depth = depth > 0 ? depth : 0;
                uint32_t bits;
                memcpy(&bits, &depth, sizeof bits);
                /* ties of depth go to the smaller neighbour bits: the output
                 * (depth, code) is then the same in any splat order */
                uint64_t key = hit ? (uint64_t)bits << 32 | nb : ~0ull;
                size_t at = (size_t)py * (size_t)c->w + (size_t)px;
                zb[at] = key < zb[at] ? key : zb[at];
            }
        }
    }
}

/* Share k of the front-facing entries (their ranges laid end to end). */
static void splat_share(void *arg, int64_t s0, int64_t s1)
{
    const splat_ctx *c = arg;
    for (int64_t share = s0; share < s1; share++) {
        int64_t g0 = c->total * share / c->shares, g1 = c->total * (share + 1) / c->shares;
        int64_t off = 0; /* position of range rg in the concatenation */
        for (int rg = 0; rg < c->nranges; rg++) {
            int64_t len = c->range_hi[rg] - c->range_lo[rg];
            int64_t a0 = g0 - off > 0 ? g0 - off : 0, a1 = g1 - off < len ? g1 - off : len;
            if (a0 < a1) splat_range(c, c->zbuf[share], c->range_lo[rg] + a0, c->range_lo[rg] + a1);
            off += len;
        }
    }
}

typedef struct merge_ctx {
    const splat_ctx *c;
    bvox_preimage *pre;
    bvox__cue cue;
} merge_ctx;

static void merge_rows(void *arg, int64_t y0, int64_t y1)
{
    const merge_ctx *m = arg;
    const splat_ctx *c = m->c;
    const int32_t range = m->pre->depth_range;
    for (size_t at = (size_t)y0 * (size_t)c->w; at < (size_t)y1 * (size_t)c->w; at++) {
        uint64_t key = c->zbuf[0][at];
        for (int k = 1; k < c->shares; k++)
            if (c->zbuf[k][at] < key) key = c->zbuf[k][at];
        if (key == ~0ull) continue;
        uint32_t bits = (uint32_t)(key >> 32);
        float depth;
        memcpy(&depth, &bits, sizeof depth);
        int32_t di = depth < (float)range ? (int32_t)depth : range - 1;
        m->pre->depth[at] = di;
        m->pre->code[at] = bvox__code((unsigned)key & 63, di, &m->cue);
    }
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
    for (unsigned k = 0; k < 64; k++) {
        if (!(~k & c.facing) || surf->class_start[k + 1] == surf->class_start[k]) continue;
        c.range_lo[c.nranges] = surf->class_start[k];
        c.range_hi[c.nranges] = surf->class_start[k + 1];
        c.total += c.range_hi[c.nranges] - c.range_lo[c.nranges];
        c.nranges++;
    }

    bvox_preimage *pre;
    st = bvox__preimage_alloc(c.w, c.hgt, &pre);
    if (st) return st;
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

    /* one z-buffer per share, as many shares as threads within a memory cap */
    size_t zbytes = (size_t)c.w * (size_t)c.hgt * sizeof(uint64_t);
    int shares = bvox_threads();
    if (c.total < 65536) shares = 1;
    while (shares > 1 && zbytes * (size_t)shares > ((size_t)256 << 20)) shares--;
    uint64_t *zb[BVOX__MAX_THREADS];
    c.zbuf = zb;
    c.shares = 0;
    for (int k = 0; k < shares; k++) {
        zb[k] = bvox__alloc(zbytes, false, "z-buffer", &st);
        if (!zb[k]) break;
        memset(zb[k], 0xff, zbytes);
        c.shares++;
    }
    if (c.shares == shares) {
        bvox__parallel_for(c.shares, 1, splat_share, &c);
        merge_ctx m = {&c, pre, {{0}}};
        bvox__cue_init(&m.cue, pre->depth_range);
        bvox__parallel_for(c.hgt, 64, merge_rows, &m);
        st = BVOX_OK;
    }
    for (int k = 0; k < c.shares; k++) bvox__free(zb[k], zbytes);
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
