/*
 * test_nrrd.c — the NRRD reader (nrrd.c) on hand-written headers: attached
 * raw data in LPS space (geometry turned to RAS), gzip-encoded detached
 * data in big-endian u16 (.nhdr), byte skip -1 and line skip, 2D, the
 * label reader on NRRD, and bad headers refused with a clear status.
 */
#include "harness.h"
#include "io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static bvox_status write_file(const char *path, const void *a, size_t na, const void *b,
                              size_t nb, int gzip)
{
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, gzip, &s);
    if (!st && na) st = bvox__sink_write(&s, a, na);
    if (!st && nb) st = bvox__sink_write(&s, b, nb);
    if (st) {
        bvox__sink_abort(&s);
        return st;
    }
    return bvox__sink_commit(&s);
}

/* 4 x 3 x 2 u8, voxel (x, y, z) = 1 where x == y or z == 1 and x == 3: 9 voxels. */
static void sample(uint8_t v[24])
{
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 4; x++) v[(z * 3 + y) * 4 + x] = (x == y) || (z == 1 && x == 3);
}

TEST(attached_raw_lps)
{
    const char *hdr = "NRRD0004\n"
                      "# Complete NRRD file format specification at:\n"
                      "type: unsigned char\n"
                      "dimension: 3\n"
                      "space: left-posterior-superior\n"
                      "sizes: 4 3 2\n"
                      "space directions: (0.5,0,0) (0,0.75,0) (0,0,2.5)\n"
                      "kinds: domain domain domain\n"
                      "encoding: raw\n"
                      "space units: \"mm\" \"mm\" \"mm\"\n"
                      "space origin: (10,-20,30)\n"
                      "Segment0_Name:=tumour\n"
                      "\n";
    uint8_t v[24];
    sample(v);
    size_t hn = strlen(hdr);
    uint8_t *buf = malloc(hn + 24);
    CHECK(buf);
    memcpy(buf, hdr, hn);
    memcpy(buf + hn, v, 24);
    bvox_volume *vol;
    CHECK_OK(bvox_read_memory(buf, hn + 24, "a.nrrd", NULL, &vol));
    bvox_dims d = bvox_volume_dims(vol);
    CHECK(d.nx == 4 && d.ny == 3 && d.nz == 2);
    CHECK_EQ(bvox_volume_count(vol), 9);
    CHECK(bvox_volume_get(vol, 2, 2, 0) && bvox_volume_get(vol, 3, 0, 1) &&
          !bvox_volume_get(vol, 3, 0, 0));
    const bvox_geometry *g = bvox_volume_geometry(vol);
    CHECK_NEAR(g->spacing[0], 0.5, 1e-12);
    CHECK_NEAR(g->spacing[1], 0.75, 1e-12);
    CHECK_NEAR(g->spacing[2], 2.5, 1e-12);
    /* LPS -> RAS */
    CHECK_NEAR(g->origin[0], -10, 1e-12);
    CHECK_NEAR(g->origin[1], 20, 1e-12);
    CHECK_NEAR(g->origin[2], 30, 1e-12);
    CHECK(g->direction[0] == -1 && g->direction[4] == -1 && g->direction[8] == 1);
    CHECK(!strcmp(g->unit, "mm"));
    bvox_volume_destroy(vol);
    /* the same bytes as a label volume: labels 1 only */
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(buf, hn + 24, "a.nrrd", NULL, 0, &set));
    CHECK(set->n == 1 && set->objects[0].count == 9);
    bvox_labelset_destroy(set);
    free(buf);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(detached_gzip_big_endian_and_skips)
{
    char dir[] = "/tmp/bvox_nrrd_XXXXXX";
    CHECK(mkdtemp(dir));
    uint8_t v8[24];
    sample(v8);
    uint8_t be[48];
    for (int i = 0; i < 24; i++) {
        uint16_t x = (uint16_t)(v8[i] ? 300 + i : 0);
        be[2 * i] = (uint8_t)(x >> 8);
        be[2 * i + 1] = (uint8_t)x;
    }
    char hpath[128], dpath[128];
    snprintf(dpath, sizeof dpath, "%s/data.raw.gz", dir);
    CHECK_OK(write_file(dpath, be, 48, NULL, 0, 1));
    const char *h = "NRRD0005\ntype: ushort\ndimension: 3\nsizes: 4 3 2\nendian: big\n"
                    "encoding: gzip\nspacings: 2 3 4\ndata file: data.raw.gz\n";
    snprintf(hpath, sizeof hpath, "%s/v.nhdr", dir);
    CHECK_OK(write_file(hpath, h, strlen(h), NULL, 0, 0));
    bvox_volume *vol;
    CHECK_OK(bvox_read(hpath, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    CHECK(bvox_volume_get(vol, 3, 0, 1));
    CHECK_NEAR(bvox_volume_geometry(vol)->spacing[2], 4, 1e-12);
    bvox_volume_destroy(vol);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(hpath, NULL, 0, &set));
    CHECK_EQ(set->n, 9); /* every 1-voxel has its own label 300 + i */
    bvox_labelset_destroy(set);
    /* raw, little endian, after a line skip of two text lines and "byte skip: -1" */
    uint16_t le[24];
    for (int i = 0; i < 24; i++) le[i] = v8[i];
    const char *junk = "first line\nsecond\nXXXX";
    snprintf(dpath, sizeof dpath, "%s/le.raw", dir);
    CHECK_OK(write_file(dpath, junk, strlen(junk), le, sizeof le, 0));
    const char *h2 = "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 4 3 2\nendian: little\n"
                     "encoding: raw\nline skip: 2\nbyte skip: -1\ndata file: le.raw\n";
    CHECK_OK(write_file(hpath, h2, strlen(h2), NULL, 0, 0));
    CHECK_OK(bvox_read(hpath, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    bvox_volume_destroy(vol);
    /* the data file missing: not found, naming it */
    remove(dpath);
    CHECK_STATUS(bvox_read(hpath, NULL, &vol), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "le.raw") != NULL);
    remove(hpath);
    snprintf(dpath, sizeof dpath, "%s/data.raw.gz", dir);
    remove(dpath);
    rmdir(dir);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(two_d_is_one_slice)
{
    const char *hdr = "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 3 2\nencoding: raw\n\n";
    uint8_t buf[128];
    size_t n = strlen(hdr);
    memcpy(buf, hdr, n);
    const uint8_t px[6] = {0, 1, 1, 0, 0, 1};
    memcpy(buf + n, px, 6);
    bvox_volume *vol;
    CHECK_OK(bvox_read_memory(buf, n + 6, "s.nrrd", NULL, &vol));
    CHECK(bvox_volume_dims(vol).nz == 1);
    CHECK_EQ(bvox_volume_count(vol), 3);
    bvox_volume_destroy(vol);
    return 0;
}

TEST(bad_headers)
{
    static const struct {
        const char *text;
        bvox_status want;
        const char *says;
    } cases[] = {
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n\nxx",
         BVOX_EFORMAT, "truncated"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\n\n", BVOX_EFORMAT, "'encoding'"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: ascii\n\n",
         BVOX_EUNSUPPORTED, "encoding 'ascii'"},
        {"NRRD0004\ntype: uchar\ndimension: 5\n", BVOX_EUNSUPPORTED, "dimension 5"},
        /* 4D only as segmentation layers: the first axis a list */
        {"NRRD0004\ntype: uchar\ndimension: 4\nsizes: 2 2 2 2\n"
         "kinds: domain domain domain domain\n",
         BVOX_EUNSUPPORTED, "segmentation layers"},
        {"NRRD0004\ntype: float\ndimension: 4\nsizes: 2 1 1 1\nkinds: list domain domain "
         "domain\nencoding: raw\n\n01234567",
         BVOX_EUNSUPPORTED, "layered segmentation of f32"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 0 2\n", BVOX_EFORMAT, "sizes"},
        {"NRRD0004\ntype: block\n", BVOX_EUNSUPPORTED, "type 'block'"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: gzip\n\nnot gzip",
         BVOX_EFORMAT, ""},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n", BVOX_EFORMAT,
         "no blank line"},
        {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n"
         "space directions: (1,0,0) (0,1,0)\n\n",
         BVOX_EFORMAT, "space directions"},
        {"NRRD0004\nnonsense\n", BVOX_EFORMAT, "not 'field: value'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bvox_volume *vol = (bvox_volume *)1;
        bvox_status st = bvox_read_memory(cases[i].text, strlen(cases[i].text), "bad.nrrd",
                                          NULL, &vol);
        if (st != cases[i].want || vol != NULL || !strstr(bvox_errmsg(), cases[i].says) ||
            !strstr(bvox_errmsg(), "bad.nrrd")) {
            fprintf(stderr, "case %zu: %s: %s\n", i, bvox_status_name(st), bvox_errmsg());
            return 1;
        }
        CHECK_EQ(bvox_memory_in_use(), 0);
    }
    return 0;
}

/* A header and samples in one buffer (malloc'ed). */
static uint8_t *with_data(const char *hdr, const uint8_t *v, size_t n, size_t *size)
{
    size_t hn = strlen(hdr);
    uint8_t *buf = malloc(hn + n);
    if (!buf) return NULL;
    memcpy(buf, hdr, hn);
    memcpy(buf + hn, v, n);
    *size = hn + n;
    return buf;
}

/* Slicer's .seg.nrrd with one layer: the label values are the labels, the
 * segments' names and colours the table. */
TEST(seg_nrrd_segments_as_labels)
{
    const char *hdr = "NRRD0004\ntype: unsigned char\ndimension: 3\n"
                      "space: left-posterior-superior\nsizes: 4 3 2\n"
                      "space directions: (1,0,0) (0,1,0) (0,0,2)\nkinds: domain domain domain\n"
                      "encoding: raw\nspace origin: (0,0,0)\n"
                      "Segment0_Color:=1 0 0\nSegment0_ID:=Segment_1\n"
                      "Segment0_LabelValue:=1\nSegment0_Layer:=0\nSegment0_Name:=Liver\n"
                      "Segment1_Color:=0 0.5 1\nSegment1_LabelValue:=7\nSegment1_Layer:=0\n"
                      "Segment1_Name:=Left kidney\n"
                      "Segmentation_MasterRepresentation:=Binary labelmap\n\n";
    uint8_t v[24] = {0};
    v[0] = v[1] = v[2] = 1;          /* 3 voxels of Liver */
    v[12] = v[13] = v[14] = v[15] = 7; /* 4 of Left kidney */
    size_t n;
    uint8_t *buf = with_data(hdr, v, 24, &n);
    CHECK(buf);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(buf, n, "s.seg.nrrd", NULL, 0, &set));
    CHECK_EQ(set->n, 2);
    CHECK(set->objects[0].label == 1 && set->objects[0].count == 3);
    CHECK(set->objects[1].label == 7 && set->objects[1].count == 4);
    bvox_labelset_destroy(set);
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_parse((const char *)buf, n, "s.seg.nrrd", &t));
    CHECK_EQ(t->n, 2);
    const bvox_label_entry *e = bvox_label_table_find(t, 1);
    CHECK(e && !strcmp(e->name, "Liver") && e->has_color && e->rgba[0] == 255 && e->rgba[1] == 0);
    e = bvox_label_table_find(t, 7);
    CHECK(e && !strcmp(e->name, "Left kidney") && e->rgba[1] == 128 && e->rgba[2] == 255);
    bvox_label_table_destroy(t);
    free(buf);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Overlapping segments in two layers (a 4D file, the layer axis first):
 * each segment becomes label N + 1; a voxel in two keeps the later one. */
TEST(seg_nrrd_segments_as_bit_layers)
{
    const char *hdr = "NRRD0004\ntype: unsigned char\ndimension: 4\n"
                      "space: left-posterior-superior\nsizes: 2 4 3 2\n"
                      "space directions: none (0.5,0,0) (0,0.5,0) (0,0,3)\n"
                      "kinds: list domain domain domain\nencoding: gzip\n"
                      "space origin: (1,2,3)\n"
                      "Segment0_LabelValue:=1\nSegment0_Layer:=0\nSegment0_Name:=skin\n"
                      "Segment1_LabelValue:=2\nSegment1_Layer:=0\nSegment1_Name:=bone\n"
                      "Segment2_LabelValue:=1\nSegment2_Layer:=1\nSegment2_Name:=tumour\n"
                      "Segment2_Color:=0 1 0\n\n";
    uint8_t v[48] = {0}; /* v[2 * voxel + layer] */
    for (int i = 0; i < 6; i++) v[2 * i] = 1;      /* voxels 0..5: skin */
    for (int i = 6; i < 10; i++) v[2 * i] = 2;     /* 6..9: bone */
    for (int i = 4; i < 8; i++) v[2 * i + 1] = 1;  /* 4..7: tumour, over skin and bone */
    const char *path = harness_path("layers.seg.nrrd");
    CHECK_OK(write_file(path, hdr, strlen(hdr), NULL, 0, 0));
    { /* the samples gzip-encoded after the plain header */
        bvox__sink s;
        CHECK_OK(bvox__sink_open(path, 0, &s));
        CHECK_OK(bvox__sink_write(&s, hdr, strlen(hdr)));
        CHECK_OK(bvox__sink_compress(&s, 1));
        CHECK_OK(bvox__sink_write(&s, v, sizeof v));
        CHECK_OK(bvox__sink_commit(&s));
    }
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(path, NULL, 0, &set));
    CHECK_EQ(set->n, 3);
    CHECK(set->objects[0].label == 1 && set->objects[0].count == 4); /* skin 0..3 */
    CHECK(set->objects[1].label == 2 && set->objects[1].count == 2); /* bone 8, 9 */
    CHECK(set->objects[2].label == 3 && set->objects[2].count == 4); /* tumour 4..7 */
    CHECK_NEAR(set->geometry.spacing[2], 3, 1e-12);
    CHECK_NEAR(set->geometry.origin[0], -1, 1e-12);
    CHECK_EQ(set->dims.nx, 4);
    bvox_labelset_destroy(set);
    bvox_label_table *t;
    CHECK_OK(bvox_label_table_read(path, &t));
    const bvox_label_entry *e = bvox_label_table_find(t, 3);
    CHECK(e && !strcmp(e->name, "tumour") && e->rgba[1] == 255);
    e = bvox_label_table_find(t, 2);
    CHECK(e && !strcmp(e->name, "bone") && !e->has_color);
    bvox_label_table_destroy(t);
    /* as a binary volume: every voxel of any segment */
    bvox_volume *vol;
    CHECK_OK(bvox_read(path, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 10);
    bvox_volume_destroy(vol);
    /* Slicer before 4.11: one 0/1 layer per segment, no LabelValue/Layer keys */
    const char *old = "NRRD0004\ntype: uchar\ndimension: 4\nsizes: 2 4 3 2\n"
                      "kinds: list domain domain domain\nencoding: raw\n"
                      "Segment0_Name:=a\nSegment1_Name:=b\n\n";
    uint8_t w[48] = {0};
    w[0] = 1;          /* voxel 0 in a */
    w[3] = w[5] = 1;   /* voxels 1, 2 in b */
    size_t n;
    uint8_t *buf = with_data(old, w, 48, &n);
    CHECK(buf);
    CHECK_OK(bvox_labels_read_memory(buf, n, "old.seg.nrrd", NULL, 0, &set));
    CHECK(set->n == 2 && set->objects[0].count == 1 && set->objects[1].count == 2);
    bvox_labelset_destroy(set);
    free(buf);
    /* float layers are refused clearly */
    const char *fl = "NRRD0004\ntype: float\ndimension: 4\nsizes: 2 4 3 2\n"
                     "kinds: list domain domain domain\nencoding: raw\n\n";
    float fz[48] = {0};
    buf = with_data(fl, (const uint8_t *)fz, sizeof fz, &n);
    CHECK(buf);
    CHECK_STATUS(bvox_labels_read_memory(buf, n, "f.seg.nrrd", NULL, 0, &set), BVOX_EUNSUPPORTED);
    free(buf);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
