/* test_samples.c — bvox_volume_from_samples and bvox_volume_to_bytes (the
 * arrays of the Python package): both sample orders at awkward sizes (nz = 1,
 * 63, 64, 65, 130; odd nx, ny), several types and modes, each voxel compared
 * with a per-voxel evaluation written here; zero tail bits when the padding
 * would pass the test; byte round trips in both orders; bad arguments. */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const bvox_dims sizes[] = {{5, 3, 1}, {7, 2, 63}, {3, 5, 64}, {2, 3, 65}, {3, 2, 130}};
#define NSIZES (sizeof sizes / sizeof sizes[0])

static size_t nvox(bvox_dims d) { return (size_t)d.nx * (size_t)d.ny * (size_t)d.nz; }
static size_t idx_x(bvox_dims d, int x, int y, int z)
{
    return ((size_t)z * (size_t)d.ny + (size_t)y) * (size_t)d.nx + (size_t)x;
}
static size_t idx_z(bvox_dims d, int x, int y, int z)
{
    return ((size_t)x * (size_t)d.ny + (size_t)y) * (size_t)d.nz + (size_t)z;
}

static int pass(double v, const bvox_binarize *how)
{
    switch (how->mode) {
    case BVOX_BIN_NONZERO: return v != 0;
    case BVOX_BIN_THRESHOLD: return v >= how->threshold;
    case BVOX_BIN_RANGE: return v >= how->lo && v <= how->hi;
    case BVOX_BIN_LABEL: return v == how->label;
    default: return -1;
    }
}

/* Random values in -3..12 of one type, stored in both orders; returns the
 * values (x fastest) as doubles. */
static double *fill(bvox_dims d, bvox_dtype dt, void *bx, void *bz)
{
    double *v = malloc(nvox(d) * sizeof *v);
    for (int z = 0; z < d.nz; z++)
        for (int y = 0; y < d.ny; y++)
            for (int x = 0; x < d.nx; x++) {
                int r = (int)(harness_rand() % 16) - 3;
                if (dt == BVOX_DT_U8 && r < 0) r = 0;
                size_t i = idx_x(d, x, y, z), j = idx_z(d, x, y, z);
                v[i] = r;
                switch (dt) {
                case BVOX_DT_U8: ((uint8_t *)bx)[i] = ((uint8_t *)bz)[j] = (uint8_t)r; break;
                case BVOX_DT_I16: ((int16_t *)bx)[i] = ((int16_t *)bz)[j] = (int16_t)r; break;
                case BVOX_DT_F32: ((float *)bx)[i] = ((float *)bz)[j] = (float)r; break;
                default: ((double *)bx)[i] = ((double *)bz)[j] = r; break;
                }
            }
    return v;
}

TEST(both_orders_every_mode)
{
    const bvox_dtype types[] = {BVOX_DT_U8, BVOX_DT_I16, BVOX_DT_F32, BVOX_DT_F64};
    bvox_binarize modes[4] = {{BVOX_BIN_NONZERO, 0, 0, 0, 0},
                              {BVOX_BIN_THRESHOLD, 5, 0, 0, 0},
                              {BVOX_BIN_RANGE, 0, 2, 7, 0},
                              {BVOX_BIN_LABEL, 0, 0, 0, 4}};
    for (size_t s = 0; s < NSIZES; s++)
        for (size_t t = 0; t < 4; t++) {
            bvox_dims d = sizes[s];
            void *bx = malloc(nvox(d) * 8), *bz = malloc(nvox(d) * 8);
            double *v = fill(d, types[t], bx, bz);
            for (size_t m = 0; m < 4; m++) {
                bvox_volume *a = NULL, *b = NULL;
                CHECK_OK(bvox_volume_from_samples(bx, types[t], d, BVOX_ORDER_X_FASTEST,
                                                  &modes[m], &a));
                CHECK_OK(bvox_volume_from_samples(bz, types[t], d, BVOX_ORDER_Z_FASTEST,
                                                  &modes[m], &b));
                CHECK_OK(bvox_volume_check(b));
                int64_t want = 0;
                for (int z = 0; z < d.nz; z++)
                    for (int y = 0; y < d.ny; y++)
                        for (int x = 0; x < d.nx; x++) {
                            int p = pass(v[idx_x(d, x, y, z)], &modes[m]);
                            want += p;
                            CHECK_EQ(bvox_volume_get(b, x, y, z), p);
                        }
                CHECK_EQ(bvox_volume_count(b), want);
                CHECK(bvox_volume_equal(a, b));
                bvox_volume_destroy(a);
                bvox_volume_destroy(b);
            }
            free(v);
            free(bx);
            free(bz);
        }
    return 0;
}

