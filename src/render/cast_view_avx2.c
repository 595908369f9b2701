/*
 * cast_view_avx2.c — the AVX2 kernels of arbitrary views: splat_list
 * (cast_view.c) four candidate pixels at a time (a row of four, or two rows
 * of two for footprints at most 2 pixels wide), with four entries projected
 * at once, and entry_bands (cast_view.h) four entries at a time.
 *
 * Every lane does the portable code's double arithmetic in the same order
 * (no FMA: the files are built without it), so the keys, and so the
 * pre-images, are bit-identical at every SIMD level. The min into the
 * z-buffer is taken one key at a time (min_keys); a row of four may run up
 * to 3 keys past the footprint into the row's padding (cast_view.h), where
 * its lanes carry the no-hit key ~0 and the min keeps what is there.
 */
#include "render/cast_view.h"

#if defined(__x86_64__) && defined(__AVX2__)
#include <immintrin.h>
#include <string.h>

/* project_axis of four entries at once, for the coefficients p: the same
 * operations in the same order, so the same values. */
static inline __m256d project_axis4(__m256i ev, const double p[4])
{
    const __m256i low = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    __m256d xyz[3];
    for (int a = 0; a < 3; a++) {
        __m256i v = _mm256_and_si256(_mm256_srli_epi64(ev, 16 * a), _mm256_set1_epi64x(0xffff));
        xyz[a] = _mm256_cvtepi32_pd(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(v, low)));
    }
    return _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(xyz[0], _mm256_set1_pd(p[0])),
                                                     _mm256_mul_pd(xyz[1], _mm256_set1_pd(p[1]))),
                                       _mm256_mul_pd(xyz[2], _mm256_set1_pd(p[2]))),
                         _mm256_set1_pd(p[3]));
}

/* The keys of four candidate pixels of one entry, lanes at offsets du, dv
 * (pixels) from its projected centre, wc its depth; lanes not in `valid`
 * miss (~0). splat_list's per-pixel arithmetic, lane by lane. */
static inline __m256i keys4(const splat_ctx *c, __m256d du, __m256d dv, __m256d wc, __m256i nb,
                            __m256d valid)
{
    __m256d tmin = _mm256_set1_pd(-INFINITY), tmax = _mm256_set1_pd(INFINITY);
    for (int a = 0; a < 3; a++) {
        __m256d k = _mm256_add_pd(_mm256_mul_pd(du, _mm256_set1_pd(c->ku[a])),
                                  _mm256_mul_pd(dv, _mm256_set1_pd(c->kv[a])));
        tmin = _mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(-c->H[a]), k), tmin);
        tmax = _mm256_min_pd(_mm256_sub_pd(_mm256_set1_pd(c->H[a]), k), tmax);
    }
    __m256d hit = _mm256_and_pd(_mm256_cmp_pd(tmin, tmax, _CMP_LE_OQ), valid);
    for (int a = 0; a < 3; a++)
        if (c->parallel[a]) {
            __m256d q = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(du, _mm256_set1_pd(c->f.r[a])),
                                                    _mm256_mul_pd(dv, _mm256_set1_pd(c->f.dn[a]))),
                                      _mm256_set1_pd(1.0 / c->scale));
            __m256d ok = _mm256_and_pd(_mm256_cmp_pd(q, _mm256_set1_pd(-c->h[a]), _CMP_GE_OQ),
                                       _mm256_cmp_pd(q, _mm256_set1_pd(c->h[a]), _CMP_LT_OQ));
            hit = _mm256_and_pd(hit, ok);
        }
    __m128 df = _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_add_pd(wc, tmin), _mm256_set1_pd(c->scale)));
    df = _mm_max_ps(df, _mm_setzero_ps());
    __m256i key =
        _mm256_or_si256(_mm256_slli_epi64(_mm256_cvtepu32_epi64(_mm_castps_si128(df)), 32), nb);
    return _mm256_or_si256(key, _mm256_castpd_si256(_mm256_xor_pd(
                                    hit, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))));
}

