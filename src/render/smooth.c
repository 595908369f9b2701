/*
 * smooth.c — surface normals per pixel beyond the paper's 26 binary ones:
 * the smooth normal (the gray-level gradient of Hoehne and Bernstein, 1986:
 * the occupancy around the hit voxel, here minus its first moment over a
 * ball), the paper's second normal method (a binary gradient operator over
 * the pre-image) and, for completeness, the binary and depth-map normals, all
 * in the eye frame (right, up, towards the viewer) of bvox__phong.
 *
 * Why a moment over a ball: over a half-space the first moment of a ball is
 * parallel to the plane's normal whatever its direction, so the estimate has
 * no preferred axes (a cube's moment leans towards its diagonals). Each
 * column of the ball is one window of the packed words (occupancy.h): the
 * x and y components weigh its popcount by the column's offset, the z
 * component is sum_k k (bit(z+k) - bit(z-k)) = sum over k of the popcounts
 * of the windows z+k..z+h minus z-h..z-k.
 */
#include "normal_cache.h"
#include "occupancy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The ball's column (i, j) reaches h = floor(sqrt(r^2 + r - i^2 - j^2))
 * voxels up and down; -1: not in it. By radius and i^2 + j^2 (0..18). */
static const int8_t half_height[4][19] = {
    {0},
    {1, 1, 0, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
    {2, 2, 2, 1, 1, 1, 0, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1},
    {3, 3, 3, 3, 2, 2, 2, 2, 2, 1, 1, 1, 0, -1, -1, -1, -1, -1, -1},
};
static int ball_half_height(int r, int i, int j) { return half_height[r][i * i + j * j]; }

/* A column's share of the ball is at most 7 voxels (z-3 .. z+3, r <= 3), so
 * it is taken as a 7-bit field (bit 3 = voxel z) and counted by two tables
 * of 128 entries instead of popcounts of nested windows (the same integers,
 * several times fewer operations: the library stays portable, without the
 * popcnt instruction, and a popcount is a dozen operations).
 * field_count: its 1-bits; field_zmoment: sum of (bit - 3) over its 1-bits. */
static const uint8_t field_mask[4] = {0x08, 0x1c, 0x3e, 0x7f}; /* voxels z-h .. z+h */
static const int8_t field_count[128] = {
    0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4,
    1, 2, 2, 3, 2, 3, 3, 4, 2, 3, 3, 4, 3, 4, 4, 5,
    1, 2, 2, 3, 2, 3, 3, 4, 2, 3, 3, 4, 3, 4, 4, 5,
    2, 3, 3, 4, 3, 4, 4, 5, 3, 4, 4, 5, 4, 5, 5, 6,
    1, 2, 2, 3, 2, 3, 3, 4, 2, 3, 3, 4, 3, 4, 4, 5,
    2, 3, 3, 4, 3, 4, 4, 5, 3, 4, 4, 5, 4, 5, 5, 6,
    2, 3, 3, 4, 3, 4, 4, 5, 3, 4, 4, 5, 4, 5, 5, 6,
    3, 4, 4, 5, 4, 5, 5, 6, 4, 5, 5, 6, 5, 6, 6, 7,
};
static const int8_t field_zmoment[128] = {
    0, -3, -2, -5, -1, -4, -3, -6, 0, -3, -2, -5, -1, -4, -3, -6,
    1, -2, -1, -4, 0, -3, -2, -5, 1, -2, -1, -4, 0, -3, -2, -5,
    2, -1, 0, -3, 1, -2, -1, -4, 2, -1, 0, -3, 1, -2, -1, -4,
    3, 0, 1, -2, 2, -1, 0, -3, 3, 0, 1, -2, 2, -1, 0, -3,
    3, 0, 1, -2, 2, -1, 0, -3, 3, 0, 1, -2, 2, -1, 0, -3,
    4, 1, 2, -1, 3, 0, 1, -2, 4, 1, 2, -1, 3, 0, 1, -2,
    5, 2, 3, 0, 4, 1, 2, -1, 5, 2, 3, 0, 4, 1, 2, -1,
    6, 3, 4, 1, 5, 2, 3, 0, 6, 3, 4, 1, 5, 2, 3, 0,
};

/* The first moment of the occupancy over the ball, in index units. */
static void ball_moment(const bvox_volume *v, int32_t x, int32_t y, int32_t z, int r, int64_t m[3])
{
    int64_t m0 = 0, m1 = 0, m2 = 0;
    /* bits z-3 .. z+3 of every column: word w from bit sh, and the next
     * word when the field crosses into it; words beyond the column read 0 */
    const int64_t start = (int64_t)z - 3, wpc = (int64_t)v->wpc;
    const int64_t w = start >= 0 ? start / 64 : -1; /* floor; start >= -4 (z >= -1) */
    const unsigned sh = (unsigned)(start - w * 64);
    const int lo_ok = w >= 0 && w < wpc, hi_ok = sh > 57 && w + 1 < wpc;
    const int inside = x - r >= 0 && y - r >= 0 && x + r < v->nx && y + r < v->ny;
    for (int j = -r; j <= r; j++)
        for (int i = -r; i <= r; i++) {
            int h = ball_half_height(r, i, j);
            if (h < 0) continue;
            const int32_t cx = x + i, cy = y + j;
            if (!inside && (cx < 0 || cy < 0 || cx >= v->nx || cy >= v->ny)) continue;
            const uint64_t *col = bvox__column_c(v, cx, cy);
            uint64_t bits = lo_ok ? col[w] >> sh : 0;
            if (hi_ok) bits |= col[w + 1] << (64 - sh);
            const unsigned f = (unsigned)bits & field_mask[h];
            if (!f) continue;
            const int n = field_count[f];
            m0 += i * n;
            m1 += j * n;
            m2 += field_zmoment[f];
        }
    m[0] = m0, m[1] = m1, m[2] = m2;
}

int bvox_smooth_normal(const bvox_volume *vol, int32_t x, int32_t y, int32_t z, int radius,
                       double n[3])
{
    n[0] = n[1] = n[2] = 0;
    if (!vol) return 0;
    int64_t m[3];
    ball_moment(vol, x, y, z, bvox__smooth_radius(radius), m);
    /* the normal points away from the mass; index units / spacing = physical */
    double len = 0;
    for (int a = 0; a < 3; a++) {
        n[a] = -(double)m[a] / vol->geom.spacing[a];
        len += n[a] * n[a];
    }
    if (len == 0) return 0;
    len = sqrt(len);
    for (int a = 0; a < 3; a++) n[a] /= len;
    return 1;
}

static inline int voxel_set(const bvox_volume *v, const int32_t q[3])
{
    if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= v->nx || q[1] >= v->ny || q[2] >= v->nz) return 0;
    return (int)(bvox__column_c(v, q[0], q[1])[q[2] >> 6] >> (q[2] & 63) & 1);
}

