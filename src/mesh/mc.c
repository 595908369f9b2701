/*
 * mc.c — marching cubes on a binary volume, 64 cells at a time.
 *
 * With binary data every vertex is the midpoint of a grid edge whose two
 * voxels differ, so a vertex IS its edge: no floats are compared or hashed.
 * The crossed edges of each kind are the bits of XORs of column words (x
 * edges: column ^ column to its right; y edges: column ^ column behind;
 * z edges: column ^ column shifted by one), and an edge's vertex number is
 * a running popcount: pass 1 stores, per word, how many crossed edges of its
 * kind come before it in its row, plus a total per row. Triangles (pass 2,
 * one buffer per chunk of rows, concatenated in order so the result does
 * not depend on the thread count) classify 64 cells from the 8 corner words
 * of a cell word, skip the word when all 8 are equal (uniform cells), and
 * look each vertex up as prefix + popcount of the mask bits below it.
 * Pass 3 writes the vertex positions, again in popcount order.
 */
#include "mesh_private.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* The hot loops are cloned for CPUs with POPCNT (GCC's target_clones: an
 * ifunc picks the clone at load time, the binary stays portable); elsewhere
 * the portable popcount. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HOT __attribute__((target_clones("popcnt", "default")))
#define POPCOUNT(x) ((unsigned)__builtin_popcountll(x))
#else
#define HOT
#define POPCOUNT(x) bvox__popcount64(x)
#endif

typedef struct chunk {
    int32_t y0, y1;    /* cell rows Y in [y0, y1) */
    int32_t *region;   /* its part of the mesh's triangle array */
    int64_t region_cap, nregion; /* triangles */
    int spilled;       /* the region filled up: the rest went to tris */
    bvox__buf tris;    /* int32 triples; negative: -(centre index + 1) */
    bvox__buf centres; /* doubles, 3 per loop centre (index space) */
    bvox_status st;
} chunk;

typedef struct mc {
    bvox__grid g;
    const bvox_geometry *geo;
    const bvox__mc_case *tab;
    const uint64_t *zero; /* a zero column of cw words */
    uint32_t *pre[3];
    size_t pre_bytes[3];
    int64_t *rowcount[3]; /* then row bases */
    int64_t tbase[3];
    size_t row_cols[3];   /* columns per row of each edge kind */
    size_t wpr[3];        /* words per column of each kind: wpc, wpc, cw */
    chunk *chunks;
    int nchunks;
    double *verts;
    int mirrored;
    int axis_aligned; /* direction is the identity */
} mc;

static inline const uint64_t *col(const mc *c, int32_t X, int32_t Y)
{
    const bvox__grid *g = &c->g;
    if (X < 1 || X > g->nx || Y < 1 || Y > g->ny) return c->zero;
    return g->words + ((size_t)(Y - 1) * (size_t)g->nx + (size_t)(X - 1)) * g->wpc;
}
static inline uint64_t hiw(const mc *c, const uint64_t *p, size_t w)
{
    return w < c->g.wpc ? p[w] : 0;
}
static inline uint64_t low(const mc *c, const uint64_t *p, size_t w)
{
    return (hiw(c, p, w) << 1) | (w ? p[w - 1] >> 63 : 0);
}

/* ---- pass 1: per-word prefix counts of crossed edges ---- */

