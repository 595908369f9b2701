/* test_components.c — run-based labelling against a voxel flood fill, and
 * hand-built cases whose component counts differ by connectivity. */
#include "harness.h"
#include "internal.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

static int adjacent(int dx, int dy, int dz, int conn)
{
    int k = abs(dx) + abs(dy) + abs(dz);
    if (k == 0) return 0;
    if (conn == 6) return k == 1;
    if (conn == 18) return k <= 2;
    return 1;
}

/* Reference: BFS flood fill, labels in scan order (z slowest). Returns count;
 * sizes[i] = voxels of label i+1. */
static int64_t ref_label(const voxref *r, int conn, int32_t *labels, int64_t *sizes)
{
    size_t n = (size_t)r->nx * r->ny * r->nz;
    memset(labels, 0, n * sizeof *labels);
    size_t *queue = malloc(n * sizeof *queue);
    int64_t count = 0;
    for (size_t i = 0; i < n; i++) {
        if (!r->v[i] || labels[i]) continue;
        count++;
        sizes[count - 1] = 0;
        size_t head = 0, tail = 0;
        queue[tail++] = i;
        labels[i] = (int32_t)count;
        while (head < tail) {
            size_t p = queue[head++];
            sizes[count - 1]++;
            int x = (int)(p % (size_t)r->nx), y = (int)(p / (size_t)r->nx % (size_t)r->ny),
                z = (int)(p / ((size_t)r->nx * r->ny));
            for (int dz = -1; dz <= 1; dz++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        if (!adjacent(dx, dy, dz, conn)) continue;
                        if (!voxref_get(r, x + dx, y + dy, z + dz)) continue;
                        size_t q = (size_t)(voxref_at(r, x + dx, y + dy, z + dz) - r->v);
                        if (labels[q]) continue;
                        labels[q] = (int32_t)count;
                        queue[tail++] = q;
                    }
        }
    }
    free(queue);
    return count;
}

static int cmp_desc(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? 1 : x > y ? -1 : 0;
}

TEST(random_against_flood_fill)
{
    static const int sizes[][3] = {{1, 1, 1}, {7, 5, 1}, {6, 7, 63}, {5, 6, 64}, {7, 3, 65},
                                   {4, 5, 130}, {16, 16, 16}};
    const int conns[3] = {6, 18, 26};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (unsigned density = 2; density <= 5; density += 3) {
            const int *s = sizes[si];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, density, 10, harness_rand);
            bvox_volume *v = voxref_to_volume(r);
            size_t n = (size_t)s[0] * s[1] * s[2];
            int32_t *labels = malloc(n * sizeof *labels);
            int64_t *ref_sizes = malloc((n + 1) * sizeof *ref_sizes);
            uint32_t *ours = malloc(n * sizeof *ours);
            for (int c = 0; c < 3; c++) {
                int64_t want = ref_label(r, conns[c], labels, ref_sizes);
                bvox_components *comps;
                CHECK_OK(bvox_components_find(v, conns[c], &comps));
                CHECK_EQ(bvox_components_count(comps), want);
                qsort(ref_sizes, (size_t)want, sizeof *ref_sizes, cmp_desc);
                int64_t total = 0;
                for (int64_t i = 0; i < want; i++) {
                    CHECK_EQ(bvox_components_get(comps, i)->voxels, ref_sizes[i]);
                    total += ref_sizes[i];
                }
                CHECK_EQ(total, voxref_count(r));
                CHECK(bvox_components_get(comps, want) == NULL);
                /* the partition is the same: labels map one to one */
                bvox_components_labels(comps, ours);
                int64_t *map = calloc((size_t)want + 2, sizeof *map);
                for (size_t i = 0; i < n; i++) {
                    CHECK_EQ(ours[i] != 0, labels[i] != 0);
                    if (!labels[i]) continue;
                    if (!map[labels[i]]) map[labels[i]] = ours[i];
                    CHECK_EQ(map[labels[i]], ours[i]);
                }
                free(map);
                /* keep the largest one */
                if (want > 0) {
                    bvox_volume *k;
                    CHECK_OK(bvox_components_keep(comps, 1, &k));
                    CHECK_EQ(bvox_volume_count(k), ref_sizes[0]);
                    CHECK_OK(bvox_volume_check(k));
                    bvox_volume_destroy(k);
                }
                bvox_components_destroy(comps);
            }
            free(labels);
            free(ref_sizes);
            free(ours);
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    return 0;
}

