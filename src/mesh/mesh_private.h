/*
 * mesh_private.h — what the files of src/mesh/ share: the generated
 * marching-cubes case table, the padded cell grid over a volume's column
 * words, growable budgeted buffers, the mesh readers' entry points and the
 * text tokenizer they use.
 *
 * Cell grid. The volume is surrounded by one layer of 0-voxels, so padded
 * voxel X = x + 1 runs over 0..nx+1 (likewise Y, Z). Cell (X, Y, Z), X in
 * 0..nx, Y in 0..ny, Z in 0..nz, has its 8 corners at padded voxels
 * (X+dx, Y+dy, Z+dz). Cells are processed 64 at a time along Z: the corner
 * words of padded column (X, Y) are `hi` = the column's word w (bit Z =
 * voxel z = Z) and `lo` = the column shifted up by one (bit Z = voxel Z-1).
 * Corner index b = dx | dy << 1 | dz << 2; cube edge e: axis = e >> 2,
 * the two other offsets in e & 3 (x edges: dy | dz<<1, y edges: dx | dz<<1,
 * z edges: dx | dy<<1).
 */
#ifndef BVOX_MESH_PRIVATE_H
#define BVOX_MESH_PRIVATE_H

#include "internal.h"

/* ---- mc_table.c ---- */
typedef struct bvox__mc_case {
    uint8_t ntri;         /* triangles */
    uint8_t nloops;       /* contour loops (surface sheets) in the cell */
    uint8_t tri[12][3];   /* 0..11: cube edge midpoints; 12 + L: centre of loop L */
    uint8_t loop_len[4];
    uint8_t loop[4][12];  /* cube edges of each loop, in order */
    int8_t edge_loop[12]; /* loop of each crossed edge, -1 if not crossed */
    uint16_t edges;       /* bit e: cube edge e is crossed */
    uint8_t centres;      /* bit L: loop L is fanned around its centre */
    uint8_t diag_faces;   /* bit axis*2+side: that face has 1s on one diagonal only */
} bvox__mc_case;
/* The 256 cases, generated once (thread-safe) from the face rule. */
const bvox__mc_case *bvox__mc_table(void);
/* Cube edge e's endpoints (corner indices). */
void bvox__mc_edge_corners(int e, int *c0, int *c1);

/* ---- hot loops (mc.c, cuberille.c) ----
 * The hot loops are cloned for CPUs with POPCNT (GCC's target_clones: an
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

/* ---- the padded cell grid ---- */
typedef struct bvox__grid {
    const uint64_t *words;
    int32_t nx, ny, nz;
    size_t wpc; /* words per column */
    size_t cw;  /* cell words along Z: ceil((nz + 1) / 64) */
} bvox__grid;

static inline void bvox__grid_init(bvox__grid *g, const bvox_volume *v)
{
    g->words = v->words;
    g->nx = v->nx;
    g->ny = v->ny;
    g->nz = v->nz;
    g->wpc = v->wpc;
    g->cw = ((size_t)v->nz + 1 + 63) / 64;
}
/* Word w of padded column (X, Y): 0 outside. */
static inline uint64_t bvox__grid_hi(const bvox__grid *g, int32_t X, int32_t Y, size_t w)
{
    if (X < 1 || X > g->nx || Y < 1 || Y > g->ny || w >= g->wpc) return 0;
    return g->words[((size_t)(Y - 1) * (size_t)g->nx + (size_t)(X - 1)) * g->wpc + w];
}
static inline uint64_t bvox__grid_lo(const bvox__grid *g, int32_t X, int32_t Y, size_t w)
{
    if (X < 1 || X > g->nx || Y < 1 || Y > g->ny) return 0;
    const uint64_t *c = g->words + ((size_t)(Y - 1) * (size_t)g->nx + (size_t)(X - 1)) * g->wpc;
    uint64_t a = w < g->wpc ? c[w] << 1 : 0;
    uint64_t b = (w >= 1 && w - 1 < g->wpc) ? c[w - 1] >> 63 : 0;
    return a | b;
}
/* The 8 corner words of cell word (X, Y, w), index b as the corners. */
static inline void bvox__grid_corners(const bvox__grid *g, int32_t X, int32_t Y, size_t w,
                                      uint64_t c[8])
{
    c[0] = bvox__grid_lo(g, X, Y, w);
    c[1] = bvox__grid_lo(g, X + 1, Y, w);
    c[2] = bvox__grid_lo(g, X, Y + 1, w);
    c[3] = bvox__grid_lo(g, X + 1, Y + 1, w);
    c[4] = bvox__grid_hi(g, X, Y, w);
    c[5] = bvox__grid_hi(g, X + 1, Y, w);
    c[6] = bvox__grid_hi(g, X, Y + 1, w);
    c[7] = bvox__grid_hi(g, X + 1, Y + 1, w);
}
/* Cells of the word that are neither all 0 nor all 1. */
static inline uint64_t bvox__grid_mixed(const uint64_t c[8])
{
    uint64_t o = c[0] | c[1] | c[2] | c[3] | c[4] | c[5] | c[6] | c[7];
    uint64_t a = c[0] & c[1] & c[2] & c[3] & c[4] & c[5] & c[6] & c[7];
    return o & ~a;
}
/* Cells of the word that may hold more than one surface sheet (a superset
 * of the cases with nloops > 1, checked against the table by
 * test_cuberille): a cube face with 1s on one diagonal only, or the 8
 * corners split into one body-diagonal pair and the other six. */
