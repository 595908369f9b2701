/*
 * measure_scan.c — one pass over the words for bvox_measure.
 *
 * Vertex windows. Every lattice vertex (x, y, z), 0 <= x <= nx etc., is the
 * centre of a 2x2x2 window of voxels (x-1|x, y-1|y, z-1|z); voxels outside the
 * volume are 0. Four voxel columns a = (x-1, y-1), b = (x, y-1), c = (x-1, y),
 * d = (x, y) hold a vertex column's windows, and for 64 vertices at once each
 * column gives two words: "hi" (the voxels at z, the column word itself) and
 * "lo" (the voxels at z-1: the word shifted up by one, carrying the top bit of
 * the previous word). Eight words thus hold 64 windows, one bit each.
 *
 * Everything measured is a sum over windows of something local, so it is a
 * few popcounts of ANDs/ORs/XORs of those eight words, never a loop over
 * voxels or over the 256 window patterns:
 *  - Euler number of the union of the closed voxel cubes, V - E + F - C, each
 *    cell of the cube complex counted at its lowest vertex: the vertex is in
 *    the complex when any of its 8 voxels is set (OR of 8 words), the three
 *    edges leaving it upwards when any of their 4 voxels is (OR of 4), the
 *    three faces when either of their 2 voxels is, the cube when its voxel d.hi
 *    is. This equals the per-pattern octant formula (Lobregt, Toriwaki) summed
 *    over the 2x2x2 configuration histogram, without building the histogram.
 *    Only V - E is counted per window: a face's two voxels p, d.hi (p = d.lo,
 *    c.hi, b.hi) give popcount(p | d) = (popcount(p) + popcount(d) +
 *    popcount(p ^ d)) / 2, and p ^ d is the window's transition along that
 *    face's axis; every voxel is each of d.lo, c.hi, b.hi and d.hi of exactly
 *    one window, so over the volume F - C = 2 count + (tx + ty + tz) / 2,
 *    added once from the scan's totals (4 of 21 popcounts saved a window).
 *  - 0/1 transitions between the voxel pairs of each window along the 13
 *    directions, each pair counted in exactly one window: along x c.hi^d.hi,
 *    along y b.hi^d.hi, along z d.lo^d.hi, and so on for the diagonals. The
 *    axis ones are the exposed faces; all 13 feed the Crofton area (the
 *    Crofton look-up table over 256 patterns is a sum over pairs too).
 * Windows that are all 0 or all 1 contribute nothing to either (an all-1
 * one only its V - E = 1 - 3, to balance the totals), so words whose 64
 * windows are all uniform (the inside and outside of an object) are skipped
 * after one OR and one AND.
 *
 * The popcounts dominate. On x86-64 BVOX_SIMD=avx512 (the default on CPUs
 * with AVX512F/BW/VL and VPOPCNTDQ) uses measure_scan_avx512.c's kernels,
 * eight z-words of the four columns at once; avx2 measure_scan_avx2.c's
 * (four words, popcounts by nibble look-ups); generic the portable ones
 * (a clone compiled for the POPCNT instruction where the CPU has it but not
 * AVX2), the reference: the
 * tests compare every integer of the scan at each level.
 *
 * Moments come from runs along z: a column's sums over its 1-voxels of 1, z
 * and z^2 are sums over run ends of prefix sums P(end) minus the same over run
 * starts, P(m) = sum_{z<m} z^k in closed form, so a run costs two terms
 * however long it is, and starts/ends are found 64 at a time.
 */
#include "measure/measure_scan.h"

#include <stdlib.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__)
#define HAVE_POPCNT_CLONE 1
#endif

typedef struct scan_job {
    const bvox_volume *v;
    const uint64_t *zero; /* a zero column standing for columns outside */
    int64_t nblocks;
    bvox__scan *parts;    /* one per block, reduced in block order */
    bvox__cells_row_fn cells;
    bvox__moments_fn moments;
    bvox__row_moments_fn row_moments; /* or NULL: moments column by column */
    bvox__colhull *hulls; /* or NULL */
} scan_job;

/* The windows of one vertex row, a word of 4 columns at a time (the
 * portable reference of the vector kernels). hw: use the POPCNT
 * instruction (only inlined into a clone built for it). */
