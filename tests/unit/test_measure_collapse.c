/* test_measure_collapse.c — bvox_measure's topology on a copy without
 * repeated slices (measure_collapse.c): the copy against slices compared
 * voxel by voxel here, and the components and cavities counted on it
 * against the breadth-first reference of the whole volume (measref.c), on
 * hand-made cases (empty rows between objects, a diagonal contact across a
 * deleted streak) and on upsampled random volumes and atlases, at every
 * SIMD level and at 1, 3 and 16 threads. */
#include "harness.h"
#include "internal.h"
#include "measure/measure.h"
#include "ref/measref.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

/* Whether y-slice y equals y - 1 (axis 1), or x-slice x equals x - 1 (axis
 * 0), voxel by voxel. */
static int slice_repeats(const voxref *r, int axis, int i)
{
    int n1 = axis == 0 ? r->ny : r->nx;
    for (int j = 0; j < n1; j++)
        for (int z = 0; z < r->nz; z++) {
            int a = axis == 0 ? voxref_get(r, i, j, z) : voxref_get(r, j, i, z);
            int b = axis == 0 ? voxref_get(r, i - 1, j, z) : voxref_get(r, j, i - 1, z);
            if (a != b) return 0;
        }
    return 1;
}

/* v's scan into sc with its hull records (calloc'd: free them). */
static bvox__colhull *scan_hulls(const bvox_volume *v, bvox__scan *sc)
{
    bvox__colhull *h = calloc((size_t)v->nx * (size_t)v->ny, sizeof *h);
    if (h && bvox__measure_scan_hulls(v, h, sc) != BVOX_OK) {
        free(h);
        return NULL;
    }
    return h;
}

/* The slices a copy keeps: the box's, less those equal to the one before
 * (xs[0..*kx), ys[0..*ky)). */
static void expected_kept(const voxref *r, const bvox_box *b, int *xs, int *kx, int *ys, int *ky)
{
    *kx = *ky = 0;
    for (int x = b->x0; x < b->x1; x++)
        if (x == b->x0 || !slice_repeats(r, 0, x)) xs[(*kx)++] = x;
    for (int y = b->y0; y < b->y1; y++)
        if (y == b->y0 || !slice_repeats(r, 1, y)) ys[(*ky)++] = y;
}

/* The copy (or none when it would not have paid) against the kept slices,
 * and bvox_measure's topology against the reference, at every SIMD level
 * and thread count. */
static int check_volume(const voxref *r, int64_t want_components)
{
    bvox_volume *v = voxref_to_volume(r);
    CHECK(v);
    measref o;
    const double sp[3] = {1, 1, 1};
    measref_compute(r, sp, &o);
    if (want_components >= 0) CHECK_EQ(o.components, want_components);
    bvox_box b;
    CHECK(voxref_bbox(r, &b));
    int *xs = malloc(((size_t)r->nx + (size_t)r->ny) * sizeof *xs), *ys = xs + r->nx, kx, ky;
    expected_kept(r, &b, xs, &kx, ys, &ky);
    bool copies = 4 * (int64_t)kx * ky <= 3 * (int64_t)(b.x1 - b.x0) * (b.y1 - b.y0);
    voxref *want = voxref_create(kx, ky, r->nz);
    for (int y = 0; y < ky; y++)
        for (int x = 0; x < kx; x++)
            for (int z = 0; z < r->nz; z++) *voxref_at(want, x, y, z) = *voxref_at(r, xs[x], ys[y], z);
    free(xs);
    bvox_simd saved = bvox_simd_active();
    const bvox_simd levels[] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
    for (int l = 0; l < 3; l++) {
        if (!bvox_simd_supported(levels[l])) continue;
        CHECK_OK(bvox_simd_set(levels[l]));
        for (int t = 0; t < 3; t++) {
            bvox_set_threads(t == 0 ? 1 : t == 1 ? 3 : 16);
            bvox__scan sc;
            bvox__colhull *hulls = scan_hulls(v, &sc);
            CHECK(hulls);
            bvox_volume *c = NULL;
            CHECK_OK(bvox__collapse_repeats(v, sc.bbox, hulls, &c));
            free(hulls);
            bool copy_ok = copies ? c && voxref_matches(want, c) : !c;
            bvox_volume_destroy(c);
            bvox_measures m;
            CHECK_OK(bvox_measure(v, &m));
            if (!copy_ok || m.components != o.components || m.cavities != o.cavities ||
                m.cavities_26 != o.cavities_26 || m.euler != o.euler) {
                fprintf(stderr,
                        "  %dx%dx%d simd %d threads %d: copy %s (%dx%d of box %dx%d expected); "
                        "components %lld / %lld, cavities %lld / %lld, 26: %lld / %lld (ref)\n",
                        r->nx, r->ny, r->nz, (int)levels[l], bvox_threads(),
                        copy_ok ? "right" : "wrong", copies ? kx : 0, copies ? ky : 0,
                        b.x1 - b.x0, b.y1 - b.y0, (long long)m.components,
                        (long long)o.components, (long long)m.cavities, (long long)o.cavities,
                        (long long)m.cavities_26, (long long)o.cavities_26);
                bvox_set_threads(0);
                bvox_simd_set(saved);
                return 1;
            }
        }
    }
    bvox_set_threads(0);
    CHECK_OK(bvox_simd_set(saved));
    voxref_destroy(want);
    bvox_volume_destroy(v);
    return 0;
}