HOT static void count_row(mc *c, int kind, int32_t r)
{
    const bvox__grid *g = &c->g;
    /* 64-bit: a row can hold more than 2^32 crossings (the total check then
     * refuses the mesh; the 32-bit prefixes are only used below that) */
    uint64_t run = 0;
    size_t ncol = c->row_cols[kind], nw = c->wpr[kind];
    uint32_t *pre = c->pre[kind] + (size_t)r * ncol * nw;
    for (size_t i = 0; i < ncol; i++) {
        const uint64_t *a, *b = NULL;
        if (kind == 0) { /* x edges: row Y = r + 1, X = i in 0..nx */
            a = col(c, (int32_t)i, r + 1);
            b = col(c, (int32_t)i + 1, r + 1);
        } else if (kind == 1) { /* y edges: Y = r in 0..ny, X = i + 1 */
            a = col(c, (int32_t)i + 1, r);
            b = col(c, (int32_t)i + 1, r + 1);
        } else {
            a = col(c, (int32_t)i + 1, r + 1);
        }
        for (size_t w = 0; w < nw; w++) {
            pre[i * nw + w] = (uint32_t)run;
            uint64_t m = kind < 2 ? a[w] ^ b[w] : (hiw(c, a, w) ^ low(c, a, w));
            if (m) run += POPCOUNT(m); /* most words: no crossing */
        }
    }
    c->rowcount[kind][r] = (int64_t)run;
    (void)g;
}

static void count_rows(void *ctx, int64_t begin, int64_t end)
{
    mc *c = ctx;
    for (int64_t y = begin; y < end; y++) {
        count_row(c, 1, (int32_t)y);
        if (y < c->g.ny) {
            count_row(c, 0, (int32_t)y);
            count_row(c, 2, (int32_t)y);
        }
    }
}

/* ---- pass 2: triangles ---- */

/* Where the vertices of the 12 cube edges of the cells of column (X, Y) are
 * numbered: the two columns whose XOR holds the edge's crossings (x and y
 * edges) or the column itself (z edges: lo ^ hi of the corner words), the
 * per-word prefix array of that edge column, and the kind and row base. */
typedef struct cellcol {
    const uint64_t *a[12], *b[12];
    const uint32_t *pre[12];
    int64_t base[12];
} cellcol;

static void cellcol_init(const mc *c, int32_t X, int32_t Y, const uint64_t *const p[4],
                         cellcol *cc)
{
    const bvox__grid *g = &c->g;
    /* x edges: rows Y-1 (e 0, 2) and Y (e 1, 3) at column X; y edges: row
     * Y at columns X-1 (e 4, 6) and X (e 5, 7); z edges: rows Y-1, Y and
     * columns X-1, X (e 8 + dx + 2 dy) */
    const uint32_t *xp[2] = {NULL, NULL}, *yp[2] = {NULL, NULL}, *zp[4] = {NULL, NULL, NULL, NULL};
    int64_t xb[2] = {0, 0}, yb = c->tbase[1] + c->rowcount[1][Y], zb[2] = {0, 0};
    for (int o = 0; o < 2; o++) {
        int32_t r = Y + o - 1;
        if (r < 0 || r >= g->ny) continue;
        xp[o] = c->pre[0] + ((size_t)r * c->row_cols[0] + (size_t)X) * g->wpc;
        xb[o] = c->tbase[0] + c->rowcount[0][r];
        zb[o] = c->tbase[2] + c->rowcount[2][r];
        for (int dx = 0; dx < 2; dx++) {
            int32_t i = X + dx - 1;
            if (i >= 0 && i < g->nx)
                zp[dx + 2 * o] = c->pre[2] + ((size_t)r * c->row_cols[2] + (size_t)i) * g->cw;
        }
    }
    for (int dx = 0; dx < 2; dx++) {
        int32_t i = X + dx - 1;
        if (i >= 0 && i < g->nx)
            yp[dx] = c->pre[1] + ((size_t)Y * c->row_cols[1] + (size_t)i) * g->wpc;
    }
    for (int e = 0; e < 4; e++) {
        int o1 = e & 1;
        cc->a[e] = p[2 * o1];
        cc->b[e] = p[2 * o1 + 1];
        cc->pre[e] = xp[o1];
        cc->base[e] = xb[o1];
        cc->a[4 + e] = p[o1];
        cc->b[4 + e] = p[2 + o1];
        cc->pre[4 + e] = yp[o1];
        cc->base[4 + e] = yb;
        cc->a[8 + e] = cc->b[8 + e] = p[e];
        cc->pre[8 + e] = zp[e];
        cc->base[8 + e] = zb[e >> 1];
    }
}

