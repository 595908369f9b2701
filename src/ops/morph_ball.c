/*
 * morph_ball.c — dilation and erosion by a ball, streamed through the cache.
 *
 * The ball is cut into xz slices, one per y offset dy: the slice at |dy| = k
 * holds the offsets (dx, dz) with |dz| <= h(dx, k). So
 *     dilate(A)[y] = OR over dy of  E_|dy|(A[y + dy]),
 *     E_k(row)[x]  = OR over dx of  Z_h(dx,k)(row)[x + dx],
 * where Z_h ORs every column with its shifts by -h..h bits (64 voxels per
 * operation, by doubling: reach 1, 3, 7, ...; the levels h1 < h2 < ... grow
 * one from the other). A thread owns a band of output rows; the band is cut
 * into x tiles narrow enough that the z levels of one input row and the
 * 2 ry + 1 output rows it reaches all stay in L2. Each
 * input row is read once per tile and pushed into the output rows it
 * reaches, so the work per word is the number of (dx, |dy|) pairs plus the
 * z levels, all on whole words, and no full-volume temporary is made (the
 * former kernel wrote one z-processed volume per reach and read them all
 * back once per (dx, dy) pair, from memory).
 * The levels carry rx zero columns beyond the volume's x faces, so every
 * term of a slice is one pointer into them, and a slice is gathered in
 * blocks of words held in registers while each term is loaded once
 * (morph_ball_kern.h, compiled per SIMD level). The slices nest (E_k holds
 * E_k+1), so they are built from k = ry down in one running buffer, each
 * from the one before and only the terms whose reach grows (radius 10: 105
 * loads per word instead of 169).
 * Erosion is the same with AND; voxels outside the volume are 0, so output
 * rows within ry of the y faces are 0 and out-of-range columns AND in 0.
 */
#include "morph_ball.h"

#define BALL_KERN(name) bvox__ball_##name##_generic
#include "morph_ball_kern.h"
#undef BALL_KERN

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bvox__morph_ball_test_tile = 0;

typedef void (*gather_fn)(uint64_t *, bool, uint64_t *, uint64_t *, const uint64_t *const *, int,
                          size_t, bool);
typedef void (*step_fn)(uint64_t *, const uint64_t *, size_t, size_t, int, uint64_t, bool);

typedef struct term {
    int dx, lev; /* x offset, index of its z level */
} term;

typedef struct ball_job {
    const bvox_volume *in;
    bvox_volume *out;
    bool erode;
    int rx, ry;
    const term *terms;
    const int *kstart; /* terms of slice k: kstart[k] .. kstart[k + 1] - 1; below ry,
                          only those not in slice k + 1 (see bvox__morph_ball) */
    const int *lev_h;  /* z reach of each level, increasing */
    int nlev;
    int64_t nchunks;     /* bands of rows, all rounds together */
    int64_t nslots;      /* bands run at once: each has its scratch slot */
    int64_t chunk0;      /* the first band of the round being run */
    int64_t tx;          /* tile width, columns */
    size_t chunk_words;  /* scratch per slot */
    uint64_t *scratch;
    const uint64_t **ptrs; /* per chunk: one pointer per term into its level, at column x0 */
    gather_fn gather;
    step_fn step;
} ball_job;

/* One z step (dst = every column of src op'ed with its shifts by -s and +s
 * bits): shifts below 64 through the SIMD kernel, longer ones (thin voxels
 * along z) bit by bit through bvox__extract_bits. */
static void z_step(const ball_job *j, uint64_t *dst, const uint64_t *src, size_t ncols,
                   size_t wpc, int64_t s, uint64_t tail)
{
    if (s < 64) {
        j->step(dst, src, ncols, wpc, (int)s, tail, j->erode);
        return;
    }
    for (size_t c = 0; c < ncols; c++) {
        const uint64_t *col = src + c * wpc;
        for (size_t k = 0; k < wpc; k++) {
            int64_t base = (int64_t)k * 64;
            uint64_t a = bvox__extract_bits(col, wpc, base - s);
            uint64_t b = bvox__extract_bits(col, wpc, base + s);
            dst[c * wpc + k] = j->erode ? col[k] & a & b : col[k] | a | b;
        }
        dst[c * wpc + wpc - 1] &= tail;
    }
}

/* dst = src with the z reach of every column grown by d >= 1 (doubling
 * steps: reach 1, 3, 7, ...; ping-ponging through tmp so that the last step
 * lands in dst). */
