/* test_cut.c — plane cuts and the half-space primitive against a per-voxel
 * reference written here in world coordinates (origin + direction * (index *
 * spacing), its own evaluation order): random volumes at awkward sizes,
 * anisotropic spacing, rotated directions, planes exactly through voxel
 * centres (exact arithmetic: the centre on the plane is "above"), planes
 * with c = 0 (whole columns), keep above + keep below splitting the volume,
 * the changed region (tight, from the before and after volumes), one and two
 * threads, a large volume split over threads, and bad planes. */
#include "harness.h"
#include "ref/voxref.h"

#include <string.h>

static const int sizes[][3] = {{7, 5, 1},   {5, 9, 63},  {9, 7, 64},
                               {3, 11, 65}, {11, 3, 130}, {1, 1, 129}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

/* The plane's value at the centre of voxel (x, y, z) in world coordinates
 * (world = 1) or in the shapes' frame (direction ignored). */
static double plane_at(const bvox_geometry *g, const double *pl, int x, int y, int z,
                       int world)
{
    const double idx[3] = {x * g->spacing[0], y * g->spacing[1], z * g->spacing[2]};
    double f = pl[3];
    for (int r = 0; r < 3; r++) {
        double w = g->origin[r];
        if (world)
            for (int c = 0; c < 3; c++) w += g->direction[r * 3 + c] * idx[c];
        else
            w += idx[r];
        f += pl[r] * w;
    }
    return f;
}

/* Rounding allowance for |f| at a centre: a voxel closer to the plane than
 * this may fall on either side unless the arithmetic is exact. */
static double plane_tol(const bvox_geometry *g, const double *pl, const int *n)
{
    double s = fabs(pl[3]);
    for (int r = 0; r < 3; r++)
        s += fabs(pl[r]) * (fabs(g->origin[r]) + 2 * (n[0] * g->spacing[0] +
                                                      n[1] * g->spacing[1] +
                                                      n[2] * g->spacing[2]));
    return 1e-12 * s;
}

static bvox_box diff_box(const voxref *a, const voxref *b)
{
    bvox_box box = {0, 0, 0, 0, 0, 0};
    int any = 0;
    for (int z = 0; z < a->nz; z++)
        for (int y = 0; y < a->ny; y++)
            for (int x = 0; x < a->nx; x++) {
                if (*voxref_at(a, x, y, z) == *voxref_at(b, x, y, z)) continue;
                if (!any) box = (bvox_box){x, y, z, x + 1, y + 1, z + 1};
                any = 1;
                if (x < box.x0) box.x0 = x;
                if (y < box.y0) box.y0 = y;
                if (z < box.z0) box.z0 = z;
                if (x >= box.x1) box.x1 = x + 1;
                if (y >= box.y1) box.y1 = y + 1;
                if (z >= box.z1) box.z1 = z + 1;
            }
    return box;
}

/* op: -1 cut keep above, -2 cut keep below, else a csg op for the half-space
 * primitive. exact: no rounding allowance (every voxel must match). Returns
 * the number of voxels that were within the allowance, or -1 on failure. */
static long check_plane(const int *n, const bvox_geometry *g, const double *pl, int op,
                        int exact)
{
    voxref *r = voxref_create(n[0], n[1], n[2]);
    if (!r) return -1;
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    if (!v || bvox_volume_set_geometry(v, g)) return -1;
    bvox_box changed;
    bvox_status st = op < 0 ? bvox_cut_plane(v, pl[0], pl[1], pl[2], pl[3], op == -1, &changed)
                            : bvox_halfspace_draw(v, pl[0], pl[1], pl[2], pl[3],
                                                  (bvox_csg_op)op, &changed);
    if (st) {
        fprintf(stderr, "plane failed: %s\n", bvox_errmsg());
        return -1;
    }
    voxref *got = voxref_from_volume(v);
    double tol = exact ? 0 : plane_tol(g, pl, n);
    long close = 0, bad = 0;
    for (int z = 0; z < n[2]; z++)
        for (int y = 0; y < n[1]; y++)
            for (int x = 0; x < n[0]; x++) {
                double f = plane_at(g, pl, x, y, z, op < 0);
                int a = f >= 0, old = *voxref_at(r, x, y, z), want;
                switch (op) {
                case -1: want = old && a; break;
                case -2: want = old && !a; break;
                case BVOX_CSG_UNION:
                case BVOX_CSG_REPLACE: want = old || a; break;
                case BVOX_CSG_INTERSECTION: want = old && a; break;
                case BVOX_CSG_DIFFERENCE: want = old && !a; break;
                default: want = old ^ a; break;
                }
                int have = *voxref_at(got, x, y, z);
                if (have == want) continue;
                if (fabs(f) <= tol) {
                    close++;
                    continue;
                }
                if (bad++ < 3)
                    fprintf(stderr, "op %d %dx%dx%d voxel (%d,%d,%d): f = %.17g, got %d want %d\n",
                            op, n[0], n[1], n[2], x, y, z, f, have, want);
            }
    bvox_box want_box = diff_box(r, got);
    if (memcmp(&want_box, &changed, sizeof changed)) {
        fprintf(stderr, "changed box (%d,%d,%d)-(%d,%d,%d), actual (%d,%d,%d)-(%d,%d,%d)\n",
                changed.x0, changed.y0, changed.z0, changed.x1, changed.y1, changed.z1,
                want_box.x0, want_box.y0, want_box.z0, want_box.x1, want_box.y1, want_box.z1);
        bad++;
    }
    if (bvox_volume_check(v)) bad++;
    bvox_volume_destroy(v);
    voxref_destroy(r);
    voxref_destroy(got);
    return bad ? -1 : close;
}

/* direction: rotation by angle t about the unit axis u (columns = rotated axes) */
static void rotation(double *d, const double *u, double t)
{
    double c = cos(t), s = sin(t), k = 1 - c;
    double m[9] = {c + u[0] * u[0] * k,        u[0] * u[1] * k - u[2] * s, u[0] * u[2] * k + u[1] * s,
                   u[1] * u[0] * k + u[2] * s, c + u[1] * u[1] * k,        u[1] * u[2] * k - u[0] * s,
                   u[2] * u[0] * k - u[1] * s, u[2] * u[1] * k + u[0] * s, c + u[2] * u[2] * k};
    memcpy(d, m, sizeof m);
}

static double rnd_unit(void) { return (double)(harness_rand() >> 11) / 9007199254740992.0; }

TEST(exact_through_centres)
{
    /* identity direction, binary-fraction spacing and origin, small integer
     * normals through a voxel centre: the arithmetic is exact, so the
     * centres on the plane must be above, everywhere */
    static const double normals[][3] = {{1, 2, -1}, {0, 0, 1},  {0, 0, -1}, {1, 0, 0},
                                        {0, -3, 0}, {2, 1, 4},  {-1, -1, -2}, {1, 1, 0}};
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.5;
    g.spacing[1] = 2;
    g.spacing[2] = 0.25;
    g.origin[0] = -1.5;
    g.origin[1] = 4;
    g.origin[2] = 0.75;
    for (int threads = 1; threads <= 2; threads++) {
        bvox_set_threads(threads);
        for (int i = 0; i < NSIZES; i++)
            for (size_t k = 0; k < sizeof normals / sizeof normals[0]; k++) {
                const int *n = sizes[i];
                int cx = (int)(harness_rand() % (uint64_t)n[0]);
                int cy = (int)(harness_rand() % (uint64_t)n[1]);
                int cz = (int)(harness_rand() % (uint64_t)n[2]);
                double pl[4] = {normals[k][0], normals[k][1], normals[k][2], 0};
                pl[3] = -plane_at(&g, pl, cx, cy, cz, 1);
                for (int op = -2; op <= BVOX_CSG_REPLACE; op++) CHECK_EQ(check_plane(n, &g, pl, op, 1), 0);
            }
    }
    bvox_set_threads(0);
    return 0;
}

TEST(hand_counts)
{
    /* 4 x 3 x 10 full block, spacing 1: the plane z = 4 keeps z 4..9 above
     * (the layer on the plane included) and z 0..3 below */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 3, 10}, &v));
    bvox_volume_fill(v, 1);
    bvox_box b;
    CHECK_OK(bvox_cut_plane(v, 0, 0, 1, -4, 1, &b));
    CHECK_EQ(bvox_volume_count(v), 4 * 3 * 6);
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 0, 4, 3, 4}, sizeof b));
    bvox_volume_fill(v, 1);
    CHECK_OK(bvox_cut_plane(v, 0, 0, 1, -4, 0, &b));
    CHECK_EQ(bvox_volume_count(v), 4 * 3 * 4);
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 4, 4, 3, 10}, sizeof b));
    /* -z normal: above is z <= 4 */
    bvox_volume_fill(v, 1);
    CHECK_OK(bvox_cut_plane(v, 0, 0, -2, 8, 1, NULL));
    CHECK_EQ(bvox_volume_count(v), 4 * 3 * 5);
    /* x + y >= 3 on a 4 x 3 grid: columns (x,y) with x+y >= 3: 6 of 12 */
    bvox_volume_fill(v, 1);
    CHECK_OK(bvox_cut_plane(v, 1, 1, 0, -3, 1, &b));
    CHECK_EQ(bvox_volume_count(v), 6 * 10);
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 0, 3, 3, 10}, sizeof b));
    /* nothing left to cut: empty box */
    CHECK_OK(bvox_cut_plane(v, 1, 1, 0, -3, 1, &b));
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 0, 0, 0, 0}, sizeof b));
    /* with the voxel size: z = 2 mm with 0.5 mm slices is slice 4 */
    CHECK_OK(bvox_volume_set_spacing(v, 1, 1, 0.5, "mm"));
    bvox_volume_fill(v, 1);
    CHECK_OK(bvox_cut_plane(v, 0, 0, 1, -2, 1, NULL));
    CHECK_EQ(bvox_volume_count(v), 4 * 3 * 6);
    /* the half-space primitive drawn into an empty volume */
    bvox_volume_fill(v, 0);
    CHECK_OK(bvox_halfspace_draw(v, 0, 0, 1, -2, BVOX_CSG_UNION, &b));
    CHECK_EQ(bvox_volume_count(v), 4 * 3 * 6);
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 4, 4, 3, 10}, sizeof b));
    bvox_volume_destroy(v);
    return 0;
}