/* Two slabs of 3 equal rows, 3 empty rows between them: the copy keeps one
 * row of each streak, the empty one too (it separates), and one x-slice
 * (all of the box's columns are equal): 1 x 3 columns, 2 components. */
TEST(empty_rows_between_objects_kept)
{
    voxref *r = voxref_create(10, 14, 64);
    voxref_fill_box(r, (bvox_box){2, 2, 5, 7, 5, 21}, 1);
    voxref_fill_box(r, (bvox_box){2, 8, 5, 7, 11, 21}, 1);
    bvox_volume *v = voxref_to_volume(r);
    bvox__scan sc;
    bvox__colhull *hulls = scan_hulls(v, &sc);
    CHECK(hulls);
    bvox_measures m = {0};
    bvox_dims d;
    CHECK_OK(bvox__measure_topology(v, &sc, hulls, &m, &d));
    CHECK(m.components == 2 && m.cavities == 0);
    CHECK(d.nx == 1 && d.ny == 3 && d.nz == 64);
    free(hulls);
    bvox_volume_destroy(v);
    CHECK(!check_volume(r, 2));
    voxref_destroy(r);
    return 0;
}

/* Two bars along y, the second one x-step to the side and starting on the
 * row after the first ends: 26-connected across the diagonal only when the
 * step is 1. The streaks collapse to one row each; the diagonal stays. */
TEST(diagonal_contact_across_streaks)
{
    for (int step = 1; step <= 2; step++) {
        voxref *r = voxref_create(12, 16, 40);
        voxref_fill_box(r, (bvox_box){3, 2, 10, 4, 7, 30}, 1);
        voxref_fill_box(r, (bvox_box){3 + step, 7, 10, 4 + step, 13, 30}, 1);
        CHECK(!check_volume(r, step == 1 ? 1 : 2));
        voxref_destroy(r);
    }
    return 0;
}

/* A random volume whose x- and y-slices are repeated 1 to 4 times each (as
 * nearest-neighbour upsampling does), with margins, some repeats then
 * changed in one voxel: the copy keeps exactly the slices that differ. */
static voxref *upsampled(int bx, int by, int nz, unsigned dens, int margin, int change)
{
    voxref *base = voxref_create(bx, by, nz);
    voxref_random(base, dens, 100, harness_rand);
    int rx[64], ry[64], nx = 2 * margin, ny = 2 * margin;
    for (int i = 0; i < bx; i++) nx += rx[i] = 1 + (int)(harness_rand() % 4);
    for (int i = 0; i < by; i++) ny += ry[i] = 1 + (int)(harness_rand() % 4);
    voxref *r = voxref_create(nx, ny, nz);
    for (int j = 0, y = margin; j < by; j++)
        for (int cy = 0; cy < ry[j]; cy++, y++)
            for (int i = 0, x = margin; i < bx; i++)
                for (int cx = 0; cx < rx[i]; cx++, x++)
                    for (int z = 0; z < nz; z++)
                        *voxref_at(r, x, y, z) = *voxref_at(base, i, j, z);
    for (int k = 0; k < change; k++) {
        int x = margin + (int)(harness_rand() % (unsigned)(nx - 2 * margin));
        int y = margin + (int)(harness_rand() % (unsigned)(ny - 2 * margin));
        *voxref_at(r, x, y, (int)(harness_rand() % (unsigned)nz)) ^= 1;
    }
    voxref_destroy(base);
    return r;
}

TEST(upsampled_random_vs_reference)
{
    static const int shapes[][3] = {{9, 7, 40}, {14, 11, 70}, {6, 12, 130}, {16, 16, 64}};
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        for (unsigned dens = 15; dens <= 75; dens += 30)
            for (int change = 0; change <= 3; change += 3) {
                const int *sh = shapes[i];
                voxref *r = upsampled(sh[0], sh[1], sh[2], dens, (int)(i % 3), change);
                if (check_volume(r, -1)) {
                    fprintf(stderr, "  shape %zu density %u/100 changes %d\n", i, dens, change);
                    return 1;
                }
                voxref_destroy(r);
            }
    return 0;
}

/* No repeats (a coin toss) and few (one repeated row): the volume itself is
 * labelled, with the same count. */
TEST(few_repeats_label_the_volume)
{
    voxref *r = voxref_create(21, 17, 50);
    voxref_random(r, 1, 2, harness_rand);
    CHECK(!check_volume(r, -1));
    for (int x = 0; x < 21; x++)
        for (int z = 0; z < 50; z++) *voxref_at(r, x, 9, z) = *voxref_at(r, x, 8, z);
    CHECK(!check_volume(r, -1));
    voxref_destroy(r);
    return 0;
}

