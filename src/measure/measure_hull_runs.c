/*
 * measure_hull_runs.c — the cavities of bvox_measure from the runs of U,
 * the background enclosed along z (measure_enclosed.c), listed: no words of
 * U are written and no labeller reads them.
 *
 * On the AAL atlas at 512^3 U is 11 MiB of mostly zero words holding 158
 * thousand runs; writing it, the labeller's two passes over it and the
 * search for its contacts with the exterior each streamed all of it. Here:
 *   1. per column, U's hull [lo, hi) and the number of U's runs, from the
 *      scan's records (bvox__measure_scan_hulls), and the counts' prefix
 *      sums a row at a time;
 *   2. per column, its runs (z0, z1) listed, and each marked touched when
 *      one of its voxels is a 6-neighbour across x or y of the exterior E
 *      (the background outside the neighbour columns' hulls; U's runs end
 *      on object voxels along z), from the object's words and the hulls;
 *   3. the runs joined 6-connected by a merge of each column's list with
 *      those of the columns at x - 1 and y - 1, in slabs of rows (union by
 *      smaller index keeps every write in the slab), then the seams;
 *   4. every run's parent made its root and the roots of touched runs
 *      marked, in parallel; a component is a 6-cavity unless its root is
 *      marked; the cavities' runs are K (listed a row at a time), whose
 *      26-cavities bvox__cavities_26_runs counts.
 * A run list costs 8 bytes a run against U's 8 bytes a word. The same rule
 * as the labelled route of measure_cavities.c (bvox__cavity_hull = 1).
 * Rows equal to the row before (twin rows, the scan's flag) own no runs:
 * they stand on their streak's first row's (see twin_touch_rows), which
 * halves the runs of an upsampled volume such as the atlas.
 */
#include "measure/measure.h"
#include "ops/components_label.h"

#include <stdlib.h>
#include <string.h>

typedef struct hull_job {
    const bvox_volume *v;
    size_t x0, y0, nx, ny;
    int32_t *zr;     /* per column: U's hull [lo, hi) along z */
    uint32_t *first;  /* per column: its runs' count, then the index of its first run */
    uint64_t *rowsum; /* per row: its runs' count, then the index of its first run */
    bvox__zrun *runs;
    uint8_t *touched; /* per run: it touches E */
    uint8_t *marked;  /* per root: its component holds a touched run */
    uint32_t *parent;
    uint8_t *same_left; /* per column: it has runs, equal to those of the column at x - 1 */
    /* per row: the row whose runs it has, itself or, for a twin row (its
     * columns, the ring's too, equal those of the row before), the first
     * row of its streak */
    uint32_t *base;
    int64_t nslabs;
} hull_job;

static inline bool twin_row(const hull_job *j, size_t y) { return j->base[y] != y; }

static inline const uint64_t *object_column(const hull_job *j, size_t x, size_t y)
{
    return j->v->words + ((j->y0 + y) * (size_t)j->v->nx + j->x0 + x) * j->v->wpc;
}

/* The first voxel at or after z whose bit is `bit` (1: object) in the
 * column o; one exists before the column's last word ends (U's runs lie
 * between object voxels). */
static inline int32_t next_voxel(const uint64_t *o, int32_t z, uint64_t bit, size_t last_word)
{
    size_t w = (size_t)z / 64;
    uint64_t flip = bit - 1; /* ~0 to look for 0s */
    uint64_t t = (o[w] ^ flip) & (~0ull << (z & 63));
    while (!t && w < last_word) t = o[++w] ^ flip;
    return (int32_t)(w * 64 + (size_t)__builtin_ctzll(t));
}

/* Whether o has a background voxel in [a, b) (within nz). */
static inline bool any_background(const uint64_t *o, int32_t a, int32_t b)
{
    for (size_t w = (size_t)a / 64; w <= (size_t)(b - 1) / 64; w++)
        if (~o[w] & bvox__range_bits(a, b, w)) return true;
    return false;
}

