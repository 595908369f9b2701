/* test_png.c — folders of PNG slices: natural order of names (s1, s2, s10),
 * every colour type and depth libpng can give (made with libpng here and
 * checked pixel by pixel), pHYs voxel size, round trips at awkward sizes,
 * file naming, and bad folders and files. */
#include "harness.h"
#include "internal.h"
#include "io/io.h"
#include "ref/voxref.h"

#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct png_spec {
    uint32_t w, h;
    int color, depth, interlace;
    const png_color *pal;
    int npal;
    const png_byte *trns;
    int ntrns;
    uint32_t ppm;
} png_spec;

/* rows: h rows of png_get_rowbytes bytes each, in PNG's own layout. */
static int write_png(const char *path, const png_spec *s, const uint8_t *rows)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop i = png_create_info_struct(p);
    png_bytep *ptrs = calloc(s->h, sizeof *ptrs);
    if (setjmp(png_jmpbuf(p))) {
        png_destroy_write_struct(&p, &i);
        fclose(f);
        free(ptrs);
        return 0;
    }
    png_init_io(p, f);
    png_set_IHDR(p, i, s->w, s->h, s->depth, s->color, s->interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (s->pal) png_set_PLTE(p, i, s->pal, s->npal);
    if (s->trns) png_set_tRNS(p, i, s->trns, s->ntrns, NULL);
    if (s->ppm) png_set_pHYs(p, i, s->ppm, s->ppm, PNG_RESOLUTION_METER);
    png_write_info(p, i);
    size_t rb = png_get_rowbytes(p, i);
    for (uint32_t y = 0; y < s->h; y++) ptrs[y] = (png_bytep)rows + y * rb;
    png_write_image(p, ptrs);
    png_write_end(p, i);
    png_destroy_write_struct(&p, &i);
    free(ptrs);
    return fclose(f) == 0;
}

static int write_gray8(const char *path, uint32_t w, uint32_t h, const uint8_t *px)
{
    png_spec s = {w, h, PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, NULL, 0, NULL, 0, 0};
    return write_png(path, &s, px);
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fputs(text, f);
    return fclose(f) == 0;
}

static const char *make_dir(const char *name)
{
    const char *d = harness_path(name);
    mkdir(d, 0755);
    return d;
}

static const char *in_dir(const char *dir, const char *file)
{
    static char buf[4][1024];
    static int slot;
    char *p = buf[slot++ & 3];
    snprintf(p, 1024, "%s/%s", dir, file);
    return p;
}

