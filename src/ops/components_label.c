/*
 * components_label.c — runs of column groups (components_label.h) joined by
 * a union-find, word by word.
 *
 * Which neighbour groups touch, and how (z-diagonal steps widen by one):
 *   g = 1, 6:  columns (x-1, y), (x, y-1)                        exact overlap
 *   g = 1, 18: the same two, widened; (x-1, y-1), (x+1, y-1)     exact overlap
 *   g = 2, 26: groups (X-1, Y), (X, Y-1) through the two facing columns of
 *              each (ORed: every column of one side touches every column of
 *              the other), (X-1, Y-1) and (X+1, Y-1) through the two corner
 *              columns; all widened.
 *
 * Single columns A, B (g = 1), with S = run starts, E = run ends and O = A & B:
 *   - every pair of runs that overlap meets in exactly one run of O; its
 *     first bit p is a run start of O;
 *   - a pair that touches only diagonally has A ending at p and B starting
 *     at p + 1 (EA & SB >> 1), or B ending at p - 1 and A starting at p.
 * The run of A containing bit p is number popcount(SA up to p) - 1 of the
 * column, so each contact costs a few popcounts and one union.
 *
 * Groups (g = 2): the runs are those of the ORs UA, UB; the contacts are
 * between the facing columns a (in UA) and b (in UB). A pair (p in a, q in b,
 * |p - q| <= 1) joins run(UA, p) with run(UB, q):
 *   - q = p: within a segment between two consecutive starts of UA or UB,
 *     every p of a & b names the same pair, so only the first one of each
 *     segment is joined. It is found for all segments at once by an
 *     addition: with e = a & b and r = the starts, ~e + (r & ~e) carries from
 *     each start through the non-e bits and stops on the first e bit after
 *     it (r & e are first bits themselves); the carry out of bit 63 is a
 *     segment still looking for its first bit in the next word;
 *   - q = p + 1 only where p is not in b and p + 1 not in a (otherwise the
 *     same pair also has q = p at p or at p + 1), and q = p - 1 likewise:
 *     these are rare, each joined on its own.
 *
 * Threads: rows of groups are split into one slab per thread; each slab's
 * runs are a contiguous index range, and a slab joins only its own groups
 * (union by smaller index keeps every write inside the slab). Then one pass
 * joins each slab's first row to the row before it.
 *
 * Two copies of the row loop (and of the run counting): without -mpopcnt (the library is built for any
 * x86-64) __builtin_popcountll is a library call, which took a third of the
 * time; the popcnt copy is used when the CPU has it (every CPU with AVX2
 * does), chosen through the SIMD level so tests can force either. The run
 * counting of 2 x 2 groups has a third, AVX-512 copy
 * (components_label_avx512.c).
 */
#include "ops/components_label.h"

#include <stdlib.h>
#include <string.h>

#define ALWAYS_INLINE static inline __attribute__((always_inline))

/* Bits 0..p of a word. */
ALWAYS_INLINE uint64_t upto(unsigned p) { return ~0ull >> (63 - p); }

/* Popcount in the kernels: the instruction in the popcnt copies (hw). */
#define PC(w) (hw ? (uint32_t)__builtin_popcountll(w) : (uint32_t)bvox__popcount64(w))

typedef struct labeller {
    const bvox__labelruns *R;
    const uint64_t *zero; /* wpc zero words: a column outside the volume */
    uint32_t *parent;
    int conn;
    int64_t nslabs;
} labeller;

/* ---- g = 1: single columns (6, 18) ---- */

/* Union every run of column ca with the runs of column cb that touch it;
 * widen: z-diagonal contacts count too. */
