/*
 * bench_contours.c — speed of the contour half of reconstruction: a stack of
 * traced sections to a model (scan conversion alone, and with shape-based
 * interpolation to isotropic voxels), the model back to contours, and the
 * JSON stack written and read back. The scan conversion is compared with the
 * per-pixel point-in-polygon reference of tests/ref (one section, scaled to
 * the stack). One JSON line per case; bench/README.md explains the keys.
 *
 *   bench_contours [--quick] [--runs N] [--sections S] [--size N] [--ratio R]
 *                  [--threads T] [--save DIR]
 * --save DIR writes DIR/stack.json and DIR/model.nii (the interpolated model)
 * for bench/compare_contours_scipy.py, which does the same with SciPy.
 * Default: 70 sections of 512 x 512 pixels, section spacing 5 pixels
 * (so the isotropic model has 350 slices).
 */
#include "internal.h"
#include "bench_util.h"
#include "ref/contourref.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* A specimen: per section an outline of 360 points (an ellipse whose radii
 * change along the stack, with a wobble) and a round hole; quarter-pixel
 * coordinates so that the reference can be exact. */
static bvox_contour_stack *make_stack(int nsec, int size, double ratio)
{
    bvox_contour_stack *s = NULL;
    if (bvox_stack_create(&s)) return NULL;
    s->pixel = 1;
    s->spacing = ratio;
    s->width = s->height = size;
    strcpy(s->unit, "um");
    bvox_point2 p[360];
    for (int k = 0; k < nsec; k++) {
        bvox_section *sec;
        if (bvox_stack_add_section(s, k * ratio, NULL, &sec)) return NULL;
        double u = (k + 0.5) / nsec, c = size / 2.0;
        double rx = size * (0.2 + 0.25 * sin(M_PI * u)), ry = size * (0.15 + 0.2 * sin(M_PI * u));
        for (int i = 0; i < 360; i++) {
            double a = 2 * M_PI * i / 360, w = 1 + 0.08 * sin(7 * a + 5 * u);
            p[i].x = round(4 * (c + rx * w * cos(a))) / 4;
            p[i].y = round(4 * (c + ry * w * sin(a))) / 4;
        }
        if (bvox_section_add_contour(sec, p, 360, 0, -1)) return NULL;
        double rh = size * 0.08 * sin(M_PI * u);
        if (rh > 2) {
            for (int i = 0; i < 90; i++) {
                double a = -2 * M_PI * i / 90;
                p[i].x = round(4 * (c + rh * cos(a))) / 4;
                p[i].y = round(4 * (c + 0.2 * size * sin(M_PI * u) * 0.3 + rh * sin(a))) / 4;
            }
            if (bvox_section_add_contour(sec, p, 90, 1, 0)) return NULL;
        }
    }
    return s;
}

/* The reference scan of one section: per pixel, exact point in polygon. */
static int64_t ref_scan(const bvox_section *sec, int size)
{
    contourref_poly polys[4];
    int64_t *buf = malloc(2 * 512 * sizeof(int64_t) * 4);
    int np = sec->ncontours < 4 ? sec->ncontours : 4;
    for (int c = 0; c < np; c++) {
        int64_t *x4 = buf + c * 1024, *y4 = x4 + 512;
        for (int i = 0; i < sec->contours[c].npoints && i < 512; i++) {
            x4[i] = (int64_t)llround(sec->contours[c].points[i].x * 4);
            y4[i] = (int64_t)llround(sec->contours[c].points[i].y * 4);
        }
        polys[c] = (contourref_poly){x4, y4, sec->contours[c].npoints};
    }
    int64_t count = 0;
    for (int j = 0; j < size; j++)
        for (int i = 0; i < size; i++) count += contourref_inside(polys, np, i, j);
    free(buf);
    return count;
}

static void usage(void)
{
    fprintf(stderr, "usage: bench_contours [--quick] [--runs N] [--sections S] [--size N] "
                    "[--ratio R] [--threads T] [--save DIR] [--threads-list 1,2,4,8,16]\n");
    exit(2);
}

