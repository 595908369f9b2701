/*
 * components.c — connected components by labelling runs, not voxels.
 *
 * Each column's set bits form maximal runs along z, found 64 voxels at a time
 * (run starts are w & ~(w << 1 | carry)). Two runs of neighbouring columns
 * belong together when they overlap in z (6-connectivity, face neighbours),
 * or overlap after widening by one voxel (the z-diagonal steps of 18 and 26).
 * Which neighbour columns count, and with which widening:
 *   6:  (x-1, y), (x, y-1)                              exact overlap
 *   18: the same two, widened; (x-1, y-1), (x+1, y-1)   exact overlap
 *   26: all four, widened
 * A union-find over runs (union by smaller index, path halving) then gives
 * the components; statistics are summed per run.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct run {
    int32_t z0, z1; /* half-open */
} run;

struct bvox_components {
    bvox_dims dims;
    bvox_geometry geom;
    size_t ncol;
    size_t *col_start;  /* runs of column c: runs[col_start[c] .. col_start[c+1]) */
    run *runs;
    size_t nruns;
    uint32_t *rank;     /* per run: its component's index in items (largest first) */
    bvox_component *items;
    int64_t count;
};

static uint64_t run_starts(uint64_t w, uint64_t carry) { return w & ~((w << 1) | carry); }

static size_t count_runs(const uint64_t *col, size_t wpc)
{
    size_t n = 0;
    uint64_t carry = 0;
    for (size_t k = 0; k < wpc; k++) {
        n += bvox__popcount64(run_starts(col[k], carry));
        carry = col[k] >> 63;
    }
    return n;
}

/* Write the runs of one column; returns how many. Run starts and run ends
 * (last set bit of a run) are each found in increasing order, a word at a
 * time, so the i-th start pairs with the i-th end. */
static size_t list_runs(const uint64_t *col, size_t wpc, run *out)
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
        for (; starts; starts &= starts - 1) out[ns++].z0 = base + __builtin_ctzll(starts);
        for (; ends; ends &= ends - 1) out[ne++].z1 = base + __builtin_ctzll(ends) + 1;
    }
    return ns;
}

static uint32_t find(uint32_t *parent, uint32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a == b) return;
    if (a < b) parent[b] = a;
    else parent[a] = b;
}

/* Union the runs of two columns that overlap (widen = 1: touch diagonally). */
static void join_columns(bvox_components *c, uint32_t *parent, size_t ca, size_t cb, int widen)
{
    size_t i = c->col_start[ca], ie = c->col_start[ca + 1];
    size_t j = c->col_start[cb], je = c->col_start[cb + 1];
    while (i < ie && j < je) {
        const run *a = &c->runs[i], *b = &c->runs[j];
        if (a->z0 < b->z1 + widen && b->z0 < a->z1 + widen) unite(parent, (uint32_t)i, (uint32_t)j);
        /* advance the run that ends first */
        if (a->z1 < b->z1) i++;
        else j++;
    }
}

typedef struct size_key {
    int64_t voxels;
    uint32_t id;
} size_key;

static int cmp_by_size(const void *pa, const void *pb)
{
    const size_key *a = pa, *b = pb;
    if (a->voxels != b->voxels) return a->voxels > b->voxels ? -1 : 1;
    return a->id < b->id ? -1 : a->id > b->id;
}

/* The per-run arrays can be hundreds of megabytes (a random volume has a run
 * every few voxels): they go through the budgeted allocator. */
static void *run_array(size_t nruns, size_t elem, bvox_status *st)
{
    return bvox__alloc((nruns ? nruns : 1) * elem, false, "component runs", st);
}

static void run_array_free(void *p, size_t nruns, size_t elem)
{
    bvox__free(p, (nruns ? nruns : 1) * elem);
}

void bvox_components_destroy(bvox_components *c)
{
    if (!c) return;
    free(c->col_start);
    run_array_free(c->runs, c->nruns, sizeof *c->runs);
    run_array_free(c->rank, c->nruns, sizeof *c->rank);
    free(c->items);
    free(c);
}

