/*
 * surface.c — the boundary voxels of a volume (1-voxels with a 0 face
 * neighbour, the outside counting as 0), listed once so that any parallel
 * view can be cast by splatting them (cast_view.c) without touching the
 * volume again. The first voxel a ray meets always has a 0 neighbour on the
 * side the ray enters from, so nothing visible is lost.
 *
 * Built word-wise: per z-word, interior = v & (6 neighbour words) and
 * boundary = v & ~interior, a whole row of words at a time. The rows are
 * split into bands over the worker threads. One pass appends each band's
 * boundary voxels, in row order, to the band's list of their neighbour
 * class (the 6 neighbour bits), in chunks; the chunks are the surface: its
 * runs (render.h) are the chunks taken class by class, band by band, so
 * that laid end to end they are the entries grouped by class, rows in
 * order within a class. (Until 2026-12 a second pass classified every voxel
 * again from the volume: that work, not the memory traffic, was most of the
 * build. Then the lists were copied into one array, which touched every
 * entry and a fresh page for it a second time.) Grouping by
 * class lets a view skip the classes that face away from it as whole ranges
 * (back-face culling without a test per voxel). Each entry packs
 * x, y, z (16 bits each: dimensions are at most 65535) and the 6 neighbour
 * bits (render.h's NB_*), from which the normal code and the per-view back
 * face cull follow. The bounding box comes from the first pass too (each
 * row's x and z range of boundary voxels): every extreme 1-voxel is one.
 */
