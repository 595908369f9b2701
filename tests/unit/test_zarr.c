/* test_zarr.c — OME-Zarr volumes: round trips at awkward sizes and odd chunk
 * shapes against the byte-per-voxel reference, the (z, y, x) byte order of a
 * chunk, the multiscales scale and unit, every sample type through the read
 * options, fill values, and the clear errors (naming the chunk) for missing
 * or wrong-sized chunks, unknown compressors and lying metadata; the JSON
 * parser under it. */
#include "harness.h"
#include "io/zarr.h"
#include "ref/voxref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <blosc.h>
#include <zlib.h>

static void put(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    fwrite(data, 1, n, f);
    fclose(f);
}

static void put_text(const char *path, const char *s) { put(path, s, strlen(s)); }

static size_t get(const char *path, uint8_t *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(buf, 1, cap, f);
    fclose(f);
    return n;
}

TEST(roundtrip_awkward_sizes_and_chunks)
{
    static const int cases[][6] = {
        /* nx ny nz, chunks x y z (0: default) */
        {1, 1, 1, 0, 0, 0},      {70, 120, 130, 37, 100, 65}, {9, 3, 65, 0, 0, 0},
        {5, 7, 64, 2, 3, 5},     {3, 11, 63, 1, 2, 3},        {130, 2, 1, 64, 64, 64},
        {31, 17, 200, 31, 17, 200},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const int *s = cases[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 3, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        bvox_geometry g = *bvox_volume_geometry(v);
        g.spacing[0] = 0.5, g.spacing[1] = 0.25, g.spacing[2] = 2;
        strcpy(g.unit, "um");
        CHECK_OK(bvox_volume_set_geometry(v, &g));
        bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
        wo.chunks[0] = s[3], wo.chunks[1] = s[4], wo.chunks[2] = s[5];
        wo.compressor = i % 2 ? "blosc" : "zlib"; /* both codecs, every shape class */
        char name[32];
        snprintf(name, sizeof name, "a%zu.zarr", i); /* a new folder per case */
        const char *p = harness_path(name);
        CHECK_OK(bvox_write(p, v, &wo));
        bvox_volume *w;
        CHECK_OK(bvox_read(p, NULL, &w));
        CHECK_OK(bvox_volume_check(w));
        CHECK(voxref_matches(r, w));
        const bvox_geometry *h = bvox_volume_geometry(w);
        CHECK_EQ(h->spacing[0], 0.5);
        CHECK_EQ(h->spacing[1], 0.25);
        CHECK_EQ(h->spacing[2], 2.0);
        CHECK(!strcmp(h->unit, "um"));
        /* the array itself (not the group) reads too */
        char arr[4200];
        snprintf(arr, sizeof arr, "%s/0", p);
        bvox_volume *u;
        CHECK_OK(bvox_read(arr, NULL, &u));
        CHECK(voxref_matches(r, u));
        bvox_volume_destroy(u);
        bvox_volume_destroy(w);
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* One voxel at (x, y, z) = (3, 5, 7) lands at byte (z * ny + y) * nx + x of
 * the one chunk: the array is (z, y, x), C order. */
TEST(chunk_order_is_zyx)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){10, 9, 8}, &v));
    bvox_volume_set(v, 3, 5, 7, 1);
    const char *p = harness_path("o.zarr");
    CHECK_OK(bvox_write(p, v, NULL));
    char path[4200];
    snprintf(path, sizeof path, "%s/0/0.0.0", p);
    static uint8_t z[4096], raw[720];
    size_t zn = get(path, z, sizeof z);
    CHECK(zn > 0);
    uLongf n = sizeof raw;
    CHECK_EQ(uncompress(raw, &n, z, zn), Z_OK);
    CHECK_EQ((size_t)n, (size_t)720);
    size_t sum = 0;
    for (size_t i = 0; i < n; i++) sum += raw[i];
    CHECK_EQ(sum, (size_t)1);
    CHECK_EQ(raw[(7 * 9 + 5) * 10 + 3], 1);
    snprintf(path, sizeof path, "%s/0/.zarray", p);
    static uint8_t meta[2048];
    size_t mn = get(path, meta, sizeof meta - 1);
    meta[mn] = 0;
    CHECK(strstr((char *)meta, "\"shape\": [8, 9, 10]") != NULL);
    bvox_volume_destroy(v);
    return 0;
}

/* A hand-made array: shape [2, 3, 4] (z, y, x) of dtype, one chunk per z
 * slice of shape [1, 3, 4], compressor as given, chunks written raw bytes. */
