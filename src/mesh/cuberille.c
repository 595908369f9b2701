/*
 * cuberille.c — the boundary faces of the voxels (Artzy, Frieder and
 * Herman's cuberille), two triangles per exposed face, vertices shared.
 *
 * Vertices sit on voxel corners, i.e. at the centres of the marching-cubes
 * cells (the 2x2x2 voxels around a corner). The exposed faces touching a
 * corner are exactly the crossed edges of that cell, and the loops of the
 * marching-cubes case (mc_table.c) group them into surface sheets. Each
 * sheet gets its own vertex: a corner where voxels touch only along an edge
 * or at a point is duplicated, one copy per sheet, so every mesh edge is on
 * exactly two triangles (the 1-voxels are taken as 6-connected, as in the
 * marching-cubes table). One case remains: a voxel edge whose four voxels
 * are 1, 0, 1, 0 around it carries two sheets, and both may belong to the
 * same loop at both of its end corners; the edge would then be on four
 * triangles. So every such "diagonal" edge gets two midpoint vertices, one
 * per 1-voxel, and the faces of each 1-voxel along it go through its own
 * midpoint (the face becomes a polygon of up to 8 points, fanned from a
 * midpoint). Geometry is unchanged by the duplication and the midpoints:
 * the enclosed volume is the voxel volume exactly.
 *
 * Numbering: the first sheet of every mixed cell is numbered by popcount of
 * the mixed-cell masks (a prefix per word, as mc.c does for edges); the rare
 * further sheets follow, found by binary search in a sorted list of the
 * multi-sheet cells. Each face is emitted once, by the cell at its lower
 * corner (its cube edge 3, 7 or 11), with the other three cells looked up.
 */
#include "mesh_private.h"

#include <stdlib.h>
#include <string.h>

typedef struct multi {
    uint64_t key;   /* cell (Y * (nx+1) + X) * cw * 64 + Z */
    int64_t first;  /* index of its second sheet among the extra vertices */
} multi;

typedef struct rowinfo {
    int64_t cells;  /* mixed cells (first sheets) */
    int64_t tris;
    int64_t diag[3]; /* diagonal edges of each direction (2 vertices each) */
} rowinfo;

typedef struct cchunk {
    int32_t y0, y1;
    bvox__buf multis; /* multi entries ('first' = number of extra sheets) */
    bvox_status st;
} cchunk;

typedef struct cub {
    bvox__grid g;
    const bvox_geometry *geo;
    const bvox__mc_case *tab;
    const uint64_t *zero;
    uint32_t *pre;      /* per cell word: mixed cells before it in its row */
    uint32_t *dpre[3];  /* per column word: diagonal edges before it in its row */
    size_t pre_bytes, dpre_bytes;
    rowinfo *rows;      /* then bases */
    cchunk *chunks;
    int nchunks;
    multi *multis;
    int64_t nmulti;
    int64_t extra_base, dbase[3];
    double *verts;
    int32_t *tris;
    int mirrored;
} cub;

static inline const uint64_t *col(const cub *c, int32_t X, int32_t Y)
{
    const bvox__grid *g = &c->g;
    if (X < 1 || X > g->nx || Y < 1 || Y > g->ny) return c->zero;
    return g->words + ((size_t)(Y - 1) * (size_t)g->nx + (size_t)(X - 1)) * g->wpc;
}

static inline void corners(const cub *c, int32_t X, int32_t Y, size_t w, uint64_t cw[8])
{
    const uint64_t *p[4] = {col(c, X, Y), col(c, X + 1, Y), col(c, X, Y + 1),
                            col(c, X + 1, Y + 1)};
    for (int i = 0; i < 4; i++) {
        uint64_t h = w < c->g.wpc ? p[i][w] : 0;
        uint64_t prev = (w >= 1 && w - 1 < c->g.wpc) ? p[i][w - 1] : 0;
        cw[4 + i] = h;
        cw[i] = (h << 1) | (prev >> 63);
    }
}

static inline uint64_t up(const cub *c, const uint64_t *p, size_t w)
{
    return (p[w] >> 1) | (w + 1 < c->g.wpc ? p[w + 1] << 63 : 0);
}

/* Diagonal-edge mask of word w, direction k, at column (X, Y) (see
 * diag_slot for the layout). */