/* A range holding 0 makes the zero padding of the last block pass: the
 * column's bits beyond nz must still come out zero. */
TEST(tail_bits_zero_when_padding_passes)
{
    bvox_dims d = {3, 2, 65};
    int16_t *buf = calloc(nvox(d), sizeof *buf);
    buf[5] = 300; /* one value outside, so the predicate is really evaluated */
    bvox_binarize how = {BVOX_BIN_RANGE, 0, -5, 200, 0};
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_from_samples(buf, BVOX_DT_I16, d, BVOX_ORDER_Z_FASTEST, &how, &v));
    CHECK_OK(bvox_volume_check(v));
    CHECK_EQ(bvox_volume_count(v), (int64_t)nvox(d) - 1);
    CHECK_EQ(bvox_volume_get(v, 0, 0, 5), 0); /* index 5 in z-fastest order: z = 5 */
    bvox_volume_destroy(v);
    free(buf);
    return 0;
}

TEST(bytes_round_trip_both_orders)
{
    for (size_t s = 0; s < NSIZES; s++) {
        bvox_dims d = sizes[s];
        bvox_volume *v = NULL;
        CHECK_OK(bvox_volume_create(d, &v));
        for (int z = 0; z < d.nz; z++)
            for (int y = 0; y < d.ny; y++)
                for (int x = 0; x < d.nx; x++)
                    if (harness_rand() % 3 == 0) CHECK_OK(bvox_volume_set(v, x, y, z, 1));
        uint8_t *bx = malloc(nvox(d)), *bz = malloc(nvox(d));
        memset(bx, 0xAA, nvox(d));
        memset(bz, 0xAA, nvox(d));
        CHECK_OK(bvox_volume_to_bytes(v, BVOX_ORDER_X_FASTEST, bx));
        CHECK_OK(bvox_volume_to_bytes(v, BVOX_ORDER_Z_FASTEST, bz));
        for (int z = 0; z < d.nz; z++)
            for (int y = 0; y < d.ny; y++)
                for (int x = 0; x < d.nx; x++) {
                    int want = bvox_volume_get(v, x, y, z);
                    CHECK_EQ(bx[idx_x(d, x, y, z)], want);
                    CHECK_EQ(bz[idx_z(d, x, y, z)], want);
                }
        bvox_volume *back = NULL;
        CHECK_OK(bvox_volume_from_samples(bz, BVOX_DT_U8, d, BVOX_ORDER_Z_FASTEST, NULL, &back));
        CHECK(bvox_volume_equal(v, back));
        bvox_volume_destroy(back);
        bvox_volume_destroy(v);
        free(bx);
        free(bz);
    }
    return 0;
}

TEST(bad_arguments)
{
    uint8_t buf[8] = {0};
    bvox_dims d = {2, 2, 2}, zero = {2, 0, 2};
    bvox_volume *v = (bvox_volume *)buf; /* must be set to NULL on failure */
    CHECK_STATUS(bvox_volume_from_samples(buf, BVOX_DT_U8, d, (bvox_order)7, NULL, &v),
                 BVOX_EINVAL);
    CHECK(v == NULL);
    CHECK_STATUS(bvox_volume_from_samples(buf, BVOX_DT_COUNT, d, BVOX_ORDER_X_FASTEST, NULL, &v),
                 BVOX_EINVAL);
    CHECK_STATUS(bvox_volume_from_samples(buf, BVOX_DT_U8, zero, BVOX_ORDER_X_FASTEST, NULL, &v),
                 BVOX_EINVAL);
    bvox_binarize nan_threshold = {BVOX_BIN_THRESHOLD, NAN, 0, 0, 0};
    CHECK_STATUS(bvox_volume_from_samples(buf, BVOX_DT_U8, d, BVOX_ORDER_X_FASTEST,
                                          &nan_threshold, &v),
                 BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "NaN") != NULL);
    CHECK_OK(bvox_volume_create(d, &v));
    CHECK_STATUS(bvox_volume_to_bytes(v, BVOX_ORDER_X_FASTEST, NULL), BVOX_EINVAL);
    CHECK_STATUS(bvox_volume_to_bytes(v, (bvox_order)3, buf), BVOX_EINVAL);
    bvox_volume_destroy(v);
    return 0;
}

