/*
 * components.c — connected components by labelling runs, not voxels.
 *
 * Each column's set bits form maximal runs along z. Runs are numbered in
 * column order (columns x fastest, then y; runs by increasing z), and never
 * stored: a run is re-derived from the column words when needed, so the only
 * per-run array is one uint32_t (the union-find parent, which becomes the
 * label, which becomes the rank). For a random 512^3 mask (33 M runs of two
 * voxels on average) that is 134 MB instead of the 670 MB that explicit run
 * records, roots and ranks took.
 *
 * Which neighbour columns touch, and how (z-diagonal steps widen by one):
 *   6:  (x-1, y), (x, y-1)                              exact overlap
 *   18: the same two, widened; (x-1, y-1), (x+1, y-1)   exact overlap
 *   26: all four, widened
 *
 * Touching run pairs of two columns A, B are found with word operations, 64
 * voxels at a time, without a merge loop (whose data-dependent branches cost
 * more than the unions on random data). With S = run starts, E = run ends
 * (last bit of a run) and O = A & B:
 *   - every pair of runs that overlap meets in exactly one run of O; its
 *     first bit p is a run start of O;
 *   - a pair that touches only diagonally has A ending at p and B starting
 *     at p + 1 (EA & SB >> 1), or B ending at p - 1 and A starting at p
 *     (SA & EB << 1).
 * The run of A containing bit p is number popcount(SA up to p) - 1 of the
 * column (the same for B); B's run starting at p + 1 is number
 * popcount(SB up to p). So each contact costs a few popcounts and one union.
 *
 * Threads: rows of columns are split into one slab per thread; each slab's
 * runs are a contiguous index range, and a slab joins only its own columns
 * (union by smaller index keeps every write inside the slab). Then one pass
 * joins each slab's first row to the row before it. A last sequential pass
 * turns parents into labels in place (parent[i] < i is already a label when
 * i is reached), statistics are summed per run, and components are ranked
 * largest first.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

struct bvox_components {
    bvox_dims dims;
    bvox_geometry geom;
    size_t ncol, wpc;
    uint64_t *words;     /* copy of the volume's words: runs are derived from them */
    size_t nwords;
    uint32_t *col_start; /* runs of column c: [col_start[c], col_start[c + 1]) */
    uint32_t *rank;      /* per run: its component's index in items (largest first) */
    size_t nruns;
    bvox_component *items;
    int64_t count;
};

static inline uint64_t run_starts(uint64_t w, uint64_t carry) { return w & ~((w << 1) | carry); }

/* Bits 0..p of a word. */
static inline uint64_t upto(unsigned p) { return ~0ull >> (63 - p); }

static uint32_t count_runs(const uint64_t *col, size_t wpc)
{
    uint32_t n = 0;
    uint64_t carry = 0;
    for (size_t k = 0; k < wpc; k++) {
        n += (uint32_t)__builtin_popcountll(run_starts(col[k], carry));
        carry = col[k] >> 63;
    }
    return n;
}

/* Run z-ranges of one column, in order, into z0[]/z1[] (half-open); returns
 * the count. Starts and ends are each found in increasing order, a word at a
 * time, so the i-th start pairs with the i-th end. */
static size_t list_runs(const uint64_t *col, size_t wpc, int32_t *z0, int32_t *z1)
{
    size_t ns = 0, ne = 0;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t w = col[k];
        if (!w) continue;
        uint64_t prev_hi = k ? col[k - 1] >> 63 : 0;
        uint64_t next_lo = k + 1 < wpc ? col[k + 1] & 1 : 0;
        uint64_t starts = run_starts(w, prev_hi);
        uint64_t ends = w & ~((w >> 1) | (next_lo << 63));
        int32_t base = (int32_t)(k * 64);
        for (; starts; starts &= starts - 1) z0[ns++] = base + __builtin_ctzll(starts);
        for (; ends; ends &= ends - 1) z1[ne++] = base + __builtin_ctzll(ends) + 1;
    }
    return ns;
}