TEST(natural_order_folder)
{
    const char *dir = make_dir("nat");
    static const char *const names[] = {"s10.png", "s2.png", "S20.PNG", "s1.png"};
    static const int marks[] = {10, 2, 20, 1};
    for (int i = 0; i < 4; i++) {
        uint8_t px[12] = {0};
        px[marks[i] % 12] = 255; /* 4 x 3 pixels, one set, at index mark % 12 */
        CHECK(write_gray8(in_dir(dir, names[i]), 4, 3, px));
    }
    /* skipped: macOS resource file, other extension, a folder named *.png */
    CHECK(write_text(in_dir(dir, "._s0.png"), "not a png"));
    CHECK(write_text(in_dir(dir, "notes.txt"), "hello"));
    mkdir(in_dir(dir, "sub.png"), 0755);
    bvox_volume *v;
    CHECK_OK(bvox_read(dir, NULL, &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 4);
    CHECK_EQ(d.ny, 3);
    CHECK_EQ(d.nz, 4);
    static const int order[] = {1, 2, 10, 20}; /* s1 s2 s10 S20 */
    for (int z = 0; z < 4; z++)
        for (int idx = 0; idx < 12; idx++)
            CHECK_EQ(bvox_volume_get(v, idx % 4, idx / 4, z), idx == order[z] % 12);
    bvox_volume_destroy(v);
    return 0;
}

static bvox_volume *read_one(const char *path, double threshold)
{
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_THRESHOLD;
    o.binarize.threshold = threshold;
    bvox_volume *v = NULL;
    if (bvox_read(path, &o, &v) != BVOX_OK) fprintf(stderr, "%s: %s\n", path, bvox_errmsg());
    return v;
}

static int row_is(const bvox_volume *v, const int *want, int n)
{
    if (!v || bvox_volume_dims(v).nx != n || bvox_volume_dims(v).nz != 1) return 0;
    for (int x = 0; x < n; x++)
        if (bvox_volume_get(v, x, 0, 0) != want[x]) return 0;
    return 1;
}

TEST(colour_types_and_depths)
{
    bvox_volume *v;
    /* 16-bit gray keeps its precision: 999 < 1000 <= 1000, 65535 */
    static const uint8_t g16[] = {0x03, 0xE7, 0x03, 0xE8, 0xFF, 0xFF};
    png_spec s16 = {3, 1, PNG_COLOR_TYPE_GRAY, 16, 0, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("g16.png"), &s16, g16));
    v = read_one(harness_path("g16.png"), 1000);
    CHECK(row_is(v, (const int[]){0, 1, 1}, 3));
    bvox_volume_destroy(v);
    /* RGB by luminance: red ~54, black, white, green ~182 */
    static const uint8_t rgb[] = {255, 0, 0, 0, 0, 0, 255, 255, 255, 0, 255, 0};
    png_spec srgb = {4, 1, PNG_COLOR_TYPE_RGB, 8, 0, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("rgb.png"), &srgb, rgb));
    v = read_one(harness_path("rgb.png"), 100);
    CHECK(row_is(v, (const int[]){0, 0, 1, 1}, 4));
    bvox_volume_destroy(v);
    /* RGBA: alpha is ignored */
    static const uint8_t rgba[] = {255, 0, 0, 255, 255, 255, 255, 0};
    png_spec srgba = {2, 1, PNG_COLOR_TYPE_RGB_ALPHA, 8, 0, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("rgba.png"), &srgba, rgba));
    v = read_one(harness_path("rgba.png"), 100);
    CHECK(row_is(v, (const int[]){0, 1}, 2));
    bvox_volume_destroy(v);
    /* gray + alpha */
    static const uint8_t ga[] = {10, 255, 200, 0};
    png_spec sga = {2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, 0, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("ga.png"), &sga, ga));
    v = read_one(harness_path("ga.png"), 100);
    CHECK(row_is(v, (const int[]){0, 1}, 2));
    bvox_volume_destroy(v);
    /* 4-bit palette with transparency: entries black, white, dark blue, grey */
    static const png_color pal[] = {{0, 0, 0}, {255, 255, 255}, {0, 0, 90}, {160, 160, 160}};
    static const png_byte trns[] = {0, 128};
    static const uint8_t idx[] = {0x01, 0x23, 0x10}; /* 0 1 2 3 1 0 */
    png_spec spal = {6, 1, PNG_COLOR_TYPE_PALETTE, 4, 0, pal, 4, trns, 2, 0};
    CHECK(write_png(harness_path("pal.png"), &spal, idx));
    v = read_one(harness_path("pal.png"), 100);
    CHECK(row_is(v, (const int[]){0, 1, 0, 1, 1, 0}, 6));
    bvox_volume_destroy(v);
    /* 1-bit gray reads 0/255 */
    static const uint8_t bits[] = {0xA5, 0x80}; /* 1010 0101 1 */
    png_spec s1 = {9, 1, PNG_COLOR_TYPE_GRAY, 1, 0, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("b1.png"), &s1, bits));
    v = read_one(harness_path("b1.png"), 255);
    CHECK(row_is(v, (const int[]){1, 0, 1, 0, 0, 1, 0, 1, 1}, 9));
    bvox_volume_destroy(v);
    return 0;
}

TEST(interlaced)
{
    enum { W = 11, H = 9 };
    uint8_t px[W * H];
    for (int i = 0; i < W * H; i++) px[i] = (uint8_t)((i * 37) % 251);
    png_spec s = {W, H, PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_ADAM7, NULL, 0, NULL, 0, 0};
    CHECK(write_png(harness_path("adam7.png"), &s, px));
    bvox_volume *v = read_one(harness_path("adam7.png"), 128);
    CHECK(v != NULL);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) CHECK_EQ(bvox_volume_get(v, x, y, 0), px[y * W + x] >= 128);
    bvox_volume_destroy(v);
    return 0;
}

