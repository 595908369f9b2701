/* test_normal_cache.c — bvox_shade_codes_cached gives exactly the codes of
 * bvox_shade_codes_volume (the cache only saves work): over a turn of views
 * of a sphere with the cache warm, zoomed in (8 voxels a pixel) and out (the
 * nearest voxel), at every smooth radius, after the volume's voxels change
 * and the caller clears it, for a volume of other dimensions (it rebinds by
 * itself) and for a long one (keys of many bits in the smallest cache); and
 * both are the bins of the per-pixel normals (bvox_preimage_normals). */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bvox_volume *sphere(int n, double r)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    const double c = (n - 1) / 2.0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++)
                if ((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c) <= r * r)
                    bvox_volume_set(v, x, y, z, 1);
    return v;
}

/* Codes of a view (azimuth az, pixels per voxel scale) with and without the
 * cache; returns the number of differing pixels (-1: a call failed). The
 * pixels that show the object are counted into *hits. */
static long compare_view(const bvox_volume *v, bvox_normal_cache *c, double az, double scale,
                         int radius, long *hits)
{
    bvox_projection p = BVOX_PROJECTION_INIT;
    p.azimuth = az, p.elevation = 25, p.width = p.height = 96, p.scale = scale;
    bvox_preimage *pre;
    if (bvox_cast_projection(v, &p, &pre)) return -1;
    const size_t n = (size_t)pre->width * (size_t)pre->height;
    uint16_t *a = calloc(n, sizeof *a), *b = calloc(n, sizeof *b);
    bvox_shade_opts o = BVOX_SHADE_OPTS_INIT;
    o.mode = BVOX_SHADE_SMOOTH;
    o.smooth_radius = radius;
    long diff = -1;
    float *nrm = calloc(3 * n, sizeof *nrm);
    if (a && b && nrm && !bvox_shade_codes_volume(v, pre, &o, a) &&
        !bvox_shade_codes_cached(v, pre, &o, c, b) &&
        !bvox_preimage_normals(v, pre, BVOX_SHADE_SMOOTH, radius, nrm)) {
        diff = 0;
        for (size_t i = 0; i < n; i++) {
            diff += a[i] != b[i];
            *hits += a[i] != BVOX_SCODE_BACKGROUND;
            if (a[i] == BVOX_SCODE_BACKGROUND) continue;
            /* and the codes are the bins (64 x 64 of right, up) of the
             * per-pixel normals (floats: a hair from a bin's edge may round
             * across it) */
            for (int k = 0; k < 2; k++) {
                double u = (nrm[3 * i + (size_t)k] + 1) * 32;
                int bin = (int)floor(u);
                bin = bin < 0 ? 0 : bin > 63 ? 63 : bin;
                int got = k ? a[i] >> 6 : a[i] & 63;
                if (got != bin && fabs(u - floor(u + 0.5)) > 1e-4) diff++;
            }
        }
    }
    free(nrm);
    free(a), free(b);
    bvox_preimage_destroy(pre);
    return diff;
}

TEST(cached_codes_equal_uncached)
{
    bvox_volume *v = sphere(48, 19.5);
    CHECK(v != NULL);
    bvox_normal_cache *c = NULL;
    CHECK_OK(bvox_normal_cache_create(1 << 14, &c)); /* small: collisions happen */
    long hits = 0;
    for (int r = 0; r <= 3; r++)
        for (int k = 0; k < 12; k++) {
            CHECK_EQ(compare_view(v, c, 30 * k, 1.7, r, &hits), 0); /* 8 voxels a pixel */
            CHECK_EQ(compare_view(v, c, 30 * k + 7, 1.7, r, &hits), 0);
            CHECK_EQ(compare_view(v, c, 30 * k, 0.8, r, &hits), 0); /* nearest voxel */
        }
    CHECK(hits > 48L * 1000);
    /* the voxels change: after a clear the new ones are used */
    bvox_volume_fill_box(v, (bvox_box){0, 0, 24, 48, 48, 48}, 0);
    bvox_normal_cache_clear(c);
    CHECK_EQ(compare_view(v, c, 40, 1.7, 2, &hits), 0);
    /* another volume's shape rebinds by itself */
    bvox_volume *w = sphere(40, 12);
    CHECK(w != NULL);
    CHECK_EQ(compare_view(w, c, 40, 1.7, 2, &hits), 0);
    CHECK_EQ(compare_view(v, c, 40, 1.7, 2, &hits), 0);
    bvox_volume_destroy(w);
    /* a long volume: keys of many bits, tags of 16 in the smallest cache */
    CHECK_OK(bvox_volume_create((bvox_dims){65000, 40, 40}, &w));
    for (int z = 10; z < 30; z++)
        for (int y = 10; y < 30; y++)
            for (int x = 32490; x < 32510; x++) bvox_volume_set(w, x, y, z, 1);
    bvox_normal_cache *small = NULL;
    CHECK_OK(bvox_normal_cache_create(1 << 12, &small));
    CHECK_EQ(compare_view(w, small, 40, 1.7, 2, &hits), 0);
    bvox_normal_cache_destroy(small);
    bvox_volume_destroy(w);
    bvox_normal_cache_destroy(c);
    bvox_normal_cache_destroy(NULL);
    bvox_normal_cache_clear(NULL);
    CHECK_STATUS(bvox_normal_cache_create(0, NULL), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}
