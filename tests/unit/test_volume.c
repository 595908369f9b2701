/* test_volume.c — the model: creation limits, voxel access, boxes, crop, pad,
 * count, bbox and the tail-bit invariant, against the byte-per-voxel reference
 * at awkward sizes. */
#include "harness.h"
#include "ref/voxref.h"
#include "internal.h"

#include <stdio.h>
#include <string.h>

static const int sizes[][3] = {{1, 1, 1},  {3, 5, 1},  {7, 3, 63}, {5, 7, 64},
                               {9, 3, 65}, {3, 11, 130}, {17, 1, 129}, {1, 13, 200}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

static bvox_box random_box(const int *s)
{
    bvox_box b;
    int32_t *lo = &b.x0, *hi = &b.x1;
    for (int a = 0; a < 3; a++) {
        int p = (int)(harness_rand() % (uint64_t)(s[a] + 2)) - 1;
        int q = (int)(harness_rand() % (uint64_t)(s[a] + 2)) - 1;
        (&b.x0)[a] = p < q ? p : q;
        (&b.x1)[a] = p < q ? q + 1 : p + 1;
    }
    (void)lo;
    (void)hi;
    return b;
}

TEST(create_limits)
{
    bvox_volume *v = (bvox_volume *)1;
    CHECK_STATUS(bvox_volume_create((bvox_dims){0, 5, 5}, &v), BVOX_EINVAL);
    CHECK(v == NULL);
    CHECK_STATUS(bvox_volume_create((bvox_dims){65536, 5, 5}, &v), BVOX_EINVAL);
    CHECK_STATUS(bvox_volume_create((bvox_dims){-3, 5, 5}, &v), BVOX_EINVAL);
    /* 65535^3 bits = 32 TiB: over any budget, refused before allocating */
    CHECK_STATUS(bvox_volume_create((bvox_dims){65535, 65535, 65535}, &v), BVOX_ETOOBIG);
    CHECK(strstr(bvox_errmsg(), "budget") != NULL);
    bvox_set_memory_budget(1 << 20);
    CHECK_STATUS(bvox_volume_create((bvox_dims){1024, 1024, 64}, &v), BVOX_ETOOBIG);
    bvox_set_memory_budget(0);
    CHECK_OK(bvox_volume_create((bvox_dims){65535, 1, 1}, &v));
    CHECK_EQ(bvox_volume_count(v), 0);
    bvox_volume_destroy(v);
    bvox_volume_destroy(NULL);
    return 0;
}

TEST(alloc_failure_is_clean)
{
    bvox_volume *v = NULL;
    bvox__alloc_fail_after(1);
    CHECK_STATUS(bvox_volume_create((bvox_dims){4, 4, 4}, &v), BVOX_ENOMEM);
    CHECK(v == NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &v));
    CHECK(bvox_memory_in_use() > 0);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Whether the mapping holding p has MADV_HUGEPAGE ("hg" in its VmFlags
 * line of /proc/self/smaps); -1 when that cannot be told. */
static int huge_page_advised(const void *p)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f) return -1;
    char line[512];
    int inside = 0, advised = -1;
    uintptr_t a = (uintptr_t)p;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' ')) {
            inside = a >= lo && a < hi;
        } else if (inside && !strncmp(line, "VmFlags:", 8)) {
            advised = strstr(line, " hg") != NULL;
            break;
        }
    }
    fclose(f);
    return advised;
}

/* Large buffers ask for huge pages (alloc.c) yet are charged their own
 * size, are zeroed to the last word and give every byte back. */
TEST(large_words_ask_for_huge_pages)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){512, 300, 512}, &v)); /* 9.4 MiB */
    CHECK_EQ(bvox_memory_in_use(), v->nwords * sizeof *v->words);
    uint64_t any = 0;
    for (size_t i = 0; i < v->nwords; i++) any |= v->words[i];
    CHECK_EQ(any, 0);
    bvox_volume_set(v, 511, 299, 511, 1);
    CHECK_EQ(bvox_volume_count(v), 1);
    /* the middle of the buffer lies on a whole advised 2 MiB page; only a
     * kernel without THP (no such folder) cannot say */
    FILE *thp = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (thp) {
        fclose(thp);
        CHECK_EQ(huge_page_advised(v->words + v->nwords / 2), 1);
    }
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    /* zeroed also when the memory comes back dirty from the last buffer
     * of the same size */
    for (int round = 0; round < 2; round++) {
        CHECK_OK(bvox_volume_create((bvox_dims){509, 301, 507}, &v)); /* 9.4 MiB + odd */
        any = 0;
        for (size_t i = 0; i < v->nwords; i++) any |= v->words[i];
        CHECK_EQ(any, 0);
        memset(v->words, 0xff, v->nwords * sizeof *v->words);
        bvox_volume_destroy(v);
    }
    /* a small buffer is left alone */
    CHECK_OK(bvox_volume_create((bvox_dims){64, 64, 64}, &v));
    CHECK_EQ((uintptr_t)v->words % 64, 0);
    bvox_volume_destroy(v);
    return 0;
}

