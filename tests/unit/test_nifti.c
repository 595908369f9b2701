/* test_nifti.c — NIfTI-1 reading and writing: round trips at awkward sizes
 * against the byte-per-voxel reference, every datatype in both byte orders
 * from headers this file builds by hand (independently of src/io/nifti.c),
 * orientation (sform, qform with qfac, pixdim only), bad and hostile inputs,
 * and the real AAL atlas against the independent slow reader. */
#include "harness.h"
#include "io/io.h"
#include "ref/nifti_ref.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

/* ------------------------------------------------ hand-made NIfTI files */

typedef struct spec {
    int16_t dim[8];
    int16_t datatype, bitpix;
    float pixdim[8];
    float vox_offset, slope, inter;
    uint8_t units;
    int16_t qform_code, sform_code;
    float quat[6]; /* quatern_b, c, d, qoffset_x, y, z */
    float srow[12];
    char magic[4];
    int swap; /* write the other byte order than this CPU's */
} spec;

static spec spec_make(int nx, int ny, int nz, int16_t datatype, int16_t bitpix)
{
    spec s;
    memset(&s, 0, sizeof s);
    int16_t dim[8] = {3, (int16_t)nx, (int16_t)ny, (int16_t)nz, 1, 1, 1, 1};
    memcpy(s.dim, dim, sizeof dim);
    s.datatype = datatype;
    s.bitpix = bitpix;
    for (int i = 0; i < 8; i++) s.pixdim[i] = 1.0f;
    s.vox_offset = 352;
    memcpy(s.magic, "n+1", 4);
    return s;
}

/* Copy n bytes, reversed when swap is set. */
static void put(uint8_t *dst, const void *src, int n, int swap)
{
    const uint8_t *p = src;
    for (int i = 0; i < n; i++) dst[i] = swap ? p[n - 1 - i] : p[i];
}

/* Header + data_bytes of data (already in the file's byte order); malloc'ed. */
static uint8_t *build(const spec *s, const void *data, size_t data_bytes, size_t *size)
{
    size_t off = s->vox_offset >= 348 && s->vox_offset < 1e6 ? (size_t)s->vox_offset : 352;
    *size = off + data_bytes;
    uint8_t *b = calloc(1, *size);
    int32_t hs = 348;
    put(b + 0, &hs, 4, s->swap);
    for (int i = 0; i < 8; i++) put(b + 40 + 2 * i, &s->dim[i], 2, s->swap);
    put(b + 70, &s->datatype, 2, s->swap);
    put(b + 72, &s->bitpix, 2, s->swap);
    for (int i = 0; i < 8; i++) put(b + 76 + 4 * i, &s->pixdim[i], 4, s->swap);
    put(b + 108, &s->vox_offset, 4, s->swap);
    put(b + 112, &s->slope, 4, s->swap);
    put(b + 116, &s->inter, 4, s->swap);
    b[123] = s->units;
    put(b + 252, &s->qform_code, 2, s->swap);
    put(b + 254, &s->sform_code, 2, s->swap);
    for (int i = 0; i < 6; i++) put(b + 256 + 4 * i, &s->quat[i], 4, s->swap);
    for (int i = 0; i < 12; i++) put(b + 280 + 4 * i, &s->srow[i], 4, s->swap);
    memcpy(b + 344, s->magic, 4);
    if (data_bytes) memcpy(b + off, data, data_bytes);
    return b;
}

/* gzip (not zlib) format, as .nii.gz files are; malloc'ed. */
static uint8_t *gzip_buf(const uint8_t *src, size_t n, size_t *out_n)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    size_t cap = deflateBound(&z, (uLong)n) + 64;
    uint8_t *out = malloc(cap);
    z.next_in = (Bytef *)src;
    z.avail_in = (uInt)n;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    deflate(&z, Z_FINISH);
    *out_n = cap - z.avail_out;
    deflateEnd(&z);
    return out;
}

/* Forced format, so a short buffer reaches the NIfTI reader's own checks. */
static bvox_status read_mem(const uint8_t *b, size_t n, bvox_volume **v)
{
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "nifti";
    return bvox_read_memory(b, n, "t.nii", &o, v);
}

static int geom_near(const bvox_geometry *a, const bvox_geometry *b, double tol)
{
    for (int i = 0; i < 3; i++) {
        CHECK_NEAR(a->spacing[i], b->spacing[i], tol * fabs(b->spacing[i]));
        CHECK_NEAR(a->origin[i], b->origin[i], tol * (1 + fabs(b->origin[i])));
    }
    for (int i = 0; i < 9; i++) CHECK_NEAR(a->direction[i], b->direction[i], tol);
    CHECK(strcmp(a->unit, b->unit) == 0);
    return 0;
}

