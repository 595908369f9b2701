/* test_labels_write.c — bvox_write_labels: a hand-made label volume with a
 * rotated, scaled and shifted geometry written as NRRD (.nrrd, .nhdr),
 * .seg.nrrd, MetaImage (.mha, .mhd) and NIfTI, read back with the readers
 * (every voxel's label, the sample type, spacing, origin and directions);
 * the segment metadata of a .seg.nrrd against a header written out by hand
 * (a golden: names and colours from a table, the rest generated, extents
 * counted on paper); the sample-type choice and its refusals; and failed or
 * refused writes that leave no file. */
#include "harness.h"
#include "common/color.h"
#include "io/io.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

enum { NX = 7, NY = 5, NZ = 4 };

/* Labels 0..3 in a pattern, and 200 at voxel (6, 4, 3). */
static void make_labels(uint32_t *l)
{
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++) l[(z * NY + y) * NX + x] = (uint32_t)((x + y * z) % 4);
    l[(3 * NY + 4) * NX + 6] = 200;
}

/* A volume of NX x NY x NZ with spacing 0.5 0.25 2 mm, origin (1, -2, 3)
 * and axes x -> +y, y -> -x, z -> +z (a quarter turn about z). */
static bvox_volume *make_like(void)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){NX, NY, NZ}, &v)) return NULL;
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.5, g.spacing[1] = 0.25, g.spacing[2] = 2;
    g.origin[0] = 1, g.origin[1] = -2, g.origin[2] = 3;
    const double dir[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}; /* row-major, columns are the axes */
    memcpy(g.direction, dir, sizeof dir);
    strcpy(g.unit, "mm");
    if (bvox_volume_set_geometry(v, &g)) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

/* The label volume a label set came from, voxel by voxel. */
static void unsplit(const bvox_labelset *set, uint32_t *l)
{
    memset(l, 0, sizeof(uint32_t) * NX * NY * NZ);
    for (int64_t i = 0; i < set->n; i++) {
        const bvox_label_object *o = &set->objects[i];
        bvox_dims c = bvox_volume_dims(o->volume);
        for (int32_t z = 0; z < c.nz; z++)
            for (int32_t y = 0; y < c.ny; y++)
                for (int32_t x = 0; x < c.nx; x++)
                    if (bvox_volume_get(o->volume, x, y, z))
                        l[((z + o->crop.z0) * NY + y + o->crop.y0) * NX + x + o->crop.x0] =
                            (uint32_t)o->label;
    }
}

static int roundtrip(const char *name, int dtype, bvox_dtype want)
{
    bvox_volume *like = make_like();
    CHECK(like);
    uint32_t l[NX * NY * NZ], back[NX * NY * NZ];
    make_labels(l);
    const char *path = harness_path(name);
    CHECK_OK(bvox_write_labels(path, like, l, dtype, NULL));
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
    CHECK_EQ((int)set->dtype, (int)want);
    CHECK_EQ(set->n, 4);
    CHECK_EQ(set->objects[3].label, 200);
    unsplit(set, back);
    CHECK(!memcmp(l, back, sizeof l));
    const bvox_geometry *a = bvox_volume_geometry(like), *b = &set->geometry;
    for (int k = 0; k < 3; k++) {
        CHECK_NEAR(b->spacing[k], a->spacing[k], 1e-12);
        CHECK_NEAR(b->origin[k], a->origin[k], 1e-12);
    }
    for (int k = 0; k < 9; k++) CHECK_NEAR(b->direction[k], a->direction[k], 1e-12);
    CHECK(!strcmp(b->unit, "mm"));
    bvox_labelset_destroy(set);
    bvox_volume_destroy(like);
    return 0;
}

TEST(roundtrip_nrrd) { return roundtrip("l.nrrd", BVOX_DT_I16, BVOX_DT_I16); }
TEST(roundtrip_nhdr) { return roundtrip("l.nhdr", BVOX_DT_U32, BVOX_DT_U32); }
TEST(roundtrip_seg_nrrd) { return roundtrip("l.seg.nrrd", -1, BVOX_DT_U8); }
TEST(roundtrip_mha) { return roundtrip("l.mha", BVOX_DT_I64, BVOX_DT_I64); }
TEST(roundtrip_mhd) { return roundtrip("l.mhd", BVOX_DT_U16, BVOX_DT_U16); }
TEST(roundtrip_nifti_any_type) { return roundtrip("l.nii.gz", BVOX_DT_U8, BVOX_DT_U8); }

