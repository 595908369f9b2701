/*
 * binarize_otsu.c — Otsu's automatic threshold for bvox__binarize.
 *
 * Histogram: one bin per value for 8- and 16-bit samples (256 or 65536 bins,
 * exact), otherwise 256 equal bins between the smallest and largest finite
 * sample (infinities go to the end bins, NaN is left out). Bins are counted
 * per chunk in parallel and summed.
 *
 * The split maximises the between-class variance. That variance does not
 * change under the affine map raw -> real, so it is computed on bin indices;
 * only the order does: with a negative slope the high real values are the
 * low raw bins. Ties go to the split lowest in REAL order. The threshold
 * returned is the largest real value of the lower class (exact bins) or the
 * real value of the bin edge between the classes (ranged bins); the caller
 * keeps voxels strictly above it.
 */
#include "binarize_kernels.h"

#include <math.h>
#include <string.h>

#define CHUNK 1024 /* samples converted to double at a time */

typedef struct hist_ctx {
    const unsigned char *data;
    bvox_dtype dt;
    bool swap;
    size_t n;           /* samples */
    int64_t nchunks;
    size_t nbins;
    uint64_t *hist;     /* nchunks * nbins */
    double *mn, *mx;    /* per chunk (ranged bins) */
    double lo, scale;   /* ranged bins: bin = (v/2 - lo) * scale */
    bool exact;
} hist_ctx;

/* Samples [i, i+k) of the volume as doubles (integers exactly up to 2^53). */
static void to_double(const hist_ctx *c, size_t i, size_t k, double *out)
{
    const unsigned char *s = c->data + i * bvox_dtype_size(c->dt);
#define CONVERT(T, U, SWAP)                                                                \
    for (size_t j = 0; j < k; j++) {                                                       \
        U u;                                                                               \
        T t;                                                                               \
        memcpy(&u, s + j * sizeof u, sizeof u);                                            \
        if (c->swap) u = SWAP(u);                                                          \
        memcpy(&t, &u, sizeof t);                                                          \
        out[j] = (double)t;                                                                \
    }
    switch (c->dt) {
    case BVOX_DT_U32: CONVERT(uint32_t, uint32_t, __builtin_bswap32) break;
    case BVOX_DT_I32: CONVERT(int32_t, uint32_t, __builtin_bswap32) break;
    case BVOX_DT_U64: CONVERT(uint64_t, uint64_t, __builtin_bswap64) break;
    case BVOX_DT_I64: CONVERT(int64_t, uint64_t, __builtin_bswap64) break;
    case BVOX_DT_F32: CONVERT(float, uint32_t, __builtin_bswap32) break;
    default: CONVERT(double, uint64_t, __builtin_bswap64) break;
    }
#undef CONVERT
}

static void chunk_bounds(const hist_ctx *c, int64_t k, size_t *b, size_t *e)
{
    *b = (size_t)((unsigned __int128)c->n * (uint64_t)k / (uint64_t)c->nchunks);
    *e = (size_t)((unsigned __int128)c->n * (uint64_t)(k + 1) / (uint64_t)c->nchunks);
}

static void minmax_range(void *ctx, int64_t begin, int64_t end)
{
    const hist_ctx *c = ctx;
    double buf[CHUNK];
    for (int64_t k = begin; k < end; k++) {
        size_t b, e;
        chunk_bounds(c, k, &b, &e);
        double mn = INFINITY, mx = -INFINITY;
        for (size_t i = b; i < e; i += CHUNK) {
            size_t len = e - i < CHUNK ? e - i : CHUNK;
            to_double(c, i, len, buf);
            for (size_t j = 0; j < len; j++) {
                if (!isfinite(buf[j])) continue;
                mn = buf[j] < mn ? buf[j] : mn;
                mx = buf[j] > mx ? buf[j] : mx;
            }
        }
        c->mn[k] = mn;
        c->mx[k] = mx;
    }
}

static void hist_range(void *ctx, int64_t begin, int64_t end)
{
    const hist_ctx *c = ctx;
    double buf[CHUNK];
    for (int64_t k = begin; k < end; k++) {
        uint64_t *h = c->hist + (size_t)k * c->nbins;
        size_t b, e;
        chunk_bounds(c, k, &b, &e);
        if (c->exact) {
            /* bin = raw bits with the sign bit flipped for signed types */
            size_t size = bvox_dtype_size(c->dt);
            unsigned flip = c->dt == BVOX_DT_I8 ? 0x80 : c->dt == BVOX_DT_I16 ? 0x8000 : 0;
            const unsigned char *s = c->data + b * size;
            if (size == 1) {
                /* four histograms, so that runs of equal samples do not wait
                 * on the previous increment of the same counter */
                uint64_t h4[4][256] = {{0}};
                size_t i = b;
                for (; i + 4 <= e; i += 4, s += 4) {
                    h4[0][s[0]]++;
                    h4[1][s[1]]++;
                    h4[2][s[2]]++;
                    h4[3][s[3]]++;
                }
                for (; i < e; i++, s++) h4[0][*s]++;
                for (unsigned j = 0; j < 256; j++)
                    h[j ^ flip] += h4[0][j] + h4[1][j] + h4[2][j] + h4[3][j];
            } else {
                for (size_t i = b; i < e; i++, s += 2) {
                    uint16_t u;
                    memcpy(&u, s, 2);
                    if (c->swap) u = __builtin_bswap16(u);
                    h[u ^ flip]++;
                }
            }
            continue;
        }
        for (size_t i = b; i < e; i += CHUNK) {
            size_t len = e - i < CHUNK ? e - i : CHUNK;
            to_double(c, i, len, buf);
            for (size_t j = 0; j < len; j++) {
                double v = buf[j];
                if (isnan(v)) continue;
                /* halves: v - lo may overflow for f64, v/2 - lo/2 cannot */
                double f = (v / 2 - c->lo) * c->scale;
                /* !(f > 0) also catches NaN (inf - inf when lo is infinite):
                 * converting NaN to an integer is undefined */
                size_t bin = !(f > 0) ? 0 : f >= 255 ? 255 : (size_t)f;
                h[bin]++;
            }
        }
    }
}

