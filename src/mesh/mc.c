/*
 * mc.c — marching cubes on a binary volume, 64 cells at a time.
 *
 * With binary data every vertex is the midpoint of a grid edge whose two
 * voxels differ, so a vertex IS its edge: no floats are compared or hashed.
 * The crossed edges of each kind are the bits of XORs of column words (x
 * edges: column ^ column to its right; y edges: column ^ column behind;
 * z edges: column ^ column shifted by one), and an edge's vertex number is
 * a running popcount: pass 1 (each column word read once for the three
 * kinds) stores, per edge column, how many crossed edges of its kind come
 * before it in its row, plus a total per row (a small array: one entry per
 * column, not per word). Triangles (pass 2, one region of the triangle
 * array per chunk of rows, closed up in order so the result does not depend
 * on the thread count) classify 64 cells from the 8 corner words of a cell
 * word, skip the word when all 8 are equal (uniform cells), and number each
 * vertex as its edge column's first vertex + the crossings of the words
 * below (counted while walking up the column: the crossings of cube edge e
 * in a cell word are the XOR of its two corner words) + the popcount of the
 * mask bits below it. The vertex count is known after pass 1, so the
 * vertex array is allocated before pass 2, which also writes the positions:
 * each edge column's vertices by the one cell column that owns it. Chunks
 * are taken dynamically by the threads (the surface is uneven).
 */
#include "mesh_private.h"

#include <stdatomic.h>
#include <assert.h>
#include <stdlib.h>
#include <string.h>

/* The hot loops are cloned for CPUs with POPCNT (GCC's target_clones: an
 * ifunc picks the clone at load time, the binary stays portable); elsewhere
 * the portable popcount. Not under ThreadSanitizer: the ifunc resolver runs
 * while the program is relocated, before TSan's runtime is ready, and
 * crashes in its instrumentation. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_THREAD__)
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

/* A case as the fast path of pass 2 uses it: its triangles' corners as
 * cube edges, in output order (orientation applied), unused entries 0;
 * slow: a case with loop centres (the slow path adds them). */
typedef struct fast_case {
    uint8_t ntri, slow;
    uint8_t v[15];
} fast_case;