/* The voxel whose box holds the point of pixel (c, r) at depth t steps
 * (voxel centres at i * spacing), clamped into the volume when clamp. */
static void voxel_at(const bvox_volume *v, const bvox_preimage *p, int32_t c, int32_t r, double t,
                     int32_t q[3])
{
    const double *e = p->eye;
    const int32_t n[3] = {v->nx, v->ny, v->nz};
    for (int a = 0; a < 3; a++) {
        double x = p->origin[a] + c * p->pixel_size[0] * e[a] + r * p->pixel_size[1] * e[3 + a] +
                   t * p->depth_step * e[6 + a];
        double u = floor(x / v->geom.spacing[a] + 0.5);
        q[a] = u < 0 ? 0 : u > n[a] - 1 ? n[a] - 1 : (int32_t)u;
    }
}

int bvox_preimage_hit_voxel(const bvox_volume *vol, const bvox_preimage *pre, int32_t c,
                            int32_t r, int32_t xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0;
    if (!vol || !pre || c < 0 || r < 0 || c >= pre->width || r >= pre->height) return 0;
    int32_t d = pre->depth[(size_t)r * (size_t)pre->width + (size_t)c];
    if (d < 0) return 0;
    /* the entry point lies in [d, d + 1) steps (axis views: exactly at the
     * voxel d); walk in half steps over two voxels' depth behind it */
    const double *s = vol->geom.spacing;
    double reach = 2 * fmax(s[0], fmax(s[1], s[2])) / (pre->depth_step > 0 ? pre->depth_step : 1);
    int32_t q[3];
    for (double t = d + 0.25; t <= d + 0.25 + reach; t += 0.5) {
        voxel_at(vol, pre, c, r, t, q);
        if (voxel_set(vol, q)) {
            memcpy(xyz, q, sizeof q);
            return 1;
        }
    }
    voxel_at(vol, pre, c, r, d + 0.5, xyz);
    return 0;
}

