/* test_mesh_voxelize.c — mesh -> volume: boxes give their exact voxel
 * counts (solid and shell) and mesh back onto their own faces; a box whose
 * triangulated faces have vertices and edges exactly on the sampling rays
 * still gives every voxel once; a UV sphere's count matches its polyhedral
 * volume within the boundary error; random closed meshes agree voxel by
 * voxel with an independent slow reference (the generalized winding number,
 * a sum of solid angles, at each voxel centre); an open mesh is reported
 * and still filled by the majority vote; the bunny voxelized at 256 and
 * meshed back keeps its volume within 2 %; bad arguments. */
#include "harness.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* The first vertex with the same coordinates as vertex i (faces share the
 * box's edges and corners; the unused copies stay, unreferenced). */
static int32_t weld(const bvox_mesh *m, int32_t i)
{
    for (int32_t j = 0; j < i; j++)
        if (!memcmp(m->vertices + 3 * j, m->vertices + 3 * i, 3 * sizeof(double))) return j;
    return i;
}

/* Box [lo, hi] with each face a g x g grid of squares split in two. */
static bvox_mesh *grid_box(const double lo[3], const double hi[3], int g)
{
    bvox_mesh *m = NULL;
    if (bvox_mesh_create(&m)) return NULL;
    for (int axis = 0; axis < 3; axis++)
        for (int side = 0; side < 2; side++) {
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            int32_t base = (int32_t)m->nvertices;
            for (int j = 0; j <= g; j++)
                for (int i = 0; i <= g; i++) {
                    double p[3];
                    p[axis] = side ? hi[axis] : lo[axis];
                    p[u] = lo[u] + (hi[u] - lo[u]) * i / g;
                    p[v] = lo[v] + (hi[v] - lo[v]) * j / g;
                    bvox_mesh_add_vertex(m, p[0], p[1], p[2]);
                }
            for (int j = 0; j < g; j++)
                for (int i = 0; i < g; i++) {
                    int32_t a = weld(m, base + j * (g + 1) + i), b = weld(m, base + j * (g + 1) + i + 1),
                            c = weld(m, base + (j + 1) * (g + 1) + i + 1),
                            d = weld(m, base + (j + 1) * (g + 1) + i);
                    /* (u, v) counter-clockwise is outward on the + side */
                    if (side) {
                        bvox_mesh_add_triangle(m, a, b, c);
                        bvox_mesh_add_triangle(m, a, c, d);
                    } else {
                        bvox_mesh_add_triangle(m, a, c, b);
                        bvox_mesh_add_triangle(m, a, d, c);
                    }
                }
        }
    return m;
}

static bvox_volume *voxelize(const bvox_mesh *m, int32_t res, double size, int shell,
                             bvox_voxelize_report *rep)
{
    bvox_voxelize_opts o;
    memset(&o, 0, sizeof o);
    o.res = res;
    o.voxel_size = size;
    o.shell = shell;
    bvox_volume *v = NULL;
    if (bvox_mesh_voxelize(m, &o, &v, rep) != BVOX_OK) {
        fprintf(stderr, "voxelize: %s\n", bvox_errmsg());
        return NULL;
    }
    if (bvox_volume_check(v) != BVOX_OK) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

TEST(box_exact)
{
    const double lo[3] = {-2, 1, 3}, hi[3] = {8, 7, 7};
    bvox_mesh *m = grid_box(lo, hi, 1);
    CHECK(m);
    bvox_voxelize_report rep;
    bvox_volume *v = voxelize(m, 0, 0.5, 0, &rep);
    CHECK(v);
    CHECK(rep.closed);
    CHECK_EQ(rep.open_edges, 0);
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 20);
    CHECK_EQ(d.ny, 12);
    CHECK_EQ(d.nz, 8);
    CHECK_EQ(bvox_volume_count(v), 20 * 12 * 8);
    const bvox_geometry *g = bvox_volume_geometry(v);
    CHECK_NEAR(g->origin[0], -2 + 0.25, 1e-12);
    CHECK_NEAR(g->spacing[2], 0.5, 0);
    /* meshed back, the faces land on the original ones */
    for (int meth = 0; meth < 2; meth++) {
        bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
        o.method = (bvox_mesh_method)meth;
        bvox_mesh *back = NULL;
        CHECK_OK(bvox_mesh_from_volume(v, &o, &back));
        bvox_mesh_info info;
        CHECK_OK(bvox_mesh_measure(back, &info));
        for (int k = 0; k < 3; k++) {
            CHECK_NEAR(info.bbox_min[k], lo[k], 1e-12);
            CHECK_NEAR(info.bbox_max[k], hi[k], 1e-12);
        }
        if (meth == 1) CHECK_NEAR(info.volume, 10 * 6 * 4, 1e-9);
        bvox_mesh_destroy(back);
    }
    bvox_volume_destroy(v);
    /* --res: 40 voxels along x (the longest side, 10) */
    v = voxelize(m, 40, 0, 0, NULL);
    CHECK(v);
    CHECK_EQ(bvox_volume_dims(v).nx, 40);
    CHECK_EQ(bvox_volume_count(v), 40 * 24 * 16);
    bvox_volume_destroy(v);
    /* shell: the outer layer of voxels */
    v = voxelize(m, 0, 1, 1, &rep);
    CHECK(v);
    CHECK_EQ(bvox_volume_count(v), 10 * 6 * 4 - 8 * 4 * 2);
    bvox_volume_destroy(v);
    bvox_mesh_destroy(m);
    return 0;
}

