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
 * multi-sheet cells; the diagonal edges' midpoints by a prefix per column
 * plus the popcounts of the column's words below. Each face is emitted
 * once, by the cell at its lower corner (its cube edge 3, 7 or 11), with the
 * other three cells looked up.
 *
 * Plain columns: where no face a cell column emits has a diagonal side or a
 * multi-sheet corner (checked per column from the diagonal-edge prefixes
 * and the multi-sheet list: every column of a digital ball, most of an
 * atlas), each face is a quad of first sheets, i.e. of ranks among the
 * mixed cells of four columns, and is written directly (emit_plain_word);
 * the other columns build each face's polygon (face_polygon). Both give the
 * same vertices and triangles in the same order (test_cuberille compares
 * them on every kind of volume through bvox__mesh_cuberille_reference).
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
    uint32_t *dpre[3];  /* per slot column: diagonal edges (x2) before it in its row */
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
    int reference; /* every face through face_polygon (tests) */
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

/* Diagonal edges of direction k in slot column (X, Y) below bit z: the
 * column's words are read up to z's (a prefix per word cost 25 MB of page
 * faults at 512^3, and diagonal edges are rare on smooth objects). */
static inline int64_t diag_below(const cub *c, int k, int32_t X, int32_t Y, int32_t z)
{
    const uint64_t *A = col(c, X, Y), *B, *C = NULL, *D = NULL;
    if (k == 2) {
        B = col(c, X + 1, Y);
        C = col(c, X, Y + 1);
        D = col(c, X + 1, Y + 1);
    } else
        B = k == 0 ? col(c, X, Y + 1) : col(c, X + 1, Y);
    const size_t wz = (size_t)z >> 6;
    int64_t n = 0;
    for (size_t w = 0; w <= wz; w++) {
        uint64_t a = A[w], b = B[w], cc, d;
        if (k == 2) {
            cc = C[w];
            d = D[w];
        } else {
            cc = up(c, A, w);
            d = up(c, B, w);
        }
        uint64_t m = (a & d & ~b & ~cc) | (b & cc & ~a & ~d);
        if (w == wz) m &= (1ull << (z & 63)) - 1;
        n += POPCOUNT(m);
    }
    return n;
}

static inline int32_t diag_vertex(const cub *c, int k, int32_t X, int32_t Y, int32_t z, int side)
{
    size_t i = (size_t)Y * (size_t)(c->g.nx + 1) + (size_t)X;
    return (int32_t)(c->dbase[k] + c->rows[Y].diag[k] + c->dpre[k][i] +
                     2 * diag_below(c, k, X, Y, z) + side);
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
    int64_t first; /* number of the first mixed cell of its word */
} ringcell;

/* The corner words and mixed-cell words of the four cell columns (X..X+1,
 * Y..Y+1), index dx | dy << 1, at cell words w and w + 1: every ring cell
 * of the faces a cell of word (X, Y, w) emits is among them, so they are
 * read once per word instead of once per ring cell. */
typedef struct wordcells {
    uint64_t cw[4][2][8];
    uint64_t mixed[4][2];
    int64_t first[4][2]; /* number of the first mixed cell of each word */
} wordcells;

static inline void wordcells_init(const cub *c, int32_t X, int32_t Y, size_t w, wordcells *wc)
{
    /* the 3 x 3 padded columns' words w and w + 1, and shifted up by one
     * (as corners(): bit Z = voxel Z - 1) */
    uint64_t hi[3][3][2], lo[3][3][2];
    const size_t wpc = c->g.wpc;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            const uint64_t *p = col(c, X + i, Y + j);
            uint64_t pm = w >= 1 && w - 1 < wpc ? p[w - 1] : 0;
            uint64_t h0 = w < wpc ? p[w] : 0, h1 = w + 1 < wpc ? p[w + 1] : 0;
            hi[j][i][0] = h0;
            hi[j][i][1] = h1;
            lo[j][i][0] = h0 << 1 | pm >> 63;
            lo[j][i][1] = h1 << 1 | h0 >> 63;
        }
    for (int j = 0; j < 4; j++)
        for (int d = 0; d < 2; d++) {
            uint64_t *cw = wc->cw[j][d];
            for (int b = 0; b < 4; b++) {
                int xi = (j & 1) + (b & 1), yj = (j >> 1) + (b >> 1);
                cw[b] = lo[yj][xi][d];
                cw[4 + b] = hi[yj][xi][d];
            }
            wc->mixed[j][d] = bvox__grid_mixed(cw);
            /* cells past the grid have no number (and are never asked for) */
            int32_t CX = X + (j & 1), CY = Y + (j >> 1);
            size_t cwi = w + (size_t)d;
            wc->first[j][d] =
                CX <= c->g.nx && CY <= c->g.ny && cwi < c->g.cw
                    ? c->rows[CY].cells +
                          c->pre[((size_t)CY * (size_t)(c->g.nx + 1) + (size_t)CX) * c->g.cw + cwi]
                    : 0;
        }
}

