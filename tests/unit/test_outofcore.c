/* test_outofcore.c — the out-of-core operations (src/stream/) against the
 * in-memory ones on volumes small enough for both: info, every field of
 * bvox_measure (bit for bit), components with 6/18/26 connectivity (count,
 * sizes, boxes, order), morphology and CSG voxels, marching-cubes
 * triangles. Slabs are forced thin (1, 2, 7 slices) so that objects cross
 * many slab faces, and the .zarr source and sink are run with an odd chunk
 * shape (37 x 100 x 65). The specimen has noise (many small components,
 * ties in size), a hollow box (cavities), a frame (a tunnel), a diagonal
 * line (joined only through corners, 26-connected) and a ball crossing
 * chunk corners. */
#include "harness.h"
#include "ref/voxref.h"
#include "stream/stream.h"

#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static bvox_volume *specimen(int nx, int ny, int nz, unsigned seed_parts)
{
    voxref *r = voxref_create(nx, ny, nz);
    voxref *noise = voxref_create(nx, ny, nz);
    voxref_random(noise, 1, 7, harness_rand);
    /* noise only in a slab of x, so the rest holds the big shapes */
    voxref_fill_box(noise, (bvox_box){nx / 3, 0, 0, nx, ny, nz}, 0);
    voxref_csg(r, BVOX_CSG_UNION, noise, (int[3]){0, 0, 0});
    voxref_destroy(noise);
    /* hollow box: two cavities (inner void split by a wall) */
    voxref_fill_box(r, (bvox_box){nx / 3 + 2, 10, 50, nx / 3 + 20, 40, 80}, 1);
    voxref_fill_box(r, (bvox_box){nx / 3 + 4, 12, 52, nx / 3 + 18, 38, 64}, 0);
    voxref_fill_box(r, (bvox_box){nx / 3 + 4, 12, 66, nx / 3 + 18, 38, 78}, 0);
    /* a frame around z: a tunnel along z crossing slabs */
    voxref_fill_box(r, (bvox_box){nx / 3 + 22, 50, 20, nx / 3 + 34, 62, nz - 5}, 1);
    voxref_fill_box(r, (bvox_box){nx / 3 + 25, 53, 20, nx / 3 + 31, 59, nz - 5}, 0);
    /* diagonal line: each voxel touches the next by a corner only */
    for (int k = 0; k < 40 && k + 30 < nz && ny > 90; k++)
        *voxref_at(r, nx / 3 + 1 + k / 2, 70 + k / 2, k + 30) = 1;
    for (int k = 0; k < 60 && k + 60 < nz && ny > 100; k++)
        *voxref_at(r, nx - 2 - k / 3, 100 - k, k + 60) = 1;
    /* a ball around a chunk corner (37, 100, 65) when it fits */
    if (seed_parts)
        for (int z = 0; z < nz; z++)
            for (int y = 0; y < ny; y++)
                for (int x = 0; x < nx; x++) {
                    double dx = x - 37.5, dy = y - 99.5, dz = z - 64.5;
                    if (dx * dx + dy * dy + dz * dz <= 9.5 * 9.5) *voxref_at(r, x, y, z) = 1;
                }
    bvox_volume *v = voxref_to_volume(r);
    voxref_destroy(r);
    bvox_geometry g = *bvox_volume_geometry(v);
    g.spacing[0] = 0.5, g.spacing[1] = 0.5, g.spacing[2] = 1.25;
    g.origin[0] = 0, g.origin[1] = 0, g.origin[2] = 0;
    strcpy(g.unit, "um");
    bvox_volume_set_geometry(v, &g);
    return v;
}

/* Entries of a folder (not . and ..). */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

static const int32_t caps[] = {1, 2, 7, 0};