static inline uint32_t find(uint32_t *parent, uint32_t i)
{
    /* Most runs point at their root or are one: answer those without the
     * redundant store of path halving. */
    uint32_t p = parent[i];
    if (p == i) return i;
    if (parent[p] == p) return p;
    while (parent[i] != i) {
        uint32_t g = parent[parent[i]];
        parent[i] = g;
        i = g;
    }
    return i;
}

static inline void unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
}

typedef struct labeller {
    const uint64_t *words;
    size_t wpc, nx, ny;
    const uint32_t *col_start;
    uint32_t *parent;
    int conn;
    int64_t nslabs;
} labeller;

/* Union every run of column ca with the runs of column cb that touch it;
 * widen: z-diagonal contacts count too. Always inlined into the two
 * instantiations of label_rows below. */
static inline __attribute__((always_inline)) void join_columns(const labeller *L, size_t ca,
                                                               size_t cb, int widen)
{
    const uint64_t *A = L->words + ca * L->wpc, *B = L->words + cb * L->wpc;
    uint32_t ia = L->col_start[ca], ib = L->col_start[cb]; /* first run not yet passed */
    if (ia == L->col_start[ca + 1] || ib == L->col_start[cb + 1]) return;
    uint32_t *parent = L->parent;
    size_t wpc = L->wpc;
    uint64_t a_hi = 0, b_hi = 0, o_hi = 0, eb_hi = 0; /* bit 63 of the previous word */
    for (size_t k = 0; k < wpc; k++) {
        uint64_t a = A[k], b = B[k];
        uint64_t sa = run_starts(a, a_hi), sb = run_starts(b, b_hi);
        uint64_t o = a & b;
        uint64_t contacts = run_starts(o, o_hi);
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
            unite(parent, ia + (uint32_t)__builtin_popcountll(sa & m) - 1,
                  ib + (uint32_t)__builtin_popcountll(sb & m) - 1);
        }
        for (uint64_t c = diag_next; c; c &= c - 1) {
            unsigned p = (unsigned)__builtin_ctzll(c);
            uint64_t m = upto(p);
            unite(parent, ia + (uint32_t)__builtin_popcountll(sa & m) - 1,
                  ib + (uint32_t)__builtin_popcountll(sb & m));
        }
        ia += (uint32_t)__builtin_popcountll(sa);
        ib += (uint32_t)__builtin_popcountll(sb);
        a_hi = a >> 63;
        b_hi = b >> 63;
        o_hi = o >> 63;
    }
}

/* Join column (x, y) with its earlier neighbours: (x-1, y) always, the row
 * y-1 when with_prev_row. */
static inline __attribute__((always_inline)) void join_column(const labeller *L, size_t x,
                                                              size_t y, int with_prev_row)
{
    size_t nx = L->nx, col = y * nx + x;
    if (L->col_start[col] == L->col_start[col + 1]) return;
    int face_widen = L->conn != 6;
    if (x > 0) join_columns(L, col, col - 1, face_widen);
    if (!with_prev_row) return;
    join_columns(L, col, col - nx, face_widen);
    if (L->conn == 6) return;
    int diag_widen = L->conn == 26;
    if (x > 0) join_columns(L, col, col - nx - 1, diag_widen);
    if (x + 1 < nx) join_columns(L, col, col - nx + 1, diag_widen);
}

/* Join rows y0..y1-1, the first of them with the row before it when
 * first_with_prev. Two copies: without -mpopcnt (the library is built for
 * any x86-64) __builtin_popcountll is a library call, which took a third of
 * the time; the popcnt copy is used when the CPU has it (every CPU with
 * AVX2 does), chosen through the SIMD level so tests can force either. */
