/* test_csg.c — set operations against the byte-per-voxel reference on random
 * volumes at awkward sizes (nz = 1, 63, 64, 65, 130; odd nx, ny): all five
 * operations, offsets (negative, z offsets that are not multiples of 64, far
 * outside), src bigger or smaller than dst, src == dst, complement and
 * count_and, with one and two threads, checking the invariant each time. */
#include "harness.h"
#include "ref/voxref.h"

#include <stdint.h>
#include <string.h>

static const int sizes[][3] = {{7, 5, 1},   {5, 9, 63},  {9, 7, 64},
                               {3, 11, 65}, {11, 3, 130}, {1, 1, 129}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

static const char *op_name(int op)
{
    static const char *names[] = {"union", "intersection", "difference", "xor", "replace"};
    return names[op];
}

/* dst OP= src at offset, for the library and the reference, then compare
 * voxel by voxel (voxref_matches also runs bvox_volume_check). */
static int check_op(const int *dn, const int *sn, int op, const int *off, unsigned density)
{
    voxref *rd = voxref_create(dn[0], dn[1], dn[2]);
    voxref *rs = voxref_create(sn[0], sn[1], sn[2]);
    CHECK(rd && rs);
    voxref_random(rd, 1, density, harness_rand);
    voxref_random(rs, 1, 2, harness_rand);
    bvox_volume *d = voxref_to_volume(rd), *s = voxref_to_volume(rs);
    CHECK(d && s);
    int32_t o[3] = {off[0], off[1], off[2]};
    CHECK_OK(bvox_csg_apply(d, (bvox_csg_op)op, s, o));
    voxref_csg(rd, (bvox_csg_op)op, rs, off);
    int ok = voxref_matches(rd, d) && bvox_volume_count(d) == voxref_count(rd);
    if (!ok)
        fprintf(stderr, "%s: dst %dx%dx%d src %dx%dx%d offset (%d,%d,%d)\n", op_name(op),
                dn[0], dn[1], dn[2], sn[0], sn[1], sn[2], off[0], off[1], off[2]);
    /* src is borrowed: unchanged */
    ok = ok && voxref_matches(rs, s);
    bvox_volume_destroy(d);
    bvox_volume_destroy(s);
    voxref_destroy(rd);
    voxref_destroy(rs);
    return ok ? 0 : 1;
}

TEST(same_size_all_ops)
{
    static const int zero[3] = {0, 0, 0};
    for (int i = 0; i < NSIZES; i++)
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
            CHECK(!check_op(sizes[i], sizes[i], op, zero, 2));
            CHECK(!check_op(sizes[i], sizes[i], op, zero, 9));
        }
    return 0;
}

TEST(offsets_and_size_mismatch)
{
    static const int zoffs[] = {-131, -70, -65, -64, -63, -1, 0, 1, 37, 63, 64, 65, 129};
    for (int i = 0; i < NSIZES; i++)
        for (int k = 0; k < NSIZES; k++) {
            const int *dn = sizes[i], *sn = sizes[k];
            for (int op = 0; op <= BVOX_CSG_REPLACE; op++)
                for (int rep = 0; rep < 3; rep++) {
                    int off[3];
                    off[0] = (int)(harness_rand() % (uint64_t)(dn[0] + sn[0] + 1)) - sn[0];
                    off[1] = (int)(harness_rand() % (uint64_t)(dn[1] + sn[1] + 1)) - sn[1];
                    off[2] = zoffs[harness_rand() % (sizeof zoffs / sizeof zoffs[0])];
                    CHECK(!check_op(dn, sn, op, off, 2));
                }
        }
    /* src bigger than dst on every axis, placed so that it covers dst */
    static const int big[3] = {13, 12, 200}, small[3] = {5, 7, 65};
    static const int cover[3] = {-3, -2, -70}, inside[3] = {4, 3, 71};
    for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
        CHECK(!check_op(small, big, op, cover, 2));
        CHECK(!check_op(big, small, op, inside, 3));
    }
    return 0;
}

TEST(far_offsets)
{
    /* src entirely outside dst (incl. offsets near the int32 limits): nothing
     * changes, except intersection clears dst, and nothing overflows */
    static const int offs[][3] = {{100, 0, 0},       {0, -100, 0},        {0, 0, 130},
                                  {0, 0, -131},      {INT32_MAX, 0, 0},   {0, INT32_MIN + 1000, 0},
                                  {0, 0, INT32_MAX}, {0, 0, INT32_MIN + 1000}};
    static const int dn[3] = {9, 7, 130}, sn[3] = {5, 6, 129};
    for (size_t i = 0; i < sizeof offs / sizeof offs[0]; i++)
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) CHECK(!check_op(dn, sn, op, offs[i], 2));
    /* INT32_MIN itself (the reference's int arithmetic cannot take it) */
    voxref *r = voxref_create(dn[0], dn[1], dn[2]);
    voxref_random(r, 1, 2, harness_rand);
    for (int axis = 0; axis < 3; axis++)
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
            bvox_volume *d = voxref_to_volume(r), *s = voxref_to_volume(r);
            int32_t o[3] = {0, 0, 0};
            o[axis] = INT32_MIN;
            CHECK_OK(bvox_csg_apply(d, (bvox_csg_op)op, s, o));
            CHECK_OK(bvox_volume_check(d));
            CHECK_EQ(bvox_volume_count(d), op == BVOX_CSG_INTERSECTION ? 0 : voxref_count(r));
            bvox_volume_destroy(d);
            bvox_volume_destroy(s);
        }
    voxref_destroy(r);
    return 0;
}