/* A physical vector in the eye frame (right, up, towards the viewer). */
static void to_eye(const bvox_preimage *p, const double v[3], double n[3])
{
    const double *e = p->eye;
    n[0] = e[0] * v[0] + e[1] * v[1] + e[2] * v[2];
    n[1] = -(e[3] * v[0] + e[4] * v[1] + e[5] * v[2]);
    n[2] = -(e[6] * v[0] + e[7] * v[1] + e[8] * v[2]);
}

/* The moment of voxel q through the cache (NULL: none). */
static void cached_moment(const bvox_volume *vol, int radius, bvox__moment_cache *mc,
                          const int32_t q[3], int64_t m[3])
{
    if (!mc) {
        ball_moment(vol, q[0], q[1], q[2], radius, m);
        return;
    }
    if (mc->shared && mc->shared->usable) { /* it is the cache: one load */
        if (!bvox__nc_get(mc->shared, q, m)) {
            ball_moment(vol, q[0], q[1], q[2], radius, m);
            bvox__nc_put(mc->shared, q, m);
        }
        return;
    }
    /* coordinates here are within -1 .. 65535 (one beyond the volume) */
    const uint64_t key = (uint64_t)(uint32_t)(q[0] + 1) | (uint64_t)(uint32_t)(q[1] + 1) << 20 |
                         (uint64_t)(uint32_t)(q[2] + 1) << 40 | 1ull << 63;
    const unsigned h = (unsigned)((uint32_t)q[0] * 73856093u ^ (uint32_t)q[1] * 19349663u ^
                                  (uint32_t)q[2] * 83492791u) % BVOX_MOMENT_CACHE;
    if (mc->key[h] != key) {
        int64_t t[3];
        if (!mc->shared || !bvox__nc_get(mc->shared, q, t)) {
            ball_moment(vol, q[0], q[1], q[2], radius, t);
            if (mc->shared) bvox__nc_put(mc->shared, q, t);
        }
        for (int a = 0; a < 3; a++) mc->m[h][a] = (int32_t)t[a];
        mc->key[h] = key;
    }
    for (int a = 0; a < 3; a++) m[a] = mc->m[h][a];
}

/* The cell of pixel (c, r)'s entry point (the middle of its depth step):
 * the voxel base and the fractions f towards base + 1 per axis; when pixels
 * are as large as voxels or larger (each pixel meets its own voxels anyway)
 * the nearest voxel alone, f = 0. Returns the number of voxels, 1 or 8. */
static int hit_cell(const bvox_volume *vol, const bvox_preimage *p, int32_t c, int32_t r,
                    int32_t base[3], double f[3])
{
    const size_t i = (size_t)r * (size_t)p->width + (size_t)c;
    const double *e = p->eye;
    const double t = p->depth[i] + 0.5;
    for (int a = 0; a < 3; a++) {
        double x = p->origin[a] + c * p->pixel_size[0] * e[a] + r * p->pixel_size[1] * e[3 + a] +
                   t * p->depth_step * e[6 + a];
        double u = x / vol->geom.spacing[a];
        const int32_t n_a = a == 0 ? vol->nx : a == 1 ? vol->ny : vol->nz;
        u = u < -1 ? -1 : u > n_a ? n_a : u; /* float slop at the border */
        double b = floor(u);
        base[a] = (int32_t)b;
        f[a] = u - b;
    }
    const double *sp = vol->geom.spacing;
    const double px = p->pixel_size[0] < p->pixel_size[1] ? p->pixel_size[0] : p->pixel_size[1];
    if (px < fmin(sp[0], fmin(sp[1], sp[2]))) return 8;
    for (int a = 0; a < 3; a++) {
        base[a] += f[a] >= 0.5;
        f[a] = 0;
    }
    return 1;
}

