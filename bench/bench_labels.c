/*
 * bench_labels.c — the AAL atlas (181 x 217 x 181, 116 labels) through what
 * `bvox labels` does: read and split in one pass (bvox_labels_read), then
 * every label measured on its crop (bvox_labelset_measure). One JSON line
 * per case with the median of the runs; the target is the whole
 * table in under 1 s on 2 cores (--threads 2, or --threads-list 1,2).
 *   bench_labels [--quick] [--runs N] [--threads T | --threads-list L] [--file PATH]
 */
#include "bench_util.h"

#include <stdio.h>

static int measure_all(const bvox_labelset *set)
{
    for (int64_t i = 0; i < set->n; i++) {
        bvox_measures m;
        if (bvox_labelset_measure(set, i, &m)) return 1;
    }
    return 0;
}

static int bench_main(int argc, char **argv)
{
    const char *path = "/usr/share/mricron/templates/aal.nii.gz";
    int runs = 9, threads = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) runs = 2;
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--file") && i + 1 < argc) path = argv[++i];
        else {
            fprintf(stderr, "usage: bench_labels [--quick] [--runs N] [--threads T] [--file P]\n");
            return 2;
        }
    }
    if (runs < 1 || runs > 64 || threads < 0) {
        fprintf(stderr, "bench_labels: runs must be 1..64, threads >= 1\n");
        return 2;
    }
    if (threads) bvox_set_threads(threads);
    threads = bvox_threads();
    bvox_labelset *set = NULL;
    if (bvox_labels_read(path, NULL, 0, &set)) {
        printf("{\"bench\":\"labels\",\"threads\":%d,\"skipped\":\"%s unreadable "
               "(install mricron-data)\"}\n",
               threads, path);
        return 0;
    }
    int64_t n = set->n;
    bvox_labelset_destroy(set);
    int bad = 0;
    double t_read = TIME_MEDIAN(runs, {
        bad |= bvox_labels_read(path, NULL, 0, &set) != BVOX_OK;
        bvox_labelset_destroy(set);
    });
    bad |= bvox_labels_read(path, NULL, 0, &set) != BVOX_OK;
    double t_measure = TIME_MEDIAN(runs, bad |= measure_all(set));
    bvox_labelset_destroy(set);
    double t_all = TIME_MEDIAN(runs, {
        bad |= bvox_labels_read(path, NULL, 0, &set) != BVOX_OK;
        bad |= measure_all(set);
        bvox_labelset_destroy(set);
    });
    if (bad) {
        fprintf(stderr, "bench_labels: %s\n", bvox_errmsg());
        return 1;
    }
    printf("{\"bench\":\"labels\",\"case\":\"aal\",\"labels\":%lld,\"threads\":%d,\"runs\":%d,"
           "\"read_split_ms\":%.1f,\"measure_all_ms\":%.1f,\"table_ms\":%.1f}\n",
           (long long)n, threads, runs, t_read, t_measure, t_all);
    return 0;
}

int main(int argc, char **argv) { return run_threads_list(argc, argv, bench_main, "bench_labels"); }