/* The min of keys k[0..n) into row[0..n), one key at a time: a 4-key load
 * right after an overlapping 4-key store of the previous entry (footprints
 * of neighbouring voxels overlap) cannot be forwarded and stalls; 8-byte
 * accesses forward. */
static inline void min_keys(uint64_t *row, const uint64_t *k, int n)
{
    for (int l = 0; l < n; l++) row[l] = k[l] < row[l] ? k[l] : row[l];
}

static void splat_avx2(const splat_ctx *c, const uint64_t *list, int64_t n, int32_t row0,
                       int32_t row1, uint64_t *zb)
{
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
    const __m128i pair_x = _mm_setr_epi32(0, 1, 0, 1), pair_y = _mm_setr_epi32(0, 0, 1, 1);
    /* four entries projected at once (project()'s arithmetic lane by lane),
     * then splatted one by one; the last n % 4 projected by project() */
    double fus[4], fvs[4], wcs[4];
    int32_t boxes[4][4];
    const __m256d vhu = _mm256_set1_pd(c->hu), vhv = _mm256_set1_pd(c->hv);
    const __m256d half = _mm256_set1_pd(-0.5);
    const __m256d wn = _mm256_set1_pd(c->w), wn1 = _mm256_set1_pd(c->w - 1);
    const __m256d hn = _mm256_set1_pd(c->hgt), hn1 = _mm256_set1_pd(c->hgt - 1);
    for (int64_t i = 0; i < n; i++) {
        uint64_t e = list[i];
        double fu, fv, wc;
        int32_t box[4];
        int j = (int)(i & 3);
        if (j == 0 && i + 4 <= n) {
            __m256i ev = _mm256_loadu_si256((const __m256i *)(list + i));
            __m256d pr[3] = {project_axis4(ev, c->pu), project_axis4(ev, c->pv),
                             project_axis4(ev, c->pw)};
            _mm256_storeu_pd(fus, pr[0]);
            _mm256_storeu_pd(fvs, pr[1]);
            _mm256_storeu_pd(wcs, pr[2]);
            /* ceil_in / floor_in: clamp, then round (exact: integral values) */
            __m256d b[4] = {
                _mm256_ceil_pd(_mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(pr[0], vhu), half), wn)),
                _mm256_floor_pd(_mm256_min_pd(_mm256_max_pd(_mm256_add_pd(pr[0], vhu), half), wn1)),
                _mm256_ceil_pd(_mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(pr[1], vhv), half), hn)),
                _mm256_floor_pd(_mm256_min_pd(_mm256_max_pd(_mm256_add_pd(pr[1], vhv), half), hn1))};
            int32_t bt[4][4];
            for (int q = 0; q < 4; q++) _mm_storeu_si128((__m128i *)bt[q], _mm256_cvttpd_epi32(b[q]));
            for (int l = 0; l < 4; l++)
                for (int q = 0; q < 4; q++) boxes[l][q] = bt[q][l];
        }
        if (i + 4 - j <= n) { /* in a projected group of four */
            fu = fus[j], fv = fvs[j], wc = wcs[j];
            memcpy(box, boxes[j], sizeof box);
            if (!(box[0] <= box[1] && box[2] <= box[3])) continue;
        } else if (!project(c, e, &fu, &fv, &wc, box))
            continue;
        int32_t py0 = box[2] > row0 ? box[2] : row0, py1 = box[3] < row1 - 1 ? box[3] : row1 - 1;
        const __m256i nb = _mm256_set1_epi64x((long long)SURF_NB(e));
        const __m256d vfu = _mm256_set1_pd(fu), vfv = _mm256_set1_pd(fv), vwc = _mm256_set1_pd(wc);
        uint64_t k4[4];
        if (box[1] - box[0] <= 1) {
            /* a footprint at most 2 pixels wide (the usual at a scale near
             * one pixel per voxel): two rows of two in the four lanes */
            __m128i xs = _mm_add_epi32(_mm_set1_epi32(box[0]), pair_x);
            __m256d du = _mm256_sub_pd(_mm256_cvtepi32_pd(xs), vfu);
            __m256d in_x = _mm256_castsi256_pd(
                _mm256_cvtepi32_epi64(_mm_cmpgt_epi32(_mm_set1_epi32(box[1] + 1), xs)));
            for (int32_t py = py0; py <= py1; py += 2) {
                __m128i ys = _mm_add_epi32(_mm_set1_epi32(py), pair_y);
                __m256d dv = _mm256_sub_pd(_mm256_cvtepi32_pd(ys), vfv);
                __m256d in = _mm256_and_pd(in_x, _mm256_castsi256_pd(_mm256_cvtepi32_epi64(
                                                     _mm_cmpgt_epi32(_mm_set1_epi32(py1 + 1), ys))));
                _mm256_storeu_si256((__m256i *)k4, keys4(c, du, dv, vwc, nb, in));
                uint64_t *row = zb + (size_t)(py - row0) * (size_t)c->stride + (size_t)box[0];
                min_keys(row, k4, 2);
                if (py < py1) min_keys(row + c->stride, k4 + 2, 2);
            }
            continue;
        }
        for (int32_t py = py0; py <= py1; py++) {
            __m256d dv = _mm256_set1_pd(py - fv);
            uint64_t *row = zb + (size_t)(py - row0) * (size_t)c->stride;
            for (int32_t px = box[0]; px <= box[1]; px += 4) {
                __m128i pxs = _mm_add_epi32(_mm_set1_epi32(px), lane);
                __m256d du = _mm256_sub_pd(_mm256_cvtepi32_pd(pxs), vfu);
                /* lanes past the footprint's last pixel miss */
                __m256d in = _mm256_castsi256_pd(
                    _mm256_cvtepi32_epi64(_mm_cmpgt_epi32(_mm_set1_epi32(box[1] + 1), pxs)));
                _mm256_storeu_si256((__m256i *)k4, keys4(c, du, dv, vwc, nb, in));
                min_keys(row + px, k4, 4);
            }
        }
    }
}