TEST(constructed_cases_by_connectivity)
{
    /* two voxels touching by a face, an edge, a corner: 6/18/26 counts */
    static const int offs[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
    static const int want[3][3] = {{1, 1, 1}, {2, 1, 1}, {2, 2, 1}};
    const int conns[3] = {6, 18, 26};
    for (int o = 0; o < 3; o++) {
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 130}, &v));
        CHECK_OK(bvox_volume_set(v, 1, 1, 63, 1));
        CHECK_OK(bvox_volume_set(v, 1 + offs[o][0], 1 + offs[o][1], 63 + offs[o][2], 1));
        for (int c = 0; c < 3; c++) {
            bvox_components *comps;
            CHECK_OK(bvox_components_find(v, conns[c], &comps));
            CHECK_EQ(bvox_components_count(comps), want[o][c]);
            bvox_components_destroy(comps);
        }
        bvox_volume_destroy(v);
    }
    /* a full column of 130 voxels across three words is one run */
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 3, 130}, &v));
    bvox_volume_fill_box(v, (bvox_box){1, 1, 0, 2, 2, 130}, 1);
    CHECK_OK(bvox_volume_set_spacing(v, 2, 2, 0.5, "mm"));
    bvox_components *comps;
    CHECK_OK(bvox_components_find(v, 6, &comps));
    CHECK_EQ(bvox_components_count(comps), 1);
    const bvox_component *c0 = bvox_components_get(comps, 0);
    CHECK_EQ(c0->voxels, 130);
    CHECK_NEAR(c0->volume, 130 * 2.0, 1e-9);
    CHECK_EQ(c0->bbox.x0, 1);
    CHECK_EQ(c0->bbox.z1, 130);
    bvox_components_destroy(comps);
    comps = (bvox_components *)1;
    CHECK_STATUS(bvox_components_find(v, 4, &comps), BVOX_EINVAL);
    CHECK(comps == NULL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(run_arrays_respect_the_budget)
{
    /* a checkerboard-like random volume has a run every two voxels: its run
     * arrays are larger than the volume, and must count against the budget */
    voxref *r = voxref_create(64, 64, 64);
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    bvox_set_memory_budget(bvox_memory_in_use() + 40000);
    bvox_components *comps = (bvox_components *)1;
    CHECK_STATUS(bvox_components_find(v, 26, &comps), BVOX_ETOOBIG);
    CHECK(comps == NULL);
    bvox_set_memory_budget(0);
    size_t before = bvox_memory_in_use();
    CHECK_OK(bvox_components_find(v, 26, &comps));
    CHECK(bvox_memory_in_use() > before);
    bvox_components_destroy(comps);
    CHECK_EQ(bvox_memory_in_use(), before);
    bvox_volume_destroy(v);
    voxref_destroy(r);
    return 0;
}

/* Slabs of rows labelled on several threads and joined at the seams, the
 * popcnt and portable join paths, and the word-boundary contacts (runs that
 * touch diagonally across bits 63/64): everything must give the flood fill's
 * partition, sizes, bounding boxes and ranks (largest first, ties in scan
 * order of the first run). */
TEST(threaded_slabs_and_both_join_paths)
{
    static const int sizes[][3] = {{9, 70, 130}, {33, 48, 64}, {5, 96, 65}};
    const int conns[3] = {6, 18, 26};
    const bvox_simd levels[2] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AUTO};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        const int *s = sizes[si];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 2, 5, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        size_t n = (size_t)s[0] * s[1] * s[2];
        int32_t *labels = malloc(n * sizeof *labels);
        int64_t *ref_sizes = malloc((n + 1) * sizeof *ref_sizes);
        uint32_t *ours = malloc(n * sizeof *ours);
        for (int c = 0; c < 3; c++) {
            int64_t want = ref_label(r, conns[c], labels, ref_sizes);
            /* reference boxes per flood-fill label */
            bvox_box *box = malloc(((size_t)want + 1) * sizeof *box);
            for (int64_t i = 0; i <= want; i++) box[i] = (bvox_box){INT32_MAX, INT32_MAX, INT32_MAX, 0, 0, 0};
            for (size_t i = 0; i < n; i++) {
                if (!labels[i]) continue;
                int32_t x = (int32_t)(i % (size_t)s[0]), y = (int32_t)(i / (size_t)s[0] % (size_t)s[1]),
                        z = (int32_t)(i / ((size_t)s[0] * s[1]));
                bvox_box *b = &box[labels[i]];
                if (x < b->x0) b->x0 = x;
                if (y < b->y0) b->y0 = y;
                if (z < b->z0) b->z0 = z;
                if (x + 1 > b->x1) b->x1 = x + 1;
                if (y + 1 > b->y1) b->y1 = y + 1;
                if (z + 1 > b->z1) b->z1 = z + 1;
            }
            for (int li = 0; li < 2; li++)
                for (int threads = 1; threads <= 4; threads++) {
                    if (levels[li] != BVOX_SIMD_AUTO && !bvox_simd_supported(levels[li])) continue;
                    CHECK_OK(bvox_simd_set(levels[li]));
                    bvox_set_threads(threads);
                    bvox_components *comps;
                    CHECK_OK(bvox_components_find(v, conns[c], &comps));
                    CHECK_EQ(bvox_components_count(comps), want);
                    bvox_components_labels(comps, ours);
                    int64_t *map = calloc((size_t)want + 2, sizeof *map);
                    for (size_t i = 0; i < n; i++) {
                        CHECK_EQ(ours[i] != 0, labels[i] != 0);
                        if (!labels[i]) continue;
                        if (!map[labels[i]]) map[labels[i]] = ours[i];
                        CHECK_EQ(map[labels[i]], ours[i]);
                    }
                    for (int32_t l = 1; l <= want; l++) {
                        const bvox_component *k = bvox_components_get(comps, map[l] - 1);
                        CHECK_EQ(k->voxels, ref_sizes[l - 1]);
                        CHECK_EQ(memcmp(&k->bbox, &box[l], sizeof box[l]), 0);
                        /* ranks: larger first; equal sizes in order of first voxel (z-major
                         * flood order differs from our column order, so only sizes here) */
                        if (map[l] > 1)
                            CHECK(bvox_components_get(comps, map[l] - 2)->voxels >= k->voxels);
                    }
                    /* index_at agrees with the label image */
                    for (size_t i = 0; i < n; i += 7) {
                        int32_t x = (int32_t)(i % (size_t)s[0]), y = (int32_t)(i / (size_t)s[0] % (size_t)s[1]),
                                z = (int32_t)(i / ((size_t)s[0] * s[1]));
                        CHECK_EQ(bvox_components_index_at(comps, x, y, z), (int64_t)ours[i] - 1);
                    }
                    free(map);
                    bvox_components_destroy(comps);
                }
            free(box);
        }
        bvox_simd_set(BVOX_SIMD_AUTO);
        bvox_set_threads(0);
        free(labels);
        free(ref_sizes);
        free(ours);
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    return 0;
}

