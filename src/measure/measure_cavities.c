/*
 * measure_cavities.c — the cavities of bvox_measure: 6-connected background
 * components that do not reach the border, and how many 26-connected ones
 * they make up.
 *
 * Only the columns of the object's x-y bounding box grown by one are
 * labelled: every background voxel outside that box reaches the border along
 * a straight line, and the ring of columns around the box is all background,
 * so joining the box's border runs to "outside" is exact. z is kept whole so
 * that no word is shifted.
 *
 * Of that background only the part U enclosed along z (between the first
 * and the last object voxel of its column) can hold a cavity: the rest sees
 * the border along z. U alone is labelled 6-connected, and a component is a
 * cavity unless one of its voxels touches the rest across x or y
 * (measure_enclosed.c; the roots of such components are marked in parallel,
 * no union-find). bvox__cavity_hull = 0 labels all of the background
 * instead, its border runs joined to "outside" (the route before U).
 *
 * 26-connected cavities are unions of 6-connected ones (a background
 * component touching the border contains a 6-connected one that does), so
 * after the 6-connected labelling only the cavity voxels K are looked at
 * again: a 26-component of K is a 26-cavity unless one of its voxels is a
 * 26-neighbour of the exterior E (background minus K). K is cleared out of
 * the labelled words in place (or, when its columns' box is small, copied
 * into that box), labelled 26-connected, and the roots of the runs holding
 * a voxel of T = K & dilate26(E), formed word by word where K has voxels,
 * are marked; the unmarked roots are the 26-cavities. This replaces a
 * second labelling of the whole background, except when the cavities are
 * everywhere on the whole-background route (see label_all_26).
 *
 * When the background percolates with many runs (a coin toss: 34 million
 * runs at 512^3, nearly all in the component that reaches the border) even
 * the 6-labelling is too dear: the flood of measure_flood.c finds the
 * reached background R with whole-word sweeps, and K = bg & ~R is labelled
 * alone (cavities_by_flood, flood_pays). All routes are exact; the
 * labelling stays for the rest and for a flood that does not settle.
 */
#include "measure/measure.h"
#include "ops/components_label.h"

#include <stdlib.h>
#include <string.h>

/* Columns [x0, x1) x [y0, y1) of a volume-sized word array, all wpc words. */
typedef struct colbox {
    size_t x0, y0, nx, ny;
} colbox;

typedef struct extract_job {
    const bvox_volume *v;
    colbox b;
    uint64_t *dst;
} extract_job;

/* The complement of the box's columns (bits beyond nz stay 0). */
static void extract_rows(void *ctx, int64_t begin, int64_t end)
{
    const extract_job *j = ctx;
    size_t wpc = j->v->wpc, nx = (size_t)j->v->nx;
    for (int64_t y = begin; y < end; y++) {
        const uint64_t *src = j->v->words + (((size_t)y + j->b.y0) * nx + j->b.x0) * wpc;
        uint64_t *dst = j->dst + (size_t)y * j->b.nx * wpc;
        size_t n = j->b.nx * wpc;
        for (size_t i = 0; i < n; i++) dst[i] = ~src[i];
        for (size_t c = wpc - 1; c < n; c += wpc) dst[c] &= j->v->tail_mask;
    }
}

/* Roots among parent[begin, end), those with touched[root] set left out
 * (touched NULL: none is). */
typedef struct root_job {
    const uint32_t *parent;
    const uint8_t *touched;
    int64_t roots;
} root_job;

static void count_roots(void *ctx, int64_t begin, int64_t end)
{
    root_job *j = ctx;
    int64_t n = 0;
    for (int64_t i = begin; i < end; i++)
        n += j->parent[i] == (uint32_t)i && !(j->touched && j->touched[i]);
    __atomic_fetch_add(&j->roots, n, __ATOMIC_RELAXED);
}

/* Components among the runs and the outside node (index nruns), the
 * outside's own not counted. */
