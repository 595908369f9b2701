/* test_render_surface_update.c — bvox_surface_update (src/render/
 * surface_update.c) against a fresh bvox_surface_build of the edited volume:
 * the same entries in the same order, the same class ranges, count and
 * bounding box, word for word, after random edits (boxes, balls, single
 * voxels, emptying and refilling) on random volumes at awkward sizes (nz = 1,
 * 63, 64, 65, 130), with the exact changed box and with a larger one; an
 * empty or outside box changes nothing; misuse is refused. */
#include "harness.h"
#include "render/render.h"

#include <stdlib.h>
#include <string.h>

static int same(const bvox_surface *a, const bvox_surface *b)
{
    if (a->count != b->count || a->empty != b->empty) return 0;
    if (memcmp(a->class_start, b->class_start, sizeof a->class_start)) return 0;
    if (memcmp(&a->bbox, &b->bbox, sizeof a->bbox)) return 0;
    if (!a->count) return 1;
    /* the runs may split the entries differently; laid end to end they must agree */
    size_t bytes = (size_t)a->count * sizeof(uint64_t);
    uint64_t *ea = malloc(bytes), *eb = malloc(bytes);
    int ok = ea && eb;
    if (ok) {
        bvox__surface_flatten(a, ea);
        bvox__surface_flatten(b, eb);
        ok = !memcmp(ea, eb, bytes);
    }
    free(ea);
    free(eb);
    return ok;
}

static int32_t rnd(int32_t n) { return (int32_t)(harness_rand() % (uint64_t)n); }

TEST(update_equals_build)
{
    static const bvox_dims sizes[] = {{9, 7, 1}, {11, 5, 63}, {6, 9, 64}, {8, 8, 65}, {13, 6, 130}};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        bvox_dims d = sizes[si];
        bvox_volume *v;
        CHECK_OK(bvox_volume_create(d, &v));
        for (int32_t z = 0; z < d.nz; z++)
            for (int32_t y = 0; y < d.ny; y++)
                for (int32_t x = 0; x < d.nx; x++)
                    if (harness_rand() % 5 < 2) CHECK_OK(bvox_volume_set(v, x, y, z, 1));
        bvox_surface *s;
        CHECK_OK(bvox_surface_build(v, &s));
        for (int k = 0; k < 60; k++) {
            bvox_box changed;
            int32_t x = rnd(d.nx), y = rnd(d.ny), z = rnd(d.nz);
            switch (k % 6) {
            case 0:
                CHECK_OK(bvox_edit_fill_box(v, (bvox_box){x - 2, y - 1, z - 3, x + 3, y + 2, z + 40},
                                            (int)(harness_rand() & 1), &changed));
                break;
            case 1: {
                bvox_shape sh;
                memset(&sh, 0, sizeof sh);
                sh.kind = BVOX_SHAPE_SPHERE;
                sh.center[0] = x, sh.center[1] = y, sh.center[2] = z;
                sh.radius = 2.5;
                CHECK_OK(bvox_shape_draw(v, &sh, k & 8 ? BVOX_CSG_UNION : BVOX_CSG_DIFFERENCE));
                changed = (bvox_box){x - 3, y - 3, z - 3, x + 4, y + 4, z + 4};
                break;
            }
            case 2: case 3:
                CHECK_OK(bvox_edit_voxel(v, x, y, z, !bvox_volume_get(v, x, y, z), &changed));
                break;
            case 4: /* a larger box than the change is fine too */
                CHECK_OK(bvox_edit_voxel(v, x, y, z, !bvox_volume_get(v, x, y, z), NULL));
                changed = (bvox_box){x - 5, y - 1, 0, x + 2, y + 7, d.nz};
                break;
            default:
                if (k == 17) { /* everything, then nothing */
                    bvox_volume_fill(v, 0);
                    changed = (bvox_box){0, 0, 0, d.nx, d.ny, d.nz};
                } else if (k == 23) {
                    bvox_volume_fill(v, 1);
                    changed = (bvox_box){-4, -4, -4, d.nx + 9, d.ny + 9, d.nz + 9};
                } else {
                    CHECK_OK(bvox_edit_fill_box(v, (bvox_box){0, y, 0, d.nx, y + 1, d.nz}, 1, &changed));
                }
                break;
            }
            CHECK_OK(bvox_surface_update(s, v, changed));
            bvox_surface *ref;
            CHECK_OK(bvox_surface_build(v, &ref));
            CHECK(same(s, ref));
            bvox_box b1, b2;
            CHECK_EQ(bvox_surface_bbox(s, &b1), bvox_volume_bbox(v, &b2));
            CHECK(!memcmp(&b1, &b2, sizeof b1));
            bvox_surface_destroy(ref);
        }
        bvox_surface_destroy(s);
        bvox_volume_destroy(v);
    }
    return 0;
}