static inline uint64_t diag_word(const cub *c, int k, int32_t X, int32_t Y, size_t w)
{
    uint64_t a, b, cc, d;
    if (k == 2) {
        a = col(c, X, Y)[w];
        b = col(c, X + 1, Y)[w];
        cc = col(c, X, Y + 1)[w];
        d = col(c, X + 1, Y + 1)[w];
    } else {
        const uint64_t *A = col(c, X, Y), *B = k == 0 ? col(c, X, Y + 1) : col(c, X + 1, Y);
        a = A[w];
        b = B[w];
        cc = up(c, A, w);
        d = up(c, B, w);
    }
    return (a & d & ~b & ~cc) | (b & cc & ~a & ~d);
}

/* The slot of the voxel edge from the corner of cell (X, Y, Z) to the next
 * corner along axis k: column (*dx, *dy), bit *dz of direction k's masks.
 * x edges: columns (X+1, Y) and (X+1, Y+1), z and z+1; y edges: (X, Y+1)
 * and (X+1, Y+1); z edges: the four columns (X..X+1, Y..Y+1) at z. */
static void diag_slot(int k, int32_t X, int32_t Y, int32_t Z, int32_t *dx, int32_t *dy,
                      int32_t *dz)
{
    *dx = k == 0 ? X + 1 : X;
    *dy = k == 1 ? Y + 1 : Y;
    *dz = k == 2 ? Z : Z - 1;
}

static inline int32_t diag_vertex(const cub *c, int k, int32_t X, int32_t Y, int32_t z, int side)
{
    size_t w = (size_t)z >> 6;
    uint64_t m = diag_word(c, k, X, Y, w) & ((1ull << (z & 63)) - 1);
    size_t i = ((size_t)Y * (size_t)(c->g.nx + 1) + (size_t)X) * c->g.wpc + w;
    return (int32_t)(c->dbase[k] + c->rows[Y].diag[k] + c->dpre[k][i] +
                     2 * bvox__popcount64(m) + side);
}

static inline uint64_t cell_key(const cub *c, int32_t X, int32_t Y, int32_t Z)
{
    return ((uint64_t)Y * (uint64_t)(c->g.nx + 1) + (uint64_t)X) * c->g.cw * 64 + (uint64_t)Z;
}

/* A cell's case and mixed-cell word (for its first sheet's number). */
typedef struct ringcell {
    int32_t X, Y, Z;
    unsigned k;
    uint64_t mixed;
} ringcell;

static inline void ring_cell(const cub *c, int32_t X, int32_t Y, int32_t Z, ringcell *r)
{
    uint64_t cw[8];
    corners(c, X, Y, (size_t)Z >> 6, cw);
    r->X = X;
    r->Y = Y;
    r->Z = Z;
    r->k = bvox__grid_case(cw, (unsigned)Z & 63);
    r->mixed = bvox__grid_mixed(cw);
}

