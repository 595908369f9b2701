/* test_measure_part.c — bvox_measure_part / bvox_measure_from_sums (the
 * per-chunk measure sums of bvox.dask): the parts of a partition, each with
 * its one-voxel high-side overlap, add up to the whole volume's scan exactly
 * (hand-counted 2x2x2 block cut into 8 single voxels; random volumes at
 * awkward sizes and cuts, with moments far from the origin), and the sums
 * give bvox_measure's physical measures. */
#include "harness.h"
#include "internal.h"
#include "measure/measure.h"

#include <string.h>

static __int128 wide(bvox_int128 v)
{
    return (__int128)(((unsigned __int128)(uint64_t)v.hi << 64) | v.lo);
}

static void add(bvox_measure_sums *acc, const bvox_measure_sums *p, int *any)
{
    acc->count += p->count;
    for (int a = 0; a < 3; a++) {
        __int128 s = wide(acc->s[a]) + wide(p->s[a]);
        acc->s[a].hi = (int64_t)(s >> 64), acc->s[a].lo = (uint64_t)s;
    }
    for (int k = 0; k < 6; k++) {
        __int128 s = wide(acc->ss[k]) + wide(p->ss[k]);
        acc->ss[k].hi = (int64_t)(s >> 64), acc->ss[k].lo = (uint64_t)s;
    }
    acc->euler += p->euler;
    for (int c = 0; c < 7; c++) acc->trans[c] += p->trans[c];
    if (p->count) {
        for (int a = 0; a < 3; a++) {
            if (!*any || p->bbox[a] < acc->bbox[a]) acc->bbox[a] = p->bbox[a];
            if (!*any || p->bbox[a + 3] > acc->bbox[a + 3]) acc->bbox[a + 3] = p->bbox[a + 3];
        }
        *any = 1;
    }
}

/* The sums of vol cut at the given planes (cuts[a] ends with the size). */
static int sum_parts(const bvox_volume *vol, const int32_t *cuts[3], const int ncut[3],
                     bvox_measure_sums *acc)
{
    memset(acc, 0, sizeof *acc);
    int any = 0;
    const int32_t n[3] = {vol->nx, vol->ny, vol->nz};
    for (int i = 0; i < ncut[0]; i++)
        for (int j = 0; j < ncut[1]; j++)
            for (int k = 0; k < ncut[2]; k++) {
                const int ix[3] = {i, j, k};
                int32_t lo[3], hi[3], core[3];
                for (int a = 0; a < 3; a++) {
                    lo[a] = ix[a] ? cuts[a][ix[a] - 1] : 0;
                    core[a] = cuts[a][ix[a]] - lo[a];
                    hi[a] = cuts[a][ix[a]] < n[a] ? cuts[a][ix[a]] + 1 : n[a];
                }
                bvox_volume *part = NULL;
                bvox_box b = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
                CHECK_OK(bvox_volume_crop(vol, b, &part));
                bvox_measure_sums s;
                bvox_status st = bvox_measure_part(part, core, lo, &s);
                bvox_volume_destroy(part);
                CHECK_OK(st);
                add(acc, &s, &any);
            }
    return 0;
}

static int same_as_scan(const bvox_measure_sums *m, const bvox__scan *s)
{
    CHECK_EQ(m->count, s->count);
    for (int a = 0; a < 3; a++) CHECK(wide(m->s[a]) == s->s[a]);
    for (int k = 0; k < 6; k++) CHECK(wide(m->ss[k]) == s->ss[k]);
    CHECK_EQ(m->euler, s->euler);
    for (int c = 0; c < 7; c++) CHECK_EQ(m->trans[c], s->trans[c]);
    if (s->count)
        for (int a = 0; a < 6; a++) CHECK_EQ(m->bbox[a], s->bbox[a]);
    return 0;
}

