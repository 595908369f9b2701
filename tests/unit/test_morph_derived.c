/* test_morph_derived.c — fill holes, hollow, islands, open and close against
 * slow references and hand-built cases. */
#include "harness.h"
#include "ref/voxref.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* Reference hole filling: flood the background from the border (6-connected). */
static voxref *ref_fill(const voxref *a)
{
    voxref *out = voxref_copy(a);
    size_t n = (size_t)a->nx * a->ny * a->nz;
    uint8_t *outside = calloc(n, 1);
    int *stack = malloc(n * 3 * sizeof *stack);
    size_t top = 0;
    for (int z = 0; z < a->nz; z++)
        for (int y = 0; y < a->ny; y++)
            for (int x = 0; x < a->nx; x++) {
                bool border = !x || !y || !z || x == a->nx - 1 || y == a->ny - 1 || z == a->nz - 1;
                if (!border || *voxref_at(a, x, y, z)) continue;
                size_t i = (size_t)(voxref_at(a, x, y, z) - a->v);
                if (outside[i]) continue;
                outside[i] = 1;
                stack[top * 3] = x, stack[top * 3 + 1] = y, stack[top * 3 + 2] = z, top++;
                while (top) {
                    top--;
                    int px = stack[top * 3], py = stack[top * 3 + 1], pz = stack[top * 3 + 2];
                    static const int d[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
                    for (int k = 0; k < 6; k++) {
                        int qx = px + d[k][0], qy = py + d[k][1], qz = pz + d[k][2];
                        if (qx < 0 || qy < 0 || qz < 0 || qx >= a->nx || qy >= a->ny || qz >= a->nz) continue;
                        if (*voxref_at(a, qx, qy, qz)) continue;
                        size_t j = (size_t)(voxref_at(a, qx, qy, qz) - a->v);
                        if (outside[j]) continue;
                        outside[j] = 1;
                        stack[top * 3] = qx, stack[top * 3 + 1] = qy, stack[top * 3 + 2] = qz, top++;
                    }
                }
            }
    for (size_t i = 0; i < n; i++) out->v[i] = !outside[i];
    free(outside);
    free(stack);
    return out;
}

TEST(fill_holes_against_flood_fill)
{
    static const int sizes[][3] = {{1, 1, 1}, {6, 5, 1}, {7, 6, 63}, {5, 7, 65}, {6, 5, 130}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const int *s = sizes[i];
        voxref *a = voxref_create(s[0], s[1], s[2]);
        voxref_random(a, 6, 10, harness_rand); /* dense: many small cavities */
        bvox_volume *v = voxref_to_volume(a), *f;
        CHECK_OK(bvox_morph_fill_holes(v, &f));
        voxref *r = ref_fill(a);
        CHECK(voxref_matches(r, f));
        voxref_destroy(r);
        voxref_destroy(a);
        bvox_volume_destroy(v);
        bvox_volume_destroy(f);
    }
    /* hand-built: a hollow 5^3 box has a 3^3 cavity */
    bvox_volume *v, *f, *h;
    CHECK_OK(bvox_volume_create((bvox_dims){7, 7, 70}, &v));
    bvox_volume_fill_box(v, (bvox_box){1, 1, 60, 6, 6, 65}, 1);
    bvox_volume_fill_box(v, (bvox_box){2, 2, 61, 5, 5, 64}, 0);
    CHECK_EQ(bvox_volume_count(v), 125 - 27);
    CHECK_OK(bvox_morph_fill_holes(v, &f));
    CHECK_EQ(bvox_volume_count(f), 125);
    /* hollow of the solid box with thickness one voxel gives the box back */
    CHECK_OK(bvox_morph_hollow(f, 1.0, &h));
    CHECK(bvox_volume_equal(h, v));
    bvox_volume_destroy(h);
    CHECK_STATUS(bvox_morph_hollow(f, 0, &h), BVOX_EINVAL);
    bvox_volume_destroy(v);
    bvox_volume_destroy(f);
    return 0;
}

TEST(islands_removed_by_size)
{
    bvox_volume *v, *out;
    CHECK_OK(bvox_volume_create((bvox_dims){20, 20, 20}, &v));
    bvox_volume_fill_box(v, (bvox_box){1, 1, 1, 5, 5, 5}, 1);   /* 64 */
    bvox_volume_fill_box(v, (bvox_box){10, 10, 10, 12, 12, 12}, 1); /* 8 */
    CHECK_OK(bvox_volume_set(v, 15, 15, 15, 1));                /* 1 */
    CHECK_OK(bvox_volume_set(v, 16, 16, 16, 1)); /* diagonal: joins the 1 for 26 only */
    CHECK_OK(bvox_morph_remove_islands(v, 26, 2, &out));
    CHECK_EQ(bvox_volume_count(out), 64 + 8 + 2);
    bvox_volume_destroy(out);
    CHECK_OK(bvox_morph_remove_islands(v, 6, 2, &out));
    CHECK_EQ(bvox_volume_count(out), 64 + 8);
    bvox_volume_destroy(out);
    CHECK_OK(bvox_morph_remove_islands(v, 6, 9, &out));
    CHECK_EQ(bvox_volume_count(out), 64);
    bvox_volume_destroy(out);
    bvox_volume_destroy(v);
    return 0;
}

TEST(open_close_properties)
{
    voxref *a = voxref_create(9, 11, 70);
    voxref_random(a, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(a), *o, *c, *t;
    for (int conn = 6; conn <= 26; conn += conn == 6 ? 12 : 8) {
        CHECK_OK(bvox_morph_open(v, conn, 0, &o));
        CHECK_OK(bvox_morph_close(v, conn, 0, &c));
        /* open is anti-extensive, close extensive, both idempotent */
        CHECK_EQ(bvox_volume_count_and(o, v), bvox_volume_count(o));
        CHECK_EQ(bvox_volume_count_and(c, v), bvox_volume_count(v));
        CHECK_OK(bvox_morph_open(o, conn, 0, &t));
        CHECK(bvox_volume_equal(t, o));
        bvox_volume_destroy(t);
        CHECK_OK(bvox_morph_close(c, conn, 0, &t));
        CHECK(bvox_volume_equal(t, c));
        bvox_volume_destroy(t);
        bvox_volume_destroy(o);
        bvox_volume_destroy(c);
    }
    /* A 3x3 bar with a one-voxel gap, touching the z border at both ends.
     * Hand-worked: the 6-dilation never reaches the gap's corner neighbours
     * outside the bar, so 6-closing fills only the gap's centre voxel; the
     * 26-dilation covers the whole 5x5 slice, so 26-closing fills all nine.
     * The bar's ends at the border stay (safe border). A ball of radius 1.5
     * on unit voxels is exactly the 18-neighbourhood. */
    bvox_volume *bar, *c18;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 5, 40}, &bar));
    bvox_volume_fill_box(bar, (bvox_box){1, 1, 0, 4, 4, 40}, 1);
    bvox_volume_fill_box(bar, (bvox_box){1, 1, 20, 4, 4, 21}, 0);
    CHECK_OK(bvox_morph_close(bar, 6, 0, &c));
    CHECK_EQ(bvox_volume_count(c), 9 * 39 + 1);
    CHECK_EQ(bvox_volume_get(c, 2, 2, 20), 1);
    bvox_volume_destroy(c);
    CHECK_OK(bvox_morph_close(bar, 26, 0, &c));
    CHECK_EQ(bvox_volume_count(c), 9 * 40);
    bvox_volume_destroy(c);
    CHECK_OK(bvox_morph_close(bar, 0, 1.5, &c));
    CHECK_OK(bvox_morph_close(bar, 18, 0, &c18));
    CHECK(bvox_volume_equal(c, c18));
    CHECK(bvox_volume_count(c) > 9 * 39);
    bvox_volume_destroy(c);
    bvox_volume_destroy(c18);
    bvox_volume_destroy(bar);
    bvox_volume_destroy(v);
    voxref_destroy(a);
    return 0;
}
