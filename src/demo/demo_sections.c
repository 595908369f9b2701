/*
 * demo_sections.c — simulated serial sections of the built-in specimen
 * (demo.h). The same model of the microscope as the reconstruction tests'
 * specimen (tests/unit/specimen_sections.h): transmitted light with a
 * gradient and a vignette, a texture in the tissue, uniform noise, dark
 * round markers, a rigid move per section. Here the tissue is the demo
 * specimen's shapes cut by the section's plane (bvox__demo_draw on a
 * one-slice volume, so the cut is exact at any z, not a voxel slice), and
 * each image pixel looks up the block pixel its inverse move lands in.
 */
#include "demo/demo.h"

#include <math.h>
#include <stdlib.h>

static uint64_t xorshift(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static double urand(uint64_t *s)
{
    return (double)(xorshift(s) >> 11) / 9007199254740992.0;
}

bvox_status bvox__demo_cut_init(bvox__demo_cut *c, int32_t n, double z0, double dz, uint64_t seed)
{
    c->n = n;
    c->z0 = z0;
    c->dz = dz;
    c->seed = seed | 1;
    c->moves = bvox__mem_alloc((size_t)n * sizeof *c->moves);
    if (!c->moves) return bvox__fail(BVOX_ENOMEM, "out of memory for the demo's sections");
    uint64_t s = c->seed;
    const double mid = DEMO_SIZE / 2.0;
    for (int32_t k = 0; k < n; k++) {
        double a = (urand(&s) * 2 - 1) * 6 * M_PI / 180;
        double tx = (urand(&s) * 2 - 1) * 12, ty = (urand(&s) * 2 - 1) * 12;
        if (k == n / 2) a = tx = ty = 0;
        /* p -> R (p - mid) + mid + t */
        bvox_sim2 m = {a, 1, 0, 0};
        bvox_point2 rc = bvox_sim2_apply(&m, (bvox_point2){mid, mid});
        m.tx = mid - rc.x + tx;
        m.ty = mid - rc.y + ty;
        c->moves[k] = m;
    }
    return BVOX_OK;
}

void bvox__demo_cut_free(bvox__demo_cut *c)
{
    free(c->moves);
    c->moves = NULL;
}

/* Embedding holes in the block frame: outside the object whatever the turn,
 * inside the image whatever the move, not symmetric (so a match is unique). */
static const double markers[3][2] = {{166, 24}, {24, 190}, {328, 220}};
#define MARKER_R 5.0

bvox_status bvox__demo_section(const bvox__demo_cut *c, int32_t k, bvox_image **out)
{
    *out = NULL;
    /* the cut: one slice of the block at the section's height */
    bvox_volume *cut = NULL;
    bvox_status st = bvox_volume_create((bvox_dims){DEMO_SIZE, DEMO_SIZE, 1}, &cut);
    if (st) return st;
    bvox_geometry g = *bvox_volume_geometry(cut);
    g.spacing[0] = g.spacing[1] = DEMO_SXY;
    g.spacing[2] = DEMO_SZ;
    g.origin[0] = g.origin[1] = -DEMO_MARGIN * DEMO_SXY;
    g.origin[2] = c->z0 + k * c->dz;
    st = bvox_volume_set_geometry(cut, &g);
    if (!st) st = bvox__demo_draw(cut);
    if (!st) st = bvox_image_create(DEMO_SIZE, DEMO_SIZE, 1, 8, out);
    if (st) {
        bvox_volume_destroy(cut);
        return st;
    }
    bvox_sim2 inv = bvox_sim2_inverse(&c->moves[k]);
    uint64_t s = c->seed * 2654435761u + (uint64_t)k * 97 + 1;
    const double n = DEMO_SIZE;
    uint8_t *px = (*out)->pixels;
    for (int32_t y = 0; y < DEMO_SIZE; y++)
        for (int32_t x = 0; x < DEMO_SIZE; x++) {
            bvox_point2 p = bvox_sim2_apply(&inv, (bvox_point2){x + 0.5, y + 0.5});
            double noise = (urand(&s) - 0.5) * 24;
            double light = 165 + 35 * x / n - 160 * ((y - n / 2) / n) * ((y - n / 2) / n);
            double tr = 1;
            int32_t u = (int32_t)floor(p.x), v = (int32_t)floor(p.y);
            /* nz = 1: voxel (u, v) is bit 0 of its column's one word */
            if (u >= 0 && v >= 0 && u < DEMO_SIZE && v < DEMO_SIZE &&
                (cut->words[(size_t)v * DEMO_SIZE + (size_t)u] & 1))
                tr = 0.48 + 0.09 * sin(p.x / 5) * cos(p.y / 7);
            for (int i = 0; i < 3; i++)
                if (hypot(p.x - markers[i][0], p.y - markers[i][1]) <= MARKER_R) tr = 0.15;
            double val = light * tr + noise;
            px[(size_t)y * DEMO_SIZE + x] = (uint8_t)(val < 0 ? 0 : val > 255 ? 255 : val);
        }
    bvox_volume_destroy(cut);
    return BVOX_OK;
}
