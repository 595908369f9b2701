/* test_binvox.c — binvox reading and writing: a hand-made file proving the
 * axis order (index = x*D1*D2 + z*D2 + y), byte-exact rewriting, round trips
 * at awkward sizes checked voxel by voxel and against an independent slow
 * decoder of the file, translate/scale, and every kind of bad input. */
#include "harness.h"
#include "internal.h"
#include "io/io.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const int sizes[][3] = {{1, 1, 1},  {3, 5, 1},    {7, 3, 63}, {5, 7, 64},  {9, 3, 65},
                               {3, 11, 130}, {65, 2, 3}, {2, 70, 5}, {1, 130, 2}, {64, 64, 1}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

static uint8_t *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *p = malloc((size_t)n + 1);
    if (p && fread(p, 1, (size_t)n, f) != (size_t)n) {
        free(p);
        p = NULL;
    }
    fclose(f);
    *size = (size_t)n;
    return p;
}

static bvox_status read_mem(const void *data, size_t size, bvox_volume **v)
{
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "binvox";
    return bvox_read_memory(data, size, "t.binvox", &o, v);
}

/* dim 2 3 4: D0 = 2 is x, D1 = 3 is z, D2 = 4 is y; index = x*12 + z*4 + y.
 * Set: index 1 (x0 z0 y1), index 4 (x0 z1 y0), index 23 (x1 z2 y3). */
static const char small_header[] = "#binvox 1\ndim 2 3 4\ntranslate 1 2 3\nscale 4\ndata\n";
static const uint8_t small_runs[] = {0, 1, 1, 1, 0, 2, 1, 1, 0, 18, 1, 1};

static size_t small_file(uint8_t *buf)
{
    size_t h = strlen(small_header);
    memcpy(buf, small_header, h);
    memcpy(buf + h, small_runs, sizeof small_runs);
    return h + sizeof small_runs;
}