TEST(self_operand)
{
    static const int offs[][3] = {{0, 0, 0}, {1, 0, 0}, {0, -2, 0}, {0, 0, 65}, {-1, 1, -3}};
    for (int i = 0; i < NSIZES; i++)
        for (size_t k = 0; k < sizeof offs / sizeof offs[0]; k++)
            for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
                const int *n = sizes[i];
                voxref *r = voxref_create(n[0], n[1], n[2]);
                voxref_random(r, 1, 2, harness_rand);
                bvox_volume *v = voxref_to_volume(r);
                CHECK(v != NULL);
                int32_t o[3] = {offs[k][0], offs[k][1], offs[k][2]};
                CHECK_OK(bvox_csg_apply(v, (bvox_csg_op)op, v, o));
                voxref *copy = voxref_copy(r); /* the reference reads src as it was */
                voxref_csg(r, (bvox_csg_op)op, copy, offs[k]);
                if (!voxref_matches(r, v)) {
                    fprintf(stderr, "self %s offset %zu size %d\n", op_name(op), k, i);
                    return 1;
                }
                bvox_volume_destroy(v);
                voxref_destroy(r);
                voxref_destroy(copy);
            }
    return 0;
}

TEST(complement_and_count_and)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *n = sizes[i];
        voxref *ra = voxref_create(n[0], n[1], n[2]), *rb = voxref_create(n[0], n[1], n[2]);
        voxref_random(ra, 1, 3, harness_rand);
        voxref_random(rb, 1, 2, harness_rand);
        bvox_volume *a = voxref_to_volume(ra), *b = voxref_to_volume(rb);
        /* count_and against the reference intersection */
        voxref *both = voxref_copy(ra);
        static const int zero[3] = {0, 0, 0};
        voxref_csg(both, BVOX_CSG_INTERSECTION, rb, zero);
        CHECK_EQ(bvox_volume_count_and(a, b), voxref_count(both));
        CHECK_EQ(bvox_volume_count_and(a, a), voxref_count(ra));
        /* complement: reference, invariant (tail bits stay zero), involution */
        bvox_volume_complement(a);
        voxref_complement(ra);
        CHECK(voxref_matches(ra, a));
        CHECK_EQ(bvox_volume_count(a), voxref_count(ra));
        bvox_volume_complement(a);
        voxref_complement(ra);
        CHECK(voxref_matches(ra, a));
        /* complement of an empty volume is full, to the last valid bit */
        bvox_volume_fill(b, 0);
        bvox_volume_complement(b);
        CHECK_OK(bvox_volume_check(b));
        CHECK_EQ(bvox_volume_count(b), (int64_t)n[0] * n[1] * n[2]);
        bvox_volume_destroy(a);
        bvox_volume_destroy(b);
        voxref_destroy(ra);
        voxref_destroy(rb);
        voxref_destroy(both);
    }
    /* different dimensions: -1 */
    bvox_volume *a, *b;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 4, 5}, &a));
    CHECK_OK(bvox_volume_create((bvox_dims){3, 4, 6}, &b));
    CHECK_EQ(bvox_volume_count_and(a, b), -1);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return 0;
}

TEST(bad_op_rejected)
{
    voxref *r = voxref_create(5, 5, 70);
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    CHECK_STATUS(bvox_csg_apply(v, (bvox_csg_op)5, v, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_csg_apply(v, (bvox_csg_op)-1, v, NULL), BVOX_EINVAL);
    CHECK(voxref_matches(r, v));
    bvox_volume_destroy(v);
    voxref_destroy(r);
    return 0;
}

/* Volumes big enough to be split over threads (flat ops: at least 4 chunks
 * of 32768 words per thread, chunk ends not on column ends; counts: 4 chunks
 * of 65536 words per thread; shifted: many rows), with one and two threads. */
TEST(large_threaded)
{
    static const int flat[][3] = {{1025, 513, 1}, {301, 299, 130}};
    static const int n[3] = {151, 149, 130}, m[3] = {149, 151, 129};
    static const int zero[3] = {0, 0, 0}, off[3] = {-3, 5, 67};
    int saved = bvox_threads();
    for (int threads = 1; threads <= 2; threads++) {
        bvox_set_threads(threads);
        for (int op = 0; op <= BVOX_CSG_REPLACE; op++) {
            CHECK(!check_op(flat[0], flat[0], op, zero, 2));
            CHECK(!check_op(n, m, op, off, 2));
        }
        CHECK(!check_op(flat[1], flat[1], BVOX_CSG_XOR, zero, 2));
        for (int i = 0; i < 2; i++) {
            const int *f = flat[i];
            voxref *r = voxref_create(f[0], f[1], f[2]), *q = voxref_create(f[0], f[1], f[2]);
            voxref_random(r, 1, 2, harness_rand);
            voxref_random(q, 1, 2, harness_rand);
            bvox_volume *v = voxref_to_volume(r), *w = voxref_to_volume(q);
            voxref *both = voxref_copy(r);
            voxref_csg(both, BVOX_CSG_INTERSECTION, q, zero);
            CHECK_EQ(bvox_volume_count_and(v, w), voxref_count(both));
            bvox_volume_complement(v);
            voxref_complement(r);
            CHECK(voxref_matches(r, v));
            CHECK_EQ(bvox_volume_count(v), voxref_count(r));
            bvox_volume_destroy(v);
            bvox_volume_destroy(w);
            voxref_destroy(r);
            voxref_destroy(q);
            voxref_destroy(both);
        }
    }
    bvox_set_threads(saved);
    return 0;
}
