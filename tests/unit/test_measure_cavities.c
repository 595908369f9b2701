/* test_measure_cavities.c — the cavities of bvox_measure (6-connected
 * background components not reaching the border, and the 26-connected ones;
 * src/measure/measure_cavities.c) against the breadth-first references of
 * tests/ref/measref.c and against the previous route (the complement of the
 * whole volume labelled 6- then 26-connected with its border merged): random
 * volumes of several densities, adversarial shapes (nested shells, cavities
 * touching each other or the exterior only diagonally, a spiral, runs across
 * word boundaries, objects on the border), the AAL atlas whole and per
 * label; at every SIMD level, with 1, 3 and 16 threads, and by every route
 * (the flood of measure_flood.c, settled or cut short so that the labelling
 * takes over, and the labelling alone), plus the flood's reached set against
 * a breadth-first search. */
#include "harness.h"
#include "internal.h"
#include "measure/measure.h"
#include "ref/measref.h"
#include "ref/voxref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The previous route, kept here as a second reference for volumes too big
 * for the breadth-first one. */
static int old_route(const bvox_volume *v, int64_t *c6, int64_t *c26)
{
    *c6 = *c26 = 0;
    if (bvox_volume_count(v) == 0 || bvox_volume_count(v) == (int64_t)v->nx * v->ny * v->nz)
        return 0;
    bvox_volume *bg = NULL;
    CHECK_OK(bvox_volume_copy(v, &bg));
    bvox_volume_complement(bg);
    CHECK_OK(bvox__components_count(bg, 6, 1, c6));
    CHECK_OK(bvox__components_count(bg, 26, 1, c26));
    bvox_volume_destroy(bg);
    return 0;
}

static const int thread_counts[] = {1, 3, 16};

/* bvox__cavity_flood_sweeps: the route chosen, the labelling alone, a flood
 * cut short after one sweep (the labelling takes over unless that settled
 * it), a flood that settles; with bvox__cavity_label_k (the flood's
 * 26-cavities): by default (labelling K minus the dilation of the reached
 * background), and after a settled flood also by labelling all of K; with
 * bvox__cavity_hull, the runs of the background enclosed along z listed and
 * joined (-1, the default), its words labelled (1), or all of the box's
 * background labelled (0); with
 * bvox__cavity_sparse_26, the labelling routes' 26-cavities as chosen (-1),
 * by relabelling K's box (0) or from K's runs alone (1); with
 * bvox__cavity_twin_rows, the listed runs' rows equal to the row before
 * taking their twins' (1, the default) or not (0). */
static const int routes[][5] = {
    {-1, 0, -1, -1, 1}, {0, 0, -1, -1, 1},      {0, 0, 1, -1, 1},       {0, 0, 0, -1, 1},
    {1, 0, -1, -1, 1},  {1, 0, 1, -1, 1},       {1, 0, 0, -1, 1},       {1 << 20, 0, -1, -1, 1},
    {1 << 20, 1, -1, -1, 1}, {0, 0, 1, 0, 1},   {0, 0, 0, 0, 1},        {0, 0, 1, 1, 1},
    {0, 0, 0, 1, 1},    {0, 0, -1, -1, 0},      {0, 0, -1, 1, 0}};
#define NROUTES (sizeof routes / sizeof *routes)

/* bvox_measure at every SIMD level, thread count and route gives cav6 and
 * cav26 (and the components, and tunnels = components + cavities - euler). */
