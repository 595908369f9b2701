/*
 * bench_recon.c — speed of the reconstruction from serial sections: 70
 * synthetic sections of 512 x 512 (the test specimen of
 * tests/unit/specimen_sections.h: noisy, textured, unevenly lit, 3 markers,
 * each section moved by a random rigid transform; generated here, not
 * timed) to a model with isotropic voxels (sections 4 pixels apart, so
 * the interpolation makes 280 slices), all steps: background estimate and
 * flat-field correction, Otsu, median, markers, specks, contours,
 * alignment, scan conversion and shape-based interpolation. One JSON line
 * per case with the median of the runs for every step (bvox_recon_report:
 * wall-clock shares of the parallel per-section phase) and the total; the
 * same with one thread (the speed-up of bvox__parallel_for over sections),
 * and the median filter against the brute-force window count on one
 * section (the word-wise running sums' speed-up). The Dice coefficient
 * against the truth shows that the timed run does the real work.
 *
 *   bench_recon [--quick] [--runs N] [--threads T] [--sections N] [--size S] [--save DIR]
 *
 * --save DIR writes the sections as DIR/s1.png ... for
 * bench/compare_recon_skimage.py (the same steps in scikit-image / SciPy).
 */
#include "internal.h"
#include "bench_util.h"
#include "unit/specimen_sections.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Median of runs of the whole pipeline; per-step medians into ms. */
static int run_pipeline(bvox_image **imgs, int n, double spacing, int runs, double ms[BVOX_RECON_NSTEPS],
                        double *dice, int64_t *pixels, const specimen *sp)
{
    double t[BVOX_RECON_NSTEPS][32];
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    o.spacing = spacing;
    if (runs > 32) runs = 32;
    for (int r = -1; r < runs; r++) { /* one warm-up */
        bvox_volume *vol = NULL;
        bvox_recon_report *rep = NULL;
        if (bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, n, &o, &vol, NULL, &rep)) {
            fprintf(stderr, "bench_recon: %s\n", bvox_errmsg());
            return -1;
        }
        if (r >= 0)
            for (int s = 0; s < BVOX_RECON_NSTEPS; s++) t[s][r] = rep->ms[s];
        if (r == runs - 1 && pixels) {
            *pixels = 0;
            for (int k = 0; k < n; k++) *pixels += rep->sections[k].area;
        }
        if (r == runs - 1 && dice) {
            bvox_volume *truth = NULL;
            if (spec_truth(sp, vol, &truth)) return -1;
            *dice = spec_dice(vol, truth);
            bvox_volume_destroy(truth);
        }
        bvox_recon_report_destroy(rep);
        bvox_volume_destroy(vol);
    }
    for (int s = 0; s < BVOX_RECON_NSTEPS; s++) ms[s] = median(t[s], runs);
    return 0;
}

static void print_case(const char *name, int n, int size, double spacing, int threads, int runs,
                       const double ms[BVOX_RECON_NSTEPS], double dice, int64_t pixels,
                       const bvox_dims *d)
{
    printf("{\"bench\":\"recon\",\"case\":\"%s\",\"sections\":%d,\"size\":%d,\"spacing_px\":%g,"
           "\"threads\":%d,\"runs\":%d,\"dims\":[%d,%d,%d]",
           name, n, size, spacing, threads, runs, d->nx, d->ny, d->nz);
    for (int s = 0; s < BVOX_RECON_NSTEPS; s++)
        printf(",\"%s_ms\":%.2f", bvox_recon_step_name((bvox_recon_step)s), ms[s]);
    double sections_ms = 0;
    for (int s = 0; s <= BVOX_RECON_CONTOURS; s++) sections_ms += ms[s];
    printf(",\"sections_ms\":%.2f", sections_ms);
    if (pixels >= 0) printf(",\"object_pixels\":%lld", (long long)pixels);
    if (dice >= 0) printf(",\"dice\":%.4f", dice);
    printf("}\n");
    fflush(stdout);
}

/* The brute-force median: every pixel counts its window. */
static void median_ref(const bvox_bitmap *in, int r, bvox_bitmap *out)
{
    for (int32_t y = 0; y < in->height; y++)
        for (int32_t x = 0; x < in->width; x++) {
            int cnt = 0, valid = 0;
            for (int32_t yy = y - r; yy <= y + r; yy++)
                for (int32_t xx = x - r; xx <= x + r; xx++) {
                    if (xx < 0 || yy < 0 || xx >= in->width || yy >= in->height) continue;
                    valid++;
                    cnt += (int)((in->words[(size_t)yy * in->words_per_row + (size_t)(xx >> 6)] >> (xx & 63)) & 1);
                }
            bvox_bitmap_set(out, x, y, 2 * cnt > valid);
        }
}