typedef struct ranked {
    int64_t voxels, first; /* first voxel in column order: (y * nx + x) * nz + z */
    int32_t x, y, z;
} ranked;

static int cmp_ranked(const void *a, const void *b)
{
    const ranked *p = a, *q = b;
    if (p->voxels != q->voxels) return p->voxels < q->voxels ? 1 : -1;
    return (p->first > q->first) - (p->first < q->first);
}

/* Columns longer than 512 voxels: the vector kernels (the 26-labelling's
 * first pass among them) work eight words at a time, and a run crossing
 * z = 512 must stay one run. Counts and sizes against the flood fill at
 * every SIMD level, 1 and 3 threads. */
TEST(long_columns_every_simd_level)
{
    static const int sizes[][3] = {{4, 4, 700}, {5, 3, 1100}};
    static const unsigned dens[] = {3, 5, 9}; /* of 10 */
    const int conns[3] = {6, 18, 26};
    const bvox_simd levels[3] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (int d = 0; d < 3; d++) {
            const int *sz = sizes[si];
            voxref *r = voxref_create(sz[0], sz[1], sz[2]);
            voxref_random(r, dens[d], 10, harness_rand);
            bvox_volume *v = voxref_to_volume(r);
            size_t n = (size_t)sz[0] * sz[1] * sz[2];
            int32_t *labels = malloc(n * sizeof *labels);
            int64_t *want = malloc((n + 1) * sizeof *want);
            for (int c = 0; c < 3; c++) {
                int64_t k = ref_label(r, conns[c], labels, want);
                qsort(want, (size_t)k, sizeof *want, cmp_desc);
                for (int li = 0; li < 3; li++)
                    for (int threads = 1; threads <= 3; threads += 2) {
                        if (!bvox_simd_supported(levels[li])) continue;
                        CHECK_OK(bvox_simd_set(levels[li]));
                        bvox_set_threads(threads);
                        bvox_components *comps;
                        CHECK_OK(bvox_components_find(v, conns[c], &comps));
                        CHECK_EQ(bvox_components_count(comps), k);
                        for (int64_t i = 0; i < k; i++)
                            CHECK_EQ(bvox_components_get(comps, i)->voxels, want[i]);
                        bvox_components_destroy(comps);
                        int64_t counted = -1;
                        CHECK_OK(bvox__components_count(v, conns[c], 0, &counted));
                        CHECK_EQ(counted, k);
                    }
            }
            bvox_simd_set(BVOX_SIMD_AUTO);
            bvox_set_threads(0);
            free(labels);
            free(want);
            bvox_volume_destroy(v);
            voxref_destroy(r);
        }
    return 0;
}

