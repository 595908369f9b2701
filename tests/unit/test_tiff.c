/* test_tiff.c — TIFF stacks: files made with libtiff directly (16-bit with an
 * ImageJ description and resolution, tiles, 1-bit, signed and float samples,
 * pages of different sizes, colour) read through bvox_read with binarisation
 * options; our writer's round trips at awkward sizes voxel by voxel, its
 * metadata, and the ImageJ layout (contiguous pages) checked with libtiff. */
#include "harness.h"
#include "internal.h"
#include "io/io.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <tiffio.h>

static const int sizes[][3] = {{1, 1, 1},   {3, 5, 1},  {7, 3, 63}, {5, 7, 64},
                               {9, 3, 65},  {3, 11, 130}, {65, 1, 2}, {1, 1, 70}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

typedef struct page_spec {
    uint32_t w, h;
    uint16_t bps, sfmt, spp, comp;
    uint32_t rps;        /* 0: tiled 16x16 */
    const char *desc;    /* first page only */
    float xres, yres;    /* 0: none */
    uint16_t resunit;
} page_spec;

/* sample(x, y, z) as a double, written in the page's type. */
typedef double (*sample_fn)(int x, int y, int z);

static void put_sample(uint8_t *p, const page_spec *s, double v)
{
    switch (s->bps) {
    case 8: *p = (uint8_t)v; break;
    case 16:
        if (s->sfmt == SAMPLEFORMAT_INT) *(int16_t *)p = (int16_t)v;
        else *(uint16_t *)p = (uint16_t)v;
        break;
    case 32:
        if (s->sfmt == SAMPLEFORMAT_IEEEFP) *(float *)p = (float)v;
        else *(int32_t *)p = (int32_t)v;
        break;
    }
}

/* A multi-page TIFF made with libtiff, one page spec per z (NULL: same). */
static int write_tiff(const char *path, const page_spec *specs, int nz, int vary, sample_fn f)
{
    TIFF *t = TIFFOpen(path, "w");
    if (!t) return 0;
    for (int z = 0; z < nz; z++) {
        const page_spec *s = vary ? &specs[z] : &specs[0];
        TIFFSetField(t, TIFFTAG_IMAGEWIDTH, s->w);
        TIFFSetField(t, TIFFTAG_IMAGELENGTH, s->h);
        TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, s->bps);
        TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, s->spp);
        TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, s->sfmt);
        TIFFSetField(t, TIFFTAG_PHOTOMETRIC,
                     s->spp == 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
        TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        TIFFSetField(t, TIFFTAG_COMPRESSION, s->comp);
        if (z == 0 && s->desc) TIFFSetField(t, TIFFTAG_IMAGEDESCRIPTION, s->desc);
        if (s->xres > 0) TIFFSetField(t, TIFFTAG_XRESOLUTION, s->xres);
        if (s->yres > 0) TIFFSetField(t, TIFFTAG_YRESOLUTION, s->yres);
        if (s->resunit) TIFFSetField(t, TIFFTAG_RESOLUTIONUNIT, s->resunit);
        size_t elem = s->bps >= 8 ? s->bps / 8 * s->spp : 1;
        size_t line = s->bps == 1 ? (s->w + 7) / 8 : s->w * elem;
        uint8_t *img = calloc((size_t)s->h * line + 16, 1);
        for (uint32_t y = 0; y < s->h; y++)
            for (uint32_t x = 0; x < s->w; x++) {
                double v = f((int)x, (int)y, z);
                if (s->bps == 1) {
                    if (v != 0) img[y * line + x / 8] |= (uint8_t)(0x80 >> (x % 8));
                } else {
                    for (int c = 0; c < s->spp; c++)
                        put_sample(img + y * line + x * elem + c * (elem / s->spp), s, v);
                }
            }
        int ok = 1;
        if (s->rps == 0) {
            TIFFSetField(t, TIFFTAG_TILEWIDTH, 16);
            TIFFSetField(t, TIFFTAG_TILELENGTH, 16);
            size_t tsz = (size_t)TIFFTileSize(t);
            uint8_t *tile = malloc(tsz);
            for (uint32_t ty = 0; ty < s->h; ty += 16)
                for (uint32_t tx = 0; tx < s->w; tx += 16) {
                    memset(tile, 0, tsz);
                    for (uint32_t r = 0; r < 16 && ty + r < s->h; r++)
                        for (uint32_t c = 0; c < 16 && tx + c < s->w; c++)
                            memcpy(tile + (r * 16 + c) * elem,
                                   img + (ty + r) * line + (tx + c) * elem, elem);
                    ok &= TIFFWriteTile(t, tile, tx, ty, 0, 0) >= 0;
                }
            free(tile);
        } else {
            TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, s->rps);
            for (uint32_t y = 0; y < s->h; y++)
                ok &= TIFFWriteScanline(t, img + y * line, y, 0) >= 0;
        }
        free(img);
        if (!ok || !TIFFWriteDirectory(t)) {
            TIFFClose(t);
            return 0;
        }
    }
    TIFFClose(t);
    return 1;
}