void bvox__smooth_normal_eye(const bvox_volume *vol, const bvox_preimage *p, int radius,
                             int32_t c, int32_t r, double n[3], bvox__moment_cache *mc)
{
    bvox__smooth_cell cell;
    cell.count = hit_cell(vol, p, c, r, cell.base, cell.f);
    bvox__smooth_normal_cell(vol, p, radius, c, r, &cell, n, mc);
}

void bvox__smooth_cells_row(const bvox_volume *vol, const bvox_preimage *p, int32_t r,
                            bvox__smooth_cell *cells, const bvox__moment_cache *mc)
{
    const int share = mc && mc->shared && mc->shared->usable;
    for (int32_t c = 0; c < p->width; c++) {
        bvox__smooth_cell *e = &cells[c];
        if (p->depth[(size_t)r * (size_t)p->width + (size_t)c] < 0) {
            e->count = 0;
            continue;
        }
        e->count = hit_cell(vol, p, c, r, e->base, e->f);
        if (!share) continue;
        for (int k = 0; k < e->count; k++) { /* their loads, not the arithmetic, are the cost */
            const int32_t q[3] = {e->base[0] + (k & 1), e->base[1] + (k >> 1 & 1), e->base[2] + (k >> 2 & 1)};
            size_t slot;
            (void)bvox__nc_key(mc->shared, q, &slot);
            __builtin_prefetch((const void *)&mc->shared->slot[slot]);
        }
    }
}

void bvox__smooth_normal_cell(const bvox_volume *vol, const bvox_preimage *p, int radius,
                              int32_t c, int32_t r, const bvox__smooth_cell *cell, double n[3],
                              bvox__moment_cache *mc)
{
    /* The moments of the 8 voxels around the ray's entry point, trilinearly
     * interpolated: the normal then turns smoothly across a voxel instead
     * of jumping at its border (pixels smaller than voxels; else the
     * nearest voxel's, see hit_cell). */
    const size_t i = (size_t)r * (size_t)p->width + (size_t)c;
    const int32_t *base = cell->base;
    const double *f = cell->f;
    double v[3] = {0, 0, 0};
    radius = bvox__smooth_radius(radius);
    const int nearest = cell->count == 1;
    for (int k = 0; k < (nearest ? 1 : 8); k++) {
        const int32_t q[3] = {base[0] + (k & 1), base[1] + (k >> 1 & 1), base[2] + (k >> 2 & 1)};
        const double w = (k & 1 ? f[0] : 1 - f[0]) * (k >> 1 & 1 ? f[1] : 1 - f[1]) *
                         (k >> 2 & 1 ? f[2] : 1 - f[2]);
        if (w == 0) continue;
        int64_t m[3];
        cached_moment(vol, radius, mc, q, m);
        for (int a = 0; a < 3; a++) v[a] -= w * (double)m[a];
    }
    double len = 0;
    for (int a = 0; a < 3; a++) {
        v[a] /= vol->geom.spacing[a];
        len += v[a] * v[a];
    }
    if (!(len > 1e-18)) {
        bvox__normal_eye(p, BVOX_CODE_NORMAL(p->code[i]), n);
        return;
    }
    to_eye(p, v, n);
    len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; a++) n[a] /= len;
    if (n[2] < 0) { /* facing away: the silhouette's normal, in the image plane */
        double l = sqrt(n[0] * n[0] + n[1] * n[1]);
        if (l > 0) n[0] /= l, n[1] /= l, n[2] = 0;
        else n[0] = 0, n[1] = 0, n[2] = 1;
    }
}

