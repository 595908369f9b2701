/* test_mesh_writer.c — bvox_mesh_writer (src/mesh/mesh_writer.c over
 * mesh_sink.c): an octahedron written as two pieces that share its four
 * equator vertices reads back as the octahedron bvox_mesh_write writes
 * whole (hand-made: 6 vertices, 8 triangles, closed) in every format; a
 * bad piece is refused before anything of it is written; a failed write
 * leaves no file. */
#include "harness.h"
#include "io/io.h"

#include <string.h>

/* Equator 0..3, then top (4) and bottom (5). */
static const double V[6][3] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

/* Piece 1: the top and the equator; piece 2: the equator (again, global
 * indices 0..3) and the bottom, in its own order. */
static bvox_status write_two(const char *path, int ascii)
{
    bvox_mesh_writer *w;
    bvox_status st = bvox_mesh_writer_open(path, NULL, ascii, &w);
    if (st) return st;
    const int32_t top[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    st = bvox_mesh_writer_add(w, &V[0][0], 5, NULL, top, 4);
    /* piece 2's vertices: bottom, then the equator backwards */
    const double v2[5][3] = {{0, 0, -1}, {0, -1, 0}, {-1, 0, 0}, {0, 1, 0}, {1, 0, 0}};
    const int64_t g2[5] = {-1, 3, 2, 1, 0};
    const int32_t bot[12] = {3, 4, 0, 2, 3, 0, 1, 2, 0, 4, 1, 0};
    if (!st) st = bvox_mesh_writer_add(w, &v2[0][0], 5, g2, bot, 4);
    int64_t nv, nt;
    bvox_mesh_writer_counts(w, &nv, &nt);
    if (!st && (nv != 6 || nt != 8)) st = BVOX_EINVAL;
    bvox_status cst = bvox_mesh_writer_close(w, !st);
    return st ? st : cst;
}

TEST(two_pieces_read_back_as_one)
{
    bvox_mesh *whole;
    CHECK_OK(bvox_mesh_create(&whole));
    for (int i = 0; i < 6; i++) CHECK_OK(bvox_mesh_add_vertex(whole, V[i][0], V[i][1], V[i][2]));
    const int32_t t[24] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 1, 0, 5, 2, 1, 5, 3, 2, 5, 0, 3, 5};
    for (int k = 0; k < 8; k++) CHECK_OK(bvox_mesh_add_triangle(whole, t[3 * k], t[3 * k + 1], t[3 * k + 2]));
    bvox_mesh_info wi;
    CHECK_OK(bvox_mesh_measure(whole, &wi));
    CHECK(wi.watertight);
    const char *names[] = {"o.ply", "o.stl", "o.obj", "o.off"};
    for (int f = 0; f < 4; f++)
        for (int ascii = 0; ascii < 2; ascii++) {
            CHECK_OK(write_two(harness_path(names[f]), ascii));
            bvox_mesh *m;
            CHECK_OK(bvox_mesh_read(harness_path(names[f]), NULL, &m));
            bvox_mesh_info mi;
            CHECK_OK(bvox_mesh_measure(m, &mi));
            CHECK_EQ(mi.vertices, 6);
            CHECK_EQ(mi.triangles, 8);
            CHECK(mi.watertight);
            CHECK_EQ(mi.inconsistent_edges, 0);
            CHECK_NEAR(mi.volume, wi.volume, 1e-12); /* 4/3, outward as the whole */
            CHECK_NEAR(mi.volume, 4.0 / 3.0, 1e-12);
            bvox_mesh_destroy(m);
        }
    bvox_mesh_destroy(whole);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 4);
    return 0;
}

TEST(bad_piece_refused_whole)
{
    const char *p = harness_path("bad.ply");
    bvox_mesh_writer *w;
    CHECK_OK(bvox_mesh_writer_open(p, NULL, 1, &w));
    const int32_t tri[3] = {0, 1, 2};
    const int64_t ahead[3] = {-1, -1, 0}; /* vertex 0 not written yet */
    CHECK_STATUS(bvox_mesh_writer_add(w, &V[0][0], 3, ahead, tri, 1), BVOX_EINVAL);
    const int32_t out_of_piece[3] = {0, 1, 3};
    CHECK_STATUS(bvox_mesh_writer_add(w, &V[0][0], 3, NULL, out_of_piece, 1), BVOX_EINVAL);
    int64_t nv, nt;
    bvox_mesh_writer_counts(w, &nv, &nt);
    CHECK_EQ(nv, 0);
    CHECK_EQ(nt, 0);
    CHECK_OK(bvox_mesh_writer_add(w, &V[0][0], 3, NULL, tri, 1)); /* still usable */
    CHECK_OK(bvox_mesh_writer_close(w, 1));
    bvox_mesh *m;
    CHECK_OK(bvox_mesh_read(p, NULL, &m));
    CHECK_EQ(m->nvertices, 3);
    CHECK_EQ(m->ntriangles, 1);
    bvox_mesh_destroy(m);
    return 0;
}

TEST(failed_write_leaves_nothing)
{
    for (long n = 1; n <= 2; n++) {
        bvox__sink_fail_after(n);
        bvox_status st = write_two(harness_path("f.off"), 0);
        bvox__sink_fail_after(0);
        CHECK_STATUS(st, BVOX_EIO);
        CHECK_EQ(harness_count_entries(harness_tmpdir()), 0);
    }
    /* dropped without commit: nothing either */
    bvox_mesh_writer *w;
    CHECK_OK(bvox_mesh_writer_open(harness_path("g.ply"), NULL, 0, &w));
    const int32_t tri[3] = {0, 1, 2};
    CHECK_OK(bvox_mesh_writer_add(w, &V[0][0], 3, NULL, tri, 1));
    CHECK_OK(bvox_mesh_writer_close(w, 0));
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