ALWAYS_INLINE void join_columns(const labeller *L, size_t ca, size_t cb, int widen, int hw)
{
    const bvox__labelruns *R = L->R;
    const uint64_t *A = R->words + ca * R->wpc, *B = R->words + cb * R->wpc;
    uint32_t ia = R->grp_start[ca], ib = R->grp_start[cb]; /* first run not yet passed */
    if (ia == R->grp_start[ca + 1] || ib == R->grp_start[cb + 1]) return;
    uint32_t *parent = L->parent;
    size_t wpc = R->wpc;
    if (!widen) {
        /* face contacts only: none unless the columns overlap somewhere, the
         * rule in sparse sets (the cavity voxels of a coin toss, 1 %, overlap
         * in one pair of columns in twenty), found by one AND per word */
        uint64_t any = 0;
        for (size_t k = 0; k < wpc; k++) any |= A[k] & B[k];
        if (!any) return;
    }
    uint64_t a_hi = 0, b_hi = 0, o_hi = 0, eb_hi = 0; /* bit 63 of the previous word */
    for (size_t k = 0; k < wpc; k++) {
        uint64_t a = A[k], b = B[k];
        if (!(a | b)) {
            /* nothing here (sparse background): no run goes on */
            a_hi = b_hi = o_hi = eb_hi = 0;
            continue;
        }
        uint64_t sa = bvox__run_starts(a, a_hi), sb = bvox__run_starts(b, b_hi);
        uint64_t o = a & b;
        uint64_t contacts = bvox__run_starts(o, o_hi);
        uint64_t diag_next = 0;
        if (widen) {
            uint64_t a_next = k + 1 < wpc ? A[k + 1] & 1 : 0;
            uint64_t b_next = k + 1 < wpc ? B[k + 1] & 1 : 0;
            uint64_t ea = a & ~((a >> 1) | (a_next << 63));
            uint64_t eb = b & ~((b >> 1) | (b_next << 63));
            uint64_t sb_next = b_next & ~(b >> 63); /* B starts at bit 0 of word k + 1 */
            contacts |= sa & ((eb << 1) | eb_hi);   /* B ended at p - 1, A starts at p */
            diag_next = ea & ((sb >> 1) | (sb_next << 63)); /* A ends at p, B starts at p + 1 */
            eb_hi = eb >> 63;
        }
        for (uint64_t c = contacts; c; c &= c - 1) {
            unsigned p = (unsigned)__builtin_ctzll(c);
            uint64_t m = upto(p);
            bvox__uf_unite(parent, ia + PC(sa & m) - 1, ib + PC(sb & m) - 1);
        }
        for (uint64_t c = diag_next; c; c &= c - 1) {
            unsigned p = (unsigned)__builtin_ctzll(c);
            uint64_t m = upto(p);
            bvox__uf_unite(parent, ia + PC(sa & m) - 1, ib + PC(sb & m));
        }
        ia += PC(sa);
        ib += PC(sb);
        a_hi = a >> 63;
        b_hi = b >> 63;
        o_hi = o >> 63;
    }
}

/* Join column (x, y) with its earlier neighbours: (x-1, y) always, the row
 * y-1 when with_prev_row. */
ALWAYS_INLINE void join_column(const labeller *L, size_t x, size_t y, int with_prev_row, int hw)
{
    const bvox__labelruns *R = L->R;
    size_t nx = R->nx, col = y * nx + x;
    if (R->grp_start[col] == R->grp_start[col + 1]) return;
    int face_widen = L->conn != 6;
    if (x > 0) join_columns(L, col, col - 1, face_widen, hw);
    if (!with_prev_row) return;
    join_columns(L, col, col - nx, face_widen, hw);
    if (L->conn == 6) return;
    if (x > 0) join_columns(L, col, col - nx - 1, 0, hw);
    if (x + 1 < nx) join_columns(L, col, col - nx + 1, 0, hw);
}

/* ---- g = 2: groups of 2 x 2 columns (26) ---- */

/* The first bit of e in each segment that begins at a bit of r (see the
 * header comment); *carry: a segment from an earlier word still open. */
ALWAYS_INLINE uint64_t first_in_segments(uint64_t e, uint64_t r, uint64_t *carry)
{
    uint64_t ne = ~e, rn = r & ne;
    uint64_t sum = ne + rn;
    uint64_t c1 = sum < ne;
    uint64_t sum2 = sum + *carry;
    uint64_t c2 = sum2 < sum;
    *carry = c1 | c2;
    return (r & e) | (sum2 & e);
}

/* Join the runs of group A (ORs UA, first run ia) with those of group B
 * touching them through the facing columns a = A0 | A1 and b = B0 | B1. */