/* The vertex of cube edge e of cell Z (bit `bit` of cell word w, corner
 * words cw). Only called for crossed edges, which always have a prefix. */
static inline __attribute__((always_inline)) int32_t vid(const cellcol *cc, const uint64_t cw[8], size_t w, unsigned bit,
                          int e)
{
    if (e >= 8) {
        int k = e - 8;
        uint64_t m = (cw[k] ^ cw[4 + k]) & ((1ull << bit) - 1);
        return (int32_t)(cc->base[e] + cc->pre[e][w] + POPCOUNT(m));
    }
    /* x and y edges at voxel height z = Z - 1 + dz (original coordinates) */
    int64_t z = (int64_t)(w * 64 + bit) - 1 + ((e & 3) >> 1);
    size_t ww = (size_t)z >> 6;
    uint64_t m = (cc->a[e][ww] ^ cc->b[e][ww]) & ((1ull << (z & 63)) - 1);
    return (int32_t)(cc->base[e] + cc->pre[e][ww] + POPCOUNT(m));
}

static bvox_status add_centre(chunk *ch, const bvox__mc_case *cs, int L, int32_t X, int32_t Y,
                              int32_t Z, int32_t *id)
{
    bvox_status st =
        bvox__buf_reserve(&ch->centres, ch->centres.size + 3 * sizeof(double), "mesh vertices");
    if (st) return st;
    double p[3] = {0, 0, 0};
    for (int i = 0; i < cs->loop_len[L]; i++) {
        int c0, c1;
        bvox__mc_edge_corners(cs->loop[L][i], &c0, &c1);
        for (int a = 0; a < 3; a++) p[a] += 0.5 * (((c0 >> a) & 1) + ((c1 >> a) & 1));
    }
    double *q = (double *)((char *)ch->centres.data + ch->centres.size);
    q[0] = X - 1 + p[0] / cs->loop_len[L];
    q[1] = Y - 1 + p[1] / cs->loop_len[L];
    q[2] = Z - 1 + p[2] / cs->loop_len[L];
    ch->centres.size += 3 * sizeof(double);
    *id = -(int32_t)(ch->centres.size / (3 * sizeof(double)));
    return BVOX_OK;
}

/* Crossed edges in edge column i of row r of a kind (0 outside), from the
 * prefixes of pass 1 (after the row bases were taken: rowcount[k][r] is the
 * row's base, rowcount[k][r + 1] the next one's). */
static inline int64_t edge_col_count(const mc *c, int k, int64_t r, int64_t i)
{
    size_t rows = k == 1 ? (size_t)c->g.ny + 1 : (size_t)c->g.ny;
    if (r < 0 || (size_t)r >= rows || i < 0 || (size_t)i >= c->row_cols[k]) return 0;
    const uint32_t *p = c->pre[k] + ((size_t)r * c->row_cols[k] + (size_t)i) * c->wpr[k];
    int64_t next = (size_t)i + 1 < c->row_cols[k] ? (int64_t)p[c->wpr[k]]
                                                  : c->rowcount[k][r + 1] - c->rowcount[k][r];
    return next - (int64_t)p[0];
}

/* 1 if some edge of the cells of column (X, Y) is crossed. */
static inline int column_has_surface(const mc *c, int32_t X, int32_t Y)
{
    return edge_col_count(c, 0, Y - 1, X) || edge_col_count(c, 0, Y, X) ||
           edge_col_count(c, 1, Y, X - 1) || edge_col_count(c, 1, Y, X) ||
           edge_col_count(c, 2, Y - 1, X - 1) || edge_col_count(c, 2, Y - 1, X) ||
           edge_col_count(c, 2, Y, X - 1) || edge_col_count(c, 2, Y, X);
}

