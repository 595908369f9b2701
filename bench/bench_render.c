/*
 * bench_render.c — speed of the display pipeline, on the cases the display
 * issue names: the six axis views of n^3 volumes (target at 512^3: 5 ms), an
 * arbitrary parallel view of n^3 into 512x512 and 1024x1024, cast and shaded
 * (target at 512^3 into 512x512, shaded: 16 ms), and reshading a 1024x1024
 * pre-image after a light change (new table + remap; target 1 ms). Sizes
 * 256^3, 512^3 and 1024^3; two objects: "sphere" (a ball filling the volume)
 * and "aal" (the AAL atlas of mricron-data read --nonzero and resampled by
 * nearest neighbour to n^3; skipped with a note when missing). Each view is
 * compared with a straightforward voxel-stepping caster on the same packed
 * words (one bit test per voxel, one thread) for the ratio; that reference
 * stops after about 20 s per case (say so "ref_directions", "ref_skipped").
 * One JSON line per case (bench/README.md explains every key):
 *
 *   {"case": "axis_view", "pattern": "sphere", "view": "+z", "n": 512,
 *    "threads": 2, "runs": 7, "ms": ..., "ms_1thread": ..., "ref_ms": ...,
 *    "speedup": ref_ms / ms, "mismatch": pixels differing from the reference}
 *
 * "surface_build" is the one-off boundary extraction of arbitrary views;
 * "surface_rebuild" the same into the built surface, its memory reused
 * (bvox_surface_rebuild: the viewer's rebuild when a cut moves);
 * "arbitrary_view" times bvox_surface_cast ("cast_ms") and the cast plus
 * bvox_lut_light + bvox_shade_into ("ms", the per-frame cost when the object
 * turns), median over several directions. "shading" times the publishable
 * shading of one 512x512 view (smooth normals, the viewer's smooth codes,
 * ambient occlusion, shadows) beside the binary table shading.
 *
 *   bench_render [--quick] [--runs N] [--sizes 256,512,1024 | --n N] [--no-ref]
 *                [--threads-list 1,2,4,8,16] [--case NAME]
 *
 * With --threads-list, every case prints one line per count; the runs of the
 * counts (and of the one thread behind "ms_1thread") are interleaved.
 */
#include "internal.h"
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define AAL_PATH "/usr/share/mricron/templates/aal.nii.gz"
/* The reference caster stops taking on more work for a case after this. */
#define REF_BUDGET_MS 20000.0

static void die(const char *what)
{
    fprintf(stderr, "bench_render: %s: %s\n", what, bvox_errmsg());
    exit(1);
}

static inline int bit(const bvox_volume *v, int x, int y, int z)
{
    const uint64_t *c = bvox__column_c(v, x, y);
    return (int)(c[z >> 6] >> (z & 63) & 1);
}

/* ---- references: one voxel per step ---- */

static void ref_axis(const bvox_volume *v, bvox_view view, int32_t *depth)
{
    const int n[3] = {v->nx, v->ny, v->nz};
    const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
    const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
    for (int r = 0; r < n[cv]; r++)
        for (int c = 0; c < n[cu]; c++) {
            int d = -1, p[3];
            p[cu] = c, p[cv] = r;
            for (int s = 0; s < n[axis]; s++) {
                p[axis] = dir > 0 ? s : n[axis] - 1 - s;
                if (bit(v, p[0], p[1], p[2])) {
                    d = s;
                    break;
                }
            }
            depth[(size_t)r * (size_t)n[cu] + (size_t)c] = d;
        }
}

/* Amanatides-Woo traversal of each pixel's centre ray through the voxel
 * grid (cells [i - 1/2, i + 1/2] in index units), using the pre-image's
 * geometry; depth in the pre-image's units. */