ALWAYS_INLINE void join_pair(const labeller *L, size_t ga, size_t gb, const uint64_t *A0,
                             const uint64_t *A1, const uint64_t *B0, const uint64_t *B1, int hw)
{
    const bvox__labelruns *R = L->R;
    uint32_t ia = R->grp_start[ga], ib = R->grp_start[gb];
    if (ib == R->grp_start[gb + 1]) return;
    const uint64_t *UA = R->uw + ga * R->wpc, *UB = R->uw + gb * R->wpc;
    uint32_t *parent = L->parent;
    size_t wpc = R->wpc;
    uint64_t ua_hi = 0, ub_hi = 0, a_prev = 0, b_prev = 0, carry = 0;
    uint64_t a = A0[0] | A1[0], b = B0[0] | B1[0];
    for (size_t k = 0; k < wpc; k++) {
        uint64_t ua = UA[k], ub = UB[k];
        uint64_t an = 0, bn = 0, sb_next = 0; /* bit 0 of word k + 1 */
        if (!(ua | ub)) {
            /* nothing here: no run goes on, no segment stays open */
            ua_hi = ub_hi = a_prev = b_prev = carry = 0;
            if (k + 1 < wpc) a = A0[k + 1] | A1[k + 1], b = B0[k + 1] | B1[k + 1];
            continue;
        }
        if (k + 1 < wpc) {
            an = A0[k + 1] | A1[k + 1];
            bn = B0[k + 1] | B1[k + 1];
            sb_next = UB[k + 1] & 1 & ~(ub >> 63);
        }
        uint64_t sa = bvox__run_starts(ua, ua_hi), sb = bvox__run_starts(ub, ub_hi);
        uint64_t f = first_in_segments(a & b, sa | sb, &carry);
        for (; f; f &= f - 1) {
            unsigned p = (unsigned)__builtin_ctzll(f);
            uint64_t m = upto(p);
            bvox__uf_unite(parent, ia + PC(sa & m) - 1, ib + PC(sb & m) - 1);
        }
        uint64_t only_a = a & ~b;
        /* q = p + 1: p not in b, p + 1 in b and not in a */
        uint64_t up = only_a & ((b >> 1) | (bn << 63)) & ~((a >> 1) | (an << 63));
        for (; up; up &= up - 1) {
            unsigned p = (unsigned)__builtin_ctzll(up);
            uint64_t m = upto(p);
            uint32_t starts_q = PC(sb & m) + (uint32_t)(p < 63 ? (sb >> (p + 1)) & 1 : sb_next);
            bvox__uf_unite(parent, ia + PC(sa & m) - 1, ib + starts_q - 1);
        }
        /* q = p - 1: p not in b, p - 1 in b and not in a */
        uint64_t down = only_a & ((b << 1) | b_prev) & ~((a << 1) | a_prev);
        for (; down; down &= down - 1) {
            unsigned p = (unsigned)__builtin_ctzll(down);
            uint64_t m = upto(p);
            bvox__uf_unite(parent, ia + PC(sa & m) - 1, ib + PC(sb & (m >> 1)) - 1);
        }
        ia += PC(sa);
        ib += PC(sb);
        ua_hi = ua >> 63;
        ub_hi = ub >> 63;
        a_prev = a >> 63;
        b_prev = b >> 63;
        a = an;
        b = bn;
    }
}

ALWAYS_INLINE const uint64_t *col_or_zero(const labeller *L, size_t x, size_t y)
{
    const bvox__labelruns *R = L->R;
    return x < R->nx && y < R->ny ? R->words + (y * R->nx + x) * R->wpc : L->zero;
}

/* Join group (X, Y) with its earlier neighbours: (X-1, Y) always, the row
 * Y-1 when with_prev_row. */
ALWAYS_INLINE void join_group(const labeller *L, size_t X, size_t Y, int with_prev_row, int hw)
{
    const bvox__labelruns *R = L->R;
    size_t gx = R->gx, grp = Y * gx + X;
    if (R->grp_start[grp] == R->grp_start[grp + 1]) return;
    size_t x0 = 2 * X, x1 = x0 + 1, y0 = 2 * Y, y1 = y0 + 1;
    const uint64_t *z = L->zero;
    if (X > 0)
        join_pair(L, grp, grp - 1, col_or_zero(L, x0, y0), col_or_zero(L, x0, y1),
                  col_or_zero(L, x0 - 1, y0), col_or_zero(L, x0 - 1, y1), hw);
    if (!with_prev_row) return;
    join_pair(L, grp, grp - gx, col_or_zero(L, x0, y0), col_or_zero(L, x1, y0),
              col_or_zero(L, x0, y0 - 1), col_or_zero(L, x1, y0 - 1), hw);
    if (X > 0)
        join_pair(L, grp, grp - gx - 1, col_or_zero(L, x0, y0), z, col_or_zero(L, x0 - 1, y0 - 1),
                  z, hw);
    if (x1 + 1 < R->nx)
        join_pair(L, grp, grp - gx + 1, col_or_zero(L, x1, y0), z, col_or_zero(L, x1 + 1, y0 - 1),
                  z, hw);
}