static const char *make_array(const char *dir, const char *dtype, const char *compressor,
                              const char *fill)
{
    const char *p = harness_path(dir);
    char cmd[4300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", p, p);
    if (system(cmd) != 0) abort();
    char meta[1024], path[4300];
    snprintf(meta, sizeof meta,
             "{\"zarr_format\": 2, \"shape\": [2, 3, 4], \"chunks\": [1, 3, 4], \"dtype\": "
             "\"%s\", \"compressor\": %s, \"fill_value\": %s, \"order\": \"C\", \"filters\": "
             "null}",
             dtype, compressor, fill);
    snprintf(path, sizeof path, "%s/.zarray", p);
    put_text(path, meta);
    return p;
}

static void put_chunk(const char *arr, const char *key, const void *data, size_t n, int gz)
{
    char path[4300];
    snprintf(path, sizeof path, "%s/%s", arr, key);
    if (gz < 0) {
        put(path, data, n);
        return;
    }
    uint8_t out[1024];
    z_stream s;
    memset(&s, 0, sizeof s);
    deflateInit2(&s, 6, Z_DEFLATED, gz ? 31 : 15, 8, Z_DEFAULT_STRATEGY);
    s.next_in = (Bytef *)data;
    s.avail_in = (uInt)n;
    s.next_out = out;
    s.avail_out = sizeof out;
    deflate(&s, Z_FINISH);
    size_t zn = sizeof out - s.avail_out;
    deflateEnd(&s);
    put(path, out, zn);
}

TEST(dtypes_and_read_options)
{
    /* int16 big-endian, values 0..23 (x fastest), gzip: threshold 12 keeps 12 */
    const char *a = make_array("i16.zarr", ">i2", "{\"id\": \"gzip\", \"level\": 5}", "0");
    uint8_t be[48];
    for (int i = 0; i < 24; i++) be[2 * i] = 0, be[2 * i + 1] = (uint8_t)i;
    put_chunk(a, "0.0.0", be, 24, 1);
    put_chunk(a, "1.0.0", be + 24, 24, 1);
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_THRESHOLD;
    o.binarize.threshold = 12;
    bvox_volume *v;
    CHECK_OK(bvox_read(a, &o, &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 4);
    CHECK_EQ(d.ny, 3);
    CHECK_EQ(d.nz, 2);
    CHECK_EQ(bvox_volume_count(v), 12);
    CHECK_EQ(bvox_volume_get(v, 0, 0, 1), 1); /* value 12 at z=1, y=0, x=0 */
    CHECK_EQ(bvox_volume_get(v, 3, 2, 0), 0); /* value 11 */
    bvox_volume_destroy(v);

    /* float32 little-endian, zlib, label 5.5 */
    a = make_array("f32.zarr", "<f4", "{\"id\": \"zlib\"}", "\"NaN\"");
    float f[24];
    for (int i = 0; i < 24; i++) f[i] = i == 7 || i == 20 ? 5.5f : (float)i;
    put_chunk(a, "0.0.0", f, 48, 0);
    put_chunk(a, "1.0.0", f + 12, 48, 0);
    o.binarize.mode = BVOX_BIN_LABEL;
    o.binarize.label = 5.5;
    CHECK_OK(bvox_read(a, &o, &v));
    CHECK_EQ(bvox_volume_count(v), 2);
    CHECK_EQ(bvox_volume_get(v, 3, 1, 0), 1);
    CHECK_EQ(bvox_volume_get(v, 0, 2, 1), 1);
    bvox_volume_destroy(v);

    /* bool, uncompressed, a missing chunk filled with true */
    a = make_array("b1.zarr", "|b1", "null", "true");
    uint8_t b[12] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    put_chunk(a, "0.0.0", b, 12, -1);
    CHECK_OK(bvox_read(a, NULL, &v));
    CHECK_EQ(bvox_volume_count(v), 2 + 12);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A box read binarises by the read options as a whole-volume read does
 * (values 0..23, x fastest, as in dtypes_and_read_options). */
TEST(box_reads_use_the_read_options)
{
    const char *a = make_array("box16.zarr", ">i2", "{\"id\": \"gzip\", \"level\": 5}", "0");
    uint8_t be[48];
    for (int i = 0; i < 24; i++) be[2 * i] = 0, be[2 * i + 1] = (uint8_t)i;
    put_chunk(a, "0.0.0", be, 24, 1);
    put_chunk(a, "1.0.0", be + 24, 24, 1);
    bvox__zarr *z;
    CHECK_OK(bvox__zarr_open(a, &z));
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){2, 3, 2}, &v)); /* x 1..2, every y and z */
    /* nonzero (no options): all but value 0 (x = 0) -> the box holds 12 set */
    CHECK_OK(bvox__zarr_read_box(z, 1, 0, 0, 2, 3, 2, NULL, v));
    CHECK_EQ(bvox_volume_count(v), 12);
    /* threshold 12: z = 1 only (values 12..23) -> 6 */
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    bvox_binarize how = ro.binarize;
    how.mode = BVOX_BIN_THRESHOLD;
    how.threshold = 12;
    CHECK_OK(bvox__zarr_read_box(z, 1, 0, 0, 2, 3, 2, &how, v));
    CHECK_EQ(bvox_volume_count(v), 6);
    CHECK_EQ(bvox_volume_get(v, 0, 0, 1), 1); /* value 13 */
    CHECK_EQ(bvox_volume_get(v, 1, 2, 0), 0); /* value 10 */
    /* label 6: x = 2, y = 1, z = 0 -> box (1, 1, 0) */
    how.mode = BVOX_BIN_LABEL;
    how.label = 6;
    CHECK_OK(bvox__zarr_read_box(z, 1, 0, 0, 2, 3, 2, &how, v));
    CHECK_EQ(bvox_volume_count(v), 1);
    CHECK_EQ(bvox_volume_get(v, 1, 1, 0), 1);
    /* Otsu on a box would not be the volume's threshold: refused */
    how.mode = BVOX_BIN_OTSU;
    CHECK_STATUS(bvox__zarr_read_box(z, 1, 0, 0, 2, 3, 2, &how, v), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), "Otsu") != NULL);
    bvox_volume_destroy(v);
    bvox__zarr_close(z);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