/* Split after bin k (lower class 0..k) maximising the between-class variance;
 * rising: ties to the lowest k, else to the highest. -1 if no split exists. */
static int64_t best_split(const uint64_t *h, size_t nbins, bool rising)
{
    double n = 0, sum = 0;
    for (size_t i = 0; i < nbins; i++) {
        n += (double)h[i];
        sum += (double)i * (double)h[i];
    }
    double w0 = 0, s0 = 0, best = -1;
    int64_t k_best = -1;
    for (size_t k = 0; k + 1 < nbins; k++) {
        w0 += (double)h[k];
        s0 += (double)k * (double)h[k];
        double w1 = n - w0;
        if (w0 == 0 || w1 == 0) continue;
        /* w0 w1 (mu0 - mu1)^2 = (s0 n - sum w0)^2 / (w0 w1) */
        double d = s0 * n - sum * w0, var = d * d / (w0 * w1);
        if (rising ? var > best : var >= best) {
            best = var;
            k_best = (int64_t)k;
        }
    }
    return k_best;
}

bvox_status bvox__otsu_threshold(const bvox__gray *g, double slope, double inter,
                                 const char *name, bool *found, double *threshold)
{
    *found = false;
    hist_ctx c = {.data = g->data, .dt = g->dtype, .swap = g->byteswap};
    c.n = (size_t)g->dims.nx * (size_t)g->dims.ny * (size_t)g->dims.nz;
    size_t size = bvox_dtype_size(g->dtype);
    c.exact = size <= 2 && g->dtype != BVOX_DT_F32 && g->dtype != BVOX_DT_F64;
    c.nbins = c.exact ? (size_t)1 << (8 * size) : 256;
    int64_t threads = bvox__parallelism();
    c.nchunks = (int64_t)(c.n >> 20) + 1; /* about a million samples each */
    if (c.nchunks > threads) c.nchunks = threads;

    bvox_status st = BVOX_OK;
    size_t hist_bytes = (size_t)c.nchunks * c.nbins * sizeof(uint64_t);
    size_t mm_bytes = (size_t)c.nchunks * 2 * sizeof(double);
    c.hist = bvox__alloc(hist_bytes, true, "Otsu histogram", &st);
    if (!c.hist) goto fail;
    c.mn = bvox__alloc(mm_bytes, false, "Otsu histogram", &st);
    if (!c.mn) goto fail;
    c.mx = c.mn + c.nchunks;

    double lo = 0, hi = 0;
    if (!c.exact) {
        bvox__parallel_for(c.nchunks, 1, minmax_range, &c);
        lo = INFINITY;
        hi = -INFINITY;
        for (int64_t k = 0; k < c.nchunks; k++) {
            lo = c.mn[k] < lo ? c.mn[k] : lo;
            hi = c.mx[k] > hi ? c.mx[k] : hi;
        }
        if (!(lo < hi)) goto done; /* no finite value, or only one: no split */
        c.lo = lo / 2;
        c.scale = 256 / (hi / 2 - lo / 2);
    }
    bvox__parallel_for(c.nchunks, 1, hist_range, &c);
    for (int64_t k = 1; k < c.nchunks; k++)
        for (size_t i = 0; i < c.nbins; i++) c.hist[i] += c.hist[(size_t)k * c.nbins + i];

    bool rising = slope > 0;
    int64_t k = best_split(c.hist, c.nbins, rising);
    if (k < 0) goto done;
    double edge_raw;
    if (c.exact) {
        /* rising: the top bin of the lower class; falling: the real order is
         * reversed, so the lower real class is bins k+1.. and its largest real
         * value is at bin k+1 */
        int64_t bin = rising ? k : k + 1;
        bool sgn = g->dtype == BVOX_DT_I8 || g->dtype == BVOX_DT_I16;
        int64_t offset = sgn ? (int64_t)c.nbins / 2 : 0;
        edge_raw = (double)(bin - offset);
    } else {
        edge_raw = lo + (double)(k + 1) * ((hi / 2 - lo / 2) / 128);
    }
    *threshold = bvox__real_value(edge_raw, slope, inter);
    *found = true;
done:
fail:
    if (c.mn) bvox__free(c.mn, mm_bytes);
    if (c.hist) bvox__free(c.hist, hist_bytes);
    if (st) bvox__error_prefix(name);
    return st;
}
