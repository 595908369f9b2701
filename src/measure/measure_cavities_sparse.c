/*
 * measure_cavities_sparse.c — the 26-cavities when the cavity voxels K are
 * given as runs, or are a few pockets of a labelled box (the AAL atlas: 41
 * cavities in 158 thousand runs of the enclosed background).
 *
 * The dense route of measure_cavities.c clears every other run out of the
 * labelled words and labels the whole box again 26-connected: on the atlas
 * that streamed 11 MiB three more times for a few hundred runs. Here K's
 * runs (per column, in z order) are joined 26-connected by a merge of each
 * column's runs with those of its four earlier neighbours, and a run is
 * touched when a voxel of the exterior E (the background minus K) lies in
 * its 26-neighbourhood: the nine columns around it over [z0 - 1, z1 + 1),
 * read as the complement of the object minus K's runs there, word by word.
 * A 26-component of K is a 26-cavity unless one of its runs is touched; the
 * same rule as the dense route, where T = K & dilate26(E) marks the roots.
 */
#include "measure/measure.h"
#include "ops/components_label.h"

#include <string.h>

void bvox__zruns_join(uint32_t *parent, const bvox__zrun *a, uint32_t ia, uint32_t na,
                      const bvox__zrun *b, uint32_t ib, uint32_t nb, int32_t reach)
{
    uint32_t q = 0;
    for (uint32_t i = 0; i < na; i++) {
        /* b[q] ends before a[i]'s reach, so before the next run's too */
        while (q < nb && b[q].z1 + reach <= a[i].z0) q++;
        for (uint32_t j = q; j < nb && b[j].z0 < a[i].z1 + reach; j++)
            bvox__uf_unite(parent, ia + i, ib + j);
    }
}

/* Word w of the voxels of runs r[0, n) (z order) that lie in [lo, hi). */
static uint64_t runs_word(const bvox__zrun *r, uint32_t n, int32_t lo, int32_t hi, size_t w)
{
    uint32_t a = 0, b = n; /* the first run ending after lo */
    while (a < b) {
        uint32_t m = a + (b - a) / 2;
        if (r[m].z1 <= lo) a = m + 1;
        else b = m;
    }
    uint64_t bits = 0;
    for (uint32_t i = a; i < n && r[i].z0 < hi; i++) bits |= bvox__range_bits(r[i].z0, r[i].z1, w);
    return bits;
}

/* Whether run k of column (x, y) has a voxel of E in its 26-neighbourhood. */
static bool touches_exterior(const bvox__zrun *kr, const uint32_t *first, size_t nx,
                             const bvox_volume *vol, size_t x0, size_t y0, size_t x, size_t y,
                             bvox__zrun k)
{
    size_t wpc = vol->wpc, vnx = (size_t)vol->nx;
    int32_t lo = k.z0 > 0 ? k.z0 - 1 : 0, hi = k.z1 < vol->nz ? k.z1 + 1 : vol->nz;
    size_t w0 = (size_t)lo / 64, w1 = (size_t)(hi - 1) / 64;
    for (size_t dy = 0; dy < 3; dy++)
        for (size_t dx = 0; dx < 3; dx++) {
            size_t cx = x + dx - 1, cy = y + dy - 1, c = cy * nx + cx;
            const uint64_t *o = vol->words + ((y0 + cy) * vnx + x0 + cx) * wpc;
            uint32_t n = first[c + 1] - first[c];
            for (size_t w = w0; w <= w1; w++) {
                int32_t wlo = lo > (int32_t)w * 64 ? lo : (int32_t)w * 64;
                int32_t whi = hi < (int32_t)w * 64 + 64 ? hi : (int32_t)w * 64 + 64;
                uint64_t e = ~o[w] & bvox__range_bits(lo, hi, w);
                if (e && n) e &= ~runs_word(kr + first[c], n, wlo, whi, w);
                if (e) return true;
            }
        }
    return false;
}

/* The touched roots of K's runs, rows in parallel (parent flattened: every
 * entry a root; a store of 1 by several threads at once is harmless). */
typedef struct touch_job {
    const bvox__zrun *kr;
    const uint32_t *first;
    size_t nx, ny;
    const bvox_volume *vol;
    size_t x0, y0;
    const uint32_t *parent;
    uint8_t *touched;
} touch_job;