/* Whether U's run [z0, z1) of a column touches E across x or y: E of a
 * neighbour column is its background outside its hull, so only the parts of
 * the run outside that hull are looked at, and most runs have none (the
 * words were read for every run, 90 ns a column on the atlas). */
static bool touches_exterior(const hull_job *j, const uint64_t *const onb[4], const size_t nb[4],
                             int k0, int32_t z0, int32_t z1)
{
    for (int k = k0; k < 4; k++) {
        int32_t lo = j->zr[2 * nb[k]], hi = j->zr[2 * nb[k] + 1];
        int32_t below = z1 < lo ? z1 : lo, above = z0 > hi ? z0 : hi;
        if (z0 < below && any_background(onb[k], z0, below)) return true;
        if (above < z1 && any_background(onb[k], above, z1)) return true;
    }
    return false;
}

/* 2. The runs of column (x, y), an inner one with runs, listed and marked:
 * U's runs are the gaps between the column's object runs after lo (the
 * voxel after the first object voxel), as many as the record says; they are
 * found from the object's words directly (building U's words first took
 * longer). */
static void list_column(const hull_job *j, size_t x, size_t y)
{
    size_t nx = j->nx, col = y * nx + x, last_word = j->v->wpc - 1;
    int32_t z = j->zr[2 * col];
    const uint64_t *o = object_column(j, x, y);
    const size_t nb[4] = {col - 1, col + 1, col - nx, col + nx};
    const uint64_t *const onb[4] = {object_column(j, x - 1, y), object_column(j, x + 1, y),
                                    object_column(j, x, y - 1), object_column(j, x, y + 1)};
    /* a run within every neighbour's hull touches no E: most of them */
    int32_t in_lo = 0, in_hi = INT32_MAX;
    for (int k = 0; k < 4; k++) {
        int32_t lo = j->zr[2 * nb[k]], hi = j->zr[2 * nb[k] + 1];
        in_lo = lo > in_lo ? lo : in_lo;
        in_hi = hi < in_hi ? hi : in_hi;
    }
    /* a column equal to the one before it (most of them on the atlas, an
     * upsampled volume) has its runs */
    uint32_t n = j->first[col + 1] - j->first[col];
    bool same = j->first[col] - j->first[col - 1] == n &&
                !memcmp(o, o - j->v->wpc, j->v->wpc * sizeof *o);
    j->same_left[col] = same;
    for (uint32_t i = j->first[col]; i < j->first[col + 1]; i++) {
        int32_t z0, z1;
        if (same) {
            z0 = j->runs[i - n].z0, z1 = j->runs[i - n].z1;
        } else {
            z0 = next_voxel(o, z, 0, last_word), z1 = next_voxel(o, z0, 1, last_word);
        }
        j->runs[i] = (bvox__zrun){z0, z1};
        j->touched[i] = (z0 < in_lo || z1 > in_hi) && touches_exterior(j, onb, nb, 0, z0, z1);
        z = z1;
    }
}

/* Twin rows (equal to the row before: 58 % of the AAL atlas's inner rows
 * at 512^3, an upsampled volume) own no runs: a streak of them has the runs
 * of its first row, the base. A twin's run r is the base's run r' moved
 * along y through equal columns, 6-connected to it, so one node stands for
 * both. Its neighbours at x - 1 and x + 1 are the base's (equal columns),
 * and at y - 1 a column equal to its own, whose hull holds r: only the
 * column at y + 1 can add a touch, which marks r' (twin_touch_rows, after
 * the listing). The row after a streak joins with the base's runs, and K
 * (the cavities' runs) lists the base's runs again for each twin. */
int bvox__cavity_twin_rows = 1;