TEST(hand_made_axis_order)
{
    uint8_t buf[128];
    size_t n = small_file(buf);
    bvox_volume *v;
    CHECK_OK(read_mem(buf, n, &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 2);
    CHECK_EQ(d.ny, 4);
    CHECK_EQ(d.nz, 3);
    CHECK_EQ(bvox_volume_count(v), 3);
    CHECK_EQ(bvox_volume_get(v, 0, 1, 0), 1);
    CHECK_EQ(bvox_volume_get(v, 0, 0, 1), 1);
    CHECK_EQ(bvox_volume_get(v, 1, 3, 2), 1);
    /* world position = translate + scale * (index + 0.5) / max(dim) */
    const bvox_geometry *g = bvox_volume_geometry(v);
    for (int a = 0; a < 3; a++) CHECK_NEAR(g->spacing[a], 1.0, 1e-12);
    CHECK_NEAR(g->origin[0], 1.5, 1e-12);
    CHECK_NEAR(g->origin[1], 2.5, 1e-12);
    CHECK_NEAR(g->origin[2], 3.5, 1e-12);
    CHECK_OK(bvox_volume_check(v));
    /* Writing it back gives the very same bytes. */
    const char *path = harness_path("small.binvox");
    CHECK_OK(bvox_write(path, v, NULL));
    size_t m;
    uint8_t *back = slurp(path, &m);
    CHECK(back != NULL);
    CHECK_EQ(m, n);
    CHECK(memcmp(back, buf, n) == 0);
    free(back);
    bvox_volume_destroy(v);
    return 0;
}

/* Independent slow decoder: the file's voxel at (x, y, z), binvox order. */
static int file_matches(const uint8_t *f, size_t size, const voxref *r)
{
    const uint8_t *p = (const uint8_t *)strstr((const char *)f, "data\n");
    if (!p) return 0;
    p += 5;
    size_t total = (size_t)r->nx * r->ny * r->nz, idx = 0;
    uint8_t *bytes = calloc(total, 1);
    while (p + 1 < f + size) {
        if (p[1] == 0 || p[0] > 1 || idx + p[1] > total) {
            free(bytes);
            return 0;
        }
        memset(bytes + idx, p[0], p[1]);
        idx += p[1];
        p += 2;
    }
    int ok = idx == total;
    for (int x = 0; x < r->nx && ok; x++)
        for (int z = 0; z < r->nz && ok; z++)
            for (int y = 0; y < r->ny && ok; y++)
                ok = bytes[((size_t)x * r->nz + z) * r->ny + y] == voxref_get(r, x, y, z);
    free(bytes);
    return ok;
}

TEST(round_trip_awkward_sizes)
{
    static const unsigned dens[][2] = {{1, 50}, {1, 2}, {49, 50}, {1, 1}, {0, 1}};
    for (int i = 0; i < NSIZES; i++)
        for (int k = 0; k < 5; k++) {
            const int *s = sizes[i];
            voxref *r = voxref_create(s[0], s[1], s[2]);
            voxref_random(r, dens[k][0], dens[k][1], harness_rand);
            bvox_volume *v = voxref_to_volume(r), *w;
            const char *path = harness_path("rt.binvox");
            CHECK_OK(bvox_write(path, v, NULL));
            size_t n;
            uint8_t *f = slurp(path, &n);
            CHECK(f && file_matches(f, n, r));
            free(f);
            CHECK_OK(bvox_read(path, NULL, &w));
            CHECK(voxref_matches(r, w));
            CHECK_OK(bvox_volume_check(w));
            bvox_volume_destroy(v);
            bvox_volume_destroy(w);
            voxref_destroy(r);
        }
    return 0;
}

TEST(translate_scale_round_trip)
{
    bvox_volume *v, *w;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 6, 3}, &v));
    CHECK_OK(bvox_volume_set(v, 3, 5, 2, 1));
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = g.spacing[1] = g.spacing[2] = 0.25;
    g.origin[0] = -1.0;
    g.origin[1] = 2.5;
    g.origin[2] = 10.125;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    const char *path = harness_path("geom.binvox");
    CHECK_OK(bvox_write(path, v, NULL));
    size_t n;
    uint8_t *f = slurp(path, &n);
    CHECK(f != NULL);
    /* dims in binvox order (x, z, y), translate = corner, scale = longest side */
    CHECK(strstr((char *)f, "dim 4 3 6\ntranslate -1.125 2.375 10\nscale 1.5\ndata\n") != NULL);
    free(f);
    CHECK_OK(bvox_read(path, NULL, &w));
    const bvox_geometry *h = bvox_volume_geometry(w);
    for (int a = 0; a < 3; a++) {
        CHECK_NEAR(h->spacing[a], 0.25, 1e-12);
        CHECK_NEAR(h->origin[a], g.origin[a], 1e-12);
    }
    CHECK(bvox_volume_equal(v, w));
    bvox_volume_destroy(v);
    bvox_volume_destroy(w);
    return 0;
}

static bvox_status read_text(const char *header, const uint8_t *runs, size_t nruns)
{
    uint8_t buf[512];
    size_t h = strlen(header);
    memcpy(buf, header, h);
    memcpy(buf + h, runs, nruns);
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = read_mem(buf, h + nruns, &v);
    if (st != BVOX_OK && v != NULL) return BVOX_OK; /* out must be NULL on failure */
    bvox_volume_destroy(v);
    return st;
}

TEST(bad_headers)
{
    static const uint8_t eight[] = {1, 8};
    CHECK_STATUS(read_text("#binvax 1\ndim 2 2 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\n", eight, 0), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "data") != NULL);
    CHECK_STATUS(read_text("#binvox 1\ntranslate 0 0 0\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "dim") != NULL);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 x 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 0 2 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim -2 2 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\ndim 2 2 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\ncolour red\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\nscale 0\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\nscale nan\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 1\ndim 2 2 2\ntranslate 1 2\ndata\n", eight, 2), BVOX_EFORMAT);
    CHECK_STATUS(read_text("#binvox 2\ndim 2 2 2\ndata\n", eight, 2), BVOX_EUNSUPPORTED);
    /* Windows line ends and optional translate/scale are fine. */
    CHECK_OK(read_text("#binvox 1\r\ndim 2 2 2\r\ndata\n", eight, 2));
    return 0;
}