static void label_rows_portable(const labeller *L, size_t y0, size_t y1, int first_with_prev)
{
    for (size_t y = y0; y < y1; y++)
        for (size_t x = 0; x < L->nx; x++) join_column(L, x, y, y > y0 || first_with_prev);
}
#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("popcnt"))) static void label_rows_popcnt(const labeller *L, size_t y0,
                                                                size_t y1, int first_with_prev)
{
    for (size_t y = y0; y < y1; y++)
        for (size_t x = 0; x < L->nx; x++) join_column(L, x, y, y > y0 || first_with_prev);
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

static size_t slab_row(const labeller *L, int64_t s) { return (size_t)s * L->ny / (size_t)L->nslabs; }

static void label_slabs(void *ctx, int64_t begin, int64_t end)
{
    const labeller *L = ctx;
    for (int64_t s = begin; s < end; s++) {
        size_t y0 = slab_row(L, s), y1 = slab_row(L, s + 1);
        uint32_t r0 = L->col_start[y0 * L->nx], r1 = L->col_start[y1 * L->nx];
        for (uint32_t i = r0; i < r1; i++) L->parent[i] = i;
        label_rows(L, y0, y1, 0);
    }
}

typedef struct count_ctx {
    const uint64_t *words;
    size_t wpc;
    uint32_t *counts; /* per column, shifted by one: counts[c + 1] */
} count_ctx;

static void count_columns(void *ctx, int64_t begin, int64_t end)
{
    const count_ctx *c = ctx;
    for (int64_t col = begin; col < end; col++)
        c->counts[col + 1] = count_runs(c->words + (size_t)col * c->wpc, c->wpc);
}

/* The per-run array can be hundreds of megabytes (a random volume has a run
 * every four voxels): it goes through the budgeted allocator. */
static void *run_array(size_t nruns, bvox_status *st)
{
    return bvox__alloc((nruns ? nruns : 1) * sizeof(uint32_t), false, "component runs", st);
}

void bvox_components_destroy(bvox_components *c)
{
    if (!c) return;
    free(c->col_start);
    if (c->rank) bvox__free(c->rank, (c->nruns ? c->nruns : 1) * sizeof(uint32_t));
    if (c->words) bvox__free(c->words, c->nwords * sizeof(uint64_t));
    free(c->items);
    free(c);
}

/* Voxels and bounding boxes summed per label over a range of columns, into
 * items (zeroed, one per label). */
static bvox_status sum_statistics_range(const bvox_components *c, const uint32_t *labels,
                                        size_t col0, size_t col1, bvox_component *items)
{
    int32_t *z0 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof *z0);
    int32_t *z1 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof *z1);
    if (!z0 || !z1) {
        free(z0);
        free(z1);
        return BVOX_ENOMEM;
    }
    size_t nx = (size_t)c->dims.nx;
    for (size_t col = col0; col < col1; col++) {
        uint32_t first = c->col_start[col];
        if (first == c->col_start[col + 1]) continue;
        size_t n = list_runs(c->words + col * c->wpc, c->wpc, z0, z1);
        int32_t x = (int32_t)(col % nx), y = (int32_t)(col / nx);
        for (size_t i = 0; i < n; i++) {
            bvox_component *it = &items[labels[first + i]];
            if (it->voxels == 0) it->bbox = (bvox_box){x, y, z0[i], x + 1, y + 1, z1[i]};
            it->voxels += z1[i] - z0[i];
            if (x < it->bbox.x0) it->bbox.x0 = x;
            if (x + 1 > it->bbox.x1) it->bbox.x1 = x + 1;
            if (y < it->bbox.y0) it->bbox.y0 = y;
            if (y + 1 > it->bbox.y1) it->bbox.y1 = y + 1;
            if (z0[i] < it->bbox.z0) it->bbox.z0 = z0[i];
            if (z1[i] > it->bbox.z1) it->bbox.z1 = z1[i];
        }
    }
    free(z0);
    free(z1);
    return BVOX_OK;
}

typedef struct stats_job {
    const bvox_components *c;
    const uint32_t *labels;
    int64_t nchunks;
    bvox_component **partial; /* per chunk; partial[0] = c->items */
    int failed;
} stats_job;

static void stats_chunks(void *ctx, int64_t begin, int64_t end)
{
    stats_job *j = ctx;
    for (int64_t s = begin; s < end; s++) {
        size_t col0 = (size_t)s * j->c->ncol / (size_t)j->nchunks;
        size_t col1 = (size_t)(s + 1) * j->c->ncol / (size_t)j->nchunks;
        if (sum_statistics_range(j->c, j->labels, col0, col1, j->partial[s]))
            __atomic_store_n(&j->failed, 1, __ATOMIC_RELAXED);
    }
}

