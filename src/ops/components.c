/*
 * components.c — connected components: the runs labelled by
 * components_label.c (runs along z of single columns for 6 and 18, of the OR
 * of 2 x 2 column groups for 26) turned into ranked components, and the
 * queries on them.
 *
 * Runs are never stored: a run is re-derived from the group's words when
 * needed, so the only per-run array is one uint32_t (the union-find parent,
 * which becomes the label, which becomes the rank). A last sequential pass
 * turns parents into labels in place (parent[i] < i is already a label when
 * i is reached), statistics are summed per run, and components are ranked
 * largest first, ties by their first voxel in column order (x fastest, then
 * y, then z): for single columns that is the order of the labels; for groups
 * each component also records its first voxel.
 */
#include "ops/components_label.h"

#include <stdlib.h>
#include <string.h>

struct bvox_components {
    bvox_dims dims;
    bvox_geometry geom;
    size_t ncol, wpc;
    uint64_t *words; /* copy of the volume's words: runs are derived from them */
    size_t nwords;
    bvox__labelruns runs; /* runs.parent becomes rank: per run, its component's index in items */
    uint32_t *rank;
    bvox_component *items;
    int64_t count;
};

/* Bits 0..p of a word. */
static inline uint64_t upto(unsigned p) { return ~0ull >> (63 - p); }

/* Run z-ranges of one column (or group OR), in order, into z0[]/z1[]
 * (half-open); returns the count. Starts and ends are each found in
 * increasing order, a word at a time, so the i-th start pairs with the i-th
 * end. */
static size_t list_runs(const uint64_t *col, size_t wpc, int32_t *z0, int32_t *z1)
{
    size_t ns = 0, ne = 0;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t w = col[k];
        if (!w) continue;
        uint64_t prev_hi = k ? col[k - 1] >> 63 : 0;
        uint64_t next_lo = k + 1 < wpc ? col[k + 1] & 1 : 0;
        uint64_t starts = bvox__run_starts(w, prev_hi);
        uint64_t ends = w & ~((w >> 1) | (next_lo << 63));
        int32_t base = (int32_t)(k * 64);
        for (; starts; starts &= starts - 1) z0[ns++] = base + __builtin_ctzll(starts);
        for (; ends; ends &= ends - 1) z1[ne++] = base + __builtin_ctzll(ends) + 1;
    }
    return ns;
}

/* The bits of word k that lie in [z0, z1). */
static inline uint64_t range_mask(size_t k, int32_t z0, int32_t z1)
{
    int64_t lo = z0 - (int64_t)k * 64, hi = z1 - (int64_t)k * 64;
    uint64_t m = ~0ull;
    if (lo > 0) m &= ~0ull << lo;
    if (hi < 64) m &= hi > 0 ? ~0ull >> (64 - hi) : 0;
    return m;
}

void bvox_components_destroy(bvox_components *c)
{
    if (!c) return;
    bvox__labelruns_free(&c->runs);
    if (c->words) bvox__free(c->words, c->nwords * sizeof(uint64_t));
    free(c->items);
    free(c);
}

/* Per-chunk sums: the statistics per label, and (groups) the column-order
 * key of each label's first voxel, (y * nx + x) * nz + z. */
typedef struct partial_sums {
    bvox_component *items;
    int64_t *first;
} partial_sums;

static void add_run(bvox_component *it, int64_t voxels, bvox_box b)
{
    if (it->voxels == 0) {
        it->voxels = voxels;
        it->bbox = b;
        return;
    }
    it->voxels += voxels;
    if (b.x0 < it->bbox.x0) it->bbox.x0 = b.x0;
    if (b.y0 < it->bbox.y0) it->bbox.y0 = b.y0;
    if (b.z0 < it->bbox.z0) it->bbox.z0 = b.z0;
    if (b.x1 > it->bbox.x1) it->bbox.x1 = b.x1;
    if (b.y1 > it->bbox.y1) it->bbox.y1 = b.y1;
    if (b.z1 > it->bbox.z1) it->bbox.z1 = b.z1;
}

/* The statistics of run [z0, z1) of a 2 x 2 group whose first column is at
 * (x, y): voxels and box into the label's item, the first voxel's key into
 * *first. Most runs lie in one word: its four column words are masked once. */