static void list_rows(void *ctx, int64_t begin, int64_t end)
{
    const hull_job *j = ctx;
    for (size_t y = (size_t)begin + 1; y < (size_t)end + 1; y++)
        for (size_t x = 1; x + 1 < j->nx; x++) {
            size_t col = y * j->nx + x;
            if (j->first[col] < j->first[col + 1]) list_column(j, x, y);
        }
}

/* The touches across y + 1 of the twin rows, marked on their bases' runs
 * (a store of 1 only: several twins of a streak may mark one run). */
static void twin_touch_rows(void *ctx, int64_t begin, int64_t end)
{
    const hull_job *j = ctx;
    size_t nx = j->nx;
    for (size_t y = (size_t)begin + 1; y < (size_t)end + 1; y++) {
        /* a twin followed by a twin: the column at y + 1 is its own, whose
         * hull holds every run (only a streak's last row can touch) */
        if (!twin_row(j, y) || twin_row(j, y + 1)) continue;
        size_t yb = j->base[y];
        for (size_t x = 1; x + 1 < nx; x++) {
            size_t cb = yb * nx + x, up = (y + 1) * nx + x;
            const size_t nb[4] = {0, 0, 0, up};
            const uint64_t *const onb[4] = {NULL, NULL, NULL, object_column(j, x, y + 1)};
            int32_t lo = j->zr[2 * up], hi = j->zr[2 * up + 1];
            for (uint32_t i = j->first[cb]; i < j->first[cb + 1]; i++) {
                int32_t z0 = j->runs[i].z0, z1 = j->runs[i].z1;
                if ((z0 < lo || z1 > hi) && touches_exterior(j, onb, nb, 3, z0, z1))
                    __atomic_store_n(&j->touched[i], 1, __ATOMIC_RELAXED);
            }
        }
    }
}

/* 3. The runs of column col joined with those of col - 1 (when with_left)
 * and col - nx (when with_prev). A column equal to col - 1 joins its runs
 * one to one with that one's, before anything else joins them (parent =
 * the other's root, no merge). When col - nx equals col - nx - 1 too, the
 * join with the row before is skipped: col - 1's join with it (or,
 * further left, that of the streak's first column) already links the same
 * runs through these one-to-one joins. */
static void join_column(const hull_job *j, size_t col, bool with_left, bool with_prev)
{
    const uint32_t *f = j->first;
    uint32_t a = f[col], na = f[col + 1] - a;
    if (!na) return;
    /* the row before's runs: its base's, when it is a twin */
    size_t y = col / j->nx, prev = j->base[y - 1] * j->nx + col % j->nx;
    if (j->same_left[col]) {
        if (with_left)
            for (uint32_t i = a; i < a + na; i++) j->parent[i] = bvox__uf_find(j->parent, i - na);
        if (j->same_left[prev]) return;
        with_left = false;
    }
    const size_t nb[2] = {col - 1, prev};
    const bool use[2] = {with_left, with_prev};
    for (int k = 0; k < 2; k++) {
        uint32_t b = f[nb[k]], n = f[nb[k] + 1] - b;
        if (use[k] && n) bvox__zruns_join(j->parent, j->runs + a, a, na, j->runs + b, b, n, 0);
    }
}

static size_t slab_row(const hull_job *j, int64_t s)
{
    return 1 + (size_t)s * (j->ny - 2) / (size_t)j->nslabs; /* the inner rows */
}

static void join_slabs(void *ctx, int64_t begin, int64_t end)
{
    const hull_job *j = ctx;
    for (int64_t s = begin; s < end; s++) {
        size_t y0 = slab_row(j, s), y1 = slab_row(j, s + 1);
        for (uint32_t i = j->first[y0 * j->nx]; i < j->first[y1 * j->nx]; i++) j->parent[i] = i;
        for (size_t y = y0; y < y1; y++) {
            if (twin_row(j, y)) continue; /* no runs of its own */
            /* the join with the row before when its runs are this slab's;
             * else the seams do it (a base before the slab) */
            bool with_prev = y > y0 && j->base[y - 1] >= y0;
            for (size_t x = 1; x + 1 < j->nx; x++) join_column(j, y * j->nx + x, true, with_prev);
        }
    }
}