static void merge_component(bvox_component *dst, const bvox_component *src)
{
    if (src->voxels == 0) return;
    if (dst->voxels == 0) {
        *dst = *src;
        return;
    }
    dst->voxels += src->voxels;
    bvox_box *d = &dst->bbox;
    const bvox_box *b = &src->bbox;
    if (b->x0 < d->x0) d->x0 = b->x0;
    if (b->y0 < d->y0) d->y0 = b->y0;
    if (b->z0 < d->z0) d->z0 = b->z0;
    if (b->x1 > d->x1) d->x1 = b->x1;
    if (b->y1 > d->y1) d->y1 = b->y1;
    if (b->z1 > d->z1) d->z1 = b->z1;
}

/* c->items (zeroed) receives the statistics; the column range is split over
 * the threads, each summing into its own array, merged at the end. */
static bvox_status sum_statistics(bvox_components *c, const uint32_t *labels)
{
    int64_t nchunks = bvox__parallelism();
    if ((int64_t)c->ncol < nchunks * 1024) nchunks = 1;
    bvox_component *partial[BVOX__MAX_THREADS] = {c->items};
    if (nchunks > BVOX__MAX_THREADS) nchunks = BVOX__MAX_THREADS;
    bvox_status st = BVOX_OK;
    for (int64_t s = 1; s < nchunks && !st; s++) {
        partial[s] = bvox__mem_zalloc((size_t)c->count ? (size_t)c->count : 1, sizeof **partial);
        if (!partial[s]) st = bvox__fail(BVOX_ENOMEM, "out of memory summing components");
    }
    stats_job j = {c, labels, nchunks, partial, 0};
    if (!st) bvox__parallel_for(nchunks, 1, stats_chunks, &j);
    if (!st && j.failed) st = bvox__fail(BVOX_ENOMEM, "out of memory summing components");
    for (int64_t s = 1; s < nchunks; s++) {
        if (partial[s] && !st)
            for (int64_t i = 0; i < c->count; i++) merge_component(&c->items[i], &partial[s][i]);
        free(partial[s]);
    }
    return st;
}

/* order[] = component ids sorted by voxels descending, ties by id
 * ascending: a stable LSD radix sort on (max - voxels), 16 bits a pass, as
 * many passes as the largest count needs (qsort of a million components took
 * longer than labelling them). */
static bvox_status sort_by_size(const bvox_component *items, size_t n, uint32_t *order)
{
    uint32_t *tmp = bvox__mem_alloc((n ? n : 1) * sizeof *tmp);
    size_t *bucket = bvox__mem_alloc(65537 * sizeof *bucket);
    if (!tmp || !bucket) {
        free(tmp);
        free(bucket);
        return bvox__fail(BVOX_ENOMEM, "out of memory ranking components");
    }
    int64_t maxv = 0;
    for (size_t i = 0; i < n; i++) {
        order[i] = (uint32_t)i;
        if (items[i].voxels > maxv) maxv = items[i].voxels;
    }
    for (unsigned shift = 0; shift < 64 && (maxv >> shift) != 0; shift += 16) {
        memset(bucket, 0, 65537 * sizeof *bucket);
        for (size_t i = 0; i < n; i++)
            bucket[(((uint64_t)(maxv - items[i].voxels)) >> shift & 0xffff) + 1]++;
        for (size_t b = 1; b <= 65536; b++) bucket[b] += bucket[b - 1];
        for (size_t i = 0; i < n; i++) {
            uint32_t id = order[i];
            tmp[bucket[((uint64_t)(maxv - items[id].voxels)) >> shift & 0xffff]++] = id;
        }
        memcpy(order, tmp, n * sizeof *order);
    }
    free(bucket);
    free(tmp);
    return BVOX_OK;
}

typedef struct relabel_job {
    uint32_t *labels;
    const uint32_t *inv;
} relabel_job;

