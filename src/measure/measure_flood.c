/*
 * measure_flood.c — the background reached from the border, for the
 * cavities of bvox_measure (measure_cavities.c): a flood fill over whole
 * words instead of a labelling of every background run.
 *
 * On a coin toss the background has a run every four voxels of a column (34
 * million at 512^3), nearly all of them in the one 6-component that reaches
 * the border; a 6-labelling spends a union per run contact on it, three
 * times the cost of the object's 26-labelling. The reached set R (background
 * voxels 6-connected to the border) is instead grown by raster sweeps,
 * alternately forward and backward over the columns, each column taking
 * R = fill_z(bg, R | R of its four neighbours): 64 voxels per operation,
 * along z within the runs of the column by an addition (upwards) and a
 * Kogge-Stone fill (downwards). Gauss-Seidel order carries a front along a
 * whole monotone path in one sweep; a coin toss settles in about ten sweeps,
 * most of which only test columns (nothing changes). The cavities are then
 * bg & ~R, a few sparse pockets, labelled alone.
 *
 * A winding corridor needs a sweep per turn: after max_sweeps without
 * settling the caller falls back to the labelling (exact either way).
 * Later sweeps change a few columns: a column is visited only when one of
 * its four neighbours changed in the sweep before or so far in this one
 * (else its inputs are as at its last visit, which left it settled), and a
 * row only when it or a neighbour row changed. On a 512^3 coin toss the
 * sweeps after the fourth grow fewer than 4000 of 260000 columns; visiting
 * only the columns due took the flood from 64 to 59 ms at 1 thread.
 *
 * A column of up to eight words is one AVX-512 vector: measure_flood_avx512.c
 * sweeps a row so, at the avx512 SIMD level (59 to 24 ms); or two AVX2
 * vectors, measure_flood_avx2.c (59 to 34 ms on the same Xeon).
 *
 * Threads: the rows are split into one slab per thread, every sweep of every
 * slab in the same direction. A column may read its neighbour in another
 * slab while that one is being written (relaxed atomics: any value read is a
 * subset of the final R, since R only grows); a sweep in which no thread
 * changed anything is a fixed point, so the result does not depend on the
 * interleaving.
 */
#include "measure/measure.h"

/* Kogge-Stone fill of seeds x downwards (towards bit 0) through the bits of m. */
static inline uint64_t fill_down(uint64_t x, uint64_t m)
{
    uint64_t p = m;
    x |= p & (x >> 1), p &= p >> 1;
    x |= p & (x >> 2), p &= p >> 2;
    x |= p & (x >> 4), p &= p >> 4;
    x |= p & (x >> 8), p &= p >> 8;
    x |= p & (x >> 16), p &= p >> 16;
    x |= p & (x >> 32);
    return x;
}

/* s (wpc words, each a subset of the column m) becomes the union of the
 * runs of m holding a bit of s. Upwards: m + s carries from the lowest seed
 * of a run through its top, clearing it, so m & ~(m + s) | s is seed..top;
 * the carry out of bit 63 continues the run in the next word. */
static void fill_column(const uint64_t *m, uint64_t *s, size_t wpc)
{
    uint64_t c = 0;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t mk = m[k], sk = (s[k] | c) & mk, t = mk + sk;
        s[k] = (mk & ~t) | sk;
        c = t < mk;
    }
    c = 0;
    for (size_t k = wpc; k-- > 0;) {
        /* a bit to fill lies just below a reached one (or the word above's
         * bit 0): most words of a short-run column have none */
        uint64_t sk = s[k] | (c & m[k]);
        if (m[k] & ~sk & ((sk >> 1) | c)) sk = fill_down(sk, m[k]);
        s[k] = sk;
        c = sk << 63;
    }
}

#define LOAD(p) __atomic_load_n((p), __ATOMIC_RELAXED)

/* Column x of row w; 1 when it grew. m and t: wpc words of scratch. */
static int sweep_column(const bvox__flood_row *w, size_t x, uint64_t *m, uint64_t *t)
{
    size_t wpc = w->wpc;
    uint64_t *r = w->r + x * wpc;
    const uint64_t *we = r - wpc, *e = r + wpc, *s = r - w->nx * wpc, *n = r + w->nx * wpc;
    const uint64_t *src = w->bg + x * wpc;
    for (size_t k = 0; k < wpc; k++) m[k] = src[k] ^ w->flip;
    m[wpc - 1] &= w->tail;
    uint64_t grew = 0;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t old = LOAD(&r[k]);
        uint64_t nb = LOAD(&we[k]) | LOAD(&e[k]) | LOAD(&s[k]) | LOAD(&n[k]);
        t[k] = (old | nb) & m[k];
        grew |= t[k] ^ old;
    }
    /* the column's ends lie on the border: z = 0 and z = nz - 1 */
    t[0] |= m[0] & 1;
    t[wpc - 1] |= m[wpc - 1] & w->top;
    grew |= (t[0] ^ LOAD(&r[0])) | (t[wpc - 1] ^ LOAD(&r[wpc - 1]));
    if (!grew) return 0;
    fill_column(m, t, wpc);
    for (size_t k = 0; k < wpc; k++) __atomic_store_n(&r[k], t[k], __ATOMIC_RELAXED);
    return 1;
}

