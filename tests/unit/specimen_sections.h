/*
 * specimen_sections.h — the known-answer specimen of the reconstruction
 * tests and benchmark, header-only: a CSG of two ellipsoids and a torus
 * with an ellipsoidal cavity, cut into sections rendered as noisy textured
 * gray on an uneven background with 3 dark round markers, each section moved
 * by a random rigid transform (up to +-8 degrees about the image centre and
 * +-20 pixels) except the reference (the middle one), which stays put.
 * Units are pixels (pixel size 1); section k lies at z = k * spacing.
 */
#ifndef BVOX_TEST_SPECIMEN_SECTIONS_H
#define BVOX_TEST_SPECIMEN_SECTIONS_H

#include "bvox.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

typedef struct specimen {
    int32_t size;      /* images size x size */
    int32_t n;         /* sections */
    double spacing;    /* between sections, pixels */
    double scale;      /* of the shapes: size / 240 */
    bvox_sim2 *moves;  /* per section: block -> image */
    uint64_t seed;
} specimen;

static inline uint64_t spec_rand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}
static inline double spec_urand(uint64_t *s)
{
    return (double)(spec_rand(s) >> 11) / 9007199254740992.0;
}

/* The shapes, for size 240 (scaled by sp->scale about the origin). */
static inline void spec_shapes(const specimen *sp, bvox_shape sh[4])
{
    double k = sp->scale, zc = (sp->n - 1) * sp->spacing / 2;
    for (int i = 0; i < 4; i++) sh[i] = (bvox_shape){0};
    sh[0].kind = BVOX_SHAPE_ELLIPSOID; /* body */
    sh[0].center[0] = 120 * k, sh[0].center[1] = 115 * k, sh[0].center[2] = zc;
    sh[0].semi_axes[0] = 55 * k, sh[0].semi_axes[1] = 40 * k, sh[0].semi_axes[2] = zc * 0.8;
    sh[1].kind = BVOX_SHAPE_ELLIPSOID; /* cavity, subtracted */
    sh[1].center[0] = 112 * k, sh[1].center[1] = 112 * k, sh[1].center[2] = zc;
    sh[1].semi_axes[0] = 20 * k, sh[1].semi_axes[1] = 14 * k, sh[1].semi_axes[2] = zc * 0.35;
    sh[2].kind = BVOX_SHAPE_ELLIPSOID; /* head */
    sh[2].center[0] = 150 * k, sh[2].center[1] = 88 * k, sh[2].center[2] = zc * 1.35;
    sh[2].semi_axes[0] = 24 * k, sh[2].semi_axes[1] = 24 * k, sh[2].semi_axes[2] = zc * 0.4;
    sh[3].kind = BVOX_SHAPE_TORUS; /* handle, axis along x */
    sh[3].center[0] = 105 * k, sh[3].center[1] = 150 * k, sh[3].center[2] = zc * 0.45;
    sh[3].axis[0] = 1;
    sh[3].radius = 22 * k;
    sh[3].minor_radius = 8 * k;
}

static inline int spec_in_ellipsoid(const bvox_shape *s, double x, double y, double z)
{
    double u = (x - s->center[0]) / s->semi_axes[0], v = (y - s->center[1]) / s->semi_axes[1],
           w = (z - s->center[2]) / s->semi_axes[2];
    return u * u + v * v + w * w <= 1;
}

static inline int spec_inside(const bvox_shape sh[4], double x, double y, double z)
{
    const bvox_shape *t = &sh[3];
    double q = hypot(y - t->center[1], z - t->center[2]) - t->radius, dx = x - t->center[0];
    if (q * q + dx * dx <= t->minor_radius * t->minor_radius) return 1;
    if (spec_in_ellipsoid(&sh[2], x, y, z)) return 1;
    return spec_in_ellipsoid(&sh[0], x, y, z) && !spec_in_ellipsoid(&sh[1], x, y, z);
}

/* The 3 markers in the block frame (+ a spurious blob's place). */
static inline bvox_point2 spec_marker(const specimen *sp, int i)
{
    static const double m[4][2] = {{40, 40}, {205, 50}, {45, 200}, {200, 205}};
    return (bvox_point2){m[i][0] * sp->scale, m[i][1] * sp->scale};
}