static double ramp16(int x, int y, int z) { return x * 100 + y * 10 + z * 1000; }

static const char ij_desc[] =
    "ImageJ=1.53t\nimages=3\nslices=3\nunit=micron\nspacing=2.5\nloop=false\n";

TEST(imagej_16bit_threshold)
{
    page_spec s = {5, 4, 16, SAMPLEFORMAT_UINT, 1, COMPRESSION_ADOBE_DEFLATE, 2, ij_desc,
                   2.0f, 4.0f, RESUNIT_NONE};
    const char *path = harness_path("ij16.tif");
    CHECK(write_tiff(path, &s, 3, 0, ramp16));
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_THRESHOLD;
    o.binarize.threshold = 1230;
    bvox_volume *v;
    CHECK_OK(bvox_read(path, &o, &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 5);
    CHECK_EQ(d.ny, 4);
    CHECK_EQ(d.nz, 3);
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 5; x++)
                CHECK_EQ(bvox_volume_get(v, x, y, z), ramp16(x, y, z) >= 1230);
    const bvox_geometry *g = bvox_volume_geometry(v);
    CHECK_NEAR(g->spacing[0], 0.5, 1e-9);
    CHECK_NEAR(g->spacing[1], 0.25, 1e-9);
    CHECK_NEAR(g->spacing[2], 2.5, 1e-12);
    CHECK(strcmp(g->unit, "um") == 0);
    bvox_volume_destroy(v);

    /* range, label and nonzero on the same file */
    o.binarize.mode = BVOX_BIN_RANGE;
    o.binarize.lo = 1100;
    o.binarize.hi = 1210;
    CHECK_OK(bvox_read(path, &o, &v));
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 5; x++) {
                double val = ramp16(x, y, z);
                CHECK_EQ(bvox_volume_get(v, x, y, z), val >= 1100 && val <= 1210);
            }
    bvox_volume_destroy(v);
    CHECK_OK(bvox_read(path, NULL, &v));
    CHECK_EQ(bvox_volume_count(v), 5 * 4 * 3 - 1); /* only (0,0,0) is zero */
    bvox_volume_destroy(v);
    return 0;
}

static double bimodal(int x, int y, int z)
{
    return ((x * 7 + y * 3 + z) % 5 == 0) ? 60000 : 100 + x;
}

TEST(otsu_splits_bimodal_stack)
{
    page_spec s = {17, 9, 16, SAMPLEFORMAT_UINT, 1, COMPRESSION_NONE, 3, NULL, 0, 0, 0};
    const char *path = harness_path("bimodal.tiff");
    CHECK(write_tiff(path, &s, 4, 0, bimodal));
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_OTSU;
    bvox_volume *v;
    CHECK_OK(bvox_read(path, &o, &v));
    for (int z = 0; z < 4; z++)
        for (int y = 0; y < 9; y++)
            for (int x = 0; x < 17; x++)
                CHECK_EQ(bvox_volume_get(v, x, y, z), bimodal(x, y, z) > 1000);
    /* No description, no resolution: unit unknown, spacing 1. */
    CHECK(strcmp(bvox_volume_geometry(v)->unit, "") == 0);
    CHECK_NEAR(bvox_volume_geometry(v)->spacing[2], 1.0, 0);
    bvox_volume_destroy(v);
    return 0;
}

