/*
 * csg.c — set operations between two volumes on whole words: union,
 * intersection, difference, xor, replace, with the second volume placed at an
 * offset; and the complement. Same-sized volumes with no offset take one
 * SIMD kernel over the whole word array, split over the threads; otherwise
 * each column of src is shifted along z 64 bits at a time (extract_bits).
 */
#include "internal.h"

#include <string.h>

typedef struct csg_job {
    bvox_volume *dst;
    const bvox_volume *src;
    bvox_csg_op op;
    int32_t ox, oy, oz;
    void (*kernel)(uint64_t *, const uint64_t *, size_t);
} csg_job;

#define CSG_CHUNK 32768 /* words per unit of work in the flat case */

static void flat_range(void *ctx, int64_t begin, int64_t end)
{
    csg_job *j = ctx;
    size_t n = j->dst->nwords;
    size_t w0 = (size_t)begin * CSG_CHUNK;
    size_t w1 = (size_t)end * CSG_CHUNK < n ? (size_t)end * CSG_CHUNK : n;
    if (j->kernel) j->kernel(j->dst->words + w0, j->src->words + w0, w1 - w0);
    else memcpy(j->dst->words + w0, j->src->words + w0, (w1 - w0) * sizeof(uint64_t));
}

static inline uint64_t combine(bvox_csg_op op, uint64_t d, uint64_t s, uint64_t footprint)
{
    switch (op) {
    case BVOX_CSG_UNION: return d | s;
    case BVOX_CSG_INTERSECTION: return d & s;
    case BVOX_CSG_DIFFERENCE: return d & ~s;
    case BVOX_CSG_XOR: return d ^ s;
    case BVOX_CSG_REPLACE: return (d & ~footprint) | s;
    }
    return d;
}

/* dst words k0..k1-1 OP= the source bits starting at 64k + sh, all of them
 * inside src. */
#define INTERIOR_LOOP(expr)                                                            \
    do {                                                                               \
        if (s == 0)                                                                    \
            for (size_t k = k0; k < k1; k++) {                                         \
                uint64_t d_ = dc[k], s_ = sc[(int64_t)k + q];                          \
                dc[k] = (expr);                                                        \
            }                                                                          \
        else                                                                           \
            for (size_t k = k0; k < k1; k++) {                                         \
                int64_t w_ = (int64_t)k + q;                                           \
                uint64_t d_ = dc[k], s_ = (sc[w_] >> s) | (sc[w_ + 1] << (64 - s));    \
                dc[k] = (expr);                                                        \
            }                                                                          \
    } while (0)

static void interior(bvox_csg_op op, uint64_t *restrict dc, const uint64_t *restrict sc,
                     size_t k0, size_t k1, int64_t sh)
{
    int64_t q = sh >> 6; /* floor */
    unsigned s = (unsigned)(sh & 63);
    switch (op) {
    case BVOX_CSG_UNION: INTERIOR_LOOP(d_ | s_); break;
    case BVOX_CSG_INTERSECTION: INTERIOR_LOOP(d_ & s_); break;
    case BVOX_CSG_DIFFERENCE: INTERIOR_LOOP(d_ & ~s_); break;
    case BVOX_CSG_XOR: INTERIOR_LOOP(d_ ^ s_); break;
    case BVOX_CSG_REPLACE: INTERIOR_LOOP(((void)d_, s_)); break;
    }
}

/* One dst row y: columns under src are combined with the shifted src column;
 * columns outside src's footprint see src = 0. */