ALWAYS_INLINE void rows_body(const labeller *L, size_t y0, size_t y1, int first_with_prev, int hw)
{
    size_t n = L->R->g == 2 ? L->R->gx : L->R->nx;
    for (size_t y = y0; y < y1; y++)
        for (size_t x = 0; x < n; x++) {
            if (L->R->g == 2) join_group(L, x, y, y > y0 || first_with_prev, hw);
            else join_column(L, x, y, y > y0 || first_with_prev, hw);
        }
}

/* Join rows y0..y1-1 (of groups), the first of them with the row before it
 * when first_with_prev. */
static void label_rows_portable(const labeller *L, size_t y0, size_t y1, int first_with_prev)
{
    rows_body(L, y0, y1, first_with_prev, 0);
}
#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("popcnt"))) static void label_rows_popcnt(const labeller *L, size_t y0,
                                                                size_t y1, int first_with_prev)
{
    rows_body(L, y0, y1, first_with_prev, 1);
}
#endif

static void label_rows(const labeller *L, size_t y0, size_t y1, int first_with_prev)
{
#if defined(__x86_64__) || defined(__i386__)
    if (bvox_simd_active() != BVOX_SIMD_GENERIC) {
        label_rows_popcnt(L, y0, y1, first_with_prev);
        return;
    }
#endif
    label_rows_portable(L, y0, y1, first_with_prev);
}

static size_t slab_row(const labeller *L, int64_t s)
{
    return (size_t)s * L->R->gy / (size_t)L->nslabs;
}

static void label_slabs(void *ctx, int64_t begin, int64_t end)
{
    const labeller *L = ctx;
    size_t gx = L->R->gx;
    for (int64_t s = begin; s < end; s++) {
        size_t y0 = slab_row(L, s), y1 = slab_row(L, s + 1);
        uint32_t r0 = L->R->grp_start[y0 * gx], r1 = L->R->grp_start[y1 * gx];
        for (uint32_t i = r0; i < r1; i++) L->parent[i] = i;
        label_rows(L, y0, y1, 0);
    }
}

/* ---- the ORs of the groups and their run counts ---- */

typedef struct count_ctx {
    bvox__labelruns *R;
    const uint64_t *src; /* the words to label; R->words is their copy when they differ */
    uint32_t *counts;    /* per group, shifted by one: counts[grp + 1] */
} count_ctx;

/* The group's columns copied from src into R->words when that is a copy. */
static void copy_group(const count_ctx *c, size_t grp)
{
    bvox__labelruns *R = c->R;
    if (c->src == R->words) return;
    size_t g = (size_t)R->g, wpc = R->wpc;
    for (size_t j = 0; j < g; j++)
        for (size_t i = 0; i < g; i++) {
            const uint64_t *col = bvox__labelruns_column(R, grp, i, j);
            if (!col) continue;
            size_t off = (size_t)(col - R->words);
            memcpy((uint64_t *)R->words + off, c->src + off, wpc * sizeof *col);
        }
}

ALWAYS_INLINE void count_body(const count_ctx *c, int64_t begin, int64_t end, int hw)
{
    bvox__labelruns *R = c->R;
    size_t wpc = R->wpc;
    for (int64_t grp = begin; grp < end; grp++) {
        copy_group(c, (size_t)grp);
        const uint64_t *u = R->words + (size_t)grp * wpc;
        if (R->g == 2) {
            const uint64_t *c00 = bvox__labelruns_column(R, (size_t)grp, 0, 0);
            const uint64_t *c10 = bvox__labelruns_column(R, (size_t)grp, 1, 0);
            const uint64_t *c01 = bvox__labelruns_column(R, (size_t)grp, 0, 1);
            const uint64_t *c11 = bvox__labelruns_column(R, (size_t)grp, 1, 1);
            uint64_t *dst = R->uw + (size_t)grp * wpc;
            for (size_t k = 0; k < wpc; k++)
                dst[k] = c00[k] | (c10 ? c10[k] : 0) | (c01 ? c01[k] : 0) | (c11 ? c11[k] : 0);
            u = dst;
        }
        uint32_t n = 0;
        uint64_t carry = 0;
        for (size_t k = 0; k < wpc; k++) {
            n += PC(bvox__run_starts(u[k], carry));
            carry = u[k] >> 63;
        }
        c->counts[grp + 1] = n;
    }
}

static void count_groups_portable(void *ctx, int64_t begin, int64_t end)
{
    count_body(ctx, begin, end, 0);
}
#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("popcnt"))) static void count_groups_popcnt(void *ctx, int64_t begin,
                                                                  int64_t end)
{
    count_body(ctx, begin, end, 1);
}
#endif