static inline int spec_init(specimen *sp, int32_t size, int32_t n, double spacing, uint64_t seed)
{
    sp->size = size;
    sp->n = n;
    sp->spacing = spacing;
    sp->scale = size / 240.0;
    sp->seed = seed | 1;
    sp->moves = malloc((size_t)n * sizeof *sp->moves);
    if (!sp->moves) return -1;
    uint64_t s = sp->seed;
    double c = size / 2.0;
    for (int32_t k = 0; k < n; k++) {
        double a = (spec_urand(&s) * 2 - 1) * 8 * M_PI / 180;
        double tx = (spec_urand(&s) * 2 - 1) * 20 * sp->scale, ty = (spec_urand(&s) * 2 - 1) * 20 * sp->scale;
        if (k == n / 2) a = tx = ty = 0;
        /* p -> R (p - c) + c + t */
        bvox_sim2 m = {a, 1, 0, 0};
        bvox_point2 rc = bvox_sim2_apply(&m, (bvox_point2){c, c});
        m.tx = c - rc.x + tx;
        m.ty = c - rc.y + ty;
        sp->moves[k] = m;
    }
    return 0;
}

static inline void spec_free(specimen *sp)
{
    free(sp->moves);
    sp->moves = NULL;
}

/* Section k as an 8-bit image. missing: index of a marker left out (-1
 * none, SPEC_NO_MARKERS all); spurious: 1 adds a round dark blob of a
 * marker's size elsewhere. */
#define SPEC_NO_MARKERS 9
static inline bvox_status spec_render(const specimen *sp, int32_t k, int missing, int spurious,
                                      bvox_image **out)
{
    bvox_status st = bvox_image_create(sp->size, sp->size, 1, 8, out);
    if (st) return st;
    bvox_shape sh[4];
    spec_shapes(sp, sh);
    bvox_sim2 inv = bvox_sim2_inverse(&sp->moves[k]);
    double z = k * sp->spacing, r = 5 * sp->scale, n = sp->size;
    uint64_t s = sp->seed * 2654435761u + (uint64_t)k * 97 + 1;
    bvox_point2 mk[4];
    for (int i = 0; i < 4; i++) mk[i] = spec_marker(sp, i);
    for (int32_t y = 0; y < sp->size; y++)
        for (int32_t x = 0; x < sp->size; x++) {
            bvox_point2 p = bvox_sim2_apply(&inv, (bvox_point2){x + 0.5, y + 0.5});
            double noise = (spec_urand(&s) - 0.5) * 24;
            /* transmitted light: an uneven illumination (a gradient and a
             * vignette, in image coordinates) times the transmittance */
            double light = 165 + 35 * x / n - 40 * ((y - n / 2) / n) * ((y - n / 2) / n) * 4;
            double tr = 1;
            if (spec_inside(sh, p.x, p.y, z))
                tr = 0.48 + 0.09 * sin(p.x / (5 * sp->scale)) * cos(p.y / (7 * sp->scale));
            for (int i = 0; i < 4; i++) {
                if (i == missing || missing == SPEC_NO_MARKERS || (i == 3 && !spurious)) continue;
                if (hypot(p.x - mk[i].x, p.y - mk[i].y) <= r) tr = 0.15;
            }
            double v = light * tr;
            v += noise;
            (*out)->pixels[(size_t)y * sp->size + x] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
        }
    return BVOX_OK;
}

/* The truth on the grid of vol (its dims and geometry): drawn with
 * bvox_shape_draw (the same shapes, the same inside rule). */
static inline bvox_status spec_truth(const specimen *sp, const bvox_volume *like, bvox_volume **out)
{
    bvox_status st = bvox_volume_create(bvox_volume_dims(like), out);
    if (!st) st = bvox_volume_set_geometry(*out, bvox_volume_geometry(like));
    bvox_shape sh[4];
    spec_shapes(sp, sh);
    if (!st) st = bvox_shape_draw(*out, &sh[0], BVOX_CSG_UNION);
    if (!st) st = bvox_shape_draw(*out, &sh[1], BVOX_CSG_DIFFERENCE);
    if (!st) st = bvox_shape_draw(*out, &sh[2], BVOX_CSG_UNION);
    if (!st) st = bvox_shape_draw(*out, &sh[3], BVOX_CSG_UNION);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

static inline double spec_dice(const bvox_volume *a, const bvox_volume *b)
{
    int64_t both = bvox_volume_count_and(a, b);
    int64_t sum = bvox_volume_count(a) + bvox_volume_count(b);
    return both < 0 || sum == 0 ? 0 : 2.0 * (double)both / (double)sum;
}

#endif
