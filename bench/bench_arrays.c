/*
 * bench_arrays.c — arrays in and out of the library, the path of the Python
 * package's from_numpy / to_numpy: bvox_volume_from_samples on n^3 bytes
 * (u8, nonzero) in both sample orders, and bvox_volume_to_bytes back, each
 * against a memcpy of the same n^3 bytes in the same run. The bytes are a
 * blocky pattern (slabs of z and rows of y), so both 0 and 1 runs occur.
 * One JSON line per size and case; bench/README.md explains the keys.
 *
 *   bench_arrays [--quick] [--runs N] [--sizes 256,512] [--threads-list 1,2,4]
 */
#include "bvox.h"
#include "bench_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void line(int n, const char *c, double ms, double memcpy_ms)
{
    double gb = (double)n * n * n / 1e9;
    printf("{\"bench\":\"arrays\",\"n\":%d,\"case\":\"%s\",\"threads\":%d,\"ms\":%.3f,"
           "\"gb_per_s\":%.2f,\"memcpy_ms\":%.3f,\"vs_memcpy\":%.2f}\n",
           n, c, bvox_threads(), ms, gb / (ms / 1e3), memcpy_ms, ms / memcpy_ms);
    fflush(stdout);
}

static int bench_main(int argc, char **argv)
{
    int sizes[8] = {256, 512}, nsizes = 2, runs = 7;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            sizes[0] = 64;
            sizes[1] = 96;
            runs = 3;
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) {
            if (!parse_size_list(argv[++i], sizes, 8, &nsizes) || nsizes == 0) {
                fprintf(stderr, "bench_arrays: --sizes a,b,c\n");
                return 2;
            }
        } else {
            fprintf(stderr, "usage: bench_arrays [--quick] [--runs N] [--sizes a,b,c]\n");
            return 2;
        }
    }
    if (runs < 1) runs = 1;
    for (int s = 0; s < nsizes; s++) {
        int n = sizes[s];
        size_t nv = (size_t)n * n * n;
        uint8_t *in = malloc(nv), *out = malloc(nv);
        if (!in || !out) {
            fprintf(stderr, "bench_arrays: no memory for %d^3\n", n);
            return 1;
        }
        for (size_t i = 0; i < nv; i++) {
            size_t a = i / ((size_t)n * n), b = i / (size_t)n % (size_t)n, c = i % (size_t)n;
            in[i] = (uint8_t)(((a / 7 + b / 3 + c / 11) % 3) == 0);
        }
        bvox_dims d = {n, n, n};
        double mc = TIME_MEDIAN(runs, parallel_memcpy(out, in, nv, bvox_threads()));
        bvox_volume *v = NULL;
        int ok = 1;
        const struct {
            const char *name;
            bvox_order order;
        } orders[] = {{"from_samples_z_fastest", BVOX_ORDER_Z_FASTEST},
                      {"from_samples_x_fastest", BVOX_ORDER_X_FASTEST}};
        for (int o = 0; o < 2; o++) {
            double ms = TIME_MEDIAN(runs, {
                bvox_volume_destroy(v);
                v = NULL;
                if (bvox_volume_from_samples(in, BVOX_DT_U8, d, orders[o].order, NULL, &v))
                    ok = 0;
            });
            line(n, orders[o].name, ms, mc);
        }
        if (!ok || !v) {
            fprintf(stderr, "bench_arrays: %s\n", bvox_errmsg());
            return 1;
        }
        double tz = TIME_MEDIAN(runs, bvox_volume_to_bytes(v, BVOX_ORDER_Z_FASTEST, out));
        line(n, "to_bytes_z_fastest", tz, mc);
        double tx = TIME_MEDIAN(runs, bvox_volume_to_bytes(v, BVOX_ORDER_X_FASTEST, out));
        line(n, "to_bytes_x_fastest", tx, mc);
        /* the last result is the x-fastest unpacking of a volume built from
         * the x-fastest samples: the round trip must give the input back */
        if (memcmp(in, out, nv) != 0) {
            fprintf(stderr, "bench_arrays: round trip differs at %d^3\n", n);
            return 1;
        }
        bvox_volume_destroy(v);
        free(in);
        free(out);
    }
    return 0;
}

int main(int argc, char **argv) { return run_threads_list(argc, argv, bench_main, "bench_arrays"); }