static int bench_main(int argc, char **argv)
{
    int runs = 7, nsec = 70, size = 512, threads = bvox_threads();
    const char *save = NULL;
    double ratio = 5;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quick")) runs = 3, nsec = 10, size = 128;
        else if (!strcmp(a, "--runs") && v) runs = atoi(v), i++;
        else if (!strcmp(a, "--sections") && v) nsec = atoi(v), i++;
        else if (!strcmp(a, "--size") && v) size = atoi(v), i++;
        else if (!strcmp(a, "--ratio") && v) ratio = atof(v), i++;
        else if (!strcmp(a, "--threads") && v) threads = atoi(v), i++;
        else if (!strcmp(a, "--save") && v) save = v, i++;
        else usage();
    }
    if (runs < 1 || runs > 63 || nsec < 2 || size < 16 || size > 8192 || !(ratio >= 1) ||
        threads < 1)
        usage();
    bvox_set_threads(threads);
    bvox_contour_stack *s = make_stack(nsec, size, ratio);
    if (!s) {
        fprintf(stderr, "bench_contours: cannot build the stack: %s\n", bvox_errmsg());
        return 1;
    }
    bvox_volume *v = NULL;
    bvox_status st = BVOX_OK;

    /* scan conversion alone: one slice per section */
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.z_spacing = ratio;
    o.interpolate = 0;
    double scan_ms = TIME_MEDIAN(runs, (bvox_volume_destroy(v), v = NULL,
                                        st |= bvox_stack_to_volume(s, &o, &v)));
    int64_t count = st ? -1 : bvox_volume_count(v);
    int64_t ref_count = 0;
    double rs = now_ms();
    ref_count = ref_scan(&s->sections[nsec / 2], size);
    double ref_ms = (now_ms() - rs) * nsec;
    printf("{\"bench\":\"contours\",\"case\":\"scan\",\"sections\":%d,\"size\":%d,"
           "\"threads\":%d,\"runs\":%d,\"median_ms\":%.3f,\"voxels\":%lld,"
           "\"ref_point_in_polygon_ms\":%.1f,\"ref_ratio\":%.1f,\"ref_mid_section_count\":%lld}\n",
           nsec, size, threads, runs, scan_ms, (long long)count, ref_ms, ref_ms / scan_ms,
           (long long)ref_count);
    bvox_volume_destroy(v);
    v = NULL;

    /* with interpolation to isotropic voxels */
    o = bvox_stack_volume_opts_default();
    double iso_ms = TIME_MEDIAN(runs, (bvox_volume_destroy(v), v = NULL,
                                       st |= bvox_stack_to_volume(s, &o, &v)));
    bvox_dims d = st ? (bvox_dims){0, 0, 0} : bvox_volume_dims(v);
    printf("{\"bench\":\"contours\",\"case\":\"interpolate\",\"sections\":%d,\"size\":%d,"
           "\"ratio\":%g,\"threads\":%d,\"runs\":%d,\"median_ms\":%.3f,\"nz\":%d,"
           "\"voxels\":%lld,\"mvoxels_per_s\":%.1f}\n",
           nsec, size, ratio, threads, runs, iso_ms, d.nz,
           st ? -1LL : (long long)bvox_volume_count(v),
           (double)d.nx * d.ny * d.nz / (iso_ms * 1e3));
    if (!st && save) {
        char path[4096];
        snprintf(path, sizeof path, "%s/stack.json", save);
        st |= bvox_stack_write_json(path, s);
        snprintf(path, sizeof path, "%s/model.nii", save);
        st |= bvox_write(path, v, NULL);
    }

    /* the model back to contours across z, x (reslicing) */
    for (int axis = 2; axis >= 0 && !st; axis -= 2) {
        bvox_contour_stack *c = NULL;
        double mc_ms = TIME_MEDIAN(runs, (bvox_stack_destroy(c), c = NULL,
                                          st |= bvox_volume_to_contours(v, axis, &c)));
        int64_t npts = 0;
        for (int32_t i = 0; c && i < c->nsections; i++)
            for (int32_t k = 0; k < c->sections[i].ncontours; k++)
                npts += c->sections[i].contours[k].npoints;
        printf("{\"bench\":\"contours\",\"case\":\"model_to_contours\",\"axis\":\"%c\","
               "\"slices\":%d,\"threads\":%d,\"runs\":%d,\"median_ms\":%.3f,\"points\":%lld}\n",
               "xyz"[axis], c ? c->nsections : 0, threads, runs, mc_ms, (long long)npts);
        if (axis == 2 && c) {
            /* JSON out and in: the stack of 350 slices */
            char path[512];
            snprintf(path, sizeof path, "/tmp/bench_contours_%d.json", (int)getpid());
            double w_ms = TIME_MEDIAN(runs, st |= bvox_stack_write_json(path, c));
            bvox_contour_stack *r = NULL;
            double r_ms = TIME_MEDIAN(runs, (bvox_stack_destroy(r), r = NULL,
                                             st |= bvox_stack_read(path, &r)));
            FILE *f = fopen(path, "rb");
            long bytes = 0;
            if (f) {
                fseek(f, 0, SEEK_END);
                bytes = ftell(f);
                fclose(f);
            }
            remove(path);
            printf("{\"bench\":\"contours\",\"case\":\"json\",\"points\":%lld,\"bytes\":%ld,"
                   "\"runs\":%d,\"write_ms\":%.3f,\"read_ms\":%.3f,\"read_mb_per_s\":%.1f}\n",
                   (long long)npts, bytes, runs, w_ms, r_ms, bytes / (r_ms * 1e3));
            bvox_stack_destroy(r);
        }
        bvox_stack_destroy(c);
    }
    bvox_volume_destroy(v);
    bvox_stack_destroy(s);
    if (st) {
        fprintf(stderr, "bench_contours: %s\n", bvox_errmsg());
        return 1;
    }
    return 0;
}

/* --threads-list 1,2,4,8,16: every case once per count (bench_util.h) */
int main(int argc, char **argv)
{
    return run_threads_list(argc, argv, bench_main, "bench_contours");
}
