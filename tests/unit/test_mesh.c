/* test_mesh.c — volume -> mesh: marching cubes and cuberille meshes of
 * random volumes of awkward sizes (single voxels, voxels touching along an
 * edge or at a corner) are closed 2-manifolds checked here independently of
 * the library's own edge statistics (every undirected edge on exactly two
 * triangles, traversed once each way, and the triangles around every vertex
 * forming one cycle); cuberille volume == voxel volume exactly; hand-computed
 * single-voxel meshes; the marching-cubes sphere within 1 % of 4/3 pi r^3;
 * voxel size, origin and a mirrored direction honoured; Taubin smoothing
 * keeps the volume; the result does not depend on the thread count. */
#include "harness.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* ---- independent checks ---- */

typedef struct edge_rec {
    int32_t lo, hi, fwd;
} edge_rec;

static int edge_cmp(const void *a, const void *b)
{
    const edge_rec *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->fwd - y->fwd;
}

/* 0 if every edge is on exactly 2 triangles with opposite directions and the
 * link of every vertex is one cycle; prints the first problem otherwise. */
static int check_manifold(const bvox_mesh *m)
{
    int64_t nt = m->ntriangles, nv = m->nvertices;
    edge_rec *e = malloc((size_t)(3 * nt + 1) * sizeof *e);
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = m->triangles[3 * t + k], b = m->triangles[3 * t + (k + 1) % 3];
            if (a < 0 || a >= nv || a == b) {
                fprintf(stderr, "triangle %lld: bad or repeated index\n", (long long)t);
                free(e);
                return 1;
            }
            e[3 * t + k] = (edge_rec){a < b ? a : b, a < b ? b : a, a < b};
        }
    qsort(e, (size_t)(3 * nt), sizeof *e, edge_cmp);
    for (int64_t i = 0; i < 3 * nt;) {
        int64_t j = i;
        while (j < 3 * nt && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        if (j - i != 2 || e[i].fwd == e[i + 1].fwd) {
            fprintf(stderr, "edge %d-%d: %lld uses\n", e[i].lo, e[i].hi, (long long)(j - i));
            free(e);
            return 1;
        }
        i = j;
    }
    free(e);
    /* vertex links: for each vertex, the opposite edges (b -> c) of its
     * triangles must chain into a single cycle */
    int64_t *deg = calloc((size_t)nv + 1, sizeof *deg);
    for (int64_t t = 0; t < 3 * nt; t++) deg[m->triangles[t] + 1]++;
    for (int64_t v = 0; v < nv; v++) deg[v + 1] += deg[v];
    int32_t *nb = malloc((size_t)(6 * nt + 2) * sizeof *nb);
    int64_t *cur = malloc((size_t)(nv + 1) * sizeof *cur);
    memcpy(cur, deg, (size_t)(nv + 1) * sizeof *cur);
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t v = m->triangles[3 * t + k];
            nb[2 * cur[v]] = m->triangles[3 * t + (k + 1) % 3];
            nb[2 * cur[v] + 1] = m->triangles[3 * t + (k + 2) % 3];
            cur[v]++;
        }
    int bad = 0;
    for (int64_t v = 0; v < nv && !bad; v++) {
        int64_t s = deg[v], n = deg[v + 1] - s;
        if (n == 0) {
            fprintf(stderr, "vertex %lld unused\n", (long long)v);
            bad = 1;
            break;
        }
        int32_t first = nb[2 * s], x = nb[2 * s + 1];
        int64_t steps = 1;
        while (x != first && steps <= n) {
            int64_t k = 0;
            while (k < n && nb[2 * (s + k)] != x) k++;
            if (k == n) break;
            x = nb[2 * (s + k) + 1];
            steps++;
        }
        if (x != first || steps != n) {
            fprintf(stderr, "vertex %lld: link is not one cycle (%lld of %lld)\n", (long long)v,
                    (long long)steps, (long long)n);
            bad = 1;
        }
    }
    free(deg);
    free(nb);
    free(cur);
    return bad;
}

static double mesh_volume(const bvox_mesh *m)
{
    double v = 0;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const double *a = m->vertices + 3 * m->triangles[3 * t],
                     *b = m->vertices + 3 * m->triangles[3 * t + 1],
                     *c = m->vertices + 3 * m->triangles[3 * t + 2];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
             a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6;
}

static bvox_mesh *mesh_of(const bvox_volume *v, bvox_mesh_method method)
{
    bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
    o.method = method;
    bvox_mesh *m = NULL;
    if (bvox_mesh_from_volume(v, &o, &m) != BVOX_OK) {
        fprintf(stderr, "meshing failed: %s\n", bvox_errmsg());
        return NULL;
    }
    return m;
}