static int64_t count_inner(const bvox__labelruns *r)
{
    root_job j = {r->parent, NULL, 0};
    bvox__parallel_for((int64_t)r->nruns + 1, 1 << 16, count_roots, &j);
    return j.roots - 1;
}

/* Roots are the smallest run of their component and parent[i] <= i, so one
 * pass in order makes every parent a root. */
static void flatten(bvox__labelruns *r)
{
    uint32_t *parent = r->parent;
    for (size_t i = 0; i <= r->nruns; i++) parent[i] = parent[parent[i]];
}

/* 64 z-neighbourhoods of a column word: w with its voxels at z - 1 and
 * z + 1 (prev/next: the words below and above, 0 outside). */
static inline uint64_t zdilate(uint64_t prev, uint64_t w, uint64_t next)
{
    return w | (w << 1) | (prev >> 63) | (w >> 1) | (next << 63);
}

/* The background of vol in the columns of box lb, read in place (the
 * complement of its words): the flood's input and the exterior of the
 * cavity voxels K (which is this minus K). */
static bvox__bgsrc volume_background(const bvox_volume *vol, colbox lb)
{
    return (bvox__bgsrc){vol->words, (size_t)vol->nx, lb.x0, lb.y0, ~0ull, vol->tail_mask};
}

/* The 26-cavities by labelling all of the box's background: cheaper than
 * going through K when the cavities are everywhere (a coin toss has a
 * million of them). */
static bvox_status label_all_26(const uint64_t *bg, colbox lb, size_t wpc, int32_t nz,
                                int64_t *out)
{
    bvox__labelruns r26;
    bvox_status st = bvox__labelruns_find(bg, NULL, lb.nx, lb.ny, wpc, 26, 1, &r26);
    if (st) return st;
    r26.parent[r26.nruns] = (uint32_t)r26.nruns;
    bvox__labelruns_join_border(&r26, (size_t)nz, (uint32_t)r26.nruns);
    *out = count_inner(&r26);
    bvox__labelruns_free(&r26);
    return BVOX_OK;
}

/* The 26-components of the cavity voxels K (words k, box kb inside the
 * labelled box; its ring of columns empty) that touch no voxel of the
 * exterior (ext minus K, ext in the labelled box's columns). K is labelled 26-connected; then, a row of groups per task,
 * each group's voxels of T = K & dilate26(exterior) mark the roots of their
 * runs, and the unmarked roots are counted. */
typedef struct mark26_job {
    const bvox__labelruns *r;
    bvox__bgsrc ext;
    colbox kb;
    uint8_t *touched;
} mark26_job;

/* T's word w of K's column (x, y) of kb (an inner column). */
static inline uint64_t touching_word(const mark26_job *j, size_t x, size_t y, size_t w)
{
    const uint64_t *k = j->r->words;
    colbox kb = j->kb;
    bvox__bgsrc ex = j->ext;
    size_t wpc = j->r->wpc;
    uint64_t flip = ex.flip, d = 0;
    for (size_t dy = 0; dy < 3; dy++)
        for (size_t dx = 0; dx < 3; dx++) {
            const uint64_t *kk = k + ((y + dy - 1) * kb.nx + (x + dx - 1)) * wpc;
            const uint64_t *bb =
                ex.words + ((ex.y0 + kb.y0 + y + dy - 1) * ex.nx + (ex.x0 + kb.x0 + x + dx - 1)) * wpc;
            uint64_t e = (bb[w] ^ flip) & (w + 1 == wpc ? ex.tail : ~0ull) & ~kk[w];
            uint64_t ep = w ? (bb[w - 1] ^ flip) & ~kk[w - 1] : 0;
            uint64_t en =
                w + 1 < wpc ? (bb[w + 1] ^ flip) & (w + 2 == wpc ? ex.tail : ~0ull) & ~kk[w + 1] : 0;
            d |= zdilate(ep, e, en);
        }
    return k[(y * kb.nx + x) * wpc + w] & d;
}