static void touch_rows(void *ctx, int64_t begin, int64_t end)
{
    const touch_job *t = ctx;
    const uint32_t *first = t->first;
    size_t nx = t->nx;
    for (size_t y = (size_t)begin; y < (size_t)end; y++) {
        if (y == 0 || y + 1 >= t->ny || first[y * nx] == first[(y + 1) * nx]) continue;
        for (size_t x = 1; x + 1 < nx; x++)
            for (uint32_t i = first[y * nx + x]; i < first[y * nx + x + 1]; i++) {
                uint32_t root = t->parent[i];
                /* its component is out already */
                if (__atomic_load_n(&t->touched[root], __ATOMIC_RELAXED)) continue;
                if (touches_exterior(t->kr, first, nx, t->vol, t->x0, t->y0, x, y, t->kr[i]))
                    __atomic_store_n(&t->touched[root], 1, __ATOMIC_RELAXED);
            }
    }
}

bvox_status bvox__cavities_26_runs(const bvox__zrun *kr, const uint32_t *first, size_t nx,
                                   size_t ny, const bvox_volume *vol, size_t x0, size_t y0,
                                   int64_t *out)
{
    size_t ncol = nx * ny;
    uint32_t nk = first[ncol];
    *out = 0;
    if (!nk) return BVOX_OK;
    bvox_status st = BVOX_OK;
    size_t bytes = (size_t)nk * (sizeof(uint32_t) + 1);
    uint32_t *parent = bvox__alloc(bytes, false, "cavity runs", &st);
    if (!parent) return st;
    uint8_t *touched = (uint8_t *)(parent + nk);
    memset(touched, 0, nk);
    for (uint32_t i = 0; i < nk; i++) parent[i] = i;
    /* K's columns are never in the box's ring (joined to outside there), so
     * their eight neighbours are all in the box; rows without K (most, when
     * K is a few pockets) are passed over whole */
    for (size_t y = 1; y + 1 < ny; y++) {
        if (first[y * nx] == first[(y + 1) * nx]) continue;
        for (size_t col = y * nx; col < (y + 1) * nx; col++) {
            uint32_t a = first[col], na = first[col + 1] - a;
            if (!na) continue;
            const size_t nb[4] = {col - 1, col - nx - 1, col - nx, col - nx + 1};
            for (int i = 0; i < 4; i++) {
                uint32_t b = first[nb[i]], n = first[nb[i] + 1] - b;
                if (n) bvox__zruns_join(parent, kr + a, a, na, kr + b, b, n, 1);
            }
        }
    }
    for (uint32_t i = 0; i < nk; i++) parent[i] = parent[parent[i]]; /* roots: parent <= i */
    touch_job tj = {kr, first, nx, ny, vol, x0, y0, parent, touched};
    bvox__parallel_for((int64_t)ny, 16, touch_rows, &tj);
    int64_t n = 0;
    for (uint32_t i = 0; i < nk; i++) n += parent[i] == i && !touched[i];
    *out = n;
    bvox__free(parent, bytes);
    return BVOX_OK;
}

/* K's runs of column col listed into kr: those of r not in outside's
 * component. */
static void list_column(const bvox__labelruns *r, const uint64_t *words, size_t col,
                        uint32_t outside, bvox__zrun *kr)
{
    uint32_t run = r->grp_start[col];
    bvox__runs_iter it;
    int32_t z0, z1;
    for (bool more = bvox__runs_begin(&it, words + col * r->wpc, 0, r->wpc);
         more && bvox__runs_next(&it, &z0, &z1); run++)
        if (r->parent[run] != outside) *kr++ = (bvox__zrun){z0, z1};
}

bvox_status bvox__cavities_26_sparse(const bvox__labelruns *r, const uint64_t *words,
                                     const bvox_volume *vol, size_t x0, size_t y0,
                                     const uint32_t *first, int64_t *out)
{
    size_t ncol = r->nx * r->ny;
    uint32_t nk = first[ncol], outside = r->parent[r->nruns];
    *out = 0;
    if (!nk) return BVOX_OK;
    bvox_status st = BVOX_OK;
    bvox__zrun *kr = bvox__alloc((size_t)nk * sizeof *kr, false, "cavity runs", &st);
    if (!kr) return st;
    for (size_t col = 0; col < ncol; col++)
        if (first[col] < first[col + 1]) list_column(r, words, col, outside, kr + first[col]);
    st = bvox__cavities_26_runs(kr, first, r->nx, r->ny, vol, x0, y0, out);
    bvox__free(kr, (size_t)nk * sizeof *kr);
    return st;
}