static void ref_view(const bvox_volume *v, const bvox_preimage *pre, int32_t *depth)
{
    const double *sp = v->geom.spacing, *e = pre->eye;
    const int n[3] = {v->nx, v->ny, v->nz};
    double d[3];
    for (int a = 0; a < 3; a++) d[a] = e[6 + a] / sp[a]; /* index units per physical unit */
    for (int py = 0; py < pre->height; py++)
        for (int px = 0; px < pre->width; px++) {
            double o[3]; /* ray start, index units */
            for (int a = 0; a < 3; a++)
                o[a] = (pre->origin[a] + px * pre->pixel_size[0] * e[a] +
                        py * pre->pixel_size[1] * e[3 + a]) / sp[a];
            double t0 = 0, t1 = INFINITY;
            for (int a = 0; a < 3; a++) {
                double lo = -0.5 - o[a], hi = n[a] - 0.5 - o[a];
                if (fabs(d[a]) < 1e-15) {
                    if (lo > 0 || hi <= 0) t0 = INFINITY;
                    continue;
                }
                double a0 = lo / d[a], a1 = hi / d[a];
                if (a0 > a1) { double t = a0; a0 = a1; a1 = t; }
                t0 = fmax(t0, a0), t1 = fmin(t1, a1);
            }
            int32_t result = -1;
            if (t0 <= t1) {
                int cell[3], step[3];
                double tmax[3], tdelta[3];
                for (int a = 0; a < 3; a++) {
                    double p = o[a] + t0 * d[a];
                    cell[a] = (int)floor(p + 0.5);
                    if (cell[a] < 0) cell[a] = 0;
                    if (cell[a] >= n[a]) cell[a] = n[a] - 1;
                    step[a] = d[a] > 0 ? 1 : -1;
                    tdelta[a] = fabs(d[a]) < 1e-15 ? INFINITY : fabs(1.0 / d[a]);
                    double bound = cell[a] + 0.5 * step[a];
                    tmax[a] = fabs(d[a]) < 1e-15 ? INFINITY : (bound - o[a]) / d[a];
                }
                double t = t0;
                for (;;) {
                    if (bit(v, cell[0], cell[1], cell[2])) {
                        result = (int32_t)(t / pre->depth_step);
                        break;
                    }
                    int a = tmax[0] < tmax[1] ? (tmax[0] < tmax[2] ? 0 : 2) : (tmax[1] < tmax[2] ? 1 : 2);
                    t = tmax[a];
                    cell[a] += step[a];
                    if (cell[a] < 0 || cell[a] >= n[a]) break;
                    tmax[a] += tdelta[a];
                }
            }
            depth[(size_t)py * (size_t)pre->width + (size_t)px] = result;
        }
}

static int64_t mismatch(const int32_t *a, const int32_t *b, size_t n, int tol)
{
    int64_t m = 0;
    for (size_t i = 0; i < n; i++)
        m += (a[i] < 0) != (b[i] < 0) || abs(a[i] - b[i]) > tol;
    return m;
}



static bvox_volume *make_sphere(int n)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) die("volume");
    bvox_shape sph = {BVOX_SHAPE_SPHERE, {(n - 1) / 2.0, (n - 1) / 2.0, (n - 1) / 2.0},
                      {0, 0, 0}, {0, 0, 0}, n * 0.45, 0, 0};
    if (bvox_shape_draw(v, &sph, BVOX_CSG_UNION)) die("sphere");
    return v;
}

typedef struct options {
    int sizes[8], nsizes, images[2], runs, ref, shade_side;
    thread_list tl;   /* one line per count; the last column is measured at 1 */
    const char *only; /* --case: run only this case (NULL: every case) */
} options;

static int wanted(const options *o, const char *c)
{
    return !o->only || !strcmp(o->only, c);
}

/* The surface of vol built (rebuild 0: destroyed and built afresh, as the
 * one-off build is) or rebuilt into itself, its memory reused (the viewer's
 * rebuild when a cut moves): the runs of the counts interleaved. */
static void time_surfaces(const options *o, const bvox_volume *vol, bvox_surface **s,
                          int rebuild, double t[16][100], double tcpu[16][100])
{
    for (int r = -1; r < o->runs; r++)
        for (int k = 0; k < o->tl.n; k++) {
            bvox_set_threads(o->tl.t[k]);
            if (!rebuild) bvox_surface_destroy(*s), *s = NULL;
            double t0 = now_ms(), c0 = cpu_ms();
            if (rebuild ? bvox_surface_rebuild(*s, vol) : bvox_surface_build(vol, s))
                die("surface");
            if (r >= 0) t[k][r] = now_ms() - t0, tcpu[k][r] = cpu_ms() - c0;
        }
}

