/*
 * demo_run.c — bvox_demo_run: the paper's system end to end on the built-in
 * specimen (include/bvox/recon.h says what it does and writes).
 *
 * The grids are chosen so that the reconstruction lands exactly on the
 * specimen's voxels and is compared voxel for voxel, without resampling:
 * the images' pixels are the specimen's 10 um (with a margin), and with
 * n = 65 sections dz = 40 um apart reconstructed at 25 um slices,
 * bvox_stack_to_volume puts slice j at z_first - dz / 2 + (n dz - nz 25) / 2
 * + 12.5 + 25 j = z_first - 7.5 + 25 j, a specimen slice centre when
 * z_first = 507.5 um (slice j is specimen slice 20 + j). The offset is computed from the model's geometry below and
 * checked to be whole.
 */
#include "demo/demo.h"
#include "io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Sections through the tissue only, as a histologist keeps them (the
 * specimen spans z 487.5 .. 3087.5 um): an empty section would have Otsu
 * split its noise (so the threshold is fixed below). The first is 20 um
 * above the body's bottom (where the bored hole is wider than the body: it
 * shows only the markers), the last 20 um below the cap's tip (a few pixels:
 * min_area is lowered for it). */
#define DEMO_SECTIONS 65
#define DEMO_DZ 40.0      /* um between sections */
#define DEMO_Z0 507.5     /* um: the first section's height in the specimen */
#define DEMO_SEED 0x5eed2026u
#define DEMO_FRAMES 36    /* turntable */