/* g = 2 with the vector kernel (components_label_avx512.c). */
static void count_groups_vector(void *ctx, int64_t begin, int64_t end)
{
    const count_ctx *c = ctx;
    bvox__labelruns *R = c->R;
    for (int64_t g = begin; g < end; g++) {
        size_t grp = (size_t)g;
        copy_group(c, grp);
        const uint64_t *c00 = bvox__labelruns_column(R, grp, 0, 0);
        const uint64_t *c10 = bvox__labelruns_column(R, grp, 1, 0);
        const uint64_t *c01 = bvox__labelruns_column(R, grp, 0, 1);
        const uint64_t *c11 = bvox__labelruns_column(R, grp, 1, 1);
        c->counts[grp + 1] =
            bvox__group_runs_avx512(c00, c10, c01, c11, R->wpc, R->uw + grp * R->wpc);
    }
}

static bvox__range_fn choose_count_groups(int g)
{
    if (g == 2 && bvox__group_runs_avx512 && bvox__simd_files(BVOX_SIMD_AVX512))
        return count_groups_vector;
#if defined(__x86_64__) || defined(__i386__)
    if (bvox_simd_active() != BVOX_SIMD_GENERIC) return count_groups_popcnt;
#endif
    return count_groups_portable;
}

void bvox__labelruns_free(bvox__labelruns *r)
{
    if (!r) return;
    bvox__free(r->grp_start, (r->ngrp + 1) * sizeof *r->grp_start);
    if (r->uw) bvox__free(r->uw, r->ngrp * r->wpc * sizeof(uint64_t));
    if (r->parent) bvox__free(r->parent, (r->nruns + r->extra ? r->nruns + r->extra : 1) * sizeof(uint32_t));
    memset(r, 0, sizeof *r);
}

bvox_status bvox__labelruns_find(const uint64_t *words, uint64_t *copy, size_t nx, size_t ny,
                                 size_t wpc, int conn, size_t extra, bvox__labelruns *out)
{
    bvox__labelruns *R = out;
    memset(R, 0, sizeof *R);
    R->nx = nx, R->ny = ny, R->wpc = wpc, R->words = copy ? copy : words, R->extra = extra;
    R->g = conn == 26 ? 2 : 1;
    R->gx = (nx + (size_t)R->g - 1) / (size_t)R->g;
    R->gy = (ny + (size_t)R->g - 1) / (size_t)R->g;
    R->ngrp = R->gx * R->gy;
    bvox_status st = BVOX_OK;
    uint64_t *zero = NULL;
    /* per-group arrays are volume-sized: from the budget (and its cache of
     * mapped buffers; a fresh one from libc costs a fault per 4 KiB) */
    R->grp_start = bvox__alloc((R->ngrp + 1) * sizeof *R->grp_start, false,
                               "component group index", &st);
    if (!R->grp_start) goto fail;
    zero = bvox__mem_zalloc(wpc, sizeof *zero);
    if (!zero) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory labelling components");
        goto fail;
    }
    if (R->g == 2) {
        R->uw = bvox__alloc(R->ngrp * wpc * sizeof(uint64_t), false, "component column groups",
                            &st);
        if (!R->uw) goto fail;
    }
    /* Run counts per group (in parallel), then their prefix sum. Counts go
     * into grp_start[c + 1] and are summed in place; 64-bit total first so
     * that more than 2^32 runs is an error, not a wrap. */
    R->grp_start[0] = 0;
    count_ctx cc = {R, words, R->grp_start};
    bvox__parallel_for((int64_t)R->ngrp, 4096 / (R->g * R->g), choose_count_groups(R->g), &cc);
    uint64_t total = 0;
    for (size_t i = 0; i < R->ngrp; i++) {
        total += R->grp_start[i + 1];
        if (total + extra >= UINT32_MAX) {
            st = bvox__fail(BVOX_ETOOBIG, "more than %u runs: too many to label",
                            (unsigned)(UINT32_MAX - 1 - extra));
            goto fail;
        }
        R->grp_start[i + 1] = (uint32_t)total;
    }
    /* The per-run array can be hundreds of megabytes (a random volume has a
     * run every four voxels of a column): it goes through the budget. */
    R->parent = bvox__alloc(((size_t)total + extra ? (size_t)total + extra : 1) * sizeof(uint32_t),
                            false, "component runs", &st);
    if (!R->parent) goto fail;
    R->nruns = (size_t)total;
    labeller L = {R, zero, R->parent, conn, 1};
    int threads = bvox__parallelism();
    /* slabs of at least 16 rows: the seam pass redoes one row per slab */
    int64_t max_slabs = (int64_t)R->gy / 16;
    L.nslabs = threads < max_slabs ? threads : (max_slabs > 0 ? max_slabs : 1);
    bvox__parallel_for(L.nslabs, 1, label_slabs, &L);
    for (int64_t sl = 1; sl < L.nslabs; sl++) {
        size_t y = slab_row(&L, sl);
        label_rows(&L, y, y + 1, 1);
    }
    free(zero);
    return BVOX_OK;
