/* test_binarize.c — bvox__binarize and bvox__unpack_slices: every sample type,
 * both byte orders, every mode, slope/intercept (negative too), NaN, awkward
 * sizes, each compared with a naive per-voxel evaluation in doubles written
 * here; hand-computed Otsu cases; every SIMD path; unpack round trips. */
#include "harness.h"
#include "io/io.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const size_t dt_size[BVOX_DT_COUNT] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

static const char *const dt_name[BVOX_DT_COUNT] = {"u8",  "i8",  "u16", "i16", "u32",
                                                    "i32", "u64", "i64", "f32", "f64"};

static int is_float_dt(bvox_dtype dt) { return dt == BVOX_DT_F32 || dt == BVOX_DT_F64; }
static int is_signed_dt(bvox_dtype dt)
{
    return dt == BVOX_DT_I8 || dt == BVOX_DT_I16 || dt == BVOX_DT_I32 || dt == BVOX_DT_I64;
}

/* ---------------------------------------------------------- naive model */

/* Sample i of a native-order buffer, as a double (the raw value). */
static double raw_at(const unsigned char *buf, bvox_dtype dt, size_t i)
{
    const unsigned char *p = buf + i * dt_size[dt];
    switch (dt) {
    case BVOX_DT_U8: return *p;
    case BVOX_DT_I8: return (int8_t)*p;
#define RD(T)                                                                              \
    {                                                                                      \
        T t;                                                                               \
        memcpy(&t, p, sizeof t);                                                           \
        return (double)t;                                                                  \
    }
    case BVOX_DT_U16: RD(uint16_t)
    case BVOX_DT_I16: RD(int16_t)
    case BVOX_DT_U32: RD(uint32_t)
    case BVOX_DT_I32: RD(int32_t)
    case BVOX_DT_U64: RD(uint64_t)
    case BVOX_DT_I64: RD(int64_t)
    case BVOX_DT_F32: RD(float)
    case BVOX_DT_F64: RD(double)
#undef RD
    default: return NAN;
    }
}

static double real_value(double raw, double slope, double inter)
{
    return raw * (slope == 0 ? 1.0 : slope) + inter;
}

static int naive_pred(double real, const bvox_binarize *how)
{
    if (isnan(real)) return 0;
    switch (how->mode) {
    case BVOX_BIN_NONZERO: return real != 0;
    case BVOX_BIN_THRESHOLD: return real >= how->threshold;
    case BVOX_BIN_RANGE: return how->lo <= real && real <= how->hi;
    case BVOX_BIN_LABEL: return real == how->label;
    default: return -1;
    }
}

/* Store a value (in range for the type) as sample i, native order. */
static void store(unsigned char *buf, bvox_dtype dt, size_t i, int64_t iv, uint64_t uv,
                  double fv)
{
    unsigned char *p = buf + i * dt_size[dt];
    switch (dt) {
#define WR(T, v)                                                                           \
    {                                                                                      \
        T t = (T)(v);                                                                      \
        memcpy(p, &t, sizeof t);                                                           \
        break;                                                                             \
    }
    case BVOX_DT_U8: WR(uint8_t, uv)
    case BVOX_DT_I8: WR(int8_t, iv)
    case BVOX_DT_U16: WR(uint16_t, uv)
    case BVOX_DT_I16: WR(int16_t, iv)
    case BVOX_DT_U32: WR(uint32_t, uv)
    case BVOX_DT_I32: WR(int32_t, iv)
    case BVOX_DT_U64: WR(uint64_t, uv)
    case BVOX_DT_I64: WR(int64_t, iv)
    case BVOX_DT_F32: WR(float, fv)
    case BVOX_DT_F64: WR(double, fv)
#undef WR
    default: break;
    }
}

/* Random samples: mostly small values around the thresholds used below,
 * some type extremes, NaN / infinities / -0 for floats, some random bits. */