TEST(absurd_dims_refused_before_allocation)
{
    static const uint8_t run[] = {0, 255};
    size_t before = bvox_memory_in_use();
    CHECK_STATUS(read_text("#binvox 1\ndim 100000 100000 100000\ndata\n", run, 2), BVOX_ETOOBIG);
    CHECK(strstr(bvox_errmsg(), "100000") != NULL);
    CHECK_STATUS(read_text("#binvox 1\ndim 99999999999 1 1\ndata\n", run, 2), BVOX_EFORMAT);
    bvox_set_memory_budget(64 << 20);
    CHECK_STATUS(read_text("#binvox 1\ndim 4000 4000 4000\ndata\n", run, 2), BVOX_ETOOBIG);
    bvox_set_memory_budget(0);
    /* Within limits, but the data cannot possibly cover the grid. */
    CHECK_STATUS(read_text("#binvox 1\ndim 1000 1000 1000\ndata\n", run, 2), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "truncated") != NULL);
    CHECK_EQ(bvox_memory_in_use(), before);
    return 0;
}

TEST(bad_runs)
{
    const char *h = "#binvox 1\ndim 2 2 2\ndata\n";
    static const uint8_t short_data[] = {0, 5};
    static const uint8_t odd[] = {0, 5, 1};
    static const uint8_t overflow[] = {0, 5, 1, 4};
    static const uint8_t value2[] = {2, 8};
    static const uint8_t count0[] = {0, 0, 1, 8};
    static const uint8_t extra[] = {0, 8, 0};
    static const uint8_t ok[] = {0, 3, 1, 5};
    CHECK_STATUS(read_text(h, short_data, sizeof short_data), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "truncated") != NULL);
    CHECK_STATUS(read_text(h, odd, sizeof odd), BVOX_EFORMAT);
    CHECK_STATUS(read_text(h, overflow, sizeof overflow), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "overflow") != NULL);
    CHECK_STATUS(read_text(h, value2, sizeof value2), BVOX_EFORMAT);
    CHECK_STATUS(read_text(h, count0, sizeof count0), BVOX_EFORMAT);
    CHECK_STATUS(read_text(h, extra, sizeof extra), BVOX_EFORMAT);
    CHECK_OK(read_text(h, ok, sizeof ok));
    return 0;
}

TEST(every_truncation_fails_cleanly)
{
    uint8_t buf[128];
    size_t n = small_file(buf);
    for (size_t k = 0; k < n; k++) {
        bvox_volume *v = (bvox_volume *)1;
        bvox_status st = read_mem(buf, k, &v);
        CHECK(st == BVOX_EFORMAT);
        CHECK(v == NULL);
    }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(alloc_and_write_failures_are_clean)
{
    uint8_t buf[128];
    size_t n = small_file(buf);
    bvox_volume *v;
    bvox__alloc_fail_after(1);
    CHECK_STATUS(read_mem(buf, n, &v), BVOX_ENOMEM);
    CHECK(v == NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_OK(read_mem(buf, n, &v));
    const char *path = harness_path("fail.binvox");
    bvox__sink_fail_after(1);
    CHECK(bvox_write(path, v, NULL) != BVOX_OK);
    struct stat sb;
    CHECK(stat(path, &sb) != 0); /* no partial file */
    bvox_volume_destroy(v);
    return 0;
}

TEST(sniffed_without_format)
{
    uint8_t buf[128];
    size_t n = small_file(buf);
    bvox_volume *v;
    CHECK_OK(bvox_read_memory(buf, n, NULL, NULL, &v));
    CHECK_EQ(bvox_volume_count(v), 3);
    bvox_volume_destroy(v);
    return 0;
}