static int bench_main(int argc, char **argv)
{
    int quick = 0, runs = 5, threads = 0, n = 70, size = 512;
    const char *save = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) quick = 1;
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--sections") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc) size = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--save") && i + 1 < argc) save = argv[++i];
        else {
            fprintf(stderr, "usage: bench_recon [--quick] [--runs N] [--threads T] [--sections N] "
                            "[--size S] [--save DIR] [--threads-list 1,2,4,8,16]\n");
            return 2;
        }
    }
    if (quick) {
        n = 16;
        size = 128;
        runs = 1;
    }
    if (runs < 1) runs = 1;
    if (threads > 0) bvox_set_threads(threads);
    threads = bvox_threads();
    double spacing = 4.0 * size / 512;
    if (spacing < 1) spacing = 1;
    specimen sp;
    if (spec_init(&sp, size, n, spacing, 2026)) return 1;
    bvox_image **imgs = calloc((size_t)n, sizeof *imgs);
    if (!imgs) return 1;
    for (int k = 0; k < n; k++)
        if (spec_render(&sp, k, k == n / 4 ? 1 : -1, k == 3 * n / 4, &imgs[k])) {
            fprintf(stderr, "bench_recon: %s\n", bvox_errmsg());
            return 1;
        }
    if (save)
        for (int k = 0; k < n; k++) {
            char path[4096];
            snprintf(path, sizeof path, "%s/s%d.png", save, k + 1);
            if (bvox_image_write_png(imgs[k], path)) {
                fprintf(stderr, "bench_recon: %s\n", bvox_errmsg());
                return 1;
            }
        }
    double ms[BVOX_RECON_NSTEPS], dice = -1;
    int64_t pixels = -1;
    bvox_volume *probe = NULL;
    {
        bvox_recon_opts o = bvox_recon_opts_default();
        o.spacing = spacing;
        o.markers.count = 3;
        if (bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, n, &o, &probe, NULL, NULL))
            return 1;
    }
    bvox_dims d = bvox_volume_dims(probe);
    bvox_volume_destroy(probe);
    if (run_pipeline(imgs, n, spacing, runs, ms, &dice, &pixels, &sp)) return 1;
    print_case("pipeline", n, size, spacing, threads, runs, ms, dice, pixels, &d);
    if (threads > 1) {
        bvox_set_threads(1);
        if (run_pipeline(imgs, n, spacing, quick ? 1 : 3, ms, NULL, NULL, &sp)) return 1;
        print_case("pipeline_1thread", n, size, spacing, 1, quick ? 1 : 3, ms, -1, -1, &d);
        bvox_set_threads(threads);
    }
    /* the median filter on one section's mask: running sums vs brute force */
    bvox_bitmap *mask = NULL, *fast = NULL, *ref = NULL;
    double t;
    if (bvox_section_otsu(imgs[0], &t) || bvox_section_threshold(imgs[0], t, 1, &mask) ||
        bvox_bitmap_create(size, size, &ref))
        return 1;
    double tf[16], tr[4];
    int rf = quick ? 1 : 9, rr = quick ? 1 : 3;
    for (int r = 0; r < rf; r++) {
        double s = now_ms();
        if (bvox_bitmap_median(mask, 2, &fast)) return 1;
        tf[r] = now_ms() - s;
        if (r < rf - 1) bvox_bitmap_destroy(fast);
    }
    for (int r = 0; r < rr; r++) {
        double s = now_ms();
        median_ref(mask, 2, ref);
        tr[r] = now_ms() - s;
    }
    int same = !memcmp(fast->words, ref->words, (size_t)size * (size_t)fast->words_per_row * 8);
    double mf = median(tf, rf), mr = median(tr, rr);
    printf("{\"bench\":\"recon\",\"case\":\"median_r2\",\"size\":%d,\"fast_ms\":%.3f,\"ref_ms\":%.3f,"
           "\"speedup\":%.1f,\"same\":%s}\n",
           size, mf, mr, mr / mf, same ? "true" : "false");
    bvox_bitmap_destroy(mask);
    bvox_bitmap_destroy(fast);
    bvox_bitmap_destroy(ref);
    for (int k = 0; k < n; k++) bvox_image_destroy(imgs[k]);
    free(imgs);
    spec_free(&sp);
    return same ? 0 : 1;
}

/* --threads-list 1,2,4,8,16: every case once per count (bench_util.h) */
int main(int argc, char **argv)
{
    return run_threads_list(argc, argv, bench_main, "bench_recon");
}