static bvox_volume *random_volume(bvox_dims d, unsigned percent)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create(d, &v) != BVOX_OK) return NULL;
    for (int32_t z = 0; z < d.nz; z++)
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++)
                if (harness_rand() % 100 < percent) bvox_volume_set(v, x, y, z, 1);
    return v;
}

/* Exposed voxel faces and "diagonal" voxel edges (the four voxels around
 * the edge are 1, 0, 1, 0), counted voxel by voxel: cuberille gives two
 * triangles per face plus one per face for each diagonal edge it borders
 * (four per diagonal edge). */
static int64_t cuberille_triangles(const bvox_volume *v)
{
    bvox_dims d = bvox_volume_dims(v);
    int64_t faces = 0, diag = 0;
    for (int32_t z = -1; z <= d.nz; z++)
        for (int32_t y = -1; y <= d.ny; y++)
            for (int32_t x = -1; x <= d.nx; x++) {
                int a = bvox_volume_get(v, x, y, z);
                faces += a != bvox_volume_get(v, x + 1, y, z);
                faces += a != bvox_volume_get(v, x, y + 1, z);
                faces += a != bvox_volume_get(v, x, y, z + 1);
                /* the edges through the corner (x+1/2, y+1/2, z+1/2) along z, x, y */
                int q[3][4] = {{a, bvox_volume_get(v, x + 1, y, z), bvox_volume_get(v, x, y + 1, z),
                                bvox_volume_get(v, x + 1, y + 1, z)},
                               {a, bvox_volume_get(v, x, y + 1, z), bvox_volume_get(v, x, y, z + 1),
                                bvox_volume_get(v, x, y + 1, z + 1)},
                               {a, bvox_volume_get(v, x + 1, y, z), bvox_volume_get(v, x, y, z + 1),
                                bvox_volume_get(v, x + 1, y, z + 1)}};
                for (int k = 0; k < 3; k++)
                    diag += q[k][0] == q[k][3] && q[k][1] == q[k][2] && q[k][0] != q[k][1];
            }
    return 2 * faces + 4 * diag;
}

/* ---- hand-computed cases ---- */

TEST(single_voxel)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){1, 1, 1}, &v));
    CHECK_OK(bvox_volume_set(v, 0, 0, 0, 1));
    bvox_mesh *m = mesh_of(v, BVOX_MESH_MC);
    CHECK(m);
    /* an octahedron: 6 edge midpoints at 0.5 from the centre, 8 faces */
    CHECK_EQ(m->nvertices, 6);
    CHECK_EQ(m->ntriangles, 8);
    CHECK_NEAR(mesh_volume(m), 1.0 / 6.0, 1e-12);
    CHECK(check_manifold(m) == 0);
    bvox_mesh_destroy(m);
    m = mesh_of(v, BVOX_MESH_CUBERILLE);
    CHECK(m);
    CHECK_EQ(m->nvertices, 8);
    CHECK_EQ(m->ntriangles, 12);
    CHECK_NEAR(mesh_volume(m), 1.0, 1e-12);
    CHECK(check_manifold(m) == 0);
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.area, 6.0, 1e-12);
    CHECK_NEAR(info.bbox_min[0], -0.5, 0);
    CHECK_NEAR(info.bbox_max[2], 0.5, 0);
    bvox_mesh_destroy(m);
    bvox_volume_destroy(v);
    return 0;
}

TEST(empty_and_full)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 4, 70}, &v));
    bvox_mesh *m = mesh_of(v, BVOX_MESH_MC);
    CHECK(m);
    CHECK_EQ(m->ntriangles, 0);
    bvox_mesh_destroy(m);
    bvox_volume_fill(v, 1);
    m = mesh_of(v, BVOX_MESH_CUBERILLE);
    CHECK(m);
    CHECK_NEAR(mesh_volume(m), 3 * 4 * 70, 1e-9);
    CHECK_EQ(m->ntriangles, 2 * 2 * (3 * 4 + 4 * 70 + 3 * 70));
    CHECK(check_manifold(m) == 0);
    bvox_mesh_destroy(m);
    m = mesh_of(v, BVOX_MESH_MC);
    CHECK(m);
    CHECK(check_manifold(m) == 0);
    /* a box: marching cubes cuts its 12 edges off */
    CHECK(mesh_volume(m) < 3 * 4 * 70 && mesh_volume(m) > 3 * 4 * 70 - (3 + 4 + 70));
    bvox_mesh_destroy(m);
    bvox_volume_destroy(v);
    return 0;
}

/* Two voxels touching along an edge, then at a corner only: cuberille
 * duplicates the shared corners (two separate cubes; along the shared edge
 * each cube also gets its own midpoint vertex, splitting its two faces
 * there: +2 vertices, +4 triangles), marching cubes keeps two separate
 * octahedra (the 1-voxels are 6-connected). */
