/* test_mesh_io.c — mesh files: write -> read round trips for every format
 * (exact for PLY, OBJ, OFF; float-rounded and welded back to the same
 * shared vertices for STL), hand-written files of each format with the
 * features readers must handle (OBJ negative indices, polygons, v/t/n
 * corners; PLY ascii, little and big endian with extra properties and
 * elements; OFF comments and polygons; ASCII STL welded), and bad files
 * (truncated, NaN, out-of-range index, absurd counts) giving BVOX_EFORMAT
 * with the file's name in the message; a failed write leaves no file. */
#include "harness.h"
#include "internal.h"
#include "io/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static bvox_mesh *sample_mesh(void)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){7, 6, 9}, &v)) return NULL;
    for (int32_t z = 0; z < 9; z++)
        for (int32_t y = 0; y < 6; y++)
            for (int32_t x = 0; x < 7; x++)
                if (harness_rand() % 2) bvox_volume_set(v, x, y, z, 1);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.3;
    g.spacing[1] = 0.7;
    g.spacing[2] = 1.1;
    g.origin[0] = -3.25;
    g.origin[1] = 1e3 / 7;
    bvox_volume_set_geometry(v, &g);
    bvox_mesh *m = NULL;
    bvox_mesh_from_volume(v, NULL, &m);
    bvox_volume_destroy(v);
    return m;
}

static int same_mesh(const bvox_mesh *a, const bvox_mesh *b)
{
    CHECK_EQ(a->nvertices, b->nvertices);
    CHECK_EQ(a->ntriangles, b->ntriangles);
    CHECK(!memcmp(a->vertices, b->vertices, (size_t)a->nvertices * 3 * sizeof(double)));
    CHECK(!memcmp(a->triangles, b->triangles, (size_t)a->ntriangles * 3 * sizeof(int32_t)));
    return 0;
}

TEST(roundtrip_exact_formats)
{
    bvox_mesh *m = sample_mesh();
    CHECK(m && m->ntriangles > 100);
    static const char *const files[] = {"a.ply", "a.obj", "a.off"};
    for (int i = 0; i < 3; i++)
        for (int ascii = 0; ascii < 2; ascii++) {
            const char *p = harness_path(files[i]);
            CHECK_OK(bvox_mesh_write(p, m, NULL, ascii));
            bvox_mesh *r = NULL;
            CHECK_OK(bvox_mesh_read(p, NULL, &r));
            if (same_mesh(m, r)) return 1;
            bvox_mesh_destroy(r);
        }
    bvox_mesh_destroy(m);
    return 0;
}

TEST(roundtrip_stl)
{
    bvox_mesh *m = sample_mesh();
    CHECK(m);
    bvox_mesh_info mi;
    CHECK_OK(bvox_mesh_measure(m, &mi));
    for (int ascii = 0; ascii < 2; ascii++) {
        const char *p = harness_path("a.stl");
        CHECK_OK(bvox_mesh_write(p, m, NULL, ascii));
        bvox_mesh *r = NULL;
        CHECK_OK(bvox_mesh_read(p, NULL, &r));
        /* welding gives back the shared vertices, in first-use order */
        CHECK_EQ(r->nvertices, m->nvertices);
        CHECK_EQ(r->ntriangles, m->ntriangles);
        for (int64_t t = 0; t < 3 * m->ntriangles; t++)
            for (int k = 0; k < 3; k++)
                CHECK((float)r->vertices[3 * r->triangles[t] + k] ==
                      (float)m->vertices[3 * m->triangles[t] + k]);
        bvox_mesh_info ri;
        CHECK_OK(bvox_mesh_measure(r, &ri));
        CHECK(ri.watertight);
        CHECK_NEAR(ri.volume, mi.volume, 1e-5 * mi.volume);
        bvox_mesh_destroy(r);
    }
    bvox_mesh_destroy(m);
    return 0;
}

static bvox_status rd(const char *text, const char *fmt, bvox_mesh **m)
{
    return bvox_mesh_read_memory(text, strlen(text), "test.file", fmt, m);
}

