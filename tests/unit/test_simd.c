/* test_simd.c — every SIMD path the CPU supports, forced in turn with
 * bvox_simd_set, gives exactly the generic path's results: the word kernels
 * directly (every length 0..70 and large ones, every start offset within a
 * 64-byte line, nothing written outside the range) and the public count,
 * count_and, set operations and complement on volumes, with 1 and 2 threads.
 * Levels the CPU lacks (and nonsense levels) are refused. */
#include "harness.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static const bvox_simd levels[] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
#define NLEVELS (int)(sizeof levels / sizeof levels[0])

static uint64_t random_word(void)
{
    switch (harness_rand() % 8) {
    case 0: return 0;
    case 1: return ~0ull;
    case 2: return harness_rand() & harness_rand() & harness_rand(); /* sparse */
    default: return harness_rand();
    }
}

TEST(unsupported_levels_refused)
{
    bvox_simd before = bvox_simd_active();
    CHECK(before != BVOX_SIMD_AUTO);
    CHECK(bvox_simd_supported(before));
    CHECK(bvox_simd_supported(BVOX_SIMD_GENERIC));
    for (int i = 0; i < NLEVELS; i++) {
        if (bvox_simd_supported(levels[i])) continue;
        CHECK_STATUS(bvox_simd_set(levels[i]), BVOX_EUNSUPPORTED);
        CHECK(strstr(bvox_errmsg(), bvox_simd_name(levels[i])) != NULL);
        CHECK_EQ(bvox_simd_active(), before);
    }
    CHECK(!bvox_simd_supported((bvox_simd)42));
    CHECK_STATUS(bvox_simd_set((bvox_simd)42), BVOX_EUNSUPPORTED);
    CHECK_STATUS(bvox_simd_set((bvox_simd)-1), BVOX_EUNSUPPORTED);
    CHECK_EQ(bvox_simd_active(), before);
    /* AUTO picks the best supported level */
    CHECK_OK(bvox_simd_set(BVOX_SIMD_AUTO));
    bvox_simd best = bvox_simd_active();
    CHECK(bvox_simd_supported(best));
    for (int i = 0; i < NLEVELS; i++)
        if (bvox_simd_supported(levels[i])) CHECK(best >= levels[i]);
    for (int i = 0; i < NLEVELS; i++)
        if (bvox_simd_supported(levels[i])) {
            CHECK_OK(bvox_simd_set(levels[i]));
            CHECK_EQ(bvox_simd_active(), levels[i]);
        }
    CHECK_OK(bvox_simd_set(BVOX_SIMD_AUTO));
    return 0;
}

#define GUARD 8
#define CANARY 0x5a5a5a5a5a5a5a5aull

/* One length and start offset: every kernel of k against the generic one.
 * The arrays are 64-byte aligned plus `start` words, with canaries around
 * the range so an overrun (or underrun) of a vector tail shows. */
static int kernels_case(const bvox__kernels *k, size_t n, size_t start, uint64_t *a,
                        uint64_t *b, uint64_t *ref, uint64_t *got)
{
    const bvox__kernels *g = &bvox__kernels_generic;
    if (n > 65536 + 32 || start >= 8) return 1; /* the arrays' capacity */
    size_t total = n + start + 2 * GUARD;
    for (size_t i = 0; i < total; i++) {
        a[i] = random_word();
        b[i] = random_word();
    }
    uint64_t *pa = a + GUARD + start, *pb = b + GUARD + start;
    /* the generic count itself (a carry-save adder tree) against one
     * word at a time */
    uint64_t want = 0, want_and = 0;
    for (size_t i = 0; i < n; i++) {
        want += (uint64_t)__builtin_popcountll(pa[i]);
        want_and += (uint64_t)__builtin_popcountll(pa[i] & pb[i]);
    }
    CHECK_EQ(g->popcount(pa, n), want);
    CHECK_EQ(g->popcount_and(pa, pb, n), want_and);
    CHECK_EQ(k->popcount(pa, n), g->popcount(pa, n));
    CHECK_EQ(k->popcount_and(pa, pb, n), g->popcount_and(pa, pb, n));
    void (*const gops[4])(uint64_t *, const uint64_t *, size_t) = {g->op_or, g->op_and,
                                                                   g->op_andnot, g->op_xor};
    void (*const kops[4])(uint64_t *, const uint64_t *, size_t) = {k->op_or, k->op_and,
                                                                   k->op_andnot, k->op_xor};
    for (int op = 0; op < 5; op++) {
        for (size_t i = 0; i < total; i++) ref[i] = got[i] = CANARY;
        memcpy(ref + GUARD + start, pa, n * sizeof *pa);
        memcpy(got + GUARD + start, pa, n * sizeof *pa);
        if (op < 4) {
            gops[op](ref + GUARD + start, pb, n);
            kops[op](got + GUARD + start, pb, n);
        } else {
            g->op_not(ref + GUARD + start, n);
            k->op_not(got + GUARD + start, n);
        }
        if (memcmp(ref, got, total * sizeof *ref) != 0) {
            fprintf(stderr, "op %d differs at n %zu start %zu\n", op, n, start);
            return 1;
        }
    }
    return 0;
}

