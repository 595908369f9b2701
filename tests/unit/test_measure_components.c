/* test_measure_components.c — bvox_measure_components: every component
 * measured alone equals bvox_measure of a volume holding only it, on random
 * volumes for each connectivity and on components that share a bounding box
 * and a size (the fallback of the cut-out). */
#include "harness.h"
#include "ref/voxref.h"

#include <string.h>

static bvox_volume *make(int nx, int ny, int nz)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){nx, ny, nz}, &v)) return NULL;
    return v;
}

static int rel_near(double a, double b, double rel)
{
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)) + 1e-12;
}

/* Every component measured alone must equal bvox_measure of a volume holding
 * only it (cut with keep(i+1) minus keep(i)), bbox included. */
static int check_components(const bvox_volume *v, int conn)
{
    bvox_measures *per = NULL;
    int64_t n = -1;
    CHECK_OK(bvox_measure_components(v, conn, &per, &n));
    bvox_components *comps;
    CHECK_OK(bvox_components_find(v, conn, &comps));
    CHECK_EQ(n, bvox_components_count(comps));
    bvox_volume *prev = NULL;
    CHECK_OK(bvox_components_keep(comps, 0, &prev));
    for (int64_t i = 0; i < n; i++) {
        bvox_volume *upto, *one;
        CHECK_OK(bvox_components_keep(comps, i + 1, &upto));
        CHECK_OK(bvox_volume_copy(upto, &one));
        CHECK_OK(bvox_csg_apply(one, BVOX_CSG_DIFFERENCE, prev, NULL));
        bvox_volume_destroy(prev);
        prev = upto;
        bvox_measures m;
        CHECK_OK(bvox_measure(one, &m));
        bvox_volume_destroy(one);
        const bvox_measures *p = &per[i];
        CHECK_EQ(p->count, bvox_components_get(comps, i)->voxels);
        CHECK_EQ(p->count, m.count);
        CHECK(memcmp(&p->bbox, &m.bbox, sizeof m.bbox) == 0);
        CHECK_EQ(p->euler, m.euler);
        CHECK_EQ(p->cavities, m.cavities);
        CHECK_EQ(p->components, 1);
        for (int a = 0; a < 3; a++) CHECK_EQ(p->faces[a], m.faces[a]);
        CHECK(rel_near(p->area, m.area, 1e-12));
        for (int a = 0; a < 3; a++) CHECK_NEAR(p->centroid[a], m.centroid[a], 1e-9);
        for (int a = 0; a < 9; a++) CHECK_NEAR(p->covariance[a], m.covariance[a], 1e-9);
    }
    bvox_volume_destroy(prev);
    bvox_components_destroy(comps);
    bvox_free(per);
    return 0;
}

TEST(components_random)
{
    for (int conn = 6; conn <= 26; conn += conn == 6 ? 12 : 8) {
        voxref *r = voxref_create(13, 9, 70);
        voxref_random(r, 3, 10, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        voxref_destroy(r);
        CHECK_OK(bvox_volume_set_spacing(v, 1, 2, 0.5, NULL));
        CHECK(!check_components(v, conn));
        bvox_volume_destroy(v);
    }
    return 0;
}

/* Two mirror-image paths with the same box and size, plus a blob inside
 * their box: the crop cannot tell them apart by size and box alone. */
TEST(components_same_box)
{
    bvox_volume *v = make(9, 9, 9);
    CHECK(v);
    for (int i = 0; i <= 6; i++) {
        bvox_volume_set(v, i, 0, 0, 1), bvox_volume_set(v, 6, 0, i, 1), bvox_volume_set(v, 6, i, 6, 1);
        bvox_volume_set(v, 6 - i, 6, 0, 1), bvox_volume_set(v, 0, 6, i, 1), bvox_volume_set(v, 0, 6 - i, 6, 1);
    }
    bvox_volume_fill_box(v, (bvox_box){2, 2, 2, 5, 5, 5}, 1);
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK_EQ(m.components, 3);
    CHECK(!check_components(v, 26));
    bvox_measures *per;
    int64_t n;
    CHECK_OK(bvox_measure_components(v, 26, &per, &n));
    CHECK_EQ(n, 3);
    CHECK_EQ(per[0].count, 27);
    CHECK_EQ(per[1].count, 19);
    CHECK_EQ(per[2].count, 19);
    bvox_free(per);
    CHECK_STATUS(bvox_measure_components(v, 7, &per, &n), BVOX_EINVAL);
    CHECK(per == NULL && n == 0);
    bvox_volume_destroy(v);
    return 0;
}

