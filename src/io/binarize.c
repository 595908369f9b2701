/*
 * binarize.c — gray volume (typed samples, x fastest) -> binary volume
 * (64 slices per word along z), following the user's bvox_binarize.
 *
 * Two steps:
 *  1. Every mode becomes one predicate on the RAW sample type (see
 *     binarize_kernels.h): an interval [a, b] of raw values, maybe inverted.
 *     Since real = raw * slope + inter is monotone in raw (rounding is
 *     monotone), the raw values whose real value passes a bound form a prefix
 *     or a suffix of the ordered raw values; a binary search over them, with
 *     the very same double arithmetic a per-voxel evaluation would use, finds
 *     the exact ends. So integer bounds, negative slopes, type clamping and
 *     empty ranges all come out right with no special cases, and the inner
 *     loop never converts a sample.
 *  2. Packing, per (y, run of x, block of 64 slices): each of the 64 rows
 *     (one per z) is compared 64 samples at a time into a 64-bit mask (bits =
 *     x); the 64x64 bit matrix (rows = z) is transposed into rows = x, bits =
 *     z, which are exactly the words of 64 columns. Rows beyond nz are zero,
 *     so the tail bits of each column come out zero. Work is split over y and
 *     runs of x with bvox__parallel_for; each piece writes its own columns.
 *     Samples in z-fastest order (NumPy's C order of [x][y][z]) skip the
 *     transpose: a column's samples compare straight into its words.
 */
#include "binarize_kernels.h"

#include <math.h>
#include <string.h>

#define SIGN64 0x8000000000000000ull

void bvox__gray_init(bvox__gray *g)
{
    memset(g, 0, sizeof *g);
    g->slope = 1.0;
    g->geom = bvox_geometry_default();
}

void bvox__gray_release(bvox__gray *g)
{
    if (g->owned) bvox__free(g->owned, g->owned_bytes);
    bvox__gray_init(g);
}

/* ------------------------------------------------ raw values as ordered keys */

/* Every non-NaN raw value has a key (a uint64) such that keys order like the
 * values: unsigned integers are themselves, signed ones have the sign bit
 * flipped, floats use the usual sign-magnitude to ordered mapping. */
typedef struct scale {
    bvox_dtype dt;
    double slope, inter;
} scale;

static bool is_float(bvox_dtype dt) { return dt == BVOX_DT_F32 || dt == BVOX_DT_F64; }
static bool is_signed(bvox_dtype dt)
{
    return dt == BVOX_DT_I8 || dt == BVOX_DT_I16 || dt == BVOX_DT_I32 || dt == BVOX_DT_I64;
}

static void key_range(bvox_dtype dt, uint64_t *kmin, uint64_t *kmax)
{
    unsigned bits = 8 * (unsigned)bvox_dtype_size(dt);
    if (dt == BVOX_DT_F32) {
        *kmin = 0x007FFFFFull; /* -inf */
        *kmax = 0xFF800000ull; /* +inf */
    } else if (dt == BVOX_DT_F64) {
        *kmin = 0x000FFFFFFFFFFFFFull;
        *kmax = 0xFFF0000000000000ull;
    } else if (is_signed(dt)) {
        *kmin = SIGN64 - (1ull << (bits - 1));
        *kmax = SIGN64 + ((1ull << (bits - 1)) - 1);
    } else {
        *kmin = 0;
        *kmax = bits == 64 ? ~0ull : (1ull << bits) - 1;
    }
}

/* The raw bits (at the sample width) of the value with this key. */
static uint64_t key_to_bits(bvox_dtype dt, uint64_t key)
{
    if (dt == BVOX_DT_F32)
        return (key & 0x80000000ull) ? key & 0x7FFFFFFFull : (~key & 0xFFFFFFFFull);
    if (dt == BVOX_DT_F64) return (key & SIGN64) ? key & ~SIGN64 : ~key;
    if (is_signed(dt)) return key ^ SIGN64; /* two's complement of the int64 */
    return key;
}