TEST(memory_is_one_slice)
{
    uint8_t px[6] = {0, 7, 0, 0, 0, 9};
    const char *path = harness_path("one.png");
    CHECK(write_gray8(path, 3, 2, px));
    bvox__bytes b;
    CHECK_OK(bvox__read_file(path, &b));
    bvox_volume *v;
    CHECK_OK(bvox_read_memory(b.data, b.size, "one.png", NULL, &v)); /* sniffed */
    CHECK_EQ(bvox_volume_dims(v).nz, 1);
    CHECK_EQ(bvox_volume_count(v), 2);
    CHECK_EQ(bvox_volume_get(v, 1, 0, 0), 1);
    CHECK_EQ(bvox_volume_get(v, 2, 1, 0), 1);
    bvox_volume_destroy(v);
    /* every truncation is a clean format error */
    for (size_t k = 0; k < b.size; k++) {
        bvox_read_opts o = BVOX_READ_OPTS_INIT;
        o.format = "png";
        v = (bvox_volume *)1;
        CHECK_STATUS(bvox_read_memory(b.data, k, "one.png", &o, &v), BVOX_EFORMAT);
        CHECK(v == NULL);
    }
    bvox__bytes_release(&b);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(round_trip_awkward_sizes)
{
    static const int sizes[][3] = {{1, 1, 1}, {3, 5, 1}, {7, 3, 63}, {5, 7, 64},
                                   {9, 3, 65}, {3, 11, 130}, {65, 1, 2}};
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.format = "png";
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 3, harness_rand);
        bvox_volume *v = voxref_to_volume(r), *w;
        const char *dir = harness_path("rt_slices");
        CHECK_OK(bvox_write(dir, v, &wo));
        struct stat sb;
        char last[32];
        snprintf(last, sizeof last, "slice_%04d.png", s[2] - 1);
        CHECK(stat(in_dir(dir, "slice_0000.png"), &sb) == 0);
        CHECK(stat(in_dir(dir, last), &sb) == 0);
        snprintf(last, sizeof last, "slice_%04d.png", s[2]);
        CHECK(stat(in_dir(dir, last), &sb) != 0); /* the old folder's extra slices are gone */
        CHECK_OK(bvox_read(dir, NULL, &w));
        CHECK(voxref_matches(r, w));
        CHECK_OK(bvox_volume_check(w));
        bvox_volume_destroy(v);
        bvox_volume_destroy(w);
        voxref_destroy(r);
    }
    return 0;
}

static char last_warning[512];
static int nwarnings;
static void on_warning(const char *msg, void *user)
{
    (void)user;
    snprintf(last_warning, sizeof last_warning, "%s", msg);
    nwarnings++;
}

/* Read dir, counting the warnings it raises. */
static bvox_volume *read_counting(const char *dir, const bvox_read_opts *o, int *warned)
{
    bvox_volume *v = NULL;
    nwarnings = 0;
    last_warning[0] = '\0';
    bvox_set_warning_handler(on_warning, NULL);
    if (bvox_read(dir, o, &v) != BVOX_OK) fprintf(stderr, "%s: %s\n", dir, bvox_errmsg());
    bvox_set_warning_handler(NULL, NULL);
    *warned = nwarnings;
    return v;
}

TEST(phys_voxel_size)
{
    bvox_volume *v, *w;
    int warned;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 3, 2}, &v));
    CHECK_OK(bvox_volume_set(v, 1, 1, 1, 1));
    CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.25, 3.0, "um"));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.format = "png";
    const char *dir = harness_path("phys");
    CHECK_OK(bvox_write(dir, v, &wo));
    /* voxel_size.txt keeps z and the unit exactly, with no warning */
    CHECK((w = read_counting(dir, NULL, &warned)) != NULL);
    CHECK_EQ(warned, 0);
    const bvox_geometry *g = bvox_volume_geometry(w);
    CHECK(strcmp(g->unit, "um") == 0);
    CHECK(g->spacing[0] == 0.5 && g->spacing[1] == 0.25 && g->spacing[2] == 3.0);
    CHECK(bvox_volume_equal(v, w));
    bvox_volume_destroy(w);
    /* without it: pHYs gives x and y in mm, z is assumed = x, and said */
    CHECK(unlink(in_dir(dir, "voxel_size.txt")) == 0);
    CHECK((w = read_counting(dir, NULL, &warned)) != NULL);
    CHECK_EQ(warned, 1);
    CHECK(strstr(last_warning, "no z spacing") && strstr(last_warning, "voxel_size.txt"));
    g = bvox_volume_geometry(w);
    CHECK(strcmp(g->unit, "mm") == 0);
    CHECK_NEAR(g->spacing[0], 0.0005, 1e-12);
    CHECK_NEAR(g->spacing[1], 0.00025, 1e-12);
    CHECK_NEAR(g->spacing[2], 0.0005, 1e-12);
    bvox_volume_destroy(w);
    /* the caller's voxel size wins over the file's and silences the warning */
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.spacing[0] = 0.1, o.spacing[1] = 0.1, o.spacing[2] = 0.7, o.unit = "mm";
    CHECK((w = read_counting(dir, &o, &warned)) != NULL);
    CHECK_EQ(warned, 0);
    g = bvox_volume_geometry(w);
    CHECK(g->spacing[2] == 0.7 && strcmp(g->unit, "mm") == 0);
    bvox_volume_destroy(w);
    /* a user's own voxel_size.txt: commas, a comment, another unit */
    CHECK(write_text(in_dir(dir, "voxel_size.txt"), "# from the microscope\n\n0.2, 0.2, 1.5 nm\n"));
    CHECK((w = read_counting(dir, NULL, &warned)) != NULL);
    CHECK_EQ(warned, 0);
    g = bvox_volume_geometry(w);
    CHECK(g->spacing[0] == 0.2 && g->spacing[2] == 1.5 && strcmp(g->unit, "nm") == 0);
    bvox_volume_destroy(w);
    /* a wrong one is an error naming it, never a silent default */
    static const char *const bad[] = {"0.2 0.2\n", "0.2 0 1\n", "a b c\n", "# only\n",
                                      "1 1 nan mm\n", "1 1 1 a-unit-far-too-long\n"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        CHECK(write_text(in_dir(dir, "voxel_size.txt"), bad[k]));
        CHECK_STATUS(bvox_read(dir, NULL, &w), BVOX_EFORMAT);
        CHECK(strstr(bvox_errmsg(), "voxel_size.txt") != NULL);
    }
    CHECK(unlink(in_dir(dir, "voxel_size.txt")) == 0);
    /* no metric unit: no pHYs; the sidecar keeps the size, without it 1 x 1 x 1 is said */
    CHECK_OK(bvox_volume_set_spacing(v, 2, 2, 2, ""));
    CHECK_OK(bvox_write(dir, v, &wo));
    CHECK((w = read_counting(dir, NULL, &warned)) != NULL);
    CHECK_EQ(warned, 0);
    CHECK(bvox_volume_geometry(w)->spacing[2] == 2.0);
    bvox_volume_destroy(w);
    CHECK(unlink(in_dir(dir, "voxel_size.txt")) == 0);
    CHECK((w = read_counting(dir, NULL, &warned)) != NULL);
    CHECK_EQ(warned, 1);
    CHECK(strstr(last_warning, "1 x 1 x 1") != NULL);
    CHECK(strcmp(bvox_volume_geometry(w)->unit, "") == 0);
    CHECK_NEAR(bvox_volume_geometry(w)->spacing[0], 1.0, 0);
    bvox_volume_destroy(w);
    bvox_volume_destroy(v);
    return 0;
}

