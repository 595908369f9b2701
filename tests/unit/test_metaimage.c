/*
 * test_metaimage.c — the MetaImage reader and writer (metaimage.c): a .mha
 * written by hand (big-endian shorts, a rotated TransformMatrix and an Offset
 * in LPS, turned into RAS), a .mhd with zlib-compressed .zraw data and one
 * with raw data after a HeaderSize, label volumes from both, write/read
 * round trips of both forms (voxels and geometry), and bad headers refused
 * with a clear status before any allocation the header drives.
 */
#include "harness.h"
#include "io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static bvox_status write_file(const char *path, const void *a, size_t na, const void *b,
                              size_t nb, int mode)
{
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, 0, &s);
    if (!st && na) st = bvox__sink_write(&s, a, na);
    if (!st && mode) st = bvox__sink_compress(&s, mode);
    if (!st && nb) st = bvox__sink_write(&s, b, nb);
    if (st) {
        bvox__sink_abort(&s);
        return st;
    }
    return bvox__sink_commit(&s);
}

/* 4 x 3 x 2, voxel (x, y, z) set where x == y or z == 1 and x == 3: 9 voxels. */
static int inside(int x, int y, int z) { return x == y || (z == 1 && x == 3); }

TEST(hand_written_mha)
{
    const char *hdr = "ObjectType = Image\n"
                      "NDims = 3\n"
                      "BinaryData = True\n"
                      "BinaryDataByteOrderMSB = True\n"
                      "CompressedData = False\n"
                      "TransformMatrix = 0 1 0 -1 0 0 0 0 1\n"
                      "Offset = 10 20 30\n"
                      "CenterOfRotation = 0 0 0\n"
                      "AnatomicalOrientation = RAI\n"
                      "ElementSpacing = 0.5 0.75 2.5\n"
                      "DimSize = 4 3 2\n"
                      "ElementType = MET_SHORT\n"
                      "ElementDataFile = LOCAL\n";
    size_t hn = strlen(hdr);
    uint8_t *buf = malloc(hn + 48);
    CHECK(buf);
    memcpy(buf, hdr, hn);
    for (int z = 0, i = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 4; x++, i++) {
                int v = inside(x, y, z) ? 1000 + i : 0; /* big endian: high byte first */
                buf[hn + 2 * i] = (uint8_t)(v >> 8);
                buf[hn + 2 * i + 1] = (uint8_t)v;
            }
    bvox_volume *vol;
    CHECK_OK(bvox_read_memory(buf, hn + 48, "a.mha", NULL, &vol));
    bvox_dims d = bvox_volume_dims(vol);
    CHECK(d.nx == 4 && d.ny == 3 && d.nz == 2);
    CHECK_EQ(bvox_volume_count(vol), 9);
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 4; x++) CHECK_EQ(bvox_volume_get(vol, x, y, z), inside(x, y, z));
    const bvox_geometry *g = bvox_volume_geometry(vol);
    CHECK_NEAR(g->spacing[0], 0.5, 1e-12);
    CHECK_NEAR(g->spacing[1], 0.75, 1e-12);
    CHECK_NEAR(g->spacing[2], 2.5, 1e-12);
    CHECK_NEAR(g->origin[0], -10, 1e-12); /* LPS -> RAS */
    CHECK_NEAR(g->origin[1], -20, 1e-12);
    CHECK_NEAR(g->origin[2], 30, 1e-12);
    /* axis x points along LPS (0,1,0) = RAS (0,-1,0); axis y along LPS
       (-1,0,0) = RAS (1,0,0) */
    CHECK(g->direction[0] == 0 && g->direction[3] == -1 && g->direction[6] == 0);
    CHECK(g->direction[1] == 1 && g->direction[4] == 0 && g->direction[7] == 0);
    CHECK(g->direction[8] == 1);
    CHECK(!strcmp(g->unit, "mm"));
    bvox_volume_destroy(vol);
    /* content sniffing finds it without a name or format */
    CHECK_OK(bvox_read_memory(buf, hn + 48, NULL, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    bvox_volume_destroy(vol);
    /* as a label volume: each voxel its own label 1000 + i */
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read_memory(buf, hn + 48, "a.mha", NULL, 0, &set));
    CHECK_EQ(set->n, 9);
    CHECK_EQ(set->objects[0].label, 1000);
    CHECK_EQ(set->objects[8].label, 1000 + 1 * 12 + 2 * 4 + 3); /* (3, 2, 1) */
    bvox_labelset_destroy(set);
    free(buf);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(mhd_with_zraw_and_header_size)
{
    uint8_t v[24];
    for (int z = 0, i = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 4; x++, i++) v[i] = inside(x, y, z) ? 7 : 0;
    /* zlib-compressed data in a .zraw beside the header */
    CHECK_OK(write_file(harness_path("v.zraw"), NULL, 0, v, 24, BVOX__SINK_ZLIB));
    const char *h = "NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\n"
                    "ElementSpacing = 2 3 4\nCompressedData = True\nElementDataFile = v.zraw\n";
    const char *hpath = harness_path("v.mhd");
    CHECK_OK(write_file(hpath, h, strlen(h), NULL, 0, 0));
    bvox_volume *vol;
    CHECK_OK(bvox_read(hpath, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    CHECK(bvox_volume_get(vol, 3, 0, 1) && !bvox_volume_get(vol, 3, 0, 0));
    CHECK_NEAR(bvox_volume_geometry(vol)->spacing[2], 4, 1e-12);
    bvox_volume_destroy(vol);
    bvox_labelset *set;
    CHECK_OK(bvox_labels_read(hpath, NULL, 0, &set));
    CHECK(set->n == 1 && set->objects[0].label == 7 && set->objects[0].count == 9);
    bvox_labelset_destroy(set);
    /* raw floats after a 5-byte header of the data file ("HeaderSize = 5"),
       and HeaderSize -1: the samples are the file's last bytes */
    float f[24];
    for (int i = 0; i < 24; i++) f[i] = v[i] ? 2.0f : 0.0f;
    CHECK_OK(write_file(harness_path("f.raw"), "JUNK!", 5, f, sizeof f, 0));
    const char *hf = "NDims = 3\nDimSize = 4 3 2\nElementType = MET_FLOAT\nHeaderSize = 5\n"
                     "ElementDataFile = f.raw\n";
    CHECK_OK(write_file(hpath, hf, strlen(hf), NULL, 0, 0));
    CHECK_OK(bvox_read(hpath, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    bvox_volume_destroy(vol);
    const char *hm = "NDims = 3\nDimSize = 4 3 2\nElementType = MET_FLOAT\nHeaderSize = -1\n"
                     "ElementDataFile = f.raw\n";
    CHECK_OK(write_file(hpath, hm, strlen(hm), NULL, 0, 0));
    CHECK_OK(bvox_read(hpath, NULL, &vol));
    CHECK_EQ(bvox_volume_count(vol), 9);
    bvox_volume_destroy(vol);
    /* the data file missing: not found, naming it */
    remove(harness_path("f.raw"));
    CHECK_STATUS(bvox_read(hpath, NULL, &vol), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "f.raw") != NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A random volume at awkward sizes, with a rotated geometry. */
static bvox_volume *random_volume(void)
{
    bvox_volume *vol = NULL;
    bvox_dims d = {13, 7, 67};
    if (bvox_volume_create(d, &vol)) return NULL;
    for (int z = 0; z < d.nz; z++)
        for (int y = 0; y < d.ny; y++)
            for (int x = 0; x < d.nx; x++)
                if (harness_rand() % 3 == 0) bvox_volume_set(vol, x, y, z, 1);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.3;
    g.spacing[1] = 0.7;
    g.spacing[2] = 2.5;
    g.origin[0] = -12.5;
    g.origin[1] = 3.25;
    g.origin[2] = 100;
    double c = cos(0.3), s = sin(0.3); /* a rotation about z */
    double dir[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    memcpy(g.direction, dir, sizeof dir);
    strcpy(g.unit, "mm");
    bvox_volume_set_geometry(vol, &g);
    return vol;
}

static int same_geometry(const bvox_geometry *a, const bvox_geometry *b)
{
    for (int i = 0; i < 3; i++)
        if (fabs(a->spacing[i] - b->spacing[i]) > 1e-12 || fabs(a->origin[i] - b->origin[i]) > 1e-12)
            return 0;
    for (int i = 0; i < 9; i++)
        if (fabs(a->direction[i] - b->direction[i]) > 1e-12) return 0;
    return 1;
}

TEST(write_read_round_trip)
{
    bvox_volume *vol = random_volume();
    CHECK(vol);
    const char *names[] = {"r.mha", "r.mhd", "r.nrrd", "r.nhdr"};
    for (int i = 0; i < 4; i++) {
        const char *p = harness_path(names[i]);
        CHECK_OK(bvox_write(p, vol, NULL));
        bvox_volume *back;
        CHECK_OK(bvox_read(p, NULL, &back));
        CHECK(bvox_volume_equal(vol, back));
        CHECK(same_geometry(bvox_volume_geometry(vol), bvox_volume_geometry(back)));
        CHECK(!strcmp(bvox_volume_geometry(back)->unit, "mm"));
        bvox_volume_destroy(back);
    }
    /* the detached forms wrote their data files beside the headers */
    CHECK(access(harness_path("r.zraw"), F_OK) == 0);
    CHECK(access(harness_path("r.raw"), F_OK) == 0);
    /* the .mha header is plain text ending in LOCAL; the data zlib (0x78) */
    FILE *fp = fopen(harness_path("r.mha"), "rb");
    CHECK(fp);
    char text[600];
    size_t n = fread(text, 1, sizeof text - 1, fp);
    fclose(fp);
    text[n] = '\0';
    char *local = strstr(text, "ElementDataFile = LOCAL\n");
    CHECK(local != NULL);
    CHECK_EQ((uint8_t)local[strlen("ElementDataFile = LOCAL\n")], 0x78);
    CHECK(strstr(text, "DimSize = 13 7 67\n") != NULL);
    bvox_volume_destroy(vol);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

static bvox_status read_text(const char *hdr, size_t extra)
{
    size_t n = strlen(hdr);
    uint8_t *buf = calloc(1, n + extra + 1);
    memcpy(buf, hdr, n);
    bvox_volume *vol = NULL;
    bvox_status st = bvox_read_memory(buf, n + extra, "bad.mha", NULL, &vol);
    bvox_volume_destroy(vol);
    free(buf);
    return st;
}

TEST(bad_headers)
{
    CHECK_STATUS(read_text("NDims = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n", 24),
                 BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "DimSize") != NULL);
    /* 2^60 voxels: refused before any allocation */
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 1048576 1048576 1048576\n"
                           "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                           24),
                 BVOX_EFORMAT);
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 1000 1000 1000\nElementType = MET_UCHAR\n"
                           "ElementDataFile = LOCAL\n",
                           24),
                 BVOX_EFORMAT); /* truncated: 10^9 bytes announced, 24 there */
    CHECK(strstr(bvox_errmsg(), "truncated") != NULL);
    CHECK_STATUS(read_text("NDims = 4\nDimSize = 2 2 2 2\n", 0), BVOX_EUNSUPPORTED);
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 4 3 2\nElementNumberOfChannels = 3\n"
                           "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                           72),
                 BVOX_EUNSUPPORTED);
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\n"
                           "ElementDataFile = LIST\n",
                           0),
                 BVOX_EUNSUPPORTED);
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 4 3 2\nElementType = MET_STRING\n"
                           "ElementDataFile = LOCAL\n",
                           24),
                 BVOX_EUNSUPPORTED);
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 4 3 2\nElementSpacing = 1 0 1\n"
                           "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                           24),
                 BVOX_EFORMAT);
    /* compressed data that are not zlib */
    CHECK_STATUS(read_text("NDims = 3\nDimSize = 4 3 2\nCompressedData = True\n"
                           "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                           24),
                 BVOX_EFORMAT);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(zlib_bomb_stops_at_the_announced_size)
{
    /* 4 x 3 x 2 announced, 1 MiB of zeros compressed: inflating stops at the
       announced 24 bytes (+ nothing): too big, not a 1 MiB allocation */
    size_t big = (size_t)1 << 20;
    uint8_t *zeros = calloc(1, big);
    CHECK(zeros);
    const char *h = "NDims = 3\nDimSize = 4 3 2\nCompressedData = True\n"
                    "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n";
    const char *p = harness_path("bomb.mha");
    CHECK_OK(write_file(p, h, strlen(h), zeros, big, BVOX__SINK_ZLIB));
    free(zeros);
    bvox_volume *vol;
    CHECK_STATUS(bvox_read(p, NULL, &vol), BVOX_ETOOBIG);
    CHECK(vol == NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