TEST(eight_single_voxels)
{
    /* a full 2x2x2 block cut into its 8 voxels: one cube, Euler 1, 24
     * exposed faces (8 along each axis), sum of x = 4 */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
    bvox_volume_fill(v, 1);
    const int32_t c2[2] = {1, 2};
    const int32_t *cuts[3] = {c2, c2, c2};
    const int ncut[3] = {2, 2, 2};
    bvox_measure_sums m;
    int r = sum_parts(v, cuts, ncut, &m);
    bvox_volume_destroy(v);
    if (r) return r;
    CHECK_EQ(m.count, 8);
    CHECK_EQ(m.euler, 1);
    CHECK_EQ(m.trans[0], 8);
    CHECK_EQ(m.trans[1], 8);
    CHECK_EQ(m.trans[2], 8);
    CHECK(wide(m.s[0]) == 4 && wide(m.ss[0]) == 4 && wide(m.ss[3]) == 2);
    CHECK_EQ(m.bbox[3], 2);
    return 0;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint64_t next(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return rng_state;
}

TEST(random_partitions_add_up)
{
    static const int32_t dims[][3] = {{13, 11, 70}, {9, 17, 130}, {5, 3, 1}, {40, 7, 65}};
    for (int d = 0; d < 4; d++) {
        bvox_volume *v = NULL;
        CHECK_OK(bvox_volume_create((bvox_dims){dims[d][0], dims[d][1], dims[d][2]}, &v));
        for (int32_t x = 0; x < dims[d][0]; x++)
            for (int32_t y = 0; y < dims[d][1]; y++)
                for (int32_t z = 0; z < dims[d][2]; z++)
                    bvox_volume_set(v, x, y, z, next() % 5 < 2);
        bvox__scan whole;
        CHECK_OK(bvox__measure_scan(v, &whole));
        /* cuts at 1, a third and two thirds (where they fit), and the end */
        int32_t c[3][4];
        int ncut[3];
        const int32_t *cuts[3];
        for (int a = 0; a < 3; a++) {
            int32_t n = dims[d][a], k = 0;
            for (int32_t p = 1; p < n && k < 3; p = p == 1 ? (n / 3 > 1 ? n / 3 : 2) : p + n / 3)
                c[a][k++] = p;
            c[a][k++] = n;
            ncut[a] = k;
            cuts[a] = c[a];
        }
        bvox_measure_sums m;
        int r = sum_parts(v, cuts, ncut, &m);
        if (!r) r = same_as_scan(&m, &whole);
        if (!r) {
            /* the measures from the sums are bvox_measure's (topology aside) */
            bvox_volume_set_spacing(v, 0.5, 0.7, 1.3, "mm");
            bvox_geometry g = *bvox_volume_geometry(v);
            g.origin[0] = 1e4; /* moments shift with the origin */
            CHECK_OK(bvox_volume_set_geometry(v, &g));
            bvox_measures got, want;
            CHECK_OK(bvox_measure_from_sums(&m, &g, &got));
            CHECK_OK(bvox_measure(v, &want));
            CHECK_EQ(got.count, want.count);
            CHECK(got.area == want.area && got.volume == want.volume);
            for (int a = 0; a < 3; a++) {
                CHECK(got.centroid[a] == want.centroid[a]);
                CHECK(got.faces[a] == want.faces[a]);
            }
            for (int k = 0; k < 9; k++) CHECK(got.covariance[k] == want.covariance[k]);
            CHECK_EQ(got.euler, want.euler);
            CHECK_EQ(got.components, 0); /* topology is the caller's */
        }
        bvox_volume_destroy(v);
        if (r) return r;
    }
    return 0;
}

TEST(far_offsets_are_exact)
{
    /* moments of a part placed at 2^30 in every axis need 128 bits */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 3, 3}, &v));
    bvox_volume_fill(v, 1);
    const int32_t core[3] = {3, 3, 3}, off[3] = {1 << 30, 1 << 30, 1 << 30};
    bvox_measure_sums m;
    CHECK_OK(bvox_measure_part(v, core, off, &m));
    bvox_volume_destroy(v);
    __int128 o = (__int128)1 << 30, sx = 0, sxx = 0;
    for (int i = 0; i < 3; i++) sx += 9 * (o + i), sxx += 9 * (o + i) * (o + i);
    CHECK(wide(m.s[0]) == sx && wide(m.ss[0]) == sxx);
    CHECK_EQ(m.bbox[0], 1 << 30);
    return 0;
}

TEST(bad_core)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &v));
    const int32_t off[3] = {0, 0, 0}, two_less[3] = {2, 4, 4}, zero[3] = {4, 0, 4};
    bvox_measure_sums m;
    CHECK_STATUS(bvox_measure_part(v, two_less, off, &m), BVOX_EINVAL);
    CHECK_STATUS(bvox_measure_part(v, zero, off, &m), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}