#include "render.h"
#include "render/surface_row.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* The blocks that every band's chunks are carved from, shared by the bands
 * (under a lock, taken once a chunk: 64 entries or more)
 * because the surface keeps them: blocks per band left one partly used 8 MiB
 * block per band, and its first huge page, resident for the surface's life
 * (a 1024^3 sphere's 18 MB of entries held 126 MB at 64 bands). */
typedef struct pool {
    pthread_mutex_t lock;
    uint64_t **blocks; /* from bvox__alloc, block_entries each */
    int nblocks, block_slots;
    size_t block_entries, block_used; /* block_used: entries carved from the last block */
    uint64_t **spare;  /* a rebuilt surface's blocks, charged in full, taken first */
    int nspare;
} pool;

/* One band of rows: its entries of each class in row order, in chunks carved
 * from the pool's blocks. Lists per class, so that the chunks, taken
 * class by class and band by band, are the surface's runs as they stand,
 * where a single list per band had to be scattered entry by entry.
 * Chunks, not buffers grown by doubling: every doubling touched fresh pages
 * again and copied, and on the 1024^3 atlas the two threads' page faults
 * made the 2-thread build no faster than 1 thread. */
typedef struct chunk {
    uint64_t *at;
    size_t used; /* entries: set when the class moves on to a new chunk, or at the end */
    int cls;
} chunk;

typedef struct band {
    uint64_t *cur[64], *end[64]; /* where each class's next entry goes; its chunk's end */
    size_t next_size[64];        /* entries of the class's next chunk */
    int last[64];                /* the class's current chunk in `chunks`, -1 for none */
    chunk *chunks;
    int nchunks, chunk_slots;
    pool *pool;
    bool failed;       /* out of memory (reported by the caller: a worker cannot) */
} band;

/* Slots for one more pointer-sized record in a growing array; false when out of memory. */
static bool grow_slots(void **array, int n, int *slots, size_t size)
{
    if (n < *slots) return true;
    int more = *slots ? 2 * *slots : 16;
    void *p = bvox__mem_resize(*array, (size_t)more * size);
    if (!p) return false;
    *array = p;
    *slots = more;
    return true;
}

/* size entries carved from the pool's last block, or a new block; NULL
 * when out of memory. The rest of a block too small for the chunk is left
 * (never touched, so it holds no pages). */
static uint64_t *pool_carve(pool *p, size_t size)
{
    uint64_t *at = NULL;
    pthread_mutex_lock(&p->lock);
    if (!p->nblocks || p->block_entries - p->block_used < size) {
        bvox_status st;
        uint64_t *b = NULL;
        if (grow_slots((void **)&p->blocks, p->nblocks, &p->block_slots, sizeof *p->blocks))
            b = p->nspare ? p->spare[--p->nspare]
                          : bvox__alloc(p->block_entries * sizeof *b, false, "surface voxels", &st);
        if (b) {
            p->blocks[p->nblocks++] = b;
            p->block_used = 0;
        }
    }
    if (p->nblocks && p->block_entries - p->block_used >= size) {
        at = p->blocks[p->nblocks - 1] + p->block_used;
        p->block_used += size;
    }
    pthread_mutex_unlock(&p->lock);
    return at;
}

/* The largest chunk, in entries (128 KiB). The surface keeps the chunks, so
 * each list's last one, half empty on average, stays allocated for the
 * surface's life: chunks of up to an eighth of a block held 1.6 times the
 * entries' bytes (a 1024^3 sphere at 1 thread), these 1.14 (1.4 at 64
 * bands); 4096 measured no different in time; bigger chunks mean fewer
 * runs for a view to walk. */
#define CHUNK_MAX 16384

/* Class k's current chunk (if any) given its count of entries: the hot loop
 * only moves cur[k]. */
static void close_chunk(band *bd, int k)
{
    if (bd->last[k] < 0) return;
    chunk *ch = bd->chunks + bd->last[k];
    ch->used = (size_t)(bd->cur[k] - ch->at);
}

/* A new chunk for class k, the class's current one being full (or there is
 * none yet): the class's chunks double from 64 entries up to CHUNK_MAX,
 * so that a band's rare classes take little room and its common ones not
 * many chunks. Returns where the entry goes;
 * NULL when out of memory. */
static uint64_t *band_new_chunk(band *bd, int k)
{
    close_chunk(bd, k);
    size_t size = bd->next_size[k];
    if (size > bd->pool->block_entries) size = bd->pool->block_entries; /* a small volume */
    if (!grow_slots((void **)&bd->chunks, bd->nchunks, &bd->chunk_slots, sizeof *bd->chunks))
        return NULL;
    uint64_t *at = pool_carve(bd->pool, size);
    if (!at) return NULL;
    bd->chunks[bd->nchunks] = (chunk){at, 0, k};
    bd->last[k] = bd->nchunks++;
    bd->cur[k] = at;
    bd->end[k] = at + size;
    if (bd->next_size[k] < CHUNK_MAX) bd->next_size[k] *= 2;
    return at;
}

/* The band's last chunks closed: each chunk knows its count. */
static void band_finish(band *bd)
{
    for (int k = 0; k < 64; k++) close_chunk(bd, k);
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
    int64_t *rowbox;   /* ny * 4: x and z range of each row's boundary */
    row_kernels kernels;
    pool *pool;
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
 * voxels, appended to the band's list of their class in row order; the
 * row's x and z range. */
static void collect_band(build_ctx *c, int64_t t)
{
    const bvox_volume *v = c->v;
    const size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    band *bd = c->bands + t;
    bd->pool = c->pool;
    /* the row's boundary words, then bits saying which are nonzero */
    uint64_t *bw = bvox__mem_alloc((row + (row + 63) / 64) * sizeof *bw), *nz = bw + row;
    if (!bw) {
        bd->failed = true;
        return;
    }
    const int64_t y0 = v->ny * t / c->nbands, y1 = v->ny * (t + 1) / c->nbands;
    /* i / wpc as a multiply by the 64-bit reciprocal: perf put a tenth of
     * this pass's samples on a divide per nonzero word. Exact for
     * i * wpc < 2^64 (i < 2^32). */
    const uint64_t recip = wpc > 1 ? UINT64_MAX / wpc + 1 : 0;
    /* each class's first chunk: 64 entries (a cache-line multiple, so
     * chunks of two threads never share a line), then doubling: a list's
     * last chunk, which the surface keeps half empty on average, is never
     * much bigger than the list (with 512 a 384^3 sphere at 48 bands held
     * twice its entries' bytes) */
    const size_t block_entries = c->pool->block_entries;
    size_t first = block_entries < 64 ? block_entries : 64;
    for (int k = 0; k < 64; k++) bd->last[k] = -1, bd->next_size[k] = first;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++) {
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
                const int32_t x =
                    wpc > 1 ? (int32_t)((unsigned __int128)i * recip >> 64) : (int32_t)i;
                const size_t w = i - (uint32_t)x * (uint32_t)wpc;
                uint64_t b = bw[i];
                int64_t z0 = (int64_t)w * 64 + __builtin_ctzll(b);
                int64_t z1 = (int64_t)w * 64 + 63 - __builtin_clzll(b);
                if (x < rb[0]) rb[0] = x;
                rb[1] = x;
                if (z0 < rb[2]) rb[2] = z0;
                if (z1 > rb[3]) rb[3] = z1;
                uint64_t nb[6];
                bvox__surface_neighbours(v, x, y, w, nb);
                const uint64_t xy = (uint64_t)x | (uint64_t)y << 16;
                for (; b; b &= b - 1) {
                    unsigned bit = (unsigned)__builtin_ctzll(b);
                    uint64_t cls = bvox__surface_nb_bits(nb, bit), z = w * 64 + bit;
                    uint64_t *out = bd->cur[cls];
                    if (out == bd->end[cls] && !(out = band_new_chunk(bd, (int)cls))) {
                        bd->failed = true;
                        free(bw);
                        return;
                    }
                    *out = xy | z << 32 | cls << 48;
                    bd->cur[cls] = out + 1;
                }
            }
        }
    }
    free(bw);
    band_finish(bd);
}