static void print_surfaces(const options *o, const char *name, const char *pattern, int n,
                           const bvox_surface *s, double t[16][100], double tcpu[16][100])
{
    for (int k = 0; k < o->tl.n; k++)
        printf("{\"case\": \"%s\", \"pattern\": \"%s\", \"n\": %d, \"threads\": %d, "
               "\"runs\": %d, \"ms\": %.3f, \"voxels\": %lld, \"cpu_ms\": %.3f}\n",
               name, pattern, n, o->tl.t[k], o->runs, median(t[k], o->runs),
               (long long)bvox_surface_count(s), median(tcpu[k], o->runs));
}

/* The counts of o->tl, then 1 (for "ms_1thread"): the runs of every count are
 * interleaved, run r at each count before run r + 1, so that the ratios
 * between counts survive a machine whose load changes. */
#define NCOUNTS(o) ((o)->tl.n + 1)
static int count_at(const options *o, int k)
{
    return k < o->tl.n ? o->tl.t[k] : 1;
}

static void bench_axis(const options *o, const bvox_volume *vol, const char *pattern)
{
    const int n = vol->nx, runs = o->runs;
    double t[17][100], last_ref = 0;
    int32_t *rdepth = o->ref ? malloc((size_t)n * n * sizeof *rdepth) : NULL;
    for (int view = 0; view < 6; view++) {
        bvox_preimage *p = NULL;
        double ms[17];
        for (int r = -1; r < runs; r++)
            for (int k = 0; k < NCOUNTS(o); k++) {
                bvox_set_threads(count_at(o, k));
                bvox_preimage_destroy(p);
                double t0 = now_ms();
                if (bvox_cast_axis(vol, (bvox_view)view, &p)) die("cast");
                if (r >= 0) t[k][r] = now_ms() - t0;
            }
        for (int k = 0; k < NCOUNTS(o); k++) ms[k] = median(t[k], runs);
        double ref_ms = -1;
        int64_t mism = 0;
        if (rdepth && last_ref <= REF_BUDGET_MS) {
            double t0 = now_ms();
            ref_axis(vol, (bvox_view)view, rdepth);
            ref_ms = last_ref = now_ms() - t0;
            mism = mismatch(p->depth, rdepth, (size_t)n * n, 0);
        }
        for (int k = 0; k < o->tl.n; k++) {
            printf("{\"case\": \"axis_view\", \"pattern\": \"%s\", \"view\": \"%s\", \"n\": %d, "
                   "\"threads\": %d, \"runs\": %d, \"ms\": %.3f, \"ms_1thread\": %.3f",
                   pattern, bvox_view_name((bvox_view)view), n, o->tl.t[k], runs, ms[k],
                   ms[o->tl.n]);
            if (rdepth && ref_ms < 0)
                printf(", \"ref_skipped\": \"the previous view's reference took %.0f ms\"",
                       last_ref);
            else if (rdepth)
                printf(", \"ref_ms\": %.3f, \"speedup\": %.1f, \"mismatch\": %lld", ref_ms,
                       ref_ms / ms[k], (long long)mism);
            printf("}\n");
        }
        fflush(stdout);
        bvox_preimage_destroy(p);
    }
    free(rdepth);
}

/* Arbitrary views of vol into side x side, over several directions: the
 * cast alone and the cast plus a new light table and the remap into an
 * existing image (what a frame costs when the object turns). */
