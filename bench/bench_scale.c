/*
 * bench_scale.c — out of core at a real size (issue 16): writes an N^3
 * OME-Zarr specimen slab by slab (never whole in memory), then runs count
 * (info), measure and 26-connected components on it by slabs under a memory
 * budget (--max-memory, default 2G), as `bvox info/measure/components` do on
 * a .zarr over the budget. One JSON line per step: seconds, voxels per
 * second, the time spent reading (chunk files, decompression and
 * binarisation) apart from the compute, and the process's peak resident
 * memory so far (getrusage).
 *
 *   bench_scale [--size N] [--max-memory SIZE] [--dir DIR] [--keep] [--quick]
 *
 * The specimen: a lattice of balls (every fourth one hollow: a cavity) joined
 * along x by bars that cross the chunk borders, so components, cavities and
 * the Euler number are all non-trivial. --quick (128^3) also checks the
 * answers against the in-memory ones.
 */
#include "bench_util.h"
#include "stream/stream.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

static double peak_rss_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* KiB on Linux */
}

/* The specimen's slices z0..z0 + slab->nz - 1 drawn into slab. */
static bvox_status draw_slab(bvox_volume *slab, int n, int z0)
{
    int step = n / 8, r = n / 20 > 2 ? n / 20 : 2;
    bvox_dims d = bvox_volume_dims(slab);
    bvox_status st = BVOX_OK;
    for (int k = 0; k < 8 && !st; k++) {
        double cz = step / 2 + k * step - z0;
        if (cz + r < 0 || cz - r >= d.nz) continue;
        for (int j = 0; j < 8 && !st; j++)
            for (int i = 0; i < 8 && !st; i++) {
                bvox_shape s = {.kind = BVOX_SHAPE_SPHERE};
                s.center[0] = step / 2 + i * step, s.center[1] = step / 2 + j * step;
                s.center[2] = cz;
                s.radius = r;
                st = bvox_shape_draw(slab, &s, BVOX_CSG_UNION);
                if (!st && (i + j + k) % 4 == 0) { /* hollow: a cavity */
                    s.radius = r / 2.0;
                    st = bvox_shape_draw(slab, &s, BVOX_CSG_DIFFERENCE);
                }
            }
    }
    /* bars along x joining the balls of even rows (one component per row) */
    for (int k = 0; k < 8; k++)
        for (int j = 0; j < 8; j += 2) {
            int y = step / 2 + j * step, z = step / 2 + k * step;
            bvox_box b = {step / 2, y - 1, z - 1 - z0, n - step / 2, y + 2, z + 2 - z0};
            bvox_volume_fill_box(slab, b, 1);
        }
    return st;
}

static bvox_status write_specimen(const char *path, int n, int chunk)
{
    bvox_dims d = {n, n, n};
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = g.spacing[1] = 0.5, g.spacing[2] = 1.0;
    strcpy(g.unit, "um");
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = wo.chunks[1] = wo.chunks[2] = chunk;
    wo.compressor = "blosc";
    bvox__slab_sink sink;
    bvox_status st = bvox__slab_sink_zarr(path, d, &g, &wo, &sink);
    if (st) return st;
    for (int z0 = 0; !st && z0 < n; z0 += chunk) {
        int t = n - z0 < chunk ? n - z0 : chunk;
        bvox_volume *slab = NULL;
        st = bvox_volume_create((bvox_dims){n, n, t}, &slab);
        if (!st) st = draw_slab(slab, n, z0);
        if (!st) st = sink.put(&sink, slab, z0);
        bvox_volume_destroy(slab);
    }
    sink.close(&sink, true, &st);
    return st;
}

/* A source that times its inner source's reads. */
typedef struct timed {
    const bvox__slab_source *inner;
    double ms;
} timed;

static bvox_status timed_read(const bvox__slab_source *s, int32_t z0, int32_t z1,
                              bvox_volume **out)
{
    timed *t = s->ctx;
    double t0 = now_ms();
    bvox_status st = t->inner->read(t->inner, z0, z1, out);
    t->ms += now_ms() - t0;
    return st;
}