bvox_status bvox_components_find(const bvox_volume *vol, int conn, bvox_components **out)
{
    *out = NULL;
    if (conn != 6 && conn != 18 && conn != 26)
        return bvox__fail(BVOX_EINVAL, "connectivity must be 6, 18 or 26, not %d", conn);
    bvox_components *c = calloc(1, sizeof *c);
    if (!c) return bvox__fail(BVOX_ENOMEM, "out of memory");
    c->dims = bvox_volume_dims(vol);
    c->geom = vol->geom;
    c->ncol = (size_t)vol->nx * (size_t)vol->ny;
    c->col_start = malloc((c->ncol + 1) * sizeof *c->col_start);
    uint32_t *parent = NULL, *roots = NULL;
    bvox_status st = BVOX_OK;
    size_t total = 0;
    if (!c->col_start) goto oom;
    for (size_t col = 0; col < c->ncol; col++) {
        c->col_start[col] = total;
        total += count_runs(vol->words + col * vol->wpc, vol->wpc);
    }
    c->col_start[c->ncol] = total;
    c->nruns = total;
    if (total >= UINT32_MAX) {
        st = bvox__fail(BVOX_ETOOBIG, "%zu runs: too many to label", total);
        goto fail;
    }
    c->runs = run_array(total, sizeof *c->runs, &st);
    if (!c->runs) goto fail;
    parent = run_array(total, sizeof *parent, &st);
    if (!parent) goto fail;
    for (size_t col = 0; col < c->ncol; col++)
        list_runs(vol->words + col * vol->wpc, vol->wpc, c->runs + c->col_start[col]);
    for (size_t i = 0; i < total; i++) parent[i] = (uint32_t)i;

    int face_widen = conn == 6 ? 0 : 1;
    size_t nx = (size_t)vol->nx;
    for (size_t y = 0; y < (size_t)vol->ny; y++)
        for (size_t x = 0; x < nx; x++) {
            size_t col = y * nx + x;
            if (c->col_start[col] == c->col_start[col + 1]) continue;
            if (x > 0) join_columns(c, parent, col, col - 1, face_widen);
            if (y > 0) {
                join_columns(c, parent, col, col - nx, face_widen);
                if (conn != 6) {
                    int diag_widen = conn == 26 ? 1 : 0;
                    if (x > 0) join_columns(c, parent, col, col - nx - 1, diag_widen);
                    if (x + 1 < nx) join_columns(c, parent, col, col - nx + 1, diag_widen);
                }
            }
        }

    /* Roots are numbered in run order; sum statistics per root. */
    roots = run_array(total, sizeof *roots, &st);
    if (!roots) goto fail;
    int64_t ncomp = 0;
    for (size_t i = 0; i < total; i++) {
        uint32_t r = find(parent, (uint32_t)i);
        roots[i] = r == i ? (uint32_t)ncomp++ : roots[r]; /* r < i: already numbered */
    }
    c->count = ncomp;
    c->items = calloc(ncomp ? (size_t)ncomp : 1, sizeof *c->items);
    if (!c->items) goto oom;
    c->rank = run_array(total, sizeof *c->rank, &st);
    if (!c->rank) goto fail;
    for (size_t col = 0; col < c->ncol; col++) {
        int32_t x = (int32_t)(col % nx), y = (int32_t)(col / nx);
        for (size_t i = c->col_start[col]; i < c->col_start[col + 1]; i++) {
            bvox_component *it = &c->items[roots[i]];
            const run *r = &c->runs[i];
            if (it->voxels == 0) it->bbox = (bvox_box){x, y, r->z0, x + 1, y + 1, r->z1};
            it->voxels += r->z1 - r->z0;
            if (x < it->bbox.x0) it->bbox.x0 = x;
            if (x + 1 > it->bbox.x1) it->bbox.x1 = x + 1;
            if (y + 1 > it->bbox.y1) it->bbox.y1 = y + 1;
            if (r->z0 < it->bbox.z0) it->bbox.z0 = r->z0;
            if (r->z1 > it->bbox.z1) it->bbox.z1 = r->z1;
        }
    }
    /* Sort largest first; rank[run] = position of its component. */
    size_key *order = malloc((ncomp ? (size_t)ncomp : 1) * sizeof *order);
    uint32_t *inv = malloc((ncomp ? (size_t)ncomp : 1) * sizeof *inv);
    bvox_component *sorted = malloc((ncomp ? (size_t)ncomp : 1) * sizeof *sorted);
    if (!order || !inv || !sorted) {
        free(order);
        free(inv);
        free(sorted);
        goto oom;
    }
    for (int64_t i = 0; i < ncomp; i++) order[i] = (size_key){c->items[i].voxels, (uint32_t)i};
    qsort(order, (size_t)ncomp, sizeof *order, cmp_by_size);
    double vv = c->geom.spacing[0] * c->geom.spacing[1] * c->geom.spacing[2];
    for (int64_t i = 0; i < ncomp; i++) {
        sorted[i] = c->items[order[i].id];
        sorted[i].volume = (double)sorted[i].voxels * vv;
        inv[order[i].id] = (uint32_t)i;
    }
    for (size_t i = 0; i < total; i++) c->rank[i] = inv[roots[i]];
    free(inv);
    free(order);
    free(c->items);
    c->items = sorted;
    goto done;
oom:
    st = bvox__fail(BVOX_ENOMEM, "out of memory labelling components");
fail:
    run_array_free(parent, total, sizeof *parent);
    run_array_free(roots, total, sizeof *roots);
    bvox_components_destroy(c);
    return st;
done:
    run_array_free(parent, total, sizeof *parent);
    run_array_free(roots, total, sizeof *roots);
    *out = c;
    return BVOX_OK;
}