/* ------------------------------------------------------------ round trips */

TEST(roundtrip_awkward_sizes)
{
    static const int sizes[][3] = {{1, 1, 1}, {3, 5, 1},  {7, 3, 63},  {5, 7, 64},
                                   {9, 3, 65}, {3, 11, 130}, {1, 13, 129},
                                   {2, 82, 2}, {1, 300, 3}}; /* narrow and tall: many rows */
    const char *names[] = {"a.nii", "a.nii.gz"};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        const int *s = sizes[i];
        voxref *r = voxref_create(s[0], s[1], s[2]);
        voxref_random(r, 1, 3, harness_rand);
        bvox_volume *v = voxref_to_volume(r);
        CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.25, 2.0, "mm"));
        for (int k = 0; k < 2; k++) {
            const char *p = harness_path(names[k]);
            CHECK_OK(bvox_write(p, v, NULL));
            bvox_volume *w;
            CHECK_OK(bvox_read(p, NULL, &w));
            CHECK_OK(bvox_volume_check(w));
            CHECK(voxref_matches(r, w));
            CHECK(geom_near(bvox_volume_geometry(w), bvox_volume_geometry(v), 1e-6) == 0);
            /* the writer's layout, seen by the independent reader */
            nifti_ref ref;
            CHECK(nifti_ref_read(p, &ref) == 0);
            CHECK_EQ(ref.nvox, (int64_t)s[0] * s[1] * s[2]);
            CHECK_EQ(ref.dim[1], s[0]);
            CHECK_EQ(ref.dim[3], s[2]);
            for (int z = 0; z < s[2]; z++)
                for (int y = 0; y < s[1]; y++)
                    for (int x = 0; x < s[0]; x++)
                        CHECK(ref.values[((size_t)z * s[1] + y) * s[0] + x] ==
                              *voxref_at(r, x, y, z));
            nifti_ref_free(&ref);
            bvox_volume_destroy(w);
        }
        bvox_volume_destroy(v);
        voxref_destroy(r);
    }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(roundtrip_rotated_and_flipped)
{
    const double c = cos(0.5), s = sin(0.5);
    /* a rotation about z, then the same with the y axis flipped (det -1) */
    const double dirs[2][9] = {{c, -s, 0, s, c, 0, 0, 0, 1}, {c, s, 0, s, -c, 0, 0, 0, 1}};
    for (int k = 0; k < 2; k++) {
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){6, 5, 4}, &v));
        CHECK_OK(bvox_volume_set(v, 1, 2, 3, 1));
        bvox_geometry g = bvox_geometry_default();
        g.spacing[0] = 0.8, g.spacing[1] = 1.5, g.spacing[2] = 3.0;
        g.origin[0] = -90.5, g.origin[1] = 12.25, g.origin[2] = 7;
        memcpy(g.direction, dirs[k], sizeof g.direction);
        strcpy(g.unit, "um");
        CHECK_OK(bvox_volume_set_geometry(v, &g));
        const char *p = harness_path("rot.nii");
        CHECK_OK(bvox_write(p, v, NULL));
        bvox_volume *w;
        CHECK_OK(bvox_read(p, NULL, &w));
        CHECK(geom_near(bvox_volume_geometry(w), &g, 1e-6) == 0);
        CHECK(bvox_volume_equal(v, w));
        bvox_volume_destroy(w);

        /* the qform alone must say the same: clear sform_code and read again */
        FILE *f = fopen(p, "rb");
        uint8_t buf[352 + 120];
        CHECK(f && fread(buf, 1, sizeof buf, f) == sizeof buf);
        fclose(f);
        int16_t zero = 0;
        memcpy(buf + 254, &zero, 2);
        float qfac;
        memcpy(&qfac, buf + 76, 4);
        CHECK_EQ(qfac, k == 0 ? 1 : -1);
        CHECK_OK(read_mem(buf, sizeof buf, &w));
        CHECK(geom_near(bvox_volume_geometry(w), &g, 1e-5) == 0);
        bvox_volume_destroy(w);
        bvox_volume_destroy(v);
    }
    return 0;
}