/* 4. Every run's parent made its root, and the roots of the components
 * holding a touched run marked. Roots are the smallest run of their
 * component and parents never larger, so a walk up always ends; other
 * threads' stores only shorten it (relaxed atomics: any value seen is an
 * ancestor). */
static void root_ranges(void *ctx, int64_t begin, int64_t end)
{
    const hull_job *j = ctx;
    uint32_t *parent = j->parent;
    for (uint32_t i = (uint32_t)begin; i < (uint32_t)end; i++) {
        uint32_t r = i, p;
        while ((p = __atomic_load_n(&parent[r], __ATOMIC_RELAXED)) != r) r = p;
        __atomic_store_n(&parent[i], r, __ATOMIC_RELAXED);
        if (j->touched[i]) __atomic_store_n(&j->marked[r], 1, __ATOMIC_RELAXED);
    }
}

/* Per row: the 6-cavities' roots and K's runs (those of unmarked roots),
 * counted into kcount[y] and roots; then (kr set) listed at kcount[y] on,
 * with kfirst[col + 1] the end of column col's. */
typedef struct k_job {
    const hull_job *j;
    uint64_t *kcount;
    int64_t roots;
    bvox__zrun *kr;
    uint32_t *kfirst;
    uint64_t nk; /* K's runs in all */
} k_job;

static void k_rows(void *ctx, int64_t begin, int64_t end)
{
    k_job *k = ctx;
    const hull_job *j = k->j;
    int64_t roots = 0;
    for (size_t y = (size_t)begin; y < (size_t)end; y++) {
        size_t yb = j->base[y]; /* a twin lists its base's runs again */
        if (!k->kr) {
            /* the count: the row's runs are one index range (a twin's,
             * its base's count, is copied after this pass) */
            if (yb != y) continue;
            uint64_t n = 0;
            for (uint32_t i = j->first[y * j->nx]; i < j->first[(y + 1) * j->nx]; i++) {
                uint32_t r = j->parent[i];
                n += !j->marked[r], roots += !j->marked[r] && r == i;
            }
            k->kcount[y] = n;
            continue;
        }
        uint64_t n = k->kcount[y];
        if (n == (y + 1 < j->ny ? k->kcount[y + 1] : k->nk)) {
            /* none in this row (most rows: K is a few pockets) */
            for (size_t col = y * j->nx; col < (y + 1) * j->nx; col++)
                k->kfirst[col + 1] = (uint32_t)n;
            continue;
        }
        for (size_t col = y * j->nx, cb = yb * j->nx; col < (y + 1) * j->nx; col++, cb++) {
            for (uint32_t i = j->first[cb]; i < j->first[cb + 1]; i++)
                if (!j->marked[j->parent[i]]) k->kr[n++] = j->runs[i];
            k->kfirst[col + 1] = (uint32_t)n;
        }
    }
    if (!k->kr) __atomic_fetch_add(&k->roots, roots, __ATOMIC_RELAXED);
}

