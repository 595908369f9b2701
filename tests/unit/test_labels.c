/*
 * test_labels.c — label volumes split in one pass (labels_read.c), measured
 * per label (measure_labels.c), and label tables (label_table.c).
 *
 * The reference for every label is the path users already have: the same
 * bytes read with --label N (bvox_read_memory, BVOX_BIN_LABEL) and measured
 * whole (bvox_measure). Every field must agree, on hand-made volumes, on
 * random blobs at awkward sizes with a rotated, anisotropic geometry, and on
 * the AAL atlas (realdata). Contacts are checked against a brute-force count
 * over the label array.
 */
#include "harness.h"
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* --------------------------------------------------------------- helpers */

static bvox_read_opts raw_opts(bvox_dims d, bvox_dtype t)
{
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    o.raw_dims = d;
    o.raw_dtype = t;
    return o;
}

static int near_rel(double a, double b)
{
    return fabs(a - b) <= 1e-9 * (fabs(a) > fabs(b) ? fabs(a) : fabs(b)) + 1e-12;
}

/* Every field of two measures equal (doubles to 1e-9 relative). */
static int same_measures(const bvox_measures *a, const bvox_measures *b, int64_t label)
{
#define SAME_I(f)                                                                          \
    if (a->f != b->f) {                                                                    \
        fprintf(stderr, "label %lld: %s %lld vs %lld\n", (long long)label, #f,             \
                (long long)a->f, (long long)b->f);                                         \
        return 0;                                                                          \
    }
#define SAME_D(f)                                                                          \
    if (!near_rel(a->f, b->f) && !(isnan(a->f) && isnan(b->f))) {                                                           \
        fprintf(stderr, "label %lld: %s %.17g vs %.17g\n", (long long)label, #f,           \
                (double)a->f, (double)b->f);                                               \
        return 0;                                                                          \
    }
    SAME_I(count);
    SAME_D(volume);
    SAME_I(bbox.x0);
    SAME_I(bbox.y0);
    SAME_I(bbox.z0);
    SAME_I(bbox.x1);
    SAME_I(bbox.y1);
    SAME_I(bbox.z1);
    for (int i = 0; i < 3; i++) {
        SAME_D(extent_min[i]);
        SAME_D(extent_max[i]);
        SAME_I(faces[i]);
        SAME_D(centroid[i]);
        SAME_D(principal_moments[i]);
        SAME_D(principal_inertia[i]);
    }
    for (int i = 0; i < 9; i++) {
        SAME_D(covariance[i]);
        SAME_D(inertia[i]);
    }
    SAME_D(area_faces);
    SAME_D(area);
    SAME_D(equivalent_diameter);
    SAME_D(sphericity);
    SAME_I(euler);
    SAME_I(components);
    SAME_I(cavities);
    SAME_I(cavities_26);
    SAME_I(tunnels);
    return 1;
#undef SAME_I
#undef SAME_D
}

/* Each object against bvox_read_memory(--label N) + bvox_measure. */
static int check_against_read(const void *data, size_t size, const bvox_read_opts *base,
                              const bvox_labelset *set)
{
    for (int64_t i = 0; i < set->n; i++) {
        bvox_read_opts o = *base;
        o.binarize.mode = BVOX_BIN_LABEL;
        o.binarize.label = (double)set->objects[i].label;
        bvox_volume *whole;
        CHECK_OK(bvox_read_memory(data, size, "ref", &o, &whole));
        bvox_measures want, got;
        CHECK_OK(bvox_measure(whole, &want));
        CHECK_OK(bvox_labelset_measure(set, i, &got));
        CHECK_EQ(set->objects[i].count, want.count);
        const bvox_box b = set->objects[i].bbox;
        CHECK(b.x0 == want.bbox.x0 && b.y0 == want.bbox.y0 && b.z0 == want.bbox.z0 &&
              b.x1 == want.bbox.x1 && b.y1 == want.bbox.y1 && b.z1 == want.bbox.z1);
        /* the crop holds exactly the label's voxels */
        bvox_volume *crop;
        CHECK_OK(bvox_volume_crop(whole, set->objects[i].crop, &crop));
        CHECK(bvox_volume_equal(crop, set->objects[i].volume));
        CHECK_OK(bvox_volume_check(set->objects[i].volume));
        /* and keeps world positions as bvox_volume_crop does */
        const bvox_geometry *g1 = bvox_volume_geometry(crop),
                            *g2 = bvox_volume_geometry(set->objects[i].volume);
        for (int a = 0; a < 3; a++) CHECK(near_rel(g1->origin[a], g2->origin[a]));
        bvox_volume_destroy(crop);
        bvox_volume_destroy(whole);
        if (!same_measures(&got, &want, set->objects[i].label)) return 1;
    }
    return 0;
}