TEST(write_units_and_limits)
{
    bvox_volume *v, *w;
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
    /* cm has no NIfTI code: written as mm, 10 times larger */
    CHECK_OK(bvox_volume_set_spacing(v, 0.1, 0.2, 0.3, "cm"));
    CHECK_OK(bvox_write(harness_path("cm.nii"), v, NULL));
    CHECK_OK(bvox_read(harness_path("cm.nii"), NULL, &w));
    CHECK(strcmp(bvox_volume_geometry(w)->unit, "mm") == 0);
    CHECK_NEAR(bvox_volume_geometry(w)->spacing[2], 3.0, 1e-6);
    bvox_volume_destroy(w);
    bvox_volume_destroy(v);
    /* sizes are 32-bit floats in the header: 1e300 would come back as 1 */
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &v));
    CHECK_OK(bvox_volume_set_spacing(v, 1, 1e300, 1, "mm"));
    CHECK_STATUS(bvox_write(harness_path("huge_voxel.nii"), v, NULL), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), "a voxel size of 1e+300 along y does not fit") != NULL);
    struct stat sb0;
    CHECK(stat(harness_path("huge_voxel.nii"), &sb0) != 0);
    CHECK_OK(bvox_volume_set_spacing(v, 1, 1e-300, 1, "mm"));
    CHECK_STATUS(bvox_write(harness_path("huge_voxel.nii"), v, NULL), BVOX_EUNSUPPORTED);
    bvox_volume_destroy(v);
    /* NIfTI-1 dims are int16 */
    CHECK_OK(bvox_volume_create((bvox_dims){40000, 1, 1}, &v));
    CHECK_STATUS(bvox_write(harness_path("big.nii"), v, NULL), BVOX_EUNSUPPORTED);
    struct stat sb;
    CHECK(stat(harness_path("big.nii"), &sb) != 0);
    bvox_volume_destroy(v);
    return 0;
}

TEST(write_failure_leaves_no_file)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){30, 30, 200}, &v));
    bvox_volume_fill(v, 1);
    /* .nii: the header, then 4 chunks of 64 slices, each write may fail;
     * .nii.gz compresses this to a single write */
    for (long n = 1; n <= 6; n++) {
        const char *name = n <= 5 ? "fail.nii" : "fail.nii.gz";
        bvox__sink_fail_after(n <= 5 ? n : 1);
        bvox_status st = bvox_write(harness_path(name), v, NULL);
        bvox__sink_fail_after(0);
        CHECK_STATUS(st, BVOX_EIO);
        struct stat sb;
        CHECK(stat(harness_path(name), &sb) != 0);
    }
    CHECK(bvox_write("/nonexistent-dir/x.nii", v, NULL) != BVOX_OK);
    bvox_volume_destroy(v);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* ------------------------------------------------- every datatype by hand */

static const struct {
    int16_t code, bits;
    int is_signed, is_float;
    double factor; /* values are pattern * factor: large enough to need every byte */
} dts[] = {
    {2, 8, 0, 0, 5},         {256, 8, 1, 0, 5},         {512, 16, 0, 0, 1000},
    {4, 16, 1, 0, 1000},     {768, 32, 0, 0, 100000},   {8, 32, 1, 0, 100000},
    {1280, 64, 0, 0, 0x1p33}, {1024, 64, 1, 0, 0x1p33}, {16, 32, 1, 1, 0.5},
    {64, 64, 1, 1, 0.5},
};

static void store(uint8_t *dst, double v, int16_t code, int swap)
{
    uint8_t b[8];
    int n = 0;
    switch (code) {
    case 2: { uint8_t x = (uint8_t)v; memcpy(b, &x, n = 1); } break;
    case 256: { int8_t x = (int8_t)v; memcpy(b, &x, n = 1); } break;
    case 512: { uint16_t x = (uint16_t)v; memcpy(b, &x, n = 2); } break;
    case 4: { int16_t x = (int16_t)v; memcpy(b, &x, n = 2); } break;
    case 768: { uint32_t x = (uint32_t)v; memcpy(b, &x, n = 4); } break;
    case 8: { int32_t x = (int32_t)v; memcpy(b, &x, n = 4); } break;
    case 1280: { uint64_t x = (uint64_t)v; memcpy(b, &x, n = 8); } break;
    case 1024: { int64_t x = (int64_t)v; memcpy(b, &x, n = 8); } break;
    case 16: { float x = (float)v; memcpy(b, &x, n = 4); } break;
    case 64: memcpy(b, &v, n = 8); break;
    }
    put(dst, b, n, swap);
}

