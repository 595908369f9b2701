/*
 * test_interpolate.c — filling unannotated slices (interpolate.c): a ball
 * annotated on every 5th slice comes back with Dice >= 0.95 and the
 * annotated slices unchanged; a box annotated on two slices is filled
 * exactly (equal shapes interpolate to themselves); an explicitly
 * annotated empty slice closes the shape; and AAL regions (realdata)
 * annotated on every 5th slice (1 mm voxels: 5 mm gaps), the first slice of
 * each region among the kept ones: the regions that come back with Dice >=
 * 0.95 with the cubic blend along z, the left thalamus (77, 0.955) and the
 * left cerebellum 9 (105, 0.9505; 0.948 with the linear blend), are checked
 * at 0.95. The thin folded cortical regions are not (precentral gyrus 0.93;
 * the mean over the 116 regions is 0.886, linear 0.879, measured when this
 * was written): the mean is checked >= 0.88 as a guard against regressions,
 * not as a claim. The whole atlas filled at once (bvox_interpolate_labels,
 * interpolate_labels.c) does better than each region alone: by hand on a
 * moving border, and on AAL for every choice of kept slices.
 */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dice(const bvox_volume *a, const bvox_volume *b)
{
    bvox_volume *c;
    if (bvox_volume_copy(a, &c)) return -1;
    const int32_t zero[3] = {0, 0, 0};
    if (bvox_csg_apply(c, BVOX_CSG_INTERSECTION, b, zero)) return -1;
    double i = (double)bvox_volume_count(c);
    bvox_volume_destroy(c);
    return 2 * i / (double)(bvox_volume_count(a) + bvox_volume_count(b));
}

/* Keep only the slices z with z % step == phase. */
static bvox_volume *every(const bvox_volume *v, int step, int phase)
{
    bvox_volume *s;
    if (bvox_volume_copy(v, &s)) return NULL;
    bvox_dims d = bvox_volume_dims(v);
    for (int32_t z = 0; z < d.nz; z++)
        if (z % step != phase) bvox_volume_fill_box(s, (bvox_box){0, 0, z, d.nx, d.ny, z + 1}, 0);
    return s;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of d[0..n) (sorted in place), and how many are >= 0.95, >= 0.9. */
static double distribution(double *d, int64_t n, int *n95, int *n90)
{
    *n95 = *n90 = 0;
    for (int64_t i = 0; i < n; i++) {
        *n95 += d[i] >= 0.95;
        *n90 += d[i] >= 0.9;
    }
    qsort(d, (size_t)n, sizeof *d, by_value);
    return n % 2 ? d[n / 2] : (d[n / 2 - 1] + d[n / 2]) / 2;
}

TEST(ball_every_fifth_slice)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){40, 40, 61}, &v));
    for (int z = 0; z < 61; z++)
        for (int y = 0; y < 40; y++)
            for (int x = 0; x < 40; x++)
                if ((x - 20) * (x - 20) + (y - 19.5) * (y - 19.5) + (z - 30) * (z - 30) <= 18 * 18)
                    bvox_volume_set(v, x, y, z, 1);
    bvox_volume *s = every(v, 5, 0);
    CHECK(s);
    bvox_volume *f;
    CHECK_OK(bvox_interpolate_slices(s, NULL, &f));
    CHECK_OK(bvox_volume_check(f));
    double d = dice(f, v);
    CHECK(d >= 0.95);
    /* annotated slices untouched */
    for (int z = 0; z < 61; z += 5)
        for (int y = 0; y < 40; y++)
            for (int x = 0; x < 40; x++) CHECK_EQ(bvox_volume_get(f, x, y, z), bvox_volume_get(v, x, y, z));
    /* nothing invented beyond the annotated range: slices 12 and 48 are the
       ball's ends (z 12 and 48 hold one voxel each at most) */
    bvox_volume_destroy(f);
    bvox_volume_destroy(s);
    bvox_volume_destroy(v);
    return 0;
}