static void collect_bands(void *arg, int64_t t0, int64_t t1)
{
    for (int64_t t = t0; t < t1; t++) collect_band(arg, t);
}

static void release_bands(band *bands, int n)
{
    for (int t = 0; t < n; t++) free(bands[t].chunks);
    free(bands);
}

/* The pool's blocks, unless the surface took them, and its spare ones. */
static void release_pool(pool *p)
{
    for (int h = 0; h < p->nblocks; h++)
        bvox__free(p->blocks[h], p->block_entries * sizeof(uint64_t));
    for (int h = 0; h < p->nspare; h++)
        bvox__free(p->spare[h], p->block_entries * sizeof(uint64_t));
    free(p->blocks);
    free(p->spare);
    pthread_mutex_destroy(&p->lock);
}

/* The surface's runs from the bands' chunks: class after class, band after
 * band, a band's chunks of the class in the order they were filled, so the
 * runs laid end to end are the entries in the build's order; and the
 * pool's blocks handed to the surface. */
static bvox_status adopt_bands(bvox_surface *s, const band *bands, int nbands, pool *p)
{
    int64_t nruns = 0;
    for (int t = 0; t < nbands; t++)
        for (int h = 0; h < bands[t].nchunks; h++) nruns += bands[t].chunks[h].used > 0;
    s->runs = bvox__mem_alloc((size_t)(nruns ? nruns : 1) * sizeof *s->runs);
    s->blocks = bvox__mem_alloc((size_t)(p->nblocks ? p->nblocks : 1) * sizeof *s->blocks);
    if (!s->runs || !s->blocks) return bvox__fail(BVOX_ENOMEM, "out of memory");
    int64_t r = 0, n = 0;
    for (int k = 0; k < 64; k++) {
        s->class_run[k] = r;
        s->class_start[k] = n;
        for (int t = 0; t < nbands; t++)
            for (int h = 0; h < bands[t].nchunks; h++) {
                const chunk *ch = bands[t].chunks + h;
                if (ch->cls != k || !ch->used) continue;
                s->runs[r++] = (bvox__surface_run){ch->at, (int64_t)ch->used};
                n += (int64_t)ch->used;
            }
    }
    s->class_run[64] = r;
    s->class_start[64] = n;
    s->count = n;
    /* the surface keeps the blocks; the never-carved tail of the last one
     * goes back to the memory budget (its pages were never touched) */
    const size_t full = p->block_entries * sizeof(uint64_t);
    for (int h = 0; h < p->nblocks; h++) {
        size_t keep = h + 1 < p->nblocks ? full : p->block_used * sizeof(uint64_t);
        bvox__budget_refund(full - keep);
        s->blocks[s->nblocks++] = (bvox__surface_block){p->blocks[h], keep, p->block_entries};
    }
    p->nblocks = 0;
    return BVOX_OK;
}

/* The blocks of old (a surface being rebuilt, or NULL) of the pool's block
 * size, charged to the budget in full again, as the pool's spares; old's
 * other blocks and its runs freed: old is left empty. */
