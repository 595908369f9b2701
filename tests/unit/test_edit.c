/* test_edit.c — in-place edits (one voxel, fill/clear a box, keep a box)
 * against the byte-per-voxel reference on random volumes at awkward sizes
 * (nz = 1, 63, 64, 65, 130; odd nx, ny), boxes partly or wholly outside,
 * empty boxes, one and two threads; the reported changed region must be the
 * tight box of exactly the voxels that changed (computed here from the
 * before and after volumes), and the invariant must hold after each edit. */
#include "harness.h"
#include "ref/voxref.h"

#include <string.h>

static const int sizes[][3] = {{7, 5, 1},   {5, 9, 63},  {9, 7, 64},
                               {3, 11, 65}, {11, 3, 130}, {1, 1, 129}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

/* Tight half-open box of the voxels that differ between a and b (all zero
 * when none do), as the API reports it. */
static bvox_box diff_box(const voxref *a, const voxref *b)
{
    bvox_box box = {0, 0, 0, 0, 0, 0};
    int any = 0;
    for (int z = 0; z < a->nz; z++)
        for (int y = 0; y < a->ny; y++)
            for (int x = 0; x < a->nx; x++) {
                if (*voxref_at(a, x, y, z) == *voxref_at(b, x, y, z)) continue;
                if (!any) box = (bvox_box){x, y, z, x + 1, y + 1, z + 1};
                any = 1;
                if (x < box.x0) box.x0 = x;
                if (y < box.y0) box.y0 = y;
                if (z < box.z0) box.z0 = z;
                if (x >= box.x1) box.x1 = x + 1;
                if (y >= box.y1) box.y1 = y + 1;
                if (z >= box.z1) box.z1 = z + 1;
            }
    return box;
}

static int box_eq(bvox_box a, bvox_box b)
{
    int eq = !memcmp(&a, &b, sizeof a);
    if (!eq)
        fprintf(stderr, "box (%d,%d,%d)-(%d,%d,%d) vs expected (%d,%d,%d)-(%d,%d,%d)\n", a.x0,
                a.y0, a.z0, a.x1, a.y1, a.z1, b.x0, b.y0, b.z0, b.x1, b.y1, b.z1);
    return eq;
}

static bvox_box random_box(const int *n)
{
    /* corners from a bit outside the volume to a bit beyond it */
    int c[6];
    for (int i = 0; i < 3; i++) {
        int span = n[i] + 6;
        int a = (int)(harness_rand() % (uint64_t)span) - 3;
        int b = (int)(harness_rand() % (uint64_t)span) - 3;
        c[i] = a < b ? a : b;
        c[i + 3] = (a < b ? b : a) + 1;
    }
    return (bvox_box){c[0], c[1], c[2], c[3], c[4], c[5]};
}

/* kind 0: fill, 1: clear, 2: keep */
static int check_box_edit(const int *n, int kind, bvox_box box, unsigned density)
{
    voxref *r = voxref_create(n[0], n[1], n[2]);
    CHECK(r);
    voxref_random(r, 1, density, harness_rand);
    voxref *before = voxref_copy(r);
    bvox_volume *v = voxref_to_volume(r);
    CHECK(v && before);
    bvox_box changed = {-7, -7, -7, -7, -7, -7};
    if (kind == 2) {
        CHECK_OK(bvox_edit_keep_box(v, box, &changed));
        /* reference: clear everything outside the box */
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int x = 0; x < n[0]; x++)
                    if (!(x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1 &&
                          z >= box.z0 && z < box.z1))
                        *voxref_at(r, x, y, z) = 0;
    } else {
        CHECK_OK(bvox_edit_fill_box(v, box, kind == 0, &changed));
        bvox_box clipped = box;
        if (clipped.x0 < 0) clipped.x0 = 0;
        if (clipped.y0 < 0) clipped.y0 = 0;
        if (clipped.z0 < 0) clipped.z0 = 0;
        if (clipped.x1 > n[0]) clipped.x1 = n[0];
        if (clipped.y1 > n[1]) clipped.y1 = n[1];
        if (clipped.z1 > n[2]) clipped.z1 = n[2];
        voxref_fill_box(r, clipped, kind == 0);
    }
    int ok = voxref_matches(r, v) && box_eq(changed, diff_box(before, r));
    if (!ok)
        fprintf(stderr, "kind %d on %dx%dx%d, box (%d,%d,%d)-(%d,%d,%d)\n", kind, n[0], n[1],
                n[2], box.x0, box.y0, box.z0, box.x1, box.y1, box.z1);
    bvox_volume_destroy(v);
    voxref_destroy(r);
    voxref_destroy(before);
    return ok ? 0 : 1;
}

