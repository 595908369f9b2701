/*
 * surface.c — the boundary voxels of a volume (1-voxels with a 0 face
 * neighbour, the outside counting as 0), listed once so that any parallel
 * view can be cast by splatting them (cast_view.c) without touching the
 * volume again. The first voxel a ray meets always has a 0 neighbour on the
 * side the ray enters from, so nothing visible is lost.
 *
 * Built word-wise: per z-word, interior = v & (6 neighbour words) and
 * boundary = v & ~interior, a whole row of words at a time. The rows are
 * split into bands over the worker threads. A first pass lists each band's
 * boundary voxels in row order and counts them per y row and neighbour
 * class (the 6 neighbour bits); a prefix sum gives each (class, row) its
 * place; a second pass moves each band's list to those places. (Until
 * 2026-12 the second pass classified every voxel again from the volume:
 * that work, not the memory traffic, was most of the build.) Grouping by
 * class lets a view skip the classes that face away from it as whole ranges
 * (back-face culling without a test per voxel). Each entry packs
 * x, y, z (16 bits each: dimensions are at most 65535) and the 6 neighbour
 * bits (render.h's NB_*), from which the normal code and the per-view back
 * face cull follow. The bounding box comes from the first pass too (each
 * row's x and z range of boundary voxels): every extreme 1-voxel is one.
 */
#include "render.h"
#include "render/surface_row.h"

#include <stdlib.h>
#include <string.h>

/* One band of rows of the first pass: its entries in row order, in chunks
 * of a fixed size. Chunks, not one buffer grown by doubling: every doubling
 * touched fresh pages again and copied, and on the 1024^3 atlas the two
 * threads' page faults made the 2-thread build no faster than 1 thread. */
typedef struct band {
    uint64_t **chunk;
    size_t *used; /* entries in each chunk */
    int nchunks, slots;
    size_t chunk_entries;
    bool failed; /* out of memory (reported by the caller: a worker cannot) */
} band;

/* Where the next word's entries go: at least 64 free places (or as many as
 * the band can have at all) in the last chunk; NULL when out of memory. */
static uint64_t *band_room(band *bd)
{
    if (bd->nchunks && bd->chunk_entries - bd->used[bd->nchunks - 1] >= 64)
        return bd->chunk[bd->nchunks - 1] + bd->used[bd->nchunks - 1];
    if (bd->nchunks == bd->slots) {
        int slots = bd->slots ? 2 * bd->slots : 8;
        uint64_t **chunk = bvox__mem_resize(bd->chunk, (size_t)slots * sizeof *chunk);
        if (chunk) bd->chunk = chunk;
        size_t *used = bvox__mem_resize(bd->used, (size_t)slots * sizeof *used);
        if (used) bd->used = used;
        if (!chunk || !used) return NULL;
        bd->slots = slots;
    }
    bvox_status st;
    uint64_t *p = bvox__alloc(bd->chunk_entries * sizeof *p, false, "surface voxels", &st);
    if (!p) return NULL;
    bd->chunk[bd->nchunks] = p;
    bd->used[bd->nchunks++] = 0;
    return p;
}

typedef struct row_kernels {
    bvox__surface_flat_fn flat;
    bvox__surface_nonzero_fn nonzero;
} row_kernels;

typedef struct build_ctx {
    const bvox_volume *v;
    const uint64_t *zero_row; /* nx * wpc zero words: the rows outside the volume */
    band *bands;
    int nbands;
    int64_t *at;       /* ny * 64: counts per row and class, then where each goes */
    int64_t *rowbox;   /* ny * 4: x and z range of each row's boundary */
    row_kernels kernels;
    uint64_t *entries; /* the result, grouped by class */
} build_ctx;