/* Every SIMD path the CPU has packs z-fastest columns exactly as the generic
 * one (the compare kernels differ per path; the column packer is shared). */
TEST(every_simd_path)
{
    bvox_dims d = {5, 4, 200};
    float *buf = malloc(nvox(d) * sizeof *buf);
    for (size_t i = 0; i < nvox(d); i++) buf[i] = (float)(harness_rand() % 100) / 10.0f;
    bvox_binarize how = {BVOX_BIN_RANGE, 0, 2.5, 7.5, 0};
    bvox_simd saved = bvox_simd_active();
    bvox_volume *ref = NULL;
    CHECK_OK(bvox_simd_set(BVOX_SIMD_GENERIC));
    CHECK_OK(bvox_volume_from_samples(buf, BVOX_DT_F32, d, BVOX_ORDER_Z_FASTEST, &how, &ref));
    const bvox_simd levels[] = {BVOX_SIMD_AVX2, BVOX_SIMD_AVX512};
    for (int i = 0; i < 2; i++) {
        if (!bvox_simd_supported(levels[i])) continue;
        CHECK_OK(bvox_simd_set(levels[i]));
        bvox_volume *v = NULL;
        CHECK_OK(bvox_volume_from_samples(buf, BVOX_DT_F32, d, BVOX_ORDER_Z_FASTEST, &how, &v));
        CHECK(bvox_volume_equal(v, ref));
        bvox_volume_destroy(v);
    }
    CHECK_OK(bvox_simd_set(saved));
    int64_t want = 0;
    for (size_t i = 0; i < nvox(d); i++) want += buf[i] >= 2.5f && buf[i] <= 7.5f;
    CHECK_EQ(bvox_volume_count(ref), want);
    bvox_volume_destroy(ref);
    free(buf);
    return 0;
}

/* bvox_volume_from_words inverts bvox_volume_words; wrong counts and bits
 * beyond nz are refused. */
TEST(from_words)
{
    bvox_dims d = {3, 4, 70};
    bvox_volume *v = NULL, *back = NULL;
    CHECK_OK(bvox_volume_create(d, &v));
    for (int i = 0; i < 40; i++)
        CHECK_OK(bvox_volume_set(v, (int)(harness_rand() % 3), (int)(harness_rand() % 4),
                                 (int)(harness_rand() % 70), 1));
    bvox_words_view w = bvox_volume_words(v);
    CHECK_OK(bvox_volume_from_words(d, w.words, w.word_count, &back));
    CHECK(bvox_volume_equal(v, back));
    CHECK_OK(bvox_volume_check(back));
    bvox_volume_destroy(back);
    back = (bvox_volume *)&d;
    CHECK_STATUS(bvox_volume_from_words(d, w.words, w.word_count - 1, &back), BVOX_EINVAL);
    CHECK(back == NULL);
    uint64_t *copy = malloc(w.word_count * sizeof *copy);
    memcpy(copy, w.words, w.word_count * sizeof *copy);
    copy[(1 * 3 + 2) * w.words_per_column + 1] |= 1ull << 6; /* z = 70: beyond nz */
    CHECK_STATUS(bvox_volume_from_words(d, copy, w.word_count, &back), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "column (2, 1)") != NULL);
    free(copy);
    bvox_volume_destroy(v);
    return 0;
}