/* Faces between different non-zero labels, brute force, for labels a < b. */
static int64_t ref_faces(const uint16_t *lab, bvox_dims d, uint16_t la, uint16_t lb, int axis)
{
    int64_t n = 0;
    int dx = axis == 0, dy = axis == 1, dz = axis == 2;
    for (int z = 0; z + dz < d.nz; z++)
        for (int y = 0; y + dy < d.ny; y++)
            for (int x = 0; x + dx < d.nx; x++) {
                uint16_t p = lab[((size_t)z * d.ny + y) * d.nx + x];
                uint16_t q = lab[((size_t)(z + dz) * d.ny + y + dy) * d.nx + x + dx];
                if ((p == la && q == lb) || (p == lb && q == la)) n++;
            }
    return n;
}

/* ----------------------------------------------------------- hand-made */

/* 6 x 5 x 4, u8: label 3 a 2x2x2 cube at x 1..2, label 7 the cube beside it
 * at x 3..4 (4 shared faces across x), label 9 one voxel at the far corner. */
TEST(two_cubes_and_a_dot)
{
    bvox_dims d = {6, 5, 4};
    uint8_t v[6 * 5 * 4] = {0};
    for (int z = 1; z <= 2; z++)
        for (int y = 1; y <= 2; y++)
            for (int x = 1; x <= 4; x++) v[(z * 5 + y) * 6 + x] = x <= 2 ? 3 : 7;
    v[(3 * 5 + 4) * 6 + 5] = 9;
    bvox_read_opts o = raw_opts(d, BVOX_DT_U8);
    o.raw_spacing[0] = 0.5;
    o.raw_spacing[1] = 2;
    o.raw_spacing[2] = 3;
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(v, sizeof v, "t", &o, 0, &set));
    CHECK_EQ(set->n, 3);
    CHECK_EQ(set->objects[0].label, 3);
    CHECK_EQ(set->objects[1].label, 7);
    CHECK_EQ(set->objects[2].label, 9);
    CHECK_EQ(set->objects[0].count, 8);
    CHECK_EQ(set->background, 6 * 5 * 4 - 17);
    bvox_box b = set->objects[0].bbox, c = set->objects[0].crop;
    CHECK(b.x0 == 1 && b.x1 == 3 && b.y0 == 1 && b.y1 == 3 && b.z0 == 1 && b.z1 == 3);
    CHECK(c.x0 == 0 && c.x1 == 4 && c.y0 == 0 && c.y1 == 4 && c.z0 == 0 && c.z1 == 4);
    /* the dot sits in the corner: its crop is clipped to the volume */
    c = set->objects[2].crop;
    CHECK(c.x0 == 4 && c.x1 == 6 && c.y0 == 3 && c.y1 == 5 && c.z0 == 2 && c.z1 == 4);
    CHECK_EQ(set->ncontacts, 1);
    CHECK_EQ(set->contacts[0].a, 0);
    CHECK_EQ(set->contacts[0].b, 1);
    CHECK(set->contacts[0].faces[0] == 4 && set->contacts[0].faces[1] == 0 &&
          set->contacts[0].faces[2] == 0);
    CHECK_NEAR(set->contacts[0].area, 4 * 2.0 * 3.0, 1e-12); /* x faces: sy * sz */
    CHECK_EQ(bvox_labelset_find(set, 7), 1);
    CHECK_EQ(bvox_labelset_find(set, 8), -1);
    CHECK(check_against_read(v, sizeof v, &o, set) == 0);
    bvox_labelset_destroy(set);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A label 5 shell around a label 6 core: the shell has a cavity (filled by
 * another label, which is background for it), the core touches it on all
 * six sides: 6 faces. */