static double key_to_raw(bvox_dtype dt, uint64_t key)
{
    uint64_t b = key_to_bits(dt, key);
    if (dt == BVOX_DT_F32) {
        uint32_t u = (uint32_t)b;
        float f;
        memcpy(&f, &u, sizeof f);
        return f;
    }
    if (dt == BVOX_DT_F64) {
        double d;
        memcpy(&d, &b, sizeof d);
        return d;
    }
    if (is_signed(dt)) return (double)(int64_t)b;
    return (double)b;
}

enum { OP_GE, OP_GT, OP_LE };

static bool holds(const scale *s, uint64_t key, int op, double v)
{
    double r = bvox__real_value(key_to_raw(s->dt, key), s->slope, s->inter);
    return op == OP_GE ? r >= v : op == OP_GT ? r > v : r <= v;
}

/* Within [lo, hi], where the condition holds on a suffix: its first key. */
static bool suffix_start(const scale *s, int op, double v, uint64_t lo, uint64_t hi,
                         uint64_t *first)
{
    if (!holds(s, hi, op, v)) return false;
    while (lo < hi) { /* invariant: holds at hi */
        uint64_t mid = lo + (hi - lo) / 2;
        if (holds(s, mid, op, v)) hi = mid;
        else lo = mid + 1;
    }
    *first = hi;
    return true;
}

/* Within [lo, hi], where the condition holds on a prefix: its last key. */
static bool prefix_end(const scale *s, int op, double v, uint64_t lo, uint64_t hi,
                       uint64_t *last)
{
    if (!holds(s, lo, op, v)) return false;
    while (lo < hi) { /* invariant: holds at lo */
        uint64_t mid = lo + (hi - lo) / 2 + 1;
        if (holds(s, mid, op, v)) lo = mid;
        else hi = mid - 1;
    }
    *last = lo;
    return true;
}

/* Keys [*ka, *kb] whose real value satisfies `lower_op lower` and (if
 * has_upper) `<= upper`; false if there are none. With slope > 0 the real
 * value rises with the key, so a lower bound holds on a suffix and an upper
 * bound on a prefix; with slope < 0 the other way round. */
static bool key_interval(const scale *s, int lower_op, double lower, bool has_upper,
                         double upper, uint64_t *ka, uint64_t *kb)
{
    uint64_t a, b;
    key_range(s->dt, &a, &b);
    bool rising = s->slope > 0;
    if (rising ? !suffix_start(s, lower_op, lower, a, b, &a)
               : !prefix_end(s, lower_op, lower, a, b, &b))
        return false;
    if (has_upper && (rising ? !prefix_end(s, OP_LE, upper, a, b, &b)
                             : !suffix_start(s, OP_LE, upper, a, b, &a)))
        return false;
    *ka = a;
    *kb = b;
    return true;
}

/* ------------------------------------------------------ mode -> predicate */

typedef enum outcome { ALL_ZERO, ALL_ONE, USE_PRED } outcome;

static bvox_status check_param(double v, const char *what, const char *name)
{
    if (isnan(v))
        return bvox__fail(BVOX_EINVAL, "%s: the %s of the binarisation is NaN", name, what);
    return BVOX_OK;
}