bvox_demo_opts bvox_demo_opts_default(void)
{
    return (bvox_demo_opts){NULL, 0};
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

/* The sections, over the worker threads (each is independent). */
typedef struct sections_job {
    const bvox__demo_cut *cut;
    bvox_image **img;
    bvox_status *st;
} sections_job;

static void sections_range(void *ctx, int64_t b, int64_t e)
{
    sections_job *j = ctx;
    for (int64_t k = b; k < e; k++) j->st[k] = bvox__demo_section(j->cut, (int32_t)k, &j->img[k]);
}

/* The reconstruction moved onto the specimen's grid: model slice j is
 * specimen slice j + dz_slices, image pixel u specimen voxel u - margin. */
static bvox_status on_specimen_grid(const bvox_volume *model, const bvox_volume *specimen,
                                    bvox_volume **out)
{
    *out = NULL;
    const bvox_geometry *g = bvox_volume_geometry(model);
    double k = (g->origin[2] + DEMO_Z0) / DEMO_SZ;
    if (fabs(k - round(k)) > 1e-6 || fabs(g->spacing[2] - DEMO_SZ) > 1e-9)
        return bvox__fail(BVOX_EINVAL, "demo: the model's slices (at %g um, %g um apart) are not "
                                       "the specimen's", g->origin[2] + DEMO_Z0, g->spacing[2]);
    bvox_status st = bvox_volume_create(bvox_volume_dims(specimen), out);
    if (!st) st = bvox_volume_set_geometry(*out, bvox_volume_geometry(specimen));
    const int32_t off[3] = {-DEMO_MARGIN, -DEMO_MARGIN, (int32_t)round(k)};
    if (!st) st = bvox_csg_apply(*out, BVOX_CSG_UNION, model, off);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

/* "tmp/name" into buf; the names are short, the folder bounded by PATH_MAX. */
static bvox_status path_in(char *buf, size_t size, const char *dir, const char *name)
{
    if ((size_t)snprintf(buf, size, "%s/%s", dir, name) >= size)
        return bvox__fail(BVOX_EINVAL, "%s: the path is too long", dir);
    return BVOX_OK;
}

static bvox_status write_all(const bvox_demo_opts *o, const bvox_volume *specimen,
                             const bvox_volume *model, bvox_image *const *img, int32_t n)
{
    bvox__dir_sink ds;
    bvox_status st = bvox__dir_sink_open(o->dir, BVOX__DIR_DEMO, o->force != 0, &ds);
    if (st) return st;
    size_t size = strlen(ds.tmp) + 32;
    char *path = bvox__mem_alloc(size);
    if (!path) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    if (!st) st = path_in(path, size, ds.tmp, "specimen.nii.gz");
    if (!st) st = bvox_write(path, specimen, NULL);
    if (!st) st = path_in(path, size, ds.tmp, "specimen.tif");
    if (!st) st = bvox_write(path, specimen, NULL);
    if (!st) st = path_in(path, size, ds.tmp, "model.nii.gz");
    if (!st) st = bvox_write(path, model, NULL);
    for (int32_t k = 0; k < n && !st; k++) {
        char name[32];
        snprintf(name, sizeof name, "section_%04d.png", (int)k);
        st = path_in(path, size, ds.tmp, name);
        if (!st) st = bvox_image_write_png(img[k], path);
    }
    /* the paper's pictures of what it reconstructed */
    if (!st) st = bvox_demo_pictures(model, ds.tmp);
    if (!st) st = path_in(path, size, ds.tmp, "turntable.gif");
    if (!st) {
        bvox_render_opts ro = bvox_render_opts_default();
        st = bvox_render_parse_view("iso", &ro);
        ro.proj.width = ro.proj.height = 256;
        if (!st) st = bvox_render_turntable(model, &ro, DEMO_FRAMES, path);
    }
    free(path);
    if (st) {
        bvox__dir_sink_abort(&ds);
        return st;
    }
    return bvox__dir_sink_commit(&ds);
}

bvox_status bvox_demo_run(const bvox_demo_opts *opts, bvox_demo_report *report)
{
    bvox__clear_error();
    if (!report) return bvox__fail(BVOX_EINVAL, "demo: no report");
    memset(report, 0, sizeof *report);
    bvox_demo_opts o = opts ? *opts : bvox_demo_opts_default();
    if (o.dir && !*o.dir) return bvox__fail(BVOX_EINVAL, "demo: an empty folder name");
    const int32_t n = DEMO_SECTIONS;
    bvox_volume *specimen = NULL, *recon = NULL, *model = NULL;
    bvox_recon_report *rr = NULL;
    bvox__demo_cut cut = {0};
    bvox_image **img = bvox__mem_zalloc((size_t)n, sizeof *img);
    bvox_status *sst = bvox__mem_zalloc((size_t)n, sizeof *sst);
    bvox_status st = img && sst ? BVOX_OK : bvox__fail(BVOX_ENOMEM, "out of memory");

    double t0 = now_ms();
    if (!st) st = bvox_demo_specimen(&specimen);
    if (!st) st = bvox__demo_cut_init(&cut, n, DEMO_Z0, DEMO_DZ, DEMO_SEED);
    if (!st) {
        sections_job job = {&cut, img, sst};
        bvox__parallel_for(n, 1, sections_range, &job);
        /* a worker's message is its thread's: make the first failed
         * section again here for it (the same inputs fail the same way) */
        for (int32_t k = 0; k < n && !st; k++)
            if (sst[k]) {
                bvox_image *again = NULL;
                st = bvox__demo_section(&cut, k, &again);
                bvox_image_destroy(again);
                if (!st) st = bvox__fail(sst[k], "demo: section %d could not be made", (int)k);
            }
    }
    double t1 = now_ms();
    if (!st) {
        bvox_recon_opts ro = bvox_recon_opts_default();
        ro.markers.count = 3;
        ro.min_area = 4;
        /* After the flat field the background is ~170 and the tissue ~80
         * (+-30 with texture and noise). Otsu per section would split the
         * noise of the end sections, whose tissue is a few pixels. */
        ro.threshold = 125;
        ro.pixel = DEMO_SXY;
        ro.spacing = DEMO_DZ;
        ro.z_spacing = DEMO_SZ;
        snprintf(ro.unit, sizeof ro.unit, "um");
        st = bvox_reconstruct_images((const bvox_image *const *)img, NULL, n, &ro, &recon, NULL, &rr);
    }
    double t2 = now_ms();
    if (!st) st = on_specimen_grid(recon, specimen, &model);
    if (!st) {
        int64_t a = bvox_volume_count(specimen), b = bvox_volume_count(model);
        int64_t both = bvox_volume_count_and(specimen, model);
        report->sections = n;
        report->width = report->height = DEMO_SIZE;
        report->pixel = DEMO_SXY;
        report->section_spacing = DEMO_DZ;
        report->markers = 3;
        report->fallbacks = rr->fallbacks;
        report->specimen_voxels = a;
        /* the whole reconstruction (voxels the grid would clip count too) */
        report->model_voxels = bvox_volume_count(recon);
        report->dice = a + b ? 2.0 * (double)both / (double)(a + b) : 0;
        report->volume_error_percent =
            a ? 100.0 * (double)(report->model_voxels - a) / (double)a : 0;
    }
    double t3 = now_ms();
    if (!st && o.dir) st = write_all(&o, specimen, model, img, n);
    double t4 = now_ms();
    report->ms_sections = t1 - t0;
    report->ms_reconstruct = t2 - t1;
    report->ms_compare = t3 - t2;
    report->ms_write = o.dir ? t4 - t3 : 0;

    for (int32_t k = 0; img && k < n; k++) bvox_image_destroy(img[k]);
    free(img);
    free(sst);
    bvox__demo_cut_free(&cut);
    bvox_recon_report_destroy(rr);
    bvox_volume_destroy(recon);
    bvox_volume_destroy(model);
    bvox_volume_destroy(specimen);
    if (st) memset(report, 0, sizeof *report);
    return st;
}