static void bench_arbitrary(const options *o, const bvox_volume *vol, const bvox_surface *s,
                            const char *pattern, int side)
{
    static const double dirs[][2] = {{30, 20}, {-60, 35}, {135, -15}, {10, 70}, {200, 5}};
    enum { NDIRS = 5 };
    const int n = vol->nx, runs = o->runs;
    double t[17][100], tc[17][100], tcpu[17][100], per_dir[17][NDIRS], per_cast[17][NDIRS],
        per_cpu[17][NDIRS], ref_ms = 0;
    int32_t *vdepth = o->ref ? malloc((size_t)side * side * sizeof *vdepth) : NULL;
    int64_t mism = 0;
    int ref_dirs = 0;
    bvox_image *img;
    if (bvox_image_create(side, side, 1, 8, &img)) die("image");
    bvox_light l = BVOX_LIGHT_INIT;
    bvox_lut lut;
    for (int d = 0; d < NDIRS; d++) {
        bvox_projection pr = BVOX_PROJECTION_INIT;
        pr.azimuth = dirs[d][0], pr.elevation = dirs[d][1], pr.width = pr.height = side;
        bvox_preimage *p = NULL;
        for (int r = -1; r < runs; r++)
            for (int k = 0; k < NCOUNTS(o); k++) {
                bvox_set_threads(count_at(o, k));
                bvox_preimage_destroy(p);
                double t0 = now_ms(), c0 = cpu_ms();
                if (bvox_surface_cast(s, &pr, &p)) die("projection");
                double t1 = now_ms(), c1 = cpu_ms();
                if (bvox_lut_light(p, &l, &lut)) die("lut");
                if (bvox_shade_into(p, &lut, img)) die("shade");
                if (r >= 0) t[k][r] = now_ms() - t0, tc[k][r] = t1 - t0, tcpu[k][r] = c1 - c0;
            }
        for (int k = 0; k < NCOUNTS(o); k++) {
            per_dir[k][d] = median(t[k], runs);
            per_cast[k][d] = median(tc[k], runs);
            per_cpu[k][d] = median(tcpu[k], runs);
        }
        if (vdepth && ref_ms <= REF_BUDGET_MS) {
            double t0 = now_ms();
            ref_view(vol, p, vdepth);
            ref_ms += now_ms() - t0;
            mism += mismatch(p->depth, vdepth, (size_t)side * side, 1);
            ref_dirs++;
        }
        bvox_preimage_destroy(p);
    }
    double ms1 = median(per_dir[o->tl.n], NDIRS);
    for (int k = 0; k < o->tl.n; k++) {
        double cast = median(per_cast[k], NDIRS), shaded = median(per_dir[k], NDIRS);
        printf("{\"case\": \"arbitrary_view\", \"pattern\": \"%s\", \"n\": %d, \"image\": %d, "
               "\"width\": %d, \"height\": %d, \"directions\": %d, \"threads\": %d, "
               "\"runs\": %d, \"cast_ms\": %.3f, \"ms\": %.3f, \"ms_1thread\": %.3f, "
               "\"cast_cpu_ms\": %.3f",
               pattern, n, side, side, side, NDIRS, o->tl.t[k], runs, cast, shaded, ms1,
               median(per_cpu[k], NDIRS));
        if (ref_dirs) {
            /* The reference gives depth only: compare it with the cast alone. */
            printf(", \"ref_ms\": %.3f, \"ref_directions\": %d, \"speedup\": %.1f, "
                   "\"speedup_shaded\": %.1f, \"mismatch\": %lld",
                   ref_ms / ref_dirs, ref_dirs, ref_ms / ref_dirs / cast,
                   ref_ms / ref_dirs / shaded, (long long)mism);
            if (ref_dirs < NDIRS)
                printf(", \"ref_skipped\": \"%d of %d directions: over %.0f s\"",
                       NDIRS - ref_dirs, NDIRS, REF_BUDGET_MS / 1000);
        }
        printf("}\n");
    }
    fflush(stdout);
    bvox_image_destroy(img);
    free(vdepth);
}

static void bench_reshade(const options *o)
{
    const int side = o->shade_side, runs = o->runs;
    double t[100], lut_t[100];
    bvox_volume *flat;
    if (bvox_volume_create((bvox_dims){side, side, 64}, &flat)) die("volume");
    bvox_shape e = {BVOX_SHAPE_ELLIPSOID, {(side - 1) / 2.0, (side - 1) / 2.0, 63},
                    {side * 0.48, side * 0.48, 60}, {0, 0, 0}, 0, 0, 0};
    if (bvox_shape_draw(flat, &e, BVOX_CSG_UNION)) die("ellipsoid");
    bvox_preimage *p;
    if (bvox_cast_axis(flat, BVOX_VIEW_POS_Z, &p)) die("cast");
    bvox_volume_destroy(flat);
    bvox_image *img;
    if (bvox_image_create(side, side, 1, 8, &img)) die("image");
    bvox_light l = BVOX_LIGHT_INIT;
    bvox_lut lut;
    for (int r = -1; r < runs; r++) {
        l.azimuth += 7; /* a new light each time */
        double t0 = now_ms();
        if (bvox_lut_light(p, &l, &lut)) die("lut");
        double t1 = now_ms();
        if (bvox_shade_into(p, &lut, img)) die("shade");
        double t2 = now_ms();
        if (r >= 0) t[r] = t2 - t0, lut_t[r] = t1 - t0;
    }
    printf("{\"case\": \"reshade\", \"width\": %d, \"height\": %d, \"runs\": %d, "
           "\"ms\": %.4f, \"lut_ms\": %.4f}\n",
           side, side, runs, median(t, runs), median(lut_t, runs));
    fflush(stdout);
    bvox_image_destroy(img);
    bvox_preimage_destroy(p);
}