static void fill_random(unsigned char *buf, bvox_dtype dt, size_t n)
{
    unsigned bits = 8 * (unsigned)dt_size[dt];
    for (size_t i = 0; i < n; i++) {
        uint64_t r = harness_rand(), kind = r % 16;
        int64_t small = (int64_t)((r >> 8) % 13) - 6;
        if (!is_signed_dt(dt) && !is_float_dt(dt)) small += 6;
        if (is_float_dt(dt)) {
            double v = (double)small / ((r >> 20) & 1 ? 2 : 1);
            if (kind == 10) v = NAN;
            else if (kind == 11) v = (r >> 30) & 1 ? INFINITY : -INFINITY;
            else if (kind == 12) v = -0.0;
            else if (kind == 13) v = dt == BVOX_DT_F32 ? FLT_MAX : DBL_MAX;
            else if (kind == 14) v = -(double)(r >> 40) * 1e-3;
            store(buf, dt, i, 0, 0, v);
            continue;
        }
        uint64_t mask = bits == 64 ? ~0ull : (1ull << bits) - 1;
        uint64_t u = (uint64_t)small;
        if (kind >= 12) u = harness_rand(); /* anything: full-width bits */
        else if (kind == 10) u = is_signed_dt(dt) ? (1ull << (bits - 1)) : 0;   /* min */
        else if (kind == 11) u = is_signed_dt(dt) ? (1ull << (bits - 1)) - 1 : mask; /* max */
        u &= mask;
        /* sign-extend for the signed store */
        int64_t s = bits == 64 ? (int64_t)u
                               : (int64_t)(u << (64 - bits)) >> (64 - bits);
        store(buf, dt, i, s, u, 0);
    }
}

static void byteswap_buf(unsigned char *buf, size_t size, size_t n)
{
    for (size_t i = 0; i < n; i++)
        for (size_t a = 0, b = size - 1; a < b; a++, b--) {
            unsigned char t = buf[i * size + a];
            buf[i * size + a] = buf[i * size + b];
            buf[i * size + b] = t;
        }
}

/* Binarize the native buffer (byteswapped first when swap) and compare every
 * voxel with the naive evaluation. Returns 0 when equal. */
static int check_case(const unsigned char *native, bvox_dtype dt, const int *s, int swap,
                      double slope, double inter, const bvox_binarize *how)
{
    size_t n = (size_t)s[0] * (size_t)s[1] * (size_t)s[2];
    unsigned char *data = malloc(n * dt_size[dt]);
    memcpy(data, native, n * dt_size[dt]);
    if (swap) byteswap_buf(data, dt_size[dt], n);
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){s[0], s[1], s[2]};
    g.dtype = dt;
    g.data = data;
    g.byteswap = swap != 0;
    g.slope = slope;
    g.inter = inter;
    g.geom.spacing[2] = 2.5;
    bvox_volume *v = NULL;
    bvox_status st = bvox__binarize(&g, how, "case.nii", &v);
    int bad = 0;
    if (st != BVOX_OK) {
        fprintf(stderr, "binarize failed: %s\n", bvox_errmsg());
        bad = 1;
    } else if (bvox_volume_check(v) != BVOX_OK || bvox_volume_geometry(v)->spacing[2] != 2.5) {
        fprintf(stderr, "invariants or geometry broken: %s\n", bvox_errmsg());
        bad = 1;
    }
    /* the streaming binariser (a reader's slices, in uneven batches that
     * straddle the 64-slice blocks) must give the very same volume */
    if (!bad && bvox__bin_stream_ok(how)) {
        bvox__bin_stream *bs = NULL;
        bvox_volume *sv = NULL;
        st = bvox__bin_stream_begin(&g, how, "case.nii", &bs);
        size_t slice = (size_t)s[0] * (size_t)s[1] * dt_size[dt];
        static const size_t batch[] = {1, 2, 70, 5, 64};
        for (size_t z = 0, b = 0; !st && z < (size_t)s[2]; b++) {
            size_t k = batch[b % 5] < (size_t)s[2] - z ? batch[b % 5] : (size_t)s[2] - z;
            bvox__bin_stream_slices(bs, data + z * slice, k);
            z += k;
        }
        if (!st) st = bvox__bin_stream_finish(bs, &sv);
        if (st || bvox_volume_check(sv) != BVOX_OK || !bvox_volume_equal(sv, v) ||
            bvox_volume_geometry(sv)->spacing[2] != 2.5) {
            fprintf(stderr, "%s %dx%dx%d mode %d: the streamed volume differs (%s)\n",
                    dt_name[dt], s[0], s[1], s[2], how->mode, st ? bvox_errmsg() : "bits");
            bad = 1;
        }
        bvox_volume_destroy(sv);
    }
    for (size_t i = 0; !bad && i < n; i++) {
        int x = (int)(i % (size_t)s[0]), y = (int)(i / (size_t)s[0] % (size_t)s[1]);
        int z = (int)(i / ((size_t)s[0] * (size_t)s[1]));
        double raw = raw_at(native, dt, i);
        int want = naive_pred(real_value(raw, slope, inter), how);
        if (bvox_volume_get(v, x, y, z) != want) {
            fprintf(stderr,
                    "%s %dx%dx%d swap %d slope %g inter %g mode %d (t %g lo %g hi %g label %g) "
                    "simd %s: voxel (%d,%d,%d) raw %.17g is %d, want %d\n",
                    dt_name[dt], s[0], s[1], s[2], swap, slope, inter, how->mode,
                    how->threshold, how->lo, how->hi, how->label,
                    bvox_simd_name(bvox_simd_active()), x, y, z, raw, !want, want);
            bad = 1;
        }
    }
    bvox_volume_destroy(v);
    free(data);
    return bad;
}