static int check_all_paths(const bvox_volume *v, int64_t comp, int64_t cav6, int64_t cav26)
{
    bvox_simd saved = bvox_simd_active();
    int threads = bvox_threads(), bad = 0;
    for (int lv = BVOX_SIMD_GENERIC; lv <= BVOX_SIMD_AVX512 && !bad; lv++) {
        if (!bvox_simd_supported((bvox_simd)lv)) continue;
        CHECK_OK(bvox_simd_set((bvox_simd)lv));
        /* every thread count by every route */
        for (size_t t = 0; t < 3 * NROUTES && !bad; t++) {
            bvox_set_threads(thread_counts[t % 3]);
            bvox__cavity_flood_sweeps = routes[t / 3][0];
            bvox__cavity_label_k = routes[t / 3][1];
            bvox__cavity_hull = routes[t / 3][2];
            bvox__cavity_sparse_26 = routes[t / 3][3];
            bvox__cavity_twin_rows = routes[t / 3][4];
            bvox_measures m;
            CHECK_OK(bvox_measure(v, &m));
            /* and without the scan's column hulls (the route scans for them) */
            bvox__scan sc;
            CHECK_OK(bvox__measure_scan(v, &sc));
            int64_t n6 = 0, n26 = 0;
            if (sc.count && sc.count < (int64_t)v->nx * v->ny * v->nz)
                CHECK_OK(bvox__measure_cavities(v, &sc, NULL, &n6, &n26));
            if (n6 != cav6 || n26 != cav26) {
                fprintf(stderr, "  without hulls: cavities %lld/%lld\n", (long long)n6,
                        (long long)n26);
                bad = 1;
            }
            if (m.components != comp || m.cavities != cav6 || m.cavities_26 != cav26 ||
                m.tunnels != m.components + m.cavities - m.euler) {
                fprintf(stderr,
                        "  %dx%dx%d simd %s threads %d route %d/%d/%d/%d (flood*100+label_k, "
                        "hull, sparse 26, twin rows): components %lld cavities %lld/%lld, expected %lld "
                        "%lld/%lld\n",
                        v->nx, v->ny, v->nz, bvox_simd_name((bvox_simd)lv), thread_counts[t % 3],
                        routes[t / 3][0] * 100 + routes[t / 3][1], routes[t / 3][2],
                        routes[t / 3][3], routes[t / 3][4],
                        (long long)m.components, (long long)m.cavities,
                        (long long)m.cavities_26, (long long)comp, (long long)cav6,
                        (long long)cav26);
                bad = 1;
            }
        }
    }
    CHECK_OK(bvox_simd_set(saved));
    bvox_set_threads(threads);
    bvox__cavity_flood_sweeps = -1;
    bvox__cavity_label_k = 0;
    bvox__cavity_hull = -1;
    bvox__cavity_sparse_26 = -1;
    bvox__cavity_twin_rows = 1;
    return bad;
}

/* r against the breadth-first reference and the previous route. */
static int check_ref(const voxref *r)
{
    const double sp[3] = {1, 1, 1};
    measref o;
    measref_compute(r, sp, &o);
    bvox_volume *v = voxref_to_volume(r);
    CHECK(v);
    int64_t c6, c26;
    CHECK(!old_route(v, &c6, &c26));
    CHECK_EQ(c6, o.cavities);
    CHECK_EQ(c26, o.cavities_26);
    int bad = check_all_paths(v, o.components, o.cavities, o.cavities_26);
    bvox_volume_destroy(v);
    return bad;
}

static void vset(voxref *r, int x, int y, int z, uint8_t value) { *voxref_at(r, x, y, z) = value; }

TEST(random_densities_vs_reference)
{
    /* sizes past one word in z and rows enough for 3- and 16-way splits */
    static const int sizes[][3] = {{1, 1, 70}, {5, 3, 64}, {9, 7, 65}, {13, 11, 130},
                                   {21, 40, 67}, {33, 260, 20}, {270, 17, 31}};
    const unsigned dens[] = {2, 4, 5, 6, 7, 8}; /* of 10: background from dense to sparse */
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t d = 0; d < sizeof dens / sizeof *dens; d++) {
            const int *s = sizes[i];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, dens[d], 10, harness_rand);
            if (check_ref(r)) {
                fprintf(stderr, "  density %u/10\n", dens[d]);
                return 1;
            }
            voxref_destroy(r);
        }
    /* a coin toss in a box away from the volume's sides: the flood reads
     * the background in place from an offset box */
    voxref *r = voxref_create(41, 37, 70);
    voxref *c = voxref_create(25, 22, 60);
    voxref_random(c, 5, 10, harness_rand);
    for (int z = 0; z < 60; z++)
        for (int y = 0; y < 22; y++)
            for (int x = 0; x < 25; x++) vset(r, x + 9, y + 4, z + 3, *voxref_at(c, x, y, z));
    voxref_destroy(c);
    CHECK(!check_ref(r));
    voxref_destroy(r);
    return 0;
}