static void relabel_range(void *ctx, int64_t begin, int64_t end)
{
    const relabel_job *j = ctx;
    for (int64_t i = begin; i < end; i++) j->labels[i] = j->inv[j->labels[i]];
}

/* Items sorted largest first; labels[] become ranks. */
static bvox_status rank_items(bvox_components *c, uint32_t *labels)
{
    size_t n = (size_t)c->count;
    uint32_t *order = bvox__mem_alloc((n ? n : 1) * sizeof *order);
    uint32_t *inv = bvox__mem_alloc((n ? n : 1) * sizeof *inv);
    bvox_component *sorted = bvox__mem_alloc((n ? n : 1) * sizeof *sorted);
    bvox_status st = order && inv && sorted
                         ? sort_by_size(c->items, n, order)
                         : bvox__fail(BVOX_ENOMEM, "out of memory ranking components");
    if (!st) {
        double vv = c->geom.spacing[0] * c->geom.spacing[1] * c->geom.spacing[2];
        for (size_t i = 0; i < n; i++) {
            sorted[i] = c->items[order[i]];
            sorted[i].volume = (double)sorted[i].voxels * vv;
            inv[order[i]] = (uint32_t)i;
        }
        relabel_job j = {labels, inv};
        bvox__parallel_for((int64_t)c->nruns, 1 << 16, relabel_range, &j);
        free(c->items);
        c->items = sorted;
        sorted = NULL;
    }
    free(sorted);
    free(inv);
    free(order);
    return st;
}

/* The labelling core shared by bvox_components_find and the count-only
 * bvox__components_count: col_start (ncol + 1 entries, malloc) and the
 * union-find parent array (nruns + extra entries, budgeted; the extra ones
 * are left for the caller to initialise) of the runs of words. */
static bvox_status label_runs(const uint64_t *words, size_t wpc, size_t nx, size_t ny, int conn,
                              size_t extra, uint32_t **col_start_out, uint32_t **parent_out,
                              size_t *nruns_out)
{
    *col_start_out = NULL;
    *parent_out = NULL;
    size_t ncol = nx * ny;
    uint32_t *col_start = bvox__mem_alloc((ncol + 1) * sizeof *col_start);
    if (!col_start) return bvox__fail(BVOX_ENOMEM, "out of memory labelling components");

    /* Run counts per column (in parallel), then their prefix sum. Counts go
     * into col_start[c + 1] and are summed in place; 64-bit total first so
     * that more than 2^32 runs is an error, not a wrap. */
    col_start[0] = 0;
    count_ctx cc = {words, wpc, col_start};
    bvox__parallel_for((int64_t)ncol, 4096, count_columns, &cc);
    uint64_t total = 0;
    for (size_t col = 0; col < ncol; col++) {
        total += col_start[col + 1];
        if (total + extra >= UINT32_MAX) {
            free(col_start);
            return bvox__fail(BVOX_ETOOBIG, "more than %u runs: too many to label",
                              (unsigned)(UINT32_MAX - 1 - extra));
        }
        col_start[col + 1] = (uint32_t)total;
    }
    bvox_status st = BVOX_OK;
    uint32_t *parent = run_array((size_t)total + extra, &st);
    if (!parent) {
        free(col_start);
        return st;
    }
    labeller L = {words, wpc, nx, ny, col_start, parent, conn, 1};
    int threads = bvox__parallelism();
    /* slabs of at least 16 rows: the seam pass redoes one row per slab */
    int64_t max_slabs = (int64_t)ny / 16;
    L.nslabs = threads < max_slabs ? threads : (max_slabs > 0 ? max_slabs : 1);
    bvox__parallel_for(L.nslabs, 1, label_slabs, &L);
    for (int64_t sl = 1; sl < L.nslabs; sl++) {
        size_t y = slab_row(&L, sl);
        label_rows(&L, y, y + 1, 1);
    }
    *col_start_out = col_start;
    *parent_out = parent;
    *nruns_out = (size_t)total;
    return BVOX_OK;
}