static double diag(int x, int y, int z) { return (x + y + z) % 3 == 0 ? 200 : 0; }

TEST(tiled_pages)
{
    page_spec s = {40, 37, 8, SAMPLEFORMAT_UINT, 1, COMPRESSION_LZW, 0, NULL, 0, 0, 0};
    const char *path = harness_path("tiled.tif");
    CHECK(write_tiff(path, &s, 2, 0, diag));
    bvox_volume *v;
    CHECK_OK(bvox_read(path, NULL, &v));
    CHECK_EQ(bvox_volume_dims(v).nx, 40);
    CHECK_EQ(bvox_volume_dims(v).ny, 37);
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 37; y++)
            for (int x = 0; x < 40; x++) CHECK_EQ(bvox_volume_get(v, x, y, z), diag(x, y, z) != 0);
    bvox_volume_destroy(v);
    return 0;
}

static double checker(int x, int y, int z) { return ((x / 2 + y + z) & 1) ? 1 : 0; }

TEST(one_bit_pages)
{
    /* 13 pixels: rows are padded to whole bytes; inch resolution gives mm */
    page_spec s = {13, 5, 1, SAMPLEFORMAT_UINT, 1, COMPRESSION_PACKBITS, 2, NULL, 254.0f, 254.0f,
                   RESUNIT_INCH};
    const char *path = harness_path("bits.tif");
    CHECK(write_tiff(path, &s, 3, 0, checker));
    bvox_volume *v;
    CHECK_OK(bvox_read(path, NULL, &v));
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 5; y++)
            for (int x = 0; x < 13; x++)
                CHECK_EQ(bvox_volume_get(v, x, y, z), checker(x, y, z) != 0);
    const bvox_geometry *g = bvox_volume_geometry(v);
    CHECK(strcmp(g->unit, "mm") == 0);
    CHECK_NEAR(g->spacing[0], 0.1, 1e-7);
    CHECK_NEAR(g->spacing[2], 0.1, 1e-7); /* no z information: same as x */
    bvox_volume_destroy(v);
    return 0;
}

static double signed_ramp(int x, int y, int z) { return x - 4 + z * 0.25; }

TEST(signed_and_float_samples)
{
    page_spec s16 = {9, 2, 16, SAMPLEFORMAT_INT, 1, COMPRESSION_NONE, 1, NULL, 0, 0, 0};
    page_spec f32 = {9, 2, 32, SAMPLEFORMAT_IEEEFP, 1, COMPRESSION_ADOBE_DEFLATE, 2, NULL, 0, 0, 0};
    const char *p16 = harness_path("s16.tif"), *pf = harness_path("f32.tif");
    CHECK(write_tiff(p16, &s16, 2, 0, signed_ramp));
    CHECK(write_tiff(pf, &f32, 3, 0, signed_ramp));
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_THRESHOLD;
    o.binarize.threshold = -2;
    bvox_volume *v;
    CHECK_OK(bvox_read(p16, &o, &v)); /* stored truncated to int16 */
    for (int z = 0; z < 2; z++)
        for (int x = 0; x < 9; x++)
            CHECK_EQ(bvox_volume_get(v, x, 1, z), (int16_t)signed_ramp(x, 1, z) >= -2);
    bvox_volume_destroy(v);
    o.binarize.threshold = -1.5;
    CHECK_OK(bvox_read(pf, &o, &v));
    for (int z = 0; z < 3; z++)
        for (int x = 0; x < 9; x++)
            CHECK_EQ(bvox_volume_get(v, x, 0, z), signed_ramp(x, 0, z) >= -1.5);
    bvox_volume_destroy(v);
    return 0;
}

static double one(int x, int y, int z) { return 1; }