static bvox_status make_predicate(const bvox__gray *g, const bvox_binarize *how,
                                  const scale *s, const char *name, bvox__binpred *p,
                                  outcome *res)
{
    static const bvox__bin_kind kinds[BVOX_DT_COUNT] = {
        BVOX__BK_INT8,  BVOX__BK_INT8,  BVOX__BK_INT16, BVOX__BK_INT16, BVOX__BK_INT32,
        BVOX__BK_INT32, BVOX__BK_INT64, BVOX__BK_INT64, BVOX__BK_F32,   BVOX__BK_F64};
    memset(p, 0, sizeof *p);
    p->kind = kinds[g->dtype];
    p->swap = g->byteswap && bvox_dtype_size(g->dtype) > 1;

    int lower_op = OP_GE;
    double lower = 0, upper = 0;
    bool has_upper = true, invert = false;
    bvox_status st = BVOX_OK;
    switch (how->mode) {
    case BVOX_BIN_NONZERO: invert = true; break; /* not (0 <= real <= 0) */
    case BVOX_BIN_THRESHOLD:
        st = check_param(how->threshold, "threshold", name);
        lower = how->threshold;
        has_upper = false;
        break;
    case BVOX_BIN_RANGE:
        st = check_param(how->lo, "lower bound", name);
        if (!st) st = check_param(how->hi, "upper bound", name);
        lower = how->lo;
        upper = how->hi;
        break;
    case BVOX_BIN_LABEL:
        st = check_param(how->label, "label", name);
        lower = upper = how->label;
        break;
    case BVOX_BIN_OTSU: {
        bool found = false;
        st = bvox__otsu_threshold(g, s->slope, s->inter, name, &found, &lower);
        if (st) return st;
        if (!found) {
            *res = ALL_ZERO;
            return BVOX_OK;
        }
        lower_op = OP_GT;
        has_upper = false;
        break;
    }
    default:
        return bvox__fail(BVOX_EINVAL, "%s: unknown binarisation mode %d", name,
                          (int)how->mode);
    }
    if (st) return st;

    uint64_t ka, kb;
    if (!key_interval(s, lower_op, lower, has_upper, upper, &ka, &kb)) {
        if (!invert) {
            *res = ALL_ZERO;
            return BVOX_OK;
        }
        /* the complement of nothing: every value that is not NaN */
        key_range(g->dtype, &ka, &kb);
        invert = false;
    }
    uint64_t kmin, kmax;
    key_range(g->dtype, &kmin, &kmax);
    if (!is_float(g->dtype) && ka == kmin && kb == kmax) {
        *res = invert ? ALL_ZERO : ALL_ONE;
        return BVOX_OK;
    }
    p->invert = invert;
    if (is_float(g->dtype)) {
        p->fa = key_to_raw(g->dtype, ka);
        p->fb = key_to_raw(g->dtype, kb);
        p->fa32 = (float)p->fa; /* exact: they are f32 values */
        p->fb32 = (float)p->fb;
    } else {
        p->a = key_to_bits(g->dtype, ka);
        p->w = key_to_bits(g->dtype, kb) - p->a; /* mod 2^64, truncated by the kernel */
    }
    *res = USE_PRED;
    return BVOX_OK;
}

/* ----------------------------------------------------------------- packing */

/* A work item covers about 4 KiB of each slice: several whole rows of y
 * when rows are short (then, for nx a multiple of 64, one contiguous run per
 * slice), else a run of x within one row. The 64 slices of a block stream
 * from 64 places while the mask matrix (at most 64 x 64 words) stays in L1. */
#define MAX_XB 64
#define ITEM_BYTES 4096
_Static_assert(ITEM_BYTES / 64 <= MAX_XB, "an item of u8 samples must fit the mask matrix");

typedef struct pack_ctx {
    const unsigned char *data;
    size_t size; /* bytes per sample */
    size_t nx, ny, nz, wpc;
    uint64_t *words;
    bvox__binpred pred;
    bvox__bin_blocks_fn blocks;
    size_t rows_per_item; /* rows of y per item (1 when a row is split) */
    size_t xb_per_item;   /* x-blocks per item and row */
    size_t items_per_row; /* 1 unless a row is split */
} pack_ctx;