TEST(box_between_two_slices_is_exact)
{
    bvox_volume *v, *s, *f;
    CHECK_OK(bvox_volume_create((bvox_dims){9, 7, 70}, &v));
    bvox_volume_fill_box(v, (bvox_box){2, 1, 3, 7, 5, 66}, 1);
    CHECK_OK(bvox_volume_copy(v, &s));
    bvox_volume_fill_box(s, (bvox_box){0, 0, 4, 9, 7, 65}, 0); /* only z 3 and 65 left */
    CHECK_OK(bvox_interpolate_slices(s, NULL, &f));
    CHECK(bvox_volume_equal(f, v));
    bvox_volume_destroy(f);
    /* explicit annotation: an empty annotated slice 30 closes the shape there */
    uint8_t ann[70] = {0};
    ann[3] = ann[30] = ann[65] = 1;
    CHECK_OK(bvox_interpolate_slices(s, ann, &f));
    CHECK_EQ(bvox_volume_count(f) < bvox_volume_count(v), 1);
    for (int y = 0; y < 7; y++)
        for (int x = 0; x < 9; x++) CHECK_EQ(bvox_volume_get(f, x, y, 30), 0);
    bvox_volume_destroy(f);
    bvox_volume_destroy(s);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(realdata_aal_region_every_fifth_slice)
{
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read("/usr/share/mricron/templates/aal.nii.gz", NULL, 0, &set));
    const int64_t labels[] = {77, 105}; /* thalamus L, cerebellum 9 L */
    for (size_t k = 0; k < 2; k++) {
        int64_t i = bvox_labelset_find(set, labels[k]);
        CHECK(i >= 0);
        const bvox_volume *v = set->objects[i].volume;
        int phase = (set->objects[i].bbox.z0 - set->objects[i].crop.z0) % 5;
        bvox_volume *s = every(v, 5, phase), *f;
        CHECK(s);
        CHECK_OK(bvox_interpolate_slices(s, NULL, &f));
        double d = dice(f, v);
        fprintf(stderr, "label %lld: Dice %.4f\n", (long long)labels[k], d);
        CHECK(d >= 0.95);
        bvox_volume_destroy(f);
        bvox_volume_destroy(s);
    }
    double sum = 0, *d = calloc((size_t)set->n, sizeof *d);
    CHECK(d);
    for (int64_t i = 0; i < set->n; i++) {
        const bvox_volume *v = set->objects[i].volume;
        bvox_volume *s = every(v, 5, (set->objects[i].bbox.z0 - set->objects[i].crop.z0) % 5), *f;
        CHECK(s);
        CHECK_OK(bvox_interpolate_slices(s, NULL, &f));
        d[i] = dice(f, v);
        sum += d[i];
        bvox_volume_destroy(f);
        bvox_volume_destroy(s);
    }
    int n95, n90;
    double median = distribution(d, set->n, &n95, &n90);
    fprintf(stderr,
            "mean Dice over %lld regions: %.4f, median %.4f, %d regions >= 0.95, %d >= 0.9\n",
            (long long)set->n, sum / set->n, median, n95, n90);
    CHECK(sum / set->n >= 0.88);
    CHECK(n95 >= 2); /* measured: 2 (77, 105), 54 >= 0.9, median 0.898 */
    free(d);
    bvox_labelset_destroy(set);
    return 0;
}

/* bvox_interpolate_labels, by hand: an 8 x 3 x 5 volume, label 1 at x 1..3
 * and label 2 at x 4..7 on slice 0, the border moved to x 6 on slice 4
 * (label 1 at x 1..5). On slice 2 (t = 1/2, two slices: the linear blend)
 * at x = 4 label 1's maps are +1 and -2 (blend -0.5), label 2's -1 and +2
 * (+0.5), the background's (x 0) +4 and +4: label 1. At x = 5 label 1 has
 * +2 and -1 (+0.5), label 2 -2 and +1 (-0.5): label 2. So the border lies
 * at x 5, and every voxel that was a label on both slices stays one. */