static void z_grow(const ball_job *j, uint64_t *dst, const uint64_t *src, uint64_t *tmp,
                   size_t ncols, size_t wpc, int64_t d, uint64_t tail)
{
    int nsteps = 0;
    for (int64_t reach = 0; reach < d; nsteps++)
        reach += reach + 1 < d - reach ? reach + 1 : d - reach;
    const uint64_t *from = src;
    int64_t reach = 0;
    for (int i = 0; i < nsteps; i++) {
        int64_t s = reach + 1 < d - reach ? reach + 1 : d - reach;
        uint64_t *to = (nsteps - 1 - i) % 2 == 0 ? dst : tmp;
        z_step(j, to, from, ncols, wpc, s, tail);
        from = to;
        reach += s;
    }
}

/* Output row segment y, from column x0. */
static inline uint64_t *out_seg(const ball_job *j, int64_t y, int64_t x0)
{
    return j->out->words + ((size_t)y * (size_t)j->out->nx + (size_t)x0) * j->out->wpc;
}

static void band(const ball_job *j, int64_t chunk)
{
    const bvox_volume *in = j->in;
    const int64_t nx = in->nx, ny = in->ny, ry = j->ry, rx = j->rx;
    const size_t wpc = in->wpc;
    const bool erode = j->erode;
    int64_t y0 = chunk * ny / j->nchunks, y1 = (chunk + 1) * ny / j->nchunks;
    /* active rows: erosion zeroes the rows within ry of the y faces */
    int64_t ya = y0, yb = y1;
    if (erode) {
        ya = y0 > ry ? y0 : ry;
        yb = y1 < ny - ry ? y1 : ny - ry;
        if (yb < ya) yb = ya;
        for (int64_t y = y0; y < y1; y++)
            if (y < ya || y >= yb) memset(out_seg(j, y, 0), 0, (size_t)nx * wpc * sizeof(uint64_t));
    }
    if (ya >= yb) return;
    const size_t slot = (size_t)(chunk % j->nslots);
    uint64_t *scratch = j->scratch + slot * j->chunk_words;
    /* level l: columns x0 - rx .. x0 + tx + rx of the current input row */
    const size_t zstride = (size_t)(j->tx + 2 * rx) * wpc;
    uint64_t *tmp = scratch + (size_t)j->nlev * zstride; /* one level's size */
    uint64_t *run = tmp + zstride;                        /* the slice, tx columns */
    const uint64_t **ptrs = j->ptrs + slot * (size_t)j->kstart[ry + 1];
    for (int t = 0; t < j->kstart[ry + 1]; t++)
        ptrs[t] = scratch + (size_t)j->terms[t].lev * zstride + (size_t)(rx + j->terms[t].dx) * wpc;
    const uint64_t fill = erode ? ~0ull : 0;
    const int64_t yi0 = ya - ry > 0 ? ya - ry : 0, yi1 = yb + ry < ny ? yb + ry : ny;

    for (int64_t x0 = 0; x0 < nx; x0 += j->tx) {
        int64_t x1 = x0 + j->tx < nx ? x0 + j->tx : nx;
        int64_t xa = x0 - rx > 0 ? x0 - rx : 0, xb = x1 + rx < nx ? x1 + rx : nx;
        size_t segw = (size_t)(x1 - x0) * wpc, nc = (size_t)(xb - xa);
        size_t pad0 = (size_t)(xa - (x0 - rx)) * wpc; /* zero columns before x = 0 */
        size_t used = (size_t)(xb - (x0 - rx)) * wpc;  /* columns up to xb */
        size_t span = (size_t)(x1 - x0 + 2 * rx) * wpc;
        /* columns outside the volume are 0 in every level (for the whole tile) */
        for (int l = 0; l < j->nlev; l++) {
            uint64_t *z = scratch + (size_t)l * zstride;
            memset(z, 0, pad0 * sizeof *z);
            memset(z + used, 0, (span - used) * sizeof *z);
        }
        for (int64_t yi = yi0; yi < yi1; yi++) {
            /* the output rows this input row reaches first */
            int64_t f0 = yi == yi0 ? ya : yi + ry, f1 = yi + ry + 1 < yb ? yi + ry + 1 : yb;
            for (int64_t y = f0 < ya ? ya : f0; y < f1; y++) {
                uint64_t *o = out_seg(j, y, x0);
                for (size_t i = 0; i < segw; i++) o[i] = fill;
            }
            /* z levels of the input row over [xa, xb) */
            const uint64_t *src = in->words + ((size_t)yi * (size_t)nx + (size_t)xa) * wpc;
            const uint64_t *prev = src;
            int64_t prev_h = 0;
            for (int l = 0; l < j->nlev; l++) {
                uint64_t *z = scratch + (size_t)l * zstride + pad0;
                if (j->lev_h[l] == prev_h) memcpy(z, prev, nc * wpc * sizeof *z);
                else z_grow(j, z, prev, tmp, nc, wpc, j->lev_h[l] - prev_h, in->tail_mask);
                prev = z;
                prev_h = j->lev_h[l];
            }
            /* each slice k into the output rows yi - k and yi + k, from
             * the narrowest (k = ry) up: slice k is slice k + 1 with the
             * terms whose reach grows (run holds the slice) */
            for (int64_t k = ry; k >= 0; k--) {
                int64_t ylo = yi - k, yhi = yi + k;
                bool lo_in = ylo >= ya && ylo < yb, hi_in = k && yhi >= ya && yhi < yb;
                uint64_t *o1 = lo_in ? out_seg(j, ylo, x0) : hi_in ? out_seg(j, yhi, x0) : NULL;
                uint64_t *o2 = lo_in && hi_in ? out_seg(j, yhi, x0) : NULL;
                j->gather(run, k == ry, o1, o2, ptrs + j->kstart[k],
                          j->kstart[k + 1] - j->kstart[k], segw, erode);
            }
        }
    }
}

