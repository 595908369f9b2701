/* test_journal.c — undo/redo of in-place edits (src/journal.c): a sequence
 * of edits (boxes, shapes, a plane cut, single voxels) on random volumes at
 * awkward sizes is undone step by step back to each earlier state, exactly
 * (compared with copies kept by the test), and redone to the last; memory
 * grows with the edited boxes, not the volume (a brush stroke of 20 balls on
 * a 1024^3 model holds well under 1 MiB where a copy would be 128 MiB);
 * edits that change nothing leave no step; a new edit drops the redo steps;
 * the cap forgets the oldest steps; misuse is refused. */
#include "harness.h"
#include "internal.h"

#include <string.h>

static bvox_volume *random_volume(bvox_dims d)
{
    bvox_volume *v;
    if (bvox_volume_create(d, &v)) return NULL;
    for (int32_t z = 0; z < d.nz; z++)
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++)
                if (harness_rand() % 3 == 0) bvox_volume_set(v, x, y, z, 1);
    return v;
}

/* One edit recorded as a step: which kind is chosen by k. */
static bvox_status edit(bvox_journal *j, bvox_volume *v, int k)
{
    bvox_dims d = bvox_volume_dims(v);
    int32_t x = (int32_t)(harness_rand() % (uint64_t)d.nx), y = (int32_t)(harness_rand() % (uint64_t)d.ny),
            z = (int32_t)(harness_rand() % (uint64_t)d.nz);
    bvox_box b = {x - 3, y - 2, z - 40, x + 4, y + 3, z + 50};
    bvox_status st;
    bvox_journal_begin(j);
    switch (k % 4) {
    case 0:
        st = bvox_journal_record(j, v, b);
        if (!st) st = bvox_edit_fill_box(v, b, (int)(harness_rand() & 1), NULL);
        break;
    case 1: {
        bvox_shape s;
        memset(&s, 0, sizeof s);
        s.kind = BVOX_SHAPE_SPHERE;
        s.center[0] = x, s.center[1] = y, s.center[2] = z;
        s.radius = 4;
        st = bvox_journal_record(j, v, (bvox_box){x - 5, y - 5, z - 5, x + 6, y + 6, z + 6});
        if (!st) st = bvox_shape_draw(v, &s, k & 4 ? BVOX_CSG_UNION : BVOX_CSG_DIFFERENCE);
        break;
    }
    case 2: /* the whole volume may change */
        st = bvox_journal_record(j, v, (bvox_box){0, 0, 0, d.nx, d.ny, d.nz});
        if (!st) st = bvox_cut_plane(v, 1, 0.5, 0.25, -(double)x, 1, NULL);
        break;
    default: /* two single voxels in one step, recorded separately */
        st = bvox_journal_record(j, v, (bvox_box){x, y, z, x + 1, y + 1, z + 1});
        if (!st) st = bvox_edit_voxel(v, x, y, z, !bvox_volume_get(v, x, y, z), NULL);
        if (!st) st = bvox_journal_sync(j, v);
        if (!st) st = bvox_journal_record(j, v, (bvox_box){0, 0, 0, 1, 1, 1});
        if (!st) st = bvox_edit_voxel(v, 0, 0, 0, !bvox_volume_get(v, 0, 0, 0), NULL);
        break;
    }
    if (!st) st = bvox_journal_sync(j, v);
    bvox_journal_end(j);
    return st;
}