/* Vertices and edges on the rays: a box [0,4]^3 with faces split into 4x4
 * grids, sampled at 4/3 (voxel centres at 2/3, 2, 10/3: the rays x = 2 and
 * y = 2 run through vertices and along edges of the top and bottom faces,
 * and x = 2 lies in the plane of edges of the side faces). */
TEST(rays_through_vertices_and_edges)
{
    const double lo[3] = {0, 0, 0}, hi[3] = {4, 4, 4};
    for (int g = 1; g <= 8; g *= 2) {
        bvox_mesh *m = grid_box(lo, hi, g);
        CHECK(m);
        bvox_volume *v = voxelize(m, 3, 0, 0, NULL);
        CHECK(v);
        CHECK_EQ(bvox_volume_count(v), 27);
        bvox_volume_destroy(v);
        v = voxelize(m, 6, 0, 0, NULL); /* centres 1/3, 1, 5/3, ...: x = 1, 2, 3 */
        CHECK(v);
        CHECK_EQ(bvox_volume_count(v), 216);
        bvox_volume_destroy(v);
        bvox_mesh_destroy(m);
    }
    return 0;
}

/* UV sphere of radius r: n rings, 2n segments. */
static bvox_mesh *uv_sphere(double r, int n)
{
    bvox_mesh *m = NULL;
    if (bvox_mesh_create(&m)) return NULL;
    bvox_mesh_add_vertex(m, 0, 0, -r);
    for (int i = 1; i < n; i++)
        for (int j = 0; j < 2 * n; j++) {
            double th = M_PI * i / n - M_PI / 2, ph = M_PI * j / n;
            bvox_mesh_add_vertex(m, r * cos(th) * cos(ph), r * cos(th) * sin(ph), r * sin(th));
        }
    bvox_mesh_add_vertex(m, 0, 0, r);
    int32_t top = (int32_t)m->nvertices - 1;
    for (int j = 0; j < 2 * n; j++) {
        int32_t a = 1 + j, b = 1 + (j + 1) % (2 * n);
        bvox_mesh_add_triangle(m, 0, b, a);
        int32_t c = 1 + (n - 2) * 2 * n + j, d = 1 + (n - 2) * 2 * n + (j + 1) % (2 * n);
        bvox_mesh_add_triangle(m, top, c, d);
    }
    for (int i = 0; i + 1 < n - 1; i++)
        for (int j = 0; j < 2 * n; j++) {
            int32_t a = 1 + i * 2 * n + j, b = 1 + i * 2 * n + (j + 1) % (2 * n);
            int32_t c = a + 2 * n, d = b + 2 * n;
            bvox_mesh_add_triangle(m, a, b, d);
            bvox_mesh_add_triangle(m, a, d, c);
        }
    return m;
}