TEST(bad_inputs)
{
    bvox_volume *v = (bvox_volume *)1;
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "tiff";
    /* wrong magic */
    CHECK_STATUS(bvox_read_memory("IX*\0\10\0\0\0", 8, "x.tif", &o, &v), BVOX_EFORMAT);
    CHECK(v == NULL);
    /* pages of different sizes */
    page_spec two[2] = {{8, 8, 8, SAMPLEFORMAT_UINT, 1, COMPRESSION_NONE, 8, NULL, 0, 0, 0},
                        {8, 9, 8, SAMPLEFORMAT_UINT, 1, COMPRESSION_NONE, 8, NULL, 0, 0, 0}};
    const char *path = harness_path("mixed.tif");
    CHECK(write_tiff(path, two, 2, 1, one));
    CHECK_STATUS(bvox_read(path, NULL, &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "page 2") != NULL);
    CHECK(strstr(bvox_errmsg(), "8 x 9") != NULL);
    /* colour */
    page_spec rgb = {4, 4, 8, SAMPLEFORMAT_UINT, 3, COMPRESSION_NONE, 4, NULL, 0, 0, 0};
    path = harness_path("rgb.tif");
    CHECK(write_tiff(path, &rgb, 1, 0, one));
    CHECK_STATUS(bvox_read(path, NULL, &v), BVOX_EUNSUPPORTED);
    /* an ImageJ hyperstack with channels */
    page_spec ch = {4, 4, 8, SAMPLEFORMAT_UINT, 1, COMPRESSION_NONE, 4,
                    "ImageJ=1.53t\nimages=2\nchannels=2\n", 0, 0, 0};
    path = harness_path("channels.tif");
    CHECK(write_tiff(path, &ch, 2, 0, one));
    CHECK_STATUS(bvox_read(path, NULL, &v), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), "channels") != NULL);
    return 0;
}

/* Little-endian classic TIFF of one page: w x h samples of bps bits in one
 * uncompressed strip at data_off, an optional description; returns the
 * header size (the caller puts the pixels at data_off). */
static size_t raw_tiff(uint8_t *b, uint32_t w, uint32_t h, uint32_t bps, const char *desc,
                       uint32_t data_off)
{
    uint16_t tags[][2] = {{256, 4}, {257, 4}, {258, 3}, {259, 3}, {262, 3}, {270, 2},
                          {273, 4}, {277, 3}, {278, 4}, {279, 4}};
    uint32_t desc_off = 8 + 2 + 12 * 10 + 4, desc_len = desc ? (uint32_t)strlen(desc) + 1 : 0;
    uint32_t vals[] = {w, h, bps, 1, 1, desc_off, data_off, 1, h, w * h * (bps / 8)};
    int n = 0;
    memset(b, 0, desc_off);
    memcpy(b, "II*\0\10\0\0\0", 8);
    for (int i = 0; i < 10; i++) {
        if (tags[i][0] == 270 && !desc) continue;
        uint8_t *e = b + 10 + 12 * n++;
        e[0] = (uint8_t)tags[i][0];
        e[1] = (uint8_t)(tags[i][0] >> 8);
        e[2] = (uint8_t)tags[i][1];
        e[4] = (uint8_t)(tags[i][0] == 270 ? desc_len : 1);
        for (int k = 0; k < 4; k++) e[8 + k] = (uint8_t)(vals[i] >> (8 * k));
    }
    b[8] = (uint8_t)n;
    if (desc) memcpy(b + desc_off, desc, desc_len);
    return desc_off + desc_len;
}

static size_t claim_tiff(uint8_t *b, uint32_t w, uint32_t h)
{
    return raw_tiff(b, w, h, 8, NULL, 1000);
}