TEST(rotated_anisotropic)
{
    long close = 0;
    for (int i = 0; i < NSIZES; i++)
        for (int rep = 0; rep < 6; rep++) {
            const int *n = sizes[i];
            bvox_geometry g = bvox_geometry_default();
            double u[3] = {rnd_unit() - 0.5, rnd_unit() - 0.5, rnd_unit() - 0.5};
            double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            for (int k = 0; k < 3; k++) u[k] /= len;
            rotation(g.direction, u, 0.3 + 2.5 * rnd_unit());
            for (int k = 0; k < 3; k++) {
                g.spacing[k] = 0.3 + 2.7 * rnd_unit();
                g.origin[k] = 20 * rnd_unit() - 10;
            }
            double pl[4] = {rnd_unit() - 0.5, rnd_unit() - 0.5, rnd_unit() - 0.5, 0};
            /* through the centre of a random voxel: many near-ties */
            pl[3] = -plane_at(&g, pl, (int)(harness_rand() % (uint64_t)n[0]),
                              (int)(harness_rand() % (uint64_t)n[1]),
                              (int)(harness_rand() % (uint64_t)n[2]), 1);
            for (int op = -2; op <= BVOX_CSG_REPLACE; op++) {
                long c = check_plane(n, &g, pl, op, 0);
                CHECK(c >= 0);
                close += c;
            }
        }
    fprintf(stderr, "voxels within rounding of the plane that went the other way: %ld\n", close);
    return 0;
}