/* Columns copied from the one at x - 1 or y - 1 (an upsampled volume: the
 * hull route copies the runs of a column equal to its left neighbour and
 * joins them one to one, and skips the join with the row before where that
 * row's pair is equal too), some copies then changed in one voxel; rows
 * enough for several slabs and seams at 3 and 16 threads. */
TEST(repeated_columns_vs_reference)
{
    static const int sizes[][3] = {{40, 70, 70}, {23, 120, 130}};
    const unsigned dens[] = {4, 5, 6, 7};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t d = 0; d < sizeof dens / sizeof *dens; d++) {
            const int *s = sizes[i];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, dens[d], 10, harness_rand);
            for (int y = 0; y < s[1]; y++)
                for (int x = 0; x < s[0]; x++) {
                    unsigned pick = (unsigned)(harness_rand() % 4);
                    int sx = pick < 2 && x > 0 ? x - 1 : x, sy = pick == 2 && y > 0 ? y - 1 : y;
                    for (int z = 0; z < s[2]; z++) vset(r, x, y, z, *voxref_at(r, sx, sy, z));
                    if (harness_rand() % 8 == 0)
                        *voxref_at(r, x, y, (int)(harness_rand() % (unsigned)s[2])) ^= 1;
                }
            if (check_ref(r)) {
                fprintf(stderr, "  repeated columns, density %u/10\n", dens[d]);
                return 1;
            }
            voxref_destroy(r);
        }
    return 0;
}

/* Rows equal to the row before (whole rows, the box's ring columns too):
 * runs of twin rows longer than a listing task's 8 rows and a join slab's
 * 16, some twins then changed by swapping voxels along z, and a random
 * volume upsampled 3 x 3 x 2 by nearest neighbour (twins and equal columns,
 * as the atlas). */
TEST(repeated_rows_vs_reference)
{
    static const int sizes[][3] = {{30, 90, 70}, {17, 140, 130}};
    const unsigned dens[] = {4, 6, 7};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (size_t d = 0; d < sizeof dens / sizeof *dens; d++) {
            const int *s = sizes[i];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, dens[d], 10, harness_rand);
            int streak = 0;
            for (int y = 1; y < s[1]; y++) {
                if (streak == 0 && harness_rand() % 3 == 0) streak = 1 + (int)(harness_rand() % 30);
                if (streak == 0) continue;
                streak--;
                for (int x = 0; x < s[0]; x++)
                    for (int z = 0; z < s[2]; z++) vset(r, x, y, z, *voxref_at(r, x, y - 1, z));
                /* near-twins: a voxel swapped with the one above it mostly
                 * keeps the column's hull and run count, so only the words
                 * tell the row from its twin */
                if (harness_rand() % 3 == 0)
                    for (int k = 0; k < 4; k++) {
                        int x = (int)(harness_rand() % (unsigned)s[0]);
                        int z = (int)(harness_rand() % (unsigned)(s[2] - 1));
                        uint8_t a = *voxref_at(r, x, y, z);
                        vset(r, x, y, z, *voxref_at(r, x, y, z + 1));
                        vset(r, x, y, z + 1, a);
                    }
            }
            if (check_ref(r)) {
                fprintf(stderr, "  repeated rows, density %u/10\n", dens[d]);
                return 1;
            }
            voxref_destroy(r);
        }
    for (unsigned dn = 5; dn <= 7; dn++) {
        voxref *small = voxref_create(12, 30, 40);
        voxref_random(small, dn, 10, harness_rand);
        voxref *r = voxref_create(36, 90, 80);
        for (int y = 0; y < 90; y++)
            for (int x = 0; x < 36; x++)
                for (int z = 0; z < 80; z++) vset(r, x, y, z, *voxref_at(small, x / 3, y / 3, z / 2));
        voxref_destroy(small);
        if (check_ref(r)) {
            fprintf(stderr, "  upsampled, density %u/10\n", dn);
            return 1;
        }
        voxref_destroy(r);
    }
    return 0;
}