/* Both counts from the joined runs. */
static bvox_status count_cavities(const hull_job *j, uint32_t nruns, int64_t *cav6,
                                  int64_t *cav26)
{
    bvox__parallel_for((int64_t)nruns, 1 << 14, root_ranges, (void *)j);
    size_t ncol = j->nx * j->ny, ny = j->ny;
    bvox_status st = BVOX_OK;
    uint64_t *kcount = bvox__mem_alloc(ny * sizeof *kcount);
    size_t kfirst_bytes = (ncol + 1) * sizeof(uint32_t);
    uint32_t *kfirst = bvox__alloc(kfirst_bytes, false, "cavity run index", &st);
    bvox__zrun *kr = NULL;
    uint64_t nk = 0;
    if (!kfirst) goto done;
    if (!kcount) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory measuring cavities");
        goto done;
    }
    k_job k = {j, kcount, 0, NULL, kfirst, 0};
    bvox__parallel_for((int64_t)ny, 16, k_rows, &k);
    *cav6 = k.roots;
    if (!k.roots) goto done;
    for (size_t y = 0; y < ny; y++) kcount[y] = kcount[j->base[y]];
    for (size_t y = 0; y < ny; y++) {
        uint64_t n = kcount[y];
        kcount[y] = nk;
        nk += n;
    }
    kr = bvox__alloc((size_t)nk * sizeof *kr, false, "cavity runs", &st);
    if (!kr) goto done;
    k.kr = kr, k.nk = nk;
    kfirst[0] = 0;
    bvox__parallel_for((int64_t)ny, 16, k_rows, &k);
    st = bvox__cavities_26_runs(kr, kfirst, j->nx, j->ny, j->v, j->x0, j->y0, cav26);
done:
    if (kr) bvox__free(kr, (size_t)nk * sizeof *kr);
    bvox__free(kfirst, kfirst_bytes);
    free(kcount);
    return st;
}

/* 1. from the scan's hulls: the box's columns, the ring's left empty. */
typedef struct copy_job {
    hull_job *j;
    const bvox__colhull *hulls;
} copy_job;

static void copy_rows(void *ctx, int64_t begin, int64_t end)
{
    const copy_job *c = ctx;
    hull_job *j = c->j;
    size_t vnx = (size_t)j->v->nx;
    for (size_t y = (size_t)begin; y < (size_t)end; y++) {
        /* an inner row twin of an inner row (the scan's flag: the whole row
         * of the volume equals the one before, so the box's row does) owns
         * no runs; the ring's rows never are (their background is E) */
        bool twin = y >= 2 && y + 1 < j->ny && bvox__cavity_twin_rows &&
                    c->hulls[(j->y0 + y) * vnx + j->x0].twin_row;
        j->base[y] = (uint32_t)(twin ? y - 1 : y); /* the streak's first row after this pass */
        size_t nx = j->nx, col0 = y * nx;
        int32_t *zr = j->zr + 2 * col0;
        uint32_t *f = j->first + col0;
        /* the ring's columns have no hull: all their background is E */
        zr[0] = zr[1] = zr[2 * nx - 2] = zr[2 * nx - 1] = 0;
        f[0] = f[nx - 1] = 0;
        uint64_t row = 0;
        if (y == 0 || y + 1 == j->ny) {
            memset(zr, 0, 2 * nx * sizeof *zr);
            memset(f, 0, nx * sizeof *f);
        } else {
            const bvox__colhull *h = c->hulls + (j->y0 + y) * vnx + j->x0;
            for (size_t x = 1; x + 1 < nx; x++) {
                zr[2 * x] = h[x].lo, zr[2 * x + 1] = h[x].hi;
                uint32_t n = twin ? 0 : h[x].runs;
                f[x] = n;
                row += n;
            }
        }
        j->rowsum[y] = row;
    }
}

/* The columns' counts turned into their first runs' indices, a row at a
 * time from the row's own (rowsum, summed). */
static void offset_rows(void *ctx, int64_t begin, int64_t end)
{
    const hull_job *j = ctx;
    for (size_t y = (size_t)begin; y < (size_t)end; y++) {
        uint32_t at = (uint32_t)j->rowsum[y];
        for (size_t col = y * j->nx; col < (y + 1) * j->nx; col++) {
            uint32_t n = j->first[col];
            j->first[col] = at;
            at += n;
        }
    }
}