/* ------------------------------------------------ differential, per dtype */

/* Sizes with every awkward nx, ny (1, 3, 63, 65, 130) and nz (1, 63, 64, 65,
 * 130); rows of whole words (nx = 64, 128: a work item's rows are one run);
 * rows wider than one work item (several items per row). */
static const int sizes[][3] = {{1, 1, 1},     {3, 1, 63},   {63, 3, 64},  {65, 5, 65},
                               {130, 3, 130}, {1, 130, 65}, {65, 63, 1},  {130, 65, 64},
                               {64, 70, 3},   {128, 5, 65}, {1100, 2, 3}, {4200, 1, 2}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

static const double scales[][2] = {{1, 0}, {0, 0}, {0.5, 1.25}, {-2, 3}, {-0.25, 0},
                                   {3e-20, -1}};
#define NSCALES (int)(sizeof scales / sizeof scales[0])

static const bvox_binarize modes[] = {
    {BVOX_BIN_NONZERO, 0, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, 2.5, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, -3, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, 0, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, 1e30, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, -1e30, 0, 0, 0},
    {BVOX_BIN_THRESHOLD, 9223372036854775808.0, 0, 0, 0},
    {BVOX_BIN_RANGE, 0, -2, 3.5, 0},
    {BVOX_BIN_RANGE, 0, 5, 1, 0}, /* empty */
    {BVOX_BIN_RANGE, 0, -INFINITY, INFINITY, 0},
    {BVOX_BIN_RANGE, 0, 127.5, 40000, 0},
    {BVOX_BIN_LABEL, 0, 0, 0, 3},
    {BVOX_BIN_LABEL, 0, 0, 0, 2.5},
    {BVOX_BIN_LABEL, 0, 0, 0, -2},
};
#define NMODES (int)(sizeof modes / sizeof modes[0])

static const bvox_simd levels[] = {BVOX_SIMD_GENERIC, BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};

/* Every mode x scale x byte order x size, on every SIMD path this CPU has.
 * Small sizes get every combination; the big ones a rotating subset. */
static int check_dtype(bvox_dtype dt)
{
    int fails = 0;
    for (int si = 0; si < NSIZES; si++) {
        const int *s = sizes[si];
        size_t n = (size_t)s[0] * (size_t)s[1] * (size_t)s[2];
        unsigned char *native = malloc(n * dt_size[dt]);
        fill_random(native, dt, n);
        for (int li = 0; li < 3; li++) {
            if (!bvox_simd_supported(levels[li])) continue;
            CHECK_OK(bvox_simd_set(levels[li]));
            for (int mi = 0; mi < NMODES; mi++)
                for (int ci = 0; ci < NSCALES; ci++)
                    for (int swap = 0; swap < 2; swap++) {
                        if (n > 20000 && (mi + ci + swap + li) % 4 != 0) continue;
                        fails += check_case(native, dt, s, swap, scales[ci][0], scales[ci][1],
                                            &modes[mi]);
                        if (fails > 5) break;
                    }
        }
        free(native);
    }
    bvox_simd_set(BVOX_SIMD_AUTO);
    CHECK_EQ(fails, 0);
    return 0;
}

TEST(modes_u8) { return check_dtype(BVOX_DT_U8); }
TEST(modes_i8) { return check_dtype(BVOX_DT_I8); }
TEST(modes_u16) { return check_dtype(BVOX_DT_U16); }
TEST(modes_i16) { return check_dtype(BVOX_DT_I16); }
TEST(modes_u32) { return check_dtype(BVOX_DT_U32); }
TEST(modes_i32) { return check_dtype(BVOX_DT_I32); }
TEST(modes_u64) { return check_dtype(BVOX_DT_U64); }
TEST(modes_i64) { return check_dtype(BVOX_DT_I64); }
TEST(modes_f32) { return check_dtype(BVOX_DT_F32); }
TEST(modes_f64) { return check_dtype(BVOX_DT_F64); }

/* Raw bounds at the very ends of 64-bit types, where doubles cannot tell
 * neighbouring integers apart: the binary search must still agree with the
 * per-voxel double evaluation. */
TEST(extremes_64bit)
{
    const int s[3] = {67, 3, 66};
    size_t n = (size_t)s[0] * s[1] * s[2];
    unsigned char *native = malloc(n * 8);
    const bvox_binarize hows[] = {
        {BVOX_BIN_THRESHOLD, 18446744073709549568.0, 0, 0, 0}, /* 2^64 - 2048 */
        {BVOX_BIN_THRESHOLD, 9223372036854774784.0, 0, 0, 0},
        {BVOX_BIN_RANGE, 0, -9223372036854775808.0, -9223372036854774784.0, 0},
        {BVOX_BIN_LABEL, 0, 0, 0, 18446744073709551616.0},
        {BVOX_BIN_NONZERO, 0, 0, 0, 0}};
    for (int d = 0; d < 2; d++) {
        bvox_dtype dt = d ? BVOX_DT_I64 : BVOX_DT_U64;
        for (size_t i = 0; i < n; i++) {
            uint64_t r = harness_rand();
            uint64_t base = d ? (r & 1 ? 0x7FFFFFFFFFFFFFFFull : 0x8000000000000000ull) : ~0ull;
            uint64_t u = r & 1 ? base - (r >> 52) : base + (r >> 52);
            if (!d) u = ~0ull - (r >> 52);
            if (r % 7 == 0) u = 0;
            memcpy(native + i * 8, &u, 8);
        }
        for (int h = 0; h < 5; h++)
            for (int c = 0; c < 3; c++) {
                double slope = c == 2 ? -1 : 1, inter = c == 1 ? 4096 : 0;
                CHECK_EQ(check_case(native, dt, s, h & 1, slope, inter, &hows[h]), 0);
            }
    }
    free(native);
    return 0;
}

/* NaN is never 1, in every mode, including nonzero and a full range. */
TEST(nan_is_zero)
{
    float f[8] = {NAN, 1, -NAN, 0, INFINITY, -INFINITY, NAN, -0.0f};
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){2, 2, 2};
    g.dtype = BVOX_DT_F32;
    g.data = f;
    const bvox_binarize hows[] = {{BVOX_BIN_NONZERO, 0, 0, 0, 0},
                                  {BVOX_BIN_RANGE, 0, -INFINITY, INFINITY, 0},
                                  {BVOX_BIN_THRESHOLD, -INFINITY, 0, 0, 0},
                                  {BVOX_BIN_OTSU, 0, 0, 0, 0}};
    /* voxel i is bit i: x + 2y + 4z */
    const unsigned want[] = {0x32, 0xBA, 0xBA, 0x12};
    for (int h = 0; h < 4; h++) {
        bvox_volume *v;
        CHECK_OK(bvox__binarize(&g, &hows[h], "nan.nii", &v));
        unsigned got = 0;
        for (int i = 0; i < 8; i++) got |= (unsigned)bvox_volume_get(v, i & 1, i >> 1 & 1, i >> 2) << i;
        CHECK_EQ(got, want[h]);
        bvox_volume_destroy(v);
    }
    return 0;
}