static bvox_volume *random_volume(bvox_dims d, int in_ten)
{
    bvox_volume *v;
    if (bvox_volume_create(d, &v)) return NULL;
    for (int32_t z = 0; z < d.nz; z++)
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++)
                if ((int)(harness_rand() % 10) < in_ten) bvox_volume_set(v, x, y, z, 1);
    return v;
}

/* bvox_surface_rebuild (surface.c) gives what a fresh build gives, from
 * any surface: one of other dimensions, an empty one, one of several
 * blocks (reused), one that bvox_surface_update left in a single block of
 * another size; at 1, 3 and 16 threads; and the memory all comes back. */
TEST(rebuild_equals_build)
{
    static const struct { bvox_dims d; int in_ten; } seq[] = {
        {{40, 33, 130}, 5}, {{40, 33, 130}, 3}, {{17, 9, 65}, 6}, {{17, 9, 65}, 0},
        {{128, 16, 1100}, 5}, {{128, 16, 1100}, 4}, {{9, 7, 1}, 4}, {{40, 33, 130}, 5}};
    const int threads[] = {1, 3, 16};
    int saved = bvox_threads();
    size_t base = bvox_memory_in_use();
    for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
        bvox_set_threads(threads[t]);
        bvox_volume *v = random_volume(seq[0].d, seq[0].in_ten);
        CHECK(v != NULL);
        bvox_surface *s;
        CHECK_OK(bvox_surface_build(v, &s));
        for (size_t k = 1; k < sizeof seq / sizeof *seq; k++) {
            bvox_volume_destroy(v);
            v = random_volume(seq[k].d, seq[k].in_ten);
            CHECK(v != NULL);
            if (k == 6) { /* a surface an update has put in one block */
                bvox_volume_set(v, 3, 3, 0, !bvox_volume_get(v, 3, 3, 0));
                CHECK_OK(bvox_surface_rebuild(s, v));
                bvox_volume_set(v, 3, 3, 0, !bvox_volume_get(v, 3, 3, 0));
                CHECK_OK(bvox_surface_update(s, v, (bvox_box){3, 3, 0, 4, 4, 1}));
            }
            /* the old surface's blocks, to see them reused below */
            const bool same_dims = !memcmp(&seq[k].d, &seq[k - 1].d, sizeof seq[k].d);
            void *old_blocks[64];
            int nold = s->nblocks < 64 ? s->nblocks : 64;
            for (int h = 0; h < nold; h++) old_blocks[h] = s->blocks[h].at;
            CHECK_OK(bvox_surface_rebuild(s, v));
            if (same_dims && k != 6 && s->count > 0) { /* same block size: a block reused */
                bool reused = false;
                for (int h = 0; h < s->nblocks; h++)
                    for (int g = 0; g < nold; g++) reused |= s->blocks[h].at == old_blocks[g];
                CHECK(reused);
            }
            bvox_surface *ref;
            CHECK_OK(bvox_surface_build(v, &ref));
            CHECK(same(s, ref));
            CHECK(!memcmp(&s->dims, &ref->dims, sizeof s->dims));
            CHECK(bvox_surface_count(s) > 0 || seq[k].in_ten == 0);
            bvox_surface_destroy(ref);
        }
        bvox_surface_destroy(s);
        bvox_volume_destroy(v);
        CHECK_EQ(bvox_memory_in_use(), base);
    }
    bvox_set_threads(saved);
    /* misuse; a failure leaves the surface empty, still to be destroyed */
    bvox_volume *v = random_volume((bvox_dims){12, 10, 70}, 5);
    bvox_surface *s;
    CHECK_OK(bvox_surface_build(v, &s));
    CHECK_STATUS(bvox_surface_rebuild(NULL, v), BVOX_EINVAL);
    CHECK_STATUS(bvox_surface_rebuild(s, NULL), BVOX_EINVAL);
    CHECK(bvox_surface_count(s) > 0);
    bvox__alloc_fail_after(1);
    bvox_status st = bvox_surface_rebuild(s, v);
    bvox__alloc_fail_after(0);
    CHECK_STATUS(st, BVOX_ENOMEM);
    CHECK_EQ(bvox_surface_count(s), 0);
    CHECK_OK(bvox_surface_rebuild(s, v));
    bvox_surface *ref;
    CHECK_OK(bvox_surface_build(v, &ref));
    CHECK(same(s, ref));
    bvox_surface_destroy(ref);
    bvox_surface_destroy(s);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), base);
    return 0;
}