/* The documented order: largest first, ties by the first voxel in column
 * order (x fastest, then y, then z). Sparse random volumes have many
 * components of equal size; 26-connectivity labels 2 x 2 column groups,
 * whose runs come in another order than the columns', so this checks that
 * the ranking does not depend on how runs were numbered. Every SIMD path,
 * 1 to 4 threads, odd and even sizes. */
TEST(ties_ranked_by_first_voxel_in_column_order)
{
    static const int sizes[][3] = {{9, 7, 70}, {16, 33, 64}, {31, 30, 5}};
    const int conns[3] = {6, 18, 26};
    const bvox_simd levels[4] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512,
                                 BVOX_SIMD_AUTO};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        const int *s = sizes[si];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 10, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        size_t n = (size_t)s[0] * s[1] * s[2];
        int32_t *labels = malloc(n * sizeof *labels);
        int64_t *sizes_ref = malloc((n + 1) * sizeof *sizes_ref);
        for (int c = 0; c < 3; c++) {
            int64_t want = ref_label(r, conns[c], labels, sizes_ref);
            ranked *rk = malloc(((size_t)want + 1) * sizeof *rk);
            for (int64_t i = 0; i < want; i++) rk[i] = (ranked){sizes_ref[i], INT64_MAX, 0, 0, 0};
            for (size_t i = 0; i < n; i++) {
                if (!labels[i]) continue;
                int32_t x = (int32_t)(i % (size_t)s[0]), y = (int32_t)(i / (size_t)s[0] % (size_t)s[1]),
                        z = (int32_t)(i / ((size_t)s[0] * s[1]));
                int64_t key = ((int64_t)y * s[0] + x) * s[2] + z;
                ranked *k = &rk[labels[i] - 1];
                if (key < k->first) *k = (ranked){k->voxels, key, x, y, z};
            }
            qsort(rk, (size_t)want, sizeof *rk, cmp_ranked);
            for (int li = 0; li < 4; li++)
                for (int threads = 1; threads <= 4; threads++) {
                    if (levels[li] != BVOX_SIMD_AUTO && !bvox_simd_supported(levels[li])) continue;
                    CHECK_OK(bvox_simd_set(levels[li]));
                    bvox_set_threads(threads);
                    bvox_components *comps;
                    CHECK_OK(bvox_components_find(v, conns[c], &comps));
                    CHECK_EQ(bvox_components_count(comps), want);
                    for (int64_t i = 0; i < want; i++) {
                        CHECK_EQ(bvox_components_get(comps, i)->voxels, rk[i].voxels);
                        CHECK_EQ(bvox_components_index_at(comps, rk[i].x, rk[i].y, rk[i].z), i);
                    }
                    bvox_components_destroy(comps);
                }
            free(rk);
        }
        bvox_simd_set(BVOX_SIMD_AUTO);
        bvox_set_threads(0);
        free(labels);
        free(sizes_ref);
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    return 0;
}

