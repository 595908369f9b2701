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
        {"NRRD0004\ntype: uchar\ndimension: 4\n", BVOX_EUNSUPPORTED, "dimension 4"},
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