TEST(info_and_measure_equal_in_memory)
{
    bvox_volume *v = specimen(70, 120, 150, 1);
    bvox_info want_i;
    CHECK_OK(bvox_info_compute(v, &want_i));
    bvox_measures want;
    CHECK_OK(bvox_measure(v, &want));
    CHECK(want.cavities >= 2 && want.tunnels >= 1); /* the specimen is what it says */
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    for (size_t c = 0; c < sizeof caps / sizeof caps[0]; c++) {
        bvox__stream_set_depth_cap(caps[c]);
        bvox_info got_i;
        CHECK_OK(bvox__stream_info(&src, &got_i));
        CHECK_EQ(got_i.count, want_i.count);
        CHECK(!memcmp(&got_i.bbox, &want_i.bbox, sizeof got_i.bbox));
        CHECK(got_i.volume == want_i.volume);
        bvox_measures got;
        CHECK_OK(bvox__stream_measure(&src, &got));
        CHECK_EQ(got.count, want.count);
        CHECK_EQ(got.euler, want.euler);
        CHECK_EQ(got.components, want.components);
        CHECK_EQ(got.cavities, want.cavities);
        CHECK_EQ(got.cavities_26, want.cavities_26);
        CHECK_EQ(got.tunnels, want.tunnels);
        for (int a = 0; a < 3; a++) CHECK_EQ(got.faces[a], want.faces[a]);
        CHECK(!memcmp(&got, &want, sizeof got)); /* areas, moments, axes: bit for bit */
    }
    bvox__stream_set_depth_cap(0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(measure_empty_full_and_one_slice)
{
    static const int dims[][3] = {{5, 6, 1}, {4, 4, 9}, {3, 2, 130}};
    for (size_t i = 0; i < 3; i++) {
        for (int fill = 0; fill < 2; fill++) {
            bvox_volume *v;
            CHECK_OK(bvox_volume_create((bvox_dims){dims[i][0], dims[i][1], dims[i][2]}, &v));
            bvox_volume_fill(v, fill);
            bvox_measures want, got;
            CHECK_OK(bvox_measure(v, &want));
            bvox__slab_source src;
            CHECK_OK(bvox__slab_source_memory(v, &src));
            bvox__stream_set_depth_cap(1);
            CHECK_OK(bvox__stream_measure(&src, &got));
            bvox__stream_set_depth_cap(0);
            CHECK_EQ(got.count, want.count);
            CHECK_EQ(got.euler, want.euler);
            CHECK_EQ(got.components, want.components);
            CHECK_EQ(got.cavities, want.cavities);
            CHECK_EQ(got.tunnels, want.tunnels);
            CHECK(!memcmp(&got, &want, sizeof got));
            bvox__slab_source_close(&src);
            bvox_volume_destroy(v);
        }
    }
    return 0;
}

TEST(components_equal_in_memory)
{
    bvox_volume *v = specimen(70, 120, 150, 1);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    static const int conns[] = {6, 18, 26};
    for (int k = 0; k < 3; k++) {
        bvox_components *c;
        CHECK_OK(bvox_components_find(v, conns[k], &c));
        int64_t n = bvox_components_count(c);
        CHECK(n > 100);
        for (size_t cp = 0; cp < sizeof caps / sizeof caps[0]; cp++) {
            bvox__stream_set_depth_cap(caps[cp]);
            int64_t m;
            bvox_component *items;
            CHECK_OK(bvox__stream_components(&src, conns[k], &m, &items));
            CHECK_EQ(m, n);
            for (int64_t i = 0; i < n; i++) {
                const bvox_component *w = bvox_components_get(c, i);
                CHECK_EQ(items[i].voxels, w->voxels);
                CHECK(items[i].volume == w->volume);
                if (memcmp(&items[i].bbox, &w->bbox, sizeof w->bbox)) {
                    fprintf(stderr, "conn %d cap %d: component %lld differs\n", conns[k],
                            (int)caps[cp], (long long)i);
                    return 1;
                }
            }
            free(items);
        }
        bvox_components_destroy(c);
    }
    bvox__stream_set_depth_cap(0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

typedef struct mcase {
    bvox__stream_morph_op op;
    int conn;
    double radius;
} mcase;

static bvox_status morph_in_memory(const mcase *m, const bvox_volume *v, bvox_volume **out)
{
    bool ball = m->radius > 0;
    switch (m->op) {
    case BVOX__SM_DILATE:
        return ball ? bvox_morph_dilate_ball(v, m->radius, out)
                    : bvox_morph_dilate(v, m->conn, out);
    case BVOX__SM_ERODE:
        return ball ? bvox_morph_erode_ball(v, m->radius, out) : bvox_morph_erode(v, m->conn, out);
    case BVOX__SM_OPEN: return bvox_morph_open(v, m->conn, m->radius, out);
    default: return bvox_morph_close(v, m->conn, m->radius, out);
    }
}

TEST(morphology_equal_in_memory)
{
    bvox_volume *v = specimen(50, 110, 90, 1);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    static const mcase cases[] = {
        {BVOX__SM_DILATE, 6, 0},  {BVOX__SM_DILATE, 26, 0}, {BVOX__SM_ERODE, 18, 0},
        {BVOX__SM_ERODE, 26, 0},  {BVOX__SM_OPEN, 26, 0},   {BVOX__SM_CLOSE, 6, 0},
        {BVOX__SM_DILATE, 0, 2.6}, {BVOX__SM_ERODE, 0, 1.3}, {BVOX__SM_OPEN, 0, 1.3},
        {BVOX__SM_CLOSE, 0, 2.6},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bvox_volume *want;
        CHECK_OK(morph_in_memory(&cases[i], v, &want));
        for (size_t cp = 0; cp < sizeof caps / sizeof caps[0]; cp++) {
            bvox__stream_set_depth_cap(caps[cp]);
            bvox__slab_sink sink;
            bvox_volume *got = NULL;
            CHECK_OK(bvox__slab_sink_memory(bvox_volume_dims(v), bvox_volume_geometry(v), &got,
                                            &sink));
            bvox_status st = bvox__stream_morph(&src, cases[i].op, cases[i].conn,
                                                cases[i].radius, &sink);
            sink.close(&sink, true, &st);
            CHECK_OK(st);
            CHECK_OK(bvox_volume_check(got));
            if (!bvox_volume_equal(got, want)) {
                fprintf(stderr, "morph case %zu cap %d differs\n", i, (int)caps[cp]);
                return 1;
            }
            bvox_volume_destroy(got);
        }
        bvox_volume_destroy(want);
    }
    bvox__stream_set_depth_cap(0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(csg_equal_in_memory)
{
    bvox_volume *a = specimen(40, 70, 70, 0), *b = specimen(40, 70, 70, 0);
    bvox__slab_source sa, sb;
    CHECK_OK(bvox__slab_source_memory(a, &sa));
    CHECK_OK(bvox__slab_source_memory(b, &sb));
    for (int op = BVOX_CSG_UNION; op <= BVOX_CSG_XOR; op++) {
        bvox_volume *want;
        CHECK_OK(bvox_volume_copy(a, &want));
        CHECK_OK(bvox_csg_apply(want, (bvox_csg_op)op, b, NULL));
        bvox__stream_set_depth_cap(op == BVOX_CSG_XOR ? 1 : 5);
        bvox__slab_sink sink;
        bvox_volume *got = NULL;
        CHECK_OK(bvox__slab_sink_memory(bvox_volume_dims(a), bvox_volume_geometry(a), &got, &sink));
        bvox_status st = bvox__stream_csg(&sa, &sb, (bvox_csg_op)op, &sink);
        sink.close(&sink, true, &st);
        CHECK_OK(st);
        CHECK(bvox_volume_equal(got, want));
        bvox_volume_destroy(got);
        bvox_volume_destroy(want);
    }
    bvox__stream_set_depth_cap(0);
    /* different sizes: a clear error */
    bvox_volume *c;
    CHECK_OK(bvox_volume_create((bvox_dims){40, 70, 71}, &c));
    bvox__slab_source sc;
    CHECK_OK(bvox__slab_source_memory(c, &sc));
    bvox__slab_sink sink;
    bvox_volume *got = NULL;
    CHECK_OK(bvox__slab_sink_memory(bvox_volume_dims(a), bvox_volume_geometry(a), &got, &sink));
    bvox_status st = bvox__stream_csg(&sa, &sc, BVOX_CSG_UNION, &sink);
    sink.close(&sink, true, &st);
    CHECK_STATUS(st, BVOX_EINVAL);
    CHECK(got == NULL);
    CHECK(strstr(bvox_errmsg(), "differ in size") != NULL);
    bvox__slab_source_close(&sa);
    bvox__slab_source_close(&sb);
    bvox__slab_source_close(&sc);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    bvox_volume_destroy(c);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(zarr_source_and_sink_odd_chunks)
{
    bvox_volume *v = specimen(70, 120, 150, 1);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = 37, wo.chunks[1] = 100, wo.chunks[2] = 65;
    const char *p = harness_path("in.zarr");
    CHECK_OK(bvox_write(p, v, &wo));
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_zarr(p, NULL, &src));
    CHECK_EQ(src.chunk_z, 65);
    CHECK(src.geom.spacing[2] == 1.25);
    bvox_measures want, got;
    CHECK_OK(bvox_measure(v, &want));
    CHECK_OK(bvox__stream_measure(&src, &got));
    CHECK(!memcmp(&got, &want, sizeof got));
    bvox_components *c;
    CHECK_OK(bvox_components_find(v, 26, &c));
    int64_t m;
    bvox_component *items;
    CHECK_OK(bvox__stream_components(&src, 26, &m, &items));
    CHECK_EQ(m, bvox_components_count(c));
    for (int64_t i = 0; i < m; i++) CHECK_EQ(items[i].voxels, bvox_components_get(c, i)->voxels);
    free(items);
    bvox_components_destroy(c);
    /* dilation into a .zarr written slab by slab, chunks 20 x 33 x 17 */
    bvox_volume *want_v;
    CHECK_OK(bvox_morph_dilate_ball(v, 2.6, &want_v));
    bvox_write_opts wo2 = BVOX_WRITE_OPTS_INIT;
    wo2.chunks[0] = 20, wo2.chunks[1] = 33, wo2.chunks[2] = 17;
    wo2.compressor = "blosc";
    const char *q = harness_path("out.zarr");
    bvox__slab_sink sink;
    CHECK_OK(bvox__slab_sink_zarr(q, bvox_volume_dims(v), &src.geom, &wo2, &sink));
    CHECK_EQ(sink.align, 17);
    bvox_status st = bvox__stream_morph(&src, BVOX__SM_DILATE, 0, 2.6, &sink);
    sink.close(&sink, true, &st);
    CHECK_OK(st);
    bvox_volume *back;
    CHECK_OK(bvox_read(q, NULL, &back));
    CHECK(bvox_volume_equal(back, want_v));
    CHECK(bvox_volume_geometry(back)->spacing[2] == 1.25);
    bvox_volume_destroy(back);
    bvox_volume_destroy(want_v);
    /* a box read touches only its chunks: spoil a chunk outside the box */
    char chunk[4300];
    snprintf(chunk, sizeof chunk, "%s/0/2.1.1", p);
    FILE *f = fopen(chunk, "wb");
    CHECK(f != NULL);
    fputs("not zlib", f);
    fclose(f);
    bvox_volume *slab;
    CHECK_OK(src.read(&src, 0, 65, &slab)); /* z chunk 0 only */
    bvox_volume_destroy(slab);
    CHECK_STATUS(src.read(&src, 100, 140, &slab), BVOX_EFORMAT); /* z chunk 2 */
    CHECK(strstr(bvox_errmsg(), "2.1.1") != NULL);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(zarr_sink_failure_leaves_nothing)
{
    bvox_volume *v = specimen(20, 20, 40, 0);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    const char *q = harness_path("fail.zarr");
    bvox__slab_sink sink;
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[2] = 8;
    CHECK_OK(bvox__slab_sink_zarr(q, bvox_volume_dims(v), &src.geom, &wo, &sink));
    /* slabs written, then a failure elsewhere: closing removes everything */
    bvox_volume *slab;
    CHECK_OK(src.read(&src, 0, 16, &slab));
    CHECK_OK(sink.put(&sink, slab, 0));
    bvox_volume_destroy(slab);
    bvox_status st = BVOX_EIO;
    sink.close(&sink, true, &st);
    CHECK_STATUS(st, BVOX_EIO);
    CHECK_EQ(entries(harness_tmpdir()), 0);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}

TEST(mesh_equal_in_memory)
{
    bvox_volume *v = specimen(50, 110, 90, 1);
    bvox_mesh *want;
    CHECK_OK(bvox_mesh_from_volume(v, NULL, &want));
    double *tw = harness_mesh_canon(want);
    bvox__slab_source src;
    CHECK_OK(bvox__slab_source_memory(v, &src));
    for (size_t cp = 0; cp < sizeof caps / sizeof caps[0]; cp++) {
        bvox__stream_set_depth_cap(caps[cp]);
        bvox_mesh *got;
        CHECK_OK(bvox__stream_mesh(&src, &got));
        CHECK_EQ(got->ntriangles, want->ntriangles);
        CHECK_EQ(got->nvertices, want->nvertices); /* welded as in memory */
        double *tg = harness_mesh_canon(got);
        CHECK(!memcmp(tg, tw, (size_t)want->ntriangles * 9 * sizeof *tg));
        free(tg);
        bvox_mesh_destroy(got);
    }
    bvox__stream_set_depth_cap(0);
    free(tw);
    bvox_mesh_destroy(want);
    bvox__slab_source_close(&src);
    bvox_volume_destroy(v);
    return 0;
}