static void mark26_rows(void *ctx, int64_t begin, int64_t end)
{
    const mark26_job *j = ctx;
    const bvox__labelruns *r = j->r;
    size_t wpc = r->wpc;
    uint64_t mask[(BVOX_MAX_DIM + 63) / 64];
    for (size_t gy = (size_t)begin; gy < (size_t)end; gy++)
        for (size_t gx = 0; gx < r->gx; gx++) {
            size_t grp = gy * r->gx + gx;
            if (r->grp_start[grp] == r->grp_start[grp + 1]) continue;
            memset(mask, 0, wpc * sizeof *mask);
            uint64_t any = 0;
            for (size_t c = 0; c < 4; c++) {
                size_t x = 2 * gx + c % 2, y = 2 * gy + c / 2;
                if (x == 0 || y == 0 || x + 1 >= j->kb.nx || y + 1 >= j->kb.ny) continue;
                const uint64_t *kc = r->words + (y * j->kb.nx + x) * wpc;
                for (size_t w = 0; w < wpc; w++)
                    if (kc[w]) {
                        uint64_t t = touching_word(j, x, y, w);
                        mask[w] |= t;
                        any |= t;
                    }
            }
            if (any) bvox__labelruns_mark_group(r, grp, mask, j->touched);
        }
}

static bvox_status count_marked_26(const uint64_t *k, colbox kb, bvox__bgsrc ext, size_t wpc,
                                   int64_t *out)
{
    bvox__labelruns r26;
    bvox_status st = bvox__labelruns_find(k, NULL, kb.nx, kb.ny, wpc, 26, 1, &r26);
    if (st) return st;
    r26.parent[r26.nruns] = (uint32_t)r26.nruns;
    uint8_t *touched = bvox__mem_zalloc(r26.nruns + 1, 1);
    if (!touched) {
        bvox__labelruns_free(&r26);
        return bvox__fail(BVOX_ENOMEM, "out of memory measuring cavities");
    }
    flatten(&r26);
    mark26_job mj = {&r26, ext, kb, touched};
    bvox__parallel_for((int64_t)r26.gy, 4, mark26_rows, &mj);
    root_job rj = {r26.parent, touched, 0};
    bvox__parallel_for((int64_t)r26.nruns, 1 << 16, count_roots, &rj);
    *out = rj.roots;
    free(touched);
    bvox__labelruns_free(&r26);
    return BVOX_OK;
}

/* K, a row of kb at a time: each column of words copied into k with only
 * its cavity runs (k != words: zeroed, then the runs filled), or with the
 * other runs cleared in place (k == words). The runs of a column in order:
 * starts and ends found a word at a time, alternating along z. */
typedef struct fill_job {
    const bvox__labelruns *r;
    uint64_t *words;
    colbox lb, kb;
    uint32_t outside;
    uint64_t *k;
} fill_job;

static void fill_rows(void *ctx, int64_t begin, int64_t end)
{
    const fill_job *j = ctx;
    const bvox__labelruns *r = j->r;
    colbox lb = j->lb, kb = j->kb;
    size_t wpc = r->wpc;
    bool in_place = j->k == j->words;
    for (size_t y = (size_t)begin; y < (size_t)end; y++)
        for (size_t x = 0; x < kb.nx; x++) {
            size_t col = (kb.y0 + y) * lb.nx + kb.x0 + x;
            uint64_t *dst = j->k + (y * kb.nx + x) * wpc;
            if (!in_place) memset(dst, 0, wpc * sizeof *dst);
            uint32_t run = r->grp_start[col];
            if (run == r->grp_start[col + 1]) continue;
            bvox__runs_iter it;
            int32_t z0, z1;
            /* in place, the runs cleared lie in words the iterator has passed */
            for (bool more = bvox__runs_begin(&it, j->words + col * wpc, 0, wpc);
                 more && bvox__runs_next(&it, &z0, &z1); run++) {
                bool cavity = r->parent[run] != j->outside;
                if (in_place && !cavity) bvox__column_fill(dst, z0, z1, 0);
                if (!in_place && cavity) bvox__column_fill(dst, z0, z1, 1);
            }
        }
}

