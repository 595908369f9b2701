/* test_stream_mesh.c — marching cubes by slabs written to a file as it is
 * made (bvox__stream_mesh_write, src/mesh/mesh_sink.c) against the
 * in-memory mesh written by bvox_mesh_write: for every format (binary and
 * ASCII STL and PLY, OBJ, OFF) and slabs of 1, 2, 7 slices and the
 * budget's depth, the file read back holds the same triangles (up to order)
 * and the same number of vertices; binary and ASCII STL are the same bytes
 * count; the measures gathered while streaming equal bvox_mesh_measure's.
 * The specimen (odd sizes, anisotropic voxels, an origin) has noise, boxes and
 * a ball crossing slab borders and triangles lying flat in slice planes.
 * Also: a mesh larger than the memory budget is written while the whole
 * mesh could not be held, and failures (writes, allocations) leave nothing. */
#include "harness.h"
#include "io/io.h"
#include "ref/voxref.h"
#include "stream/stream.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static bvox_volume *specimen(int nx, int ny, int nz)
{
    voxref *r = voxref_create(nx, ny, nz);
    voxref *noise = voxref_create(nx, ny, nz);
    voxref_random(noise, 1, 5, harness_rand);
    voxref_fill_box(noise, (bvox_box){nx / 2, 0, 0, nx, ny, nz}, 0);
    voxref_csg(r, BVOX_CSG_UNION, noise, (int[3]){0, 0, 0});
    voxref_destroy(noise);
    /* boxes whose faces lie on many slice planes, one hollow */
    voxref_fill_box(r, (bvox_box){nx / 2 + 1, 2, 3, nx - 2, ny / 2, nz / 2}, 1);
    voxref_fill_box(r, (bvox_box){nx / 2 + 3, 4, 6, nx - 4, ny / 2 - 2, nz / 2 - 3}, 0);
    /* one-voxel steps along z: a staircase */
    for (int z = 0; z < nz; z++)
        for (int x = nx / 2 + 1; x < nx / 2 + 1 + (z % 7); x++) *voxref_at(r, x, ny - 2, z) = 1;
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = nx / 2; x < nx; x++) {
                double dx = x - 0.75 * nx, dy = y - 0.6 * ny, dz = z - 0.5 * nz;
                if (dx * dx + dy * dy + dz * dz <= 7.3 * 7.3) *voxref_at(r, x, y, z) = 1;
            }
    bvox_volume *v = voxref_to_volume(r);
    voxref_destroy(r);
    bvox_geometry g = *bvox_volume_geometry(v);
    g.spacing[0] = 0.5, g.spacing[1] = 0.75, g.spacing[2] = 1.25;
    g.origin[0] = -3, g.origin[1] = 2.5, g.origin[2] = 10;
    bvox_volume_set_geometry(v, &g);
    return v;
}

/* The two files hold the same triangles and vertex counts. */
static int same_mesh_files(const char *a, const char *b)
{
    bvox_mesh *ma, *mb;
    CHECK_OK(bvox_mesh_read(a, NULL, &ma));
    CHECK_OK(bvox_mesh_read(b, NULL, &mb));
    CHECK_EQ(ma->ntriangles, mb->ntriangles);
    CHECK_EQ(ma->nvertices, mb->nvertices);
    double *ta = harness_mesh_canon(ma), *tb = harness_mesh_canon(mb);
    int same = !memcmp(ta, tb, (size_t)ma->ntriangles * 9 * sizeof *ta);
    free(ta);
    free(tb);
    bvox_mesh_destroy(ma);
    bvox_mesh_destroy(mb);
    CHECK(same);
    return 0;
}

static long long file_size(const char *p)
{
    struct stat sb;
    return stat(p, &sb) ? -1 : (long long)sb.st_size;
}

/* Triangles with a vertex in slice plane P (a multiple of 14: where slabs
 * of 1, 2 and 7 slices meet) and the others below it (sign -1) or above it
 * (sign 1): the vertices two slabs share. bvox's marching cubes makes no
 * triangle lying flat in a slice plane (a loop of one cell never has three
 * points on one face: checked on half-density noise, none), so the rule for
 * those is not reached by any volume. */