static int read_fails(const char *path, bvox_status want, const char *needle)
{
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = bvox_read(path, NULL, &v);
    if (st != want || v != NULL || !strstr(bvox_errmsg(), needle)) {
        fprintf(stderr, "  %s: got %s '%s', want %s containing '%s'\n", path,
                bvox_status_name(st), bvox_errmsg(), bvox_status_name(want), needle);
        return 1;
    }
    return 0;
}

TEST(bad_arrays_name_the_chunk)
{
    uint8_t c[12] = {0};
    /* missing chunk and no fill value */
    const char *a = make_array("miss.zarr", "|u1", "null", "null");
    put_chunk(a, "0.0.0", c, 12, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 1.0.0 is missing"));
    /* a chunk of the wrong size: raw, zlib too short, zlib too long */
    put_chunk(a, "1.0.0", c, 11, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 1.0.0 does not hold 1 x 3 x 4"));
    a = make_array("size.zarr", "|u1", "{\"id\": \"zlib\"}", "0");
    uint8_t big[13] = {0};
    put_chunk(a, "0.0.0", big, 13, 0);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0 does not hold"));
    put_chunk(a, "0.0.0", big, 11, 0);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0 does not hold"));
    put_chunk(a, "0.0.0", "garbage!", 8, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0: corrupt"));
    /* Blosc: a valid chunk of the wrong size, a truncated one, a lying header */
    a = make_array("blosc.zarr", "|u1", "{\"id\": \"blosc\", \"cname\": \"lz4\"}", "0");
    uint8_t bz[64 + BLOSC_MAX_OVERHEAD];
    int bn = blosc_compress_ctx(5, BLOSC_BITSHUFFLE, 1, 13, big, bz, sizeof bz, "lz4", 0, 1);
    CHECK(bn > 0);
    put_chunk(a, "0.0.0", bz, (size_t)bn, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0 does not hold"));
    bn = blosc_compress_ctx(5, BLOSC_BITSHUFFLE, 1, 12, big, bz, sizeof bz, "lz4", 0, 1);
    put_chunk(a, "0.0.0", bz, (size_t)bn - 1, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0: corrupt"));
    bz[12] = 0xff; /* cbytes claims more than the file holds */
    put_chunk(a, "0.0.0", bz, (size_t)bn, -1);
    CHECK(!read_fails(a, BVOX_EFORMAT, "chunk 0.0.0: corrupt"));
    /* unknown compressor, dtype, order, filters */
    a = make_array("comp.zarr", "|u1", "{\"id\": \"lz4\"}", "0");
    CHECK(!read_fails(a, BVOX_EUNSUPPORTED, "unknown compressor \"lz4\""));
    a = make_array("dt.zarr", "<c8", "null", "0");
    CHECK(!read_fails(a, BVOX_EUNSUPPORTED, "dtype \"<c8\""));
    a = make_array("fill.zarr", "|u1", "null", "300");
    CHECK(!read_fails(a, BVOX_EFORMAT, "fill_value 300"));
    /* shape over the limits, not 3-D, chunks nonsense, not JSON */
    const char *p = harness_path("shape.zarr");
    char path[4300];
    mkdir(p, 0777);
    snprintf(path, sizeof path, "%s/.zarray", p);
    put_text(path, "{\"zarr_format\": 2, \"shape\": [70000, 1, 1], \"chunks\": [1, 1, 1], "
                   "\"dtype\": \"|u1\", \"compressor\": null, \"fill_value\": 0, \"order\": "
                   "\"C\", \"filters\": null}");
    CHECK(!read_fails(p, BVOX_EFORMAT, "\"shape\" entries must be integers"));
    put_text(path, "{\"zarr_format\": 2, \"shape\": [4, 4], \"chunks\": [1, 1], "
                   "\"dtype\": \"|u1\", \"order\": \"C\"}");
    CHECK(!read_fails(p, BVOX_EUNSUPPORTED, "3 dimensions"));
    put_text(path, "{\"zarr_format\": 2, \"shape\": [4, 4, 4], \"chunks\": [0, 1, 1], "
                   "\"dtype\": \"|u1\", \"order\": \"C\"}");
    CHECK(!read_fails(p, BVOX_EFORMAT, "\"chunks\""));
    put_text(path, "{\"zarr_format\": 2, \"shape\": [4, 4, 4],");
    CHECK(!read_fails(p, BVOX_EFORMAT, "line 1"));
    CHECK(!read_fails(harness_path("nothing_here"), BVOX_ENOTFOUND, "no such file"));
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A failed write leaves nothing: the output folder's parent is missing, and
 * an existing output is kept when the write fails (bad chunk size). */
TEST(failed_write_leaves_nothing)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 4, 4}, &v));
    CHECK_STATUS(bvox_write(harness_path("no/such/x.zarr"), v, NULL), BVOX_ENOTFOUND);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = -1;
    const char *p = harness_path("keep.zarr");
    CHECK_STATUS(bvox_write(p, v, &wo), BVOX_EINVAL);
    struct stat sb;
    CHECK(stat(p, &sb) != 0);
    bvox_volume_destroy(v);
    return 0;
}

TEST(json_parser)
{
    bvox__jtree j;
    const char *ok = " {\"a\": [1, -2.5e3, true, false, null], \"s\": \"x\\u00e9\\n\\ud83d\\ude00\","
                     " \"o\": {}, \"e\": []} ";
    CHECK_OK(bvox__jtree_parse(ok, strlen(ok), "t", &j));
    const bvox__jnode *a = bvox__jtree_get(&j, &j.nodes[0], "a");
    CHECK(a && a->count == 5);
    CHECK(bvox__jtree_at(&j, a, 0)->is_int);
    CHECK_EQ(bvox__jtree_at(&j, a, 1)->num, -2500.0);
    CHECK(!bvox__jtree_at(&j, a, 1)->is_int);
    CHECK(bvox__jtree_at(&j, a, 5) == NULL);
    const bvox__jnode *s = bvox__jtree_get(&j, &j.nodes[0], "s");
    CHECK(s && !strcmp(s->str, "x\xc3\xa9\n\xf0\x9f\x98\x80"));
    CHECK(bvox__jtree_get(&j, &j.nodes[0], "missing") == NULL);
    bvox__jtree_release(&j);
    static const char *const bad[] = {
        "", "{", "[1,]", "{\"a\" 1}", "{\"a\":1,}", "01", "1.", "-", "nul", "\"\\x\"",
        "\"\\ud800\"", "[1] 2", "NaN", "\"a\nb\"", "{1: 2}", "1e999",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_STATUS(bvox__jtree_parse(bad[i], strlen(bad[i]), "t", &j), BVOX_EFORMAT);
        CHECK(j.nodes == NULL && j.text == NULL);
    }
    /* depth limit */
    char deep[200];
    memset(deep, '[', sizeof deep);
    CHECK_STATUS(bvox__jtree_parse(deep, sizeof deep, "t", &j), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "deeper") != NULL);
    return 0;
}