static inline __attribute__((always_inline)) void
group_run(const bvox_components *c, size_t grp, int32_t x, int32_t y, int32_t z0, int32_t z1,
          bvox_component *item, int64_t *first, int hw)
{
    const bvox__labelruns *R = &c->runs;
    const uint64_t *cols[4];
    for (size_t j = 0; j < 2; j++)
        for (size_t i = 0; i < 2; i++) cols[j * 2 + i] = bvox__labelruns_column(R, grp, i, j);
    int64_t voxels = 0;
    int32_t fz[4] = {0, 0, 0, 0}; /* first z of each column's voxels in the run */
    unsigned any = 0;             /* bit i: column i has voxels in the run */
    for (size_t k = (size_t)z0 / 64; k <= (size_t)(z1 - 1) / 64; k++) {
        uint64_t m = range_mask(k, z0, z1);
        for (unsigned ci = 0; ci < 4; ci++) {
            if (!cols[ci]) continue;
            uint64_t w = cols[ci][k] & m;
            if (!w) continue;
            voxels += hw ? __builtin_popcountll(w) : bvox__popcount64(w);
            if (!(any >> ci & 1)) fz[ci] = (int32_t)(k * 64) + __builtin_ctzll(w);
            any |= 1u << ci;
        }
    }
    /* the first voxel: the first column in column order ((x, y), (x+1, y),
     * (x, y+1), (x+1, y+1)) that has any, at its first z */
    unsigned ci = (unsigned)__builtin_ctz(any);
    int64_t key = (int64_t)((size_t)(cols[ci] - c->words) / c->wpc) * c->dims.nz + fz[ci];
    bvox_box b = {any & 5 ? x : x + 1, any & 3 ? y : y + 1, z0,
                  any & 10 ? x + 2 : x + 1, any & 12 ? y + 2 : y + 1, z1};
    add_run(item, voxels, b);
    if (key < *first) *first = key;
}

/* Voxels, bounding boxes and first voxels summed per label over a range of
 * groups, into out (zeroed items, first at INT64_MAX). */
static inline __attribute__((always_inline)) bvox_status
stats_body(const bvox_components *c, const uint32_t *labels, size_t g0, size_t g1,
           partial_sums out, int hw)
{
    const bvox__labelruns *R = &c->runs;
    int32_t *z0 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof *z0);
    int32_t *z1 = bvox__mem_alloc(((size_t)c->dims.nz / 2 + 1) * sizeof *z1);
    if (!z0 || !z1) {
        free(z0);
        free(z1);
        return BVOX_ENOMEM;
    }
    size_t g = (size_t)R->g;
    for (size_t grp = g0; grp < g1; grp++) {
        uint32_t first = R->grp_start[grp];
        if (first == R->grp_start[grp + 1]) continue;
        size_t n = list_runs(bvox__labelruns_group(R, grp), c->wpc, z0, z1);
        int32_t x = (int32_t)(grp % R->gx * g), y = (int32_t)(grp / R->gx * g);
        for (size_t i = 0; i < n; i++) {
            uint32_t l = labels[first + i];
            if (g == 1)
                add_run(&out.items[l], z1[i] - z0[i], (bvox_box){x, y, z0[i], x + 1, y + 1, z1[i]});
            else
                group_run(c, grp, x, y, z0[i], z1[i], &out.items[l], &out.first[l], hw);
        }
    }
    free(z0);
    free(z1);
    return BVOX_OK;
}

static bvox_status stats_portable(const bvox_components *c, const uint32_t *labels, size_t g0,
                                  size_t g1, partial_sums out)
{
    return stats_body(c, labels, g0, g1, out, 0);
}
#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("popcnt"))) static bvox_status
stats_popcnt(const bvox_components *c, const uint32_t *labels, size_t g0, size_t g1,
             partial_sums out)
{
    return stats_body(c, labels, g0, g1, out, 1);
}
#endif

static bvox_status sum_statistics_range(const bvox_components *c, const uint32_t *labels,
                                        size_t g0, size_t g1, partial_sums out)
{
#if defined(__x86_64__) || defined(__i386__)
    if (bvox_simd_active() != BVOX_SIMD_GENERIC) return stats_popcnt(c, labels, g0, g1, out);
#endif
    return stats_portable(c, labels, g0, g1, out);
}

typedef struct stats_job {
    const bvox_components *c;
    const uint32_t *labels;
    int64_t nchunks;
    partial_sums *partial; /* per chunk; partial[0] = c->items */
    int failed;
} stats_job;