static void take_spares(pool *p, bvox_surface *old)
{
    if (!old) return;
    p->spare = bvox__mem_alloc((size_t)(old->nblocks ? old->nblocks : 1) * sizeof *p->spare);
    for (int h = 0; h < old->nblocks; h++) {
        bvox__surface_block *b = old->blocks + h;
        const size_t full = p->block_entries * sizeof(uint64_t);
        bvox_status st;
        if (p->spare && b->capacity == p->block_entries &&
            bvox__budget_charge(full - b->bytes, "surface voxels", &st)) {
            p->spare[p->nspare++] = b->at;
            b->at = NULL; /* now the pool's */
        }
    }
    bvox__surface_release(old); /* frees the blocks not taken */
    old->count = 0;
    old->empty = 1;
    old->bbox = (bvox_box){0, 0, 0, 0, 0, 0};
    memset(old->class_start, 0, sizeof old->class_start);
    memset(old->class_run, 0, sizeof old->class_run);
}

/* bvox_surface_build, with the memory of old (or NULL) reused. */
static bvox_status build_with(const bvox_volume *vol, bvox_surface *old, bvox_surface **out)
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
    /* each row's box (ny * 4) */
    size_t box_bytes = (size_t)vol->ny * 4 * sizeof(int64_t);
    size_t row_bytes = (size_t)vol->nx * vol->wpc * sizeof(uint64_t);
    int64_t *rowbox = NULL;
    uint64_t *zero_row = NULL;
    if (!s || !bands) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    if (!st) rowbox = bvox__alloc(box_bytes, false, "surface rows", &st);
    if (!st) zero_row = bvox__alloc(row_bytes, true, "surface rows", &st);
    /* blocks of 8 MiB (huge pages, see alloc.c), less in a small volume */
    pool pl = {.block_entries = (size_t)1 << 20};
    const size_t voxels = (size_t)vol->ny * (size_t)vol->nx * vol->wpc * 64;
    if (voxels < pl.block_entries) pl.block_entries = voxels > 64 ? voxels : 64;
    pthread_mutex_init(&pl.lock, NULL);
    take_spares(&pl, old);
    build_ctx c = {.v = vol, .zero_row = zero_row, .bands = bands, .nbands = nbands,
                   .rowbox = rowbox, .kernels = choose_kernels(), .pool = &pl};
    if (!st) bvox__parallel_for_dynamic(nbands, 1, collect_bands, &c);
    for (int t = 0; !st && t < nbands; t++)
        if (bands[t].failed)
            st = bvox__fail(BVOX_ENOMEM, "out of memory listing the surface voxels");
    bvox__free(zero_row, row_bytes);
    if (st) {
        if (bands) release_bands(bands, nbands);
        release_pool(&pl);
        bvox__free(rowbox, box_bytes);
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
    bvox__free(rowbox, box_bytes);
    st = adopt_bands(s, bands, nbands, &pl);
    release_bands(bands, nbands);
    release_pool(&pl);
    if (st) {
        bvox_surface_destroy(s);
        return st;
    }
    s->dims = (bvox_dims){vol->nx, vol->ny, vol->nz};
    memcpy(s->spacing, vol->geom.spacing, sizeof s->spacing);
    *out = s;
    return BVOX_OK;
}

bvox_status bvox_surface_build(const bvox_volume *vol, bvox_surface **out)
{
    return build_with(vol, NULL, out);
}

bvox_status bvox_surface_rebuild(bvox_surface *surf, const bvox_volume *vol)
{
    if (!surf) return bvox__fail(BVOX_EINVAL, "surface rebuild: no surface");
    bvox_surface *s;
    bvox_status st = build_with(vol, vol ? surf : NULL, &s);
    if (st) return st;
    bvox__surface_release(surf); /* nothing left in it: take_spares emptied it */
    *surf = *s;
    free(s);
    return BVOX_OK;
}

void bvox__surface_release(bvox_surface *s)
{
    for (int h = 0; h < s->nblocks; h++) {
        const bvox__surface_block *b = s->blocks + h;
        bvox__free_charged(b->at, b->capacity * sizeof(uint64_t), b->bytes);
    }
    free(s->blocks);
    free(s->runs);
    s->blocks = NULL;
    s->runs = NULL;
    s->nblocks = 0;
}

void bvox_surface_destroy(bvox_surface *surf)
{
    if (!surf) return;
    bvox__surface_release(surf);
    free(surf);
}

void bvox__surface_flatten(const bvox_surface *s, uint64_t *out)
{
    for (int64_t r = 0; r < s->class_run[64]; r++) {
        memcpy(out, s->runs[r].at, (size_t)s->runs[r].n * sizeof *out);
        out += s->runs[r].n;
    }
}

int64_t bvox_surface_count(const bvox_surface *surf) { return surf ? surf->count : 0; }