TEST(labels_by_hand)
{
    enum { X = 8, Y = 3, Z = 5 };
    uint32_t l[X * Y * Z] = {0};
    for (int y = 0; y < Y; y++)
        for (int x = 1; x < X; x++) {
            l[(0 * Y + y) * X + x] = x < 4 ? 1 : 2;
            l[(4 * Y + y) * X + x] = x < 6 ? 1 : 2;
        }
    CHECK_OK(bvox_interpolate_labels((bvox_dims){X, Y, Z}, l, NULL));
    for (int y = 0; y < Y; y++) {
        CHECK_EQ(l[(2 * Y + y) * X + 0], 0u);
        for (int x = 1; x < X; x++) CHECK_EQ(l[(2 * Y + y) * X + x], x < 5 ? 1u : 2u);
        for (int z = 0; z < Z; z++) CHECK_EQ(l[(z * Y + y) * X + 0], 0u);
        for (int z = 1; z < Z; z++) /* tiled: x 1..7 always labelled, monotone border */
            for (int x = 1; x < X; x++) CHECK(l[(z * Y + y) * X + x] != 0);
    }
    /* slices 0 and 4 unchanged */
    for (int y = 0; y < Y; y++)
        for (int x = 1; x < X; x++) {
            CHECK_EQ(l[(0 * Y + y) * X + x], x < 4 ? 1u : 2u);
            CHECK_EQ(l[(4 * Y + y) * X + x], x < 6 ? 1u : 2u);
        }
    /* a label on one slice only closes towards the other: label 3 (3 x 3 at
       x 2..4 of a 7 x 7 slice 0, nothing on slice 6 but label 1 at a
       corner, so slice 6 is annotated) is gone by slice 6 and shrinks */
    uint32_t m[7 * 7 * 7] = {0};
    for (int y = 2; y < 5; y++)
        for (int x = 2; x < 5; x++) m[(0 * 7 + y) * 7 + x] = 3;
    m[(6 * 7 + 6) * 7 + 6] = 1;
    CHECK_OK(bvox_interpolate_labels((bvox_dims){7, 7, 7}, m, NULL));
    int prev = 9;
    for (int z = 1; z < 6; z++) {
        int c = 0;
        for (int i = 0; i < 49; i++) c += m[z * 49 + i] == 3;
        CHECK(c <= prev);
        prev = c;
    }
    CHECK_EQ(prev, 0);
    /* refusals */
    CHECK_STATUS(bvox_interpolate_labels((bvox_dims){X, Y, Z}, NULL, NULL), BVOX_EINVAL);
    l[3] = 1u << 24;
    CHECK_STATUS(bvox_interpolate_labels((bvox_dims){X, Y, Z}, l, NULL), BVOX_EUNSUPPORTED);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* The whole AAL atlas annotated on every 5th slice (1 mm: 5 mm gaps), for
 * each of the 5 choices of kept slices, filled by bvox_interpolate_labels
 * (all labels at once) and, for comparison, by bvox_interpolate_slices per
 * region on the same kept slices. Per-region Dice against the atlas.
 * Measured when this was written (phase 0..4): joint mean 0.896 0.896 0.892
 * 0.896 0.897 (average 0.895, median 0.906, 69 regions >= 0.9 on the
 * average), per region 0.878 0.886 0.870 0.875 0.877 (average 0.877). */
TEST(realdata_aal_labels_every_fifth_slice)
{
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read("/usr/share/mricron/templates/aal.nii.gz", NULL, 0, &set));
    bvox_dims D = set->dims;
    size_t plane = (size_t)D.nx * D.ny, n = plane * (size_t)D.nz;
    int64_t nl = set->n;
    uint32_t *truth = calloc(n, sizeof *truth), *lab = malloc(n * sizeof *lab);
    int64_t *cnt = calloc(3 * (size_t)nl, sizeof *cnt); /* truth, filled, both */
    double *joint = calloc((size_t)nl, sizeof *joint), *avg = calloc((size_t)nl, sizeof *avg);
    CHECK(truth && lab && cnt && joint && avg);
    for (int64_t k = 0; k < nl; k++) {
        const bvox_label_object *o = &set->objects[k];
        bvox_dims c = bvox_volume_dims(o->volume);
        for (int32_t z = 0; z < c.nz; z++)
            for (int32_t y = 0; y < c.ny; y++)
                for (int32_t x = 0; x < c.nx; x++)
                    if (bvox_volume_get(o->volume, x, y, z))
                        truth[((size_t)(z + o->crop.z0) * D.ny + y + o->crop.y0) * D.nx + x +
                              o->crop.x0] = (uint32_t)k + 1; /* index + 1: dense */
    }
    double avg_joint = 0, avg_sep = 0;
    for (int ph = 0; ph < 5; ph++) {
        memcpy(lab, truth, n * sizeof *lab);
        for (int32_t z = 0; z < D.nz; z++)
            if (z % 5 != ph) memset(lab + (size_t)z * plane, 0, plane * sizeof *lab);
        CHECK_OK(bvox_interpolate_labels(D, lab, NULL));
        memset(cnt, 0, 3 * (size_t)nl * sizeof *cnt);
        for (size_t i = 0; i < n; i++) {
            if (truth[i]) cnt[truth[i] - 1]++;
            if (lab[i]) cnt[nl + lab[i] - 1]++;
            if (truth[i] && truth[i] == lab[i]) cnt[2 * nl + lab[i] - 1]++;
            if ((int32_t)(i / plane) % 5 == ph) CHECK_EQ(lab[i], truth[i]); /* kept as is */
        }
        double sj = 0, ss = 0;
        for (int64_t k = 0; k < nl; k++) {
            joint[k] = 2.0 * cnt[2 * nl + k] / (double)(cnt[k] + cnt[nl + k]);
            avg[k] += joint[k] / 5;
            sj += joint[k];
            /* the same region alone, on the same kept slices */
            const bvox_label_object *o = &set->objects[k];
            bvox_volume *s, *f;
            CHECK_OK(bvox_volume_copy(o->volume, &s));
            bvox_dims c = bvox_volume_dims(s);
            for (int32_t z = 0; z < c.nz; z++)
                if ((z + o->crop.z0) % 5 != ph)
                    bvox_volume_fill_box(s, (bvox_box){0, 0, z, c.nx, c.ny, z + 1}, 0);
            CHECK_OK(bvox_interpolate_slices(s, NULL, &f));
            ss += dice(f, o->volume);
            bvox_volume_destroy(f);
            bvox_volume_destroy(s);
        }
        int n95, n90;
        double median = distribution(joint, nl, &n95, &n90);
        fprintf(stderr,
                "kept z %% 5 == %d: joint mean Dice %.4f, median %.4f, %d regions >= 0.95, %d >= "
                "0.9; each region alone: mean %.4f\n",
                ph, sj / nl, median, n95, n90, ss / nl);
        CHECK(sj / nl >= 0.885);
        CHECK(sj / nl >= ss / nl + 0.005); /* measured: 0.0097 to 0.022 better */
        avg_joint += sj / nl / 5;
        avg_sep += ss / nl / 5;
    }
    int n95, n90;
    double median = distribution(avg, nl, &n95, &n90);
    fprintf(stderr,
            "over the 5 choices: joint mean Dice %.4f (median %.4f, %d regions >= 0.95, %d >= "
            "0.9), each region alone %.4f\n",
            avg_joint, median, n95, n90, avg_sep);
    CHECK(avg_joint >= 0.89);
    CHECK(avg_joint >= avg_sep + 0.012); /* measured 0.018 */
    CHECK(n90 >= 60);
    free(truth);
    free(lab);
    free(cnt);
    free(joint);
    free(avg);
    bvox_labelset_destroy(set);
    return 0;
}