/* ring_cell from the word's cached corners: cell (X+dx, Y+dy, Z+dz), Z in
 * word w of the cells. */
static inline void ring_cell_at(const wordcells *wc, int32_t X, int32_t Y, int32_t Z, int dx,
                                int dy, int dz, ringcell *r)
{
    int j = dx | dy << 1, d = ((Z & 63) + dz) >> 6;
    r->X = X + dx;
    r->Y = Y + dy;
    r->Z = Z + dz;
    r->k = bvox__grid_case(wc->cw[j][d], (unsigned)r->Z & 63);
    r->mixed = wc->mixed[j][d];
    r->first = wc->first[j][d];
}

/* The vertex of the sheet of cell r that holds its cube edge e. */
static inline int32_t sheet_vertex(const cub *c, const ringcell *r, int e)
{
    unsigned bit = (unsigned)r->Z & 63;
    int L = c->tab[r->k].edge_loop[e];
    if (L <= 0) return (int32_t)(r->first + POPCOUNT(r->mixed & ((1ull << bit) - 1)));
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
static inline int face_polygon(const cub *c, const wordcells *wc, int32_t X, int32_t Y,
                               int32_t Z, int f, unsigned k, uint64_t mixed, int32_t *poly,
                               int *mid)
{
    /* bvox__mc_edge_corners of cube edges 3, 7, 11: corners 6, 5, 3 to 7 */
    static const int8_t face_c0[3] = {6, 5, 3};
    const int c0 = face_c0[f], c1 = 7;
    int outward_pos = (k >> c0) & 1; /* the lower voxel is the 1 */
    int vin = outward_pos ? c0 : c1;
    int32_t VX = X + (vin & 1), VY = Y + ((vin >> 1) & 1);
    ringcell rc[4];
    rc[0] = (ringcell){X, Y, Z, k, mixed, wc->first[0][0]};
    for (int i = 1; i < 4; i++)
        ring_cell_at(wc, X, Y, Z, ring[f][i][0], ring[f][i][1], ring[f][i][2], &rc[i]);
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

/* Voxels a, b, c, d around a voxel edge (a, d and b, c diagonal): where
 * they are 1, 0, 0, 1 or 0, 1, 1, 0, the edge is "diagonal". */
static inline uint64_t alt(uint64_t a, uint64_t b, uint64_t cc, uint64_t d)
{
    return (a & d & ~b & ~cc) | (b & cc & ~a & ~d);
}

/* Word w of a column, 0 past its end. */
static inline uint64_t cwd(const cub *c, const uint64_t *p, size_t w)
{
    return w < c->g.wpc ? p[w] : 0;
}

/* Record the multi-sheet cells of cell word (X, Y, w): their keys, in
 * order, with their number of extra sheets. */
static void add_multis(const cub *c, cchunk *ch, int32_t X, int32_t Y, size_t w,
                       const uint64_t cw[8], uint64_t mixed)
{
    for (mixed &= bvox__grid_maybe_multi(cw); mixed && !ch->st; mixed &= mixed - 1) {
        unsigned bit = (unsigned)__builtin_ctzll(mixed);
        const bvox__mc_case *cs = &c->tab[bvox__grid_case(cw, bit)];
        if (cs->nloops <= 1) continue;
        bvox_status st =
            bvox__buf_reserve(&ch->multis, ch->multis.size + sizeof(multi), "cuberille sheets");
        if (st) {
            ch->st = st;
            return;
        }
        multi *mm = (multi *)((char *)ch->multis.data + ch->multis.size);
        mm->key = cell_key(c, X, Y, (int32_t)(w * 64 + bit));
        mm->first = cs->nloops - 1;
        ch->multis.size += sizeof(multi);
    }
}

/* Pass 1 for cell row Y, from whole words, each word of the 2 x 2 voxel
 * columns of cell column X read once: the mixed-cell prefixes (pre), the
 * diagonal edges of each direction (dpre per slot column, as diag_word),
 * the multi-sheet cells, and the row's faces. Triangles: each exposed face
 * is a polygon of its 4 corners plus one midpoint per diagonal voxel edge
 * among its sides, fanned into (that many - 2) triangles; so 2 per face
 * plus 1 per (face, diagonal side) pair. The faces are popcounts of XORs
 * of neighbour words; the diagonal sides are added per row afterwards from
 * the diagonal-edge counts (diag_sides). Row Y emits the x and z faces of
 * voxel row y = Y and the y faces between voxel rows Y - 1 and Y (cube
 * edges 3, 11 and 7 of its cells). V(x, y) is voxel column (x, y) (0
 * outside) = padded column (x+1, y+1): cell column X = x has corners in
 * V(x-1..x, Y-1..Y). */
HOT static void count_row(cub *c, cchunk *ch, int32_t Y)
{
    const bvox__grid *g = &c->g;
    int64_t run = 0, faces = 0;
    uint64_t drun[3] = {0, 0, 0}; /* see mc.c: the total check bounds them */
#define V(x, y) col(c, (x) + 1, (y) + 1)
    for (int32_t x = 0; x <= g->nx; x++) {
        const uint64_t *a0 = V(x - 1, Y - 1), *b0 = V(x, Y - 1);
        const uint64_t *a1 = V(x - 1, Y), *b1 = V(x, Y);
        size_t at = (size_t)Y * (size_t)(g->nx + 1) + (size_t)x;
        uint32_t *pre = c->pre + at * g->cw;
        for (int k = 0; k < 3; k++) c->dpre[k][at] = (uint32_t)drun[k];
        /* the 4 columns' words below (pv), at (cu) and above (nx) word w */
        const uint64_t *cols[4] = {a0, b0, a1, b1};
        uint64_t pv[4], cu[4], nx[4];
        for (int i = 0; i < 4; i++) {
            pv[i] = 0;
            cu[i] = cwd(c, cols[i], 0);
            nx[i] = cwd(c, cols[i], 1);
        }
        for (size_t w = 0; w < g->cw; w++) {
            uint64_t o = 0, a = ~0ull, ends_o = 0, ends_a = ~0ull;
            for (int i = 0; i < 4; i++) {
                o |= cu[i];
                a &= cu[i];
                uint64_t ends = (pv[i] >> 63) | (nx[i] << 63);
                ends_o |= ends;
                ends_a &= ends | ~(1ull | 1ull << 63);
            }
            const uint64_t A0 = cu[0], B0 = cu[1], A1 = cu[2], B1 = cu[3];
            const uint64_t lA0 = A0 << 1 | pv[0] >> 63, lB0 = B0 << 1 | pv[1] >> 63;
            const uint64_t lA1 = A1 << 1 | pv[2] >> 63, lB1 = B1 << 1 | pv[3] >> 63;
            const uint64_t hA0 = A0 >> 1 | nx[0] << 63, hB0 = B0 >> 1 | nx[1] << 63;
            const uint64_t hA1 = A1 >> 1 | nx[2] << 63;
            for (int i = 0; i < 4; i++) {
                pv[i] = cu[i];
                cu[i] = nx[i];
                nx[i] = cwd(c, cols[i], w + 2);
            }
            /* all 2 x 2 x 3 voxels around every cell of the word equal: no
             * mixed cell, face or diagonal edge (most words) */
            if ((o | ends_o) == 0 || (a == ~0ull && ends_a == ~0ull)) {
                pre[w] = (uint32_t)run;
                continue;
            }
            /* cells: corners as corners() */
            uint64_t cw[8] = {lA0, lB0, lA1, lB1, A0, B0, A1, B1};
            uint64_t mixed = bvox__grid_mixed(cw);
            pre[w] = (uint32_t)run;
            if (mixed) {
                run += POPCOUNT(mixed);
                add_multis(c, ch, x, Y, w, cw, mixed);
            }
            if (w < g->wpc) { /* diagonal edges, diag_word's three directions */
                drun[0] += 2 * (uint64_t)POPCOUNT(alt(A0, A1, hA0, hA1));
                drun[1] += 2 * (uint64_t)POPCOUNT(alt(A0, B0, hA0, hB0));
                drun[2] += 2 * (uint64_t)POPCOUNT(alt(A0, B0, A1, B1));
            }
            /* the faces: x faces between V(x-1, Y) and V(x, Y); y faces
             * between V(x, Y-1) and V(x, Y), z faces of V(x, Y) between
             * voxels z - 1 and z (voxel columns x < nx) */
            faces += POPCOUNT(A1 ^ B1);
            if (x == g->nx) continue;
            faces += POPCOUNT(B0 ^ B1) + POPCOUNT(B1 ^ lB1);
        }
    }
#undef V
    c->rows[Y].cells = run;
    c->rows[Y].tris = 2 * faces; /* + the diagonal sides: see diag_sides */
    for (int k = 0; k < 3; k++) c->rows[Y].diag[k] = (int64_t)drun[k];
}

/* The triangles that diagonal edges add to the rows' faces (before the
 * rows' counts become prefixes). The four voxels around a diagonal edge
 * alternate, so its four faces are all exposed and each gets one more
 * triangle, from the row that emits it. Slot row Y (count_row's) holds the
 * x edges between voxel rows Y - 1 and Y (their 2 y faces and the z face
 * of row Y: 3 to row Y, the z face of row Y - 1: 1 to row Y - 1), the y
 * edges of voxel row Y - 1 (4 faces, all to row Y - 1) and the z edges
 * between rows Y - 1 and Y (as the x edges: 3 to row Y, 1 to row Y - 1).
 * rows[].diag counts 2 per edge (its two midpoints). */
static void diag_sides(rowinfo *rows, int32_t ny)
{
    for (int32_t Y = 0; Y <= ny; Y++) {
        const int64_t *d = rows[Y].diag, *n = rows[Y + 1].diag; /* row ny + 1: none */
        rows[Y].tris += (3 * (d[0] + d[2]) + n[0] + 4 * n[1] + n[2]) / 2;
    }
}

static void pass_count(void *ctx, int64_t begin, int64_t end)
{
    cub *c = ctx;
    for (int64_t kk = begin; kk < end; kk++) {
        cchunk *ch = &c->chunks[kk];
        for (int32_t Y = ch->y0; Y < ch->y1; Y++) count_row(c, ch, Y);
    }
}

/* Diagonal edges of direction k in the slots of row Y before column X
 * (X up to nx + 1, Y up to ny + 1), counted from the start of the grid. */
static inline int64_t diag_before(const cub *c, int k, int32_t X, int32_t Y)
{
    const bvox__grid *g = &c->g;
    if (Y > g->ny) return c->rows[g->ny + 1].diag[k];
    if (X > g->nx) return c->rows[Y + 1].diag[k];
    return c->rows[Y].diag[k] +
           c->dpre[k][(size_t)Y * (size_t)(g->nx + 1) + (size_t)X];
}

/* Whether cell row Y's emission has no diagonal voxel edge in slot rows Y
 * and Y + 1 (the slots of every face side its cells emit). */
static inline int row_without_diagonals(const cub *c, int32_t Y)
{
    int32_t Y2 = Y + 2 > c->g.ny + 1 ? c->g.ny + 1 : Y + 2;
    for (int k = 0; k < 3; k++)
        if (c->rows[Y2].diag[k] != c->rows[Y].diag[k]) return 0;
    return 1;
}

/* Whether the faces of cell column (X, Y) are all plain quads: no
 * diagonal voxel edge in slot columns X..X+1 of rows Y..Y+1 (the sides of
 * its faces) and no multi-sheet cell among cell columns X..X+1 of rows
 * Y..Y+1 (its faces' ring cells). cur[i] is row Y + i's cursor into the
 * sorted multi-sheet cells, moved forward as X grows. */
static inline int column_plain(const cub *c, int32_t X, int32_t Y, int diag_free, int64_t cur[2])
{
    const bvox__grid *g = &c->g;
    int32_t X2 = X + 2 > g->nx + 1 ? g->nx + 1 : X + 2;
    if (!diag_free)
        for (int i = 0; i < 2; i++)
            for (int k = 0; k < 3; k++)
                if (diag_before(c, k, X2, Y + i) != diag_before(c, k, X, Y + i)) return 0;
    for (int i = 0; i < 2 && c->nmulti; i++) {
        if (Y + i > g->ny) break;
        uint64_t k0 = cell_key(c, X, Y + i, 0), k1 = cell_key(c, X2, Y + i, 0);
        while (cur[i] < c->nmulti && c->multis[cur[i]].key < k0) cur[i]++;
        if (cur[i] < c->nmulti && c->multis[cur[i]].key < k1) return 0;
    }
    return 1;
}

/* The first multi-sheet cell of row Y or later (a cursor for column_plain). */
static int64_t multi_row_start(const cub *c, int32_t Y)
{
    uint64_t key = cell_key(c, 0, Y, 0);
    int64_t lo = 0, hi = c->nmulti;
    while (lo < hi) {
        int64_t mid = (lo + hi) / 2;
        if (c->multis[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* One face as two triangles, q counter-clockwise seen from +axis; flipped
 * (q[0] kept) when its outside is toward -axis, or in a mirrored frame:
 * face_polygon and the fan of emit_row for a 4-corner polygon. */
static inline int32_t *quad(int32_t *t, int32_t q0, int32_t q1, int32_t q2, int32_t q3, int flip)
{
    if (flip) {
        int32_t s = q1;
        q1 = q3;
        q3 = s;
    }
    t[0] = q0;
    t[1] = q1;
    t[2] = q2;
    t[3] = q0;
    t[4] = q2;
    t[5] = q3;
    return t + 6;
}

/* Cell word (X, Y, w) of a plain column (column_plain): every ring cell's
 * vertex is its first sheet, the rank of the cell among the mixed cells of
 * its column (first[j] + popcount below, j = dx | dy << 1), and a ring cell
 * one up (dz = 1) is the next mixed cell of its column, since both hold the
 * face's edge. The vertex positions and triangles, in emit_row's order,
 * without building polygons. base: the world position of (X - 0.5, Y -
 * 0.5, 0) as bvox__grid_world sums it, so a cell adds only its z term (the
 * same operations in the same order: bitwise-equal positions). */
/* always inlined: a call of its own would leave it outside emit_row's POPCNT
 * clone, with the portable popcount */
static inline __attribute__((always_inline)) int32_t *emit_plain_word(cub *c, int32_t X, int32_t Y, size_t w,
                                       const uint64_t cw[8], uint64_t mixed_word,
                                       const double base[3], int64_t *vi, int32_t *t)
{
    const bvox__grid *g = &c->g;
    const size_t wpc = g->wpc;
    uint64_t hi[3][3], lo[3][3];
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            const uint64_t *p = col(c, X + i, Y + j);
            uint64_t pm = w >= 1 && w - 1 < wpc ? p[w - 1] : 0;
            uint64_t h = w < wpc ? p[w] : 0;
            hi[j][i] = h;
            lo[j][i] = h << 1 | pm >> 63;
        }
    uint64_t mx[4];
    int64_t first[4];
    for (int j = 1; j < 4; j++) {
        int xi = j & 1, yj = j >> 1;
        uint64_t o = lo[yj][xi] | lo[yj][xi + 1] | lo[yj + 1][xi] | lo[yj + 1][xi + 1] |
                     hi[yj][xi] | hi[yj][xi + 1] | hi[yj + 1][xi] | hi[yj + 1][xi + 1];
        uint64_t a = lo[yj][xi] & lo[yj][xi + 1] & lo[yj + 1][xi] & lo[yj + 1][xi + 1] &
                     hi[yj][xi] & hi[yj][xi + 1] & hi[yj + 1][xi] & hi[yj + 1][xi + 1];
        mx[j] = o & ~a;
        int32_t CX = X + xi, CY = Y + yj;
        first[j] = CX <= g->nx && CY <= g->ny
                       ? c->rows[CY].cells +
                             c->pre[((size_t)CY * (size_t)(g->nx + 1) + (size_t)CX) * g->cw + w]
                       : 0;
    }
    const double *d = c->geo->direction, s2 = c->geo->spacing[2];
    const uint64_t f0 = cw[6] ^ cw[7], f1 = cw[5] ^ cw[7], f2 = cw[3] ^ cw[7];
    /* flip where the upper voxel is the 1 (outward toward -axis), unless
     * the frame is mirrored */
    const uint64_t fl = c->mirrored ? ~0ull : 0;
    const uint64_t flip0 = ~(cw[6] ^ fl), flip1 = ~(cw[5] ^ fl), flip2 = ~(cw[3] ^ fl);
    int64_t v = *vi;
    for (uint64_t m = mixed_word; m; m &= m - 1) {
        unsigned bit = (unsigned)__builtin_ctzll(m);
        uint64_t below = (1ull << bit) - 1;
        double cz = ((double)(int32_t)(w * 64 + bit) - 0.5) * s2;
        double *pv = c->verts + 3 * v;
        pv[0] = base[0] + d[2] * cz;
        pv[1] = base[1] + d[5] * cz;
        pv[2] = base[2] + d[8] * cz;
        int32_t v0 = (int32_t)v++;
        if ((f0 >> bit) & 1) {
            int32_t v2 = (int32_t)(first[2] + POPCOUNT(mx[2] & below));
            t = quad(t, v0, v2, v2 + 1, v0 + 1, (int)((flip0 >> bit) & 1));
        }
        if ((f1 >> bit) & 1) {
            int32_t v1 = (int32_t)(first[1] + POPCOUNT(mx[1] & below));
            t = quad(t, v0, v0 + 1, v1 + 1, v1, (int)((flip1 >> bit) & 1));
        }
        if ((f2 >> bit) & 1) {
            int32_t v1 = (int32_t)(first[1] + POPCOUNT(mx[1] & below));
            int32_t v2 = (int32_t)(first[2] + POPCOUNT(mx[2] & below));
            int32_t v3 = (int32_t)(first[3] + POPCOUNT(mx[3] & below));
            t = quad(t, v0, v1, v3, v2, (int)((flip2 >> bit) & 1));
        }
    }
    *vi = v;
    return t;
}

HOT static void emit_row(cub *c, int32_t Y)
{
    const bvox__grid *g = &c->g;
    {
        int64_t vi = c->rows[Y].cells;
        int32_t *t = c->tris + 3 * c->rows[Y].tris;
        const int64_t row_cells = c->rows[Y + 1].cells - c->rows[Y].cells;
        const int diag_free = row_without_diagonals(c, Y);
        int64_t cur[2] = {c->nmulti ? multi_row_start(c, Y) : 0, 0};
        cur[1] = cur[0];
        const double *d = c->geo->direction, *o = c->geo->origin, *sp = c->geo->spacing;
        for (int32_t X = 0; X <= g->nx; X++) {
            /* skip columns without mixed cells (their faces are none either) */
            const uint32_t *pre = c->pre + ((size_t)Y * (size_t)(g->nx + 1) + (size_t)X) * g->cw;
            const int64_t col_end = X < g->nx ? (int64_t)pre[g->cw] : row_cells;
            if (col_end == (int64_t)pre[0]) continue;
            const int plain = !c->reference && column_plain(c, X, Y, diag_free, cur);
            /* bvox__grid_world's x and y terms, summed in its order */
            const double a = (X - 0.5) * sp[0], b = (Y - 0.5) * sp[1];
            const double base[3] = {o[0] + d[0] * a + d[1] * b, o[1] + d[3] * a + d[4] * b,
                                    o[2] + d[6] * a + d[7] * b};
            for (size_t w = 0; w < g->cw; w++) {
                /* the prefixes say which words hold mixed cells */
                if ((w + 1 < g->cw ? (int64_t)pre[w + 1] : col_end) == (int64_t)pre[w]) continue;
                wordcells wc;
                uint64_t cw[8];
                corners(c, X, Y, w, cw);
                const uint64_t mixed_word = bvox__grid_mixed(cw);
                if (!mixed_word) continue;
                if (plain) {
                    t = emit_plain_word(c, X, Y, w, cw, mixed_word, base, &vi, t);
                    continue;
                }
                wordcells_init(c, X, Y, w, &wc);
                for (uint64_t mixed = mixed_word; mixed; mixed &= mixed - 1) {
                    unsigned bit = (unsigned)__builtin_ctzll(mixed);
                    int32_t Z = (int32_t)(w * 64 + bit);
                    unsigned k = bvox__grid_case(cw, bit);
                    const bvox__mc_case *cs = &c->tab[k];
                    double p[3];
                    bvox__grid_world(c->geo, X - 0.5, Y - 0.5, Z - 0.5, p);
                    memcpy(c->verts + 3 * vi++, p, sizeof p);
                    if (cs->nloops > 1) {
                        ringcell self = {X, Y, Z, k, mixed_word, wc.first[0][0]};
                        int32_t first = sheet_vertex(c, &self, cs->loop[1][0]);
                        for (int L = 1; L < cs->nloops; L++)
                            memcpy(c->verts + 3 * (first + L - 1), p, sizeof p);
                    }
                    for (int f = 0; f < 3; f++) {
                        if (cs->edge_loop[face_edge[f]] < 0) continue;
                        int32_t q[8];
                        int mid;
                        int n = face_polygon(c, &wc, X, Y, Z, f, k, mixed_word, q, &mid);
                        int s = mid < 0 ? 0 : mid;
                        int32_t qq[16]; /* q twice: the fan from q[s] without % n */
                        for (int i = 0; i < n; i++) qq[i] = qq[i + n] = q[i];
                        for (int i = 1; i + 1 < n; i++) {
                            t[0] = qq[s];
                            t[1] = qq[s + i];
                            t[2] = qq[s + i + 1];
                            t += 3;
                        }
                    }
                }
            }
        }
        /* the midpoints of this row's diagonal edges, two per edge */
        static const double off[3][3] = {{-1, -0.5, 0.5}, {-0.5, -1, 0.5}, {-0.5, -0.5, 0}};
        for (int k = 0; k < 3; k++) {
            int64_t di = c->dbase[k] + c->rows[Y].diag[k];
            if (c->rows[Y + 1].diag[k] == c->rows[Y].diag[k]) continue; /* none */
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

static void pass_emit(void *ctx, int64_t begin, int64_t end)
{
    for (int64_t Y = begin; Y < end; Y++) emit_row(ctx, (int32_t)Y);
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

static bvox_status cuberille(const bvox_volume *vol, bvox_mesh *m, int reference)
{
    cub c;
    memset(&c, 0, sizeof c);
    c.reference = reference;
    bvox__grid_init(&c.g, vol);
    c.geo = &vol->geom;
    c.mirrored = bvox__geometry_mirrored(c.geo);
    c.tab = bvox__mc_table();
    const bvox__grid *g = &c.g;
    bvox_status st = BVOX_OK;
    size_t ncells, ncols;
    if (!bvox__mul_size((size_t)(g->nx + 1) * (size_t)(g->ny + 1), g->cw * sizeof(uint32_t),
                        &ncells) ||
        !bvox__mul_size((size_t)(g->nx + 1) * (size_t)(g->ny + 1), sizeof(uint32_t), &ncols))
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
    diag_sides(c.rows, g->ny);
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
    /* the row past the last: the totals (emit_row's counts per row) */
    c.rows[g->ny + 1].cells = cells;
    c.rows[g->ny + 1].tris = tris;
    for (int k = 0; k < 3; k++) c.rows[g->ny + 1].diag[k] = diag[k];
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

bvox_status bvox__mesh_cuberille(const bvox_volume *vol, bvox_mesh *m)
{
    return cuberille(vol, m, 0);
}

bvox_status bvox__mesh_cuberille_reference(const bvox_volume *vol, bvox_mesh *m)
{
    return cuberille(vol, m, 1);
}