static bvox_status check_conn(int conn)
{
    if (conn != 6 && conn != 18 && conn != 26)
        return bvox__fail(BVOX_EINVAL, "connectivity must be 6, 18 or 26, not %d", conn);
    return BVOX_OK;
}

bvox_status bvox_components_find(const bvox_volume *vol, int conn, bvox_components **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    bvox_status st = check_conn(conn);
    if (st) return st;
    bvox_components *c = bvox__mem_zalloc(1, sizeof *c);
    if (!c) return bvox__fail(BVOX_ENOMEM, "out of memory");
    c->dims = bvox_volume_dims(vol);
    c->geom = vol->geom;
    c->ncol = (size_t)vol->nx * (size_t)vol->ny;
    c->wpc = vol->wpc;
    c->nwords = vol->nwords;
    c->words = bvox__alloc(c->nwords * sizeof(uint64_t), false, "component words", &st);
    if (!c->words) goto fail;
    memcpy(c->words, vol->words, c->nwords * sizeof(uint64_t));
    st = label_runs(c->words, c->wpc, (size_t)vol->nx, (size_t)vol->ny, conn, 0, &c->col_start,
                    &c->rank, &c->nruns);
    if (st) goto fail;
    uint32_t *parent = c->rank; /* parent, then label, then rank: one array */

    /* Parents to labels in place: runs in increasing order; a root gets the
     * next label, any other run its parent's (parent < run: already a label). */
    uint32_t ncomp = 0;
    for (size_t i = 0; i < c->nruns; i++)
        parent[i] = parent[i] == i ? ncomp++ : parent[parent[i]];
    c->count = ncomp;
    c->items = bvox__mem_zalloc(ncomp ? ncomp : 1, sizeof *c->items);
    if (!c->items) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory labelling components");
        goto fail;
    }
    st = sum_statistics(c, parent);
    if (!st) st = rank_items(c, parent);
    if (st) goto fail;
    *out = c;
    return BVOX_OK;
fail:
    bvox_components_destroy(c);
    return st;
}

bvox_status bvox__components_count(const bvox_volume *vol, int conn, int merge_border,
                                   int64_t *count)
{
    *count = 0;
    bvox_status st = check_conn(conn);
    if (st) return st;
    uint32_t *col_start = NULL, *parent = NULL;
    size_t nruns = 0, nx = (size_t)vol->nx, ny = (size_t)vol->ny, wpc = vol->wpc;
    st = label_runs(vol->words, wpc, nx, ny, conn, merge_border ? 1 : 0, &col_start, &parent,
                    &nruns);
    if (st) return st;
    if (merge_border) {
        /* One extra node, the outside, joined to every run on the border. */
        uint32_t outside = (uint32_t)nruns;
        parent[outside] = outside;
        unsigned last_bit = (unsigned)((vol->nz - 1) % 64);
        for (size_t y = 0; y < ny; y++)
            for (size_t x = 0; x < nx; x++) {
                size_t col = y * nx + x;
                uint32_t r0 = col_start[col], r1 = col_start[col + 1];
                if (r0 == r1) continue;
                if (x == 0 || y == 0 || x + 1 == nx || y + 1 == ny) {
                    for (uint32_t r = r0; r < r1; r++) unite(parent, r, outside);
                    continue;
                }
                const uint64_t *w = vol->words + col * wpc;
                if (w[0] & 1) unite(parent, r0, outside);
                if ((w[wpc - 1] >> last_bit) & 1) unite(parent, r1 - 1, outside);
            }
    }
    int64_t roots = 0;
    size_t nodes = nruns + (merge_border ? 1 : 0);
    for (size_t i = 0; i < nodes; i++) roots += parent[i] == i;
    *count = merge_border ? roots - 1 : roots;
    free(col_start);
    bvox__free(parent, (nodes ? nodes : 1) * sizeof(uint32_t));
    return BVOX_OK;
}

int64_t bvox_components_count(const bvox_components *c) { return c->count; }

const bvox_component *bvox_components_get(const bvox_components *c, int64_t i)
{
    return i >= 0 && i < c->count ? &c->items[i] : NULL;
}