/* bvox_components_labels_box equals the box's part of the whole label
 * image: random boxes (single planes, the volume's faces, boxes that start
 * and end inside a word or across words) on odd sizes, every connectivity;
 * bad boxes are refused. */
TEST(labels_box_equals_the_whole_labels_cut)
{
    static const int sizes[][3] = {{7, 5, 1}, {9, 6, 63}, {5, 7, 130}, {16, 16, 16}};
    const int conns[3] = {6, 18, 26};
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
        const int *s = sizes[si];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 2, 5, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        size_t n = (size_t)s[0] * s[1] * s[2];
        uint32_t *all = malloc(n * sizeof *all), *part = malloc(n * sizeof *part);
        for (int c = 0; c < 3; c++) {
            bvox_components *comps;
            CHECK_OK(bvox_components_find(v, conns[c], &comps));
            bvox_components_labels(comps, all);
            for (int t = 0; t < 40; t++) {
                bvox_box b;
                if (t < 6) { /* the six faces */
                    b = (bvox_box){0, 0, 0, s[0], s[1], s[2]};
                    int a = t / 2, hi = t % 2;
                    int32_t *lo_ = a == 0 ? &b.x0 : a == 1 ? &b.y0 : &b.z0;
                    int32_t *hi_ = a == 0 ? &b.x1 : a == 1 ? &b.y1 : &b.z1;
                    if (hi) *lo_ = *hi_ - 1;
                    else *hi_ = 1;
                } else {
                    int32_t lo[3], hi[3];
                    for (int a = 0; a < 3; a++) {
                        lo[a] = (int32_t)(harness_rand() % (uint64_t)s[a]);
                        hi[a] = lo[a] + 1 + (int32_t)(harness_rand() % (uint64_t)(s[a] - lo[a]));
                    }
                    b = (bvox_box){lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
                }
                CHECK_OK(bvox_components_labels_box(comps, b, part));
                size_t i = 0;
                for (int32_t z = b.z0; z < b.z1; z++)
                    for (int32_t y = b.y0; y < b.y1; y++)
                        for (int32_t x = b.x0; x < b.x1; x++, i++)
                            CHECK_EQ(part[i], all[((size_t)z * s[1] + y) * s[0] + x]);
            }
            part[0] = 12345;
            CHECK_EQ(bvox_components_labels_box(comps, (bvox_box){0, 0, 0, s[0] + 1, 1, 1}, part),
                     BVOX_EINVAL);
            CHECK_EQ(bvox_components_labels_box(comps, (bvox_box){1, 0, 0, 1, 1, 1}, part),
                     BVOX_EINVAL);
            CHECK_EQ(bvox_components_labels_box(comps, (bvox_box){0, 0, -1, 1, 1, 1}, part),
                     BVOX_EINVAL);
            CHECK_EQ(part[0], 12345u);
            bvox_components_destroy(comps);
        }
        free(all);
        free(part);
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    return 0;
}