/* The 26-cavities, given the 6-labelling r of words (the box's background
 * or the part of it that holds every cavity, words of lb's columns, which
 * this overwrites) whose parents have been flattened (parent[i] is i's
 * root): the runs not in outside's component are the cavity voxels K; their
 * exterior is the background of vol minus K. K is labelled where it lies:
 * copied into the box of its columns when that is small, else in place. */
static bvox_status count_cavities_26(const bvox__labelruns *r, uint64_t *words,
                                     const bvox_volume *vol, colbox lb, int64_t *out)
{
    size_t wpc = r->wpc, ncol = lb.nx * lb.ny;
    uint32_t outside = r->parent[r->nruns];
    bvox__bgsrc ext = volume_background(vol, lb);
    uint32_t *first = bvox__mem_alloc((ncol + 1) * sizeof *first);
    if (!first) return bvox__fail(BVOX_ENOMEM, "out of memory measuring cavities");
    /* the columns holding cavity runs, and their runs' first indices */
    size_t x0 = lb.nx, x1 = 0, y0 = lb.ny, y1 = 0;
    first[0] = 0;
    for (size_t col = 0; col < ncol; col++) {
        uint32_t n = 0;
        for (uint32_t i = r->grp_start[col]; i < r->grp_start[col + 1]; i++)
            n += r->parent[i] != outside;
        first[col + 1] = first[col] + n;
        if (!n) continue;
        size_t x = col % lb.nx, y = col / lb.nx;
        if (x < x0) x0 = x;
        if (x + 1 > x1) x1 = x + 1;
        if (y < y0) y0 = y;
        if (y + 1 > y1) y1 = y + 1;
    }
    /* K's runs alone when they are few: each costs a merge and a look at
     * nine columns, against a labelling of every word of K's box */
    bool sparse = bvox__cavity_sparse_26 < 0 ? first[ncol] <= ncol : bvox__cavity_sparse_26;
    if (sparse) {
        bvox_status st = bvox__cavities_26_sparse(r, words, vol, lb.x0, lb.y0, first, out);
        free(first);
        return st;
    }
    free(first);
    /* never on the labelled box's border (joined to outside there) */
    colbox kb = {x0 - 1, y0 - 1, x1 - x0 + 2, y1 - y0 + 2};
    bool in_place = 4 * kb.nx * kb.ny > lb.nx * lb.ny;
    if (in_place) kb = (colbox){0, 0, lb.nx, lb.ny};
    size_t nw = kb.nx * kb.ny * wpc;
    bvox_status st = BVOX_OK;
    uint64_t *k = words;
    if (!in_place) k = bvox__alloc(nw * sizeof *k, false, "cavity voxels", &st);
    if (!k) return st;
    fill_job fj = {r, words, lb, kb, outside, k};
    bvox__parallel_for((int64_t)kb.ny, 4, fill_rows, &fj);
    st = count_marked_26(k, kb, ext, wpc, out);
    if (!in_place) bvox__free(k, nw * sizeof *k);
    return st;
}

int bvox__cavity_sparse_26 = -1;

/* -1: choose (see bvox__measure_cavities); 0: always label the background;
 * n > 0: always flood first, at most n sweeps (tests force each route). */
int bvox__cavity_flood_sweeps = -1;

/* Sweeps a flood may take before the labelling takes over: a coin toss at
 * 512^3 settles in ten. */
#define FLOOD_MAX_SWEEPS 24

int bvox__cavity_label_k = 0;