/* Word i = x * wpc + w of the row, with the outside counting as 0. */
static inline uint64_t boundary_at(const uint64_t *prev, const uint64_t *cur,
                                   const uint64_t *next, size_t nx, size_t wpc, size_t x,
                                   size_t w)
{
    size_t i = x * wpc + w;
    return bvox__boundary_word(cur[i], x > 0 ? cur[i - wpc] : 0, x + 1 < nx ? cur[i + wpc] : 0,
                               prev[i], next[i], w > 0 ? cur[i - 1] : 0,
                               w + 1 < wpc ? cur[i + 1] : 0);
}

/* The portable row kernels (surface_row.h); the compiler vectorises the
 * first for the baseline instruction set. */
static void flat_generic(const uint64_t *prev, const uint64_t *cur, const uint64_t *next,
                         size_t n, size_t wpc, uint64_t *b)
{
    for (size_t i = wpc; i + wpc < n; i++)
        b[i] = bvox__boundary_word(cur[i], cur[i - wpc], cur[i + wpc], prev[i], next[i],
                                   cur[i - 1], cur[i + 1]);
}

static void nonzero_generic(const uint64_t *b, size_t n, uint64_t *m)
{
    for (size_t i0 = 0; i0 < n; i0 += 64) {
        const size_t nw = n - i0 < 64 ? n - i0 : 64;
        uint64_t w = 0;
        for (size_t j = 0; j < nw; j++) w |= (uint64_t)(b[i0 + j] != 0) << j;
        m[i0 / 64] = w;
    }
}

static row_kernels choose_kernels(void)
{
    if (bvox_simd_active() >= BVOX_SIMD_AVX2 && bvox__surface_flat_avx2 &&
        __builtin_cpu_supports("avx2"))
        return (row_kernels){bvox__surface_flat_avx2, bvox__surface_nonzero_avx2};
    return (row_kernels){flat_generic, nonzero_generic};
}

/* The boundary words b[0, nx * wpc) of a whole row (prev and next are the
 * rows y - 1 and y + 1, the zero row outside). A row is nx * wpc consecutive
 * words, and in it the x neighbours are wpc words away and the z neighbours
 * one word away. So all but the end columns go through one flat loop that
 * the compiler vectorises; a column at a time (8 or 16 words) was too short
 * a loop for vectors. The flat loop carries z bits across the ends of
 * columns, so each column's first and last words are redone with a zero
 * carry, and the two end columns whole, with their outside x neighbour. */
static void row_boundary(const uint64_t *prev, const uint64_t *cur, const uint64_t *next,
                         size_t nx, size_t wpc, bvox__surface_flat_fn flat, uint64_t *b)
{
    const size_t n = nx * wpc;
    flat(prev, cur, next, n, wpc, b);
    for (size_t x = 1; x + 1 < nx; x++) {
        b[x * wpc] = boundary_at(prev, cur, next, nx, wpc, x, 0);
        b[x * wpc + wpc - 1] = boundary_at(prev, cur, next, nx, wpc, x, wpc - 1);
    }
    for (size_t w = 0; w < wpc; w++) {
        b[w] = boundary_at(prev, cur, next, nx, wpc, 0, w);
        b[n - wpc + w] = boundary_at(prev, cur, next, nx, wpc, nx - 1, w);
    }
}

/* First pass over one band: each row's boundary words, then its boundary
 * voxels, appended to the band's list in row order and counted per class;
 * the row's x and z range. */