TEST(c_zero_whole_columns)
{
    /* c == 0: every column is wholly kept or cleared */
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.7;
    g.spacing[1] = 1.9;
    g.spacing[2] = 3.3;
    const double pl[4] = {1, -0.5, 0, 0.3};
    for (int i = 0; i < NSIZES; i++)
        for (int op = -2; op <= BVOX_CSG_REPLACE; op++) CHECK(check_plane(sizes[i], &g, pl, op, 0) >= 0);
    /* a rotation about z keeps index z along world z: c == 0 is still
     * whole columns in index space */
    const double u[3] = {0, 0, 1};
    rotation(g.direction, u, 0.6);
    for (int i = 0; i < NSIZES; i++)
        CHECK(check_plane(sizes[i], &g, pl, -1, 0) >= 0);
    /* and a plane with c != 0 whose normal is perpendicular to index z
     * after a rotation about x by 90 degrees (index z -> world -y) */
    const double ux[3] = {1, 0, 0};
    rotation(g.direction, ux, M_PI / 2);
    const double pz[4] = {1, 0, 0.8, -1};
    for (int i = 0; i < NSIZES; i++)
        CHECK(check_plane(sizes[i], &g, pz, -1, 0) >= 0);
    return 0;
}

TEST(above_below_split)
{
    /* keep above + keep below = the volume, disjoint */
    bvox_geometry g = bvox_geometry_default();
    const double u[3] = {0.48, -0.6, 0.64};
    rotation(g.direction, u, 1.1);
    g.spacing[2] = 2.5;
    voxref *r = voxref_create(13, 11, 130);
    CHECK(r);
    voxref_random(r, 1, 3, harness_rand);
    bvox_volume *a = voxref_to_volume(r), *b = voxref_to_volume(r), *all = voxref_to_volume(r);
    CHECK(a && b && all);
    CHECK_OK(bvox_volume_set_geometry(a, &g));
    CHECK_OK(bvox_volume_set_geometry(b, &g));
    CHECK_OK(bvox_cut_plane(a, 0.3, 0.2, -0.9, 12.5, 1, NULL));
    CHECK_OK(bvox_cut_plane(b, 0.3, 0.2, -0.9, 12.5, 0, NULL));
    CHECK(bvox_volume_count(a) > 0 && bvox_volume_count(b) > 0);
    CHECK_EQ(bvox_volume_count_and(a, b), 0);
    CHECK_EQ(bvox_volume_count(a) + bvox_volume_count(b), voxref_count(r));
    CHECK_OK(bvox_csg_apply(a, BVOX_CSG_UNION, b, NULL));
    CHECK(bvox_volume_equal(a, all));
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    bvox_volume_destroy(all);
    voxref_destroy(r);
    return 0;
}