/* K = bg & ~R in place in R's words. */
typedef struct cavity_job {
    uint64_t *r;
    const bvox__bgsrc *bg;
    size_t nx, wpc;
} cavity_job;

static void cavity_rows(void *ctx, int64_t begin, int64_t end)
{
    const cavity_job *j = ctx;
    size_t nx = j->nx, wpc = j->wpc;
    for (size_t y = (size_t)begin; y < (size_t)end; y++)
        for (size_t x = 0; x < nx; x++) {
            uint64_t *c = j->r + (y * nx + x) * wpc;
            for (size_t w = 0; w < wpc; w++) c[w] = bvox__bg_word(j->bg, x, y, wpc, w) & ~c[w];
        }
}

/* L = K & ~dilate26(R) in place in K's words (k), R = bg & ~K read from
 * them, the inner rows of one parity (the ring of columns holds no voxel of
 * K), one per index: a row reads the rows beside it, of the other parity,
 * which no task writes meanwhile. Rows stripped before make R read as R +
 * some voxels of T; the count does not change: every voxel of T is still
 * stripped, and a voxel next to one of T is in a component of K that holds a
 * voxel of T (it is not a 26-cavity either way), so no voxel of a 26-cavity
 * is ever stripped. */
typedef struct strip_job {
    uint64_t *k;
    const bvox_volume *vol;
    colbox lb;
    size_t parity;
} strip_job;

static void strip_rows(void *ctx, int64_t begin, int64_t end)
{
    const strip_job *j = ctx;
    const bvox_volume *vol = j->vol;
    size_t nx = j->lb.nx, wpc = vol->wpc, vnx = (size_t)vol->nx;
    uint64_t d[(BVOX_MAX_DIM + 63) / 64];
    for (size_t i = (size_t)begin; i < (size_t)end; i++) {
        size_t y = 1 + 2 * i + j->parity;
        for (size_t x = 1; x + 1 < nx; x++) {
            uint64_t *kc = j->k + (y * nx + x) * wpc, any = 0;
            for (size_t w = 0; w < wpc; w++) any |= kc[w];
            if (!any) continue;
            /* the dilation of a union is the union of the dilations: R's
             * words of the nine columns ORed (R = ~(object | K), within
             * nz), then dilated along z */
            const uint64_t *kq[9], *oq[9];
            for (size_t c = 0; c < 9; c++) {
                size_t cx = x + c % 3 - 1, cy = y + c / 3 - 1;
                kq[c] = j->k + (cy * nx + cx) * wpc;
                oq[c] = vol->words + ((j->lb.y0 + cy) * vnx + j->lb.x0 + cx) * wpc;
            }
            for (size_t w = 0; w < wpc; w++) {
                uint64_t closed = ~0ull;
                for (size_t c = 0; c < 9; c++) closed &= oq[c][w] | kq[c][w];
                d[w] = ~closed;
            }
            d[wpc - 1] &= vol->tail_mask;
            for (size_t w = 0; w < wpc; w++)
                kc[w] &= ~zdilate(w ? d[w - 1] : 0, d[w], w + 1 < wpc ? d[w + 1] : 0);
        }
    }
}

/* Both counts through the flood of measure_flood.c, which reads the
 * background in place (the complement of vol's words in the box lb): R =
 * the background reached from the border, and the cavity voxels K = bg & ~R
 * (written over R: the one buffer of the route) are labelled 6-connected
 * (the 6-cavities). The 26-cavities are the 26-components of K with no
 * voxel 26-adjacent to R. Those voxels of K that are (T, on a coin toss
 * nearly all of its 1.4 million at 512^3) are stripped by one dilation of
 * R, leaving L = K & ~dilate26(R) (a handful): a 26-component of K without
 * a voxel of T lies in L whole and is a 26-component of L no voxel of which
 * is 26-adjacent to T (a neighbour in T would be in the same component of
 * K), and a 26-component of L with no neighbour in T is one of K, since K =
 * L + T. So L is labelled 26-connected and its components with no voxel
 * next to bg & ~L (which is R + T, and none is next to R) are counted. This
 * replaced a 26-flood of R through K (9 ms of a 131 ms measure at 2
 * threads; the dilation takes 1-2): its second sweep visited every row to
 * change 16. bvox__cavity_label_k = 1 labels all of K 26-connected instead,
 * the components with a voxel next to R = bg & ~K left out. *settled =
 * false when the 6-flood did not settle. */