HOT static void tri_chunks(void *ctx, int64_t begin, int64_t end)
{
    mc *c = ctx;
    const bvox__grid *g = &c->g;
    const bvox__mc_case *tab = c->tab;
    const int i1 = c->mirrored ? 2 : 1, i2 = c->mirrored ? 1 : 2;
    cellcol cc;
    for (int64_t k = begin; k < end; k++) {
        chunk *ch = &c->chunks[k];
        /* the hot counters live here, not in the chunk array, whose
         * neighbouring entries belong to other threads (false sharing) */
        int64_t nregion = 0, region_cap = ch->region_cap;
        for (int32_t Y = ch->y0; Y < ch->y1 && !ch->st; Y++)
            for (int32_t X = 0; X <= g->nx && !ch->st; X++) {
                const uint64_t *p[4] = {col(c, X, Y), col(c, X + 1, Y), col(c, X, Y + 1),
                                        col(c, X + 1, Y + 1)};
                if (p[0] == c->zero && p[1] == c->zero && p[2] == c->zero && p[3] == c->zero)
                    continue;
                if (!column_has_surface(c, X, Y)) continue; /* all cells uniform */
                int ready = 0;
                uint64_t carry[4] = {0, 0, 0, 0};
                for (size_t w = 0; w < g->cw; w++) {
                    uint64_t cw[8];
                    for (int i = 0; i < 4; i++) {
                        uint64_t h = w < g->wpc ? p[i][w] : 0;
                        cw[4 + i] = h;
                        cw[i] = (h << 1) | carry[i];
                        carry[i] = h >> 63;
                    }
                    uint64_t mixed = bvox__grid_mixed(cw);
                    if (!mixed) continue;
                    if (!ready) {
                        cellcol_init(c, X, Y, p, &cc);
                        ready = 1;
                    }
                    while (mixed) {
                        unsigned bit = (unsigned)__builtin_ctzll(mixed);
                        mixed &= mixed - 1;
                        const bvox__mc_case *cs = &tab[bvox__grid_case(cw, bit)];
                        int32_t ids[16];
                        for (unsigned em = cs->edges; em; em &= em - 1) {
                            int e = __builtin_ctz(em);
                            ids[e] = vid(&cc, cw, w, bit, e);
                        }
                        for (unsigned lm = cs->centres; lm; lm &= lm - 1) {
                            int L = __builtin_ctz(lm);
                            bvox_status st = add_centre(ch, cs, L, X, Y, (int32_t)(w * 64 + bit),
                                                        &ids[12 + L]);
                            if (st) ch->st = st;
                        }
                        int32_t *out;
                        if (nregion + cs->ntri <= region_cap) {
                            out = ch->region + 3 * nregion;
                            nregion += cs->ntri;
                        } else {
                            ch->spilled = 1;
                            region_cap = 0; /* in order: the rest goes to the spill */
                            size_t need = ch->tris.size + (size_t)cs->ntri * 3 * sizeof(int32_t);
                            if (need > ch->tris.cap && !ch->st)
                                ch->st = bvox__buf_reserve(&ch->tris, need, "mesh triangles");
                            if (ch->st) break;
                            out = (int32_t *)((char *)ch->tris.data + ch->tris.size);
                            ch->tris.size = need;
                        }
                        for (int t = 0; t < cs->ntri; t++) {
                            out[3 * t] = ids[cs->tri[t][0]];
                            out[3 * t + 1] = ids[cs->tri[t][i1]];
                            out[3 * t + 2] = ids[cs->tri[t][i2]];
                        }
                    }
                    if (ch->st) break;
                }
            }
        ch->nregion = nregion;
    }
}

/* ---- pass 3: vertex positions ---- */

static inline void put(const mc *c, int64_t idx, double px, double py, double pz)
{
    double *q = c->verts + 3 * idx;
    if (c->axis_aligned) { /* the usual identity direction: 3 multiply-adds */
        q[0] = c->geo->origin[0] + px * c->geo->spacing[0];
        q[1] = c->geo->origin[1] + py * c->geo->spacing[1];
        q[2] = c->geo->origin[2] + pz * c->geo->spacing[2];
        return;
    }
    bvox__grid_world(c->geo, px, py, pz, q);
}