static void collect_band(build_ctx *c, int64_t t)
{
    const bvox_volume *v = c->v;
    const size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    band *bd = c->bands + t;
    /* the row's boundary words, then bits saying which are nonzero */
    uint64_t *bw = bvox__mem_alloc((row + (row + 63) / 64) * sizeof *bw), *nz = bw + row;
    if (!bw) {
        bd->failed = true;
        return;
    }
    const int64_t y0 = v->ny * t / c->nbands, y1 = v->ny * (t + 1) / c->nbands;
    /* chunks of 8 MiB (huge pages, see alloc.c), less where the band has
     * fewer voxels, but room for one word */
    const size_t voxels = (size_t)(y1 - y0) * (size_t)v->nx * wpc * 64;
    bd->chunk_entries = voxels < ((size_t)1 << 20) ? (voxels > 64 ? voxels : 64) : (size_t)1 << 20;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
        int64_t *at = c->at + (size_t)y * 64;
        /* the bounding box comes from the boundary (every extreme 1-voxel is
         * on it), so no separate scan of the volume is needed */
        int64_t *rb = c->rowbox + (size_t)y * 4;
        rb[0] = v->nx, rb[1] = -1, rb[2] = v->nz, rb[3] = -1;
        const uint64_t *cur = bvox__column_c(v, 0, y);
        row_boundary(y > 0 ? cur - row : c->zero_row, cur,
                     y + 1 < v->ny ? cur + row : c->zero_row, (size_t)v->nx, wpc, c->kernels.flat,
                     bw);
        c->kernels.nonzero(bw, row, nz);
        /* the row's nonzero boundary words, found 64 at a time through a
         * mask: a test and branch per word mispredicted on every nonzero
         * word of a sparse row, and that cost more than the row pass */
        for (size_t i0 = 0; i0 < row; i0 += 64) {
            for (uint64_t m = nz[i0 / 64]; m; m &= m - 1) {
                const uint32_t i = (uint32_t)(i0 + (size_t)__builtin_ctzll(m));
                const int32_t x = (int32_t)(i / (uint32_t)wpc);
                const size_t w = i - (uint32_t)x * (uint32_t)wpc;
                uint64_t b = bw[i];
                /* room for the word's 64 voxels at most */
                uint64_t *out = band_room(bd);
                if (!out) {
                    bd->failed = true;
                    free(bw);
                    return;
                }
                int64_t z0 = (int64_t)w * 64 + __builtin_ctzll(b);
                int64_t z1 = (int64_t)w * 64 + 63 - __builtin_clzll(b);
                if (x < rb[0]) rb[0] = x;
                rb[1] = x;
                if (z0 < rb[2]) rb[2] = z0;
                if (z1 > rb[3]) rb[3] = z1;
                uint64_t nb[6];
                bvox__surface_neighbours(v, x, y, w, nb);
                size_t k = 0;
                for (; b; b &= b - 1, k++) {
                    unsigned bit = (unsigned)__builtin_ctzll(b);
                    uint64_t cls = bvox__surface_nb_bits(nb, bit), z = w * 64 + bit;
                    at[cls]++;
                    out[k] = (uint64_t)x | (uint64_t)y << 16 | z << 32 | cls << 48;
                }
                bd->used[bd->nchunks - 1] += k;
            }
        }
    }
    free(bw);
}

static void collect_bands(void *arg, int64_t t0, int64_t t1)
{
    for (int64_t t = t0; t < t1; t++) collect_band(arg, t);
}

/* Second pass: each band's list to its place, class by class; a band's rows
 * are its own, so its places in at are too. */
static void place_bands(void *arg, int64_t t0, int64_t t1)
{
    build_ctx *c = arg;
    for (int64_t t = t0; t < t1; t++) {
        const band *bd = c->bands + t;
        for (int h = 0; h < bd->nchunks; h++) {
            const uint64_t *e = bd->chunk[h];
            for (size_t i = 0; i < bd->used[h]; i++) {
                size_t y = (size_t)(e[i] >> 16 & 0xffff), cls = (size_t)(e[i] >> 48);
                c->entries[c->at[y * 64 + cls]++] = e[i];
            }
        }
    }
}

static void release_bands(band *bands, int n)
{
    for (int t = 0; t < n; t++) {
        for (int h = 0; h < bands[t].nchunks; h++)
            bvox__free(bands[t].chunk[h], bands[t].chunk_entries * sizeof(uint64_t));
        free(bands[t].chunk);
        free(bands[t].used);
    }
    free(bands);
}