/* The header of a file up to and including its blank line. */
static char *read_header(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    static char buf[8192];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    char *end = strstr(buf, "\n\n");
    if (end) end[2] = '\0';
    return buf;
}

/* 3 x 2 x 2, spacing 1: label 2 at (0,0,0) and (1,1,1), label 5 at (2,0,1),
 * label 9 (not in the table) at (2,1,0). Extents are inclusive x0 x1 y0 y1
 * z0 z1. Label 9's colour is the renderer's (bvox__label_color). */
TEST(seg_nrrd_header_golden)
{
    bvox_volume *like;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 2, 2}, &like));
    uint32_t l[12] = {0};
    l[0] = 2;                   /* (0,0,0) */
    l[(1 * 2 + 1) * 3 + 1] = 2; /* (1,1,1) */
    l[(1 * 2 + 0) * 3 + 2] = 5; /* (2,0,1) */
    l[(0 * 2 + 1) * 3 + 2] = 9; /* (2,1,0) */
    const char lut[] = "# FreeSurfer style\n2 Left-Liver 255 0 51 0\n5 Spleen 0 128 255 0\n";
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_parse(lut, sizeof lut - 1, "lut", &t));
    const char *path = harness_path("g.seg.nrrd");
    CHECK_OK(bvox_write_labels(path, like, l, -1, t));
    uint8_t c9[3];
    bvox__label_color(9, c9);
    char want[4096];
    snprintf(want, sizeof want,
             "NRRD0004\n"
             "# Complete NRRD file format specification at:\n"
             "# http://teem.sourceforge.net/nrrd/format.html\n"
             "# written by bvox\n"
             "type: uint8\n"
             "dimension: 3\n"
             "space: left-posterior-superior\n"
             "sizes: 3 2 2\n"
             "space directions: (-1,0,0) (0,-1,0) (0,0,1)\n"
             "kinds: domain domain domain\n"
             "endian: little\n"
             "encoding: gzip\n"
             "space origin: (0,0,0)\n"
             "Segmentation_ContainedRepresentationNames:=Binary labelmap|\n"
             "Segmentation_ConversionParameters:=\n"
             "Segmentation_MasterRepresentation:=Binary labelmap\n"
             "Segmentation_ReferenceImageExtentOffset:=0 0 0\n"
             "Segment0_Color:=1 0 0.2\n"
             "Segment0_ColorAutoGenerated:=0\n"
             "Segment0_Extent:=0 1 0 1 0 1\n"
             "Segment0_ID:=Segment_2\n"
             "Segment0_LabelValue:=2\n"
             "Segment0_Layer:=0\n"
             "Segment0_Name:=Left-Liver\n"
             "Segment0_NameAutoGenerated:=0\n"
             "Segment0_Tags:=|\n"
             "Segment1_Color:=0 0.501961 1\n"
             "Segment1_ColorAutoGenerated:=0\n"
             "Segment1_Extent:=2 2 0 0 1 1\n"
             "Segment1_ID:=Segment_5\n"
             "Segment1_LabelValue:=5\n"
             "Segment1_Layer:=0\n"
             "Segment1_Name:=Spleen\n"
             "Segment1_NameAutoGenerated:=0\n"
             "Segment1_Tags:=|\n"
             "Segment2_Color:=%.6g %.6g %.6g\n"
             "Segment2_ColorAutoGenerated:=1\n"
             "Segment2_Extent:=2 2 1 1 0 0\n"
             "Segment2_ID:=Segment_9\n"
             "Segment2_LabelValue:=9\n"
             "Segment2_Layer:=0\n"
             "Segment2_Name:=Segment_9\n"
             "Segment2_NameAutoGenerated:=1\n"
             "Segment2_Tags:=|\n"
             "\n",
             c9[0] / 255.0, c9[1] / 255.0, c9[2] / 255.0);
    const char *got = read_header(path);
    CHECK(got);
    if (strcmp(got, want)) fprintf(stderr, "got:\n%s\nwant:\n%s\n", got, want);
    CHECK(!strcmp(got, want));
    /* and the reader names and colours the segments as the table did */
    bvox_label_table *back;
    CHECK_OK(bvox_label_table_read(path, &back));
    CHECK_EQ(back->n, 3);
    const bvox_label_entry *e2 = bvox_label_table_find(back, 2),
                           *e5 = bvox_label_table_find(back, 5),
                           *e9 = bvox_label_table_find(back, 9);
    CHECK(e2 && e5 && e9);
    CHECK(!strcmp(e2->name, "Left-Liver") && !strcmp(e5->name, "Spleen") &&
          !strcmp(e9->name, "Segment_9"));
    CHECK(e2->rgba[0] == 255 && e2->rgba[1] == 0 && e2->rgba[2] == 51);
    CHECK(e5->rgba[0] == 0 && e5->rgba[1] == 128 && e5->rgba[2] == 255);
    CHECK(!memcmp(e9->rgba, c9, 3));
    bvox_label_table_destroy(back);
    bvox_label_table_destroy(t);
    bvox_volume_destroy(like);
    return 0;
}