/* A unit cube [0,1]^3 as 6 quads, outward. */
#define CUBE_V "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"

TEST(obj_features)
{
    bvox_mesh *m = NULL;
    /* positive, negative and v/t/n corners, quads, ignored records */
    CHECK_OK(rd("# cube\nmtllib x.mtl\no cube\n" CUBE_V "vt 0 0\nvn 0 0 1\ns off\n"
                "f 1 4 3 2\nf 5/1 6/1 7/1 8/1\nf 1//1 2//1 6//1 5//1\n"
                "f -5 -1 -2 -6\nf 2/1/1 3/1/1 7/1/1 6/1/1\nf 1 5 8 4\n",
                NULL, &m));
    CHECK_EQ(m->nvertices, 8);
    CHECK_EQ(m->ntriangles, 12);
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_EQ(info.inconsistent_edges, 0);
    CHECK_NEAR(info.volume, 1.0, 1e-12);
    CHECK_NEAR(info.area, 6.0, 1e-12);
    bvox_mesh_destroy(m);
    return 0;
}

TEST(off_and_ply_ascii)
{
    bvox_mesh *m = NULL;
    CHECK_OK(rd("OFF\n# a tetrahedron\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1 0.5 0.5 0.5\n"
                "3 0 2 1\n3 0 1 3  255 0 0\n3 0 3 2\n3 1 2 3\n",
                NULL, &m));
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.volume, 1.0 / 6.0, 1e-12);
    bvox_mesh_destroy(m);
    CHECK_OK(rd("ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\n"
                "property float y\nproperty float z\nproperty uchar red\nelement face 2\n"
                "property uchar flags\nproperty list uchar int vertex_indices\n"
                "element edge 1\nproperty int a\nproperty int b\nend_header\n"
                "0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n7 3 0 1 2\n7 3 0 2 3\n0 1\n",
                NULL, &m));
    CHECK_EQ(m->nvertices, 4);
    CHECK_EQ(m->ntriangles, 2);
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK_NEAR(info.area, 1.0, 1e-12);
    CHECK_EQ(info.boundary_edges, 4);
    CHECK(!info.watertight);
    bvox_mesh_destroy(m);
    return 0;
}

static size_t put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
    return 4;
}

TEST(ply_big_endian)
{
    uint8_t buf[512];
    const char *hdr = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 4\n"
                      "property list uchar uint vertex_indices\nend_header\n";
    size_t n = strlen(hdr);
    memcpy(buf, hdr, n);
    static const float xyz[4][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
    for (int v = 0; v < 4; v++)
        for (int k = 0; k < 3; k++) {
            uint32_t u;
            memcpy(&u, &xyz[v][k], 4);
            n += put_be32(buf + n, u);
        }
    static const uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (int i = 0; i < 4; i++) {
        buf[n++] = 3;
        for (int k = 0; k < 3; k++) n += put_be32(buf + n, f[i][k]);
    }
    bvox_mesh *m = NULL;
    CHECK_OK(bvox_mesh_read_memory(buf, n, "be.ply", NULL, &m));
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.volume, 8.0 / 6.0, 1e-12);
    bvox_mesh_destroy(m);
    /* the same bytes cut short: a clear error */
    CHECK_STATUS(bvox_mesh_read_memory(buf, n - 3, "be.ply", NULL, &m), BVOX_EFORMAT);
    CHECK(m == NULL);
    CHECK(strstr(bvox_errmsg(), "be.ply"));
    return 0;
}

TEST(stl_ascii_welds)
{
    const char *t = "solid t\n"
                    "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\n"
                    "endloop\nendfacet\n"
                    "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\n"
                    "endloop\nendfacet\n"
                    "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\n"
                    "endloop\nendfacet\n"
                    "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex -0 0 1\n"
                    "endloop\nendfacet\nendsolid t\n";
    bvox_mesh *m = NULL;
    CHECK_OK(rd(t, NULL, &m));
    CHECK_EQ(m->nvertices, 4); /* -0 welded with 0 */
    CHECK_EQ(m->ntriangles, 4);
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK(info.watertight);
    CHECK_NEAR(info.volume, 1.0 / 6.0, 1e-12);
    bvox_mesh_destroy(m);
    return 0;
}

