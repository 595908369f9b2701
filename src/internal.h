/*
 * internal.h — private layout of bvox_volume and the bvox__ helpers shared by
 * the files of src/. Not installed; outside users see only include/bvox.h.
 *
 * Packing (as the paper packs 8 slices per frame-buffer byte, but 64 per word):
 * the voxels of one column (x, y) along z are bits of consecutive uint64_t
 * words; voxel (x, y, z) is bit (z & 63) of words[col(x, y) * wpc + (z >> 6)]
 * with col(x, y) = y * nx + x and wpc = ceil(nz / 64). The bits of the last
 * word of each column beyond nz are ALWAYS zero: counts are plain popcounts
 * and complements must mask them (tail_mask). bvox_volume_check verifies it.
 */
#ifndef BVOX_INTERNAL_H
#define BVOX_INTERNAL_H

#include "bvox.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct bvox_volume {
    int32_t nx, ny, nz;
    size_t wpc;          /* words per column = ceil(nz / 64) */
    size_t nwords;       /* nx * ny * wpc */
    uint64_t tail_mask;  /* valid bits of the last word of a column */
    uint64_t *words;     /* from bvox__alloc, 64-byte aligned */
    bvox_geometry geom;
};

/* ---- status.c: error reporting ---- */
/* Format the thread-local message and return status (for `return bvox__fail(...)`). */
bvox_status bvox__fail(bvox_status status, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Clear the message (at the start of public calls that may succeed). */
void bvox__clear_error(void);
/* Raise one warning (see bvox_set_warning_handler): formatted, passed to the
 * calling thread's handler if any. */
void bvox__warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Prefix the current message with "prefix: " (adds a file name to a codec error). */
void bvox__error_prefix(const char *prefix);

/* ---- alloc.c: the one allocation seam (both kinds: see core/alloc.h) ---- */
#include "core/alloc.h"
#include "core/check.h" /* BVOX_ASSERT, BVOX_CHECK_VOLUME...: debug-build invariants */
/* Count bytes held outside bvox__alloc (growing arrays, such as contour
 * stacks and text buffers) against the budget: false (status BVOX_ETOOBIG,
 * message naming what) when they would exceed it. Every charge is refunded
 * once, when the memory is freed. */
bool bvox__budget_charge(size_t bytes, const char *what, bvox_status *status);
void bvox__budget_refund(size_t bytes);
/* A byte count for messages: "812 bytes", "2.4 MiB", "11.8 GiB". */
void bvox__format_bytes(char *buf, size_t len, size_t bytes);
/* Overflow-safe a*b; returns false on overflow. */
static inline bool bvox__mul_size(size_t a, size_t b, size_t *out)
{
    return !__builtin_mul_overflow(a, b, out);
}

/* ---- volume.c ---- */
/* Validate dimensions and compute the word-array size; BVOX_EINVAL for a
 * dimension outside 1..BVOX_MAX_DIM, BVOX_ETOOBIG over the budget. what names
 * the source for the message (a file name, or NULL). */
bvox_status bvox__check_dims(bvox_dims dims, const char *what, size_t *bytes);
/* Create without zero-filling the words (caller writes every word). */
bvox_status bvox__volume_create_uninit(bvox_dims dims, bvox_volume **out);

static inline uint64_t *bvox__column(bvox_volume *v, int32_t x, int32_t y)
{
    return v->words + ((size_t)y * (size_t)v->nx + (size_t)x) * v->wpc;
}
static inline const uint64_t *bvox__column_c(const bvox_volume *v, int32_t x, int32_t y)
{
    return v->words + ((size_t)y * (size_t)v->nx + (size_t)x) * v->wpc;
}
/* Mask of bits [lo, hi) within one word, 0 <= lo <= hi <= 64. */
static inline uint64_t bvox__bit_range(unsigned lo, unsigned hi)
{
    uint64_t upper = hi >= 64 ? ~0ull : ((1ull << hi) - 1);
    uint64_t lower = lo >= 64 ? ~0ull : ((1ull << lo) - 1);
    return upper & ~lower;
}
/* The 64 bits of a column starting at bit `start` (which may be negative or
 * beyond the end: missing bits read as 0). Used to shift columns along z. */
static inline uint64_t bvox__extract_bits(const uint64_t *col, size_t nwords, int64_t start)
{
    int64_t w = start >> 6; /* arithmetic shift: floor division */
    unsigned s = (unsigned)(start & 63);
    uint64_t lo = (w >= 0 && (size_t)w < nwords) ? col[w] : 0;
    if (s == 0) return lo;
    uint64_t hi = (w + 1 >= 0 && (size_t)(w + 1) < nwords) ? col[w + 1] : 0;
    return (lo >> s) | (hi << (64 - s));
}
/* volume_box.c: move g's origin by a voxel offset (di, dj, dk) along its
 * axes so that voxels keep their world position (crops, pads). */
void bvox__geometry_shift(bvox_geometry *g, double di, double dj, double dk);
/* Set (value) or clear bits z0..z1-1 of one column. */
void bvox__column_fill(uint64_t *col, int32_t z0, int32_t z1, int value);

/* ---- volume_box.c ---- */
/* b clipped to the volume (each bound into 0..n; it may come out empty). */
bvox_box bvox__box_clip(const bvox_volume *v, bvox_box b);

/* ---- components.c: the count alone (no statistics, no copy of the words) ----
 * The number of conn-components of vol's 1-voxels; with merge_border, those
 * touching the volume's border are not counted (for the background of a
 * volume: its cavities). */
bvox_status bvox__components_count(const bvox_volume *vol, int conn, int merge_border,
                                   int64_t *count);

/* ---- parallel.c: split a range over the worker threads ---- */
/* Calls fn(ctx, begin, end) on disjoint chunks covering [0, n): T chunks
 * [n t / T, n (t + 1) / T), T = bvox__parallelism() capped at
 * n / min_per_thread. Runs inline when T <= 1. fn must not fail. */
typedef void (*bvox__range_fn)(void *ctx, int64_t begin, int64_t end);
void bvox__parallel_for(int64_t n, int64_t min_per_thread, bvox__range_fn fn, void *ctx);
/* The most worker threads bvox_threads() ever reports: per-thread arrays
 * may be sized by it. */
#define BVOX__MAX_THREADS 64
/* ---- parallel_dynamic.c: the same, dynamically scheduled ----
 * Calls fn(ctx, b, min(b + grain, n)) for b = 0, grain, 2 grain, ... < n, one
 * task per thread taking the next block until none is left, so that a thread
 * slowed down (uneven work, a busy core) takes fewer blocks. Inline when one
 * thread is configured or n <= grain. fn must not fail; results must not
 * depend on which thread runs a block. */
void bvox__parallel_for_dynamic(int64_t n, int64_t grain, bvox__range_fn fn, void *ctx);
/* How many threads can run at once: bvox_threads(), at most the CPUs the
 * process may use (BVOX_CPUS overrides those; the tests set it high).
 * bvox__parallel_for splits into at most this many chunks; kernels that size
 * their own split or per-thread scratch use it instead of bvox_threads(). */
int bvox__parallelism(void);

/* ---- progress.c: the progress callback's checks (bvox_set_progress) ----
 * A public entry that reports brackets its work:
 *     bvox__progress_scope ps;
 *     bvox__progress_begin(&ps, "mesh");
 *     ... st = bvox__progress(fraction) at safe points (0..1 of this call) ...
 *     return bvox__progress_end(&ps, st);
 * bvox__progress returns BVOX_ECANCELED (message set) when the callback asked
 * to stop; the caller then cleans up like for any failure. bvox__progress_sub
 * narrows the range to [lo, hi] of the current one (for a nested call or a
 * stage) until bvox__progress_restore. Cheap without a callback. */
typedef struct bvox__progress_scope {
    double base, span;
    const char *stage;
} bvox__progress_scope;
void bvox__progress_begin(bvox__progress_scope *saved, const char *stage);
bvox_status bvox__progress_end(const bvox__progress_scope *saved, bvox_status st);
void bvox__progress_sub(bvox__progress_scope *saved, double lo, double hi, const char *stage);
void bvox__progress_restore(const bvox__progress_scope *saved);
bvox_status bvox__progress(double fraction);
/* done of total steps; does nothing measurable without a callback. */
bvox_status bvox__progress_steps(int64_t done, int64_t total);
int bvox__progress_active(void);
/* Work split into bands run one after the other, with a progress check
 * between them (for Ctrl-C): without a callback one band; with one, bands of
 * about a quarter of a second of work each, timed from the first band (which
 * is 1/nfixed of the work), so that a callback costs nothing measurable; with
 * a progress interval of 0 (every check reported, what the tests ask for) the
 * nfixed equal bands, always the same. Use:
 *     bvox__bands b;
 *     bvox__bands_begin(&b, total, 16);
 *     for (int64_t lo = 0, hi; lo < total && !st; lo = hi) {
 *         hi = bvox__bands_next(&b, lo);
 *         ... [lo, hi) ...; st = bvox__progress_steps(hi, total);
 *     } */
typedef struct bvox__bands {
    int64_t total, nfixed, i, t0_ns;
} bvox__bands;
void bvox__bands_begin(bvox__bands *b, int64_t total, int64_t nfixed);
int64_t bvox__bands_next(bvox__bands *b, int64_t lo);
/* bvox__parallel_for that, with a callback set, runs [0, n) in bands (as
 * bvox__bands, 32 of them with interval 0) one after the other and reports
 * after each (fraction 0..1 of the current range).
 * fn must be a pure function of its range. BVOX_ECANCELED when canceled: the
 * output is then partly computed and must be discarded. */
bvox_status bvox__parallel_for_progress(int64_t n, int64_t min_per_thread, bvox__range_fn fn,
                                        void *ctx);

/* ---- simd/dispatch.c: word kernels chosen at run time ---- */
typedef struct bvox__kernels {
    uint64_t (*popcount)(const uint64_t *w, size_t n);
    uint64_t (*popcount_and)(const uint64_t *a, const uint64_t *b, size_t n);
    /* dst[i] = dst[i] OP src[i] for the four csg ops (not REPLACE) */
    void (*op_or)(uint64_t *dst, const uint64_t *src, size_t n);
    void (*op_and)(uint64_t *dst, const uint64_t *src, size_t n);
    void (*op_andnot)(uint64_t *dst, const uint64_t *src, size_t n);
    void (*op_xor)(uint64_t *dst, const uint64_t *src, size_t n);
    void (*op_not)(uint64_t *dst, size_t n);
} bvox__kernels;
const bvox__kernels *bvox__simd(void);
/* Whether the active level is at least level (AVX2 or AVX-512) and the CPU
 * has every feature the build gives that level's src/DIR/NAME_LEVEL.c
 * files, so that their kernels may run. */
bool bvox__simd_files(bvox_simd level);
extern const bvox__kernels bvox__kernels_generic;
extern const bvox__kernels bvox__kernels_avx2;
extern const bvox__kernels bvox__kernels_avx512;

/* Popcount of one word, portable (no POPCNT needed). */
static inline unsigned bvox__popcount64(uint64_t x)
{
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
    return (unsigned)((x * 0x0101010101010101ull) >> 56);
}

#endif /* BVOX_INTERNAL_H */