/* The smallest unsigned type by the largest label, at each boundary; the
 * type asked for when every label fits it, a clean refusal when not. */
TEST(sample_type_choice)
{
    bvox_volume *like = make_like();
    CHECK(like);
    uint32_t l[NX * NY * NZ];
    const struct {
        uint32_t top;
        bvox_dtype want;
    } cases[] = {{255, BVOX_DT_U8}, {256, BVOX_DT_U16}, {65535, BVOX_DT_U16},
                 {65536, BVOX_DT_U32}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        make_labels(l);
        l[0] = cases[k].top;
        const char *path = harness_path("t.nrrd");
        CHECK_OK(bvox_write_labels(path, like, l, -1, NULL));
        bvox_labelset *set;
        CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
        CHECK_EQ((int)set->dtype, (int)cases[k].want);
        CHECK_EQ(set->objects[set->n - 1].label, (int64_t)cases[k].top);
        bvox_labelset_destroy(set);
    }
    make_labels(l); /* largest 200: over int8 */
    const char *path = harness_path("r.mha");
    CHECK_STATUS(bvox_write_labels(path, like, l, BVOX_DT_I8, NULL), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "label 200 does not fit i8"));
    CHECK_STATUS(bvox_write_labels(path, like, l, BVOX_DT_F32, NULL), BVOX_EINVAL);
    CHECK(!exists(path));
    CHECK_OK(bvox_write_labels(path, like, l, BVOX_DT_U8, NULL));
    bvox_volume_destroy(like);
    return 0;
}

TEST(refused_and_failed_writes_leave_nothing)
{
    bvox_volume *like = make_like();
    CHECK(like);
    uint32_t l[NX * NY * NZ];
    make_labels(l);
    CHECK_STATUS(bvox_write_labels(harness_path("x.png"), like, l, -1, NULL), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), ".seg.nrrd"));
    CHECK_STATUS(bvox_write_labels(NULL, like, l, -1, NULL), BVOX_EINVAL);
    l[5] = 70000; /* over the .seg.nrrd bound, fine as .nrrd */
    const char *seg = harness_path("big.seg.nrrd");
    CHECK_STATUS(bvox_write_labels(seg, like, l, -1, NULL), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), "label 70000"));
    CHECK(!exists(seg));
    CHECK_OK(bvox_write_labels(harness_path("big.nrrd"), like, l, -1, NULL));
    /* a write failing part-way: no header, no data file, whatever fails */
    const char *names[] = {"f.nrrd", "f.nhdr", "f.mha", "f.mhd", "f.seg.nrrd", "f.nii"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        for (long n = 1; n <= 3; n++) {
            make_labels(l);
            bvox__sink_fail_after(n);
            bvox_status st = bvox_write_labels(harness_path(names[k]), like, l, -1, NULL);
            bvox__sink_fail_after(0);
            if (st == BVOX_OK) { /* fewer writes than n: nothing failed */
                remove(harness_path(names[k]));
                remove(harness_path("f.raw"));
                remove(harness_path("f.zraw"));
                continue;
            }
            CHECK_EQ(st, BVOX_EIO);
            CHECK_EQ(harness_count_entries(harness_tmpdir()), 1); /* big.nrrd alone */
        }
    bvox_volume_destroy(like);
    return 0;
}