TEST(imagej_contiguous_single_ifd)
{
    /* ImageJ's layout for stacks over 4 GiB: one IFD, "images=3", the three
     * 16-bit images back to back from the strip offset. */
    static uint8_t b[1024];
    const char *desc = "ImageJ=1.54f\nimages=3\nslices=3\nunit=mm\nspacing=4\n";
    uint32_t off = 302; /* even: the samples are used in place */
    size_t hs = raw_tiff(b, 5, 2, 16, desc, off);
    CHECK(hs <= off);
    for (int i = 0; i < 30; i++) {
        b[off + 2 * i] = (uint8_t)(i * 100);
        b[off + 2 * i + 1] = (uint8_t)((i * 100) >> 8);
    }
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "tiff";
    o.binarize.mode = BVOX_BIN_THRESHOLD;
    o.binarize.threshold = 1450;
    for (int shift = 0; shift < 2; shift++) { /* also at an odd address: copied */
        static uint8_t c[1100];
        memcpy(c + shift, b, off + 60);
        bvox_volume *v;
        CHECK_OK(bvox_read_memory(c + shift, off + 60, "big.tif", &o, &v));
        CHECK_EQ(bvox_volume_dims(v).nz, 3);
        for (int i = 0; i < 30; i++)
            CHECK_EQ(bvox_volume_get(v, i % 5, (i / 5) % 2, i / 10), i * 100 >= 1450);
        CHECK_NEAR(bvox_volume_geometry(v)->spacing[2], 4.0, 0);
        CHECK(strcmp(bvox_volume_geometry(v)->unit, "mm") == 0);
        bvox_volume_destroy(v);
    }
    /* the images must be in the file */
    bvox_volume *v;
    CHECK_STATUS(bvox_read_memory(b, off + 59, "cut.tif", &o, &v), BVOX_EFORMAT);
    return 0;
}

TEST(absurd_sizes_and_truncation)
{
    uint8_t b[256];
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "tiff";
    bvox_volume *v;
    bvox_set_memory_budget(64 << 20);
    size_t n = claim_tiff(b, 65535, 65535);
    CHECK_STATUS(bvox_read_memory(b, n, "big.tif", &o, &v), BVOX_ETOOBIG);
    bvox_set_memory_budget(0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    /* a small claim whose strip lies beyond the end of the file */
    n = claim_tiff(b, 10, 10);
    CHECK_STATUS(bvox_read_memory(b, n, "short.tif", &o, &v), BVOX_EFORMAT);
    CHECK(v == NULL);

    /* every truncation of a real file fails cleanly */
    page_spec s = {6, 5, 16, SAMPLEFORMAT_UINT, 1, COMPRESSION_ADOBE_DEFLATE, 2, ij_desc, 2, 2,
                   RESUNIT_NONE};
    const char *path = harness_path("cut.tif");
    CHECK(write_tiff(path, &s, 3, 0, ramp16));
    bvox__bytes file;
    CHECK_OK(bvox__read_file(path, &file));
    for (size_t k = 0; k < file.size; k++) {
        v = (bvox_volume *)1;
        bvox_status st = bvox_read_memory(file.data, k, "cut.tif", &o, &v);
        if (st != BVOX_EFORMAT)
            fprintf(stderr, "prefix %zu of %zu: %s\n", k, file.size, bvox_status_name(st));
        CHECK(st == BVOX_EFORMAT);
        CHECK(v == NULL);
    }
    CHECK_OK(bvox_read_memory(file.data, file.size, "cut.tif", &o, &v));
    bvox_volume_destroy(v);
    /* every allocation failure is clean */
    for (long k = 1;; k++) {
        bvox__alloc_fail_after(k);
        bvox_status st = bvox_read_memory(file.data, file.size, "cut.tif", &o, &v);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            bvox_volume_destroy(v);
            break;
        }
        CHECK_STATUS(st, BVOX_ENOMEM);
        CHECK(k < 20);
    }
    bvox__bytes_release(&file);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(round_trip_awkward_sizes)
{
    for (int i = 0; i < NSIZES; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 2, harness_rand);
        bvox_volume *v = voxref_to_volume(r), *w;
        const char *path = harness_path("rt.tif");
        CHECK_OK(bvox_write(path, v, NULL));
        CHECK_OK(bvox_read(path, NULL, &w));
        CHECK(voxref_matches(r, w));
        CHECK_OK(bvox_volume_check(w));
        bvox_volume_destroy(v);
        bvox_volume_destroy(w);
        voxref_destroy(r);
    }
    return 0;
}