static bvox_status cavities_by_flood(const bvox_volume *vol, colbox lb, int max_sweeps,
                                     bool *settled, int64_t *cav6, int64_t *cav26)
{
    size_t wpc = vol->wpc, nw = lb.nx * lb.ny * wpc;
    bvox_status st = BVOX_OK;
    /* R (zeroed) and the flood's row and column stamps; a copy of the
     * background and separate R, K and T buffers (64 MiB of fresh pages at
     * 512^3) cost a tenth of the call in page faults */
    size_t nr = nw + (lb.ny + lb.nx * lb.ny) / 2 + 1;
    uint64_t *r = bvox__alloc(nr * sizeof *r, true, "reached background", &st);
    if (!r) return st;
    int32_t *rows = (int32_t *)(r + nw);
    bvox__bgsrc bg = volume_background(vol, lb);
    *settled = bvox__flood_border(&bg, lb.nx, lb.ny, wpc, (size_t)vol->nz, max_sweeps, r, rows);
    if (!*settled) goto done;
    cavity_job cj = {r, &bg, lb.nx, wpc};
    bvox__parallel_for((int64_t)lb.ny, 4, cavity_rows, &cj);
    uint64_t *k = r;
    bvox__labelruns r6;
    st = bvox__labelruns_find(k, NULL, lb.nx, lb.ny, wpc, 6, 1, &r6);
    if (st) goto done;
    r6.parent[r6.nruns] = (uint32_t)r6.nruns;
    *cav6 = count_inner(&r6);
    bvox__labelruns_free(&r6);
    st = bvox__progress(0.8);
    if (st || *cav6 == 0) goto done;
    colbox kb = {0, 0, lb.nx, lb.ny};
    /* the exterior of the labelled voxels (K, or L) is the rest of the
     * background; neither has a voxel in the ring of border columns
     * (reached whole) */
    if (!bvox__cavity_label_k) {
        for (size_t parity = 0; parity < 2 && lb.nx > 2 && lb.ny > 2; parity++) {
            strip_job sj = {k, vol, lb, parity};
            bvox__parallel_for((int64_t)(lb.ny - 2 - parity + 1) / 2, 4, strip_rows, &sj);
        }
    }
    st = count_marked_26(k, kb, bg, wpc, cav26);
done:
    bvox__free(r, nr * sizeof *r);
    return st;
}

/* The flood pays when the background mostly reaches the border (it
 * percolates: above the cubic lattice's site threshold, 0.31, of the box)
 * and has runs enough (a labelling's cost grows with the runs, the flood's
 * with the words): a coin toss has 16 runs per word, the AAL atlas 0.2.
 * Measured on random runs at 256^3, one thread: 1.5 runs per word and 31 %
 * background 8.6 ms by the flood against 9.6 by the labelling, 2 and 42 %
 * 7.7 against 14.6; below the threshold the labelling wins (18 %: 12.2
 * against 10.2); on the atlas both cost the same. The object's runs along z
 * are half its z faces; the background's in the box are as many, give or
 * take one per column. */
static bool flood_pays(const bvox__scan *sc, colbox lb, int32_t nz, size_t wpc)
{
    double cols = (double)lb.nx * (double)lb.ny;
    double bg = cols * nz - (double)sc->count;
    double runs = (double)sc->trans[BVOX__DIR_Z] / 2 + cols;
    return bg >= 0.31 * cols * nz && runs >= cols * (double)wpc;
}