TEST(sphere_count)
{
    bvox_mesh *m = uv_sphere(10, 48);
    CHECK(m);
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.volume / (4.0 / 3.0 * M_PI * 1000), 1.0, 0.01);
    for (int res = 16; res <= 128; res *= 2) {
        bvox_volume *v = voxelize(m, res, 0, 0, NULL);
        CHECK(v);
        double s = bvox_volume_geometry(v)->spacing[0];
        double got = (double)bvox_volume_count(v) * s * s * s;
        /* centre sampling: the error is a fraction of the boundary layer */
        CHECK_NEAR(got, info.volume, 0.25 * info.area * s);
        bvox_volume *sh = voxelize(m, res, 0, 1, NULL);
        CHECK(sh);
        /* every shell voxel is within a half diagonal of the surface: the
         * shell's volume is about area x (1 to 1.7) voxels thick */
        double shell = (double)bvox_volume_count(sh) * s * s * s;
        CHECK(shell > 0.9 * info.area * s && shell < 2.2 * info.area * s);
        bvox_volume_destroy(sh);
        bvox_volume_destroy(v);
    }
    bvox_mesh_destroy(m);
    return 0;
}

/* ---- the reference: generalized winding number at a point ---- */

static double winding(const bvox_mesh *m, const double p[3])
{
    double w = 0;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = m->vertices[3 * m->triangles[3 * t] + k] - p[k];
            b[k] = m->vertices[3 * m->triangles[3 * t + 1] + k] - p[k];
            c[k] = m->vertices[3 * m->triangles[3 * t + 2] + k] - p[k];
        }
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
        double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
        double den = la * lb * lc + ab * lc + bc * la + ca * lb;
        /* p on the triangle: the solid angle jumps by 4 pi there */
        if (fabs(det) <= 1e-12 * la * lb * lc && den < 0) return NAN;
        w += 2 * atan2(det, den);
    }
    return w / (4 * M_PI);
}

TEST(random_meshes_match_winding_number)
{
    for (int trial = 0; trial < 3; trial++) {
        /* a random blobby volume, meshed (marching cubes, smoothed: vertices
         * off the grid), then voxelized on another grid */
        bvox_volume *src = NULL;
        CHECK_OK(bvox_volume_create((bvox_dims){9, 8, 7}, &src));
        for (int32_t z = 1; z < 6; z++)
            for (int32_t y = 1; y < 7; y++)
                for (int32_t x = 1; x < 8; x++)
                    if (harness_rand() % 100 < 60) bvox_volume_set(src, x, y, z, 1);
        bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
        o.smooth = trial;
        bvox_mesh *m = NULL;
        CHECK_OK(bvox_mesh_from_volume(src, &o, &m));
        bvox_volume_destroy(src);
        bvox_voxelize_report rep;
        bvox_volume *v = voxelize(m, 23 + trial, 0, 0, &rep);
        CHECK(v);
        CHECK(rep.closed);
        bvox_dims d = bvox_volume_dims(v);
        const bvox_geometry *g = bvox_volume_geometry(v);
        int64_t decisive = 0;
        for (int32_t z = 0; z < d.nz; z++)
            for (int32_t y = 0; y < d.ny; y++)
                for (int32_t x = 0; x < d.nx; x++) {
                    double p[3] = {g->origin[0] + x * g->spacing[0],
                                   g->origin[1] + y * g->spacing[1],
                                   g->origin[2] + z * g->spacing[2]};
                    double w = winding(m, p);
                    if (!(fabs(w - round(w)) <= 0.2)) continue; /* on the surface */
                    decisive++;
                    int want = round(w) != 0;
                    if (bvox_volume_get(v, x, y, z) != want) {
                        fprintf(stderr, "trial %d voxel %d %d %d: winding %.3f, got %d\n", trial,
                                x, y, z, w, bvox_volume_get(v, x, y, z));
                        return 1;
                    }
                }
        CHECK(decisive > (int64_t)d.nx * d.ny * d.nz * 9 / 10);
        bvox_volume_destroy(v);
        bvox_mesh_destroy(m);
    }
    return 0;
}

TEST(open_mesh_vote)
{
    const double lo[3] = {0, 0, 0}, hi[3] = {6, 5, 4};
    bvox_mesh *m = grid_box(lo, hi, 1);
    CHECK(m);
    m->ntriangles -= 2; /* the last face (z = 4) goes */
    bvox_voxelize_report rep;
    bvox_volume *v = voxelize(m, 0, 1, 0, &rep);
    CHECK(v);
    CHECK(!rep.closed);
    CHECK_EQ(rep.open_edges, 4);
    CHECK(!strcmp(rep.method, "vote-xyz"));
    /* x and y rays still see two walls: every voxel is in */
    CHECK_EQ(bvox_volume_count(v), 6 * 5 * 4);
    bvox_volume_destroy(v);
    bvox_mesh_destroy(m);
    return 0;
}