static void stats_chunks(void *ctx, int64_t begin, int64_t end)
{
    stats_job *j = ctx;
    size_t ngrp = j->c->runs.ngrp;
    for (int64_t s = begin; s < end; s++) {
        size_t g0 = (size_t)s * ngrp / (size_t)j->nchunks;
        size_t g1 = (size_t)(s + 1) * ngrp / (size_t)j->nchunks;
        if (sum_statistics_range(j->c, j->labels, g0, g1, j->partial[s]))
            __atomic_store_n(&j->failed, 1, __ATOMIC_RELAXED);
    }
}

static void merge_component(bvox_component *dst, const bvox_component *src)
{
    if (src->voxels) add_run(dst, src->voxels, src->bbox);
}

/* c->items (zeroed) receives the statistics, first[] (groups only, else
 * NULL) the first voxel of each; the groups are split over the threads,
 * each summing into its own arrays, merged at the end. */
static bvox_status sum_statistics(bvox_components *c, const uint32_t *labels, int64_t *first)
{
    int64_t nchunks = bvox__parallelism();
    if ((int64_t)c->runs.ngrp < nchunks * 256) nchunks = 1;
    if (nchunks > BVOX__MAX_THREADS) nchunks = BVOX__MAX_THREADS;
    partial_sums partial[BVOX__MAX_THREADS] = {{c->items, first}};
    size_t n = (size_t)c->count ? (size_t)c->count : 1;
    bvox_status st = BVOX_OK;
    for (int64_t s = 1; s < nchunks && !st; s++) {
        partial[s].items = bvox__mem_zalloc(n, sizeof *partial[s].items);
        if (first) partial[s].first = bvox__mem_alloc(n * sizeof *partial[s].first);
        if (!partial[s].items || (first && !partial[s].first))
            st = bvox__fail(BVOX_ENOMEM, "out of memory summing components");
    }
    for (int64_t s = 0; s < nchunks && !st; s++)
        if (first)
            for (int64_t i = 0; i < c->count; i++) partial[s].first[i] = INT64_MAX;
    stats_job j = {c, labels, nchunks, partial, 0};
    if (!st) bvox__parallel_for(nchunks, 1, stats_chunks, &j);
    if (!st && j.failed) st = bvox__fail(BVOX_ENOMEM, "out of memory summing components");
    for (int64_t s = 1; s < nchunks; s++) {
        if (partial[s].items && !st)
            for (int64_t i = 0; i < c->count; i++) {
                merge_component(&c->items[i], &partial[s].items[i]);
                if (first && partial[s].first[i] < first[i]) first[i] = partial[s].first[i];
            }
        free(partial[s].items);
        free(partial[s].first);
    }
    return st;
}

/* Stable LSD radix sort of order[0..n) by key(order[i]), 16 bits a pass, as
 * many passes as the largest key needs (qsort of a million components took
 * longer than labelling them). */
static void radix_sort(uint32_t *order, uint32_t *tmp, size_t *bucket, size_t n,
                       const uint64_t *key)
{
    uint64_t maxk = 0;
    for (size_t i = 0; i < n; i++)
        if (key[i] > maxk) maxk = key[i];
    for (unsigned shift = 0; shift < 64 && (maxk >> shift) != 0; shift += 16) {
        memset(bucket, 0, 65537 * sizeof *bucket);
        for (size_t i = 0; i < n; i++) bucket[(key[i] >> shift & 0xffff) + 1]++;
        for (size_t b = 1; b <= 65536; b++) bucket[b] += bucket[b - 1];
        for (size_t i = 0; i < n; i++) {
            uint32_t id = order[i];
            tmp[bucket[key[id] >> shift & 0xffff]++] = id;
        }
        memcpy(order, tmp, n * sizeof *order);
    }
}

/* order[] = component ids sorted by voxels descending, ties by first voxel
 * (first[], or the id itself when NULL: ids are then in that order). */