TEST(more_digits_past_10000_slices)
{
    bvox_volume *v, *w;
    CHECK_OK(bvox_volume_create((bvox_dims){1, 1, 10001}, &v));
    CHECK_OK(bvox_volume_set(v, 0, 0, 10000, 1));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.format = "png";
    const char *dir = harness_path("many");
    CHECK_OK(bvox_write(dir, v, &wo));
    struct stat sb;
    CHECK(stat(in_dir(dir, "slice_00000.png"), &sb) == 0);
    CHECK(stat(in_dir(dir, "slice_10000.png"), &sb) == 0);
    CHECK_OK(bvox_read(dir, NULL, &w));
    CHECK(bvox_volume_equal(v, w));
    bvox_volume_destroy(v);
    bvox_volume_destroy(w);
    return 0;
}

TEST(bad_folders_and_files)
{
    bvox_volume *v = (bvox_volume *)1;
    const char *empty = make_dir("empty");
    CHECK(write_text(in_dir(empty, "readme.txt"), "no slices here"));
    CHECK_STATUS(bvox_read(empty, NULL, &v), BVOX_EFORMAT);
    CHECK(v == NULL);
    CHECK(strstr(bvox_errmsg(), "no .png") != NULL);

    const char *fake = make_dir("fake");
    uint8_t px[4] = {1, 2, 3, 4};
    CHECK(write_gray8(in_dir(fake, "a1.png"), 2, 2, px));
    CHECK(write_text(in_dir(fake, "a2.png"), "GIF89a, not a png at all"));
    CHECK_STATUS(bvox_read(fake, NULL, &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "a2.png") != NULL);

    const char *mixed = make_dir("mixed");
    CHECK(write_gray8(in_dir(mixed, "z1.png"), 2, 2, px));
    CHECK(write_gray8(in_dir(mixed, "z2.png"), 1, 4, px));
    CHECK_STATUS(bvox_read(mixed, NULL, &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "z2.png is 1 x 4") != NULL);
    CHECK(strstr(bvox_errmsg(), "z1.png is 2 x 2") != NULL);

    CHECK_STATUS(bvox_read(harness_path("missing.png"), NULL, &v), BVOX_ENOTFOUND);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(failures_leave_no_folder)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 3, 3}, &v));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.format = "png";
    const char *dir = harness_path("nofolder");
    bvox__alloc_fail_after(1);
    CHECK_STATUS(bvox_write(dir, v, &wo), BVOX_ENOMEM);
    bvox__alloc_fail_after(0);
    struct stat sb;
    CHECK(stat(dir, &sb) != 0);
    /* a target that is a file cannot become a folder; the file is kept */
    const char *file = harness_path("plain");
    CHECK(write_text(file, "keep me"));
    CHECK(bvox_write(file, v, &wo) != BVOX_OK);
    CHECK(stat(file, &sb) == 0 && S_ISREG(sb.st_mode));
    bvox_volume_destroy(v);
    return 0;
}