/* ---- issue 18: the per-frame cost of the publishable shading ----
 * One 512 x 512 (o->images[0]) projection at 30,20 of the prepared surface,
 * then, per thread count, the median of: the binary table shading (lut +
 * remap, the baseline), smooth normals for every pixel
 * (bvox_preimage_normals), the smooth shading codes the viewer uses
 * (bvox_shade_codes_volume), the same through a bvox_normal_cache warmed by
 * the view 6 degrees before (bvox_shade_codes_cached: a turning viewer's
 * frame), ambient occlusion and shadows. */
static void bench_shading(const options *o, const bvox_volume *vol, const bvox_surface *s,
                          const char *pattern, int side)
{
    bvox_projection proj = BVOX_PROJECTION_INIT;
    proj.azimuth = 30, proj.elevation = 20, proj.width = proj.height = side;
    bvox_preimage *p, *before;
    if (bvox_surface_cast(s, &proj, &p)) die("cast");
    proj.azimuth = 24;
    if (bvox_surface_cast(s, &proj, &before)) die("cast");
    bvox_normal_cache *cache;
    if (bvox_normal_cache_create(0, &cache)) die("normal cache");
    const size_t n = (size_t)side * (size_t)side;
    float *nrm = malloc(3 * n * sizeof *nrm);
    uint16_t *codes = malloc(n * sizeof *codes);
    uint8_t *f = malloc(n);
    bvox_image *img;
    if (!nrm || !codes || !f || bvox_image_create(side, side, 1, 8, &img)) die("buffers");
    bvox_light l = BVOX_LIGHT_INIT;
    bvox_shade_opts so = BVOX_SHADE_OPTS_INIT;
    so.mode = BVOX_SHADE_SMOOTH;
    enum { BIN, SMOOTH, CODES, AO, SHADOWS, CACHED, NK };
    static const char *const key[NK] = {"binary_ms", "smooth_ms", "smooth_codes_ms", "ao_ms",
                                        "shadows_ms", "smooth_codes_cached_ms"};
    double t[16][NK][100];
    long long hits = 0;
    for (size_t i = 0; i < n; i++) hits += p->depth[i] >= 0;
    for (int r = -1; r < o->runs; r++)
        for (int k = 0; k < o->tl.n; k++) {
            bvox_set_threads(o->tl.t[k]);
            double t0 = now_ms();
            bvox_lut lut;
            if (bvox_lut_light(p, &l, &lut) || bvox_shade_into(p, &lut, img)) die("shade");
            double t1 = now_ms();
            if (bvox_preimage_normals(vol, p, BVOX_SHADE_SMOOTH, 0, nrm)) die("normals");
            double t2 = now_ms();
            if (bvox_shade_codes_volume(vol, p, &so, codes)) die("codes");
            double t3 = now_ms();
            if (bvox_preimage_ao(vol, p, 0, f)) die("ao");
            double t4 = now_ms();
            if (bvox_preimage_shadows(vol, p, &l, 0, f)) die("shadows");
            double t5 = now_ms();
            bvox_normal_cache_clear(cache);
            if (bvox_shade_codes_cached(vol, before, &so, cache, codes)) die("codes");
            double t6 = now_ms();
            if (bvox_shade_codes_cached(vol, p, &so, cache, codes)) die("codes");
            double t7 = now_ms();
            if (r < 0) continue;
            t[k][CACHED][r] = t7 - t6;
            t[k][BIN][r] = t1 - t0, t[k][SMOOTH][r] = t2 - t1, t[k][CODES][r] = t3 - t2;
            t[k][AO][r] = t4 - t3, t[k][SHADOWS][r] = t5 - t4;
        }
    for (int k = 0; k < o->tl.n; k++) {
        printf("{\"case\": \"shading\", \"pattern\": \"%s\", \"n\": %d, \"image\": %d, "
               "\"hit_pixels\": %lld, \"threads\": %d, \"runs\": %d",
               pattern, vol->nx, side, hits, o->tl.t[k], o->runs);
        for (int c = 0; c < NK; c++) printf(", \"%s\": %.3f", key[c], median(t[k][c], o->runs));
        printf("}\n");
    }
    fflush(stdout);
    bvox_image_destroy(img);
    free(f);
    free(codes);
    free(nrm);
    bvox_normal_cache_destroy(cache);
    bvox_preimage_destroy(before);
    bvox_preimage_destroy(p);
}