/* The complement of the box's columns, nw words from the budget. */
static uint64_t *background_words(const bvox_volume *vol, colbox lb, bvox_status *st)
{
    uint64_t *bg = bvox__alloc(lb.nx * lb.ny * vol->wpc * sizeof *bg, false, "background words", st);
    if (!bg) return NULL;
    extract_job ej = {vol, lb, bg};
    bvox__parallel_for((int64_t)lb.ny, 16, extract_rows, &ej);
    return bg;
}

typedef struct outside_job {
    uint32_t *parent;
    const uint8_t *touched;
    uint32_t outside;
} outside_job;

static void to_outside(void *ctx, int64_t begin, int64_t end)
{
    const outside_job *j = ctx;
    for (int64_t i = begin; i < end; i++)
        if (j->touched[j->parent[i]]) j->parent[i] = j->outside;
}

/* The hull route's join to outside: every run whose component touches the
 * background outside U points at outside, the others at their root
 * (flattened; all in parallel, no union-find). */
static bvox_status join_exterior(bvox__labelruns *r, const bvox_volume *vol, colbox lb,
                                 const int32_t *zr)
{
    uint8_t *touched = bvox__mem_zalloc(r->nruns + 1, 1);
    if (!touched) return bvox__fail(BVOX_ENOMEM, "out of memory measuring cavities");
    flatten(r);
    bvox__enclosed_mark_exterior(r, vol, lb.x0, lb.y0, zr, touched);
    outside_job j = {r->parent, touched, (uint32_t)r->nruns};
    bvox__parallel_for((int64_t)r->nruns, 1 << 16, to_outside, &j);
    free(touched);
    return BVOX_OK;
}

/* -1 (default): the labelling route lists the runs of the background
 * enclosed along z (measure_hull_runs.c); 1: labels its words
 * (measure_enclosed.c); 0: labels all of the box's background. */
int bvox__cavity_hull = -1;

/* Both counts from the background U enclosed along z alone (see
 * measure_enclosed.c): its 6-components that do not touch the rest of the
 * background are the 6-cavities, and their union K gives the 26-cavities
 * (count_cavities_26; labelling all of U 26-connected instead, K being a
 * few pockets of it, cost 1.4 x the whole call on the atlas). */
static bvox_status cavities_in_hull(const bvox_volume *vol, colbox lb, int64_t *cav6,
                                    int64_t *cav26)
{
    size_t ncol = lb.nx * lb.ny, nw = ncol * vol->wpc;
    bvox_status st = BVOX_OK;
    int32_t *zr = NULL;
    uint64_t *u = bvox__alloc(nw * sizeof *u, false, "enclosed background", &st);
    if (u) zr = bvox__alloc(2 * ncol * sizeof *zr, false, "column hulls", &st);
    bvox__labelruns r;
    if (zr) {
        bvox__enclosed_background(vol, lb.x0, lb.y0, lb.nx, lb.ny, u, zr);
        st = bvox__labelruns_find(u, NULL, lb.nx, lb.ny, vol->wpc, 6, 1, &r);
    }
    if (zr && !st) {
        r.parent[r.nruns] = (uint32_t)r.nruns;
        st = join_exterior(&r, vol, lb, zr);
        if (!st) *cav6 = count_inner(&r);
        if (!st) st = bvox__progress(0.8);
        if (!st && *cav6) st = count_cavities_26(&r, u, vol, lb, cav26);
        bvox__labelruns_free(&r);
    }
    bvox__free(u, nw * sizeof *u);
    bvox__free(zr, 2 * ncol * sizeof *zr);
    return st;
}

/* Both counts by a 6-labelling of all the box's background, joined to
 * outside on the border. */