bvox_status bvox_surface_build(const bvox_volume *vol, bvox_surface **out)
{
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "surface: no volume");
    bvox__clear_error();
    bvox_surface *s = bvox__mem_zalloc(1, sizeof *s);
    /* bands of at least 8 rows, four per thread, so that a thread with the
     * busier rows takes fewer */
    int nbands = 4 * bvox__parallelism();
    if (nbands > vol->ny / 8) nbands = vol->ny / 8 > 0 ? vol->ny / 8 : 1;
    band *bands = bvox__mem_zalloc((size_t)nbands, sizeof *bands);
    bvox_status st = BVOX_OK;
    size_t at_bytes = (size_t)vol->ny * (64 + 4) * sizeof(int64_t);
    size_t row_bytes = (size_t)vol->nx * vol->wpc * sizeof(uint64_t);
    int64_t *at = NULL;
    uint64_t *zero_row = NULL;
    if (!s || !bands) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    if (!st) at = bvox__alloc(at_bytes, true, "surface rows", &st);
    if (!st) zero_row = bvox__alloc(row_bytes, true, "surface rows", &st);
    build_ctx c = {.v = vol, .zero_row = zero_row, .bands = bands, .nbands = nbands,
                   .at = at, .rowbox = at ? at + (size_t)vol->ny * 64 : NULL,
                   .kernels = choose_kernels()};
    if (!st) bvox__parallel_for_dynamic(nbands, 1, collect_bands, &c);
    for (int t = 0; !st && t < nbands; t++)
        if (bands[t].failed)
            st = bvox__fail(BVOX_ENOMEM, "out of memory listing the surface voxels");
    bvox__free(zero_row, row_bytes);
    if (st) {
        if (bands) release_bands(bands, nbands);
        bvox__free(at, at_bytes);
        free(s);
        return st;
    }
    /* the bounding box, as bvox_volume_bbox gives it (zero box if empty) */
    bvox_box bb = {vol->nx, vol->ny, vol->nz, -1, -1, -1};
    for (int32_t y = 0; y < vol->ny; y++) {
        const int64_t *rb = c.rowbox + (size_t)y * 4;
        if (rb[1] < 0) continue;
        if (y < bb.y0) bb.y0 = y;
        bb.y1 = y;
        if (rb[0] < bb.x0) bb.x0 = (int32_t)rb[0];
        if (rb[1] > bb.x1) bb.x1 = (int32_t)rb[1];
        if (rb[2] < bb.z0) bb.z0 = (int32_t)rb[2];
        if (rb[3] > bb.z1) bb.z1 = (int32_t)rb[3];
    }
    s->empty = bb.x1 < 0;
    s->bbox = s->empty ? (bvox_box){0, 0, 0, 0, 0, 0}
                       : (bvox_box){bb.x0, bb.y0, bb.z0, bb.x1 + 1, bb.y1 + 1, bb.z1 + 1};
    /* entries grouped by class, rows in order within a class */
    int64_t n = 0;
    for (int k = 0; k < 64; k++) {
        s->class_start[k] = n;
        for (int32_t y = 0; y < vol->ny; y++) {
            int64_t cnt = at[(size_t)y * 64 + (size_t)k];
            at[(size_t)y * 64 + (size_t)k] = n;
            n += cnt;
        }
    }
    s->class_start[64] = n;
    s->bytes = (size_t)(n ? n : 1) * sizeof(uint64_t);
    s->entries = bvox__alloc(s->bytes, false, "surface voxels", &st);
    if (s->entries) {
        c.entries = s->entries;
        bvox__parallel_for_dynamic(nbands, 1, place_bands, &c);
    }
    release_bands(bands, nbands);
    bvox__free(at, at_bytes);
    if (!s->entries) {
        free(s);
        return st;
    }
    s->count = n;
    s->dims = (bvox_dims){vol->nx, vol->ny, vol->nz};
    memcpy(s->spacing, vol->geom.spacing, sizeof s->spacing);
    *out = s;
    return BVOX_OK;
}

void bvox_surface_destroy(bvox_surface *surf)
{
    if (!surf) return;
    bvox__free(surf->entries, surf->bytes);
    free(surf);
}

int64_t bvox_surface_count(const bvox_surface *surf) { return surf ? surf->count : 0; }