static void line(const char *step, int n, double ms, double read_ms, const char *extra)
{
    double vox = (double)n * n * n;
    printf("{\"bench\": \"scale\", \"case\": \"%s\", \"n\": %d, \"voxels\": %.0f, \"threads\": %d, "
           "\"max_memory\": %zu, \"seconds\": %.3f, \"read_seconds\": %.3f, "
           "\"compute_seconds\": %.3f, \"voxels_per_second\": %.4g, \"peak_rss_mib\": %.1f%s}\n",
           step, n, vox, bvox_threads(), bvox_memory_budget(), ms / 1000, read_ms / 1000,
           (ms - read_ms) / 1000, vox / (ms / 1000), peak_rss_mib(), extra);
    fflush(stdout);
}

static int run(int argc, char **argv)
{
    int n = 1024, quick = 0, keep = 0;
    size_t budget = (size_t)2 << 30;
    const char *dir = "/tmp";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) quick = 1, n = 128, budget = (size_t)8 << 20;
        else if (!strcmp(argv[i], "--keep")) keep = 1;
        else if (!strcmp(argv[i], "--size") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--dir") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--max-memory") && i + 1 < argc) {
            char *e;
            double v = strtod(argv[++i], &e);
            size_t m = *e == 'G' ? (size_t)1 << 30 : *e == 'M' ? (size_t)1 << 20 : 1;
            budget = (size_t)(v * (double)m);
        } else {
            fprintf(stderr, "usage: bench_scale [--size N] [--max-memory SIZE] [--dir DIR] "
                            "[--keep] [--quick] [--threads-list L]\n");
            return 2;
        }
    }
    if (n < 16 || n > 65535) return fprintf(stderr, "bench_scale: --size in 16..65535\n"), 2;
    char path[4200];
    snprintf(path, sizeof path, "%s/bench_scale_%d_%d.zarr", dir, n, (int)getpid());
    bvox_set_memory_budget(budget);
    double t0 = now_ms();
    bvox_status st = write_specimen(path, n, 64);
    if (st) return fprintf(stderr, "bench_scale: %s\n", bvox_errmsg()), 1;
    line("write", n, now_ms() - t0, 0, "");

    bvox__slab_source zsrc;
    if (bvox__slab_source_zarr(path, NULL, &zsrc)) return fprintf(stderr, "%s\n", bvox_errmsg()), 1;
    timed tm = {&zsrc, 0};
    bvox__slab_source src = zsrc;
    src.read = timed_read;
    src.ctx = &tm;

    bvox_info info;
    t0 = now_ms();
    st = bvox__stream_info(&src, &info);
    char extra[256];
    snprintf(extra, sizeof extra, ", \"count\": %lld", (long long)info.count);
    if (!st) line("count", n, now_ms() - t0, tm.ms, extra);

    bvox_measures m;
    tm.ms = 0, t0 = now_ms();
    if (!st) st = bvox__stream_measure(&src, &m);
    snprintf(extra, sizeof extra, ", \"euler\": %lld, \"components\": %lld, \"cavities\": %lld",
             (long long)m.euler, (long long)m.components, (long long)m.cavities);
    if (!st) line("measure", n, now_ms() - t0, tm.ms, extra);

    int64_t nc = 0;
    tm.ms = 0, t0 = now_ms();
    bvox_component *items = NULL;
    if (!st) st = bvox__stream_components(&src, 26, &nc, &items);
    snprintf(extra, sizeof extra, ", \"component_count\": %lld, \"largest\": %lld", (long long)nc,
             (long long)(nc ? items[0].voxels : 0));
    if (!st) line("components26", n, now_ms() - t0, tm.ms, extra);
    free(items);

    if (!st && quick) { /* the answers equal the in-memory ones */
        bvox_set_memory_budget(0);
        bvox_volume *v = NULL;
        bvox_measures w;
        st = bvox_read(path, NULL, &v);
        if (!st) st = bvox_measure(v, &w);
        if (!st && (w.count != m.count || w.euler != m.euler || w.components != nc ||
                    w.cavities != m.cavities || w.area != m.area)) {
            fprintf(stderr, "bench_scale: streamed answers differ from the in-memory ones\n");
            st = BVOX_EINVAL;
        }
        bvox_volume_destroy(v);
    }
    bvox__slab_source_close(&zsrc);
    if (!keep) {
        char cmd[4300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
        if (system(cmd) != 0) fprintf(stderr, "bench_scale: could not remove %s\n", path);
    }
    if (st) return fprintf(stderr, "bench_scale: %s\n", bvox_errmsg()), 1;
    return 0;
}

int main(int argc, char **argv) { return run_threads_list(argc, argv, run, "bench_scale"); }
