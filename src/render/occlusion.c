/*
 * occlusion.c — the depth cues the paper lists beyond depth shading, per
 * pixel of a pre-image: ambient occlusion (how much of the space in front of
 * the surface the object fills, at three scales) and cast shadows (does a ray
 * from the surface towards the light meet the object). Both start from the
 * hit voxel and its smooth normal (smooth.c); occlusion counts 1-voxels in
 * cubes by popcounts of column windows (occupancy.h), shadows walk the voxels
 * of a ray (Amanatides and Woo) testing bits of the packed volume.
 * Rows are split over the worker threads; each pixel is independent.
 */
#include "occupancy.h"

#include <math.h>

enum { AO_RADII = 3 };
#define SHADOW_SKIP 2.5 /* voxels along the ray not tested (see ray_blocked) */
static const int ao_radius[AO_RADII] = {2, 4, 8};

/* The hit voxel q and the unit index-space direction u of its smooth normal
 * (physical normal n / spacing, made unit); 0 for background. */
static int hit_and_normal(const bvox_volume *v, const bvox_preimage *p, int radius, int32_t c,
                          int32_t r, int32_t q[3], double u[3], double n[3])
{
    if (p->depth[(size_t)r * (size_t)p->width + (size_t)c] < 0) return 0;
    bvox_preimage_hit_voxel(v, p, c, r, q);
    if (!bvox_smooth_normal(v, q[0], q[1], q[2], radius, n)) {
        /* no direction: towards the viewer */
        for (int a = 0; a < 3; a++) n[a] = -p->eye[6 + a];
    }
    double len = 0;
    for (int a = 0; a < 3; a++) {
        u[a] = n[a] / v->geom.spacing[a];
        len += u[a] * u[a];
    }
    len = sqrt(len);
    for (int a = 0; a < 3; a++) u[a] = len > 0 ? u[a] / len : 0;
    return 1;
}

/* 1-voxels in the cube of half-size r centred on voxel (x, y, z). */
static int64_t cube_count(const bvox_volume *v, int32_t x, int32_t y, int32_t z, int r)
{
    const uint64_t mask = bvox__window_mask(-r, r);
    int64_t n = 0;
    for (int j = -r; j <= r; j++)
        for (int i = -r; i <= r; i++)
            n += bvox__popcount64(bvox__column_window(v, x + i, y + j, (int64_t)z - 32) & mask);
    return n;
}

typedef struct occ_ctx {
    const bvox_volume *vol;
    const bvox_preimage *pre;
    int radius;
    double l[3]; /* shadows: unit light direction, physical */
    uint8_t *out;
} occ_ctx;

static void ao_rows(void *arg, int64_t y0, int64_t y1)
{
    const occ_ctx *g = arg;
    const bvox_preimage *p = g->pre;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++)
        for (int32_t x = 0; x < p->width; x++) {
            size_t i = (size_t)y * (size_t)p->width + (size_t)x;
            int32_t q[3];
            double u[3], n[3];
            if (!hit_and_normal(g->vol, p, g->radius, x, y, q, u, n)) {
                g->out[i] = 255;
                continue;
            }
            double share = 0;
            for (int k = 0; k < AO_RADII; k++) {
                const int r = ao_radius[k];
                int32_t c[3];
                for (int a = 0; a < 3; a++) c[a] = (int32_t)floor(q[a] + (1 + r) * u[a] + 0.5);
                double side = 2 * r + 1;
                share += (double)cube_count(g->vol, c[0], c[1], c[2], r) / (side * side * side);
            }
            double occ = fmin(1.0, 2 * share / AO_RADII);
            g->out[i] = (uint8_t)(255 * (1 - 0.6 * occ) + 0.5);
        }
}

static inline int voxel_bit(const bvox_volume *v, const int32_t q[3])
{
    return (int)(bvox__column_c(v, q[0], q[1])[q[2] >> 6] >> (q[2] & 63) & 1);
}

/* Does the ray from index point s along the unit index direction d meet a
 * 1-voxel farther than skip voxels from s before it leaves the volume?
 * (voxel i's box is [i - 1/2, i + 1/2).) The skip steps over the staircase
 * of the surface the ray starts from, which would otherwise shadow itself
 * in speckles wherever the light grazes it. */