TEST(every_datatype_both_byte_orders)
{
    enum { NX = 5, NY = 3, NZ = 7, N = NX * NY * NZ };
    double vals[N];
    uint8_t data[N * 8];
    for (size_t t = 0; t < sizeof dts / sizeof dts[0]; t++)
        for (int swap = 0; swap < 2; swap++)
            for (int scaled = 0; scaled < 2; scaled++) {
                spec s = spec_make(NX, NY, NZ, dts[t].code, dts[t].bits);
                s.swap = swap;
                s.slope = scaled ? 2.0f : 0.0f; /* 0: no scaling, inter ignored */
                s.inter = scaled ? -3.0f : 7.0f;
                for (int i = 0; i < N; i++) {
                    int p = (i * 37) % 23 - (dts[t].is_signed ? 8 : 0);
                    vals[i] = p * dts[t].factor;
                    store(data + (size_t)i * (size_t)(dts[t].bits / 8), vals[i], dts[t].code,
                          swap);
                }
                size_t n;
                uint8_t *file = build(&s, data, (size_t)N * (size_t)(dts[t].bits / 8), &n);
                double thr = 2.5 * dts[t].factor;
                bvox_read_opts o = BVOX_READ_OPTS_INIT;
                o.binarize.mode = BVOX_BIN_THRESHOLD;
                o.binarize.threshold = thr;
                bvox_volume *v, *nz;
                CHECK_OK(bvox_read_memory(file, n, "dt.nii", &o, &v));
                CHECK_OK(bvox_read_memory(file, n, "dt.nii", NULL, &nz));
                for (int i = 0; i < N; i++) {
                    double real = scaled ? vals[i] * 2.0 - 3.0 : vals[i];
                    int x = i % NX, y = (i / NX) % NY, z = i / (NX * NY);
                    if (bvox_volume_get(v, x, y, z) != (real >= thr) ||
                        bvox_volume_get(nz, x, y, z) != (real != 0)) {
                        fprintf(stderr, "datatype %d swap %d scaled %d voxel %d: value %g\n",
                                dts[t].code, swap, scaled, i, real);
                        return 1;
                    }
                }
                bvox_volume_destroy(v);
                bvox_volume_destroy(nz);
                free(file);
            }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* ------------------------------------------------------------ orientation */

TEST(orientation_qform_sform_pixdim)
{
    uint8_t one = 1;
    bvox_volume *v;
    size_t n;
    /* qform: 90 degrees about z (a = d = sqrt(1/2)), qfac -1 flips z */
    spec s = spec_make(1, 1, 1, 2, 8);
    s.qform_code = 1;
    s.quat[2] = (float)sqrt(0.5);
    s.quat[3] = 10, s.quat[4] = 20, s.quat[5] = 30;
    s.pixdim[0] = -1, s.pixdim[1] = 2, s.pixdim[2] = -3, s.pixdim[3] = 4;
    s.units = 2 | 8; /* mm, seconds */
    uint8_t *f = build(&s, &one, 1, &n);
    CHECK_OK(read_mem(f, n, &v));
    bvox_geometry want = {{2, 3, 4}, {10, 20, 30}, {0, -1, 0, 1, 0, 0, 0, 0, -1}, "mm"};
    CHECK(geom_near(bvox_volume_geometry(v), &want, 1e-6) == 0);
    bvox_volume_destroy(v);
    free(f);

    /* sform wins over qform; spacing from its column lengths */
    s.sform_code = 2;
    float srow[12] = {0, 0, 5, -1, -2, 0, 0, -2, 0, 0.5f, 0, -3};
    memcpy(s.srow, srow, sizeof srow);
    s.units = 3;
    f = build(&s, &one, 1, &n);
    CHECK_OK(read_mem(f, n, &v));
    bvox_geometry want2 = {{2, 0.5, 5}, {-1, -2, -3}, {0, 0, 1, -1, 0, 0, 0, 1, 0}, "um"};
    CHECK(geom_near(bvox_volume_geometry(v), &want2, 1e-6) == 0);
    bvox_volume_destroy(v);
    free(f);

    /* neither: pixdim only; abs, and 0 / NaN become 1; unknown unit is "" */
    s = spec_make(1, 1, 1, 2, 8);
    s.pixdim[1] = -0.5f, s.pixdim[2] = 0, s.pixdim[3] = NAN;
    s.units = 6;
    f = build(&s, &one, 1, &n);
    CHECK_OK(read_mem(f, n, &v));
    bvox_geometry want3 = bvox_geometry_default();
    want3.spacing[0] = 0.5;
    CHECK(geom_near(bvox_volume_geometry(v), &want3, 1e-9) == 0);
    CHECK_EQ(bvox_volume_count(v), 1);
    bvox_volume_destroy(v);
    free(f);
    return 0;
}

TEST(fewer_and_more_dims)
{
    uint8_t data[4 * 3 * 2];
    for (int i = 0; i < 24; i++) data[i] = (uint8_t)(i % 5 == 0);
    bvox_volume *v;
    size_t n;
    /* dim[0] = 2: a single slice; dim[3] is ignored even if 0 */
    spec s = spec_make(4, 3, 0, 2, 8);
    s.dim[0] = 2;
    uint8_t *f = build(&s, data, 12, &n);
    CHECK_OK(read_mem(f, n, &v));
    CHECK_EQ(bvox_volume_dims(v).nz, 1);
    CHECK_EQ(bvox_volume_count(v), 3); /* i = 0, 5, 10 */
    bvox_volume_destroy(v);
    free(f);
    /* dim[0] = 4 with 2 time points: only the first volume (4x3x1) is read */
    s = spec_make(4, 3, 1, 2, 8);
    s.dim[0] = 4, s.dim[4] = 2;
    f = build(&s, data, 24, &n);
    CHECK_OK(read_mem(f, n, &v));
    CHECK_EQ(bvox_volume_count(v), 3);
    CHECK_EQ(bvox_volume_get(v, 1, 1, 0), 1); /* i = 5 */
    bvox_volume_destroy(v);
    free(f);
    return 0;
}

/* ------------------------------------------------------------- bad inputs */

/* Expect `want`, a message mentioning `word`, and nothing left allocated. */
static int expect_fail(const uint8_t *b, size_t n, bvox_status want, const char *word)
{
    bvox_volume *v = (bvox_volume *)1;
    CHECK_STATUS(read_mem(b, n, &v), want);
    CHECK(v == NULL);
    if (word && !strstr(bvox_errmsg(), word)) {
        fprintf(stderr, "message '%s' lacks '%s'\n", bvox_errmsg(), word);
        return 1;
    }
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* One broken field per case, on an otherwise valid 4x4x4 uint8 file. */
static const struct {
    const char *what;
    bvox_status want;
    const char *word;
} bad[] = {
    {"magic", BVOX_EFORMAT, "magic"},         {"pair", BVOX_EUNSUPPORTED, ".hdr"},
    {"dim0", BVOX_EFORMAT, "dim[0]"},         {"dim8", BVOX_EFORMAT, "dim[0]"},
    {"dim2", BVOX_EFORMAT, "dim[2]"},         {"dimneg", BVOX_EFORMAT, "dim[1]"},
    {"complex", BVOX_EUNSUPPORTED, "complex"}, {"rgb", BVOX_EUNSUPPORTED, "RGB"},
    {"code3", BVOX_EFORMAT, "datatype"},      {"bitpix", BVOX_EFORMAT, "bitpix"},
    {"off0", BVOX_EFORMAT, "vox_offset"},     {"offnan", BVOX_EFORMAT, "vox_offset"},
    {"offfrac", BVOX_EFORMAT, "vox_offset"},  {"offfar", BVOX_EFORMAT, "vox_offset"},
    {"nifti2", BVOX_EFORMAT, "NIfTI-2"},      {"size", BVOX_EFORMAT, "sizeof_hdr"},
};

static void breakit(uint8_t *f, const char *what)
{
    int16_t i16;
    float f32;
    int32_t i32;
#define SET(off, v, var) (var = (v), memcpy(f + (off), &var, sizeof var))
    if (!strcmp(what, "magic")) memcpy(f + 344, "n+2", 4);
    if (!strcmp(what, "pair")) memcpy(f + 344, "ni1", 4);
    if (!strcmp(what, "dim0")) SET(40, 0, i16);
    if (!strcmp(what, "dim8")) SET(40, 8, i16);
    if (!strcmp(what, "dim2")) SET(44, 0, i16);
    if (!strcmp(what, "dimneg")) SET(42, -4, i16);
    if (!strcmp(what, "complex")) SET(70, 32, i16), SET(72, 64, i16);
    if (!strcmp(what, "rgb")) SET(70, 128, i16), SET(72, 24, i16);
    if (!strcmp(what, "code3")) SET(70, 3, i16);
    if (!strcmp(what, "bitpix")) SET(72, 16, i16);
    if (!strcmp(what, "off0")) SET(108, 0.0f, f32);
    if (!strcmp(what, "offnan")) SET(108, NAN, f32);
    if (!strcmp(what, "offfrac")) SET(108, 352.5f, f32);
    if (!strcmp(what, "offfar")) SET(108, 1e9f, f32);
    if (!strcmp(what, "nifti2")) SET(0, 540, i32);
    if (!strcmp(what, "size")) SET(0, 347, i32);
#undef SET
}

TEST(bad_headers)
{
    uint8_t data[64] = {0};
    size_t n;
    spec s = spec_make(4, 4, 4, 2, 8);
    uint8_t *f = build(&s, data, 64, &n);
    CHECK(expect_fail(f, 0, BVOX_EFORMAT, NULL) == 0);
    CHECK(expect_fail(f, 100, BVOX_EFORMAT, "truncated") == 0);
    CHECK(expect_fail(f, 351, BVOX_EFORMAT, "vox_offset") == 0);
    CHECK(expect_fail(f, n - 1, BVOX_EFORMAT, "truncated: header claims 64 bytes") == 0);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        uint8_t *g = malloc(n);
        memcpy(g, f, n);
        breakit(g, bad[i].what);
        bvox_read_opts o = BVOX_READ_OPTS_INIT;
        o.format = "nifti";
        bvox_volume *v = (bvox_volume *)1;
        bvox_status st = bvox_read_memory(g, n, "bad.nii", &o, &v);
        if (st != bad[i].want || v != NULL || !strstr(bvox_errmsg(), bad[i].word)) {
            fprintf(stderr, "case %s: %s '%s'\n", bad[i].what, bvox_status_name(st),
                    bvox_errmsg());
            return 1;
        }
        free(g);
    }
    free(f);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(huge_dims_fail_fast_without_allocating)
{
    bvox_set_memory_budget((size_t)256 << 20);
    uint8_t data[16] = {0};
    size_t n;
    /* 2^40 voxels, then every one of the 7 axes at the int16 maximum (the
     * product of all of them overflows 64 bits) */
    spec a = spec_make(16384, 8192, 8192, 2, 8);
    spec b = spec_make(32767, 32767, 32767, 64, 64);
    b.dim[0] = 7;
    for (int i = 4; i < 8; i++) b.dim[i] = 32767;
    /* fits the budget as bits, but the 8-byte samples are not in the file */
    spec c = spec_make(1000, 1000, 1000, 64, 64);
    const spec *cases[] = {&a, &b, &c};
    const bvox_status want[] = {BVOX_ETOOBIG, BVOX_ETOOBIG, BVOX_EFORMAT};
    for (int i = 0; i < 3; i++) {
        uint8_t *f = build(cases[i], data, sizeof data, &n);
        size_t gn;
        uint8_t *gz = gzip_buf(f, n, &gn);
        /* any allocation attempt would turn the status into ENOMEM */
        bvox__alloc_fail_after(1);
        CHECK(expect_fail(f, n, want[i], NULL) == 0);
        bvox__alloc_fail_after(1);
        /* c: the 8 GB of samples cannot be in the small gzip stream */
        CHECK(expect_fail(gz, gn, want[i], NULL) == 0);
        bvox__alloc_fail_after(0);
        free(f);
        free(gz);
    }
    bvox_set_memory_budget(0);
    return 0;
}

TEST(bad_gzip)
{
    uint8_t data[4 * 4 * 4];
    for (int i = 0; i < 64; i++) data[i] = (uint8_t)(i & 1);
    size_t n, gn;
    spec s = spec_make(4, 4, 4, 2, 8);
    uint8_t *f = build(&s, data, sizeof data, &n);
    uint8_t *gz = gzip_buf(f, n, &gn);
    bvox_volume *v;
    CHECK_OK(bvox_read_memory(gz, gn, NULL, NULL, &v)); /* found by content */
    CHECK_EQ(bvox_volume_count(v), 32);
    bvox_volume_destroy(v);
    CHECK_OK(bvox_read_memory(f, n, NULL, NULL, &v));
    CHECK_EQ(bvox_volume_count(v), 32);
    bvox_volume_destroy(v);
    /* two gzip members, the first ending inside the header */
    size_t g1, g2;
    uint8_t *m1 = gzip_buf(f, 100, &g1), *m2 = gzip_buf(f + 100, n - 100, &g2);
    uint8_t *cat = malloc(g1 + g2);
    memcpy(cat, m1, g1);
    memcpy(cat + g1, m2, g2);
    CHECK_OK(read_mem(cat, g1 + g2, &v));
    CHECK_EQ(bvox_volume_count(v), 32);
    bvox_volume_destroy(v);
    free(m1), free(m2), free(cat);
    CHECK(expect_fail(gz, gn / 2, BVOX_EFORMAT, NULL) == 0);
    CHECK(expect_fail(gz, gn - 6, BVOX_EFORMAT, NULL) == 0);
    for (size_t i = 12; i < gn - 8; i += 7) { /* corrupt one byte of the deflate stream */
        uint8_t *g = malloc(gn);
        memcpy(g, gz, gn);
        g[i] ^= 0x55;
        bvox_read_opts o = BVOX_READ_OPTS_INIT;
        o.format = "nifti";
        bvox_status st = bvox_read_memory(g, gn, "c.nii.gz", &o, &v);
        if (st == BVOX_OK) bvox_volume_destroy(v); /* a flip may still inflate to valid data */
        else CHECK(st == BVOX_EFORMAT || st == BVOX_ETOOBIG || st == BVOX_EUNSUPPORTED);
        free(g);
    }
    free(gz);
    /* a bomb: the header promises 64 bytes, the stream holds 8 MB more */
    size_t big = n + ((size_t)8 << 20);
    uint8_t *b = calloc(1, big);
    memcpy(b, f, n);
    gz = gzip_buf(b, big, &gn);
    CHECK(expect_fail(gz, gn, BVOX_ETOOBIG, NULL) == 0);
    free(gz);
    free(b);
    free(f);
    return 0;
}

TEST(gzip_allocation_failures_are_clean)
{
    uint8_t data[20 * 20 * 70];
    for (size_t i = 0; i < sizeof data; i++) data[i] = (uint8_t)(i % 3 == 0);
    size_t n, gn;
    spec s = spec_make(20, 20, 70, 2, 8);
    uint8_t *f = build(&s, data, sizeof data, &n);
    uint8_t *gz = gzip_buf(f, n, &gn);
    int ok = 0;
    for (long k = 1; k <= 10 && !ok; k++) {
        bvox_volume *v = (bvox_volume *)1;
        bvox__alloc_fail_after(k);
        bvox_status st = read_mem(gz, gn, &v);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            CHECK_EQ(bvox_volume_count(v), (int64_t)(sizeof data + 2) / 3);
            bvox_volume_destroy(v);
            ok = 1;
        } else {
            CHECK_EQ(st, BVOX_ENOMEM);
            CHECK(v == NULL);
        }
        CHECK_EQ(bvox_memory_in_use(), 0);
    }
    CHECK(ok);
    free(f);
    free(gz);
    return 0;
}

/* ------------------------------------------------------------- real data */

TEST(realdata_aal_count)
{
    const char *path = "/usr/share/mricron/templates/aal.nii.gz";
    nifti_ref ref;
    CHECK(nifti_ref_read(path, &ref) == 0);
    int64_t want = nifti_ref_count_nonzero(&ref);
    CHECK(want > 0 && want < ref.nvox);
    bvox_volume *v;
    CHECK_OK(bvox_read(path, NULL, &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, ref.dim[1]);
    CHECK_EQ(d.ny, ref.dim[2]);
    CHECK_EQ(d.nz, ref.dim[3]);
    CHECK_EQ(bvox_volume_count(v), want);
    const bvox_geometry *g = bvox_volume_geometry(v);
    for (int i = 0; i < 3; i++) CHECK_NEAR(g->spacing[i], fabs(ref.pixdim[i + 1]), 1e-5);
    if (ref.sform_code > 0)
        for (int i = 0; i < 3; i++) CHECK_NEAR(g->origin[i], ref.srow[i][3], 1e-4);
    /* a label, voxel by voxel against the reference */
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_LABEL;
    o.binarize.label = 2;
    bvox_volume *lab;
    CHECK_OK(bvox_read(path, &o, &lab));
    int64_t nlab = 0;
    for (int64_t i = 0; i < ref.nvox; i++) {
        int x = (int)(i % d.nx), y = (int)((i / d.nx) % d.ny);
        int z = (int)(i / ((int64_t)d.nx * d.ny));
        int is = ref.values[i] == 2.0;
        nlab += is;
        if (bvox_volume_get(lab, x, y, z) != is) {
            fprintf(stderr, "label voxel %d,%d,%d differs\n", x, y, z);
            return 1;
        }
        if (bvox_volume_get(v, x, y, z) != (ref.values[i] != 0)) {
            fprintf(stderr, "nonzero voxel %d,%d,%d differs\n", x, y, z);
            return 1;
        }
    }
    CHECK(nlab > 0);
    bvox_volume_destroy(lab);
    bvox_volume_destroy(v);
    nifti_ref_free(&ref);
    return 0;
}

/* A .nii.gz is inflated and binarised a few slices at a time: reading it
 * needs the volume's bits plus a bounded buffer, not the inflated file (which
 * the whole-file reader held beside the compressed one). 256^3 u8: 2 MiB of
 * bits, 16 MiB of samples; the budget is 4 MiB. */
TEST(gz_read_streams_within_budget_of_the_bits)
{
    bvox_volume *v, *w = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){256, 256, 256}, &v));
    bvox_shape sp = {.kind = BVOX_SHAPE_SPHERE, .center = {128, 120, 131}, .radius = 97};
    CHECK_OK(bvox_shape_draw(v, &sp, BVOX_CSG_UNION));
    const char *gzp = harness_path("stream.nii.gz"), *plain = harness_path("stream.nii");
    CHECK_OK(bvox_write(gzp, v, NULL));
    CHECK_OK(bvox_write(plain, v, NULL));
    /* what is in use already (v) plus 4 MiB */
    size_t base = bvox_memory_in_use();
    bvox_set_memory_budget(base + ((size_t)4 << 20));
    const char *paths[] = {gzp, plain};
    for (int i = 0; i < 2; i++) {
        bvox_status st = bvox_read(paths[i], NULL, &w);
        if (st) fprintf(stderr, "%s: %s\n", paths[i], bvox_errmsg());
        CHECK_OK(st);
        CHECK(bvox_volume_equal(v, w));
        bvox_volume_destroy(w);
        w = NULL;
    }
    /* the same from a gzip buffer in memory (the caller's, not budgeted) */
    bvox__bytes file;
    bvox_set_memory_budget(0);
    CHECK_OK(bvox__read_file(gzp, &file));
    uint8_t *copy = malloc(file.size);
    memcpy(copy, file.data, file.size);
    size_t size = file.size;
    bvox__bytes_release(&file);
    bvox_set_memory_budget(base + ((size_t)4 << 20));
    CHECK_OK(bvox_read_memory(copy, size, "stream.nii.gz", NULL, &w));
    CHECK(bvox_volume_equal(v, w));
    bvox_volume_destroy(w);
    /* Otsu needs every sample first: it still inflates the whole file, and
     * says how much that needs in MiB, not in bytes */
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.binarize.mode = BVOX_BIN_OTSU;
    w = (bvox_volume *)1;
    CHECK_STATUS(bvox_read(gzp, &o, &w), BVOX_ETOOBIG);
    CHECK(w == NULL);
    CHECK(strstr(bvox_errmsg(), "16.0 MiB") != NULL);
    bvox_set_memory_budget(0);
    CHECK_EQ(bvox_memory_in_use(), base);
    free(copy);
    bvox_volume_destroy(v);
    return 0;
}