TEST(get_set_random)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){s[0], s[1], s[2]}, &v));
        for (int k = 0; k < 500; k++) {
            int x = (int)(harness_rand() % (uint64_t)s[0]);
            int y = (int)(harness_rand() % (uint64_t)s[1]);
            int z = (int)(harness_rand() % (uint64_t)s[2]);
            int val = (int)(harness_rand() & 1);
            *voxref_at(r, x, y, z) = (uint8_t)val;
            CHECK_OK(bvox_volume_set(v, x, y, z, val));
        }
        CHECK(voxref_matches(r, v));
        CHECK_EQ(bvox_volume_count(v), voxref_count(r));
        CHECK_STATUS(bvox_volume_set(v, s[0], 0, 0, 1), BVOX_EINVAL);
        CHECK_STATUS(bvox_volume_set(v, 0, 0, -1, 1), BVOX_EINVAL);
        CHECK_EQ(bvox_volume_get(v, -1, 0, 0), 0);
        CHECK_EQ(bvox_volume_get(v, 0, 0, s[2]), 0);
        voxref_destroy(r);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(fill_box_and_fill_keep_tail_zero)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 3, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        CHECK(v);
        for (int k = 0; k < 20; k++) {
            bvox_box b = random_box(s);
            int val = k & 1;
            voxref_fill_box(r, b, val);
            bvox_volume_fill_box(v, b, val);
        }
        CHECK(voxref_matches(r, v));
        bvox_volume_fill(v, 1);
        CHECK_OK(bvox_volume_check(v));
        CHECK_EQ(bvox_volume_count(v), (int64_t)s[0] * s[1] * s[2]);
        bvox_volume_fill(v, 0);
        CHECK_EQ(bvox_volume_count(v), 0);
        voxref_destroy(r);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(crop_and_pad_against_reference)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 2, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.25, 2.0, "mm"));
        for (int k = 0; k < 10; k++) {
            bvox_box b = random_box(s);
            bvox_box c = b; /* clip for the reference */
            if (c.x0 < 0) c.x0 = 0;
            if (c.y0 < 0) c.y0 = 0;
            if (c.z0 < 0) c.z0 = 0;
            if (c.x1 > s[0]) c.x1 = s[0];
            if (c.y1 > s[1]) c.y1 = s[1];
            if (c.z1 > s[2]) c.z1 = s[2];
            bvox_volume *cv;
            if (c.x0 >= c.x1 || c.y0 >= c.y1 || c.z0 >= c.z1) {
                CHECK_STATUS(bvox_volume_crop(v, b, &cv), BVOX_EINVAL);
                continue;
            }
            CHECK_OK(bvox_volume_crop(v, b, &cv));
            voxref *cr = voxref_crop(r, c);
            CHECK(voxref_matches(cr, cv));
            /* voxels keep their world position */
            CHECK_NEAR(bvox_volume_geometry(cv)->origin[2], c.z0 * 2.0, 1e-12);
            CHECK_NEAR(bvox_volume_geometry(cv)->origin[0], c.x0 * 0.5, 1e-12);
            int before[3] = {(int)(harness_rand() % 3), (int)(harness_rand() % 3),
                             (int)(harness_rand() % 70)};
            int after[3] = {(int)(harness_rand() % 3), (int)(harness_rand() % 3),
                            (int)(harness_rand() % 70)};
            bvox_volume *pv;
            CHECK_OK(bvox_volume_pad(cv, before, after, &pv));
            voxref *pr = voxref_pad(cr, before, after);
            CHECK(voxref_matches(pr, pv));
            CHECK_NEAR(bvox_volume_geometry(pv)->origin[2], (c.z0 - before[2]) * 2.0, 1e-12);
            voxref_destroy(cr);
            voxref_destroy(pr);
            bvox_volume_destroy(cv);
            bvox_volume_destroy(pv);
        }
        bvox_volume *none = (bvox_volume *)1;
        CHECK_STATUS(bvox_volume_crop(v, (bvox_box){s[0], 0, 0, s[0] + 2, 1, 1}, &none),
                     BVOX_EINVAL);
        CHECK(none == NULL);
        voxref_destroy(r);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(bbox_and_equal)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        bvox_volume *v = voxref_to_volume(r);
        bvox_box b, rb;
        CHECK_EQ(bvox_volume_bbox(v, &b), 0);
        for (int k = 0; k < 3; k++) {
            int x = (int)(harness_rand() % (uint64_t)s[0]);
            int y = (int)(harness_rand() % (uint64_t)s[1]);
            int z = (int)(harness_rand() % (uint64_t)s[2]);
            *voxref_at(r, x, y, z) = 1;
            CHECK_OK(bvox_volume_set(v, x, y, z, 1));
            CHECK_EQ(bvox_volume_bbox(v, &b), 1);
            CHECK_EQ(voxref_bbox(r, &rb), 1);
            CHECK(memcmp(&b, &rb, sizeof b) == 0);
        }
        bvox_volume *c;
        CHECK_OK(bvox_volume_copy(v, &c));
        CHECK(bvox_volume_equal(v, c));
        bvox_volume_complement(c);
        CHECK(!bvox_volume_equal(v, c));
        bvox_volume_destroy(c);
        voxref_destroy(r);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(geometry_validation)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
    CHECK_STATUS(bvox_volume_set_spacing(v, 0, 1, 1, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_volume_set_spacing(v, NAN, 1, 1, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_volume_set_spacing(v, 1, 1, 1, "a-very-long-unit-name"), BVOX_EINVAL);
    CHECK_OK(bvox_volume_set_spacing(v, 0.1, 0.1, 3, "um"));
    CHECK(!strcmp(bvox_volume_geometry(v)->unit, "um"));
    bvox_info info;
    CHECK_OK(bvox_volume_set(v, 1, 1, 1, 1));
    CHECK_OK(bvox_info_compute(v, &info));
    CHECK_EQ(info.count, 1);
    CHECK_NEAR(info.volume, 0.03, 1e-12);
    CHECK_EQ(info.bbox.x0, 1);
    CHECK_EQ(info.bbox.z1, 2);
    bvox_volume_destroy(v);
    return 0;
}
