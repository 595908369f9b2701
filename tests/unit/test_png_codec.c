/* test_png_codec.c — src/common/png.c, the one libpng wrapper: encode into
 * memory and decode back (8/16-bit, gray/RGB, pHYs), the conversions
 * (luminance, 8 <-> 16 bits), a header-only decode, and the failures
 * (not a PNG, truncated, a callback's or the writer's own status). */
#include "harness.h"
#include "common/png.h"

#include <stdlib.h>
#include <string.h>

typedef struct membuf {
    uint8_t *data;
    size_t size, cap;
    int fail_after; /* writes accepted before failing; -1: never */
} membuf;

static bvox_status mem_write(void *ctx, const void *data, size_t n)
{
    membuf *m = ctx;
    if (m->fail_after == 0) return BVOX_EIO;
    if (m->fail_after > 0) m->fail_after--;
    if (m->size + n > m->cap) {
        m->cap = (m->size + n) * 2;
        m->data = realloc(m->data, m->cap);
        if (!m->data) return BVOX_ENOMEM;
    }
    memcpy(m->data + m->size, data, n);
    m->size += n;
    return BVOX_OK;
}

typedef struct sink_rows {
    bvox__png_info info;
    uint8_t *buf;   /* NULL: header only */
    bvox_status fail;
} sink_rows;

static bvox_status take_rows(void *ctx, const bvox__png_info *info, uint8_t **rows)
{
    sink_rows *s = ctx;
    s->info = *info;
    if (s->fail) return bvox__fail(s->fail, "refused by the callback");
    *rows = s->buf;
    return BVOX_OK;
}

TEST(round_trip_8_and_16_bit)
{
    /* 3 x 2 RGB 8-bit, then the same as 16-bit gray with big values */
    const uint8_t rgb[18] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 0, 0, 0, 255, 255, 255};
    membuf m = {NULL, 0, 0, -1};
    bvox__png_write_opts wo = {3, 8, {2000, 4000}, 0};
    CHECK_OK(bvox__png_encode(3, 2, rgb, &wo, mem_write, &m, "rgb.png"));
    uint8_t got[18];
    sink_rows s = {{0}, got, BVOX_OK};
    bvox__png_read_opts ro = {1000, 0, 0};
    CHECK_OK(bvox__png_decode(m.data, m.size, "rgb.png", &ro, take_rows, &s));
    CHECK_EQ(s.info.width, 3);
    CHECK_EQ(s.info.height, 2);
    CHECK_EQ(s.info.channels, 3);
    CHECK_EQ(s.info.bytes, 1);
    CHECK_EQ(s.info.depth, 8);
    CHECK_EQ(s.info.ppm[0], 2000);
    CHECK_EQ(s.info.ppm[1], 4000);
    CHECK(memcmp(got, rgb, sizeof rgb) == 0);

    /* gray: luminance of pure red/green/blue and white/black */
    uint8_t gray[6];
    sink_rows g = {{0}, gray, BVOX_OK};
    bvox__png_read_opts go = {1000, 1, 0};
    CHECK_OK(bvox__png_decode(m.data, m.size, "rgb.png", &go, take_rows, &g));
    CHECK_EQ(g.info.channels, 1);
    CHECK(gray[0] > gray[2] && gray[1] > gray[0]); /* green > red > blue */
    CHECK_EQ(gray[4], 0);
    CHECK_EQ(gray[5], 255);
    /* 8 bits expanded to 16: 255 -> 65535, 0 -> 0 (native order) */
    uint16_t wide[6];
    sink_rows w = {{0}, (uint8_t *)wide, BVOX_OK};
    bvox__png_read_opts wo16 = {1000, 1, 2};
    CHECK_OK(bvox__png_decode(m.data, m.size, "rgb.png", &wo16, take_rows, &w));
    CHECK_EQ(w.info.bytes, 2);
    CHECK_EQ(wide[5], 65535);
    CHECK_EQ(wide[4], 0);
    free(m.data);

    const uint16_t g16[4] = {0, 1, 0x1234, 65535};
    membuf m16 = {NULL, 0, 0, -1};
    bvox__png_write_opts o16 = {1, 16, {0, 0}, 0};
    CHECK_OK(bvox__png_encode(2, 2, g16, &o16, mem_write, &m16, "g16.png"));
    uint16_t back[4];
    sink_rows b = {{0}, (uint8_t *)back, BVOX_OK};
    CHECK_OK(bvox__png_decode(m16.data, m16.size, "g16.png", &ro, take_rows, &b));
    CHECK_EQ(b.info.depth, 16);
    CHECK_EQ(b.info.ppm[0], 0);
    CHECK(memcmp(back, g16, sizeof g16) == 0);
    uint8_t narrow[4]; /* 16 scaled to 8: 65535 -> 255, 0x1234 -> 0x12 */
    sink_rows n = {{0}, narrow, BVOX_OK};
    bvox__png_read_opts no = {1000, 1, 1};
    CHECK_OK(bvox__png_decode(m16.data, m16.size, "g16.png", &no, take_rows, &n));
    CHECK_EQ(narrow[3], 255);
    CHECK_EQ(narrow[2], 0x12);
    CHECK_EQ(narrow[0], 0);
    free(m16.data);
    return 0;
}