static int sweep_row(const bvox__flood_row *w)
{
    uint64_t m[(BVOX_MAX_DIM + 63) / 64], t[(BVOX_MAX_DIM + 63) / 64];
    int changed = 0;
    for (size_t xi = 1; xi + 1 < w->nx; xi++) {
        size_t x = w->backward ? w->nx - 1 - xi : xi;
        if (!bvox__flood_due(w, w->stamps + x) || !sweep_column(w, x, m, t)) continue;
        __atomic_store_n(&w->stamps[x], w->sweep, __ATOMIC_RELAXED);
        changed = 1;
    }
    return changed;
}

typedef struct flood_job {
    const bvox__bgsrc *bg; /* the background, nx * ny columns */
    uint64_t *r;       /* reached, grows */
    size_t nx, ny, wpc;
    uint64_t top;      /* bit of z = nz - 1 in a column's last word */
    int32_t *row_sweep; /* per row: the last sweep that changed it, -1 */
    int32_t *col_sweep; /* per column, the same */
    bvox__flood_row_fn row_fn;
    int64_t nslabs;
    int sweep, backward;
    int changed;
} flood_job;

static void sweep_slabs(void *ctx, int64_t begin, int64_t end)
{
    flood_job *j = ctx;
    const bvox__bgsrc *bg = j->bg;
    int changed = 0;
    for (int64_t sl = begin; sl < end; sl++) {
        /* rows 1 .. ny - 2: the border ring is reached from the start */
        size_t inner = j->ny - 2;
        size_t y0 = 1 + (size_t)sl * inner / (size_t)j->nslabs;
        size_t y1 = 1 + (size_t)(sl + 1) * inner / (size_t)j->nslabs;
        for (size_t i = 0; i < y1 - y0; i++) {
            size_t y = j->backward ? y1 - 1 - i : y0 + i;
            int32_t last = LOAD(&j->row_sweep[y - 1]), mid = LOAD(&j->row_sweep[y]),
                    next = LOAD(&j->row_sweep[y + 1]);
            if (last < j->sweep - 1 && mid < j->sweep - 1 && next < j->sweep - 1) continue;
            bvox__flood_row w = {bg->words + ((bg->y0 + y) * bg->nx + bg->x0) * j->wpc,
                                 j->r + y * j->nx * j->wpc,
                                 j->col_sweep + y * j->nx,
                                 j->nx,
                                 j->wpc,
                                 bg->flip,
                                 bg->tail,
                                 j->top,
                                 j->sweep,
                                 j->backward};
            if (!j->row_fn(&w)) continue;
            __atomic_store_n(&j->row_sweep[y], j->sweep, __ATOMIC_RELAXED);
            changed = 1;
        }
    }
    if (changed) __atomic_store_n(&j->changed, 1, __ATOMIC_RELAXED);
}

/* A SIMD row when the active SIMD level allows it and a column fits eight
 * words. ThreadSanitizer does not see its vector loads of the words other
 * threads store as the relaxed atomic loads they stand for (on x86-64 each
 * aligned 8-byte lane is read whole; and any mix of a word's old and new
 * bits is still a subset of R), so its builds take the portable row. */
static bvox__flood_row_fn choose_row(size_t wpc)
{
#if defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
    if (wpc <= 8 && bvox__flood_row_avx512 && bvox_simd_active() >= BVOX_SIMD_AVX512 &&
        __builtin_cpu_supports("avx512f"))
        return bvox__flood_row_avx512;
    if (wpc <= 8 && bvox__flood_row_avx2 && bvox_simd_active() >= BVOX_SIMD_AVX2 &&
        __builtin_cpu_supports("avx2"))
        return bvox__flood_row_avx2;
#else
    (void)wpc;
#endif
    return sweep_row;
}

/* Sweeps until one changes nothing (true) or max_sweeps were spent. */
static bool run_sweeps(const bvox__bgsrc *bg, size_t nx, size_t ny, size_t wpc, uint64_t top,
                       int max_sweeps, uint64_t *reached, int32_t *stamps)
{
    /* every row and column visited first */
    for (size_t i = 0; i < ny + nx * ny; i++) stamps[i] = -1;
    flood_job j = {bg, reached, nx, ny, wpc, top, stamps, stamps + ny, choose_row(wpc), 1, 0, 0, 0};
    int64_t threads = bvox__parallelism(), max_slabs = (int64_t)(ny - 2) / 8;
    j.nslabs = threads < max_slabs ? threads : (max_slabs > 0 ? max_slabs : 1);
    for (int sweep = 0; sweep < max_sweeps; sweep++) {
        j.sweep = sweep;
        j.backward = sweep & 1;
        j.changed = 0;
        bvox__parallel_for(j.nslabs, 1, sweep_slabs, &j);
        if (!j.changed) return true;
    }
    return false;
}

bool bvox__flood_border(const bvox__bgsrc *bg, size_t nx, size_t ny, size_t wpc, size_t nz,
                        int max_sweeps, uint64_t *reached, int32_t *stamps)
{
    /* the border ring of columns: all of their background is reached */
    for (size_t y = 0; y < ny; y++)
        for (size_t x = 0; x < nx; x++)
            if (x == 0 || y == 0 || x + 1 == nx || y + 1 == ny) {
                uint64_t *col = reached + (y * nx + x) * wpc;
                for (size_t k = 0; k < wpc; k++) col[k] = bvox__bg_word(bg, x, y, wpc, k);
            }
    if (nx < 3 || ny < 3) return true; /* every column is on the ring */
    return run_sweeps(bg, nx, ny, wpc, 1ull << ((nz - 1) % 64), max_sweeps, reached, stamps);
}
