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
 * its 26-neighbourhood, looked for only where K's 6-connectivity allows one
 * (touches_exterior: the run's ends and the diagonal columns beside it).
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

/* Whether z lies in one of the runs r[0, n) (z order; a column has few). */
static inline bool in_runs(const bvox__zrun *r, uint32_t n, int32_t z)
{
    for (uint32_t i = 0; i < n && r[i].z0 <= z; i++)
        if (z < r[i].z1) return true;
    return false;
}

/* Whether run k = [z0, z1) of column (x, y) is touched: a voxel e of E in
 * its 26-neighbourhood, looked for only where the 6-connectivity of K
 * allows one. K is a union of 6-components of the background, so a
 * background voxel 6-adjacent to a voxel of K is in K, and e has no
 * background 6-neighbour that is 6-adjacent to a voxel of K:
 *  - in the column itself there is none (z0 - 1 and z1 are object);
 *  - in a face column (x +- 1 or y +- 1) e is not 6-adjacent to the run, so
 *    it is at z0 - 1 or z1, with the face column's voxel at z0 (or z1 - 1)
 *    object;
 *  - in a diagonal column at z in [z0, z1), the two face columns between
 *    are object at z;
 *  - in a diagonal column at z0 - 1 (or z1), looked at when the two face
 *    columns are object at z0 (or z1 - 1). When one, a, is background there,
 *    a is in K, in this run's component, and its voxel at z0 - 1 is object
 *    (else e would be in K); so e is in a face column of a's run at that
 *    run's end, and that run's test finds it.
 * So a component has a touched run exactly when one of its runs has E in
 * its 26-neighbourhood, and most runs need a few bit tests: the nine
 * columns' K runs were read for every run before, 78 ns a run on a sphere
 * with a torus-shaped cavity. */
static bool touches_exterior(const bvox__zrun *kr, const uint32_t *first, size_t nx,
                             const bvox_volume *vol, size_t x0, size_t y0, size_t x, size_t y,
                             bvox__zrun k)
{
    /* the nine columns, j = 3 dy + dx (4: the run's own) */
    ptrdiff_t wpc = (ptrdiff_t)vol->wpc, row = (ptrdiff_t)vol->nx * wpc;
    const uint64_t *mid = vol->words + ((y0 + y) * (size_t)vol->nx + x0 + x) * (size_t)wpc;
    const uint64_t *o[9];
    for (int j = 0; j < 9; j++) o[j] = mid + (j / 3 - 1) * row + (j % 3 - 1) * wpc;
    /* the two ends (K's runs lie strictly inside the volume along z): bit j
     * of at/in, column j's voxel at the end / at the run's voxel next to it;
     * candidates: background at the end, the face column object next to it,
     * or a diagonal column's two face columns (1 3 5 7) */
    const int32_t end[2] = {k.z0 - 1, k.z1}, inner[2] = {k.z0, k.z1 - 1};
    for (int s = 0; s < 2; s++) {
        unsigned at = 0, in = 0;
        for (int j = 0; j < 9; j++) {
            at |= (unsigned)(o[j][end[s] >> 6] >> (end[s] & 63) & 1) << j;
            in |= (unsigned)(o[j][inner[s] >> 6] >> (inner[s] & 63) & 1) << j;
        }
        unsigned diag = (in >> 1 & in >> 3 & 1) | (in >> 1 & in >> 5 & 1) << 2 |
                        (in >> 3 & in >> 7 & 1) << 6 | (in >> 5 & in >> 7 & 1) << 8;
        for (unsigned c = ~at & ((in & 0xaa) | diag); c; c &= c - 1) {
            unsigned j = (unsigned)__builtin_ctz(c);
            size_t col = (y + j / 3 - 1) * nx + x + j % 3 - 1;
            if (!in_runs(kr + first[col], first[col + 1] - first[col], end[s])) return true;
        }
    }
    /* the diagonal columns along the run, j and its face columns */
    static const int diag[4][3] = {{0, 1, 3}, {2, 1, 5}, {6, 7, 3}, {8, 7, 5}};
    for (size_t w = (size_t)k.z0 / 64; w <= (size_t)(k.z1 - 1) / 64; w++) {
        uint64_t m = bvox__range_bits(k.z0, k.z1, w);
        for (int d = 0; d < 4; d++) {
            const int *j = diag[d];
            uint64_t e = ~o[j[0]][w] & o[j[1]][w] & o[j[2]][w] & m;
            if (!e) continue;
            size_t col = (y + (size_t)j[0] / 3 - 1) * nx + x + (size_t)j[0] % 3 - 1;
            uint32_t n = first[col + 1] - first[col];
            int32_t lo = (int32_t)w * 64, hi = lo + 64;
            if (n) e &= ~runs_word(kr + first[col], n, lo > k.z0 ? lo : k.z0, hi < k.z1 ? hi : k.z1, w);
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