static bvox_status cavities_by_labelling(const bvox_volume *vol, colbox lb, int64_t *cav6,
                                         int64_t *cav26)
{
    size_t wpc = vol->wpc, nw = lb.nx * lb.ny * wpc;
    bvox_status st = BVOX_OK;
    uint64_t *bg = background_words(vol, lb, &st);
    if (!bg) return st;
    bvox__labelruns r;
    st = bvox__labelruns_find(bg, NULL, lb.nx, lb.ny, wpc, 6, 1, &r);
    if (!st) {
        uint32_t outside = (uint32_t)r.nruns;
        r.parent[outside] = outside;
        bvox__labelruns_join_border(&r, (size_t)vol->nz, outside);
        *cav6 = count_inner(&r);
        st = bvox__progress(0.8);
        if (st || *cav6 == 0) {
            /* done */
        } else if (*cav6 > 16384 && (size_t)*cav6 > r.nruns / 64) {
            /* cavities everywhere (a coin toss): one labelling of all the
             * background costs less than copying K and finding its contacts
             * (small volumes take the K route whatever they hold: it is the
             * one they test) */
            st = label_all_26(bg, lb, wpc, vol->nz, cav26);
        } else {
            flatten(&r);
            st = count_cavities_26(&r, bg, vol, lb, cav26);
        }
        bvox__labelruns_free(&r);
    }
    bvox__free(bg, nw * sizeof *bg);
    return st;
}

/* The default route (measure_hull_runs.c), the columns' hulls scanned for
 * when the caller has none. */
static bvox_status cavities_from_runs(const bvox_volume *vol, const bvox__colhull *hulls,
                                      colbox lb, int64_t *cav6, int64_t *cav26)
{
    if (hulls) return bvox__cavities_from_hull_runs(vol, hulls, lb.x0, lb.y0, lb.nx, lb.ny,
                                                    cav6, cav26);
    bvox_status st = BVOX_OK;
    size_t bytes = (size_t)vol->nx * (size_t)vol->ny * sizeof(bvox__colhull);
    bvox__colhull *own = bvox__alloc(bytes, false, "column hulls", &st);
    if (!own) return st;
    bvox__scan sc;
    st = bvox__measure_scan_hulls(vol, own, &sc);
    if (!st)
        st = bvox__cavities_from_hull_runs(vol, own, lb.x0, lb.y0, lb.nx, lb.ny, cav6, cav26);
    bvox__free(own, bytes);
    return st;
}

bvox_status bvox__measure_cavities(const bvox_volume *vol, const bvox__scan *sc,
                                   const bvox__colhull *hulls, int64_t *cav6, int64_t *cav26)
{
    const int32_t *bbox = sc->bbox;
    *cav6 = *cav26 = 0;
    size_t x0 = bbox[0] > 0 ? (size_t)bbox[0] - 1 : 0, y0 = bbox[1] > 0 ? (size_t)bbox[1] - 1 : 0;
    size_t x1 = bbox[3] < vol->nx ? (size_t)bbox[3] + 1 : (size_t)vol->nx;
    size_t y1 = bbox[4] < vol->ny ? (size_t)bbox[4] + 1 : (size_t)vol->ny;
    colbox lb = {x0, y0, x1 - x0, y1 - y0};
    size_t wpc = vol->wpc;
    bvox_status st = BVOX_OK;
    int sweeps = bvox__cavity_flood_sweeps;
    if (sweeps < 0) sweeps = flood_pays(sc, lb, vol->nz, wpc) ? FLOOD_MAX_SWEEPS : 0;
    if (sweeps > 0) {
        bool settled = false;
        st = cavities_by_flood(vol, lb, sweeps, &settled, cav6, cav26);
        if (st || settled) return st;
    }
    if (bvox__cavity_hull < 0) return cavities_from_runs(vol, hulls, lb, cav6, cav26);
    if (bvox__cavity_hull > 0) return cavities_in_hull(vol, lb, cav6, cav26);
    return cavities_by_labelling(vol, lb, cav6, cav26);
}
