/*
 * test_mesh_labels.c — per-label meshes (mesh_labels.c): touching labels
 * share their boundary exactly. For every pair of labels that touch, the
 * voxel faces the two meshes cover (each whole) number the contact count of
 * the label set, with opposite normals: no gap (every shared face is in
 * both) and no overlap (a face is in both only where the labels meet); and
 * every voxel corner of one mesh next to a voxel of the other label is a
 * bitwise equal vertex of the other mesh. Triangles are mapped to voxel
 * faces geometrically (cuberille fans a face from an edge midpoint where
 * four voxels around that edge alternate, so the two sides of a face need
 * not be split alike). Each mesh is also closed and encloses exactly its
 * label's voxel volume.
 */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A voxel face: axis, the corner with the lowest indices, and the side the
 * triangle's normal points to (+1 / -1 along the axis). */
typedef struct face {
    int64_t key;
    double area;
} face;

static int cmp_face(const void *a, const void *b)
{
    int64_t x = ((const face *)a)->key, y = ((const face *)b)->key;
    return (x > y) - (x < y);
}

/* World -> index space of the label volume: D^T (p - origin) / spacing. */
static void to_index(const bvox_geometry *g, const double *p, double *q)
{
    double d[3] = {p[0] - g->origin[0], p[1] - g->origin[1], p[2] - g->origin[2]};
    for (int a = 0; a < 3; a++)
        q[a] = (g->direction[a] * d[0] + g->direction[3 + a] * d[1] + g->direction[6 + a] * d[2]) /
               g->spacing[a];
}

/* Faces covered by the mesh's triangles, with the area each covers
 * (merged: one entry per face and side), sorted by key. */
static face *faces_of(const bvox_mesh *m, const bvox_geometry *g, int64_t *nf)
{
    face *f = malloc((size_t)m->ntriangles * sizeof *f);
    if (!f) return NULL;
    for (int64_t i = 0; i < m->ntriangles; i++) {
        double q[3][3], c[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) {
            to_index(g, m->vertices + 3 * m->triangles[3 * i + k], q[k]);
            for (int a = 0; a < 3; a++) c[a] += q[k][a] / 3;
        }
        double e1[3], e2[3], n[3];
        for (int a = 0; a < 3; a++) e1[a] = q[1][a] - q[0][a], e2[a] = q[2][a] - q[0][a];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        int axis = fabs(n[0]) > fabs(n[1]) ? (fabs(n[0]) > fabs(n[2]) ? 0 : 2)
                                           : (fabs(n[1]) > fabs(n[2]) ? 1 : 2);
        /* corners are at half-integers: the face's lowest corner + 0.5 */
        int64_t lo[3];
        for (int a = 0; a < 3; a++)
            lo[a] = a == axis ? (int64_t)llround(c[a] + 0.5) : (int64_t)floor(c[a] + 0.5);
        int side = n[axis] > 0 ? 1 : 0;
        f[i].key = ((((lo[0] + 1) * 4096 + lo[1] + 1) * 4096 + lo[2] + 1) * 3 + axis) * 2 + side;
        f[i].area = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2; /* index units */
    }
    qsort(f, (size_t)m->ntriangles, sizeof *f, cmp_face);
    int64_t k = 0;
    for (int64_t i = 0; i < m->ntriangles; i++) {
        if (k && f[k - 1].key == f[i].key) f[k - 1].area += f[i].area;
        else f[k++] = f[i];
    }
    *nf = k;
    return f;
}

