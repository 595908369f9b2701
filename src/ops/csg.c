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
    const struct z_plan *plan;
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


/* The z offset is the same for every column, so where each dst word's
 * source bits come from is worked out once per call (the plan), and a row
 * is then a tight loop over its columns: with 4 words a column (256^3) the
 * per-column bookkeeping of a general loop cost more than the words.
 *  - words [k0, k1): every bit from src, word q + k (and q + k + 1 when the
 *    shift s is not 0), no mask;
 *  - at most two edge words partly inside the footprint: explicit source
 *    words (or -1: none) and the footprint mask fp;
 *  - the other words get no source bits (only intersection changes them). */
typedef struct z_edge {
    size_t k;         /* dst word */
    int64_t w0, w1;   /* source words for the low/high part, -1: none */
    uint64_t fp;      /* footprint bits in this dst word */
} z_edge;

typedef struct z_plan {
    size_t k0, k1;   /* interior dst words */
    int64_t q;       /* source word of dst word k is q + k (+1) */
    unsigned s;      /* bit shift */
    int nedges;
    z_edge edge[2];
    size_t out0, out1; /* dst words [0, out0) and [out1, wpc) outside the footprint */
} z_plan;

static void plan_z(const bvox_volume *d, const bvox_volume *src, int32_t oz, z_plan *p)
{
    memset(p, 0, sizeof *p);
    int64_t fz0 = oz > 0 ? oz : 0;
    int64_t fz1 = (int64_t)oz + src->nz < d->nz ? (int64_t)oz + src->nz : d->nz;
    int64_t sh = -(int64_t)oz; /* dst bit z reads src bit z + sh */
    p->q = sh >> 6;            /* floor */
    p->s = (unsigned)(sh & 63);
    if (fz0 >= fz1) { /* no overlap in z: every word is outside */
        p->out0 = p->out1 = d->wpc;
        return;
    }
    p->k0 = (size_t)((fz0 + 63) >> 6);
    p->k1 = (size_t)(fz1 >> 6);
    if (p->k1 < p->k0) p->k1 = p->k0; /* footprint inside one word */
    p->out0 = (size_t)(fz0 >> 6);
    p->out1 = (size_t)((fz1 + 63) >> 6);
    for (size_t k = p->out0; k < p->out1; k++) {
        if (k >= p->k0 && k < p->k1) continue;
        int64_t z0 = (int64_t)k * 64, lo = fz0 - z0, hi = fz1 - z0;
        z_edge *e = &p->edge[p->nedges++];
        e->k = k;
        e->fp = bvox__bit_range(lo < 0 ? 0 : (unsigned)lo, hi > 64 ? 64 : (unsigned)hi);
        int64_t w = (int64_t)k + p->q;
        e->w0 = w >= 0 && w < (int64_t)src->wpc ? w : -1;
        e->w1 = p->s && w + 1 >= 0 && w + 1 < (int64_t)src->wpc ? w + 1 : -1;
    }
}

static inline uint64_t edge_bits(const z_plan *p, const z_edge *e, const uint64_t *sc)
{
    uint64_t lo = e->w0 >= 0 ? sc[e->w0] >> p->s : 0;
    uint64_t hi = e->w1 >= 0 ? sc[e->w1] << (64 - p->s) : 0;
    return (lo | hi) & e->fp; /* src tail bits are zero; fp cuts what lies beyond dst */
}

/* Columns x0..x1-1 of dst row dr, under src columns starting at sr; fp_ is
 * the footprint of the word (all ones inside), for REPLACE. */