static void vert_rows(void *ctx, int64_t begin, int64_t end)
{
    mc *c = ctx;
    const bvox__grid *g = &c->g;
    for (int64_t yy = begin; yy < end; yy++) {
        int32_t r = (int32_t)yy;
        /* y edges of row r: between Y = r and r + 1 (edge columns without a
         * crossing, most of them, are skipped on their prefix counts) */
        int64_t idx = c->tbase[1] + c->rowcount[1][r];
        for (int32_t X = 1; X <= g->nx; X++) {
            if (!edge_col_count(c, 1, r, X - 1)) continue;
            const uint64_t *a = col(c, X, r), *b = col(c, X, r + 1);
            for (size_t w = 0; w < g->wpc; w++)
                for (uint64_t m = a[w] ^ b[w]; m; m &= m - 1)
                    put(c, idx++, X - 1, r - 0.5, (double)(w * 64 + (size_t)__builtin_ctzll(m)));
        }
        if (r >= g->ny) continue;
        idx = c->tbase[0] + c->rowcount[0][r];
        for (int32_t X = 0; X <= g->nx; X++) {
            if (!edge_col_count(c, 0, r, X)) continue;
            const uint64_t *a = col(c, X, r + 1), *b = col(c, X + 1, r + 1);
            for (size_t w = 0; w < g->wpc; w++)
                for (uint64_t m = a[w] ^ b[w]; m; m &= m - 1)
                    put(c, idx++, X - 0.5, r, (double)(w * 64 + (size_t)__builtin_ctzll(m)));
        }
        idx = c->tbase[2] + c->rowcount[2][r];
        for (int32_t X = 1; X <= g->nx; X++) {
            if (!edge_col_count(c, 2, r, X - 1)) continue;
            const uint64_t *a = col(c, X, r + 1);
            for (size_t w = 0; w < g->cw; w++)
                for (uint64_t m = hiw(c, a, w) ^ low(c, a, w); m; m &= m - 1)
                    put(c, idx++, X - 1, r, (double)(w * 64 + (size_t)__builtin_ctzll(m)) - 0.5);
        }
    }
}

/* ---- dynamic scheduling: one task per thread, each takes the next block
 * of the range until none is left, so that a thread slowed down (uneven
 * surface, or a core busy with something else) takes fewer blocks. The
 * blocks' results do not depend on which thread runs them. ---- */

typedef struct dyn {
    bvox__range_fn fn;
    void *ctx;
    int64_t n, grain;
    int64_t next; /* atomic */
} dyn;

static void dyn_worker(void *ctx, int64_t begin, int64_t end)
{
    dyn *d = ctx;
    (void)begin;
    (void)end;
    for (;;) {
        int64_t b = __atomic_fetch_add(&d->next, d->grain, __ATOMIC_RELAXED);
        if (b >= d->n) return;
        d->fn(d->ctx, b, b + d->grain < d->n ? b + d->grain : d->n);
    }
}

static void dyn_for(int64_t n, int64_t grain, bvox__range_fn fn, void *ctx)
{
    int threads = bvox_threads();
    if (threads < 2 || n <= grain) {
        fn(ctx, 0, n);
        return;
    }
    dyn d = {fn, ctx, n, grain, 0};
    bvox__parallel_for(threads, 1, dyn_worker, &d);
}

static void mc_release(mc *c)
{
    for (int k = 0; k < 3; k++) {
        if (c->pre[k]) bvox__free(c->pre[k], c->pre_bytes[k]);
        free(c->rowcount[k]);
    }
    if (c->chunks)
        for (int i = 0; i < c->nchunks; i++) {
            bvox__buf_release(&c->chunks[i].tris);
            bvox__buf_release(&c->chunks[i].centres);
        }
    free(c->chunks);
    free((void *)c->zero);
}