static int cmp_vertex(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static double *sorted_vertices(const bvox_mesh *m)
{
    double *v = malloc((size_t)m->nvertices * 3 * sizeof *v);
    if (!v) return NULL;
    memcpy(v, m->vertices, (size_t)m->nvertices * 3 * sizeof *v);
    qsort(v, (size_t)m->nvertices, 3 * sizeof *v, cmp_vertex);
    return v;
}

static int check_set(const bvox_labelset *set)
{
    const bvox_geometry *g = &set->geometry;
    bvox_mesh **m = calloc((size_t)set->n, sizeof *m);
    face **f = calloc((size_t)set->n, sizeof *f);
    int64_t *nf = calloc((size_t)set->n, sizeof *nf);
    double **vs = calloc((size_t)set->n, sizeof *vs);
    CHECK(m && f && nf && vs);
    for (int64_t i = 0; i < set->n; i++) {
        CHECK_OK(bvox_labelset_mesh(set, i, &m[i]));
        CHECK(f[i] = faces_of(m[i], g, &nf[i]));
        CHECK(vs[i] = sorted_vertices(m[i]));
        bvox_mesh_info info;
        CHECK_OK(bvox_mesh_measure(m[i], &info));
        CHECK(info.watertight && info.inconsistent_edges == 0);
        const double *s = g->spacing;
        CHECK_NEAR(info.volume, set->objects[i].count * s[0] * s[1] * s[2],
                   1e-9 * set->objects[i].count * s[0] * s[1] * s[2]);
        /* every face is covered whole: area 1 in index units */
        for (int64_t k = 0; k < nf[i]; k++) CHECK_NEAR(f[i][k].area, 1.0, 1e-9);
    }
    int64_t touching = 0;
    for (int64_t a = 0; a < set->n; a++)
        for (int64_t b = a + 1; b < set->n; b++) {
            int64_t faces = 0;
            for (int64_t k = 0; k < set->ncontacts; k++)
                if (set->contacts[k].a == a && set->contacts[k].b == b)
                    faces = set->contacts[k].faces[0] + set->contacts[k].faces[1] +
                            set->contacts[k].faces[2];
            int64_t opp = 0, same = 0;
            for (int64_t k = 0; k < nf[a]; k++) {
                face flip = {f[a][k].key ^ 1, 0}, keep = {f[a][k].key, 0};
                if (bsearch(&flip, f[b], (size_t)nf[b], sizeof flip, cmp_face)) opp++;
                if (bsearch(&keep, f[b], (size_t)nf[b], sizeof keep, cmp_face)) same++;
            }
            CHECK_EQ(same, 0);   /* no overlap */
            CHECK_EQ(opp, faces); /* no gap: every shared face in both */
            touching += faces > 0;
        }
    /* Corners shared by two labels' meshes are bitwise the same vertex:
       every vertex of a at a voxel corner that lies on a face of b is one
       of b's vertices (checked for the corners of the shared faces). */
    int64_t corners = 0;
    for (int64_t a = 0; a < set->n; a++)
        for (int64_t t = 0; t < m[a]->ntriangles; t++)
            for (int k = 0; k < 3; k++) {
                const double *p = m[a]->vertices + 3 * m[a]->triangles[3 * t + k];
                double q[3];
                to_index(g, p, q);
                /* a corner: all three index coordinates half-integers */
                int corner = 1;
                for (int c = 0; c < 3; c++) corner &= fabs(q[c] - floor(q[c]) - 0.5) < 1e-6;
                if (!corner) continue;
                int64_t ix = (int64_t)llround(q[0] - 0.5), iy = (int64_t)llround(q[1] - 0.5),
                        iz = (int64_t)llround(q[2] - 0.5);
                for (int64_t b = 0; b < set->n; b++) {
                    if (b == a) continue;
                    /* the corner is b's if one of the 8 voxels around it is b */
                    const bvox_label_object *o = &set->objects[b];
                    int near_b = 0;
                    for (int dz = 0; dz < 2; dz++)
                        for (int dy = 0; dy < 2; dy++)
                            for (int dx = 0; dx < 2; dx++) {
                                int64_t x = ix + dx - o->crop.x0, y = iy + dy - o->crop.y0,
                                        z = iz + dz - o->crop.z0;
                                if (x >= 0 && y >= 0 && z >= 0 &&
                                    bvox_volume_get(o->volume, (int32_t)x, (int32_t)y, (int32_t)z))
                                    near_b = 1;
                            }
                    if (!near_b) continue;
                    corners++;
                    CHECK(bsearch(p, vs[b], (size_t)m[b]->nvertices, 3 * sizeof(double),
                                  cmp_vertex) != NULL);
                }
            }
    CHECK(touching > 0 && corners > 0);
    for (int64_t i = 0; i < set->n; i++) {
        bvox_mesh_destroy(m[i]);
        free(f[i]);
        free(vs[i]);
    }
    free(m);
    free(f);
    free(nf);
    free(vs);
    return 0;
}

/* Blocks of labels in a rotated, mirrored, anisotropic frame, through a
 * NIfTI file. */
TEST(touching_labels_share_faces)
{
    bvox_dims d = {14, 11, 70};
    size_t n = (size_t)d.nx * d.ny * d.nz;
    uint32_t *lab = calloc(n, sizeof *lab);
    CHECK(lab);
    srand(7);
    for (int k = 0; k < 30; k++) {
        uint32_t l = 1 + (uint32_t)(rand() % 5);
        int x0 = rand() % d.nx, y0 = rand() % d.ny, z0 = rand() % d.nz;
        for (int z = z0; z < z0 + 1 + rand() % 30 && z < d.nz; z++)
            for (int y = y0; y < y0 + 5 && y < d.ny; y++)
                for (int x = x0; x < x0 + 5 && x < d.nx; x++)
                    lab[((size_t)z * d.ny + y) * d.nx + x] = rand() % 7 ? l : 0;
    }
    bvox_volume *like;
    CHECK_OK(bvox_volume_create(d, &like));
    bvox_geometry g = bvox_geometry_default();
    double c = cos(0.3), s = sin(0.3);
    double dir[9] = {c, -s, 0, s, c, 0, 0, 0, -1}; /* det -1: mirrored */
    memcpy(g.direction, dir, sizeof dir);
    g.spacing[0] = 0.3;
    g.spacing[1] = 0.7;
    g.spacing[2] = 1.9;
    g.origin[0] = 10.1;
    g.origin[2] = -3.3;
    CHECK_OK(bvox_volume_set_geometry(like, &g));
    char path[] = "/tmp/bvox_meshlabels_XXXXXX.nii";
    int fd = mkstemps(path, 4);
    CHECK(fd >= 0);
    close(fd);
    CHECK_OK(bvox_write_labels_nifti(path, like, lab));
    bvox_volume_destroy(like);
    free(lab);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
    remove(path);
    CHECK(set->n >= 3);
    CHECK(check_set(set) == 0);

    /* the folder output: one file per label, named, readable back */
    char tmpl[] = "/tmp/bvox_meshdir_XXXXXX";
    CHECK(mkdtemp(tmpl));
    char out[64];
    snprintf(out, sizeof out, "%s/m", tmpl);
    int64_t idx[2] = {0, set->n - 1};
    const char *names[2] = {"Left hippocampus (CA1)", NULL};
    CHECK_OK(bvox_labelset_write_meshes(set, idx, 2, names, out, "ply", 0));
    char f1[128], f2[128], name[96];
    bvox_label_file_name(set->objects[0].label, names[0], "ply", name, sizeof name);
    CHECK(!strncmp(name + strcspn(name, "_"), "_Left_hippocampus_CA1.ply", 26));
    snprintf(f1, sizeof f1, "%s/%s", out, name);
    bvox_label_file_name(set->objects[set->n - 1].label, NULL, "ply", name, sizeof name);
    snprintf(f2, sizeof f2, "%s/%s", out, name);
    bvox_mesh *r;
    CHECK_OK(bvox_mesh_read(f1, NULL, &r));
    bvox_mesh *m0;
    CHECK_OK(bvox_labelset_mesh(set, 0, &m0));
    CHECK_EQ(r->ntriangles, m0->ntriangles);
    bvox_mesh_destroy(r);
    bvox_mesh_destroy(m0);
    struct stat sb;
    CHECK(stat(f2, &sb) == 0);
    remove(f1);
    remove(f2);
    rmdir(out);
    rmdir(tmpl);
    bvox_labelset_destroy(set);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A small label volume (blocks 1, 2, 3 touching, 5 apart) as a label set. */
static bvox_labelset *block_labels(void)
{
    bvox_dims d = {9, 6, 5};
    uint32_t lab[9 * 6 * 5] = {0};
    for (int z = 1; z < 4; z++)
        for (int y = 1; y < 5; y++)
            for (int x = 0; x < 9; x++)
                lab[(z * 6 + y) * 9 + x] = x < 3 ? 1 : x < 5 ? 2 : x < 7 ? 3 : (y > 2 ? 5 : 0);
    bvox_volume *like;
    if (bvox_volume_create(d, &like)) return NULL;
    bvox_geometry g = bvox_geometry_default();
    g.spacing[2] = 2.5;
    g.origin[0] = -1.25;
    bvox_volume_set_geometry(like, &g);
    const char *path = harness_path("blocks.nii");
    bvox_labelset *set = NULL;
    if (!bvox_write_labels_nifti(path, like, lab)) bvox_labels_read(path, NULL, 0, &set);
    bvox_volume_destroy(like);
    return set;
}

/* The file's objects are the labels' own meshes (bitwise: %.17g text), in
 * the given colours: the ascii PLY parsed by hand, face by face. */
TEST(one_file_ply_objects_are_the_label_meshes)
{
    bvox_labelset *set = block_labels();
    CHECK(set && set->n == 4);
    int64_t idx[3] = {0, 1, 3}; /* labels 1, 2, 5 */
    const char *names[3] = {"left", NULL, "far away"};
    unsigned char rgb[9] = {255, 0, 0, 0, 255, 0, 1, 2, 3};
    const char *path = harness_path("all.ply");
    CHECK_OK(bvox_labelset_write_mesh_file(set, idx, 3, names, rgb, path, 1));
    FILE *f = fopen(path, "r");
    CHECK(f);
    char line[512];
    long long nv = -1, nf = -1;
    int objects = 0;
    while (fgets(line, sizeof line, f) && strcmp(line, "end_header\n")) {
        sscanf(line, "element vertex %lld", &nv);
        sscanf(line, "element face %lld", &nf);
        objects += !strncmp(line, "comment object ", 15);
    }
    CHECK_EQ(objects, 3);
    bvox_mesh *m[3];
    long long tv = 0, tf = 0;
    for (int i = 0; i < 3; i++) {
        CHECK_OK(bvox_labelset_mesh(set, idx[i], &m[i]));
        tv += m[i]->nvertices;
        tf += m[i]->ntriangles;
    }
    CHECK_EQ(nv, tv);
    CHECK_EQ(nf, tf);
    double *v = malloc((size_t)nv * 3 * sizeof *v);
    unsigned *vc = malloc((size_t)nv * 3 * sizeof *vc);
    CHECK(v && vc);
    for (long long i = 0; i < nv; i++)
        CHECK(fscanf(f, "%lf %lf %lf %u %u %u", v + 3 * i, v + 3 * i + 1, v + 3 * i + 2,
                     vc + 3 * i, vc + 3 * i + 1, vc + 3 * i + 2) == 6);
    int obj = 0;
    long long in_obj = 0, base = 0;
    for (long long t = 0; t < nf; t++) {
        int three;
        long long a[3], label;
        unsigned c[3];
        CHECK(fscanf(f, "%d %lld %lld %lld %u %u %u %lld", &three, a, a + 1, a + 2, c, c + 1,
                     c + 2, &label) == 8);
        while (in_obj == m[obj]->ntriangles) { /* the next object */
            base += m[obj]->nvertices;
            obj++;
            in_obj = 0;
        }
        CHECK_EQ(label, set->objects[idx[obj]].label);
        for (int k = 0; k < 3; k++) CHECK_EQ(c[k], rgb[3 * obj + k]);
        for (int k = 0; k < 3; k++) {
            long long want = base + m[obj]->triangles[3 * in_obj + k];
            CHECK_EQ(a[k], want);
            for (int j = 0; j < 3; j++) {
                CHECK(v[3 * a[k] + j] == m[obj]->vertices[3 * (want - base) + j]);
                CHECK_EQ(vc[3 * a[k] + j], rgb[3 * obj + j]);
            }
        }
        in_obj++;
    }
    CHECK(obj == 2 && in_obj == m[2]->ntriangles);
    fclose(f);
    free(v);
    free(vc);
    /* binary: the same counts through the mesh reader (colours read past) */
    CHECK_OK(bvox_labelset_write_mesh_file(set, idx, 3, names, NULL, path, 0));
    bvox_mesh *r;
    CHECK_OK(bvox_mesh_read(path, NULL, &r));
    CHECK_EQ(r->nvertices, tv);
    CHECK_EQ(r->ntriangles, tf);
    CHECK(r->vertices[0] == m[0]->vertices[0]);
    bvox_mesh_destroy(r);
    for (int i = 0; i < 3; i++) bvox_mesh_destroy(m[i]);
    /* STL holds no colours: refused, nothing written */
    CHECK_STATUS(bvox_labelset_write_mesh_file(set, idx, 3, NULL, NULL, harness_path("x.stl"), 0),
                 BVOX_EINVAL);
    CHECK(access(harness_path("x.stl"), F_OK) != 0);
    bvox_labelset_destroy(set);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* OBJ: an o/g/usemtl per label with its own vertices and faces, and the
 * .mtl's Kd the given colour. */
TEST(one_file_obj_with_materials)
{
    bvox_labelset *set = block_labels();
    CHECK(set && set->n == 4);
    int64_t idx[2] = {1, 2}; /* labels 2 and 3: they touch */
    unsigned char rgb[6] = {255, 128, 0, 0, 0, 255};
    const char *path = harness_path("two.obj");
    CHECK_OK(bvox_labelset_write_mesh_file(set, idx, 2, NULL, rgb, path, 0));
    FILE *f = fopen(path, "r");
    CHECK(f);
    char line[512];
    int obj = -1, mtllib = 0;
    long long nv[2] = {0, 0}, nf[2] = {0, 0};
    while (fgets(line, sizeof line, f)) {
        if (!strcmp(line, "mtllib two.mtl\n")) mtllib = 1;
        if (!strncmp(line, "o ", 2)) {
            obj++;
            char want[64];
            snprintf(want, sizeof want, "o %lld\n", (long long)set->objects[idx[obj]].label);
            CHECK(!strcmp(line, want));
        }
        if (!strncmp(line, "usemtl ", 7)) {
            char want[64];
            snprintf(want, sizeof want, "usemtl label_%lld\n",
                     (long long)set->objects[idx[obj]].label);
            CHECK(!strcmp(line, want));
        }
        if (line[0] == 'v' && line[1] == ' ') nv[obj]++;
        if (line[0] == 'f' && line[1] == ' ') nf[obj]++;
    }
    fclose(f);
    CHECK(mtllib && obj == 1);
    for (int i = 0; i < 2; i++) {
        bvox_mesh *m;
        CHECK_OK(bvox_labelset_mesh(set, idx[i], &m));
        CHECK_EQ(nv[i], m->nvertices);
        CHECK_EQ(nf[i], m->ntriangles);
        bvox_mesh_destroy(m);
    }
    f = fopen(harness_path("two.mtl"), "r");
    CHECK(f);
    int kd = 0;
    double r, g, b;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "Kd %lf %lf %lf", &r, &g, &b) == 3) {
            CHECK_NEAR(r, rgb[3 * kd] / 255.0, 1e-6);
            CHECK_NEAR(g, rgb[3 * kd + 1] / 255.0, 1e-6);
            CHECK_NEAR(b, rgb[3 * kd + 2] / 255.0, 1e-6);
            kd++;
        }
    fclose(f);
    CHECK_EQ(kd, 2);
    bvox_labelset_destroy(set);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(realdata_aal_neighbours_share_faces)
{
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read("/usr/share/mricron/templates/aal.nii.gz", NULL, 0, &set));
    /* the first 12 labels and their contacts: enough for a real test, quick */
    bvox_labelset sub = *set;
    sub.n = 12;
    int64_t nc = 0;
    bvox_label_contact *c = malloc((size_t)set->ncontacts * sizeof *c);
    CHECK(c);
    for (int64_t k = 0; k < set->ncontacts; k++)
        if (set->contacts[k].b < 12) c[nc++] = set->contacts[k];
    sub.contacts = c;
    sub.ncontacts = nc;
    CHECK(check_set(&sub) == 0);
    free(c);
    bvox_labelset_destroy(set);
    return 0;
}