static inline __attribute__((always_inline)) void
cells_body(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc, bool extra,
           const uint64_t *zero, bvox__scan *s, bool hw)
{
    int64_t eul = 0, t[BVOX__NDIR] = {0};
    size_t nw = wpc + (extra ? 1 : 0);
    for (size_t x = 0; x <= nx; x++) {
        const uint64_t *col[4];
        bvox__cells_cols(prev, cur, x, nx, wpc, zero, col);
        const uint64_t *A = col[0], *B = col[1], *C = col[2], *D = col[3];
        uint64_t ca = 0, cb = 0, cc = 0, cd = 0; /* top bits of the previous words */
        for (size_t k = 0; k < nw; k++) {
            uint64_t ah = 0, bh = 0, ch = 0, dh = 0;
            if (k < wpc) ah = A[k], bh = B[k], ch = C[k], dh = D[k];
            uint64_t al = (ah << 1) | ca, bl = (bh << 1) | cb, cl = (ch << 1) | cc,
                     dl = (dh << 1) | cd;
            ca = ah >> 63, cb = bh >> 63, cc = ch >> 63, cd = dh >> 63;
            bvox__cells_word(ah, bh, ch, dh, al, bl, cl, dl, &eul, t, hw);
        }
    }
    s->euler += eul;
    for (int i = 0; i < BVOX__NDIR; i++) s->trans[i] += t[i];
}

static void cells_generic(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc,
                          bool extra, const uint64_t *zero, bvox__scan *s)
{
    cells_body(prev, cur, nx, wpc, extra, zero, s, false);
}

#ifdef HAVE_POPCNT_CLONE
__attribute__((target("popcnt"))) static void
cells_popcnt(const uint64_t *prev, const uint64_t *cur, size_t nx, size_t wpc, bool extra,
             const uint64_t *zero, bvox__scan *s)
{
    cells_body(prev, cur, nx, wpc, extra, zero, s, true);
}
#endif

static bvox__cells_row_fn choose_cells(void)
{
#ifdef HAVE_POPCNT_CLONE
    if (bvox__cells_row_avx512 && bvox__simd_files(BVOX_SIMD_AVX512))
        return bvox__cells_row_avx512;
    if (bvox__cells_row_avx2 && bvox__simd_files(BVOX_SIMD_AVX2)) return bvox__cells_row_avx2;
    if (bvox_simd_active() != BVOX_SIMD_GENERIC && __builtin_cpu_supports("popcnt"))
        return cells_popcnt;
#endif
    return cells_generic;
}

/* Bit t of a word is in mask b when bit b of t is 1: the moments' sums of
 * the bit indices t and t^2 over a word are popcounts of the word ANDed
 * with these. */
static const uint64_t bit_of_index[6] = {0xaaaaaaaaaaaaaaaaull, 0xccccccccccccccccull,
                                         0xf0f0f0f0f0f0f0f0ull, 0xff00ff00ff00ff00ull,
                                         0xffff0000ffff0000ull, 0xffffffff00000000ull};

/* The hull of column x of the current row (s->hull_row), a column with an
 * object voxel, words col, first and last object voxel zlo and zhi - 1.
 * popcnt: the instruction may be used. */
static inline __attribute__((always_inline)) void
hull_add(bvox__scan *s, int32_t x, const uint64_t *col, int32_t zlo, int32_t zhi, bool popcnt)
{
    uint32_t runs = 0;
    uint64_t carry = 0; /* the words below zlo's are 0 */
    for (size_t w = (size_t)zlo / 64; w <= (size_t)(zhi - 1) / 64; w++) {
        uint64_t starts = col[w] & ~((col[w] << 1) | carry);
        runs += popcnt ? (uint32_t)__builtin_popcountll(starts) : bvox__popcount64(starts);
        carry = col[w] >> 63;
    }
    s->hull_row[x] = (bvox__colhull){zlo + 1, zhi - 1, runs - 1, 0};
}

/* Prefix sums over z < m of 1, z and z^2 (m <= 65536: fits easily). */
static inline int64_t p1(int64_t m) { return m * (m - 1) / 2; }
static inline int64_t p2(int64_t m) { return (m - 1) * m * (2 * m - 1) / 6; }

/* Count, sums and z range of the 1-voxels of one voxel column. Each word is
 * summed on its own: a word of few runs (the usual case) by its run
 * boundaries, P(end) - P(start); a word of many runs (a noisy volume has 16)
 * by popcounts: with t the bit index, sum t = sum_b 2^b |w & M_b| and
 * sum t^2 = sum_{b,c} 2^(b+c) |w & M_b & M_c|, 27 popcounts whatever the
 * runs, then shifted by the word's base z. */