TEST(header_only_masks_and_failures)
{
    uint8_t mask[64 * 3];
    for (size_t i = 0; i < sizeof mask; i++) mask[i] = (i / 7) % 2 ? 255 : 0;
    membuf m = {NULL, 0, 0, -1};
    bvox__png_write_opts wo = {1, 8, {0, 0}, 1};
    CHECK_OK(bvox__png_encode(64, 3, mask, &wo, mem_write, &m, "mask.png"));
    sink_rows h = {{0}, NULL, BVOX_OK}; /* rows NULL: stop after the header */
    bvox__png_read_opts ro = {1000, 1, 0};
    CHECK_OK(bvox__png_decode(m.data, m.size, "mask.png", &ro, take_rows, &h));
    CHECK_EQ(h.info.width, 64);
    CHECK_EQ(h.info.height, 3);
    uint8_t got[64 * 3];
    sink_rows r = {{0}, got, BVOX_OK};
    CHECK_OK(bvox__png_decode(m.data, m.size, "mask.png", &ro, take_rows, &r));
    CHECK(memcmp(got, mask, sizeof mask) == 0);

    /* over max_dim, truncated, not a PNG: EFORMAT naming the file */
    bvox__png_read_opts small = {32, 1, 0};
    CHECK_STATUS(bvox__png_decode(m.data, m.size, "mask.png", &small, take_rows, &r),
                 BVOX_EFORMAT);
    CHECK_STATUS(bvox__png_decode(m.data, m.size - 20, "cut.png", &ro, take_rows, &r),
                 BVOX_EFORMAT);
    CHECK(strncmp(bvox_errmsg(), "cut.png: ", 9) == 0);
    CHECK_STATUS(bvox__png_decode("GIF89a..", 8, "x.gif", &ro, take_rows, &r), BVOX_EFORMAT);
    CHECK(strcmp(bvox_errmsg(), "x.gif: not a PNG file") == 0);
    /* the callback's own status and message come back unchanged */
    sink_rows f = {{0}, got, BVOX_ENOMEM};
    CHECK_STATUS(bvox__png_decode(m.data, m.size, "mask.png", &ro, take_rows, &f), BVOX_ENOMEM);
    CHECK(strcmp(bvox_errmsg(), "refused by the callback") == 0);
    free(m.data);

    /* a failing writer: EIO naming the file, at every point of the stream */
    for (int k = 0; k < 4; k++) {
        membuf bad = {NULL, 0, 0, k};
        CHECK_STATUS(bvox__png_encode(64, 3, mask, &wo, mem_write, &bad, "full.png"), BVOX_EIO);
        CHECK(strstr(bvox_errmsg(), "full.png: write failed") != NULL);
        free(bad.data);
    }
    return 0;
}