static int parse_sizes(const char *s, options *o)
{
    o->nsizes = 0;
    for (char *end; *s && o->nsizes < 8; s = *end == ',' ? end + 1 : end) {
        long v = strtol(s, &end, 10);
        if (end == s || v < 8 || v > 2048) return 0;
        o->sizes[o->nsizes++] = (int)v;
    }
    return o->nsizes > 0 && !*s;
}

int main(int argc, char **argv)
{
    options o = {{256, 512, 1024}, 3, {512, 1024}, 7, 1, 1024, thread_list_default(), NULL};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            o.sizes[0] = 64, o.nsizes = 1, o.runs = 3, o.shade_side = 128;
            o.images[0] = 64, o.images[1] = 128;
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            o.runs = atoi(argv[++i]);
        } else if ((!strcmp(argv[i], "--n") || !strcmp(argv[i], "--sizes")) && i + 1 < argc) {
            if (!parse_sizes(argv[++i], &o)) o.runs = 0; /* reported below */
        } else if (!strcmp(argv[i], "--no-ref")) {
            o.ref = 0;
        } else if (!strcmp(argv[i], "--threads-list") && i + 1 < argc) {
            if (!thread_list_parse(argv[++i], &o.tl)) o.runs = 0;
        } else if (!strcmp(argv[i], "--case") && i + 1 < argc) {
            o.only = argv[++i];
        } else {
            o.runs = 0;
            break;
        }
    }
    if (o.runs < 1 || o.runs > 99) {
        fprintf(stderr, "usage: bench_render [--quick] [--runs N (1..99)] "
                        "[--sizes 256,512,1024 | --n N (8..2048)] [--no-ref]\n"
                        "       [--threads-list 1,2,4,8,16] "
                        "[--case reshade|axis_view|surface_build|surface_rebuild|\n"
                        "        arbitrary_view|shading]\n");
        return 2;
    }

    bvox_volume *aal = NULL;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT; /* --nonzero: every labelled region */
    if (bvox_read(AAL_PATH, &ro, &aal) != BVOX_OK) aal = NULL;

    if (wanted(&o, "reshade")) bench_reshade(&o);
    for (int si = 0; si < o.nsizes; si++) {
        const int n = o.sizes[si];
        for (int pat = 0; pat < 2; pat++) {
            const char *pattern = pat ? "aal" : "sphere";
            if (pat && !aal) {
                printf("{\"case\": \"note\", \"pattern\": \"aal\", \"n\": %d, \"skipped\": "
                       "\"" AAL_PATH " is missing or unreadable (install mricron-data)\"}\n",
                       n);
                continue;
            }
            bvox_volume *vol = pat ? resample(aal, n) : make_sphere(n);
            if (!vol) die("aal resampling");
            if (wanted(&o, "axis_view")) bench_axis(&o, vol, pattern);

            double t[16][100], tcpu[16][100];
            bvox_surface *s = NULL;
            time_surfaces(&o, vol, &s, 0, t, tcpu);
            if (wanted(&o, "surface_build"))
                print_surfaces(&o, "surface_build", pattern, n, s, t, tcpu);
            if (wanted(&o, "surface_rebuild")) {
                time_surfaces(&o, vol, &s, 1, t, tcpu);
                print_surfaces(&o, "surface_rebuild", pattern, n, s, t, tcpu);
            }
            fflush(stdout);
            for (int k = 0; wanted(&o, "arbitrary_view") && k < 2; k++)
                bench_arbitrary(&o, vol, s, pattern, o.images[k]);
            if (wanted(&o, "shading")) bench_shading(&o, vol, s, pattern, o.images[0]);
            bvox_surface_destroy(s);
            bvox_volume_destroy(vol);
        }
    }
    bvox_volume_destroy(aal);
    return 0;
}