TEST(alloc_failure_is_clean)
{
    voxref *r = upsampled(8, 8, 64, 40, 1, 0);
    bvox_volume *v = voxref_to_volume(r);
    bvox__scan sc;
    bvox__colhull *hulls = scan_hulls(v, &sc);
    CHECK(hulls);
    size_t before = bvox_memory_in_use();
    int failed = 0;
    for (long k = 1; k < 80; k++) {
        bvox__alloc_fail_after(k);
        bvox_measures m = {0};
        bvox_dims d = {0, 0, 0};
        bvox_status st = bvox__measure_topology(v, &sc, hulls, &m, &d);
        long pending = bvox__alloc_fail_pending();
        bvox__alloc_fail_after(0);
        CHECK_EQ(bvox_memory_in_use(), before);
        if (pending) { /* the armed failure was not reached: done */
            CHECK_OK(st);
            CHECK(d.nx < r->nx && d.ny < r->ny); /* it went through a copy */
            break;
        }
        CHECK_STATUS(st, BVOX_ENOMEM);
        failed++;
    }
    CHECK(failed >= 4); /* the lists, the copy, its hulls, the labeller's arrays */
    free(hulls);
    bvox_volume_destroy(v);
    voxref_destroy(r);
    return 0;
}

/* Rows of distinct heights but every fourth a repeat, columns of distinct
 * heights along x: a copy of three quarters of the volume, which needs
 * more than the volume's own labelling. Under a budget the copy's way
 * exceeds, the measure goes without the copy, and is right. */
TEST(over_budget_goes_without_the_copy)
{
    voxref *r = voxref_create(64, 64, 1024);
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++)
            for (int z = 5; z < 200 + (y % 4 == 3 ? y - 1 : y) + 3 * (x % 7); z++)
                *voxref_at(r, x, y, z) = 1;
    bvox_volume *v = voxref_to_volume(r);
    size_t budget = bvox_memory_budget(), words = v->nwords * sizeof(uint64_t);
    size_t hull_bytes = 64 * 64 * sizeof(bvox__colhull);
    bvox_measures m;
    CHECK_OK(bvox_measure(v, &m));
    CHECK(m.components == 1 && m.cavities == 0);
    bvox__scan sc;
    bvox__colhull *hulls = scan_hulls(v, &sc);
    CHECK(hulls);
    bvox_volume *c = NULL;
    CHECK_OK(bvox__collapse_repeats(v, sc.bbox, hulls, &c));
    CHECK(c && c->nx == 64 && c->ny == 48); /* the copy is made when it fits */
    bvox_volume_destroy(c);
    /* room for the hulls and half the words: the labelling of the volume
     * (a quarter of its words for the groups' ORs) fits, the copy does not */
    bvox_set_memory_budget(bvox_memory_in_use() + hull_bytes + words / 2);
    bvox_measures b;
    bvox_status st = bvox_measure(v, &b);
    bvox_dims d = {0, 0, 0};
    bvox_status st_top = bvox__measure_topology(v, &sc, hulls, &b, &d);
    bvox_set_memory_budget(budget);
    CHECK_OK(st);
    CHECK_OK(st_top);
    CHECK(d.nx == 64 && d.ny == 64);
    CHECK(b.components == m.components && b.cavities == m.cavities && b.euler == m.euler);
    free(hulls);
    bvox_volume_destroy(v);
    voxref_destroy(r);
    return 0;
}

/* r resampled to n^3 by nearest neighbour (index i of the copy takes
 * i * r's size / n), as the benchmarks make the 512^3 atlas. */
static voxref *resampled(const voxref *r, int n)
{
    voxref *o = voxref_create(n, n, n);
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++)
                *voxref_at(o, x, y, z) = *voxref_at(r, (int)((int64_t)x * r->nx / n),
                                                    (int)((int64_t)y * r->ny / n),
                                                    (int)((int64_t)z * r->nz / n));
    return o;
}

#define AAL "/usr/share/mricron/templates/aal.nii.gz"

/* The atlas (all labels, and a few labels alone) upsampled: the copy is
 * back on the atlas's own grid, and the topology that of the reference. */
TEST(realdata_aal_upsampled)
{
    bvox_volume *v = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    CHECK_OK(bvox_read(AAL, &ro, &v));
    voxref *r = voxref_from_volume(v);
    voxref *up = resampled(r, 256);
    CHECK(!check_volume(up, 1));
    voxref_destroy(up);
    voxref_destroy(r);
    bvox_volume_destroy(v);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(AAL, NULL, 0, &set));
    for (int64_t i = 0; i < set->n; i += 23) {
        r = voxref_from_volume(set->objects[i].volume);
        up = resampled(r, 2 * (r->nx > r->ny ? r->nx : r->ny));
        if (check_volume(up, -1)) {
            fprintf(stderr, "  label %lld\n", (long long)i);
            return 1;
        }
        voxref_destroy(up);
        voxref_destroy(r);
    }
    bvox_labelset_destroy(set);
    return 0;
}