static inline uint64_t bvox__grid_maybe_multi(const uint64_t c[8])
{
#define BVOX__ALT(a, b, cc, d) (((a) & (d) & ~(b) & ~(cc)) | ((b) & (cc) & ~(a) & ~(d)))
    uint64_t m = BVOX__ALT(c[0], c[2], c[4], c[6]) | BVOX__ALT(c[1], c[3], c[5], c[7]) |
                 BVOX__ALT(c[0], c[1], c[4], c[5]) | BVOX__ALT(c[2], c[3], c[6], c[7]) |
                 BVOX__ALT(c[0], c[1], c[2], c[3]) | BVOX__ALT(c[4], c[5], c[6], c[7]);
#undef BVOX__ALT
    for (int p = 0; p < 4; p++) { /* corners p and 7 - p equal, the six others not */
        uint64_t b = ~(c[p] ^ c[7 - p]);
        for (int r = 0; r < 8; r++)
            if (r != p && r != 7 - p) b &= c[r] ^ c[p];
        m |= b;
    }
    return m;
}
static inline unsigned bvox__grid_case(const uint64_t c[8], unsigned bit)
{
    unsigned k = 0;
    for (int b = 0; b < 8; b++) k |= (unsigned)((c[b] >> bit) & 1) << b;
    return k;
}
/* Index space -> world: origin + direction * (p .* spacing). */
static inline void bvox__grid_world(const bvox_geometry *geo, double px, double py, double pz,
                                    double *out)
{
    double a = px * geo->spacing[0], b = py * geo->spacing[1], c = pz * geo->spacing[2];
    const double *d = geo->direction;
    out[0] = geo->origin[0] + d[0] * a + d[1] * b + d[2] * c;
    out[1] = geo->origin[1] + d[3] * a + d[4] * b + d[5] * c;
    out[2] = geo->origin[2] + d[6] * a + d[7] * b + d[8] * c;
}
/* 1 if the direction matrix has a negative determinant (a mirrored frame:
 * triangles must be flipped to stay outward). */
int bvox__geometry_mirrored(const bvox_geometry *geo);

/* ---- mesh.c: a large buffer's pages as transparent huge pages (a hint) ---- */
void bvox__advise_huge(void *p, size_t bytes);

/* ---- growable budgeted buffer (mesh.c) ---- */
typedef struct bvox__buf {
    void *data;
    size_t size, cap; /* bytes */
} bvox__buf;
bvox_status bvox__buf_reserve(bvox__buf *b, size_t bytes, const char *what);
void bvox__buf_release(bvox__buf *b);

/* ---- mesh.c ---- */
/* Grow the mesh arrays (budgeted). */
bvox_status bvox__mesh_grow(bvox_mesh *m, int64_t nv, int64_t nt);
/* Vertex adjacency in CSR form over the distinct undirected edges:
 * neighbours of v are adj[start[v] .. start[v+1]). Budgeted arrays. */
typedef struct bvox__adjacency {
    int64_t *start;
    int32_t *adj;
    int64_t nedges;
    size_t start_bytes, adj_bytes; /* budgeted (bvox__alloc) */
} bvox__adjacency;
bvox_status bvox__mesh_adjacency(const bvox_mesh *m, bvox__adjacency *a);
void bvox__adjacency_release(bvox__adjacency *a);
/* Counts of edges used by 1, 2, >2 triangles, and of 2-triangle edges
 * traversed the same way by both. */
bvox_status bvox__mesh_edge_stats(const bvox_mesh *m, int64_t *edges, int64_t *boundary,
                                  int64_t *nonmanifold, int64_t *inconsistent);

/* ---- volume -> mesh (mc.c, cuberille.c; dispatched by mesh_from_volume.c) ---- */
bvox_status bvox__mesh_mc(const bvox_volume *vol, bvox_mesh *m);
bvox_status bvox__mesh_cuberille(const bvox_volume *vol, bvox_mesh *m);
/* The same mesh with every face built as a general polygon (no plain-quad
 * path): what the tests compare bvox__mesh_cuberille with. */
bvox_status bvox__mesh_cuberille_reference(const bvox_volume *vol, bvox_mesh *m);