static void bands(void *ctx, int64_t begin, int64_t end)
{
    const ball_job *j = ctx;
    for (int64_t c = begin; c < end; c++) band(j, j->chunk0 + c);
}

bvox_status bvox__morph_ball(const bvox_volume *in, double radius, bool erode, bvox_volume **out)
{
    *out = NULL;
    const double *sp = in->geom.spacing;
    int rx = (int)floor(radius / sp[0]), ry = (int)floor(radius / sp[1]);
    int nterm_max = (2 * rx + 1) * (ry + 1);
    term *terms = bvox__mem_alloc((size_t)nterm_max * sizeof *terms);
    int *kstart = bvox__mem_alloc((size_t)(ry + 2) * sizeof *kstart);
    int *hs = bvox__mem_alloc((size_t)nterm_max * sizeof *hs);
    int *lev_h = NULL;
    int nlev = 0;
    bvox_status st = BVOX_OK;
    ball_job j = {.in = in, .erode = erode, .rx = rx, .ry = ry};
    if (!terms || !kstart || !hs) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    /* the slices: for each k = |dy|, the dx with a reach h >= 0 */
    int n = 0;
    double r2 = radius * radius;
    for (int k = 0; k <= ry; k++) {
        kstart[k] = n;
        for (int dx = -rx; dx <= rx; dx++) {
            double rest = r2 - (dx * sp[0]) * (dx * sp[0]) - (k * sp[1]) * (k * sp[1]);
            if (rest < 0) continue;
            double h = floor(sqrt(rest) / sp[2] + 1e-9); /* capped before the cast */
            hs[n] = h > in->nz ? in->nz : (int)h;
            terms[n++] = (term){dx, 0};
        }
    }
    kstart[ry + 1] = n;
    /* distinct reaches, increasing (each level grows from the one before) */
    lev_h = bvox__mem_alloc((size_t)n * sizeof *lev_h);
    if (!lev_h) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    for (int t = 0; t < n; t++) {
        int l = 0;
        while (l < nlev && lev_h[l] < hs[t]) l++;
        if (l < nlev && lev_h[l] == hs[t]) continue;
        memmove(lev_h + l + 1, lev_h + l, (size_t)(nlev - l) * sizeof *lev_h);
        lev_h[l] = hs[t];
        nlev++;
    }
    for (int t = 0; t < n; t++) {
        int l = 0;
        while (lev_h[l] != hs[t]) l++;
        terms[t].lev = l;
    }
    /* Slices nest: slice k + 1's offsets are slice k's with reaches no
     * larger, and a term of smaller reach is contained in (for erosion,
     * contains) the term of the same dx with larger reach. So slice k is
     * slice k + 1 OR'ed (AND'ed) with the terms of slice k that slice k + 1
     * lacks; band() builds them from k = ry down and keeps only those
     * (radius 10: 105 of 169 terms). Filtered in place, k ascending: slice
     * k's kept terms never pass slice k's own start. */
    {
        int m = 0;
        for (int k = 0; k <= ry; k++) {
            int start = m;
            for (int t = kstart[k]; t < kstart[k + 1]; t++) {
                bool shared = false;
                for (int u = kstart[k + 1]; k < ry && u < kstart[k + 2] && !shared; u++)
                    shared = terms[u].dx == terms[t].dx && terms[u].lev == terms[t].lev;
                if (!shared) terms[m++] = terms[t];
            }
            kstart[k] = start;
        }
        kstart[ry + 1] = m;
        n = m;
    }
    j.gather = bvox__ball_gather_generic;
    j.step = bvox__ball_step_generic;
#if defined(__x86_64__)
    if (bvox__simd_files(BVOX_SIMD_AVX512)) {
        j.gather = bvox__ball_gather_avx512;
        j.step = bvox__ball_step_avx512;
    } else if (bvox__simd_files(BVOX_SIMD_AVX2)) {
        j.gather = bvox__ball_gather_avx2;
        j.step = bvox__ball_step_avx2;
    }
#endif
    j.terms = terms;
    j.kstart = kstart;
    j.lev_h = lev_h;
    j.nlev = nlev;

    bvox_dims d = {in->nx, in->ny, in->nz};
    st = bvox__volume_create_uninit(d, out);
    if (st) goto done;
    (*out)->geom = in->geom;
    j.out = *out;
    /* tile width: the z levels and a spare (with the x halo) and the 2 ry + 1
     * output rows in about 512 KB (half this machine's L2 per core) */
    size_t wpc = in->wpc;
    int64_t budget = (int64_t)((64 * 1024) / wpc) - 2 * (int64_t)rx * (nlev + 1);
    int64_t tx = budget / (nlev + 2 * ry + 3);
    if (tx < 8) tx = 8;
    if (bvox__morph_ball_test_tile > 0) tx = bvox__morph_ball_test_tile;
    if (tx > in->nx) tx = in->nx;
    j.tx = tx;
    /* bands of rows; each recomputes ry input rows on either side, and a
     * small volume stays on the calling thread */
    int64_t nchunks = bvox__parallelism();
    int64_t min_rows = bvox__morph_ball_test_tile > 0 ? 1 : 2 * (int64_t)ry + 8;
    if (nchunks > in->ny / min_rows) nchunks = in->ny / min_rows;
    if ((double)in->nwords * n < 1 << 20 && bvox__morph_ball_test_tile <= 0) nchunks = 1;
    if (nchunks < 1) nchunks = 1;
    /* With a progress callback, the rows go in rounds of nchunks bands, the
     * callback (which may cancel) between rounds. Each band recomputes ry
     * rows on either side, so rounds are few enough to keep bands 16 reaches
     * high: at most an eighth more work. */
    int64_t rounds = 1;
    if (bvox__progress_active()) {
        rounds = in->ny / (nchunks * 16 * ((int64_t)ry + 1));
        if (rounds > 16) rounds = 16;
        if (rounds < 1) rounds = 1;
    }
    j.nslots = nchunks;
    j.nchunks = nchunks * rounds;
    j.chunk_words = (size_t)(nlev + 2) * (size_t)(tx + 2 * rx) * wpc; /* + tmp, run */
    size_t bytes = 0;
    j.ptrs = bvox__mem_zalloc((size_t)nchunks * (size_t)n, sizeof *j.ptrs);
    if (!j.ptrs) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
    } else if (!bvox__mul_size(j.chunk_words * sizeof(uint64_t), (size_t)nchunks, &bytes)) {
        st = bvox__fail(BVOX_ETOOBIG, "columns too long for the ball buffers");
    } else {
        j.scratch = bvox__alloc(bytes, false, "ball dilation buffers", &st);
    }
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
        goto done;
    }
    for (int64_t r = 0; r < rounds && !st; r++) {
        j.chunk0 = r * nchunks;
        bvox__parallel_for(nchunks, 1, bands, &j);
        st = bvox__progress_steps(r + 1, rounds);
    }
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    bvox__free(j.scratch, bytes);
done:
    free(terms);
    free(kstart);
    free(hs);
    free(lev_h);
    free(j.ptrs);
    return st;
}