typedef struct mc {
    bvox__grid g;
    const bvox_geometry *geo;
    const bvox__mc_case *tab;
    const uint64_t *zero; /* a zero column of cw words */
    uint32_t *pre[3];     /* per edge column: crossings before it in its row */
    size_t pre_bytes[3];
    const uint32_t *zrow; /* a zero prefix row (rows outside) */
    size_t stride[3];     /* prefix entries per row: columns + 3 */
    int64_t nrows[3];
    int64_t *rowcount[3]; /* then row bases */
    int64_t tbase[3];
    size_t row_cols[3];   /* columns per row of each edge kind */
    fast_case fast[256];
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
/* ---- pass 1: per-column prefix counts of crossed edges ---- */

/* Row r of a kind's prefix array: stride entries, e[0] = 0, e[1 + i] = the
 * crossings before edge column i, e[1 + ncol] = e[2 + ncol] = the row's
 * total; so that column i's count, e[i + 2] - e[i + 1], is 0 for the
 * columns just outside (i = -1 and i = ncol). Rows outside: zeros. */
static inline const uint32_t *prow(const mc *c, int k, int64_t r)
{
    if (r < 0 || r >= c->nrows[k]) return c->zrow;
    return c->pre[k] + (size_t)r * c->stride[k];
}
static inline uint32_t pcount(const uint32_t *p, int64_t i)
{
    return p[i + 2] - p[i + 1];
}
/* Vertex index base of kind k's row r (0 outside). */
static inline int64_t rbase(const mc *c, int k, int64_t r)
{
    if (r < 0 || r >= c->nrows[k]) return 0;
    return c->tbase[k] + c->rowcount[k][r];
}

/* Row y of all three kinds at once, each column's words read once: y edges
 * of row y (volume rows y - 1 and y), x and z edges of volume row y. */
HOT static void count_row(mc *c, int32_t y)
{
    const bvox__grid *g = &c->g;
    /* 64-bit: a row can hold more than 2^32 crossings (the total check then
     * refuses the mesh; the 32-bit prefixes are only used below that) */
    uint64_t r0 = 0, r1 = 0, r2 = 0;
    const size_t nw = g->wpc, nx = (size_t)g->nx;
    const int has = y < g->ny; /* x and z rows exist */
    uint32_t *p0 = has ? c->pre[0] + (size_t)y * c->stride[0] : NULL;
    uint32_t *p1 = c->pre[1] + (size_t)y * c->stride[1];
    uint32_t *p2 = has ? c->pre[2] + (size_t)y * c->stride[2] : NULL;
    const uint64_t *left = c->zero;
    /* volume rows y and y - 1 (NULL outside: the zero column instead) */
    const uint64_t *row = has ? g->words + (size_t)y * nx * nw : NULL;
    const uint64_t *prev = y > 0 ? g->words + (size_t)(y - 1) * nx * nw : NULL;
    for (size_t x = 0; x < nx; x++) {
        const uint64_t *cur = row ? row + x * nw : c->zero;
        const uint64_t *above = prev ? prev + x * nw : c->zero;
        p1[1 + x] = (uint32_t)r1;
        if (has) {
            p0[1 + x] = (uint32_t)r0;
            p2[1 + x] = (uint32_t)r2;
            uint64_t carry = 0;
            for (size_t w = 0; w < nw; w++) {
                uint64_t h = cur[w];
                r0 += POPCOUNT(h ^ left[w]);
                r1 += POPCOUNT(h ^ above[w]);
                r2 += POPCOUNT(h ^ ((h << 1) | carry));
                carry = h >> 63;
            }
            r2 += carry; /* the cell word past the column (nz % 64 == 0) */
        } else {
            for (size_t w = 0; w < nw; w++) r1 += POPCOUNT(above[w]);
        }
        left = cur;
    }
    p1[0] = 0;
    p1[1 + nx] = p1[2 + nx] = (uint32_t)r1;
    c->rowcount[1][y] = (int64_t)r1;
    if (!has) return;
    p0[1 + nx] = (uint32_t)r0; /* x edge column nx: the last column against 0s */
    for (size_t w = 0; w < nw; w++) r0 += POPCOUNT(left[w]);
    p0[0] = 0;
    p0[2 + nx] = p0[3 + nx] = (uint32_t)r0;
    p2[0] = 0;
    p2[1 + nx] = p2[2 + nx] = (uint32_t)r2;
    c->rowcount[0][y] = (int64_t)r0;
    c->rowcount[2][y] = (int64_t)r2;
}

static void count_rows(void *ctx, int64_t begin, int64_t end)
{
    mc *c = ctx;
    for (int64_t y = begin; y < end; y++) count_row(c, (int32_t)y);
}

/* ---- pass 2: triangles ---- */

/* The edge-column prefix rows around cell row Y and their vertex bases:
 * x edges of rows Y-1 (x0) and Y (x1), y edges of row Y (y), z edges of
 * rows Y-1 (z0) and Y (z1). */
typedef struct cellrow {
    const uint32_t *x0, *x1, *y, *z0, *z1;
    int64_t bx0, bx1, by, bz0, bz1;
} cellrow;

static void cellrow_init(const mc *c, int32_t Y, cellrow *cr)
{
    cr->x0 = prow(c, 0, Y - 1);
    cr->x1 = prow(c, 0, Y);
    cr->y = prow(c, 1, Y);
    cr->z0 = prow(c, 2, Y - 1);
    cr->z1 = prow(c, 2, Y);
    cr->bx0 = rbase(c, 0, Y - 1);
    cr->bx1 = rbase(c, 0, Y);
    cr->by = rbase(c, 1, Y);
    cr->bz0 = rbase(c, 2, Y - 1);
    cr->bz1 = rbase(c, 2, Y);
}

/* 1 if some edge of the cells of column X is crossed. */
static inline int column_has_surface(const cellrow *cr, int64_t X)
{
    return (pcount(cr->x0, X) | pcount(cr->x1, X) | pcount(cr->y, X - 1) | pcount(cr->y, X) |
            pcount(cr->z0, X - 1) | pcount(cr->z0, X) | pcount(cr->z1, X - 1) |
            pcount(cr->z1, X)) != 0;
}

/* The first vertex index of the edge column of each of the 12 cube edges
 * of the cells of column X: x edges: rows Y-1 (e 0, 2) and Y (e 1, 3) at
 * column X; y edges: row Y at columns X-1 (e 4, 6) and X (e 5, 7); z edges:
 * rows Y-1, Y and columns X-1, X (e 8 + dx + 2 dy). Edge columns outside
 * the grid are never crossed (their base is never used). */
static inline void column_bases(const cellrow *cr, int64_t X, int64_t base[12])
{
    base[0] = base[2] = cr->bx0 + cr->x0[1 + X];
    base[1] = base[3] = cr->bx1 + cr->x1[1 + X];
    base[4] = base[6] = cr->by + cr->y[X];
    base[5] = base[7] = cr->by + cr->y[1 + X];
    base[8] = cr->bz0 + cr->z0[X];
    base[9] = cr->bz0 + cr->z0[1 + X];
    base[10] = cr->bz1 + cr->z1[X];
    base[11] = cr->bz1 + cr->z1[1 + X];
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

/* ---- vertex positions ---- */

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

/* The vertices of the crossings m (bits of cell word w) of one edge column,
 * numbered from idx up, at index-space (px, py, w * 64 + bit + dz). x and y
 * are the same for the whole column: with the identity direction only z is
 * computed per vertex. */
static inline void put_bits(const mc *c, int64_t idx, uint64_t m, size_t w, double px, double py,
                            double dz)
{
    const bvox_geometry *geo = c->geo;
    if (c->axis_aligned) {
        double wx = geo->origin[0] + px * geo->spacing[0];
        double wy = geo->origin[1] + py * geo->spacing[1];
        double oz = geo->origin[2], sz = geo->spacing[2];
        double *q = c->verts + 3 * idx;
        for (; m; m &= m - 1, q += 3) {
            double pz = (double)(w * 64 + (size_t)__builtin_ctzll(m)) + dz;
            q[0] = wx;
            q[1] = wy;
            q[2] = oz + pz * sz;
        }
        return;
    }
    for (; m; m &= m - 1) put(c, idx++, px, py, (double)(w * 64 + (size_t)__builtin_ctzll(m)) + dz);
}

HOT static void tri_chunks(void *ctx, int64_t begin, int64_t end)
{
    mc *c = ctx;
    const bvox__grid *g = &c->g;
    const bvox__mc_case *tab = c->tab;
    const int i1 = c->mirrored ? 2 : 1, i2 = c->mirrored ? 1 : 2;
    for (int64_t k = begin; k < end; k++) {
        chunk *ch = &c->chunks[k];
        /* the hot counters live here, not in the chunk array, whose
         * neighbouring entries belong to other threads (false sharing) */
        int64_t nregion = 0, region_cap = ch->region_cap;
        for (int32_t Y = ch->y0; Y < ch->y1 && !ch->st; Y++) {
            cellrow cr;
            cellrow_init(c, Y, &cr);
            for (int32_t X = 0; X <= g->nx && !ch->st; X++) {
                if (!column_has_surface(&cr, X)) continue; /* all cells uniform */
                const uint64_t *p[4] = {col(c, X, Y), col(c, X + 1, Y), col(c, X, Y + 1),
                                        col(c, X + 1, Y + 1)};
                /* id of cube edge e's vertex in cell bit b of word w: base[e]
                 * (its edge column's first vertex + the crossings of the
                 * column's words below w) + those below bit b in word w */
                int64_t base[12];
                column_bases(&cr, X, base);
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
                    if (!mixed) continue; /* no edge of the word is crossed */
                    /* crossings of each cube edge: the XOR of its corners
                     * (bvox__mc_edge_corners, spelled out for the compiler) */
                    const uint64_t xe[12] = {cw[0] ^ cw[1], cw[2] ^ cw[3], cw[4] ^ cw[5],
                                             cw[6] ^ cw[7], cw[0] ^ cw[2], cw[1] ^ cw[3],
                                             cw[4] ^ cw[6], cw[5] ^ cw[7], cw[0] ^ cw[4],
                                             cw[1] ^ cw[5], cw[2] ^ cw[6], cw[3] ^ cw[7]};
                    /* pass 3, the vertex positions, here: the cell column
                     * (X, Y) writes those of 3 of its 12 edge columns, the
                     * x edges of row Y at column X (cube edge 3), the y
                     * edges of row Y at column X (7), the z edges of row Y
                     * at column X (11): each edge column has exactly one
                     * such cell column, a surface column, and each crossing
                     * lies in a mixed word */
                    if (xe[3]) put_bits(c, base[3], xe[3], w, X - 0.5, Y, 0);
                    if (xe[7]) put_bits(c, base[7], xe[7], w, X, Y - 0.5, 0);
                    if (xe[11]) put_bits(c, base[11], xe[11], w, X, Y, -0.5);
                    while (mixed) {
                        unsigned bit = (unsigned)__builtin_ctzll(mixed);
                        mixed &= mixed - 1;
                        unsigned kase = bvox__grid_case(cw, bit);
                        const uint64_t below = (1ull << bit) - 1;
                        const fast_case *fc = &c->fast[kase];
                        if (!fc->slow && nregion + 5 <= region_cap) {
                            /* the usual cell, without loops over its
                             * edges or triangles: 2 triangles written,
                             * 2 more when there are more, a 5th when
                             * there is one (what lies past ntri is
                             * overwritten by the next cell or unused),
                             * each corner's id computed where it is
                             * written */
                            int32_t *o = ch->region + 3 * nregion;
                            for (int j = 0; j < 6; j++) {
                                int e = fc->v[j];
                                o[j] = (int32_t)(base[e] + POPCOUNT(xe[e] & below));
                            }
                            if (fc->ntri > 2) {
                                for (int j = 6; j < 12; j++) {
                                    int e = fc->v[j];
                                    o[j] = (int32_t)(base[e] + POPCOUNT(xe[e] & below));
                                }
                                if (fc->ntri > 4)
                                    for (int j = 12; j < 15; j++) {
                                        int e = fc->v[j];
                                        o[j] = (int32_t)(base[e] + POPCOUNT(xe[e] & below));
                                    }
                            }
                            nregion += fc->ntri;
                            continue;
                        }
                        const bvox__mc_case *cs = &tab[kase];
                        int32_t ids[16];
                        for (unsigned em = cs->edges; em; em &= em - 1) {
                            int e = __builtin_ctz(em);
                            ids[e] = (int32_t)(base[e] + POPCOUNT(xe[e] & below));
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
                    for (int e = 0; e < 12; e++) base[e] += POPCOUNT(xe[e]);
                }
            }
        }
        ch->nregion = nregion;
    }
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
    free((void *)c->zrow);
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
#ifndef NDEBUG
    for (int e = 0; e < 12; e++) { /* the corners spelled out in tri_chunks */
        static const uint8_t ec[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                          {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
        int c0, c1;
        bvox__mc_edge_corners(e, &c0, &c1);
        BVOX_ASSERT(c0 == ec[e][0] && c1 == ec[e][1]);
    }
#endif
    for (int k = 0; k < 256; k++) {
        const bvox__mc_case *cs = &c.tab[k];
        fast_case *fc = &c.fast[k];
        memset(fc, 0, sizeof *fc);
        fc->ntri = cs->ntri;
        fc->slow = cs->centres != 0 || cs->ntri > 5;
        if (fc->slow) continue;
        for (int t = 0; t < cs->ntri; t++) {
            fc->v[3 * t] = cs->tri[t][0];
            fc->v[3 * t + 1] = cs->tri[t][c.mirrored ? 2 : 1];
            fc->v[3 * t + 2] = cs->tri[t][c.mirrored ? 1 : 2];
        }
    }
    const bvox__grid *g = &c.g;
    bvox_status st = BVOX_OK;
    c.zero = bvox__mem_zalloc(g->cw + 1, sizeof(uint64_t));
    c.zrow = bvox__mem_zalloc((size_t)g->nx + 4, sizeof(uint32_t));
    size_t rows[3] = {(size_t)g->ny, (size_t)g->ny + 1, (size_t)g->ny};
    c.row_cols[0] = (size_t)g->nx + 1;
    c.row_cols[1] = (size_t)g->nx;
    c.row_cols[2] = (size_t)g->nx;
    if (!c.zero || !c.zrow) st = bvox__fail(BVOX_ENOMEM, "out of memory (marching cubes)");
    for (int k = 0; k < 3 && !st; k++) {
        size_t n;
        c.stride[k] = c.row_cols[k] + 3;
        c.nrows[k] = (int64_t)rows[k];
        if (!bvox__mul_size(rows[k], c.stride[k] * sizeof(uint32_t), &n)) {
            st = bvox__fail(BVOX_ETOOBIG, "volume too large to mesh");
            break;
        }
        c.pre_bytes[k] = n ? n : 1;
        c.pre[k] = bvox__alloc(c.pre_bytes[k], false, "marching cubes edge index", &st);
        c.rowcount[k] = bvox__mem_zalloc(rows[k] + 1, sizeof(int64_t));
        if (!c.pre[k]) break;
        if (!c.rowcount[k]) st = bvox__fail(BVOX_ENOMEM, "out of memory (marching cubes)");
    }
    if (st) {
        mc_release(&c);
        return st;
    }
    bvox__parallel_for_dynamic((int64_t)g->ny + 1, 4, count_rows, &c);
    if ((st = bvox__progress(0.4))) { /* the count pass: about 40 % of the work */
        mc_release(&c);
        return st;
    }
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
    int threads = bvox__parallelism();
    int nch = threads * 16; /* blocks for the dynamic for: small enough to balance */
    if (nch > g->ny + 1) nch = g->ny + 1;
    c.nchunks = nch;
    c.chunks = bvox__mem_zalloc((size_t)nch, sizeof(chunk));
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
    /* the vertices of the crossed edges are known: allocated now and
     * written with the triangles (loop centres, if any, are added after) */
    st = bvox__mesh_grow(m, total, tcap);
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
    c.verts = m->vertices;
    bvox__parallel_for_dynamic(nch, 1, tri_chunks, &c);
    m->nvertices = total; /* kept if the array grows for the centres */
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
    if (!st && ncent) st = bvox__mesh_grow(m, total + ncent, 0);
    if (st) {
        if (dst != m->triangles && dst) bvox__free(dst, dst_bytes);
        mc_release(&c);
        return st;
    }
    c.verts = m->vertices;
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