TEST(kernels_match_generic)
{
    static const size_t big[] = {1000, 4099, 65536 + 13};
    size_t cap = 65536 + 64 + 2 * GUARD; /* a multiple of 8 words, as aligned_alloc wants */
    uint64_t *a = aligned_alloc(64, cap * 8), *b = aligned_alloc(64, cap * 8);
    uint64_t *ref = aligned_alloc(64, cap * 8), *got = aligned_alloc(64, cap * 8);
    CHECK(a && b && ref && got);
    int tested = 0;
    for (int l = 0; l < NLEVELS; l++) {
        if (!bvox_simd_supported(levels[l])) continue;
        CHECK_OK(bvox_simd_set(levels[l]));
        const bvox__kernels *k = bvox__simd();
        for (size_t start = 0; start < 8; start++) {
            for (size_t n = 0; n <= 70; n++)
                CHECK(!kernels_case(k, n, start, a, b, ref, got));
            for (size_t i = 0; i < sizeof big / sizeof big[0]; i++)
                CHECK(!kernels_case(k, big[i], start, a, b, ref, got));
        }
        tested++;
    }
    CHECK(tested >= 1);
    CHECK_OK(bvox_simd_set(BVOX_SIMD_AUTO));
    free(a);
    free(b);
    free(ref);
    free(got);
    return 0;
}

/* Random volume of dims n, content drawn word by word (tail bits masked
 * through the public fill of an empty volume and xor). */
static bvox_volume *random_volume(const int *n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n[0], n[1], n[2]}, &v) != BVOX_OK) return NULL;
    for (size_t i = 0; i < v->nwords; i++) v->words[i] = random_word();
    for (size_t c = v->wpc - 1; c < v->nwords; c += v->wpc) v->words[c] &= v->tail_mask;
    return v;
}

/* Results of every public word operation on (a, b) under the active level. */
typedef struct results {
    int64_t count_a, count_and;
    bvox_volume *ops[4];
    bvox_volume *complement;
} results;

static int compute(const bvox_volume *a, const bvox_volume *b, results *r)
{
    r->count_a = bvox_volume_count(a);
    r->count_and = bvox_volume_count_and(a, b);
    for (int op = 0; op < 4; op++) {
        CHECK_OK(bvox_volume_copy(a, &r->ops[op]));
        CHECK_OK(bvox_csg_apply(r->ops[op], (bvox_csg_op)op, b, NULL));
        CHECK_OK(bvox_volume_check(r->ops[op]));
    }
    CHECK_OK(bvox_volume_copy(a, &r->complement));
    bvox_volume_complement(r->complement);
    CHECK_OK(bvox_volume_check(r->complement));
    return 0;
}

static void release(results *r)
{
    for (int op = 0; op < 4; op++) bvox_volume_destroy(r->ops[op]);
    bvox_volume_destroy(r->complement);
}

TEST(public_ops_match_generic)
{
    /* small and odd sizes, and sizes that split over two threads (set ops
     * from 8 chunks of 32768 words, counts from 8 chunks of 65536 words) */
    static const int sizes[][3] = {{1, 1, 1},    {3, 5, 63},   {7, 3, 64},
                                   {5, 5, 65},   {9, 11, 130}, {13, 7, 1000},
                                   {1025, 513, 1}, {301, 299, 130}};
    int saved = bvox_threads();
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        bvox_volume *a = random_volume(sizes[s]), *b = random_volume(sizes[s]);
        CHECK(a && b);
        results want;
        CHECK_OK(bvox_simd_set(BVOX_SIMD_GENERIC));
        bvox_set_threads(1);
        CHECK(!compute(a, b, &want));
        int64_t plain = 0; /* the generic path itself against the compiler's popcount */
        for (size_t i = 0; i < a->nwords; i++) plain += __builtin_popcountll(a->words[i]);
        CHECK_EQ(want.count_a, plain);
        for (int threads = 1; threads <= 2; threads++) {
            bvox_set_threads(threads);
            for (int l = 0; l < NLEVELS; l++) {
                if (!bvox_simd_supported(levels[l])) continue;
                CHECK_OK(bvox_simd_set(levels[l]));
                results got;
                CHECK(!compute(a, b, &got));
                int same = got.count_a == want.count_a && got.count_and == want.count_and &&
                           bvox_volume_equal(got.complement, want.complement);
                for (int op = 0; op < 4; op++)
                    same = same && bvox_volume_equal(got.ops[op], want.ops[op]);
                release(&got);
                if (!same) {
                    fprintf(stderr, "%s, %d threads, size %zu differs from generic\n",
                            bvox_simd_name(levels[l]), threads, s);
                    return 1;
                }
            }
        }
        release(&want);
        bvox_volume_destroy(a);
        bvox_volume_destroy(b);
    }
    bvox_set_threads(saved);
    CHECK_OK(bvox_simd_set(BVOX_SIMD_AUTO));
    return 0;
}