bvox_status bvox__cavities_from_hull_runs(const bvox_volume *vol, const bvox__colhull *hulls,
                                          size_t x0, size_t y0, size_t nx, size_t ny,
                                          int64_t *cav6, int64_t *cav26)
{
    *cav6 = *cav26 = 0;
    if (nx < 3 || ny < 3) return BVOX_OK; /* every column in the ring: U is empty */
    size_t ncol = nx * ny;
    bvox_status st = BVOX_OK;
    hull_job j = {vol, x0, y0, nx, ny, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, 1};
    size_t zr_bytes = 2 * ncol * sizeof *j.zr, run_bytes = 0;
    /* the per-column arrays from the budget, whose cached mappings spare a
     * call the faults of fresh pages */
    size_t first_bytes = (ncol + 1) * sizeof *j.first;
    j.zr = bvox__alloc(zr_bytes, false, "column hulls", &st);
    if (j.zr) j.first = bvox__alloc(first_bytes, false, "column run index", &st);
    if (j.first) j.same_left = bvox__alloc(ncol, true, "column equalities", &st);
    if (j.same_left) j.rowsum = bvox__mem_alloc(ny * sizeof *j.rowsum);
    if (j.rowsum) j.base = bvox__mem_alloc(ny * sizeof *j.base);
    if (j.same_left && !j.base) st = bvox__fail(BVOX_ENOMEM, "out of memory measuring cavities");
    if (st) goto done;
    copy_job cj = {&j, hulls};
    bvox__parallel_for((int64_t)ny, 64, copy_rows, &cj);
    for (size_t y = 0; y < ny; y++) j.base[y] = j.base[j.base[y]]; /* the row before's base */
    uint64_t total = 0;
    for (size_t y = 0; y < ny; y++) {
        uint64_t n = j.rowsum[y];
        j.rowsum[y] = total;
        total += n;
    }
    if (total >= UINT32_MAX) {
        st = bvox__fail(BVOX_ETOOBIG, "more than %u background runs: too many to label",
                        (unsigned)(UINT32_MAX - 1));
        goto done;
    }
    if (!total) goto done;
    bvox__parallel_for((int64_t)ny, 64, offset_rows, &j);
    j.first[ncol] = (uint32_t)total;
    /* runs, parents, touched and marked flags in one block from the budget */
    run_bytes = (size_t)total * (sizeof *j.runs + sizeof *j.parent + 2);
    j.runs = bvox__alloc(run_bytes, false, "enclosed background runs", &st);
    if (!j.runs) goto done;
    j.parent = (uint32_t *)(j.runs + total);
    j.touched = (uint8_t *)(j.parent + total);
    j.marked = j.touched + total;
    memset(j.marked, 0, total);
    bvox__parallel_for((int64_t)ny - 2, 8, list_rows, &j);
    bvox__parallel_for((int64_t)ny - 2, 8, twin_touch_rows, &j);
    /* slabs of at least 16 rows: the seams redo one row each */
    int threads = bvox__parallelism();
    int64_t max_slabs = (int64_t)(ny - 2) / 16;
    j.nslabs = threads < max_slabs ? threads : (max_slabs > 0 ? max_slabs : 1);
    bvox__parallel_for(j.nslabs, 1, join_slabs, &j);
    for (int64_t s = 1; s < j.nslabs; s++) {
        /* the slab's first row with runs of its own, joined with the row
         * before (or that one's base), which lies in an earlier slab */
        size_t y = slab_row(&j, s), y1 = slab_row(&j, s + 1);
        while (y < y1 && twin_row(&j, y)) y++;
        if (y < y1)
            for (size_t x = 1; x + 1 < nx; x++) join_column(&j, y * nx + x, false, true);
    }
    st = count_cavities(&j, (uint32_t)total, cav6, cav26);
done:
    if (j.runs) bvox__free(j.runs, run_bytes);
    bvox__free(j.same_left, ncol);
    free(j.base);
    free(j.rowsum);
    bvox__free(j.first, first_bytes);
    if (j.zr) bvox__free(j.zr, zr_bytes);
    return st;
}