#define ROW_LOOP(expr)                                                                 \
    for (int32_t x = x0; x < x1; x++) {                                                \
        uint64_t *restrict dc = dr + (size_t)x * dwpc;                                 \
        const uint64_t *restrict sc = sr + (size_t)(x - x0) * swpc;                    \
        if (p->s == 0)                                                                 \
            for (size_t k = p->k0; k < p->k1; k++) {                                   \
                uint64_t d_ = dc[k], s_ = sc[(int64_t)k + p->q], fp_ = ~0ull;          \
                (void)fp_;                                                             \
                dc[k] = (expr);                                                        \
            }                                                                          \
        else                                                                           \
            for (size_t k = p->k0; k < p->k1; k++) {                                   \
                int64_t w_ = (int64_t)k + p->q;                                        \
                uint64_t d_ = dc[k], s_ = (sc[w_] >> p->s) | (sc[w_ + 1] << (64 - p->s)); \
                uint64_t fp_ = ~0ull; /* interior: every bit is in the footprint */    \
                (void)fp_;                                                             \
                dc[k] = (expr);                                                        \
            }                                                                          \
        for (int e_ = 0; e_ < p->nedges; e_++) {                                       \
            const z_edge *e = &p->edge[e_];                                            \
            uint64_t d_ = dc[e->k], s_ = edge_bits(p, e, sc), fp_ = e->fp;             \
            (void)fp_;                                                                 \
            dc[e->k] = (expr);                                                         \
        }                                                                              \
        if (intersect) {                                                               \
            for (size_t k = 0; k < p->out0; k++) dc[k] = 0;                            \
            for (size_t k = p->out1; k < dwpc; k++) dc[k] = 0;                         \
        }                                                                              \
    }

static void row_segment(bvox_csg_op op, const z_plan *p, uint64_t *dr, size_t dwpc,
                        const uint64_t *sr, size_t swpc, int32_t x0, int32_t x1)
{
    int intersect = 0;
    switch (op) {
    case BVOX_CSG_UNION: ROW_LOOP(d_ | s_); break;
    case BVOX_CSG_DIFFERENCE: ROW_LOOP(d_ & ~s_); break;
    case BVOX_CSG_XOR: ROW_LOOP(d_ ^ s_); break;
    case BVOX_CSG_INTERSECTION:
        intersect = 1;
        ROW_LOOP(d_ & s_);
        break;
    case BVOX_CSG_REPLACE: ROW_LOOP((d_ & ~fp_) | s_); break;
    }
}

/* Rows begin..end-1 of dst: columns under src are combined with the shifted
 * src column; columns outside src's footprint see src = 0. */
static void shifted_rows(void *ctx, int64_t begin, int64_t end)
{
    csg_job *j = ctx;
    bvox_volume *d = j->dst;
    const bvox_volume *s = j->src;
    const z_plan *p = j->plan;
    int64_t xa = j->ox > 0 ? j->ox : 0;
    int64_t xb = (int64_t)j->ox + s->nx < d->nx ? (int64_t)j->ox + s->nx : d->nx;
    for (int64_t y = begin; y < end; y++) {
        int64_t sy = y - j->oy;
        uint64_t *dr = bvox__column(d, 0, (int32_t)y);
        bool under = sy >= 0 && sy < s->ny && xa < xb && p->out0 < p->out1;
        if (!under) {
            if (j->op == BVOX_CSG_INTERSECTION) memset(dr, 0, (size_t)d->nx * d->wpc * 8);
            continue;
        }
        if (j->op == BVOX_CSG_INTERSECTION) {
            memset(dr, 0, (size_t)xa * d->wpc * 8);
            memset(dr + (size_t)xb * d->wpc, 0, (size_t)(d->nx - xb) * d->wpc * 8);
        }
        const uint64_t *sr = bvox__column_c(s, (int32_t)(xa - j->ox), (int32_t)sy);
        row_segment(j->op, p, dr, d->wpc, sr, s->wpc, (int32_t)xa, (int32_t)xb);
    }
}

bvox_status bvox_csg_apply(bvox_volume *dst, bvox_csg_op op, const bvox_volume *src,
                           const int32_t offset[3])
{
    BVOX_CHECK_VOLUME(dst);
    BVOX_CHECK_VOLUME(src);
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
    csg_job j = {dst, src, op, o[0], o[1], o[2], NULL, NULL};
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
        z_plan plan;
        plan_z(dst, src, o[2], &plan);
        j.plan = &plan;
        bvox__parallel_for(dst->ny, 16, shifted_rows, &j);
    }
    bvox_volume_destroy(tmp);
    BVOX_CHECK_VOLUME(dst);
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
    BVOX_CHECK_VOLUME(vol); /* the tail bits beyond nz stayed zero */
}