static bvox_status sort_by_size(const bvox_component *items, const int64_t *first, size_t n,
                                uint32_t *order)
{
    uint32_t *tmp = bvox__mem_alloc((n ? n : 1) * sizeof *tmp);
    uint64_t *key = bvox__mem_alloc((n ? n : 1) * sizeof *key);
    const size_t bucket_bytes = 65537 * sizeof(size_t);
    bvox_status st = BVOX_OK;
    size_t *bucket = bvox__alloc(bucket_bytes, false, "component ranking", &st);
    if (!tmp || !key || !bucket) {
        free(tmp);
        free(key);
        bvox__free(bucket, bucket_bytes);
        return st ? st : bvox__fail(BVOX_ENOMEM, "out of memory ranking components");
    }
    for (size_t i = 0; i < n; i++) order[i] = (uint32_t)i;
    if (first) {
        for (size_t i = 0; i < n; i++) key[i] = (uint64_t)first[i];
        radix_sort(order, tmp, bucket, n, key);
    }
    int64_t maxv = 0;
    for (size_t i = 0; i < n; i++)
        if (items[i].voxels > maxv) maxv = items[i].voxels;
    for (size_t i = 0; i < n; i++) key[i] = (uint64_t)(maxv - items[i].voxels);
    radix_sort(order, tmp, bucket, n, key);
    bvox__free(bucket, bucket_bytes);
    free(key);
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
static bvox_status rank_items(bvox_components *c, uint32_t *labels, const int64_t *first)
{
    size_t n = (size_t)c->count;
    uint32_t *order = bvox__mem_alloc((n ? n : 1) * sizeof *order);
    uint32_t *inv = bvox__mem_alloc((n ? n : 1) * sizeof *inv);
    bvox_component *sorted = bvox__mem_alloc((n ? n : 1) * sizeof *sorted);
    bvox_status st = order && inv && sorted
                         ? sort_by_size(c->items, first, n, order)
                         : bvox__fail(BVOX_ENOMEM, "out of memory ranking components");
    if (!st) {
        double vv = c->geom.spacing[0] * c->geom.spacing[1] * c->geom.spacing[2];
        for (size_t i = 0; i < n; i++) {
            sorted[i] = c->items[order[i]];
            sorted[i].volume = (double)sorted[i].voxels * vv;
            inv[order[i]] = (uint32_t)i;
        }
        relabel_job j = {labels, inv};
        bvox__parallel_for((int64_t)c->runs.nruns, 1 << 16, relabel_range, &j);
        free(c->items);
        c->items = sorted;
        sorted = NULL;
    }
    free(sorted);
    free(inv);
    free(order);
    return st;
}

static bvox_status check_conn(int conn)
{
    if (conn != 6 && conn != 18 && conn != 26)
        return bvox__fail(BVOX_EINVAL, "connectivity must be 6, 18 or 26, not %d", conn);
    return BVOX_OK;
}

static bvox_status components_find(const bvox_volume *vol, int conn, bvox_components **out);

bvox_status bvox_components_find(const bvox_volume *vol, int conn, bvox_components **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "components");
    return bvox__progress_end(&ps, components_find(vol, conn, out));
}

/* Progress is reported between the stages (labelling is most of the work). */
static bvox_status components_find(const bvox_volume *vol, int conn, bvox_components **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    bvox_status st = check_conn(conn);
    if (st) return st;
    bvox_components *c = bvox__mem_zalloc(1, sizeof *c);
    if (!c) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int64_t *first = NULL;
    c->dims = bvox_volume_dims(vol);
    c->geom = vol->geom;
    c->ncol = (size_t)vol->nx * (size_t)vol->ny;
    c->wpc = vol->wpc;
    c->nwords = vol->nwords;
    c->words = bvox__alloc(c->nwords * sizeof(uint64_t), false, "component words", &st);
    if (!c->words) goto fail;
    st = bvox__labelruns_find(vol->words, c->words, (size_t)vol->nx, (size_t)vol->ny, c->wpc, conn,
                              0, &c->runs);
    if (st) goto fail;
    uint32_t *parent = c->rank = c->runs.parent; /* parent, then label, then rank: one array */

    /* Parents to labels in place: runs in increasing order; a root gets the
     * next label, any other run its parent's (parent < run: already a label). */
    uint32_t ncomp = 0;
    for (size_t i = 0; i < c->runs.nruns; i++)
        parent[i] = parent[i] == i ? ncomp++ : parent[parent[i]];
    c->count = ncomp;
    c->items = bvox__mem_zalloc(ncomp ? ncomp : 1, sizeof *c->items);
    if (c->runs.g > 1) first = bvox__mem_alloc((ncomp ? ncomp : 1) * sizeof *first);
    if (!c->items || (c->runs.g > 1 && !first)) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory labelling components");
        goto fail;
    }
    if ((st = bvox__progress(0.7))) goto fail; /* labelling: most of the work */
    st = sum_statistics(c, parent, first);
    if (!st) st = bvox__progress(0.9);
    if (!st) st = rank_items(c, parent, first);
    if (st) goto fail;
    free(first);
    *out = c;
    return BVOX_OK;