static void pack_item(const pack_ctx *c, int64_t item, uint64_t m[MAX_XB][64])
{
    size_t nx = c->nx, ny = c->ny, size = c->size, wpc = c->wpc;
    size_t y0 = (size_t)item / c->items_per_row * c->rows_per_item;
    size_t rows = ny - y0 < c->rows_per_item ? ny - y0 : c->rows_per_item;
    size_t xs = (size_t)item % c->items_per_row * c->xb_per_item * 64;
    size_t width = nx - xs < c->xb_per_item * 64 ? nx - xs : c->xb_per_item * 64;
    size_t nfull = width / 64, tail = width % 64, nxb = nfull + (tail != 0);
    /* whole rows without a tail lie back to back: one run per slice */
    bool contiguous = width == nx && tail == 0;
    /* The row's last partial block is compared from a padded copy. Its bits
     * beyond the row become rows beyond `width` after the transpose, which
     * are never stored, so they need no masking. */
    _Alignas(64) unsigned char pad[64 * 8];

    for (size_t zb = 0; zb < wpc; zb++) {
        size_t z0 = zb * 64;
        size_t zc = c->nz - z0 < 64 ? c->nz - z0 : 64;
        for (size_t z = 0; z < zc; z++) {
            const unsigned char *base = c->data + (((z0 + z) * ny + y0) * nx + xs) * size;
            if (contiguous) {
                c->blocks(base, rows * nfull, &c->pred, &m[0][z], 64);
                continue;
            }
            for (size_t r = 0; r < rows; r++) {
                const unsigned char *row = base + r * nx * size;
                if (nfull) c->blocks(row, nfull, &c->pred, &m[r * nxb][z], 64);
                if (tail) {
                    memcpy(pad, row + nfull * 64 * size, tail * size);
                    memset(pad + tail * size, 0, (64 - tail) * size);
                    c->blocks(pad, 1, &c->pred, &m[r * nxb + nfull][z], 64);
                }
            }
        }
        for (size_t r = 0; r < rows; r++)
            for (size_t xb = 0; xb < nxb; xb++) {
                uint64_t *t = m[r * nxb + xb];
                if (zc < 64) memset(t + zc, 0, (64 - zc) * sizeof(uint64_t));
                bvox__transpose64(t);
                size_t n = xb < nfull ? 64 : tail;
                uint64_t *dst = c->words + ((y0 + r) * nx + xs + xb * 64) * wpc + zb;
                for (size_t i = 0; i < n; i++) dst[i * wpc] = t[i];
            }
    }
}

static void pack_range(void *ctx, int64_t begin, int64_t end)
{
    _Alignas(64) uint64_t m[MAX_XB][64];
    for (int64_t i = begin; i < end; i++) pack_item(ctx, i, m);
}

/* z-fastest samples (g->z_fastest): a column's nz samples are contiguous, so
 * the compare kernel's 64 bits per block are already the column's words (bit
 * i = slice i); no transpose. Item i is the column x = i / ny, y = i % ny. */
static void pack_columns(void *ctx, int64_t begin, int64_t end)
{
    const pack_ctx *c = ctx;
    size_t nz = c->nz, wpc = c->wpc, size = c->size;
    size_t nfull = nz / 64, tail = nz % 64;
    _Alignas(64) unsigned char pad[64 * 8];
    for (int64_t i = begin; i < end; i++) {
        size_t x = (size_t)i / c->ny, y = (size_t)i % c->ny;
        const unsigned char *src = c->data + (size_t)i * nz * size;
        uint64_t *dst = c->words + (y * c->nx + x) * wpc;
        if (nfull) c->blocks(src, nfull, &c->pred, dst, 1);
        if (tail) {
            memcpy(pad, src + nfull * 64 * size, tail * size);
            memset(pad + tail * size, 0, (64 - tail) * size);
            c->blocks(pad, 1, &c->pred, dst + nfull, 1);
            dst[nfull] &= (1ull << tail) - 1; /* the padding may pass the test */
        }
    }
}

static bvox__bin_blocks_fn choose_blocks(void)
{
#if defined(__x86_64__)
    bvox_simd level = bvox_simd_active();
    /* the AVX-512 kernels also need BW (byte and word compares) */
    if (level == BVOX_SIMD_AVX512 && bvox__bin_blocks_avx512 &&
        __builtin_cpu_supports("avx512bw"))
        return bvox__bin_blocks_avx512;
    if (level >= BVOX_SIMD_AVX2 && bvox__bin_blocks_avx2 && __builtin_cpu_supports("avx2"))
        return bvox__bin_blocks_avx2;
#endif
    return bvox__bin_blocks_generic;
}