static int ray_blocked(const bvox_volume *v, const double s[3], const double d[3], double skip)
{
    const int32_t n[3] = {v->nx, v->ny, v->nz};
    int32_t cell[3], step[3];
    double tmax[3], tdelta[3];
    for (int a = 0; a < 3; a++) {
        double g = s[a] + 0.5;
        cell[a] = (int32_t)floor(g);
        step[a] = d[a] > 0 ? 1 : d[a] < 0 ? -1 : 0;
        if (step[a] == 0) {
            tmax[a] = tdelta[a] = INFINITY;
        } else {
            double edge = step[a] > 0 ? cell[a] + 1 - g : g - cell[a];
            tdelta[a] = 1.0 / fabs(d[a]);
            tmax[a] = edge * tdelta[a];
        }
    }
    for (int64_t it = 0, lim = 2 * ((int64_t)n[0] + n[1] + n[2]) + 8; it < lim; it++) {
        int inside = 1;
        for (int a = 0; a < 3; a++) {
            if ((cell[a] < 0 && step[a] <= 0) || (cell[a] >= n[a] && step[a] >= 0)) return 0;
            inside &= cell[a] >= 0 && cell[a] < n[a];
        }
        int a = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
        if (inside && tmax[a] > skip && voxel_bit(v, cell)) return 1; /* leaves it beyond skip */
        cell[a] += step[a];
        tmax[a] += tdelta[a];
    }
    return 0;
}

static void shadow_rows(void *arg, int64_t y0, int64_t y1)
{
    const occ_ctx *g = arg;
    const bvox_preimage *p = g->pre;
    const bvox_volume *v = g->vol;
    double d[3], len = 0;
    for (int a = 0; a < 3; a++) {
        d[a] = g->l[a] / v->geom.spacing[a];
        len += d[a] * d[a];
    }
    for (int a = 0; a < 3; a++) d[a] /= sqrt(len);
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++)
        for (int32_t x = 0; x < p->width; x++) {
            size_t i = (size_t)y * (size_t)p->width + (size_t)x;
            int32_t q[3];
            double u[3], n[3], s[3];
            if (!hit_and_normal(v, p, g->radius, x, y, q, u, n)) {
                g->out[i] = 1;
                continue;
            }
            if (n[0] * g->l[0] + n[1] * g->l[1] + n[2] * g->l[2] <= 0) {
                g->out[i] = 0; /* facing away from the light */
                continue;
            }
            /* start clear of the voxel's own staircase */
            for (int a = 0; a < 3; a++) s[a] = q[a] + 1.5 * u[a];
            g->out[i] = !ray_blocked(v, s, d, SHADOW_SKIP);
        }
}

static bvox_status occ_check(const bvox_volume *vol, const bvox_preimage *pre, const void *out,
                             const char *what)
{
    if (!vol || !pre || !pre->depth || !pre->code || !out)
        return bvox__fail(BVOX_EINVAL, "%s: missing volume, pre-image or output", what);
    return BVOX_OK;
}

bvox_status bvox_preimage_ao(const bvox_volume *vol, const bvox_preimage *pre, int radius,
                             uint8_t *ao)
{
    bvox_status st = occ_check(vol, pre, ao, "ambient occlusion");
    if (st) return st;
    occ_ctx g = {vol, pre, radius, {0, 0, 0}, ao};
    bvox__parallel_for(pre->height, 8, ao_rows, &g);
    return BVOX_OK;
}

bvox_status bvox_preimage_shadows(const bvox_volume *vol, const bvox_preimage *pre,
                                  const bvox_light *light, int radius, uint8_t *lit)
{
    bvox_status st = occ_check(vol, pre, lit, "shadows");
    if (!st) st = bvox__light_check(light);
    if (st) return st;
    /* the light's eye direction (right, up, towards the viewer) made physical */
    double l[3];
    bvox__light_dir(light, l);
    occ_ctx g = {vol, pre, radius, {0, 0, 0}, lit};
    for (int a = 0; a < 3; a++)
        g.l[a] = l[0] * pre->eye[a] - l[1] * pre->eye[3 + a] - l[2] * pre->eye[6 + a];
    bvox__parallel_for(pre->height, 8, shadow_rows, &g);
    return BVOX_OK;
}