TEST(shell_and_core)
{
    bvox_dims d = {5, 5, 5};
    uint16_t v[125] = {0};
    for (int z = 1; z <= 3; z++)
        for (int y = 1; y <= 3; y++)
            for (int x = 1; x <= 3; x++) v[(z * 5 + y) * 5 + x] = 5;
    v[(2 * 5 + 2) * 5 + 2] = 6;
    bvox_read_opts o = raw_opts(d, BVOX_DT_U16);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(v, sizeof v, "t", &o, 0, &set));
    CHECK_EQ(set->n, 2);
    bvox_measures m;
    CHECK_OK(bvox_labelset_measure(set, 0, &m));
    CHECK_EQ(m.cavities, 1);
    CHECK_EQ(m.count, 26);
    CHECK_EQ(set->ncontacts, 1);
    CHECK(set->contacts[0].faces[0] == 2 && set->contacts[0].faces[1] == 2 &&
          set->contacts[0].faces[2] == 2);
    CHECK(check_against_read(v, sizeof v, &o, set) == 0);
    bvox_labelset_destroy(set);
    return 0;
}

/* -------------------------------------------------------- random blobs */

/* Random blobs of labels (box unions, overlapping: later wins) at awkward
 * sizes; geometry rotated and anisotropic through a NIfTI file. */