static inline __attribute__((always_inline)) void
moments_body(const uint64_t *col, size_t wpc, int32_t x, int32_t y, bvox__scan *s, bool hw)
{
#define pc(w) ((int64_t)(hw ? (unsigned)__builtin_popcountll(w) : bvox__popcount64(w)))
    int64_t n = 0, sz = 0, szz = 0;
    int32_t zlo = -1, zhi = -1;
    for (size_t k = 0; k < wpc; k++) {
        uint64_t w = col[k];
        if (!w) continue;
        int64_t base = (int64_t)k * 64;
        if (zlo < 0) zlo = (int32_t)(base + __builtin_ctzll(w));
        zhi = (int32_t)(base + 64 - __builtin_clzll(w));
        uint64_t starts = w & ~(w << 1); /* runs cut at the word's edges */
        if (pc(starts) <= 4) {
            uint64_t ends = w & ~(w >> 1);
            for (; starts; starts &= starts - 1) {
                int64_t z = base + __builtin_ctzll(starts);
                n -= z, sz -= p1(z), szz -= p2(z);
            }
            for (; ends; ends &= ends - 1) {
                int64_t z = base + __builtin_ctzll(ends) + 1;
                n += z, sz += p1(z), szz += p2(z);
            }
            continue;
        }
        int64_t c = pc(w), t1 = 0, t2 = 0;
        for (int b = 0; b < 6; b++) {
            uint64_t wb = w & bit_of_index[b];
            int64_t cb = pc(wb);
            t1 += cb << b;
            t2 += cb << (2 * b);
            for (int d = b + 1; d < 6; d++) t2 += pc(wb & bit_of_index[d]) << (b + d + 1);
        }
        n += c;
        sz += base * c + t1;
        szz += base * base * c + 2 * base * t1 + t2;
    }
#undef pc
    if (zlo < 0) {
        if (s->hull_row) s->hull_row[x] = (bvox__colhull){0, 0, 0, 0};
        return;
    }
    bvox__moments_add(s, x, y, n, sz, szz, zlo, zhi);
    if (s->hull_row) hull_add(s, x, col, zlo, zhi, hw);
}

static void moments_generic(const uint64_t *col, size_t wpc, int32_t x, int32_t y,
                            bvox__scan *s)
{
    moments_body(col, wpc, x, y, s, false);
}

#ifdef HAVE_POPCNT_CLONE
__attribute__((target("popcnt"))) static void
moments_popcnt(const uint64_t *col, size_t wpc, int32_t x, int32_t y, bvox__scan *s)
{
    moments_body(col, wpc, x, y, s, true);
}
#endif

/* The moments and hulls of voxel row y (words cur) into s. twin: the row
 * equals row y - 1; when that row was this block's (last_valid: its sums
 * are last[], its hull records written) they are taken over and the box
 * grown by the row. Every hull record of a twin row then says so. */
static void row_moments_of(const scan_job *j, const uint64_t *cur, int64_t y, bool twin,
                           bool last_valid, const uint64_t last[6], bvox__scan *s)
{
    size_t nx = (size_t)j->v->nx, wpc = j->v->wpc;
    s->hull_row = j->hulls ? j->hulls + (size_t)y * nx : NULL;
    if (twin && last_valid) {
        memcpy(s->row, last, sizeof s->row);
        if (last[0]) s->bbox[4] = (int32_t)y + 1; /* the row before is in the box */
        if (s->hull_row) memcpy(s->hull_row, s->hull_row - nx, nx * sizeof *s->hull_row);
    } else if (j->row_moments) {
        j->row_moments(cur, nx, wpc, (int32_t)y, s);
    } else {
        for (size_t x = 0; x < nx; x++) j->moments(cur + x * wpc, wpc, (int32_t)x, (int32_t)y, s);
    }
    /* the kernels write records saying "no twin" */
    if (s->hull_row && twin)
        for (size_t x = 0; x < nx; x++) s->hull_row[x].twin_row = 1;
}