static int keep_first_n(const bvox_component *comp, int64_t index, void *ctx)
{
    (void)comp;
    return index < *(const int64_t *)ctx;
}

bvox_status bvox_components_keep(const bvox_components *c, int64_t n, bvox_volume **out)
{
    return bvox_components_keep_if(c, keep_first_n, &n, out);
}

/* Scratch arrays for the runs of one column (at most ceil(nz / 2)). */
static bvox_status run_scratch(const bvox_components *c, int32_t **z0, int32_t **z1)
{
    *z0 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof **z0);
    *z1 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof **z1);
    if (*z0 && *z1) return BVOX_OK;
    free(*z0);
    free(*z1);
    return bvox__fail(BVOX_ENOMEM, "out of memory");
}

void bvox_components_labels(const bvox_components *c, uint32_t *dst)
{
    size_t plane = c->ncol;
    memset(dst, 0, plane * (size_t)c->dims.nz * sizeof *dst);
    /* No scratch needed: walk each column's bits directly, counting run
     * starts to know which run a set bit belongs to. */
    for (size_t col = 0; col < c->ncol; col++) {
        const uint64_t *w = c->words + col * c->wpc;
        uint32_t run = c->col_start[col];
        if (run == c->col_start[col + 1]) continue;
        uint64_t carry = 0;
        for (size_t k = 0; k < c->wpc; k++) {
            uint64_t starts = run_starts(w[k], carry);
            carry = w[k] >> 63;
            for (uint64_t bits = w[k]; bits; bits &= bits - 1) {
                unsigned p = (unsigned)__builtin_ctzll(bits);
                uint32_t r = run + (uint32_t)__builtin_popcountll(starts & upto(p)) - 1;
                dst[(k * 64 + p) * plane + col] = c->rank[r] + 1;
            }
            run += (uint32_t)__builtin_popcountll(starts);
        }
    }
}

int64_t bvox_components_index_at(const bvox_components *c, int32_t x, int32_t y, int32_t z)
{
    if (x < 0 || y < 0 || z < 0 || x >= c->dims.nx || y >= c->dims.ny || z >= c->dims.nz)
        return -1;
    size_t col = (size_t)y * (size_t)c->dims.nx + (size_t)x;
    const uint64_t *w = c->words + col * c->wpc;
    size_t k = (size_t)z / 64;
    unsigned p = (unsigned)z % 64;
    if (!((w[k] >> p) & 1)) return -1;
    uint32_t run = c->col_start[col];
    uint64_t carry = 0;
    for (size_t j = 0; j < k; j++) {
        run += (uint32_t)__builtin_popcountll(run_starts(w[j], carry));
        carry = w[j] >> 63;
    }
    run += (uint32_t)__builtin_popcountll(run_starts(w[k], carry) & upto(p)) - 1;
    return c->rank[run];
}

bvox_status bvox_components_keep_if(const bvox_components *c,
                                    int (*keep)(const bvox_component *, int64_t, void *),
                                    void *ctx, bvox_volume **out)
{
    *out = NULL;
    uint8_t *flags = bvox__mem_alloc(c->count ? (size_t)c->count : 1);
    if (!flags) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int32_t *z0 = NULL, *z1 = NULL;
    bvox_status st = run_scratch(c, &z0, &z1);
    if (st) {
        free(flags);
        return st;
    }
    for (int64_t i = 0; i < c->count; i++) flags[i] = keep(&c->items[i], i, ctx) != 0;
    st = bvox_volume_create(c->dims, out);
    if (!st) {
        (*out)->geom = c->geom;
        for (size_t col = 0; col < c->ncol; col++) {
            uint32_t first = c->col_start[col];
            if (first == c->col_start[col + 1]) continue;
            size_t n = list_runs(c->words + col * c->wpc, c->wpc, z0, z1);
            uint64_t *dst = (*out)->words + col * (*out)->wpc;
            for (size_t i = 0; i < n; i++)
                if (flags[c->rank[first + i]]) bvox__column_fill(dst, z0[i], z1[i], 1);
        }
    }
    free(z0);
    free(z1);
    free(flags);
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}