TEST(voxel)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 4, 70}, &v));
    bvox_box b;
    CHECK_OK(bvox_edit_voxel(v, 3, 2, 66, 1, &b));
    CHECK(box_eq(b, (bvox_box){3, 2, 66, 4, 3, 67}));
    CHECK_EQ(bvox_volume_get(v, 3, 2, 66), 1);
    CHECK_EQ(bvox_volume_count(v), 1);
    /* setting it again changes nothing: empty box */
    CHECK_OK(bvox_edit_voxel(v, 3, 2, 66, 7, &b));
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 0, 0, 0}));
    CHECK_OK(bvox_edit_voxel(v, 0, 0, 0, 1, NULL));
    CHECK_OK(bvox_edit_voxel(v, 3, 2, 66, 0, &b));
    CHECK(box_eq(b, (bvox_box){3, 2, 66, 4, 3, 67}));
    CHECK_EQ(bvox_volume_count(v), 1);
    CHECK_OK(bvox_edit_voxel(v, 4, 3, 69, 1, &b)); /* last voxel, the tail word */
    CHECK(box_eq(b, (bvox_box){4, 3, 69, 5, 4, 70}));
    CHECK_OK(bvox_volume_check(v));
    CHECK_STATUS(bvox_edit_voxel(v, 5, 0, 0, 1, &b), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "outside"));
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 0, 0, 0}));
    CHECK_STATUS(bvox_edit_voxel(v, 0, 0, 70, 1, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_edit_voxel(v, 0, -1, 0, 1, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_edit_voxel(NULL, 0, 0, 0, 1, NULL), BVOX_EINVAL);
    CHECK_EQ(bvox_volume_count(v), 2);
    bvox_volume_destroy(v);
    return 0;
}

TEST(boxes_random)
{
    for (int threads = 1; threads <= 2; threads++) {
        bvox_set_threads(threads);
        for (int i = 0; i < NSIZES; i++)
            for (int kind = 0; kind < 3; kind++)
                for (int rep = 0; rep < 12; rep++) {
                    bvox_box box = random_box(sizes[i]);
                    CHECK(!check_box_edit(sizes[i], kind, box, rep % 3 ? 2 : 7));
                }
    }
    bvox_set_threads(0);
    return 0;
}

TEST(boxes_word_edges)
{
    /* z ranges that start and end on and around word boundaries */
    static const int n[3] = {5, 4, 200};
    static const int zs[][2] = {{0, 64}, {63, 65}, {64, 128}, {1, 199}, {127, 129},
                                {0, 200}, {190, 260}, {-5, 1}, {64, 64}, {150, 100}};
    for (size_t k = 0; k < sizeof zs / sizeof zs[0]; k++)
        for (int kind = 0; kind < 3; kind++) {
            bvox_box box = {1, 0, zs[k][0], 4, 3, zs[k][1]};
            CHECK(!check_box_edit(n, kind, box, 2));
        }
    return 0;
}

TEST(box_outside_and_empty)
{
    static const int n[3] = {9, 7, 65};
    const bvox_box outside = {20, 0, 0, 30, 7, 65}, empty = {3, 3, 3, 3, 5, 9};
    for (int kind = 0; kind < 3; kind++) {
        CHECK(!check_box_edit(n, kind, outside, 2));
        CHECK(!check_box_edit(n, kind, empty, 2));
    }
    /* fill outside: nothing changes, empty box; keep outside: all cleared */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){9, 7, 65}, &v));
    bvox_volume_fill(v, 1);
    bvox_box b;
    CHECK_OK(bvox_edit_fill_box(v, outside, 0, &b));
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 0, 0, 0}));
    CHECK_EQ(bvox_volume_count(v), 9 * 7 * 65);
    CHECK_OK(bvox_edit_keep_box(v, outside, &b));
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 9, 7, 65}));
    CHECK_EQ(bvox_volume_count(v), 0);
    CHECK_STATUS(bvox_edit_fill_box(NULL, outside, 1, &b), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(keep_box_hand)
{
    /* a full 6x5x70 block, keep x 1..2, y 2..4, z 60..65 (inclusive) */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){6, 5, 70}, &v));
    bvox_volume_fill(v, 1);
    bvox_box b;
    CHECK_OK(bvox_edit_keep_box(v, (bvox_box){1, 2, 60, 3, 5, 66}, &b));
    CHECK_EQ(bvox_volume_count(v), 2 * 3 * 6);
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 6, 5, 70}));
    bvox_box bb;
    CHECK(bvox_volume_bbox(v, &bb));
    CHECK(box_eq(bb, (bvox_box){1, 2, 60, 3, 5, 66}));
    /* the same again changes nothing */
    CHECK_OK(bvox_edit_keep_box(v, (bvox_box){1, 2, 60, 3, 5, 66}, &b));
    CHECK(box_eq(b, (bvox_box){0, 0, 0, 0, 0, 0}));
    /* clearing one z layer of what is left reports just that layer */
    CHECK_OK(bvox_edit_fill_box(v, (bvox_box){0, 0, 64, 6, 5, 65}, 0, &b));
    CHECK(box_eq(b, (bvox_box){1, 2, 64, 3, 5, 65}));
    CHECK_EQ(bvox_volume_count(v), 2 * 3 * 5);
    CHECK_OK(bvox_volume_check(v));
    bvox_volume_destroy(v);
    return 0;
}