static void scan_range(void *ctx, int64_t begin, int64_t end)
{
    scan_job *j = ctx;
    const bvox_volume *v = j->v;
    size_t wpc = v->wpc, nx = (size_t)v->nx;
    bool extra = (v->nz & 63) == 0;
    int64_t rows = (int64_t)v->ny + 1;
    for (int64_t b = begin; b < end; b++) {
        bvox__scan *s = &j->parts[b];
        int64_t y0 = rows * b / j->nblocks;
        uint64_t last[6]; /* the sums of the row before, when it is this block's */
        /* the cells of the vertex row before, when it lay between two equal
         * rows (a twin): the next one between the same rows has the same */
        int64_t twin_eul = 0, twin_t[BVOX__NDIR] = {0};
        bool twin_cells = false;
        for (int64_t y = y0; y < rows * (b + 1) / j->nblocks; y++) {
            const uint64_t *prev = y > 0 ? v->words + (size_t)(y - 1) * nx * wpc : NULL;
            const uint64_t *cur = y < v->ny ? v->words + (size_t)y * nx * wpc : NULL;
            /* a row equal to the one before: one compare of words the
             * cells kernel reads anyway, against the moments kernel */
            bool twin = prev && cur && !memcmp(cur, prev, nx * wpc * sizeof *cur);
            if (twin && twin_cells) {
                /* rows y - 2, y - 1 and y equal: these windows are the last ones */
                s->euler += twin_eul;
                for (int i = 0; i < BVOX__NDIR; i++) s->trans[i] += twin_t[i];
            } else {
                int64_t eul = s->euler, t[BVOX__NDIR];
                memcpy(t, s->trans, sizeof t);
                j->cells(prev, cur, nx, wpc, extra, j->zero, s);
                twin_eul = s->euler - eul;
                for (int i = 0; i < BVOX__NDIR; i++) twin_t[i] = s->trans[i] - t[i];
            }
            twin_cells = twin;
            if (cur) {
                row_moments_of(j, cur, y, twin, y > y0, last, s);
                memcpy(last, s->row, sizeof last);
                bvox__moments_row(s, (int32_t)y);
            }
        }
    }
}

bvox_status bvox__measure_scan(const bvox_volume *vol, bvox__scan *out)
{
    return bvox__measure_scan_hulls(vol, NULL, out);
}

bvox_status bvox__measure_scan_hulls(const bvox_volume *vol, bvox__colhull *hulls,
                                     bvox__scan *out)
{
    memset(out, 0, sizeof *out);
    int64_t rows = (int64_t)vol->ny + 1;
    /* blocks of 8 rows or more: a block's first row cannot take over the
     * sums of a row before it that another block computes (twin rows) */
    int64_t nblocks = rows / 8 < 256 ? (rows / 8 > 0 ? rows / 8 : 1) : 256;
    uint64_t *zero = bvox__mem_zalloc(vol->wpc, sizeof *zero);
    bvox__scan *parts = bvox__mem_zalloc((size_t)nblocks, sizeof *parts);
    if (!zero || !parts) {
        free(zero);
        free(parts);
        return bvox__fail(BVOX_ENOMEM, "out of memory measuring a volume");
    }
    bvox__cells_row_fn cells = choose_cells();
    bvox__moments_fn moments = moments_generic;
    bvox__row_moments_fn row_moments = NULL;
#ifdef HAVE_POPCNT_CLONE
    if (cells == bvox__cells_row_avx512) row_moments = bvox__row_moments_avx512;
    else if (cells == bvox__cells_row_avx2) row_moments = bvox__row_moments_avx2;
    else if (cells != cells_generic) moments = moments_popcnt;
#endif
    scan_job job = {vol, zero, nblocks, parts, cells, moments, row_moments, hulls};
    /* Threads only pay off from about 64K words each. */
    int64_t per_block = (int64_t)((vol->nwords + (size_t)vol->nx * vol->wpc) / (size_t)nblocks) + 1;
    int64_t min_blocks = ((int64_t)1 << 16) / per_block + 1;
    bvox__parallel_for(nblocks, min_blocks, scan_range, &job);
    for (int64_t b = 0; b < nblocks; b++) {
        const bvox__scan *p = &parts[b];
        if (p->count) {
            if (!out->count) memcpy(out->bbox, p->bbox, sizeof out->bbox);
            for (int a = 0; a < 3; a++) {
                if (p->bbox[a] < out->bbox[a]) out->bbox[a] = p->bbox[a];
                if (p->bbox[a + 3] > out->bbox[a + 3]) out->bbox[a + 3] = p->bbox[a + 3];
            }
        }
        out->count += p->count;
        for (int a = 0; a < 3; a++) out->s[a] += p->s[a];
        for (int a = 0; a < 6; a++) out->ss[a] += p->ss[a];
        out->euler += p->euler;
        for (int a = 0; a < BVOX__NDIR; a++) out->trans[a] += p->trans[a];
    }
    /* the Euler number's F - C (header comment); each axis's transitions
     * come in pairs along its lines, so their sum is even */
    out->euler += 2 * out->count +
                  (out->trans[BVOX__DIR_X] + out->trans[BVOX__DIR_Y] + out->trans[BVOX__DIR_Z]) / 2;
    free(zero);
    free(parts);
    return BVOX_OK;
}