fail:
    free(first);
    bvox_components_destroy(c);
    return st;
}

typedef struct root_count {
    const uint32_t *parent;
    int64_t roots;
} root_count;

static void count_roots(void *ctx, int64_t begin, int64_t end)
{
    root_count *rc = ctx;
    int64_t n = 0;
    for (int64_t i = begin; i < end; i++) n += rc->parent[i] == (uint32_t)i;
    __atomic_fetch_add(&rc->roots, n, __ATOMIC_RELAXED);
}

bvox_status bvox__components_count(const bvox_volume *vol, int conn, int merge_border,
                                   int64_t *count)
{
    *count = 0;
    bvox_status st = check_conn(conn);
    if (st) return st;
    bvox__labelruns r;
    st = bvox__labelruns_find(vol->words, NULL, (size_t)vol->nx, (size_t)vol->ny, vol->wpc, conn,
                          merge_border ? 1 : 0, &r);
    if (st) return st;
    size_t nodes = r.nruns;
    if (merge_border) {
        /* One extra node, the outside, joined to every run on the border. */
        uint32_t outside = (uint32_t)r.nruns;
        r.parent[outside] = outside;
        bvox__labelruns_join_border(&r, (size_t)vol->nz, outside);
        nodes++;
    }
    root_count rc = {r.parent, 0};
    bvox__parallel_for((int64_t)nodes, 1 << 16, count_roots, &rc);
    *count = merge_border ? rc.roots - 1 : rc.roots;
    bvox__labelruns_free(&r);
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

/* Scratch arrays for the runs of one group (at most ceil(nz / 2)). */
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
    const bvox__labelruns *R = &c->runs;
    size_t plane = c->ncol, g = (size_t)R->g;
    memset(dst, 0, plane * (size_t)c->dims.nz * sizeof *dst);
    /* No scratch needed: walk each column's bits directly, counting the
     * group's run starts to know which run a set bit belongs to. */
    for (size_t grp = 0; grp < R->ngrp; grp++) {
        uint32_t run0 = R->grp_start[grp];
        if (run0 == R->grp_start[grp + 1]) continue;
        const uint64_t *u = bvox__labelruns_group(R, grp);
        for (size_t j = 0; j < g; j++)
            for (size_t i = 0; i < g; i++) {
                const uint64_t *w = bvox__labelruns_column(R, grp, i, j);
                if (!w) continue;
                size_t col = (size_t)(w - c->words) / c->wpc;
                uint32_t run = run0;
                uint64_t carry = 0;
                for (size_t k = 0; k < c->wpc; k++) {
                    uint64_t starts = bvox__run_starts(u[k], carry);
                    carry = u[k] >> 63;
                    for (uint64_t bits = w[k]; bits; bits &= bits - 1) {
                        unsigned p = (unsigned)__builtin_ctzll(bits);
                        uint32_t r = run + (uint32_t)__builtin_popcountll(starts & upto(p)) - 1;
                        dst[(k * 64 + p) * plane + col] = c->rank[r] + 1;
                    }
                    run += (uint32_t)__builtin_popcountll(starts);
                }
            }
    }
}