TEST(diagonal_touching)
{
    static const int32_t other[2][3] = {{1, 1, 0}, {1, 1, 1}};
    for (int c = 0; c < 2; c++) {
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
        CHECK_OK(bvox_volume_set(v, 0, 0, 0, 1));
        CHECK_OK(bvox_volume_set(v, other[c][0], other[c][1], other[c][2], 1));
        bvox_mesh *m = mesh_of(v, BVOX_MESH_CUBERILLE);
        CHECK(m);
        CHECK_EQ(m->nvertices, c == 0 ? 18 : 16);
        CHECK_EQ(m->ntriangles, c == 0 ? 28 : 24);
        CHECK_NEAR(mesh_volume(m), 2.0, 1e-12);
        CHECK(check_manifold(m) == 0);
        bvox_mesh_destroy(m);
        m = mesh_of(v, BVOX_MESH_MC);
        CHECK(m);
        CHECK_EQ(m->nvertices, 12);
        CHECK_EQ(m->ntriangles, 16);
        CHECK_NEAR(mesh_volume(m), 2.0 / 6.0, 1e-12);
        CHECK(check_manifold(m) == 0);
        bvox_mesh_destroy(m);
        bvox_volume_destroy(v);
    }
    return 0;
}

/* All 256 configurations of one cell (a 2x2x2 volume): closed, manifold,
 * positive volume. */
TEST(all_cell_cases)
{
    for (int k = 1; k < 256; k++) {
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
        for (int b = 0; b < 8; b++)
            if (k >> b & 1) CHECK_OK(bvox_volume_set(v, b & 1, b >> 1 & 1, b >> 2 & 1, 1));
        for (int meth = 0; meth < 2; meth++) {
            bvox_mesh *m = mesh_of(v, (bvox_mesh_method)meth);
            CHECK(m);
            if (check_manifold(m)) {
                fprintf(stderr, "case %d method %d\n", k, meth);
                return 1;
            }
            double vol = mesh_volume(m);
            CHECK(vol > 0);
            if (meth == 1) CHECK_NEAR(vol, __builtin_popcount((unsigned)k), 1e-12);
            bvox_mesh_destroy(m);
        }
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(random_volumes_manifold)
{
    static const bvox_dims sizes[] = {{1, 1, 1},  {1, 1, 64}, {2, 3, 65}, {3, 5, 7},
                                      {7, 3, 64}, {5, 4, 129}, {9, 1, 63}, {1, 8, 128},
                                      {6, 6, 6},  {11, 7, 33}};
    static const unsigned dens[] = {5, 30, 50, 70, 95};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (size_t d = 0; d < sizeof dens / sizeof dens[0]; d++) {
            bvox_volume *v = random_volume(sizes[s], dens[d]);
            CHECK(v);
            CHECK_OK(bvox_volume_set_spacing(v, 0.5, 1.25, 2.0, NULL));
            int64_t count = bvox_volume_count(v);
            for (int meth = 0; meth < 2; meth++) {
                bvox_mesh *m = mesh_of(v, (bvox_mesh_method)meth);
                CHECK(m);
                if (check_manifold(m)) {
                    fprintf(stderr, "size %d %d %d density %u method %d\n", sizes[s].nx,
                            sizes[s].ny, sizes[s].nz, dens[d], meth);
                    return 1;
                }
                bvox_mesh_info info;
                CHECK_OK(bvox_mesh_measure(m, &info));
                CHECK_EQ(info.boundary_edges, 0);
                CHECK_EQ(info.nonmanifold_edges, 0);
                CHECK_EQ(info.inconsistent_edges, 0);
                CHECK(info.watertight == (count > 0));
                if (meth == 1) {
                    CHECK_NEAR(info.volume, count * 0.5 * 1.25 * 2.0, 1e-9 * (count + 1));
                    CHECK_EQ(m->ntriangles, cuberille_triangles(v));
                }
                else CHECK(count == 0 || info.volume > 0);
                bvox_mesh_destroy(m);
            }
            bvox_volume_destroy(v);
        }
    return 0;
}

TEST(sphere_volume_r40)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){90, 91, 92}, &v));
    bvox_shape s = {.kind = BVOX_SHAPE_SPHERE, .center = {44.5, 45.25, 45.9}, .radius = 40};
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    double exact = 4.0 / 3.0 * M_PI * 40 * 40 * 40;
    bvox_mesh *m = mesh_of(v, BVOX_MESH_MC);
    CHECK(m);
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_EQ(info.inconsistent_edges, 0);
    CHECK_NEAR(info.volume / exact, 1.0, 0.01);
    /* the area of a sphere: marching cubes ~1.08x, cuberille ~1.5x */
    CHECK_NEAR(info.area / (4 * M_PI * 1600), 1.08, 0.04); /* binary MC overestimates ~8 % */
    bvox_mesh_destroy(m);
    m = mesh_of(v, BVOX_MESH_CUBERILLE);
    CHECK(m);
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.volume, (double)bvox_volume_count(v), 1e-6);
    CHECK_NEAR(info.area / (4 * M_PI * 1600), 1.5, 0.1);
    /* smoothing: the volume stays within 1 %, the staircase area goes */
    double before = info.volume;
    CHECK_OK(bvox_mesh_smooth(m, 20, 0.5, -0.53));
    bvox_mesh_info after;
    CHECK_OK(bvox_mesh_measure(m, &after));
    CHECK_NEAR(after.volume / before, 1.0, 0.01);
    CHECK(after.area < info.area * 0.8);
    bvox_mesh_destroy(m);
    bvox_volume_destroy(v);
    return 0;
}