/* -------------------------------------------------------------------- Otsu */

/* Binarize n samples (nx = n, ny = nz = 1) with Otsu and return the bits. */
static int otsu_bits(const void *data, bvox_dtype dt, int n, double slope, double inter,
                     uint64_t *bits)
{
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){n, 1, 1};
    g.dtype = dt;
    g.data = data;
    g.slope = slope;
    g.inter = inter;
    bvox_binarize how = {BVOX_BIN_OTSU, 0, 0, 0, 0};
    bvox_volume *v;
    CHECK_OK(bvox__binarize(&g, &how, "otsu.nii", &v));
    *bits = 0;
    for (int x = 0; x < n; x++) *bits |= (uint64_t)bvox_volume_get(v, x, 0, 0) << x;
    bvox_volume_destroy(v);
    return 0;
}

/* Histogram 0:4, 2:2, 5:2 (N = 8). Between-class variance w0 w1 (mu0-mu1)^2:
 * split {0} | {2,5}: .5 * .5 * (0 - 3.5)^2 = 3.0625;
 * split {0,2} | {5}: .75 * .25 * (2/3 - 5)^2 = 3.5208 -> the maximum.
 * So the threshold is 2 and only the 5s are 1. With slope -1 the real values
 * are 0, -2, -5: {-5} | {-2,0} is 3.5208 again, the threshold is -5, and the
 * 0s and 2s are 1. */
