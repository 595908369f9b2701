/* test_big_buffers.c — bvox__alloc's large buffers (core/big_buffers.c):
 * own mappings in huge pages, kept after bvox__free and handed to the next
 * request they fit; the cache's limits (a share of the budget, 16 buffers),
 * its trim, and the budget's counts around it. */
#include "harness.h"

#include "core/big_buffers.h"
#include "internal.h"

#include <stdint.h>
#include <string.h>

#define MiB ((size_t)1 << 20)

static void *big(size_t bytes, bool zero)
{
    bvox_status st;
    return bvox__alloc(bytes, zero, "test buffer", &st);
}

static int all_zero(const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i]) return 0;
    return 1;
}

TEST(freed_buffer_is_reused_and_zeroed_on_request)
{
    bvox_memory_trim();
    CHECK_EQ(bvox__big_cached(), 0);
    unsigned char *p = big(3 * MiB, false);
    CHECK(p != NULL);
    CHECK_EQ(bvox_memory_in_use(), 3 * MiB);
    memset(p, 0xab, 3 * MiB);
    bvox__free(p, 3 * MiB);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_EQ(bvox__big_cached(), 4 * MiB); /* whole huge pages */
    /* a smaller request of the same size class gets it back, cleared */
    unsigned char *q = big(3 * MiB - 1000, true);
    CHECK(q == p);
    CHECK_EQ(bvox__big_cached(), 0);
    CHECK(all_zero(q, 3 * MiB - 1000));
    bvox__free(q, 3 * MiB - 1000);
    bvox_memory_trim();
    CHECK_EQ(bvox__big_cached(), 0);
    return 0;
}

TEST(fresh_buffers_are_zero_and_aligned)
{
    bvox_memory_trim();
    const size_t sizes[] = {BVOX__BIG_MIN, BVOX__BIG_MIN + 1, MiB - 64, MiB, 5 * MiB + 3};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
        unsigned char *p = big(sizes[i], true);
        CHECK(p != NULL);
        CHECK_EQ((uintptr_t)p % 4096, 0);
        if (sizes[i] >= MiB) CHECK_EQ((uintptr_t)p % (2 * MiB), 0); /* huge-page aligned */
        CHECK(all_zero(p, sizes[i]));
        memset(p, 1, sizes[i]); /* every byte asked for is writable */
        bvox__free(p, sizes[i]);
    }
    /* below the threshold: libc's heap, nothing cached */
    bvox_memory_trim();
    unsigned char *s = big(BVOX__BIG_MIN - 64, true);
    CHECK(s != NULL);
    CHECK(all_zero(s, BVOX__BIG_MIN - 64));
    bvox__free(s, BVOX__BIG_MIN - 64);
    CHECK_EQ(bvox__big_cached(), 0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(small_request_does_not_take_a_much_bigger_buffer)
{
    bvox_memory_trim();
    void *large = big(8 * MiB, false);
    CHECK(large != NULL);
    bvox__free(large, 8 * MiB);
    void *small = big(MiB, false); /* 2 MiB mapped: an 8 MiB one is over twice that */
    CHECK(small != NULL && small != large);
    CHECK_EQ(bvox__big_cached(), 8 * MiB);
    void *again = big(7 * MiB, false);
    CHECK(again == large);
    bvox__free(small, MiB);
    bvox__free(again, 7 * MiB);
    /* the smallest buffer that fits is taken */
    CHECK_EQ(bvox__big_cached(), 10 * MiB);
    void *fit = big(MiB + 1, false);
    CHECK(fit == small);
    bvox__free(fit, MiB + 1);
    bvox_memory_trim();
    return 0;
}

TEST(cache_stays_within_its_share_of_the_budget)
{
    bvox_memory_trim();
    bvox_set_memory_budget(16 * MiB); /* an eighth: 2 MiB may stay cached */
    void *a = big(3 * MiB, false);    /* 4 MiB mapped: over the share, unmapped */
    CHECK(a != NULL);
    bvox__free(a, 3 * MiB);
    CHECK_EQ(bvox__big_cached(), 0);
    void *b = big(MiB, false), *c = big(MiB, false);
    CHECK(b && c && b != c);
    bvox__free(b, MiB);
    CHECK_EQ(bvox__big_cached(), 2 * MiB);
    bvox__free(c, MiB); /* b, the older, makes room */
    CHECK_EQ(bvox__big_cached(), 2 * MiB);
    void *d = big(MiB, false);
    CHECK(d == c);
    bvox__free(d, MiB);
    /* a lower budget trims what is cached to its share */
    bvox_set_memory_budget(8 * MiB);
    CHECK_EQ(bvox__big_cached(), 0);
    bvox_set_memory_budget(0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(cache_holds_at_most_sixteen_buffers)
{
    bvox_memory_trim();
    void *p[20];
    for (int i = 0; i < 20; i++) {
        p[i] = big(BVOX__BIG_MIN, false);
        CHECK(p[i] != NULL);
    }
    for (int i = 0; i < 20; i++) bvox__free(p[i], BVOX__BIG_MIN);
    CHECK_EQ(bvox__big_cached(), 16 * BVOX__BIG_MIN);
    /* the four freed first went back to the system: the sixteen requests
     * get the other sixteen, never one of those four */
    for (int i = 0; i < 16; i++) {
        void *q = big(BVOX__BIG_MIN, false);
        for (int k = 0; k < 4; k++) CHECK(q != p[k]);
        p[i] = q;
    }
    CHECK_EQ(bvox__big_cached(), 0);
    for (int i = 0; i < 16; i++) bvox__free(p[i], BVOX__BIG_MIN);
    bvox_memory_trim();
    return 0;
}

TEST(partly_refunded_buffer_is_freed_whole)
{
    bvox_memory_trim();
    void *p = big(4 * MiB, false);
    CHECK(p != NULL);
    bvox__budget_refund(3 * MiB); /* as the surface does with a block's unused tail */
    CHECK_EQ(bvox_memory_in_use(), MiB);
    bvox__free_charged(p, 4 * MiB, MiB);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_EQ(bvox__big_cached(), 4 * MiB);
    void *q = big(4 * MiB, false);
    CHECK(q == p);
    bvox__free(q, 4 * MiB);
    bvox_memory_trim();
    return 0;
}

/* A loop of the same operation reuses its buffers: after the first call
 * the labelling maps nothing new (the cache then holds what it freed). */
TEST(repeated_labelling_reuses_its_buffers)
{
    bvox_memory_trim();
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){160, 160, 160}, &v));
    bvox_shape ball = {.kind = BVOX_SHAPE_SPHERE, .center = {80, 80, 80}, .radius = 60};
    CHECK_OK(bvox_shape_draw(v, &ball, BVOX_CSG_UNION));
    bvox_components *c = NULL;
    CHECK_OK(bvox_components_find(v, 26, &c));
    CHECK_EQ(bvox_components_count(c), 1);
    bvox_components_destroy(c);
    size_t cached = bvox__big_cached();
    CHECK(cached > 0);
    for (int i = 0; i < 3; i++) {
        CHECK_OK(bvox_components_find(v, 26, &c));
        CHECK_EQ(bvox_components_count(c), 1);
        bvox_components_destroy(c);
        CHECK_EQ(bvox__big_cached(), cached);
    }
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    bvox_memory_trim();
    return 0;
}