/* ---- readers (read_*.c), on a buffer; name for messages ---- */
bvox_status bvox__mesh_read_stl(const uint8_t *d, size_t n, const char *name, bvox_mesh *m);
bvox_status bvox__mesh_read_obj(const uint8_t *d, size_t n, const char *name, bvox_mesh *m);
bvox_status bvox__mesh_read_ply(const uint8_t *d, size_t n, const char *name, bvox_mesh *m);
bvox_status bvox__mesh_read_off(const uint8_t *d, size_t n, const char *name, bvox_mesh *m);

/* ---- text tokenizer (mesh_text.c) ---- */
typedef struct bvox__text {
    const char *p, *end;
    const char *name;
    int64_t line; /* 1-based line of p */
} bvox__text;
void bvox__text_init(bvox__text *t, const uint8_t *d, size_t n, const char *name);
/* Skip spaces and tabs (and '\r'); not newlines. */
void bvox__text_skip_blank(bvox__text *t);
/* Skip to the start of the next line. */
void bvox__text_next_line(bvox__text *t);
/* Skip whitespace including newlines and '#' comments. */
void bvox__text_skip_ws(bvox__text *t);
/* Next token (non-whitespace run) into buf (NUL-terminated, truncated
 * tokens are an error); 0 if none before the end of the data. */
int bvox__text_token(bvox__text *t, char *buf, size_t size, int same_line);
/* Parse a finite double / an integer token; BVOX_EFORMAT naming the file,
 * the line and what. */
bvox_status bvox__text_double(bvox__text *t, int same_line, const char *what, double *out);
bvox_status bvox__text_int(bvox__text *t, int same_line, const char *what, int64_t lo,
                           int64_t hi, int64_t *out);
/* Check a vertex and add it / add a polygon as triangles: a fan for up to 16
 * corners, longer ones split by halving (mesh.c; indices
 * already 0-based, checked against nvertices). */
bvox_status bvox__mesh_add_polygon(bvox_mesh *m, const int64_t *idx, int64_t n, const char *name,
                                   int64_t line);

/* ---- buffered mesh output (mesh_write.c), for the writers of mesh_write.c
 * and mesh_labels_file.c: 1 MiB blocks into a temporary-file sink; the
 * first failure is kept in st and later writes do nothing. ---- */
#include "io/io.h"
#define BVOX__MESH_OUT_BLOCK (1u << 20)
typedef struct bvox__mesh_out {
    bvox__sink sink;
    char *buf;
    size_t n;
    bvox_status st;
} bvox__mesh_out;
bvox_status bvox__mesh_out_open(bvox__mesh_out *o, const char *path);
void bvox__mesh_out_put(bvox__mesh_out *o, const void *p, size_t n);
void bvox__mesh_out_printf(bvox__mesh_out *o, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
void bvox__mesh_out_le32(bvox__mesh_out *o, uint32_t v);
void bvox__mesh_out_f64(bvox__mesh_out *o, double d);
/* Hand the buffered bytes to the sink (errors kept in st). */
void bvox__mesh_out_flush(bvox__mesh_out *o);
/* Flush and commit (commit false, or an earlier failure: remove); frees. */
bvox_status bvox__mesh_out_close(bvox__mesh_out *o, bool commit);

/* ---- the formats one element at a time (mesh_write.c), shared by
 * bvox_mesh_write and the streamed writer (mesh_sink.c). kind: 0 STL,
 * 1 PLY, 2 OBJ, 3 OFF (bvox__mesh_format_kind: from format, else path's
 * extension; BVOX_EINVAL naming what is wrong). ---- */
bvox_status bvox__mesh_format_kind(const char *path, const char *format, int *kind);
void bvox__mesh_out_stl_header(bvox__mesh_out *o, uint32_t ntriangles, int ascii);
void bvox__mesh_out_stl_triangle(bvox__mesh_out *o, const double *const p[3], int ascii);
/* PLY's (ascii or binary) and OFF's (ascii) vertex and face records. */
void bvox__mesh_out_vertex(bvox__mesh_out *o, const double *p, int ascii);
void bvox__mesh_out_face(bvox__mesh_out *o, int64_t a, int64_t b, int64_t c, int ascii);
void bvox__mesh_out_obj_vertex(bvox__mesh_out *o, const double *p);
void bvox__mesh_out_obj_face(bvox__mesh_out *o, int64_t a, int64_t b, int64_t c);
/* The header of PLY, OBJ (its first comment line) or OFF (kind 1, 2, 3)
 * for nv vertices and nt triangles into buf, with pad spaces (at most
 * BVOX__MESH_HEADER_PAD) where readers ignore them: the end of PLY's
 * comment, OBJ's comment, OFF's count line. A streamed file reserves the
 * header with the widest counts and writes the real one, padded to the same
 * length, at the end. Returns the length (snprintf's). */
#define BVOX__MESH_HEADER_PAD 64
#define BVOX__MESH_HEADER_MAX 512
int bvox__mesh_header(char *buf, size_t size, int kind, int64_t nv, int64_t nt, int ascii,
                      size_t pad);

#endif