int64_t bvox_components_count(const bvox_components *c) { return c->count; }

const bvox_component *bvox_components_get(const bvox_components *c, int64_t i)
{
    return i >= 0 && i < c->count ? &c->items[i] : NULL;
}

static int keep_first_n(const bvox_component *comp, int64_t index, void *ctx)
{
    return index < *(const int64_t *)ctx;
}

bvox_status bvox_components_keep(const bvox_components *c, int64_t n, bvox_volume **out)
{
    return bvox_components_keep_if(c, keep_first_n, &n, out);
}

void bvox_components_labels(const bvox_components *c, uint32_t *dst)
{
    size_t plane = c->ncol;
    memset(dst, 0, plane * (size_t)c->dims.nz * sizeof *dst);
    for (size_t col = 0; col < c->ncol; col++)
        for (size_t i = c->col_start[col]; i < c->col_start[col + 1]; i++)
            for (int32_t z = c->runs[i].z0; z < c->runs[i].z1; z++)
                dst[(size_t)z * plane + col] = c->rank[i] + 1;
}

int64_t bvox_components_index_at(const bvox_components *c, int32_t x, int32_t y, int32_t z)
{
    if (x < 0 || y < 0 || z < 0 || x >= c->dims.nx || y >= c->dims.ny || z >= c->dims.nz)
        return -1;
    size_t col = (size_t)y * (size_t)c->dims.nx + (size_t)x;
    for (size_t i = c->col_start[col]; i < c->col_start[col + 1]; i++)
        if (z >= c->runs[i].z0 && z < c->runs[i].z1) return c->rank[i];
    return -1;
}

bvox_status bvox_components_keep_if(const bvox_components *c,
                                    int (*keep)(const bvox_component *, int64_t, void *),
                                    void *ctx, bvox_volume **out)
{
    *out = NULL;
    uint8_t *flags = malloc(c->count ? (size_t)c->count : 1);
    if (!flags) return bvox__fail(BVOX_ENOMEM, "out of memory");
    for (int64_t i = 0; i < c->count; i++) flags[i] = keep(&c->items[i], i, ctx) != 0;
    bvox_status st = bvox_volume_create(c->dims, out);
    if (!st) {
        (*out)->geom = c->geom;
        for (size_t col = 0; col < c->ncol; col++)
            for (size_t i = c->col_start[col]; i < c->col_start[col + 1]; i++)
                if (flags[c->rank[i]])
                    bvox__column_fill((*out)->words + col * (*out)->wpc, c->runs[i].z0,
                                      c->runs[i].z1, 1);
    }
    free(flags);
    return st;
}