fail:
    free(zero);
    bvox__labelruns_free(R);
    return st;
}

/* ---- the border ---- */

/* Join to `outside` every run of group grp holding a voxel of the OR of
 * cols[0..nc) (words within the group's columns): the first such voxel of
 * each run, found for all runs of a word at once. */
static void join_hits(bvox__labelruns *r, size_t grp, const uint64_t *const *cols, int nc,
                      uint32_t outside)
{
    const uint64_t *u = bvox__labelruns_group(r, grp);
    uint64_t carry = 0, u_hi = 0;
    uint32_t run = r->grp_start[grp];
    for (size_t k = 0; k < r->wpc; k++) {
        uint64_t e = 0;
        for (int c = 0; c < nc; c++) e |= cols[c][k];
        uint64_t s = bvox__run_starts(u[k], u_hi);
        for (uint64_t f = first_in_segments(e, s, &carry); f; f &= f - 1) {
            unsigned p = (unsigned)__builtin_ctzll(f);
            bvox__uf_unite(r->parent, run + bvox__popcount64(s & upto(p)) - 1, outside);
        }
        run += bvox__popcount64(s);
        u_hi = u[k] >> 63;
    }
}

void bvox__labelruns_join_border(bvox__labelruns *r, size_t nz, uint32_t outside)
{
    size_t wpc = r->wpc, g = (size_t)r->g;
    unsigned last_bit = (unsigned)((nz - 1) % 64);
    for (size_t grp = 0; grp < r->ngrp; grp++) {
        uint32_t r0 = r->grp_start[grp], r1 = r->grp_start[grp + 1];
        if (r0 == r1) continue;
        const uint64_t *u = bvox__labelruns_group(r, grp);
        size_t X = grp % r->gx, Y = grp / r->gx;
        size_t x0 = X * g, y0 = Y * g;
        size_t xl = x0 + g - 1 < r->nx ? x0 + g - 1 : r->nx - 1;
        size_t yl = y0 + g - 1 < r->ny ? y0 + g - 1 : r->ny - 1;
        if (x0 == 0 || y0 == 0 || xl + 1 == r->nx || yl + 1 == r->ny) {
            /* the runs holding a voxel of a border column: the first such
             * voxel of each run */
            const uint64_t *cols[4];
            int nc = 0;
            for (size_t j = 0; j < g; j++)
                for (size_t i = 0; i < g; i++) {
                    size_t x = x0 + i, y = y0 + j;
                    if (x >= r->nx || y >= r->ny) continue;
                    if (x == 0 || y == 0 || x + 1 == r->nx || y + 1 == r->ny)
                        cols[nc++] = r->words + (y * r->nx + x) * wpc;
                }
            join_hits(r, grp, cols, nc, outside);
        }
        if (u[0] & 1) bvox__uf_unite(r->parent, r0, outside);
        if ((u[wpc - 1] >> last_bit) & 1) bvox__uf_unite(r->parent, r1 - 1, outside);
    }
}

void bvox__labelruns_mark_group(const bvox__labelruns *r, size_t grp, const uint64_t *mask,
                                uint8_t *touched)
{
    const uint64_t *u = bvox__labelruns_group(r, grp);
    uint64_t carry = 0, u_hi = 0;
    uint32_t run = r->grp_start[grp];
    for (size_t k = 0; k < r->wpc; k++) {
        uint64_t s = bvox__run_starts(u[k], u_hi);
        for (uint64_t f = first_in_segments(mask[k], s, &carry); f; f &= f - 1) {
            unsigned p = (unsigned)__builtin_ctzll(f);
            uint32_t root = r->parent[run + bvox__popcount64(s & upto(p)) - 1];
            __atomic_store_n(&touched[root], 1, __ATOMIC_RELAXED);
        }
        run += bvox__popcount64(s);
        u_hi = u[k] >> 63;
    }
}