/* Every bad file: BVOX_EFORMAT, *out NULL, the name in the message. */
static int bad(const void *data, size_t n, const char *fmt, const char *needle)
{
    bvox_mesh *m = (bvox_mesh *)1;
    bvox_status st = bvox_mesh_read_memory(data, n, "bad.mesh", fmt, &m);
    if (st != BVOX_EFORMAT || m != NULL || !strstr(bvox_errmsg(), "bad.mesh") ||
        (needle && !strstr(bvox_errmsg(), needle))) {
        fprintf(stderr, "expected EFORMAT (%s), got %s: %s\n", needle ? needle : "",
                bvox_status_name(st), bvox_errmsg());
        return 1;
    }
    return 0;
}
#define BAD(text, fmt, needle) CHECK(bad(text, strlen(text), fmt, needle) == 0)

TEST(bad_files)
{
    size_t base = bvox_memory_in_use();
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "obj", "out of range");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "obj", "out of range");
    BAD("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "obj", "line 2");
    BAD("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "obj", "at least 3");
    BAD("v 0 0\n", "obj", "truncated");
    BAD("OFF\n1000000000 1000000000 0\n0 0 0\n", "off", "cannot fit");
    BAD("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "off", "vertex index");
    BAD("OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n", "off", "finite");
    BAD("OFF\n3 1 0\n0 0 0\n1 0 0\n", "off", "cannot fit");
    BAD("OFF\n3 -1 0\n", "off", "face count");
    BAD("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n",
        "ply", "out of range");
    BAD("ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n0 0 0\n",
        "ply", "truncated");
    BAD("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "ply",
        "x, y, z");
    BAD("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n", "ply",
        "end_header");
    BAD("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "stl",
        "truncated");
    BAD("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 NaN 0\n"
        "endloop\nendfacet\nendsolid x\n",
        "stl", "finite");
    /* binary STL: a count beyond the data, and a NaN coordinate */
    uint8_t b[84 + 50];
    memset(b, 0, sizeof b);
    b[80] = 2;
    CHECK(bad(b, sizeof b, "stl", "truncated") == 0);
    b[80] = 1;
    float nan = __builtin_nanf("");
    memcpy(b + 84 + 12 + 4, &nan, 4);
    CHECK(bad(b, sizeof b, "stl", "finite") == 0);
    CHECK(bad(b, 40, "stl", "too short") == 0);
    BAD("hello", NULL, "not a mesh");
    /* huge coordinates: finite, but their products in the measures are not */
    BAD("v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n", "obj", "-1e+308");
    BAD("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e61 0\n3 0 1 2\n", "off", "vertex 3 has a coordinate");
    /* random bytes with the .obj format: not an empty mesh */
    BAD("\x7f\x01\x93garbage\n\xff\xfe no obj here\n", "obj", "no vertices or faces found");
    CHECK_EQ(bvox_memory_in_use(), base);
    bvox_mesh *m = NULL;
    CHECK_STATUS(bvox_mesh_read(harness_path("missing.stl"), NULL, &m), BVOX_ENOTFOUND);
    return 0;
}

TEST(failed_write_leaves_nothing)
{
    bvox_mesh *m = sample_mesh();
    CHECK(m);
    const char *p = harness_path("w.stl");
    for (long n = 1; n < 4; n++) {
        bvox__sink_fail_after(n);
        bvox_status st = bvox_mesh_write(p, m, NULL, 1);
        bvox__sink_fail_after(0);
        if (st == BVOX_OK) break;
        CHECK(access(p, F_OK) != 0);
    }
    CHECK_STATUS(bvox_mesh_write(harness_path("w.xyz"), m, NULL, 0), BVOX_EINVAL);
    CHECK_STATUS(bvox_mesh_write(harness_path("w.stl"), m, "vrml", 0), BVOX_EINVAL);
    bvox_mesh_destroy(m);
    return 0;
}

/* Every allocation of a read (and of the measure) failing in turn: a clean
 * status, *out NULL, nothing left allocated. */
TEST(allocation_failures_are_clean)
{
    bvox_mesh *m = sample_mesh();
    CHECK(m);
    static const char *const files[] = {"f.stl", "f.ply", "f.obj", "f.off"};
    size_t base = bvox_memory_in_use();
    for (int i = 0; i < 4; i++) {
        const char *p = harness_path(files[i]);
        CHECK_OK(bvox_mesh_write(p, m, NULL, i == 1));
        for (long n = 1; n < 30; n++) {
            bvox_mesh *r = NULL;
            bvox__alloc_fail_after(n);
            bvox_status st = bvox_mesh_read(p, NULL, &r);
            bvox_mesh_info info;
            if (st == BVOX_OK) st = bvox_mesh_measure(r, &info);
            bvox__alloc_fail_after(0);
            if (st != BVOX_OK) CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
            bvox_mesh_destroy(r);
            CHECK_EQ(bvox_memory_in_use(), base);
        }
    }
    bvox_mesh_destroy(m);
    return 0;
}

/* One OBJ face of 100000 corners (a regular polygon in the x-z plane). A fan
 * from corner 1 made 99998 slivers that all span the face: the shell's
 * triangle-box tests grew with n times the face (16 s at --res 256, minutes
 * at 1024). Split by halving, no corner is in more than ~2 log2(n) triangles
 * and the triangles' boxes add up to a few times the face. Work bound, not a
 * timing: the sum of the triangles' box areas in voxels at res 1024. */
TEST(long_face_is_not_a_fan)
{
    const int n = 100000;
    size_t cap = (size_t)n * 48 + 16, len = 0;
    char *text = malloc(cap);
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n;
        len += (size_t)snprintf(text + len, cap - len, "v %.12f 0 %.12f\n", cos(a), sin(a));
    }
    len += (size_t)snprintf(text + len, cap - len, "f");
    for (int i = 0; i < n; i++) len += (size_t)snprintf(text + len, cap - len, " %d", i + 1);
    len += (size_t)snprintf(text + len, cap - len, "\n");
    CHECK(len < cap);
    bvox_mesh *m = NULL;
    CHECK_OK(bvox_mesh_read_memory(text, len, "gon.obj", "obj", &m));
    free(text);
    CHECK_EQ(m->ntriangles, (int64_t)n - 2);
    /* a triangulation of the convex face: the areas add up to the polygon's */
    bvox_mesh_info info;
    CHECK_OK(bvox_mesh_measure(m, &info));
    CHECK_NEAR(info.area, 0.5 * n * sin(2 * M_PI / n), 1e-9);
    int32_t *valence = calloc((size_t)n, sizeof *valence);
    int32_t most = 0;
    double boxes = 0, res = 1024, s = 2.0 / res;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++) {
            int32_t v = m->triangles[3 * t + k];
            if (++valence[v] > most) most = valence[v];
            for (int a = 0; a < 2; a++) {
                double c = m->vertices[3 * v + 2 * a];
                lo[a] = fmin(lo[a], c), hi[a] = fmax(hi[a], c);
            }
        }
        boxes += (floor((hi[0] - lo[0]) / s) + 2) * (floor((hi[1] - lo[1]) / s) + 2);
    }
    free(valence);
    CHECK(most <= 40);                      /* a fan: 99998 */
    CHECK(boxes < 8 * res * res);           /* a fan: ~1e10 */
    /* and the shell is the polygon's outline and inside */
    bvox_voxelize_opts o;
    memset(&o, 0, sizeof o);
    o.res = 1024;
    o.shell = 1;
    bvox_volume *v = NULL;
    CHECK_OK(bvox_mesh_voxelize(m, &o, &v, NULL));
    CHECK_EQ(bvox_volume_dims(v).ny, 1);
    int64_t count = bvox_volume_count(v);
    CHECK(count > (int64_t)(M_PI * 511 * 511) && count < (int64_t)(M_PI * 514 * 514));
    bvox_volume_destroy(v);
    bvox_mesh_destroy(m);
    return 0;
}