TEST(otsu_hand_u8)
{
    const uint8_t v[8] = {0, 5, 0, 2, 0, 5, 2, 0};
    uint64_t bits;
    if (otsu_bits(v, BVOX_DT_U8, 8, 1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0x22); /* the 5s: x = 1, 5 */
    if (otsu_bits(v, BVOX_DT_U8, 8, -1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0xDD);
    /* an intercept shifts nothing */
    if (otsu_bits(v, BVOX_DT_U8, 8, 3, -100, &bits)) return 1;
    CHECK_EQ(bits, 0x22);
    return 0;
}

/* i16 (exact 65536 bins), values -300:4, 100:2, 1000:2:
 * {-300} | {100,1000}: .25 * 850^2 = 180625;
 * {-300,100} | {1000}: .1875 * (1000 + 1000/6)^2 = 255208 -> threshold 100. */
TEST(otsu_hand_i16)
{
    const int16_t v[8] = {-300, 100, 1000, -300, -300, 1000, 100, -300};
    uint64_t bits;
    if (otsu_bits(v, BVOX_DT_I16, 8, 1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0x24);
    if (otsu_bits(v, BVOX_DT_I16, 8, -0.5, 7, &bits)) return 1;
    CHECK_EQ(bits, 0xDB);
    return 0;
}

/* f32 (256 bins between min 0 and max 5): 0 -> bin 0, 2 -> bin 102, 5 -> bin
 * 255; the split lies after bin 102, the threshold is the bin edge
 * 103 * 5 / 256 = 2.0117: the 5s are 1. */
TEST(otsu_hand_f32)
{
    const float v[9] = {0, 5, 0, 2, 0, 5, 2, 0, NAN};
    uint64_t bits;
    if (otsu_bits(v, BVOX_DT_F32, 9, 1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0x22);
    if (otsu_bits(v, BVOX_DT_F32, 9, -1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0xDD); /* NaN (x = 8) stays 0 */
    /* one value only: nothing to split, all zero */
    const float one[3] = {4, 4, NAN};
    if (otsu_bits(one, BVOX_DT_F32, 3, 1, 0, &bits)) return 1;
    CHECK_EQ(bits, 0);
    return 0;
}

/* Two tight clusters far apart, in every type, both byte orders, both slope
 * signs: Otsu's split falls in the gap, so exactly the cluster with the
 * higher REAL values is 1. */
TEST(otsu_two_clusters_all_dtypes)
{
    const int s[3] = {65, 7, 67};
    size_t n = (size_t)s[0] * s[1] * s[2];
    for (int dt = 0; dt < BVOX_DT_COUNT; dt++) {
        unsigned char *native = malloc(n * dt_size[dt]);
        int64_t lo = is_signed_dt((bvox_dtype)dt) || is_float_dt((bvox_dtype)dt) ? -50 : 10;
        for (size_t i = 0; i < n; i++) {
            uint64_t r = harness_rand();
            int64_t val = (r & 1 ? lo : 100) + (int64_t)(r >> 1) % 3;
            store(native, (bvox_dtype)dt, i, val, (uint64_t)val, (double)val);
        }
        for (int sign = 0; sign < 2; sign++)
            for (int swap = 0; swap < 2; swap++) {
                unsigned char *data = malloc(n * dt_size[dt]);
                memcpy(data, native, n * dt_size[dt]);
                if (swap) byteswap_buf(data, dt_size[dt], n);
                bvox__gray g;
                bvox__gray_init(&g);
                g.dims = (bvox_dims){s[0], s[1], s[2]};
                g.dtype = (bvox_dtype)dt;
                g.data = data;
                g.byteswap = swap;
                g.slope = sign ? -1.5 : 2;
                bvox_binarize how = {BVOX_BIN_OTSU, 0, 0, 0, 0};
                bvox_volume *v;
                CHECK_OK(bvox__binarize(&g, &how, "clusters", &v));
                int64_t want = 0;
                for (size_t i = 0; i < n; i++) {
                    int high = raw_at(native, (bvox_dtype)dt, i) >= 100;
                    int on = sign ? !high : high;
                    want += on;
                    int x = (int)(i % 65), y = (int)(i / 65 % 7), z = (int)(i / (65 * 7));
                    if (bvox_volume_get(v, x, y, z) != on) {
                        fprintf(stderr, "%s sign %d swap %d: voxel %zu wrong\n", dt_name[dt],
                                sign, swap, i);
                        return 1;
                    }
                }
                CHECK_EQ(bvox_volume_count(v), want);
                bvox_volume_destroy(v);
                free(data);
            }
        free(native);
    }
    return 0;
}

/* ------------------------------------------------------------ errors, misc */

TEST(errors)
{
    uint8_t d[8] = {0};
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){2, 2, 2};
    g.data = d;
    bvox_volume *v = (bvox_volume *)1;
    bvox_binarize how = {BVOX_BIN_THRESHOLD, NAN, 0, 0, 0};
    CHECK_STATUS(bvox__binarize(&g, &how, "a.nii", &v), BVOX_EINVAL);
    CHECK(v == NULL);
    CHECK(strstr(bvox_errmsg(), "a.nii") != NULL);
    how = (bvox_binarize){BVOX_BIN_RANGE, 0, 1, NAN, 0};
    CHECK_STATUS(bvox__binarize(&g, &how, "a.nii", &v), BVOX_EINVAL);
    how = (bvox_binarize){(bvox_binarize_mode)42, 0, 0, 0, 0};
    CHECK_STATUS(bvox__binarize(&g, &how, "a.nii", &v), BVOX_EINVAL);
    g.slope = INFINITY;
    CHECK_STATUS(bvox__binarize(&g, NULL, "b.nii", &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "b.nii") != NULL);
    g.slope = 1;
    g.dims.nz = 0;
    CHECK_STATUS(bvox__binarize(&g, NULL, "c.nii", &v), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "c.nii") != NULL);
    g.dims.nz = 2;
    g.dtype = BVOX_DT_COUNT;
    CHECK_STATUS(bvox__binarize(&g, NULL, "d.nii", &v), BVOX_EINVAL);
    g.dtype = BVOX_DT_U8;
    g.geom.spacing[0] = -1;
    CHECK_STATUS(bvox__binarize(&g, NULL, "e.nii", &v), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "e.nii") != NULL);
    g.geom.spacing[0] = 1;
    bvox__alloc_fail_after(1);
    CHECK_STATUS(bvox__binarize(&g, NULL, "f.nii", &v), BVOX_ENOMEM);
    CHECK(v == NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    how = (bvox_binarize){BVOX_BIN_OTSU, 0, 0, 0, 0};
    bvox__alloc_fail_after(1); /* the histogram */
    CHECK_STATUS(bvox__binarize(&g, &how, "g.nii", &v), BVOX_ENOMEM);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_OK(bvox__binarize(&g, NULL, "ok.nii", &v));
    CHECK_EQ(bvox_volume_count(v), 0);
    bvox_volume_destroy(v);
    return 0;
}

TEST(gray_init_release)
{
    bvox__gray g;
    memset(&g, 0x5A, sizeof g);
    bvox__gray_init(&g);
    CHECK(g.slope == 1 && g.inter == 0 && g.data == NULL && g.owned == NULL && !g.byteswap);
    CHECK(g.geom.spacing[0] == 1 && g.geom.direction[4] == 1);
    bvox_status st;
    g.owned_bytes = 1000;
    g.owned = bvox__alloc(g.owned_bytes, true, "samples", &st);
    CHECK(g.owned != NULL);
    g.data = g.owned;
    CHECK_EQ(bvox_memory_in_use(), 1000);
    bvox__gray_release(&g);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK(g.owned == NULL && g.data == NULL);
    bvox__gray_release(&g); /* twice is harmless */
    return 0;
}

/* Big enough to be split over threads: the result must not depend on the
 * thread count, and must match the naive evaluation. */
TEST(threads_agree)
{
    const int s[3] = {301, 97, 131};
    size_t n = (size_t)s[0] * s[1] * s[2];
    uint16_t *d = malloc(n * 2);
    for (size_t i = 0; i < n; i++) d[i] = (uint16_t)(harness_rand() % 9);
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){s[0], s[1], s[2]};
    g.dtype = BVOX_DT_U16;
    g.data = d;
    bvox_binarize how = {BVOX_BIN_RANGE, 0, 2, 5, 0};
    bvox_volume *v1, *v4;
    bvox_set_threads(1);
    CHECK_OK(bvox__binarize(&g, &how, "t", &v1));
    bvox_set_threads(4);
    CHECK_OK(bvox__binarize(&g, &how, "t", &v4));
    bvox_set_threads(0);
    CHECK(bvox_volume_equal(v1, v4));
    int64_t want = 0;
    for (size_t i = 0; i < n; i++) want += d[i] >= 2 && d[i] <= 5;
    CHECK_EQ(bvox_volume_count(v4), want);
    CHECK_EQ(check_case((const unsigned char *)d, BVOX_DT_U16, s, 0, 1, 0, &how), 0);
    bvox_volume_destroy(v1);
    bvox_volume_destroy(v4);
    free(d);
    return 0;
}

/* ------------------------------------------------------------------ unpack */

TEST(unpack_round_trip)
{
    static const int usizes[][3] = {{1, 1, 1},   {3, 5, 63},  {63, 3, 64}, {65, 2, 65},
                                    {130, 3, 130}, {1, 7, 200}, {200, 1, 129}};
    for (int si = 0; si < 7; si++) {
        const int *s = usizes[si];
        bvox_volume *v;
        CHECK_OK(bvox_volume_create((bvox_dims){s[0], s[1], s[2]}, &v));
        for (int z = 0; z < s[2]; z++)
            for (int y = 0; y < s[1]; y++)
                for (int x = 0; x < s[0]; x++)
                    if (harness_rand() % 3 == 0) CHECK_OK(bvox_volume_set(v, x, y, z, 1));
        size_t plane = (size_t)s[0] * s[1];
        uint8_t *buf = malloc(64 * plane + 16);
        for (int z0 = 0; z0 < s[2]; z0 += 64) {
            int counts[3] = {s[2] - z0 < 64 ? s[2] - z0 : 64, 1, 0};
            counts[2] = counts[0] > 2 ? counts[0] - 1 : 1;
            for (int c = 0; c < 3; c++) {
                int n = counts[c];
                uint8_t one = c == 1 ? 1 : 255;
                memset(buf, 0xA5, 64 * plane + 16);
                bvox__unpack_slices(v, z0, n, one, buf);
                for (int z = 0; z < n; z++)
                    for (int y = 0; y < s[1]; y++)
                        for (int x = 0; x < s[0]; x++) {
                            uint8_t want = bvox_volume_get(v, x, y, z0 + z) ? one : 0;
                            CHECK_EQ(buf[((size_t)z * s[1] + y) * s[0] + x], want);
                        }
                /* nothing written past the n slices */
                CHECK_EQ(buf[(size_t)n * plane], 0xA5);
            }
        }
        free(buf);
        bvox_volume_destroy(v);
    }
    return 0;
}

/* binarize(unpack(v)) == v, with threads, for a larger volume. */
TEST(unpack_binarize_inverse)
{
    const int s[3] = {257, 131, 129};
    bvox_volume *v, *back;
    CHECK_OK(bvox_volume_create((bvox_dims){s[0], s[1], s[2]}, &v));
    for (int i = 0; i < 200000; i++) {
        int x = (int)(harness_rand() % 257), y = (int)(harness_rand() % 131);
        int z = (int)(harness_rand() % 129);
        CHECK_OK(bvox_volume_set(v, x, y, z, 1));
    }
    size_t plane = (size_t)s[0] * s[1];
    uint8_t *bytes = malloc(plane * s[2]);
    for (int z0 = 0; z0 < s[2]; z0 += 64)
        bvox__unpack_slices(v, z0, s[2] - z0 < 64 ? s[2] - z0 : 64, 7, bytes + z0 * plane);
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = (bvox_dims){s[0], s[1], s[2]};
    g.data = bytes;
    bvox_set_threads(2);
    CHECK_OK(bvox__binarize(&g, NULL, "rt", &back));
    bvox_set_threads(0);
    CHECK(bvox_volume_equal(v, back));
    CHECK_OK(bvox_volume_check(back));
    bvox_volume_destroy(back);
    bvox_volume_destroy(v);
    free(bytes);
    return 0;
}