bvox_status bvox__mesh_mc(const bvox_volume *vol, bvox_mesh *m)
{
    mc c;
    memset(&c, 0, sizeof c);
    bvox__grid_init(&c.g, vol);
    c.geo = &vol->geom;
    c.mirrored = bvox__geometry_mirrored(c.geo);
    static const double ident[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    c.axis_aligned = !memcmp(c.geo->direction, ident, sizeof ident);
    c.tab = bvox__mc_table();
    const bvox__grid *g = &c.g;
    bvox_status st = BVOX_OK;
    c.zero = calloc(g->cw + 1, sizeof(uint64_t));
    size_t rows[3] = {(size_t)g->ny, (size_t)g->ny + 1, (size_t)g->ny};
    c.row_cols[0] = (size_t)g->nx + 1;
    c.row_cols[1] = (size_t)g->nx;
    c.row_cols[2] = (size_t)g->nx;
    c.wpr[0] = c.wpr[1] = g->wpc;
    c.wpr[2] = g->cw;
    if (!c.zero) st = bvox__fail(BVOX_ENOMEM, "out of memory (marching cubes)");
    for (int k = 0; k < 3 && !st; k++) {
        size_t n;
        if (!bvox__mul_size(rows[k] * c.row_cols[k], c.wpr[k] * sizeof(uint32_t), &n)) {
            st = bvox__fail(BVOX_ETOOBIG, "volume too large to mesh");
            break;
        }
        c.pre_bytes[k] = n ? n : 1;
        c.pre[k] = bvox__alloc(c.pre_bytes[k], false, "marching cubes edge index", &st);
        if (c.pre[k]) bvox__advise_huge(c.pre[k], c.pre_bytes[k]);
        c.rowcount[k] = calloc(rows[k] + 1, sizeof(int64_t));
        if (!c.pre[k]) break;
        if (!c.rowcount[k]) st = bvox__fail(BVOX_ENOMEM, "out of memory (marching cubes)");
    }
    if (st) {
        mc_release(&c);
        return st;
    }
    dyn_for((int64_t)g->ny + 1, 8, count_rows, &c);
    /* row totals -> row bases; kind totals -> kind bases */
    int64_t total = 0;
    for (int k = 0; k < 3; k++) {
        c.tbase[k] = total;
        int64_t run = 0;
        for (size_t r = 0; r < rows[k]; r++) {
            int64_t n = c.rowcount[k][r];
            c.rowcount[k][r] = run;
            run += n;
        }
        c.rowcount[k][rows[k]] = run;
        total += run;
    }
    if (total > INT32_MAX) {
        mc_release(&c);
        return bvox__fail(BVOX_ETOOBIG, "the mesh would have %lld vertices (at most %d)",
                          (long long)total, INT32_MAX);
    }
    int threads = bvox_threads();
    int nch = threads * 16; /* blocks for dyn_for: small enough to balance */
    if (nch > g->ny + 1) nch = g->ny + 1;
    c.nchunks = nch;
    c.chunks = calloc((size_t)nch, sizeof(chunk));
    if (!c.chunks) {
        mc_release(&c);
        return bvox__fail(BVOX_ENOMEM, "out of memory (marching cubes)");
    }
    for (int i = 0; i < nch; i++) {
        c.chunks[i].y0 = (int32_t)((int64_t)(g->ny + 1) * i / nch);
        c.chunks[i].y1 = (int32_t)((int64_t)(g->ny + 1) * (i + 1) / nch);
    }
    /* a closed mesh has about two triangles per vertex: each chunk gets a
     * region of the mesh's triangle array that large (with slack), spilling
     * into its own buffer only if it fills up */
    int64_t tcap = 0;
    for (int i = 0; i < nch; i++) {
        int64_t est = 0;
        for (int k = 0; k < 3; k++) {
            int64_t a = c.chunks[i].y0 < (int64_t)rows[k] ? c.chunks[i].y0 : (int64_t)rows[k];
            int64_t b = c.chunks[i].y1 < (int64_t)rows[k] ? c.chunks[i].y1 : (int64_t)rows[k];
            est += c.rowcount[k][b] - c.rowcount[k][a];
        }
        /* 2 per vertex on average; the rows of a chunk can hold more (its
         * cells also use the vertices of the row before): 25 % slack, the
         * pages never written cost nothing */
        c.chunks[i].region_cap = est * 2 + est / 2 + 256;
        tcap += c.chunks[i].region_cap;
    }
    if (tcap > INT32_MAX) tcap = INT32_MAX; /* the mesh limit: the spill path reports it */
    m->nvertices = 0;
    m->ntriangles = 0;
    st = bvox__mesh_grow(m, 0, tcap);
    if (st) {
        mc_release(&c);
        return st;
    }
    for (int64_t i = 0, off = 0; i < nch; i++) {
        if (off + c.chunks[i].region_cap > tcap)
            c.chunks[i].region_cap = tcap > off ? tcap - off : 0;
        c.chunks[i].region = m->triangles + 3 * off;
        off += c.chunks[i].region_cap;
    }
    dyn_for(nch, 1, tri_chunks, &c);
    int64_t ntri = 0, ncent = 0;
    int spilled = 0;
    for (int i = 0; i < nch && !st; i++) {
        st = c.chunks[i].st;
        ntri += c.chunks[i].nregion + (int64_t)(c.chunks[i].tris.size / (3 * sizeof(int32_t)));
        ncent += (int64_t)(c.chunks[i].centres.size / (3 * sizeof(double)));
        spilled |= c.chunks[i].spilled;
    }
    if (!st && (total + ncent > INT32_MAX || ntri > INT32_MAX))
        st = bvox__fail(BVOX_ETOOBIG, "the mesh would be too large (%lld triangles)",
                        (long long)ntri);
    int32_t *dst = m->triangles;
    size_t dst_bytes = 0;
    if (!st && spilled) { /* rare: gather into a new array */
        dst_bytes = (size_t)(ntri ? ntri : 1) * 3 * sizeof(int32_t);
        dst = bvox__alloc(dst_bytes, false, "mesh triangles", &st);
    }
    if (!st) st = bvox__mesh_grow(m, total + ncent, 0);
    if (st) {
        if (dst != m->triangles && dst) bvox__free(dst, dst_bytes);
        mc_release(&c);
        return st;
    }
    c.verts = m->vertices;
    dyn_for((int64_t)g->ny + 1, 8, vert_rows, &c);
    int64_t cb = total, tb = 0;
    for (int i = 0; i < nch; i++) {
        chunk *ch = &c.chunks[i];
        const double *cp = ch->centres.data;
        int64_t nc = (int64_t)(ch->centres.size / (3 * sizeof(double)));
        for (int64_t j = 0; j < nc; j++)
            put(&c, cb + j, cp[3 * j], cp[3 * j + 1], cp[3 * j + 2]);
        /* region (moved down over the gaps) then spill, in order */
        int32_t *to = dst + 3 * tb;
        if (to != ch->region) memmove(to, ch->region, (size_t)ch->nregion * 3 * sizeof(int32_t));
        int64_t n = ch->nregion * 3;
        const int32_t *sp = ch->tris.data;
        int64_t ns = (int64_t)(ch->tris.size / sizeof(int32_t));
        if (ns) memcpy(to + n, sp, (size_t)ns * sizeof(int32_t));
        n += ns;
        if (nc)
            for (int64_t j = 0; j < n; j++)
                if (to[j] < 0) to[j] = (int32_t)(cb + (-(int64_t)to[j] - 1));
        tb += n / 3;
        cb += nc;
    }
    if (dst != m->triangles) {
        bvox__free(m->triangles, (size_t)m->tcap * 3 * sizeof(int32_t));
        m->triangles = dst;
        m->tcap = ntri ? ntri : 1;
    }
    m->nvertices = total + ncent;
    m->ntriangles = ntri;
    mc_release(&c);
    return BVOX_OK;
}