TEST(undo_redo_exact)
{
    static const bvox_dims sizes[] = {{7, 5, 1}, {9, 7, 64}, {5, 6, 65}, {11, 3, 130}};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        bvox_volume *v = random_volume(sizes[si]);
        CHECK(v);
        bvox_journal *j;
        CHECK_OK(bvox_journal_create(sizes[si], 0, &j));
        enum { N = 12 };
        bvox_volume *states[N + 1];
        int nstates = 0;
        CHECK_OK(bvox_volume_copy(v, &states[nstates++]));
        for (int k = 0; k < N; k++) {
            CHECK_OK(edit(j, v, k));
            CHECK_OK(bvox_volume_check(v));
            /* a step that changed something is kept, else not */
            if (!bvox_volume_equal(v, states[nstates - 1])) CHECK_OK(bvox_volume_copy(v, &states[nstates++]));
            CHECK_EQ(bvox_journal_steps(j), nstates - 1);
        }
        CHECK(nstates > 4);
        int done;
        bvox_box changed;
        for (int k = nstates - 2; k >= 0; k--) {
            CHECK_OK(bvox_journal_undo(j, v, &done, &changed));
            CHECK_EQ(done, 1);
            CHECK(bvox_volume_equal(v, states[k]));
            CHECK(changed.x1 > changed.x0);
            CHECK_OK(bvox_volume_check(v));
        }
        CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
        CHECK_EQ(done, 0);
        CHECK(!bvox_journal_can_undo(j));
        for (int k = 1; k < nstates; k++) {
            CHECK_OK(bvox_journal_redo(j, v, &done, NULL));
            CHECK_EQ(done, 1);
            CHECK(bvox_volume_equal(v, states[k]));
        }
        CHECK_OK(bvox_journal_redo(j, v, &done, NULL));
        CHECK_EQ(done, 0);
        for (int k = 0; k < nstates; k++) bvox_volume_destroy(states[k]);
        bvox_journal_destroy(j);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(brush_stroke_memory_follows_the_edit)
{
    bvox_dims d = {1024, 1024, 1024};
    bvox_volume *v;
    CHECK_OK(bvox_volume_create(d, &v));
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_SPHERE;
    s.center[0] = s.center[1] = s.center[2] = 511.5;
    s.radius = 300;
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    bvox_volume *before;
    CHECK_OK(bvox_volume_copy(v, &before));
    bvox_journal *j;
    CHECK_OK(bvox_journal_create(d, 0, &j));
    size_t in_use = bvox_memory_in_use();
    /* one stroke: 20 balls of radius 5 along the top of the sphere */
    bvox_journal_begin(j);
    size_t box_words = 0;
    for (int i = 0; i < 20; i++) {
        int32_t x = 400 + 10 * i, y = 511, z = 212;
        bvox_box b = {x - 6, y - 6, z - 6, x + 7, y + 7, z + 7};
        CHECK_OK(bvox_journal_record(j, v, b));
        box_words += 13 * 13 * 2; /* z 206..218 spans at most 2 words */
        s.center[0] = x, s.center[1] = y, s.center[2] = z;
        s.radius = 5;
        CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_DIFFERENCE));
        CHECK_OK(bvox_journal_sync(j, v));
    }
    bvox_journal_end(j);
    size_t bytes = bvox_journal_bytes(j);
    CHECK(bytes > 0);
    CHECK(bytes <= box_words * 8 + 20 * 128);         /* the balls' boxes, nothing more */
    CHECK(bvox_memory_in_use() - in_use <= box_words * 8); /* the budget sees the same */
    CHECK(bytes < ((size_t)1 << 20));                  /* a copy would be 128 MiB */
    CHECK(!bvox_volume_equal(v, before));
    int done;
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_EQ(done, 1);
    CHECK(bvox_volume_equal(v, before));
    bvox_journal_destroy(j);
    CHECK_EQ(bvox_memory_in_use(), in_use);
    bvox_volume_destroy(before);
    bvox_volume_destroy(v);
    return 0;
}