TEST(metadata_round_trip)
{
    static const char *const units[][2] = {{"um", "um"}, {"mm", "mm"}, {"", ""}, {"nm", "nm"}};
    for (int u = 0; u < 4; u++) {
        bvox_volume *v, *w;
        CHECK_OK(bvox_volume_create((bvox_dims){7, 5, 4}, &v));
        CHECK_OK(bvox_volume_set(v, 6, 4, 3, 1));
        bvox_geometry g = bvox_geometry_default();
        g.spacing[0] = 0.3;
        g.spacing[1] = 0.4;
        g.spacing[2] = 2.0;
        g.origin[0] = -0.9;
        g.origin[1] = 0.0;
        g.origin[2] = 4.0;
        strcpy(g.unit, units[u][0]);
        CHECK_OK(bvox_volume_set_geometry(v, &g));
        const char *path = harness_path("meta.tif");
        CHECK_OK(bvox_write(path, v, NULL));
        CHECK_OK(bvox_read(path, NULL, &w));
        const bvox_geometry *h = bvox_volume_geometry(w);
        CHECK(strcmp(h->unit, units[u][1]) == 0);
        for (int a = 0; a < 3; a++) {
            CHECK_NEAR(h->spacing[a], g.spacing[a], 1e-6 * g.spacing[a]);
            CHECK_NEAR(h->origin[a], g.origin[a], 1e-6);
        }
        CHECK(bvox_volume_equal(v, w));
        bvox_volume_destroy(v);
        bvox_volume_destroy(w);
    }
    return 0;
}

TEST(written_file_is_imagej_stack)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){9, 6, 70}, &v));
    CHECK_OK(bvox_volume_set(v, 8, 5, 69, 1));
    CHECK_OK(bvox_volume_set(v, 0, 0, 0, 1));
    CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.5, 1.5, "um"));
    const char *path = harness_path("ij.tif");
    CHECK_OK(bvox_write(path, v, NULL));
    TIFF *t = TIFFOpen(path, "r");
    CHECK(t != NULL);
    CHECK_EQ(TIFFNumberOfDirectories(t), 70);
    char *desc = NULL;
    CHECK(TIFFGetField(t, TIFFTAG_IMAGEDESCRIPTION, &desc));
    CHECK(strcmp(desc, "ImageJ=1.11a\nimages=70\nslices=70\nunit=micron\nspacing=1.5\n"
                       "loop=false\n") == 0);
    float xr = 0;
    uint16_t ru = 0, bps = 0;
    CHECK(TIFFGetField(t, TIFFTAG_XRESOLUTION, &xr));
    CHECK_NEAR(xr, 2.0, 1e-6);
    CHECK(TIFFGetField(t, TIFFTAG_RESOLUTIONUNIT, &ru));
    CHECK_EQ(ru, RESUNIT_NONE);
    CHECK(TIFFGetField(t, TIFFTAG_BITSPERSAMPLE, &bps));
    CHECK_EQ(bps, 8);
    /* ImageJ reads "images=70" as 70 pages stored back to back after page 1. */
    uint64_t *offs = NULL, first = 0;
    for (int z = 0; z < 70; z++) {
        CHECK(TIFFSetDirectory(t, (tdir_t)z));
        CHECK(TIFFGetField(t, TIFFTAG_STRIPOFFSETS, &offs));
        CHECK_EQ(TIFFNumberOfStrips(t), 1);
        if (z == 0) first = offs[0];
        CHECK_EQ(offs[0], first + (uint64_t)z * 54);
        uint8_t page[54];
        CHECK_EQ(TIFFReadEncodedStrip(t, 0, page, 54), 54);
        for (int i = 0; i < 54; i++) {
            int want = (z == 0 && i == 0) || (z == 69 && i == 53);
            CHECK_EQ(page[i], want ? 255 : 0);
        }
    }
    TIFFClose(t);
    bvox_volume_destroy(v);
    return 0;
}

TEST(write_failure_leaves_nothing)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 5, 5}, &v));
    const char *path = harness_path("fail.tif");
    for (long k = 1; k <= 3; k++) {
        bvox__sink_fail_after(k);
        bvox_status st = bvox_write(path, v, NULL);
        bvox__sink_fail_after(0);
        CHECK(st != BVOX_OK);
        struct stat sb;
        CHECK(stat(path, &sb) != 0);
    }
    CHECK_OK(bvox_write(path, v, NULL));
    bvox_volume_destroy(v);
    return 0;
}