static int64_t touching_planes(const bvox_mesh *m, const bvox_geometry *g, int sign)
{
    int64_t n = 0;
    for (int64_t k = 0; k < m->ntriangles; k++) {
        double z[3], plane = -1;
        for (int i = 0; i < 3; i++) {
            z[i] = (m->vertices[3 * m->triangles[3 * k + i] + 2] - g->origin[2]) / g->spacing[2];
            if (z[i] == floor(z[i]) && (int64_t)z[i] % 14 == 0) plane = z[i];
        }
        if (z[0] == z[1] && z[1] == z[2] && z[0] == floor(z[0])) return -1; /* flat */
        if (plane < 0) continue;
        int side = 0; /* the vertices off the plane, all on one side (one cell) */
        for (int i = 0; i < 3; i++)
            if (z[i] != plane) side = z[i] > plane ? 1 : -1;
        n += side == sign;
    }
    return n;
}

static const int32_t caps[] = {1, 2, 7, 0};
static const struct {
    const char *ext;
    int ascii;
} formats[] = {{"stl", 0}, {"stl", 1}, {"ply", 0}, {"ply", 1}, {"obj", 0}, {"off", 0}};

TEST(file_equals_in_memory_every_format)
{
    bvox_volume *v = specimen(41, 37, 57);
    bvox_mesh *want;
    CHECK_OK(bvox_mesh_from_volume(v, NULL, &want));
    CHECK(touching_planes(want, bvox_volume_geometry(v), -1) > 0);
    CHECK(touching_planes(want, bvox_volume_geometry(v), 1) > 0);
    bvox_mesh_info wi;
    CHECK_OK(bvox_mesh_measure(want, &wi));
    CHECK(wi.watertight);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    for (size_t f = 0; f < sizeof formats / sizeof formats[0]; f++) {
        char mem[64], str[64];
        snprintf(mem, sizeof mem, "mem%d.%s", formats[f].ascii, formats[f].ext);
        snprintf(str, sizeof str, "str%d.%s", formats[f].ascii, formats[f].ext);
        char *pm = strdup(harness_path(mem)), *ps = strdup(harness_path(str));
        CHECK_OK(bvox_mesh_write(pm, want, formats[f].ext, formats[f].ascii));
        for (size_t cp = 0; cp < sizeof caps / sizeof caps[0]; cp++) {
            bvox__stream_set_depth_cap(caps[cp]);
            bvox_mesh_info gi;
            CHECK_OK(bvox__stream_mesh_write(&src, ps, NULL, formats[f].ascii, &gi, true));
            if (same_mesh_files(pm, ps)) {
                fprintf(stderr, "%s, slabs of %d\n", str, caps[cp]);
                return 1;
            }
            if (!strcmp(formats[f].ext, "stl")) /* no header counts to pad */
                CHECK_EQ(file_size(ps), file_size(pm));
            else if (!formats[f].ascii && strcmp(formats[f].ext, "obj") && strcmp(formats[f].ext, "off"))
                /* binary PLY: the same records, the header padded to its widest */
                CHECK(file_size(ps) > file_size(pm) && file_size(ps) < file_size(pm) + 64);
            /* measured on the way: as bvox_mesh_measure */
            CHECK_EQ(gi.vertices, wi.vertices);
            CHECK_EQ(gi.triangles, wi.triangles);
            CHECK_EQ(gi.edges, wi.edges);
            CHECK_EQ(gi.boundary_edges, 0);
            CHECK_EQ(gi.nonmanifold_edges, wi.nonmanifold_edges);
            CHECK_EQ(gi.inconsistent_edges, wi.inconsistent_edges);
            CHECK_EQ(gi.degenerate_triangles, wi.degenerate_triangles);
            CHECK_EQ(gi.watertight, 1);
            for (int k = 0; k < 3; k++) {
                CHECK(gi.bbox_min[k] == wi.bbox_min[k]);
                CHECK(gi.bbox_max[k] == wi.bbox_max[k]);
            }
            CHECK_NEAR(gi.volume, wi.volume, 1e-9 * wi.volume);
            CHECK_NEAR(gi.area, wi.area, 1e-9 * wi.area);
        }
        free(pm);
        free(ps);
    }
    bvox__stream_set_depth_cap(0);
    /* nothing but the outputs: the faces' temporary files are gone */
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 2 * (int)(sizeof formats / sizeof formats[0]));
    bvox_mesh_destroy(want);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Vertices of two slabs meet only in their seam plane: the streamed
 * indices are those of a mesh welded as in memory (PLY read back keeps the
 * file's vertices as they are: none twice, none unused). */
TEST(seam_vertices_written_once)
{
    bvox_volume *v = specimen(30, 33, 40);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    const char *p = harness_path("seam.ply");
    bvox__stream_set_depth_cap(1);
    CHECK_OK(bvox__stream_mesh_write(&src, p, NULL, 0, NULL, false));
    bvox__stream_set_depth_cap(0);
    bvox_mesh *m;
    CHECK_OK(bvox_mesh_read(p, NULL, &m));
    bvox_mesh_info mi;
    CHECK_OK(bvox_mesh_measure(m, &mi));
    CHECK(mi.watertight);
    CHECK_EQ(mi.inconsistent_edges, 0);
    char *used = calloc((size_t)m->nvertices, 1);
    for (int64_t i = 0; i < 3 * m->ntriangles; i++) used[m->triangles[i]] = 1;
    for (int64_t i = 0; i < m->nvertices; i++) CHECK(used[i]);
    free(used);
    bvox_mesh_destroy(m);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}

/* The whole mesh does not fit the budget (in memory: BVOX_ETOOBIG), one
 * slab's does: the streamed file is written, and equals the mesh made
 * without the budget. The first slab planned from the voxels alone is too
 * deep for its mesh and is retried thinner. */
TEST(mesh_over_budget_streams)
{
    bvox_volume *v = specimen(64, 64, 300); /* noise: about 10^6 triangles */
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    size_t old = bvox_memory_budget();
    bvox_set_memory_budget(bvox_memory_in_use() + ((size_t)12 << 20));
    bvox_mesh *m = NULL;
    CHECK_STATUS(bvox_mesh_from_volume(v, NULL, &m), BVOX_ETOOBIG);
    const char *p = harness_path("big.ply");
    bvox_mesh_info gi;
    bvox_status st = bvox__stream_mesh_write(&src, p, NULL, 0, &gi, true);
    bvox_set_memory_budget(old);
    CHECK_OK(st);
    CHECK_OK(bvox_mesh_from_volume(v, NULL, &m));
    /* over the budget: vertices and triangles of 24 and 12 bytes */
    CHECK(m->nvertices * 24 + m->ntriangles * 12 > ((int64_t)12 << 20));
    CHECK_EQ(gi.triangles, m->ntriangles);
    CHECK_EQ(gi.vertices, m->nvertices);
    CHECK_OK(bvox_mesh_write(harness_path("want.ply"), m, NULL, 0));
    bvox_mesh_destroy(m);
    if (same_mesh_files(harness_path("want.ply"), p)) return 1;
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}

/* A failed write or allocation anywhere leaves no file (neither the output
 * nor the faces' temporary file) and no memory in use. */
TEST(failures_leave_nothing)
{
    bvox_volume *v = specimen(20, 21, 30);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    const char *p = harness_path("fail.ply");
    bvox__stream_set_depth_cap(4);
    size_t base = bvox_memory_in_use();
    for (long n = 1; n <= 3; n++) { /* the faces, the vertices, the faces appended */
        bvox__sink_fail_after(n);
        bvox_status st = bvox__stream_mesh_write(&src, p, NULL, 1, NULL, false);
        bvox__sink_fail_after(0);
        CHECK_STATUS(st, BVOX_EIO);
        CHECK_EQ(harness_count_entries(harness_tmpdir()), 0);
        CHECK_EQ(bvox_memory_in_use(), base);
    }
    bvox_mesh_info mi;
    int done = 0;
    for (long n = 1; !done && n < 100000; n++) {
        bvox__alloc_fail_after(n);
        bvox_status st = bvox__stream_mesh_write(&src, p, "off", 0, &mi, true);
        done = bvox__alloc_fail_pending() > 0;
        bvox__alloc_fail_after(0);
        if (done) {
            CHECK_OK(st);
            break;
        }
        CHECK_STATUS(st, BVOX_ENOMEM);
        CHECK_EQ(harness_count_entries(harness_tmpdir()), 0);
        CHECK_EQ(bvox_memory_in_use(), base);
    }
    CHECK(done);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    bvox__stream_set_depth_cap(0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}

/* An unknown format is refused before anything is made. */
TEST(unknown_format_refused)
{
    bvox_volume *v = specimen(10, 10, 10);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    CHECK_STATUS(bvox__stream_mesh_write(&src, harness_path("x.vtk"), NULL, 0, NULL, false),
                 BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "x.vtk") != NULL);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}