/* Hollow box shell [x0, x1) etc. of thickness 1 (value 1), inside cleared. */
static void shell(voxref *r, int x0, int y0, int z0, int x1, int y1, int z1)
{
    voxref_fill_box(r, (bvox_box){x0, y0, z0, x1, y1, z1}, 1);
    voxref_fill_box(r, (bvox_box){x0 + 1, y0 + 1, z0 + 1, x1 - 1, y1 - 1, z1 - 1}, 0);
}

TEST(adversarial_vs_reference)
{
    /* nested shells: cavity, object inside it, cavity inside that */
    voxref *r = voxref_create(20, 20, 140);
    shell(r, 1, 1, 1, 19, 19, 139);
    shell(r, 4, 4, 50, 16, 16, 90);
    shell(r, 7, 7, 60, 13, 13, 80);
    CHECK(!check_ref(r));
    /* the object fills the border: the labelled box is the whole volume */
    shell(r, 0, 0, 0, 20, 20, 140);
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* two cavities touching only along an edge (one 26-cavity), and a cavity
     * that touches the exterior only at a corner (6- but no 26-cavity) */
    r = voxref_create(16, 12, 66);
    voxref_fill_box(r, (bvox_box){1, 1, 1, 15, 11, 65}, 1);
    voxref_fill_box(r, (bvox_box){3, 3, 60, 5, 5, 64}, 0);
    voxref_fill_box(r, (bvox_box){5, 5, 62, 7, 7, 63}, 0); /* edge contact across x and y */
    voxref_fill_box(r, (bvox_box){10, 3, 30, 12, 5, 34}, 0);
    vset(r, 14, 10, 64, 0); /* a notch on the box's corner, open to the outside */
    vset(r, 13, 9, 63, 0);  /* its corner neighbour: enclosed for 6, not for 26 */
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* pits open only along z, up or down, ending on a word boundary or not:
     * never cavities, whatever their x-y neighbours hold; and one that is */
    r = voxref_create(9, 9, 140);
    voxref_fill_box(r, (bvox_box){1, 1, 1, 8, 8, 128}, 1);
    voxref_fill_box(r, (bvox_box){4, 4, 100, 5, 5, 128}, 0); /* open upwards */
    voxref_fill_box(r, (bvox_box){2, 2, 1, 3, 3, 64}, 0);    /* open downwards */
    voxref_fill_box(r, (bvox_box){6, 6, 64, 7, 7, 128}, 0);  /* upwards, from a word boundary */
    voxref_fill_box(r, (bvox_box){5, 4, 127, 6, 5, 128}, 0); /* beside the first pit's mouth */
    voxref_fill_box(r, (bvox_box){2, 6, 30, 3, 7, 40}, 0);   /* a cavity */
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* a U-shaped cavity whose right arm (the later root, made a child of the
     * left arm's when the bar joins them) touches the exterior only along a
     * diagonal, at rows where its runs are two steps from the root: one
     * 6-cavity, no 26-cavity (the root of the touched runs must be found) */
    r = voxref_create(12, 14, 3);
    voxref_fill_box(r, (bvox_box){0, 0, 0, 12, 14, 3}, 1);
    voxref_fill_box(r, (bvox_box){3, 2, 1, 4, 12, 2}, 0);
    voxref_fill_box(r, (bvox_box){7, 2, 1, 8, 12, 2}, 0);
    voxref_fill_box(r, (bvox_box){3, 11, 1, 8, 12, 2}, 0);
    vset(r, 8, 6, 0, 0); /* on the volume's face: 26-adjacent to (7, 5..7, 1) */
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* a cavity running across the 64-bit word boundaries of its columns */
    r = voxref_create(6, 5, 200);
    voxref_fill_box(r, (bvox_box){1, 1, 1, 5, 4, 199}, 1);
    voxref_fill_box(r, (bvox_box){2, 2, 60, 4, 3, 131}, 0);
    voxref_fill_box(r, (bvox_box){2, 2, 135, 3, 3, 190}, 0);
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* a square spiral corridor inside a slab, closed at its outer end: one
     * long thin cavity that winds through most columns */
    r = voxref_create(41, 41, 7);
    voxref_fill_box(r, (bvox_box){0, 0, 1, 41, 41, 6}, 1);
    int x = 2, y = 2, len = 36, dir = 0;
    static const int step[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int leg = 0; len > 0; leg++) {
        for (int i = 0; i < len; i++) {
            vset(r, x, y, 3, 0);
            x += step[dir][0];
            y += step[dir][1];
        }
        dir = (dir + 1) % 4;
        if (leg % 2) len -= 2;
    }
    CHECK(!check_ref(r));
    /* opened to the outside at its start: no cavity */
    vset(r, 2, 2, 2, 0);
    vset(r, 2, 2, 1, 0);
    vset(r, 2, 2, 0, 0);
    CHECK(!check_ref(r));
    voxref_destroy(r);

    /* many small hollow blobs and single-voxel holes, some diagonal pairs */
    r = voxref_create(35, 29, 97);
    for (int k = 0; k < 60; k++) {
        int bx = (int)(harness_rand() % 31), by = (int)(harness_rand() % 25),
            bz = (int)(harness_rand() % 92);
        int dx = 3 + (int)(harness_rand() % 4), dy = 3 + (int)(harness_rand() % 4),
            dz = 3 + (int)(harness_rand() % 5);
        shell(r, bx, by, bz, bx + dx, by + dy, bz + dz);
    }
    CHECK(!check_ref(r));
    voxref_destroy(r);
    return 0;
}

/* Big coin tosses (cavities everywhere: the whole-background route) and
 * sparse ones, against the previous route. */
TEST(large_random_vs_previous)
{
    static const unsigned dens[] = {3, 5, 7};
    for (size_t d = 0; d < 3; d++) {
        voxref *r = voxref_create(97, 300, 131);
        voxref_random(r, dens[d], 10, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        voxref_destroy(r);
        int64_t c6, c26, comp;
        CHECK(!old_route(v, &c6, &c26));
        CHECK_OK(bvox__components_count(v, 26, 0, &comp));
        CHECK(!check_all_paths(v, comp, c6, c26));
        bvox_volume_destroy(v);
    }
    return 0;
}

#define AAL "/usr/share/mricron/templates/aal.nii.gz"

TEST(realdata_aal_whole_and_per_label)
{
    bvox_volume *v = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    CHECK_OK(bvox_read(AAL, &ro, &v));
    voxref *r = voxref_from_volume(v);
    CHECK(!check_ref(r));
    voxref_destroy(r);
    bvox_volume_destroy(v);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(AAL, NULL, 0, &set));
    int64_t with_cavities = 0;
    for (int64_t i = 0; i < set->n; i++) {
        r = voxref_from_volume(set->objects[i].volume);
        measref o;
        measref_compute(r, (const double[3]){1, 1, 1}, &o);
        voxref_destroy(r);
        bvox_measures m;
        CHECK_OK(bvox_measure(set->objects[i].volume, &m));
        CHECK_EQ(m.components, o.components);
        CHECK_EQ(m.cavities, o.cavities);
        CHECK_EQ(m.cavities_26, o.cavities_26);
        with_cavities += m.cavities > 0;
        if (i % 29 == 0) /* a few at every level and thread count */
            CHECK(!check_all_paths(set->objects[i].volume, o.components, o.cavities,
                                   o.cavities_26));
    }
    CHECK_EQ(set->n, 116);
    fprintf(stderr, "  %lld of 116 labels have cavities\n", (long long)with_cavities);
    bvox_labelset_destroy(set);
    return 0;
}

/* Breadth-first reference of the flood: the background voxels 6-connected
 * to the border of r (x or y on the edge, z = 0 or nz - 1). */
static uint8_t *reached_ref(const voxref *r)
{
    size_t n = (size_t)r->nx * r->ny * r->nz;
    uint8_t *seen = calloc(n, 1);
    int32_t *queue = malloc(n * 3 * sizeof *queue);
    size_t head = 0, tail = 0;
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++) {
                bool edge = x == 0 || y == 0 || z == 0 || x + 1 == r->nx || y + 1 == r->ny ||
                            z + 1 == r->nz;
                size_t i = ((size_t)z * r->ny + y) * r->nx + x;
                if (!edge || r->v[i]) continue;
                seen[i] = 1;
                queue[tail * 3] = x, queue[tail * 3 + 1] = y, queue[tail * 3 + 2] = z, tail++;
            }
    static const int d[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    const int nd = 6;
    while (head < tail) {
        const int32_t *p = &queue[3 * head++];
        for (int k = 0; k < nd; k++) {
            int x = p[0] + d[k][0], y = p[1] + d[k][1], z = p[2] + d[k][2];
            if (x < 0 || y < 0 || z < 0 || x >= r->nx || y >= r->ny || z >= r->nz) continue;
            size_t i = ((size_t)z * r->ny + y) * r->nx + x;
            if (r->v[i] || seen[i]) continue;
            seen[i] = 1;
            queue[tail * 3] = x, queue[tail * 3 + 1] = y, queue[tail * 3 + 2] = z, tail++;
        }
    }
    free(queue);
    return seen;
}

/* bvox__flood_border into got (zeroed first), v holding the background;
 * whether it settled within max_sweeps. */
static bool flood(const bvox_volume *v, int max_sweeps, uint64_t *got, int32_t *rows)
{
    memset(got, 0, v->nwords * sizeof *got);
    size_t nx = (size_t)v->nx, ny = (size_t)v->ny;
    bvox__bgsrc bg = {v->words, nx, 0, 0, 0, v->tail_mask}; /* v holds the background */
    return bvox__flood_border(&bg, nx, ny, v->wpc, (size_t)v->nz, max_sweeps, got, rows);
}

/* bvox__flood_border on the complement of r's words: settled, the reached
 * set is the reference's bit for bit at every SIMD level and 1, 3 and 16
 * threads; cut short at max_short sweeps it must not settle (when
 * short_settles is 0) and must be a subset. */
static int check_flood(const voxref *r, int max_short, int short_settles)
{
    bvox_volume *v = voxref_to_volume(r);
    CHECK(v);
    bvox_volume_complement(v);
    uint8_t *want = reached_ref(r);
    size_t nw = v->nwords;
    uint64_t *got = calloc(nw, sizeof *got);
    int32_t *rows = calloc((size_t)v->ny * (1 + (size_t)v->nx), sizeof *rows);
    int threads = bvox_threads();
    bvox_simd saved = bvox_simd_active();
    for (size_t t = 0; t < 3 * (BVOX_SIMD_AVX512 + 1); t++) {
        if (!bvox_simd_supported((bvox_simd)(t / 3))) continue;
        CHECK_OK(bvox_simd_set((bvox_simd)(t / 3)));
        bvox_set_threads(thread_counts[t % 3]);
        CHECK(flood(v, 1 << 20, got, rows));
        for (int z = 0; z < r->nz; z++)
            for (int y = 0; y < r->ny; y++)
                for (int x = 0; x < r->nx; x++) {
                    size_t w = ((size_t)y * r->nx + x) * v->wpc + (size_t)z / 64;
                    int bit = (int)((got[w] >> (z % 64)) & 1);
                    CHECK_EQ(bit, want[((size_t)z * r->ny + y) * r->nx + x]);
                }
        bool settled = flood(v, max_short, got, rows);
        if (!short_settles) CHECK(!settled);
        for (int z = 0; z < r->nz; z++)
            for (int y = 0; y < r->ny; y++)
                for (int x = 0; x < r->nx; x++) {
                    size_t w = ((size_t)y * r->nx + x) * v->wpc + (size_t)z / 64;
                    if ((got[w] >> (z % 64)) & 1)
                        CHECK(want[((size_t)z * r->ny + y) * r->nx + x]);
                }
    }
    bvox_set_threads(threads);
    CHECK_OK(bvox_simd_set(saved));
    free(got);
    free(rows);
    free(want);
    bvox_volume_destroy(v);
    return 0;
}

TEST(flood_vs_breadth_first)
{
    /* random densities on both sides of the percolation threshold, runs
     * across word boundaries, thin volumes (every column on the ring) */
    static const int sizes[][3] = {{1, 1, 70},    {2, 9, 64},   {9, 7, 65},
                                   {23, 40, 130}, {40, 19, 200}, {16, 13, 500}};
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++)
        for (unsigned d = 1; d <= 9; d += 2) {
            voxref *r = voxref_create(sizes[i][0], sizes[i][1], sizes[i][2]);
            voxref_random(r, d, 10, harness_rand);
            CHECK(!check_flood(r, 1, 1));
            voxref_destroy(r);
        }
    /* columns of 8 words (one AVX-512 vector) and of 9 (the portable row):
     * a column of background [z0, z1) reached only at one z, through a
     * tunnel from the border, fills up and down across whole words of
     * background (the vector's carries between lanes, up to 7 lanes away),
     * or to both ends of the column, in one visit (it has no other
     * neighbour to pass a part on and take the rest back from): nz, z0,
     * z1, the tunnel's z */
    static const int spans[][4] = {{500, 10, 490, 20}, {500, 10, 490, 480}, {512, 64, 448, 250},
                                   {512, 0, 512, 250}, {520, 5, 515, 300}};
    for (size_t i = 0; i < sizeof spans / sizeof *spans; i++) {
        const int *sp = spans[i];
        voxref *c = voxref_create(6, 5, sp[0]);
        voxref_fill_box(c, (bvox_box){0, 0, 0, 6, 5, sp[0]}, 1);
        voxref_fill_box(c, (bvox_box){2, 2, sp[1], 3, 3, sp[2]}, 0);
        voxref_fill_box(c, (bvox_box){0, 2, sp[3], 2, 3, sp[3] + 1}, 0); /* the tunnel */
        CHECK(!check_flood(c, 1 << 20, 1));
        vset(c, 1, 2, sp[3], 1); /* closed: the column is a cavity */
        CHECK(!check_flood(c, 1 << 20, 1));
        voxref_destroy(c);
    }
    /* a fill down from the seed at z = 50 must stop at the object voxel
     * z = 26; below it, 16 background voxels (a cavity) are a full window
     * for the Kogge-Stone mask after four steps, so a mask not narrowed at
     * the fifth would let the last step (32 down, from z = 42) jump the gap */
    voxref *c = voxref_create(5, 5, 64);
    voxref_fill_box(c, (bvox_box){0, 0, 0, 5, 5, 64}, 1);
    voxref_fill_box(c, (bvox_box){2, 2, 10, 3, 3, 26}, 0);
    voxref_fill_box(c, (bvox_box){2, 2, 27, 3, 3, 60}, 0);
    voxref_fill_box(c, (bvox_box){0, 2, 50, 2, 3, 51}, 0); /* the tunnel */
    CHECK(!check_flood(c, 1 << 20, 1));
    voxref_destroy(c);
    /* a corridor that winds back and forth in x, open at its far end: each
     * turn needs another sweep, so 3 sweeps cannot settle it */
    voxref *r = voxref_create(30, 41, 5);
    voxref_fill_box(r, (bvox_box){0, 0, 0, 30, 41, 5}, 1);
    for (int y = 2; y < 39; y += 4) {
        voxref_fill_box(r, (bvox_box){2, y, 2, 28, y + 1, 3}, 0); /* a leg along x */
        int x = (y / 4) % 2 ? 2 : 27;                             /* joined at alternate ends */
        if (y + 4 < 39) voxref_fill_box(r, (bvox_box){x, y, 2, x + 1, y + 5, 3}, 0);
    }
    voxref_fill_box(r, (bvox_box){27, 38, 2, 28, 41, 3}, 0); /* the open end */
    CHECK(!check_flood(r, 3, 0));
    CHECK(!check_ref(r)); /* and the cavities by every route */
    voxref_fill_box(r, (bvox_box){27, 40, 2, 28, 41, 3}, 1); /* closed: one long cavity */
    CHECK(!check_ref(r));
    /* open again only diagonally (to the border voxel (28, 40, 2)): a
     * 6-cavity, no 26-cavity; the one corridor voxel next to the border is
     * the only one that a dilation of the reached background strips, the
     * rest (L) is joined to it through a chain of turns */
    vset(r, 28, 40, 2, 0);
    CHECK(!check_ref(r));
    voxref_destroy(r);
    return 0;
}
