/* test_raw.c — headerless raw files: round trips at awkward sizes against the
 * byte-per-voxel reference, every element type in both byte orders after an
 * offset, geometry from the options, and the clear errors for missing
 * dimensions and files of the wrong size. */
#include "harness.h"
#include "io/io.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static bvox_read_opts raw_opts(int nx, int ny, int nz, bvox_dtype dt)
{
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    o.raw_dims = (bvox_dims){nx, ny, nz};
    o.raw_dtype = dt;
    return o;
}

TEST(roundtrip_awkward_sizes)
{
    static const int sizes[][3] = {{1, 1, 1}, {3, 5, 1}, {7, 3, 63}, {5, 7, 64},
                                   {9, 3, 65}, {3, 11, 130}, {1, 300, 2}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 2, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        const char *p = harness_path("a.raw");
        CHECK_OK(bvox_write(p, v, NULL));
        /* the file is exactly the reference's bytes: 0/1, x fastest */
        size_t n = (size_t)s[0] * (size_t)s[1] * (size_t)s[2];
        uint8_t *buf = malloc(n + 1);
        FILE *f = fopen(p, "rb");
        CHECK(f != NULL);
        CHECK_EQ(fread(buf, 1, n + 1, f), n);
        fclose(f);
        CHECK(memcmp(buf, r->v, n) == 0);
        free(buf);
        bvox_read_opts o = raw_opts(s[0], s[1], s[2], BVOX_DT_U8);
        o.format = NULL; /* by extension */
        bvox_volume *w;
        CHECK_OK(bvox_read(p, &o, &w));
        CHECK_OK(bvox_volume_check(w));
        CHECK(voxref_matches(r, w));
        bvox_volume_destroy(w);
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Store v as dtype in the given byte order (big != 0: most significant first). */
static void store(uint8_t *dst, double v, bvox_dtype dt, int big)
{
    uint64_t bits = 0;
    size_t n = bvox_dtype_size(dt);
    switch (dt) {
    case BVOX_DT_U8: case BVOX_DT_U16: case BVOX_DT_U32: case BVOX_DT_U64:
        bits = (uint64_t)v;
        break;
    case BVOX_DT_I8: case BVOX_DT_I16: case BVOX_DT_I32: case BVOX_DT_I64:
        bits = (uint64_t)(int64_t)v;
        break;
    case BVOX_DT_F32: {
        float f = (float)v;
        uint32_t u;
        memcpy(&u, &f, 4);
        bits = u;
    } break;
    case BVOX_DT_F64: memcpy(&bits, &v, 8); break;
    default: break;
    }
    for (size_t i = 0; i < n; i++) { /* byte i of the little-endian form */
        uint8_t byte = (uint8_t)(bits >> (8 * i));
        dst[big ? n - 1 - i : i] = byte;
    }
}

TEST(every_dtype_both_byte_orders_with_offset)
{
    enum { NX = 7, NY = 3, NZ = 66, N = NX * NY * NZ, OFF = 13 };
    static uint8_t file[OFF + N * 8];
    static double vals[N];
    for (int dt = 0; dt < BVOX_DT_COUNT; dt++)
        for (int big = 0; big < 2; big++) {
            size_t es = bvox_dtype_size((bvox_dtype)dt);
            int is_signed = dt == BVOX_DT_I8 || dt == BVOX_DT_I16 || dt == BVOX_DT_I32 ||
                            dt == BVOX_DT_I64 || dt >= BVOX_DT_F32;
            double factor = es == 1 ? 3 : es == 2 ? 700 : es == 4 ? 90000 : 0x1p35;
            if (dt >= BVOX_DT_F32) factor = 0.25;
            memset(file, 0xee, OFF);
            for (int i = 0; i < N; i++) {
                int p = (int)(harness_rand() % 40) - (is_signed ? 15 : 0);
                vals[i] = p * factor;
                store(file + OFF + (size_t)i * es, vals[i], (bvox_dtype)dt, big);
            }
            bvox_read_opts o = raw_opts(NX, NY, NZ, (bvox_dtype)dt);
            o.raw_big_endian = big;
            o.raw_offset = OFF;
            o.binarize.mode = BVOX_BIN_RANGE;
            o.binarize.lo = 3 * factor;
            o.binarize.hi = 20 * factor;
            bvox_volume *v;
            CHECK_OK(bvox_read_memory(file, OFF + (size_t)N * es, "t.raw", &o, &v));
            for (int i = 0; i < N; i++) {
                int x = i % NX, y = (i / NX) % NY, z = i / (NX * NY);
                int want = vals[i] >= o.binarize.lo && vals[i] <= o.binarize.hi;
                if (bvox_volume_get(v, x, y, z) != want) {
                    fprintf(stderr, "%s big %d voxel %d: %g\n", bvox_dtype_name((bvox_dtype)dt),
                            big, i, vals[i]);
                    return 1;
                }
            }
            bvox_volume_destroy(v);
        }
    return 0;
}

TEST(geometry_from_options)
{
    uint8_t data[8] = {1, 0, 0, 0, 0, 0, 0, 1};
    bvox_read_opts o = raw_opts(2, 2, 2, BVOX_DT_U8);
    o.raw_spacing[0] = 0.5, o.raw_spacing[2] = 4;
    o.raw_unit = "um";
    bvox_volume *v;
    CHECK_OK(bvox_read_memory(data, 8, NULL, &o, &v));
    const bvox_geometry *g = bvox_volume_geometry(v);
    CHECK_NEAR(g->spacing[0], 0.5, 0);
    CHECK_NEAR(g->spacing[1], 1.0, 0); /* 0: not given */
    CHECK_NEAR(g->spacing[2], 4.0, 0);
    CHECK(strcmp(g->unit, "um") == 0);
    CHECK_EQ(bvox_volume_count(v), 2);
    CHECK_EQ(bvox_volume_get(v, 1, 1, 1), 1);
    bvox_volume_destroy(v);
    o.raw_spacing[1] = -1;
    CHECK_STATUS(bvox_read_memory(data, 8, NULL, &o, &v), BVOX_EINVAL);
    o.raw_spacing[1] = NAN;
    CHECK_STATUS(bvox_read_memory(data, 8, NULL, &o, &v), BVOX_EINVAL);
    o.raw_spacing[1] = 1;
    o.raw_unit = "a-unit-name-that-is-too-long";
    CHECK_STATUS(bvox_read_memory(data, 8, NULL, &o, &v), BVOX_EINVAL);
    return 0;
}

TEST(bad_inputs)
{
    uint8_t data[100] = {0};
    bvox_volume *v = (bvox_volume *)1;
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "--dims NX,NY,NZ") != NULL);
    CHECK(v == NULL);
    o = raw_opts(5, 5, 0, BVOX_DT_U8);
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EINVAL);
    o = raw_opts(5, 5, -4, BVOX_DT_U8);
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EINVAL);
    /* one byte short, by size and by offset */
    o = raw_opts(5, 5, 4, BVOX_DT_U8);
    CHECK_STATUS(bvox_read_memory(data, 99, "x.raw", &o, &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "need 100 bytes, the file has 99") != NULL);
    o.raw_offset = 1;
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EFORMAT);
    o.raw_offset = UINT64_MAX;
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EFORMAT);
    o = raw_opts(5, 5, 2, BVOX_DT_U16);
    CHECK_OK(bvox_read_memory(data, 100, "x.raw", &o, &v));
    bvox_volume_destroy(v);
    o = raw_opts(5, 5, 2, BVOX_DT_F64);
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EFORMAT);
    o.raw_dtype = (bvox_dtype)99;
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_EINVAL);
    /* huge dims: refused before any allocation (the hook would make it ENOMEM) */
    bvox_set_memory_budget((size_t)64 << 20);
    o = raw_opts(65535, 65535, 65535, BVOX_DT_U8);
    bvox__alloc_fail_after(1);
    CHECK_STATUS(bvox_read_memory(data, 100, "x.raw", &o, &v), BVOX_ETOOBIG);
    bvox__alloc_fail_after(0);
    bvox_set_memory_budget(0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(write_options)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 3, 3}, &v));
    bvox_write_opts w = BVOX_WRITE_OPTS_INIT;
    w.raw_bits = 1;
    CHECK_STATUS(bvox_write(harness_path("b.raw"), v, &w), BVOX_EUNSUPPORTED);
    struct stat sb;
    CHECK(stat(harness_path("b.raw"), &sb) != 0);
    bvox__sink_fail_after(1);
    CHECK(bvox_write(harness_path("b.raw"), v, NULL) != BVOX_OK);
    bvox__sink_fail_after(0);
    CHECK(stat(harness_path("b.raw"), &sb) != 0);
    bvox_volume_destroy(v);
    return 0;
}