/* Extensions between the header and vox_offset are skipped while streaming;
 * a 4-D file's later volumes are not read (nor counted as a gzip bomb). */
TEST(gz_stream_skips_extensions_and_later_volumes)
{
    uint8_t data[5 * 4 * 3 * 2];
    for (size_t i = 0; i < sizeof data; i++) data[i] = (uint8_t)(i % 7 == 0);
    spec s = spec_make(5, 4, 3, 2, 8);
    s.vox_offset = 352 + 160;
    s.dim[0] = 4;
    s.dim[4] = 2;
    size_t n;
    uint8_t *f = build(&s, data, sizeof data, &n);
    size_t gn;
    uint8_t *gz = gzip_buf(f, n, &gn);
    const char *p = harness_path("ext.nii.gz");
    FILE *fp = fopen(p, "wb");
    CHECK(fp && fwrite(gz, 1, gn, fp) == gn && fclose(fp) == 0);
    bvox_volume *v = NULL;
    CHECK_OK(bvox_read(p, NULL, &v));
    CHECK_EQ(bvox_volume_count(v), (int64_t)((5 * 4 * 3 + 6) / 7));
    CHECK_EQ(bvox_volume_get(v, 2, 1, 0), 1); /* i = 7 */
    bvox_volume_destroy(v);
    /* cut short inside the first volume's voxel data */
    fp = fopen(p, "wb");
    uint8_t *cut = gzip_buf(f, n - 70, &gn);
    CHECK(fp && fwrite(cut, 1, gn, fp) == gn && fclose(fp) == 0);
    CHECK_STATUS(bvox_read(p, NULL, &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "truncated") != NULL);
    free(cut);
    free(gz);
    free(f);
    return 0;
}