/* entry_bands (cast_view.h) four entries at a time. */
static void bands_avx2(const splat_ctx *c, const uint64_t *list, int n, int32_t *b0, int32_t *b1)
{
    const __m256d vhv = _mm256_set1_pd(c->hv), margin = _mm256_set1_pd(1e-3);
    const __m256d half = _mm256_set1_pd(-0.5);
    const __m256d hn = _mm256_set1_pd(c->hgt), hn1 = _mm256_set1_pd(c->hgt - 1);
    const __m128i none = _mm_set1_epi32(-1);
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        __m256d fv = project_axis4(_mm256_loadu_si256((const __m256i *)(list + i)), c->pv);
        __m128i py0 = _mm256_cvttpd_epi32(_mm256_ceil_pd(
            _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(_mm256_sub_pd(fv, vhv), margin), half), hn)));
        __m128i py1 = _mm256_cvttpd_epi32(_mm256_floor_pd(
            _mm256_min_pd(_mm256_max_pd(_mm256_add_pd(_mm256_add_pd(fv, vhv), margin), half), hn1)));
        __m128i s0 = _mm_srai_epi32(py0, c->band_shift), s1 = _mm_srai_epi32(py1, c->band_shift);
        s1 = _mm_blendv_epi8(s1, none, _mm_cmpgt_epi32(py0, py1));
        _mm_storeu_si128((__m128i *)(b0 + i), s0);
        _mm_storeu_si128((__m128i *)(b1 + i), s1);
    }
    for (; i < n; i++) entry_bands(c, list[i], &b0[i], &b1[i]); /* the last n % 4 */
}

const bvox__splat_fn bvox__splat_avx2 = splat_avx2;
const bvox__bands_fn bvox__bands_avx2 = bands_avx2;
#else
const bvox__splat_fn bvox__splat_avx2 = NULL;
const bvox__bands_fn bvox__bands_avx2 = NULL;
#endif
