/*
 * bench_io.c — load and save speed of every file format on an n^3 specimen
 * (a hollow sphere with a handle and a cavity: long runs, as real
 * reconstructions have), in a temporary folder that is removed afterwards.
 * A format whose writer (or reader) returns an error is reported as skipped
 * with the library's message, so the benchmark runs while formats are being
 * added. One JSON line per format; bench/README.md explains every key.
 *
 *   bench_io [--quick] [--runs N] [--n 512]
 */
#define _XOPEN_SOURCE 700
#include "bvox.h"
#include "bench_util.h"
#include "common/json.h"

#include <dirent.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

typedef struct format_case {
    const char *key;    /* name in the output */
    const char *file;   /* name in the temporary folder */
    const char *format; /* forced format for write and read, or NULL: extension */
} format_case;

static const format_case cases[] = {
    {"nifti", "specimen.nii", NULL},       {"nifti.gz", "specimen.nii.gz", NULL},
    {"binvox", "specimen.binvox", NULL},   {"tiff", "specimen.tif", NULL},
    {"png", "specimen_slices", "png"},     {"raw", "specimen.raw", "raw"},
};

/* A message as a JSON string (the library's one escaping, common/json.h). */
static void print_json_string(const char *s)
{
    bvox__strbuf b = {0};
    bvox__sb_json_string(&b, s);
    fputs(b.data ? b.data : "\"\"", stdout);
    bvox__sb_free(&b);
}

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb, (void)flag, (void)ftw;
    return remove(path);
}

static void remove_tree(const char *path) { nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS); }

/* Size of a file, or the sum over a folder's files (PNG slices). */
static long long path_bytes(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0) return -1;
    if (!S_ISDIR(sb.st_mode)) return (long long)sb.st_size;
    DIR *d = opendir(path);
    if (!d) return -1;
    long long total = 0;
    char buf[8192];
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.') continue;
        snprintf(buf, sizeof buf, "%s/%s", path, e->d_name);
        if (stat(buf, &sb) == 0 && S_ISREG(sb.st_mode)) total += (long long)sb.st_size;
    }
    closedir(d);
    return total;
}

static bvox_volume *specimen(int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v) != BVOX_OK) return NULL;
    double c = (n - 1) / 2.0;
    bvox_shape body = {BVOX_SHAPE_SPHERE, {c, c, c}, {0}, {0}, 0.42 * n, 0, 0};
    bvox_shape cavity = {BVOX_SHAPE_ELLIPSOID, {c, c * 1.05, c * 0.95},
                         {0.25 * n, 0.3 * n, 0.2 * n}, {0}, 0, 0, 0};
    bvox_shape handle = {BVOX_SHAPE_TORUS, {c, c, c + 0.3 * n}, {0}, {1, 0.2, 0.1},
                         0.3 * n, 0.05 * n, 0};
    bvox_shape canal = {BVOX_SHAPE_CYLINDER, {c, c, c}, {0}, {0.3, -0.5, 1}, 0.04 * n, 0,
                        1.0 * n};
    if (bvox_shape_draw(v, &body, BVOX_CSG_UNION) || bvox_shape_draw(v, &cavity, BVOX_CSG_DIFFERENCE) ||
        bvox_shape_draw(v, &handle, BVOX_CSG_UNION) || bvox_shape_draw(v, &canal, BVOX_CSG_XOR) ||
        bvox_volume_set_spacing(v, 1.0, 1.0, 1.0, "um")) {
        bvox_volume_destroy(v);
        return NULL;
    }
    return v;
}

static void skipped(const format_case *fc, int n, const char *stage, bvox_status st)
{
    printf("{\"bench\":\"io\",\"format\":\"%s\",\"n\":%d,\"skipped\":\"%s %s\",\"error\":", fc->key,
           n, stage, bvox_status_name(st));
    print_json_string(bvox_errmsg());
    printf("}\n");
    fflush(stdout);
}

static void bench_format(const format_case *fc, const char *dir, const bvox_volume *vol, int n,
                         int runs)
{
    char path[4096 + 512];
    snprintf(path, sizeof path, "%s/%s", dir, fc->file);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.format = fc->format;
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    ro.format = fc->format;
    if (fc->format && !strcmp(fc->format, "raw")) {
        ro.raw_dims = (bvox_dims){n, n, n};
        ro.raw_dtype = BVOX_DT_U8;
    }
    double tw[64], tr[64];
    for (int r = 0; r < runs; r++) {
        double s = now_ms();
        bvox_status st = bvox_write(path, vol, &wo);
        tw[r] = now_ms() - s;
        if (st) {
            skipped(fc, n, "write", st);
            return;
        }
    }
    long long bytes = path_bytes(path);
    int same = 1;
    for (int r = 0; r < runs; r++) {
        bvox_volume *back = NULL;
        double s = now_ms();
        bvox_status st = bvox_read(path, &ro, &back);
        tr[r] = now_ms() - s;
        if (st) {
            skipped(fc, n, "read", st);
            return;
        }
        same = same && bvox_volume_equal(back, vol);
        bvox_volume_destroy(back);
    }
    double w = median(tw, runs), rd = median(tr, runs), vox = (double)n * n * n;
    printf("{\"bench\":\"io\",\"format\":\"%s\",\"n\":%d,\"runs\":%d,\"file_bytes\":%lld,"
           "\"bits_per_voxel\":%.4f,\"write_ms\":%.1f,\"read_ms\":%.1f,\"write_MBps\":%.1f,"
           "\"read_MBps\":%.1f,\"write_Mvoxps\":%.1f,\"read_Mvoxps\":%.1f,\"roundtrip\":%s,"
           "\"threads\":%d}\n",
           fc->key, n, runs, bytes, 8.0 * (double)bytes / vox, w, rd, (double)bytes / (w * 1e3),
           (double)bytes / (rd * 1e3), vox / (w * 1e3), vox / (rd * 1e3), same ? "true" : "false",
           bvox_threads());
    fflush(stdout);
    remove_tree(path); /* keep the temporary folder small */
}

static int bench_main(int argc, char **argv)
{
    int n = 512, runs = 3;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) n = 64, runs = 2;
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: bench_io [--quick] [--runs N] [--n SIZE] [--threads-list 1,2,4,8,16]\n");
            return 2;
        }
    }
    if (runs < 1 || runs > 64 || n < 8 || n > 4096) {
        fprintf(stderr, "bench_io: runs must be 1..64 and n 8..4096\n");
        return 2;
    }
    bvox_volume *vol = specimen(n);
    if (!vol) {
        fprintf(stderr, "bench_io: cannot build the %d^3 specimen: %s\n", n, bvox_errmsg());
        return 1;
    }
    const char *base = getenv("TMPDIR");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/bvox-bench-io-XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(dir)) {
        perror("bench_io: mkdtemp");
        return 1;
    }
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        bench_format(&cases[i], dir, vol, n, runs);
    remove_tree(dir);
    bvox_volume_destroy(vol);
    return 0;
}

/* --threads-list 1,2,4,8,16: every case once per count (bench_util.h) */
int main(int argc, char **argv)
{
    return run_threads_list(argc, argv, bench_main, "bench_io");
}