static int random_case(bvox_dims d, int nlabels, unsigned seed)
{
    size_t n = (size_t)d.nx * d.ny * d.nz;
    uint32_t *lab = calloc(n, sizeof *lab);
    uint16_t *lab16 = calloc(n, sizeof *lab16);
    CHECK(lab && lab16);
    srand(seed);
    for (int k = 0; k < nlabels * 3; k++) {
        uint32_t l = 1 + (uint32_t)(rand() % nlabels) * 37; /* sparse values */
        int x0 = rand() % d.nx, y0 = rand() % d.ny, z0 = rand() % d.nz;
        int x1 = x0 + 1 + rand() % 6, y1 = y0 + 1 + rand() % 6, z1 = z0 + 1 + rand() % 40;
        for (int z = z0; z < z1 && z < d.nz; z++)
            for (int y = y0; y < y1 && y < d.ny; y++)
                for (int x = x0; x < x1 && x < d.nx; x++) {
                    size_t i = ((size_t)z * d.ny + y) * d.nx + x;
                    /* holes of background inside, for cavities and tunnels */
                    lab[i] = (rand() % 9 == 0) ? 0 : l;
                }
    }
    for (size_t i = 0; i < n; i++) lab16[i] = (uint16_t)lab[i];
    bvox_volume *like;
    CHECK_OK(bvox_volume_create(d, &like));
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.7;
    g.spacing[1] = 1.3;
    g.spacing[2] = 2.5;
    g.origin[0] = -12.5;
    g.origin[1] = 3;
    g.origin[2] = 40;
    double c = cos(0.4), s = sin(0.4); /* a rotation about z */
    double dir[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    memcpy(g.direction, dir, sizeof dir);
    strcpy(g.unit, "mm");
    CHECK_OK(bvox_volume_set_geometry(like, &g));
    char path[] = "/tmp/bvox_labels_XXXXXX.nii";
    int fd = mkstemps(path, 4);
    CHECK(fd >= 0);
    close(fd);
    CHECK_OK(bvox_write_labels_nifti(path, like, lab));
    bvox_volume_destroy(like);
    FILE *f = fopen(path, "rb");
    CHECK(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *bytes = malloc((size_t)size);
    CHECK(bytes && fread(bytes, 1, (size_t)size, f) == (size_t)size);
    fclose(f);
    bvox_labelset *set, *set2;
    CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
    CHECK_OK(bvox_labels_read_memory(bytes, (size_t)size, path, NULL, 0, &set2));
    CHECK_EQ(set->n, set2->n);
    remove(path);
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    int bad = check_against_read(bytes, (size_t)size, &o, set);
    /* contacts against brute force, every pair of labels present */
    int64_t pairs = 0;
    for (int64_t a = 0; a < set->n && !bad; a++)
        for (int64_t b = a + 1; b < set->n && !bad; b++) {
            int64_t f3[3];
            for (int ax = 0; ax < 3; ax++)
                f3[ax] = ref_faces(lab16, d, (uint16_t)set->objects[a].label,
                                   (uint16_t)set->objects[b].label, ax);
            const bvox_label_contact *found = NULL;
            for (int64_t k = 0; k < set->ncontacts; k++)
                if (set->contacts[k].a == a && set->contacts[k].b == b) found = &set->contacts[k];
            if (f3[0] + f3[1] + f3[2] == 0) {
                if (found) bad = 1;
                continue;
            }
            pairs++;
            if (!found || memcmp(found->faces, f3, sizeof f3)) bad = 1;
        }
    CHECK(!bad);
    CHECK_EQ(pairs, set->ncontacts);
    bvox_labelset_destroy(set);
    bvox_labelset_destroy(set2);
    free(bytes);
    free(lab);
    free(lab16);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(random_blobs_awkward_sizes)
{
    static const bvox_dims sizes[] = {{7, 5, 1}, {9, 11, 63}, {13, 6, 64}, {5, 17, 65},
                                      {11, 9, 130}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        CHECK(random_case(sizes[i], 6, 100 + (unsigned)i) == 0);
    return 0;
}

/* ------------------------------------------------------------ bad input */

/* 10^6 distinct labels: refused by the default limit after one small map,
 * never a volume per label. */
TEST(million_labels_refused)
{
    bvox_dims d = {100, 100, 100};
    int32_t *v = malloc(1000000 * sizeof *v);
    CHECK(v);
    for (int i = 0; i < 1000000; i++) v[i] = i + 1;
    bvox_read_opts o = raw_opts(d, BVOX_DT_I32);
    bvox_labelset *set = (bvox_labelset *)1;
    CHECK_STATUS(bvox_labels_read_memory(v, 4000000, "many", &o, 0, &set), BVOX_ETOOBIG);
    CHECK(set == NULL);
    CHECK(strstr(bvox_errmsg(), "more than 65535 distinct labels") != NULL);
    CHECK(strstr(bvox_errmsg(), "many") != NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    /* a lower limit is honoured exactly: 1000 labels pass at 1000, fail at 999 */
    for (int i = 0; i < 1000000; i++) v[i] = 1 + i % 1000;
    CHECK_OK(bvox_labels_read_memory(v, 4000000, "many", &o, 1000, &set));
    CHECK_EQ(set->n, 1000);
    CHECK_EQ(set->objects[999].count, 1000);
    bvox_labelset_destroy(set);
    CHECK_STATUS(bvox_labels_read_memory(v, 4000000, "many", &o, 999, &set), BVOX_ETOOBIG);
    free(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(float_labels)
{
    bvox_dims d = {4, 3, 2};
    float v[24] = {0};
    v[5] = 2.0f;
    v[6] = 2.0f;
    v[17] = -4.0f;
    bvox_read_opts o = raw_opts(d, BVOX_DT_F32);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(v, sizeof v, "f", &o, 0, &set));
    CHECK_EQ(set->n, 2);
    CHECK_EQ(set->objects[0].label, -4);
    CHECK_EQ(set->objects[1].count, 2);
    bvox_labelset_destroy(set);
    v[17] = 1.5f; /* voxel (1, 1, 1) */
    CHECK_STATUS(bvox_labels_read_memory(v, sizeof v, "f", &o, 0, &set), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "voxel (1, 1, 1) is not an integer label") != NULL);
    v[17] = NAN;
    CHECK_STATUS(bvox_labels_read_memory(v, sizeof v, "f", &o, 0, &set), BVOX_EFORMAT);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(binary_formats_refused)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &v));
    char path[] = "/tmp/bvox_labels_XXXXXX.binvox";
    int fd = mkstemps(path, 7);
    CHECK(fd >= 0);
    close(fd);
    CHECK_OK(bvox_write(path, v, NULL));
    bvox_volume_destroy(v);
    bvox_labelset *set;
    CHECK_STATUS(bvox_labels_read(path, NULL, 0, &set), BVOX_EUNSUPPORTED);
    remove(path);
    CHECK_STATUS(bvox_labels_read("/nonexistent/x.nii", NULL, 0, &set), BVOX_ENOTFOUND);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Every allocation failing in turn: a clean status, nothing leaked. */
TEST(alloc_failures)
{
    bvox_dims d = {9, 8, 70};
    size_t n = 9 * 8 * 70;
    uint16_t *v = calloc(n, sizeof *v);
    CHECK(v);
    for (size_t i = 0; i < n; i++) v[i] = (uint16_t)(i % 5 == 0 ? 0 : 1 + (i / 50) % 4);
    bvox_read_opts o = raw_opts(d, BVOX_DT_U16);
    int ok = 0;
    for (long k = 1; k < 100 && !ok; k++) {
        bvox__alloc_fail_after(k);
        bvox_labelset *set;
        bvox_status st = bvox_labels_read_memory(v, n * 2, "t", &o, 0, &set);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            ok = 1;
            CHECK_EQ(set->n, 4);
            bvox_labelset_destroy(set);
        } else {
            CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
            CHECK(set == NULL);
        }
        CHECK_EQ(bvox_memory_in_use(), 0);
    }
    CHECK(ok);
    free(v);
    return 0;
}

/* ---------------------------------------------------------- label tables */

TEST(table_formats)
{
    const char *fs = "#$Id: FreeSurferColorLUT.txt\n"
                     "#No. Label Name:                            R   G   B   A\n"
                     "\n"
                     "0   Unknown                                 0   0   0   0\n"
                     "2   Left-Cerebral-White-Matter              245 245 245 0\n"
                     "17  Left-Hippocampus                        220 216 20  0\r\n";
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_parse(fs, strlen(fs), "fs", &t));
    CHECK_EQ(t->n, 3);
    CHECK_EQ(t->nwarnings, 0);
    const bvox_label_entry *e = bvox_label_table_find(t, 17);
    CHECK(e && !strcmp(e->name, "Left-Hippocampus") && e->has_color);
    CHECK(e->rgba[0] == 220 && e->rgba[1] == 216 && e->rgba[2] == 20 && e->rgba[3] == 255);
    CHECK(bvox_label_table_find(t, 3) == NULL);
    bvox_label_table_destroy(t);

    const char *itk = "################################################\n"
                      "# ITK-SNAP Label Description File\n"
                      "#    IDX:   Zero-based index\n"
                      "################################################\n"
                      "    0     0    0    0        0  0  0    \"Clear Label\"\n"
                      "    1   255    0    0        1  1  1    \"Liver, left lobe\"\n"
                      "    2     0  255    0      0.5  1  1    \"Label #2\"\n";
    CHECK_OK(bvox_label_table_parse(itk, strlen(itk), "itk", &t));
    CHECK_EQ(t->n, 3);
    e = bvox_label_table_find(t, 1);
    CHECK(e && !strcmp(e->name, "Liver, left lobe") && e->rgba[0] == 255 && e->rgba[3] == 255);
    e = bvox_label_table_find(t, 2);
    CHECK(e && !strcmp(e->name, "Label #2") && e->rgba[1] == 255 && e->rgba[3] == 128);
    bvox_label_table_destroy(t);

    const char *slicer = "# Color table file /tmp/GenericColors.ctbl\n"
                         "# 3 values\n"
                         "0 background 0 0 0 0\n"
                         "1 tissue 128 174 128 255\n"
                         "2 bone 241 214 145 255\n";
    CHECK_OK(bvox_label_table_parse(slicer, strlen(slicer), "ctbl", &t));
    e = bvox_label_table_find(t, 2);
    CHECK(t->n == 3 && e && !strcmp(e->name, "bone") && e->rgba[2] == 145);
    bvox_label_table_destroy(t);

    const char *aal = "1 Precentral_L 2001\n2 Precentral_R 2002\n";
    CHECK_OK(bvox_label_table_parse(aal, strlen(aal), "aal", &t));
    e = bvox_label_table_find(t, 2);
    CHECK(t->n == 2 && e && !strcmp(e->name, "Precentral_R") && !e->has_color);
    bvox_label_table_destroy(t);
    return 0;
}

static char warned[4][300];
static int nwarned;
static void on_warning(const char *msg, void *user)
{
    (void)user;
    if (nwarned < 4) snprintf(warned[nwarned], sizeof warned[0], "%s", msg);
    nwarned++;
}

TEST(table_duplicates_and_bad_lines_warn)
{
    bvox_set_warning_handler(on_warning, NULL);
    const char *txt = "5 five 1 2 3 0\n"
                      "x y z\n"
                      "5 again 4 5 6 0\n"
                      "3 three\n";
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_parse(txt, strlen(txt), "dup.txt", &t));
    CHECK_EQ(t->n, 2);
    CHECK_EQ(t->nwarnings, 2);
    CHECK(strstr(warned[0], "dup.txt:2: not a label line") != NULL);
    CHECK(strstr(warned[1], "dup.txt:3: label 5 is listed again") != NULL);
    CHECK_EQ(nwarned, 2);
    bvox_set_warning_handler(NULL, NULL);
    CHECK(!strcmp(bvox_label_table_find(t, 5)->name, "five"));
    CHECK_EQ(t->entries[0].label, 3); /* sorted */
    bvox_label_table_destroy(t);
    CHECK_STATUS(bvox_label_table_parse("# only comments\n", 16, "c", &t), BVOX_EFORMAT);
    CHECK(t == NULL);
    return 0;
}

/* ---------------------------------------------------------- real data */

TEST(realdata_aal_every_label_as_measure_label)
{
    const char *path = "/usr/share/mricron/templates/aal.nii.gz";
    FILE *f = fopen(path, "rb");
    CHECK(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *bytes = malloc((size_t)size);
    CHECK(bytes && fread(bytes, 1, (size_t)size, f) == (size_t)size);
    fclose(f);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
    CHECK_EQ(set->n, 116);
    CHECK_EQ(set->objects[0].label, 1);
    CHECK_EQ(set->objects[115].label, 116);
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    CHECK(check_against_read(bytes, (size_t)size, &o, set) == 0);
    /* left and right precentral gyri do not touch; precentral L touches
       postcentral L (57) */
    int touch = 0;
    for (int64_t k = 0; k < set->ncontacts; k++)
        if (set->contacts[k].a == 0 && set->objects[set->contacts[k].b].label == 57) touch = 1;
    CHECK(touch);
    bvox_labelset_destroy(set);
    free(bytes);
    return 0;
}
