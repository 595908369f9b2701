/* test_normal_cache.c — bvox_shade_codes_cached gives exactly the codes of
 * bvox_shade_codes_volume (the cache only saves work): over a turn of views
 * of a sphere with the cache warm, zoomed in (8 voxels a pixel) and out (the
 * nearest voxel), at every smooth radius, after the volume's voxels change
 * and the caller clears it, for a volume of other dimensions (it rebinds by
 * itself) and for a long one (keys of many bits in the smallest cache); and
 * both are the bins of the per-pixel normals (bvox_preimage_normals). After
 * an edit, clearing only the edited box (grown by the radius) is enough: the
 * codes equal the uncached ones, while a cache left as it was does not, and
 * entries far from the box are kept. */
#include "harness.h"
#include "render/normal_cache.h"

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

/* Entries of the cache that hold a voxel (valid bit set). */
static long valid_entries(const bvox_normal_cache *c)
{
    long n = 0;
    for (size_t i = 0; i < ((size_t)1 << c->slot_bits); i++)
        n += (atomic_load_explicit(&c->slot[i], memory_order_relaxed) >> 63) != 0;
    return n;
}

TEST(clear_box_forgets_what_an_edit_reaches)
{
    bvox_volume *v = sphere(48, 19.5);
    CHECK(v != NULL);
    bvox_normal_cache *kept = NULL, *boxed = NULL;
    CHECK_OK(bvox_normal_cache_create(1 << 18, &kept)); /* big: no collisions */
    CHECK_OK(bvox_normal_cache_create(1 << 18, &boxed));
    long hits = 0;
    for (int r = 1; r <= 3; r++) {
        bvox_normal_cache_clear(kept), bvox_normal_cache_clear(boxed);
        for (int k = 0; k < 12; k++) { /* warm both with a whole turn */
            CHECK_EQ(compare_view(v, kept, 30 * k, 1.7, r, &hits), 0);
            CHECK_EQ(compare_view(v, boxed, 30 * k, 1.7, r, &hits), 0);
        }
        long before = valid_entries(boxed);
        /* a brush-like edit: a small block dug out of the surface at +x */
        bvox_box e = {38, 20, 20, 44, 27, 27};
        bvox_volume_fill_box(v, e, 0);
        bvox_normal_cache_clear_box(boxed, &e);
        long after = valid_entries(boxed);
        /* far entries kept, near ones forgotten: at most the bricks of the
         * box grown by r (here 4 x 4 x 4 of them at r = 3), 64 slots each */
        CHECK(after < before);
        CHECK(before - after <= 4L * 4 * 4 * 64);
        long stale = 0;
        for (int k = 0; k < 12; k++) {
            CHECK_EQ(compare_view(v, boxed, 30 * k, 1.7, r, &hits), 0);
            long d = compare_view(v, kept, 30 * k, 1.7, r, &hits);
            CHECK(d >= 0);
            stale += d;
        }
        CHECK(stale > 0); /* the test sees stale entries when they are kept */
        bvox_volume_fill_box(v, e, 1); /* restore, then forget again */
        bvox_normal_cache_clear_box(boxed, &e);
        for (int k = 0; k < 12; k += 3) CHECK_EQ(compare_view(v, boxed, 30 * k, 1.7, r, &hits), 0);
    }
    /* edits at the volume's faces and corners (the cache holds -1 .. n) */
    bvox_box corner = {0, 0, 0, 3, 3, 3}, face = {45, 0, 10, 48, 48, 20}, empty = {5, 5, 5, 5, 9, 9};
    bvox_normal_cache_clear_box(boxed, &corner);
    bvox_normal_cache_clear_box(boxed, &face);
    long n0 = valid_entries(boxed);
    bvox_normal_cache_clear_box(boxed, &empty); /* empty: nothing forgotten */
    CHECK_EQ(valid_entries(boxed), n0);
    bvox_box far = {1000, 1000, 1000, 1010, 1010, 1010};
    bvox_normal_cache_clear_box(boxed, &far); /* outside the volume */
    CHECK_EQ(valid_entries(boxed), n0);
    CHECK_EQ(compare_view(v, boxed, 45, 1.7, 3, &hits), 0);
    bvox_normal_cache_clear_box(NULL, &corner);
    bvox_normal_cache_clear_box(boxed, NULL);
    bvox_normal_cache_destroy(kept);
    bvox_normal_cache_destroy(boxed);
    bvox_volume_destroy(v);
    return 0;
}