TEST(nothing_changed_no_step_and_redo_dropped)
{
    bvox_dims d = {20, 20, 70};
    bvox_volume *v;
    CHECK_OK(bvox_volume_create(d, &v));
    bvox_journal *j;
    CHECK_OK(bvox_journal_create(d, 0, &j));
    /* clearing an empty box: recorded, then nothing changed: no step */
    bvox_journal_begin(j);
    CHECK_OK(bvox_journal_record(j, v, (bvox_box){2, 2, 2, 8, 8, 68}));
    CHECK_OK(bvox_edit_fill_box(v, (bvox_box){2, 2, 2, 8, 8, 68}, 0, NULL));
    CHECK_OK(bvox_journal_sync(j, v));
    bvox_journal_end(j);
    CHECK_EQ(bvox_journal_steps(j), 0);
    CHECK_EQ(bvox_journal_bytes(j), 0);
    /* a box outside the volume records nothing */
    CHECK_OK(bvox_journal_record(j, v, (bvox_box){30, 0, 0, 40, 5, 5}));
    bvox_journal_end(j);
    CHECK_EQ(bvox_journal_steps(j), 0);
    /* two steps, undo one, a new edit: the undone one cannot be redone */
    for (int k = 0; k < 2; k++) {
        bvox_journal_begin(j);
        CHECK_OK(bvox_journal_record(j, v, (bvox_box){k, 0, 0, k + 1, 1, 1}));
        CHECK_OK(bvox_edit_voxel(v, k, 0, 0, 1, NULL));
        CHECK_OK(bvox_journal_sync(j, v));
        bvox_journal_end(j);
    }
    int done;
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK(bvox_journal_can_redo(j));
    bvox_journal_begin(j);
    CHECK_OK(bvox_journal_record(j, v, (bvox_box){5, 5, 5, 6, 6, 6}));
    CHECK_OK(bvox_edit_voxel(v, 5, 5, 5, 1, NULL));
    CHECK_OK(bvox_journal_sync(j, v));
    bvox_journal_end(j);
    CHECK(!bvox_journal_can_redo(j));
    CHECK_EQ(bvox_journal_steps(j), 2);
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_EQ(bvox_volume_count(v), 0);
    bvox_journal_destroy(j);
    bvox_volume_destroy(v);
    return 0;
}

TEST(cap_forgets_oldest)
{
    bvox_dims d = {16, 16, 64};
    bvox_volume *v;
    CHECK_OK(bvox_volume_create(d, &v));
    bvox_journal *j;
    /* each step: 16 x 16 columns x 1 word = 2 KiB (+ bookkeeping) */
    CHECK_OK(bvox_journal_create(d, 5000, &j));
    for (int k = 0; k < 5; k++) {
        bvox_journal_begin(j);
        CHECK_OK(bvox_journal_record(j, v, (bvox_box){0, 0, 0, 16, 16, 64}));
        CHECK_OK(bvox_edit_voxel(v, k, k, k, 1, NULL));
        CHECK_OK(bvox_journal_sync(j, v));
        bvox_journal_end(j);
        CHECK(bvox_journal_bytes(j) <= 5000);
    }
    CHECK_EQ(bvox_journal_steps(j), 2);
    int done;
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_OK(bvox_journal_undo(j, v, &done, NULL));
    CHECK_EQ(done, 0);
    CHECK_EQ(bvox_volume_count(v), 3); /* the three oldest edits are kept */
    bvox_journal_destroy(j);
    bvox_volume_destroy(v);
    return 0;
}

TEST(misuse)
{
    bvox_journal *j = (bvox_journal *)1;
    CHECK_STATUS(bvox_journal_create((bvox_dims){0, 1, 1}, 0, &j), BVOX_EINVAL);
    CHECK(j == NULL);
    CHECK_OK(bvox_journal_create((bvox_dims){4, 4, 4}, 0, &j));
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 5}, &v));
    CHECK_STATUS(bvox_journal_record(j, v, (bvox_box){0, 0, 0, 1, 1, 1}), BVOX_EINVAL);
    int done;
    CHECK_STATUS(bvox_journal_undo(j, v, &done, NULL), BVOX_EINVAL);
    /* an allocation failure records nothing and leaks nothing */
    bvox_volume *w;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &w));
    bvox__alloc_fail_after(1);
    bvox_status st = bvox_journal_record(j, w, (bvox_box){0, 0, 0, 4, 4, 4});
    bvox__alloc_fail_after(0);
    CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
    bvox_journal_end(j);
    CHECK_EQ(bvox_journal_steps(j), 0);
    bvox_journal_destroy(j);
    bvox_journal_destroy(NULL);
    bvox_volume_destroy(v);
    bvox_volume_destroy(w);
    return 0;
}