TEST(nothing_to_do_and_misuse)
{
    bvox_volume *v, *w;
    CHECK_OK(bvox_volume_create((bvox_dims){10, 10, 10}, &v));
    bvox_volume_fill_box(v, (bvox_box){2, 2, 2, 7, 7, 7}, 1);
    bvox_surface *s, *ref;
    CHECK_OK(bvox_surface_build(v, &s));
    CHECK_OK(bvox_surface_build(v, &ref));
    CHECK_OK(bvox_surface_update(s, v, (bvox_box){0, 0, 0, 0, 0, 0}));  /* empty box */
    CHECK_OK(bvox_surface_update(s, v, (bvox_box){20, 0, 0, 30, 5, 5})); /* outside */
    CHECK(same(s, ref));
    CHECK_OK(bvox_volume_create((bvox_dims){10, 10, 11}, &w));
    CHECK_STATUS(bvox_surface_update(s, w, (bvox_box){0, 0, 0, 1, 1, 1}), BVOX_EINVAL);
    CHECK_STATUS(bvox_surface_update(NULL, v, (bvox_box){0, 0, 0, 1, 1, 1}), BVOX_EINVAL);
    /* an allocation failure leaves the surface as it was */
    bvox_volume_set(v, 5, 5, 5, 0);
    for (long n = 1; n <= 2; n++) {
        bvox__alloc_fail_after(n);
        bvox_status st = bvox_surface_update(s, v, (bvox_box){5, 5, 5, 6, 6, 6});
        bvox__alloc_fail_after(0);
        CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
        CHECK(same(s, ref));
    }
    CHECK_EQ(bvox_surface_bbox(NULL, NULL), 0);
    bvox_surface_destroy(ref);
    bvox_surface_destroy(s);
    bvox_volume_destroy(v);
    bvox_volume_destroy(w);
    return 0;
}

/* bvox_surface_build takes its bounding box from the counting pass's rows
 * (no scan of its own): it must equal bvox_volume_bbox with the rows split
 * over 1, 3 and 16 threads, for a few voxels anywhere, one voxel, and none. */
TEST(build_bbox_matches_volume)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){37, 70, 130}, &v));
    for (int round = 0; round < 12; round++) {
        bvox_volume_fill(v, 0);
        int nvox = round < 2 ? round : 1 + (int)(harness_rand() % 6);
        for (int i = 0; i < nvox; i++)
            CHECK_OK(bvox_volume_set(v, rnd(37), rnd(70), rnd(130), 1));
        for (int t = 0; t < 3; t++) {
            bvox_set_threads(t == 0 ? 1 : t == 1 ? 3 : 16);
            bvox_surface *s;
            CHECK_OK(bvox_surface_build(v, &s));
            bvox_box b1, b2;
            CHECK_EQ(bvox_surface_bbox(s, &b1), bvox_volume_bbox(v, &b2));
            CHECK(!memcmp(&b1, &b2, sizeof b1));
            bvox_surface_destroy(s);
        }
    }
    bvox_set_threads(0);
    bvox_volume_destroy(v);
    return 0;
}