static void shifted_rows(void *ctx, int64_t begin, int64_t end)
{
    csg_job *j = ctx;
    bvox_volume *d = j->dst;
    const bvox_volume *s = j->src;
    /* z range of dst covered by src, as a per-word footprint mask */
    int64_t fz0 = j->oz > 0 ? j->oz : 0;
    int64_t fz1 = (int64_t)j->oz + s->nz < d->nz ? (int64_t)j->oz + s->nz : d->nz;
    for (int64_t y = begin; y < end; y++) {
        int64_t sy = y - j->oy;
        for (int32_t x = 0; x < d->nx; x++) {
            int64_t sx = (int64_t)x - j->ox; /* int32 - INT32_MIN overflows int */
            uint64_t *dc = bvox__column(d, x, (int32_t)y);
            bool under = sy >= 0 && sy < s->ny && sx >= 0 && sx < s->nx && fz0 < fz1;
            if (!under) {
                if (j->op == BVOX_CSG_INTERSECTION) memset(dc, 0, d->wpc * sizeof(uint64_t));
                continue;
            }
            const uint64_t *sc = bvox__column_c(s, (int32_t)sx, (int32_t)sy);
            /* Words wholly inside the footprint, k0 <= k < k1: every bit
             * comes from src, no mask, no bounds check, the op chosen once
             * (most of a column). The (at most two) others below. */
            size_t k0 = (size_t)((fz0 + 63) >> 6), k1 = (size_t)(fz1 >> 6);
            bool inner = k1 > k0;
            if (inner) interior(j->op, dc, sc, k0, k1, -(int64_t)j->oz);
            for (size_t k = 0; k < d->wpc; k++) {
                if (inner && k == k0) {
                    k = k1 - 1;
                    continue;
                }
                int64_t z0 = (int64_t)k * 64;
                int64_t lo = fz0 - z0, hi = fz1 - z0;
                uint64_t fp = (lo >= 64 || hi <= 0)
                                  ? 0
                                  : bvox__bit_range(lo < 0 ? 0 : (unsigned)lo,
                                                    hi > 64 ? 64 : (unsigned)hi);
                /* src tail bits are zero, and fp masks the part beyond dst */
                uint64_t sw = bvox__extract_bits(sc, s->wpc, z0 - j->oz) & fp;
                dc[k] = combine(j->op, dc[k], sw, fp);
            }
        }
    }
}

bvox_status bvox_csg_apply(bvox_volume *dst, bvox_csg_op op, const bvox_volume *src,
                           const int32_t offset[3])
{
    if ((unsigned)op > BVOX_CSG_REPLACE) return bvox__fail(BVOX_EINVAL, "unknown set operation");
    int32_t o[3] = {0, 0, 0};
    if (offset) memcpy(o, offset, sizeof o);
    if (src == dst && !o[0] && !o[1] && !o[2]) {
        /* a OP a: the kernels take restrict pointers, so answer directly */
        if (op == BVOX_CSG_DIFFERENCE || op == BVOX_CSG_XOR) bvox_volume_fill(dst, 0);
        return BVOX_OK;
    }
    bvox_volume *tmp = NULL;
    if (src == dst) { /* shifted self-operation: work from a copy */
        bvox_status st = bvox_volume_copy(src, &tmp);
        if (st) return st;
        src = tmp;
    }
    csg_job j = {dst, src, op, o[0], o[1], o[2], NULL};
    if (!o[0] && !o[1] && !o[2] && src->nx == dst->nx && src->ny == dst->ny &&
        src->nz == dst->nz) {
        const bvox__kernels *k = bvox__simd();
        switch (op) {
        case BVOX_CSG_UNION: j.kernel = k->op_or; break;
        case BVOX_CSG_INTERSECTION: j.kernel = k->op_and; break;
        case BVOX_CSG_DIFFERENCE: j.kernel = k->op_andnot; break;
        case BVOX_CSG_XOR: j.kernel = k->op_xor; break;
        case BVOX_CSG_REPLACE: j.kernel = NULL; break;
        }
        int64_t chunks = (int64_t)((dst->nwords + CSG_CHUNK - 1) / CSG_CHUNK);
        bvox__parallel_for(chunks, 4, flat_range, &j);
    } else {
        bvox__parallel_for(dst->ny, 16, shifted_rows, &j);
    }
    bvox_volume_destroy(tmp);
    return BVOX_OK;
}

static void complement_range(void *ctx, int64_t begin, int64_t end)
{
    bvox_volume *v = ctx;
    size_t w0 = (size_t)begin * CSG_CHUNK;
    size_t w1 = (size_t)end * CSG_CHUNK < v->nwords ? (size_t)end * CSG_CHUNK : v->nwords;
    bvox__simd()->op_not(v->words + w0, w1 - w0);
    if (v->tail_mask == ~0ull) return;
    /* keep the invariant: bits beyond nz stay zero */
    size_t first = w0 / v->wpc * v->wpc + v->wpc - 1;
    for (size_t c = first; c < w1; c += v->wpc)
        if (c >= w0) v->words[c] &= v->tail_mask;
}

void bvox_volume_complement(bvox_volume *vol)
{
    int64_t chunks = (int64_t)((vol->nwords + CSG_CHUNK - 1) / CSG_CHUNK);
    bvox__parallel_for(chunks, 4, complement_range, vol);
}