TEST(geometry_honoured)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 5, 6}, &v));
    bvox_volume_fill_box(v, (bvox_box){1, 2, 3, 3, 4, 5}, 1);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.5;
    g.spacing[1] = 2;
    g.spacing[2] = 3;
    g.origin[0] = 10;
    g.origin[1] = -20;
    g.origin[2] = 30;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    for (int meth = 0; meth < 2; meth++) {
        bvox_mesh *m = mesh_of(v, (bvox_mesh_method)meth);
        CHECK(m);
        bvox_mesh_info info;
        CHECK_OK(bvox_mesh_measure(m, &info));
        /* voxels 1..2 along x: faces at (1 - 0.5) and (2 + 0.5) voxel units */
        CHECK_NEAR(info.bbox_min[0], 10 + 0.5 * 0.5, 1e-12);
        CHECK_NEAR(info.bbox_max[0], 10 + 2.5 * 0.5, 1e-12);
        CHECK_NEAR(info.bbox_min[1], -20 + 1.5 * 2, 1e-12);
        CHECK_NEAR(info.bbox_max[1], -20 + 3.5 * 2, 1e-12);
        CHECK_NEAR(info.bbox_min[2], 30 + 2.5 * 3, 1e-12);
        CHECK_NEAR(info.bbox_max[2], 30 + 4.5 * 3, 1e-12);
        if (meth == 1) CHECK_NEAR(info.volume, 8 * 0.5 * 2 * 3, 1e-9);
        CHECK(info.volume > 0);
        bvox_mesh_destroy(m);
    }
    /* a mirrored frame (x axis reversed): still outward */
    g.direction[0] = -1;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    for (int meth = 0; meth < 2; meth++) {
        bvox_mesh *m = mesh_of(v, (bvox_mesh_method)meth);
        CHECK(m);
        bvox_mesh_info info;
        CHECK_OK(bvox_mesh_measure(m, &info));
        CHECK(info.volume > 0);
        CHECK_NEAR(info.bbox_max[0], 10 - 0.5 * 0.5, 1e-12);
        CHECK_EQ(info.inconsistent_edges, 0);
        bvox_mesh_destroy(m);
    }
    bvox_volume_destroy(v);
    return 0;
}

TEST(threads_do_not_change_result)
{
    bvox_volume *v = random_volume((bvox_dims){37, 29, 131}, 50);
    CHECK(v);
    for (int meth = 0; meth < 2; meth++) {
        bvox_set_threads(1);
        bvox_mesh *a = mesh_of(v, (bvox_mesh_method)meth);
        bvox_set_threads(3);
        bvox_mesh *b = mesh_of(v, (bvox_mesh_method)meth);
        bvox_set_threads(0);
        CHECK(a && b);
        CHECK_EQ(a->nvertices, b->nvertices);
        CHECK_EQ(a->ntriangles, b->ntriangles);
        CHECK(!memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double)));
        CHECK(!memcmp(a->triangles, b->triangles, (size_t)a->ntriangles * 3 * sizeof(int32_t)));
        bvox_mesh_destroy(a);
        bvox_mesh_destroy(b);
    }
    bvox_volume_destroy(v);
    return 0;
}

TEST(allocation_failures_are_clean)
{
    bvox_volume *v = random_volume((bvox_dims){9, 8, 70}, 40);
    CHECK(v);
    size_t base = bvox_memory_in_use();
    for (int meth = 0; meth < 2; meth++)
        for (long n = 1; n < 40; n++) {
            bvox__alloc_fail_after(n);
            bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
            o.method = (bvox_mesh_method)meth;
            o.smooth = 1;
            bvox_mesh *m = NULL;
            bvox_status st = bvox_mesh_from_volume(v, &o, &m);
            bvox__alloc_fail_after(0);
            if (st == BVOX_OK) {
                CHECK(m);
                bvox_mesh_destroy(m);
            } else {
                CHECK(m == NULL);
            }
            CHECK_EQ(bvox_memory_in_use(), base);
        }
    bvox_volume_destroy(v);
    return 0;
}