TEST(threads_agree_large)
{
    /* 150 x 130 x 200: rows split over 1, 2 and 5 threads give one answer */
    bvox_volume *v[3] = {NULL, NULL, NULL};
    bvox_box b[3];
    static const int threads[3] = {1, 2, 5};
    bvox_geometry g = bvox_geometry_default();
    const double u[3] = {0.6, 0.8, 0};
    rotation(g.direction, u, 0.4);
    g.spacing[0] = 0.8;
    for (int t = 0; t < 3; t++) {
        CHECK_OK(bvox_volume_create((bvox_dims){150, 130, 200}, &v[t]));
        CHECK_OK(bvox_volume_set_geometry(v[t], &g));
        bvox_volume_fill(v[t], 1);
        bvox_set_threads(threads[t]);
        CHECK_OK(bvox_cut_plane(v[t], 0.2, -0.4, 0.9, -60, 1, &b[t]));
        CHECK_OK(bvox_volume_check(v[t]));
    }
    bvox_set_threads(0);
    CHECK(bvox_volume_count(v[0]) > 0 && bvox_volume_count(v[0]) < 150 * 130 * 200);
    for (int t = 1; t < 3; t++) {
        CHECK(bvox_volume_equal(v[0], v[t]));
        CHECK(!memcmp(&b[0], &b[t], sizeof b[0]));
    }
    for (int t = 0; t < 3; t++) bvox_volume_destroy(v[t]);
    return 0;
}

TEST(bad_planes)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &v));
    bvox_volume_fill(v, 1);
    bvox_box b = {1, 1, 1, 1, 1, 1};
    CHECK_STATUS(bvox_cut_plane(v, 0, 0, 0, 1, 1, &b), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "zero"));
    CHECK(!memcmp(&b, &(bvox_box){0, 0, 0, 0, 0, 0}, sizeof b));
    CHECK_STATUS(bvox_cut_plane(v, NAN, 0, 1, 1, 1, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_cut_plane(v, 0, 0, 1, INFINITY, 1, NULL), BVOX_EINVAL);
    CHECK_OK(bvox_cut_plane(v, 0, 0, 1e280, 0, 1, NULL));
    CHECK_OK(bvox_volume_set_spacing(v, 1e20, 1e20, 1e20, NULL));
    CHECK_STATUS(bvox_cut_plane(v, 0, 0, 1e280, 0, 1, NULL), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "too large"));
    CHECK_STATUS(bvox_halfspace_draw(v, 0, 0, 0, 1, BVOX_CSG_UNION, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_halfspace_draw(v, 0, 0, 1, 1, (bvox_csg_op)9, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_cut_plane(NULL, 0, 0, 1, 1, 1, NULL), BVOX_EINVAL);
    /* failures leave the volume alone */
    CHECK_EQ(bvox_volume_count(v), 64);
    bvox_volume_destroy(v);
    return 0;
}
