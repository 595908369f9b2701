/*
 * bench_render.c — speed of the display pipeline: the six axis views of an
 * n^3 sphere (target at 512^3: 5 ms), reshading a 1024x1024 pre-image after a
 * light change (new table + remap; target 1 ms), and an arbitrary parallel
 * view of the n^3 sphere into 512x512 (target 16 ms), each beside a
 * straightforward voxel-stepping caster on the same packed words (one bit
 * test per voxel, one thread) for the ratio. One JSON line per case:
 *
 *   {"case": "axis_view", "view": "+z", "n": 512, "threads": 2, "runs": 7,
 *    "ms": ..., "ms_1thread": ..., "ref_ms": ..., "speedup": ref_ms / ms,
 *    "mismatch": pixels differing from the reference}
 *
 * "surface_build" is the one-off boundary extraction of arbitrary views;
 * "arbitrary_view" times bvox_surface_cast alone (the per-frame cost when the
 * object turns), median over several directions.
 *
 *   bench_render [--quick] [--runs N] [--n 512] [--no-ref]
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    return n % 2 ? t[n / 2] : (t[n / 2 - 1] + t[n / 2]) / 2;
}

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

int main(int argc, char **argv)
{
    int n = 512, runs = 7, ref = 1, shade_side = 1024;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) n = 64, runs = 3, shade_side = 128;
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-ref")) ref = 0;
        else {
            fprintf(stderr, "usage: bench_render [--quick] [--runs N] [--n 512] [--no-ref]\n");
            return 2;
        }
    }
    if (runs < 1 || runs > 99 || n < 8 || n > 2048) return 2;
    const int threads = bvox_threads();
    double t[100];

    /* ---- axis views of an n^3 sphere ---- */
    bvox_volume *vol;
    if (bvox_volume_create((bvox_dims){n, n, n}, &vol)) die("volume");
    bvox_shape sph = {BVOX_SHAPE_SPHERE, {(n - 1) / 2.0, (n - 1) / 2.0, (n - 1) / 2.0},
                      {0, 0, 0}, {0, 0, 0}, n * 0.45, 0, 0};
    if (bvox_shape_draw(vol, &sph, BVOX_CSG_UNION)) die("sphere");
    int32_t *rdepth = malloc((size_t)n * n * sizeof *rdepth);
    for (int view = 0; view < 6; view++) {
        bvox_preimage *p = NULL;
        double ms[2];
        for (int th = 0; th < 2; th++) {
            bvox_set_threads(th ? 1 : threads);
            for (int r = -1; r < runs; r++) {
                bvox_preimage_destroy(p);
                double t0 = now_ms();
                if (bvox_cast_axis(vol, (bvox_view)view, &p)) die("cast");
                if (r >= 0) t[r] = now_ms() - t0;
            }
            ms[th] = median(t, runs);
        }
        bvox_set_threads(threads);
        printf("{\"case\": \"axis_view\", \"view\": \"%s\", \"n\": %d, \"threads\": %d, "
               "\"runs\": %d, \"ms\": %.3f, \"ms_1thread\": %.3f",
               bvox_view_name((bvox_view)view), n, threads, runs, ms[0], ms[1]);
        if (ref) {
            double t0 = now_ms();
            ref_axis(vol, (bvox_view)view, rdepth);
            double rms = now_ms() - t0;
            printf(", \"ref_ms\": %.3f, \"speedup\": %.1f, \"mismatch\": %lld", rms, rms / ms[0],
                   (long long)mismatch(p->depth, rdepth, (size_t)n * n, 0));
        }
        printf("}\n");
        fflush(stdout);
        bvox_preimage_destroy(p);
    }

    /* ---- reshading after a light change ---- */
    {
        bvox_volume *flat;
        if (bvox_volume_create((bvox_dims){shade_side, shade_side, 64}, &flat)) die("volume");
        bvox_shape e = {BVOX_SHAPE_ELLIPSOID, {(shade_side - 1) / 2.0, (shade_side - 1) / 2.0, 63},
                        {shade_side * 0.48, shade_side * 0.48, 60}, {0, 0, 0}, 0, 0, 0};
        if (bvox_shape_draw(flat, &e, BVOX_CSG_UNION)) die("ellipsoid");
        bvox_preimage *p;
        if (bvox_cast_axis(flat, BVOX_VIEW_POS_Z, &p)) die("cast");
        bvox_volume_destroy(flat);
        bvox_image *img;
        if (bvox_image_create(shade_side, shade_side, 1, 8, &img)) die("image");
        bvox_light l = BVOX_LIGHT_INIT;
        bvox_lut lut;
        double lut_t[100];
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
               shade_side, shade_side, runs, median(t, runs), median(lut_t, runs));
        fflush(stdout);
        bvox_image_destroy(img);
        bvox_preimage_destroy(p);
    }

    /* ---- arbitrary parallel view into 512x512 ---- */
    {
        bvox_surface *s = NULL;
        for (int r = -1; r < runs; r++) {
            bvox_surface_destroy(s);
            double t0 = now_ms();
            if (bvox_surface_build(vol, &s)) die("surface");
            if (r >= 0) t[r] = now_ms() - t0;
        }
        printf("{\"case\": \"surface_build\", \"n\": %d, \"threads\": %d, \"runs\": %d, "
               "\"ms\": %.3f, \"voxels\": %lld}\n",
               n, threads, runs, median(t, runs), (long long)bvox_surface_count(s));
        fflush(stdout);
        static const double dirs[][2] = {{30, 20}, {-60, 35}, {135, -15}, {10, 70}, {200, 5}};
        const int ndirs = 5, side = n < 512 ? n : 512;
        int32_t *vdepth = malloc((size_t)side * side * sizeof *vdepth);
        double per_dir[5], per_dir1[5], ref_ms = 0;
        int64_t mism = 0;
        for (int k = 0; k < ndirs; k++) {
            bvox_projection pr = BVOX_PROJECTION_INIT;
            pr.azimuth = dirs[k][0], pr.elevation = dirs[k][1], pr.width = pr.height = side;
            bvox_preimage *p = NULL;
            for (int th = 0; th < 2; th++) {
                bvox_set_threads(th ? 1 : threads);
                for (int r = -1; r < runs; r++) {
                    bvox_preimage_destroy(p);
                    double t0 = now_ms();
                    if (bvox_surface_cast(s, &pr, &p)) die("projection");
                    if (r >= 0) t[r] = now_ms() - t0;
                }
                (th ? per_dir1 : per_dir)[k] = median(t, runs);
            }
            bvox_set_threads(threads);
            if (ref) {
                double t0 = now_ms();
                ref_view(vol, p, vdepth);
                ref_ms += now_ms() - t0;
                mism += mismatch(p->depth, vdepth, (size_t)side * side, 1);
            }
            bvox_preimage_destroy(p);
        }
        double ms = median(per_dir, ndirs), ms1 = median(per_dir1, ndirs);
        printf("{\"case\": \"arbitrary_view\", \"n\": %d, \"width\": %d, \"height\": %d, "
               "\"directions\": %d, \"threads\": %d, \"runs\": %d, \"ms\": %.3f, "
               "\"ms_1thread\": %.3f",
               n, side, side, ndirs, threads, runs, ms, ms1);
        if (ref)
            printf(", \"ref_ms\": %.3f, \"speedup\": %.1f, \"mismatch\": %lld", ref_ms / ndirs,
                   ref_ms / ndirs / ms, (long long)mism);
        printf("}\n");
        free(vdepth);
        bvox_surface_destroy(s);
    }
    free(rdepth);
    bvox_volume_destroy(vol);
    return 0;
}