/* The paper's binary gradient operator over the pre-image (see bvox.h). */
void bvox__preimage_binary_normal(const bvox_preimage *p, int32_t x, int32_t y, double n[3])
{
    const int32_t d = p->depth[(size_t)y * (size_t)p->width + (size_t)x];
#define ONE(xx, yy)                                                                          \
    ((xx) >= 0 && (yy) >= 0 && (xx) < p->width && (yy) < p->height &&                       \
     p->depth[(size_t)(yy) * (size_t)p->width + (size_t)(xx)] >= 0 &&                        \
     p->depth[(size_t)(yy) * (size_t)p->width + (size_t)(xx)] <= d)
    const int right = ONE(x - 1, y) - ONE(x + 1, y), down = ONE(x, y - 1) - ONE(x, y + 1);
#undef ONE
    /* pixel steps to physical (divide by the step's length), as the codes */
    n[0] = right / (p->pixel_size[0] > 0 ? p->pixel_size[0] : 1.0);
    n[1] = -down / (p->pixel_size[1] > 0 ? p->pixel_size[1] : 1.0);
    n[2] = 1.0 / (p->depth_step > 0 ? p->depth_step : 1.0);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; a++) n[a] /= len;
}

void bvox__pixel_normal(const bvox_volume *vol, const bvox_preimage *p, bvox_shade_mode mode,
                        int radius, int32_t x, int32_t y, double n[3], bvox__moment_cache *mc)
{
    switch (mode) {
    case BVOX_SHADE_SMOOTH: bvox__smooth_normal_eye(vol, p, radius, x, y, n, mc); return;
    case BVOX_SHADE_PREIMAGE_BINARY: bvox__preimage_binary_normal(p, x, y, n); return;
    case BVOX_SHADE_GRADIENT:
    case BVOX_SHADE_ENLARGED_GRADIENT: bvox__depth_normal(p, BVOX_GRADIENT_SOBEL, x, y, n); return;
    default:
        bvox__normal_eye(p, BVOX_CODE_NORMAL(p->code[(size_t)y * (size_t)p->width + (size_t)x]), n);
        return;
    }
}

typedef struct normals_ctx {
    const bvox_volume *vol;
    const bvox_preimage *pre;
    bvox_shade_mode mode;
    int radius;
    float *out;
} normals_ctx;

static void normal_rows(void *arg, int64_t y0, int64_t y1)
{
    const normals_ctx *g = arg;
    const bvox_preimage *p = g->pre;
    bvox__moment_cache *mc = g->mode == BVOX_SHADE_SMOOTH ? bvox__moment_cache_new() : NULL;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++)
        for (int32_t x = 0; x < p->width; x++) {
            size_t i = (size_t)y * (size_t)p->width + (size_t)x;
            float *o = g->out + 3 * i;
            if (p->depth[i] < 0) {
                o[0] = o[1] = o[2] = 0;
                continue;
            }
            double n[3];
            bvox__pixel_normal(g->vol, p, g->mode, g->radius, x, y, n, mc);
            o[0] = (float)n[0], o[1] = (float)n[1], o[2] = (float)n[2];
        }
    free(mc);
}

bvox_status bvox_preimage_normals(const bvox_volume *vol, const bvox_preimage *pre,
                                  bvox_shade_mode mode, int radius, float *normals)
{
    if (!pre || !pre->depth || !pre->code || !normals)
        return bvox__fail(BVOX_EINVAL, "normals: missing pre-image or output");
    if ((unsigned)mode > (unsigned)BVOX_SHADE_ENLARGED_GRADIENT)
        return bvox__fail(BVOX_EINVAL, "normals: unknown shading %d", (int)mode);
    if (mode == BVOX_SHADE_SMOOTH && !vol)
        return bvox__fail(BVOX_EINVAL, "normals: smooth normals need the volume");
    normals_ctx g = {vol, pre, mode, radius, normals};
    bvox__parallel_for(pre->height, 16, normal_rows, &g);
    return BVOX_OK;
}