/* The vertex of the sheet of cell r that holds its cube edge e. */
static int32_t sheet_vertex(const cub *c, const ringcell *r, int e)
{
    size_t w = (size_t)r->Z >> 6;
    unsigned bit = (unsigned)r->Z & 63;
    int L = c->tab[r->k].edge_loop[e];
    if (L <= 0)
        return (int32_t)(c->rows[r->Y].cells +
                         c->pre[((size_t)r->Y * (size_t)(c->g.nx + 1) + (size_t)r->X) * c->g.cw +
                                w] +
                         bvox__popcount64(r->mixed & ((1ull << bit) - 1)));
    uint64_t key = cell_key(c, r->X, r->Y, r->Z);
    int64_t lo = 0, hi = c->nmulti - 1;
    while (lo < hi) {
        int64_t mid = (lo + hi) / 2;
        if (c->multis[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return (int32_t)(c->extra_base + c->multis[lo].first + L - 1);
}

static const int face_edge[3] = {3, 7, 11};
/* the four cells around each face, counter-clockwise seen from +axis: cell
 * offsets (dx, dy, dz) and the face's cube edge in that cell */
static const int8_t ring[3][4][4] = {
    {{0, 0, 0, 3}, {0, 1, 0, 2}, {0, 1, 1, 0}, {0, 0, 1, 1}},   /* x faces, (y, z) */
    {{0, 0, 0, 7}, {0, 0, 1, 5}, {1, 0, 1, 4}, {1, 0, 0, 6}},   /* y faces, (z, x) */
    {{0, 0, 0, 11}, {1, 0, 0, 10}, {1, 1, 0, 8}, {0, 1, 0, 9}}, /* z faces, (x, y) */
};

/* The polygon of the face (cube edge face_edge[f] of cell (X, Y, Z), case
 * k, mixed word mixed): its 4 corners (the sheets of the 4 cells around it)
 * with the midpoints of its diagonal edges between them, counter-clockwise
 * from outside. The voxel edge between two ring cells is diagonal when the
 * cells' common face is ambiguous. Returns its length; with poly == NULL
 * only counts. *mid gets the position of a midpoint (-1 if none). */
static int face_polygon(const cub *c, int32_t X, int32_t Y, int32_t Z, int f, unsigned k,
                        uint64_t mixed, int32_t *poly, int *mid)
{
    int e = face_edge[f], c0, c1;
    bvox__mc_edge_corners(e, &c0, &c1);
    int outward_pos = (k >> c0) & 1; /* the lower voxel is the 1 */
    int vin = outward_pos ? c0 : c1;
    int32_t VX = X + (vin & 1), VY = Y + ((vin >> 1) & 1);
    ringcell rc[4];
    rc[0] = (ringcell){X, Y, Z, k, mixed};
    for (int i = 1; i < 4; i++)
        ring_cell(c, X + ring[f][i][0], Y + ring[f][i][1], Z + ring[f][i][2], &rc[i]);
    int n = 0;
    *mid = -1;
    for (int i = 0; i < 4; i++) {
        const int8_t *r = ring[f][i], *r2 = ring[f][(i + 1) & 3];
        if (poly) poly[n] = sheet_vertex(c, &rc[i], r[3]);
        n++;
        /* the voxel edge from ring cell i to i + 1: cell i's face toward it */
        int k2 = r[0] != r2[0] ? 0 : r[1] != r2[1] ? 1 : 2;
        int side = r2[k2] > r[k2];
        if (!((c->tab[rc[i].k].diag_faces >> (k2 * 2 + side)) & 1)) continue;
        int32_t lx = X + (r[0] < r2[0] ? r[0] : r2[0]), ly = Y + (r[1] < r2[1] ? r[1] : r2[1]),
                lz = Z + (r[2] < r2[2] ? r[2] : r2[2]);
        if (poly) {
            int32_t dx, dy, dz;
            diag_slot(k2, lx, ly, lz, &dx, &dy, &dz);
            int vside = k2 == 0 ? VY - dy : VX - dx;
            poly[n] = diag_vertex(c, k2, dx, dy, dz, vside);
        }
        if (*mid < 0) *mid = n;
        n++;
    }
    if (poly && outward_pos == c->mirrored) { /* reverse, keeping poly[0] */
        for (int i = 1, j = n - 1; i < j; i++, j--) {
            int32_t s = poly[i];
            poly[i] = poly[j];
            poly[j] = s;
        }
        if (*mid > 0) *mid = n - *mid;
    }
    return n;
}

static void pass_count(void *ctx, int64_t begin, int64_t end)
{
    cub *c = ctx;
    const bvox__grid *g = &c->g;
    for (int64_t kk = begin; kk < end; kk++) {
        cchunk *ch = &c->chunks[kk];
        for (int32_t Y = ch->y0; Y < ch->y1; Y++) {
            int64_t run = 0, tris = 0;
            for (int32_t X = 0; X <= g->nx; X++) {
                uint32_t *pre = c->pre + ((size_t)Y * (size_t)(g->nx + 1) + (size_t)X) * g->cw;
                for (size_t w = 0; w < g->cw; w++) {
                    uint64_t cw[8];
                    corners(c, X, Y, w, cw);
                    uint64_t mixed = bvox__grid_mixed(cw);
                    pre[w] = (uint32_t)run;
                    run += bvox__popcount64(mixed);
                    for (; mixed; mixed &= mixed - 1) {
                        unsigned bit = (unsigned)__builtin_ctzll(mixed);
                        int32_t Z = (int32_t)(w * 64 + bit);
                        unsigned k = bvox__grid_case(cw, bit);
                        const bvox__mc_case *cs = &c->tab[k];
                        for (int f = 0; f < 3; f++) {
                            if (cs->edge_loop[face_edge[f]] < 0) continue;
                            int mid;
                            tris += face_polygon(c, X, Y, Z, f, k, 0, NULL, &mid) - 2;
                        }
                        if (cs->nloops > 1 && !ch->st) {
                            bvox_status st = bvox__buf_reserve(
                                &ch->multis, ch->multis.size + sizeof(multi), "cuberille sheets");
                            if (st) {
                                ch->st = st;
                                continue;
                            }
                            multi *mm = (multi *)((char *)ch->multis.data + ch->multis.size);
                            mm->key = cell_key(c, X, Y, Z);
                            mm->first = cs->nloops - 1;
                            ch->multis.size += sizeof(multi);
                        }
                    }
                }
            }
            c->rows[Y].cells = run;
            c->rows[Y].tris = tris;
            for (int k = 0; k < 3; k++) {
                uint64_t drun = 0; /* see mc.c: the total check bounds it */
                for (int32_t X = 0; X <= g->nx; X++) {
                    uint32_t *dp =
                        c->dpre[k] + ((size_t)Y * (size_t)(g->nx + 1) + (size_t)X) * g->wpc;
                    for (size_t w = 0; w < g->wpc; w++) {
                        dp[w] = (uint32_t)drun;
                        drun += 2 * (uint64_t)bvox__popcount64(diag_word(c, k, X, Y, w));
                    }
                }
                c->rows[Y].diag[k] = (int64_t)drun;
            }
        }
    }
}

static void pass_emit(void *ctx, int64_t begin, int64_t end)
{
    cub *c = ctx;
    const bvox__grid *g = &c->g;
    for (int64_t yy = begin; yy < end; yy++) {
        int32_t Y = (int32_t)yy;
        int64_t vi = c->rows[Y].cells;
        int32_t *t = c->tris + 3 * c->rows[Y].tris;
        for (int32_t X = 0; X <= g->nx; X++)
            for (size_t w = 0; w < g->cw; w++) {
                uint64_t cw[8];
                corners(c, X, Y, w, cw);
                const uint64_t mixed_word = bvox__grid_mixed(cw);
                for (uint64_t mixed = mixed_word; mixed; mixed &= mixed - 1) {
                    unsigned bit = (unsigned)__builtin_ctzll(mixed);
                    int32_t Z = (int32_t)(w * 64 + bit);
                    unsigned k = bvox__grid_case(cw, bit);
                    const bvox__mc_case *cs = &c->tab[k];
                    double p[3];
                    bvox__grid_world(c->geo, X - 0.5, Y - 0.5, Z - 0.5, p);
                    memcpy(c->verts + 3 * vi++, p, sizeof p);
                    if (cs->nloops > 1) {
                        ringcell self = {X, Y, Z, k, mixed_word};
                        int32_t first = sheet_vertex(c, &self, cs->loop[1][0]);
                        for (int L = 1; L < cs->nloops; L++)
                            memcpy(c->verts + 3 * (first + L - 1), p, sizeof p);
                    }
                    for (int f = 0; f < 3; f++) {
                        if (cs->edge_loop[face_edge[f]] < 0) continue;
                        int32_t q[8];
                        int mid;
                        int n = face_polygon(c, X, Y, Z, f, k, mixed_word, q, &mid);
                        int s = mid < 0 ? 0 : mid;
                        for (int i = 1; i + 1 < n; i++) {
                            t[0] = q[s];
                            t[1] = q[(s + i) % n];
                            t[2] = q[(s + i + 1) % n];
                            t += 3;
                        }
                    }
                }
            }
        /* the midpoints of this row's diagonal edges, two per edge */
        static const double off[3][3] = {{-1, -0.5, 0.5}, {-0.5, -1, 0.5}, {-0.5, -0.5, 0}};
        for (int k = 0; k < 3; k++) {
            int64_t di = c->dbase[k] + c->rows[Y].diag[k];
            for (int32_t X = 0; X <= g->nx; X++)
                for (size_t w = 0; w < g->wpc; w++)
                    for (uint64_t m = diag_word(c, k, X, Y, w); m; m &= m - 1) {
                        double z = (double)(w * 64 + (size_t)__builtin_ctzll(m));
                        double p[3];
                        bvox__grid_world(c->geo, X + off[k][0], Y + off[k][1], z + off[k][2], p);
                        memcpy(c->verts + 3 * di++, p, sizeof p);
                        memcpy(c->verts + 3 * di++, p, sizeof p);
                    }
        }
    }
}

static void cub_release(cub *c)
{
    if (c->pre) bvox__free(c->pre, c->pre_bytes);
    for (int k = 0; k < 3; k++)
        if (c->dpre[k]) bvox__free(c->dpre[k], c->dpre_bytes);
    free(c->rows);
    if (c->chunks)
        for (int i = 0; i < c->nchunks; i++) bvox__buf_release(&c->chunks[i].multis);
    free(c->chunks);
    free(c->multis);
    free((void *)c->zero);
}

bvox_status bvox__mesh_cuberille(const bvox_volume *vol, bvox_mesh *m)
{
    cub c;
    memset(&c, 0, sizeof c);
    bvox__grid_init(&c.g, vol);
    c.geo = &vol->geom;
    c.mirrored = bvox__geometry_mirrored(c.geo);
    c.tab = bvox__mc_table();
    const bvox__grid *g = &c.g;
    bvox_status st = BVOX_OK;
    size_t ncells, ncols;
    if (!bvox__mul_size((size_t)(g->nx + 1) * (size_t)(g->ny + 1), g->cw * sizeof(uint32_t),
                        &ncells) ||
        !bvox__mul_size((size_t)(g->nx + 1) * (size_t)(g->ny + 1), g->wpc * sizeof(uint32_t),
                        &ncols))
        return bvox__fail(BVOX_ETOOBIG, "volume too large to mesh");
    c.zero = bvox__mem_zalloc(g->wpc + 1, sizeof(uint64_t));
    c.rows = bvox__mem_zalloc((size_t)g->ny + 2, sizeof(rowinfo));
    int nch = bvox__parallelism() * 4;
    if (nch > g->ny + 1) nch = g->ny + 1;
    c.nchunks = nch;
    c.chunks = bvox__mem_zalloc((size_t)nch, sizeof(cchunk));
    if (!c.zero || !c.rows || !c.chunks) st = bvox__fail(BVOX_ENOMEM, "out of memory (cuberille)");
    if (!st) {
        c.pre_bytes = ncells;
        c.pre = bvox__alloc(ncells, false, "cuberille cell index", &st);
    }
    c.dpre_bytes = ncols;
    for (int k = 0; k < 3 && !st; k++)
        c.dpre[k] = bvox__alloc(ncols, false, "cuberille edge index", &st);
    if (st) {
        cub_release(&c);
        return st;
    }
    for (int i = 0; i < nch; i++) {
        c.chunks[i].y0 = (int32_t)((int64_t)(g->ny + 1) * i / nch);
        c.chunks[i].y1 = (int32_t)((int64_t)(g->ny + 1) * (i + 1) / nch);
    }
    bvox__parallel_for(nch, 1, pass_count, &c);
    if ((st = bvox__progress(0.4))) { /* the count pass: about 40 % of the work */
        cub_release(&c);
        return st;
    }
    int64_t cells = 0, tris = 0, diag[3] = {0, 0, 0};
    for (int32_t Y = 0; Y <= g->ny; Y++) {
        rowinfo r = c.rows[Y];
        c.rows[Y].cells = cells;
        c.rows[Y].tris = tris;
        cells += r.cells;
        tris += r.tris;
        for (int k = 0; k < 3; k++) {
            c.rows[Y].diag[k] = diag[k];
            diag[k] += r.diag[k];
        }
    }
    for (int i = 0; i < nch && !st; i++) {
        st = c.chunks[i].st;
        c.nmulti += (int64_t)(c.chunks[i].multis.size / sizeof(multi));
    }
    if (!st && c.nmulti) {
        c.multis = bvox__mem_alloc((size_t)c.nmulti * sizeof(multi));
        if (!c.multis) st = bvox__fail(BVOX_ENOMEM, "out of memory (cuberille)");
    }
    int64_t total = 0;
    if (!st) {
        int64_t j = 0, extra = 0;
        for (int i = 0; i < nch; i++) {
            const multi *src = c.chunks[i].multis.data;
            int64_t n = (int64_t)(c.chunks[i].multis.size / sizeof(multi));
            for (int64_t k = 0; k < n; k++) {
                c.multis[j] = src[k];
                c.multis[j].first = extra;
                extra += src[k].first;
                j++;
            }
        }
        c.extra_base = cells;
        total = cells + extra;
        for (int k = 0; k < 3; k++) {
            c.dbase[k] = total;
            total += diag[k];
        }
        if (total > INT32_MAX || tris > INT32_MAX)
            st = bvox__fail(BVOX_ETOOBIG, "the mesh would be too large (%lld triangles)",
                            (long long)tris);
    }
    if (!st) {
        m->nvertices = 0;
        m->ntriangles = 0;
        st = bvox__mesh_grow(m, total, tris);
    }
    if (st) {
        cub_release(&c);
        return st;
    }
    c.verts = m->vertices;
    c.tris = m->triangles;
    bvox__parallel_for((int64_t)g->ny + 1, 4, pass_emit, &c);
    m->nvertices = total;
    m->ntriangles = tris;
    cub_release(&c);
    return BVOX_OK;
}