bvox_status bvox_components_labels_box(const bvox_components *c, bvox_box box, uint32_t *dst)
{
    if (box.x0 < 0 || box.y0 < 0 || box.z0 < 0 || box.x1 > c->dims.nx || box.y1 > c->dims.ny ||
        box.z1 > c->dims.nz || box.x0 >= box.x1 || box.y0 >= box.y1 || box.z0 >= box.z1)
        return bvox__fail(BVOX_EINVAL, "label box [%d,%d) x [%d,%d) x [%d,%d) is empty or outside "
                          "the %d x %d x %d volume", box.x0, box.x1, box.y0, box.y1, box.z0, box.z1,
                          c->dims.nx, c->dims.ny, c->dims.nz);
    const bvox__labelruns *R = &c->runs;
    size_t bx = (size_t)(box.x1 - box.x0), by = (size_t)(box.y1 - box.y0);
    size_t plane = bx * by, g = (size_t)R->g;
    memset(dst, 0, plane * (size_t)(box.z1 - box.z0) * sizeof *dst);
    size_t k1 = (size_t)(box.z1 - 1) / 64;
    /* Per column of the box: its group's run starts are counted from z = 0
     * (a run's number is its group's first plus the starts before it), the
     * column's bits in [z0, z1) get their run's rank. Only the words up to
     * z1 are read: a face of the volume costs one plane of columns. */
    for (int32_t y = box.y0; y < box.y1; y++)
        for (int32_t x = box.x0; x < box.x1; x++) {
            size_t grp = (size_t)y / g * R->gx + (size_t)x / g;
            uint32_t run = R->grp_start[grp];
            if (run == R->grp_start[grp + 1]) continue;
            const uint64_t *u = bvox__labelruns_group(R, grp);
            const uint64_t *w = c->words + ((size_t)y * (size_t)c->dims.nx + (size_t)x) * c->wpc;
            uint32_t *out = dst + (size_t)(y - box.y0) * bx + (size_t)(x - box.x0);
            uint64_t carry = 0;
            for (size_t k = 0; k <= k1; k++) {
                uint64_t starts = bvox__run_starts(u[k], carry);
                carry = u[k] >> 63;
                if ((int64_t)(k + 1) * 64 > box.z0)
                    for (uint64_t bits = w[k] & range_mask(k, box.z0, box.z1); bits;
                         bits &= bits - 1) {
                        unsigned p = (unsigned)__builtin_ctzll(bits);
                        uint32_t r = run + (uint32_t)__builtin_popcountll(starts & upto(p)) - 1;
                        out[((size_t)k * 64 + p - (size_t)box.z0) * plane] = c->rank[r] + 1;
                    }
                run += (uint32_t)__builtin_popcountll(starts);
            }
        }
    return BVOX_OK;
}

int64_t bvox_components_index_at(const bvox_components *c, int32_t x, int32_t y, int32_t z)
{
    if (x < 0 || y < 0 || z < 0 || x >= c->dims.nx || y >= c->dims.ny || z >= c->dims.nz)
        return -1;
    const bvox__labelruns *R = &c->runs;
    size_t col = (size_t)y * (size_t)c->dims.nx + (size_t)x;
    size_t grp = (size_t)y / (size_t)R->g * R->gx + (size_t)x / (size_t)R->g;
    const uint64_t *w = c->words + col * c->wpc, *u = bvox__labelruns_group(R, grp);
    size_t k = (size_t)z / 64;
    unsigned p = (unsigned)z % 64;
    if (!((w[k] >> p) & 1)) return -1;
    uint32_t run = R->grp_start[grp];
    uint64_t carry = 0;
    for (size_t j = 0; j < k; j++) {
        run += (uint32_t)__builtin_popcountll(bvox__run_starts(u[j], carry));
        carry = u[j] >> 63;
    }
    run += (uint32_t)__builtin_popcountll(bvox__run_starts(u[k], carry) & upto(p)) - 1;
    return c->rank[run];
}

/* The bits of src in [z0, z1) ORed into dst. */
static void copy_range(uint64_t *dst, const uint64_t *src, int32_t z0, int32_t z1)
{
    for (size_t k = (size_t)z0 / 64; k <= (size_t)(z1 - 1) / 64; k++)
        dst[k] |= src[k] & range_mask(k, z0, z1);
}

bvox_status bvox_components_keep_if(const bvox_components *c,
                                    int (*keep)(const bvox_component *, int64_t, void *),
                                    void *ctx, bvox_volume **out)
{
    *out = NULL;
    const bvox__labelruns *R = &c->runs;
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
        size_t g = (size_t)R->g;
        for (size_t grp = 0; grp < R->ngrp; grp++) {
            uint32_t first = R->grp_start[grp];
            if (first == R->grp_start[grp + 1]) continue;
            size_t n = list_runs(bvox__labelruns_group(R, grp), c->wpc, z0, z1);
            for (size_t j = 0; j < g; j++)
                for (size_t i = 0; i < g; i++) {
                    const uint64_t *src = bvox__labelruns_column(R, grp, i, j);
                    if (!src) continue;
                    uint64_t *dst = (*out)->words + (size_t)(src - c->words);
                    for (size_t r = 0; r < n; r++)
                        if (flags[c->rank[first + r]]) {
                            if (g == 1) bvox__column_fill(dst, z0[r], z1[r], 1);
                            else copy_range(dst, src, z0[r], z1[r]);
                        }
                }
        }
    }
    free(z0);
    free(z1);
    free(flags);
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}