bvox_status bvox__binarize_setup(const bvox__gray *g, const bvox_binarize *how,
                                 const char *name, bvox__binpred *pred, bool *use_pred,
                                 bvox__bin_blocks_fn *blocks, bvox_volume **out)
{
    static const bvox_binarize nonzero = {BVOX_BIN_NONZERO, 0, 0, 0, 0};
    *out = NULL;
    if (!name) name = "volume";
    if (!how) how = &nonzero;
    if (!g || (unsigned)g->dtype >= BVOX_DT_COUNT)
        return bvox__fail(BVOX_EINVAL, "%s: invalid sample type", name);
    size_t bytes;
    bvox_status st = bvox__check_dims(g->dims, name, &bytes);
    if (st) return st;
    if (!g->data && how->mode == BVOX_BIN_OTSU) /* Otsu's histogram needs every sample */
        return bvox__fail(BVOX_EINVAL, "%s: no sample data", name);
    if (!isfinite(g->slope) || !isfinite(g->inter))
        return bvox__fail(BVOX_EFORMAT, "%s: the intensity scaling (slope %g, intercept %g) is "
                          "not finite", name, g->slope, g->inter);
    scale s = {g->dtype, g->slope == 0 ? 1.0 : g->slope, g->inter};

    outcome res = ALL_ZERO;
    st = make_predicate(g, how, &s, name, pred, &res);
    if (st) return st;

    bvox_volume *v;
    st = res == USE_PRED ? bvox__volume_create_uninit(g->dims, &v)
                         : bvox_volume_create(g->dims, &v);
    if (st) {
        bvox__error_prefix(name);
        return st;
    }
    st = bvox_volume_set_geometry(v, &g->geom);
    if (st) {
        bvox_volume_destroy(v);
        bvox__error_prefix(name);
        return BVOX_EFORMAT;
    }
    if (res == ALL_ONE) bvox_volume_fill(v, 1);
    *use_pred = res == USE_PRED;
    *blocks = choose_blocks();
    *out = v;
    return BVOX_OK;
}

bvox_status bvox__binarize(const bvox__gray *g, const bvox_binarize *how, const char *name,
                           bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "volume";
    if (g && !g->data) return bvox__fail(BVOX_EINVAL, "%s: no sample data", name);
    bvox__binpred pred;
    bool use_pred = false;
    bvox__bin_blocks_fn blocks = NULL;
    bvox_volume *v;
    bvox_status st = bvox__binarize_setup(g, how, name, &pred, &use_pred, &blocks, &v);
    if (st) return st;
    if (use_pred) {
        pack_ctx c = {.data = g->data, .size = bvox_dtype_size(g->dtype),
                      .nx = (size_t)v->nx, .ny = (size_t)v->ny, .nz = (size_t)v->nz,
                      .wpc = v->wpc, .words = v->words, .pred = pred,
                      .blocks = blocks};
        if (g->z_fastest) {
            st = bvox__parallel_for_progress((int64_t)(c.nx * c.ny),
                                             ((int64_t)1 << 20) / (int64_t)c.nz + 1, pack_columns,
                                             &c);
            if (st) {
                bvox_volume_destroy(v);
                return st;
            }
            *out = v;
            return BVOX_OK;
        }
        size_t nxb = (c.nx + 63) / 64, per_item = ITEM_BYTES / (64 * c.size);
        if (nxb <= per_item) {
            c.rows_per_item = per_item / nxb;
            c.xb_per_item = nxb;
            c.items_per_row = 1;
        } else {
            c.rows_per_item = 1;
            c.xb_per_item = per_item;
            c.items_per_row = (nxb + per_item - 1) / per_item;
        }
        int64_t items = (int64_t)((c.ny + c.rows_per_item - 1) / c.rows_per_item *
                                  c.items_per_row);
        /* a thread is worth starting for about a million samples */
        int64_t item_samples = (int64_t)(c.rows_per_item * c.xb_per_item * 64 * c.nz);
        st = bvox__parallel_for_progress(items, ((int64_t)1 << 20) / item_samples + 1, pack_range,
                                         &c);
        if (st) {
            bvox_volume_destroy(v);
            return st;
        }
    }
    *out = v;
    return BVOX_OK;
}