TEST(bad_arguments)
{
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    bvox_mesh *m = grid_box(lo, hi, 1);
    bvox_voxelize_opts o;
    memset(&o, 0, sizeof o);
    bvox_volume *v = NULL;
    CHECK_STATUS(bvox_mesh_voxelize(m, &o, &v, NULL), BVOX_EINVAL);
    o.res = 4;
    o.voxel_size = 1;
    CHECK_STATUS(bvox_mesh_voxelize(m, &o, &v, NULL), BVOX_EINVAL);
    o.res = 0;
    o.voxel_size = 1e-6;
    CHECK_STATUS(bvox_mesh_voxelize(m, &o, &v, NULL), BVOX_ETOOBIG);
    CHECK(v == NULL);
    /* a count printed with %g, not 300 digits */
    o.voxel_size = 1e-300;
    CHECK_STATUS(bvox_mesh_voxelize(m, &o, &v, NULL), BVOX_ETOOBIG);
    CHECK(strstr(bvox_errmsg(), "spans 1e+300 voxels") != NULL);
    CHECK(strlen(bvox_errmsg()) < 120);
    bvox_mesh *empty = NULL;
    CHECK_OK(bvox_mesh_create(&empty));
    o.voxel_size = 1;
    CHECK_STATUS(bvox_mesh_voxelize(empty, &o, &v, NULL), BVOX_EINVAL);
    bvox_mesh_destroy(empty);
    bvox_mesh_destroy(m);
    return 0;
}

TEST(voxelize_bunny)
{
    bvox_mesh *m = NULL;
    CHECK_OK(bvox_mesh_read(BVOX_TEST_MESH_DIR "/bunny00.off", NULL, &m));
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_EQ(info.vertices, 37706);
    bvox_voxelize_report rep;
    bvox_volume *v = voxelize(m, 256, 0, 0, &rep);
    CHECK(v);
    CHECK(rep.closed);
    CHECK_EQ(bvox_volume_dims(v).nx, 256);
    double s = bvox_volume_geometry(v)->spacing[0];
    CHECK_NEAR((double)bvox_volume_count(v) * s * s * s / info.volume, 1.0, 0.02);
    for (int meth = 0; meth < 2; meth++) {
        bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
        o.method = (bvox_mesh_method)meth;
        o.smooth = meth == 0 ? 5 : 0;
        bvox_mesh *back = NULL;
        CHECK_OK(bvox_mesh_from_volume(v, &o, &back));
        bvox_mesh_info bi;
        CHECK_OK(bvox_mesh_measure(back, &bi));
        CHECK(bi.watertight);
        CHECK_NEAR(bi.volume / info.volume, 1.0, 0.02);
        for (int k = 0; k < 3; k++) CHECK_NEAR(bi.bbox_min[k], info.bbox_min[k], 2 * s);
        bvox_mesh_destroy(back);
    }
    bvox_volume_destroy(v);
    bvox_mesh_destroy(m);
    return 0;
}

TEST(allocation_failures_are_clean)
{
    bvox_mesh *m = uv_sphere(3, 12);
    CHECK(m);
    size_t base = bvox_memory_in_use();
    for (int mode = 0; mode < 3; mode++)
        for (long n = 1; n < 30; n++) {
            bvox_voxelize_opts o;
            memset(&o, 0, sizeof o);
            o.res = 10;
            o.shell = mode == 1;
            if (mode == 2) m->ntriangles -= 1; /* open: the three-axis vote */
            bvox_volume *v = NULL;
            bvox__alloc_fail_after(n);
            bvox_status st = bvox_mesh_voxelize(m, &o, &v, NULL);
            bvox__alloc_fail_after(0);
            if (mode == 2) m->ntriangles += 1;
            if (st == BVOX_OK) {
                CHECK(v);
                bvox_volume_destroy(v);
            } else {
                CHECK(v == NULL);
                CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
            }
            CHECK_EQ(bvox_memory_in_use(), base);
        }
    bvox_mesh_destroy(m);
    return 0;
}
