/*
 * bench_mesh.c — speed of volume -> mesh (marching cubes, cuberille) on n^3
 * volumes and of mesh -> volume (voxelizing CGAL's bunny at n), with
 * VTK's flying edges and scikit-image's marching cubes on the very same
 * volumes in the same run (bench/compare_vtk.py, when /usr/bin/python3 has
 * vtk and skimage).
 *
 * Specimens: "sphere" (radius 0.4 n, centred) and "bunny" (bunny00.off from
 * Debian's libcgal-demo, voxelized at n - 2 and padded to n^3 with 0s;
 * skipped with a note when the mesh is missing — run ctest -R setup.meshdata
 * or pass --bunny PATH). The naive reference (8 voxel reads per cell, the
 * same case table) counts the triangles for n <= 256: its count must agree.
 * One JSON line per case (bench/README.md).
 *
 *   bench_mesh [--quick] [--sizes 256,512] [--runs N] [--threads T] [--threads-list L]
 *              [--no-ref] [--bunny PATH] [--save DIR] [--peers]
 *
 * --save DIR writes DIR/<pattern>_<n>.nii (uint8 0/1), DIR/bunny.stl and
 * DIR/bvox.jsonl; --peers (implies --save, to a temporary folder if none)
 * then runs bench/compare_vtk.py on them, which prints one line per peer
 * and case with its median and the ratio to bvox.
 */
#include "internal.h"
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../src/mesh/mesh_private.h"

#ifndef BVOX_TEST_MESH_DIR
#define BVOX_TEST_MESH_DIR "."
#endif

typedef struct options {
    int runs, threads, ref, nsizes, peers;
    int sizes[8];
    const char *save, *bunny;
    thread_list tl; /* --threads-list: every line repeats per count */
} options;

static FILE *jsonl; /* DIR/bvox.jsonl with --save */

static void emit(const char *line)
{
    puts(line);
    fflush(stdout);
    if (jsonl) {
        fputs(line, jsonl);
        fputc('\n', jsonl);
    }
}

/* Naive marching-cubes triangle count: 8 voxel reads per cell. */
static int64_t ref_mc_triangles(const bvox_volume *v)
{
    const bvox__mc_case *tab = bvox__mc_table();
    int64_t n = 0;
    for (int32_t z = -1; z < v->nz; z++)
        for (int32_t y = -1; y < v->ny; y++)
            for (int32_t x = -1; x < v->nx; x++) {
                unsigned k = 0;
                for (int b = 0; b < 8; b++)
                    k |= (unsigned)bvox_volume_get(v, x + (b & 1), y + (b >> 1 & 1),
                                                   z + (b >> 2)) << b;
                n += tab[k].ntri;
            }
    return n;
}

static void bench_meshing(const options *o, const bvox_volume *v, const char *pattern, int n)
{
    for (int meth = 0; meth < 2; meth++) {
        bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
        mo.method = (bvox_mesh_method)meth;
        double t[64];
        int runs = o->runs > 64 ? 64 : o->runs;
        bvox_mesh *m = NULL;
        /* warm-up: 3 calls, the steady state (glibc's malloc moves its mmap
         * threshold over the first frees of the output arrays: until then
         * each call takes fresh pages from the kernel) */
        for (int w = 0; w < 3; w++) {
            bvox_mesh_destroy(m);
            m = NULL;
            if (bvox_mesh_from_volume(v, &mo, &m) != BVOX_OK) {
                fprintf(stderr, "bench_mesh: %s\n", bvox_errmsg());
                return;
            }
        }
        for (int i = 0; i < runs; i++) {
            bvox_mesh_destroy(m);
            m = NULL;
            double s = now_ms();
            bvox_mesh_from_volume(v, &mo, &m);
            t[i] = now_ms() - s;
        }
        double ms = median(t, runs);
        /* the same on one thread (a busy machine hurts the threaded figure) */
        int threads = bvox_threads();
        double ms1 = ms;
        if (threads > 1) {
            bvox_set_threads(1);
            for (int i = 0; i < runs; i++) {
                bvox_mesh_destroy(m);
                m = NULL;
                double s = now_ms();
                bvox_mesh_from_volume(v, &mo, &m);
                t[i] = now_ms() - s;
            }
            ms1 = median(t, runs);
            bvox_set_threads(threads);
        }
        char ref[128] = "";
        if (meth == 0 && o->ref && n <= 256) {
            double s = now_ms();
            int64_t nt = ref_mc_triangles(v);
            snprintf(ref, sizeof ref, ",\"ref_ms\":%.3f,\"agree\":%s", now_ms() - s,
                     nt == m->ntriangles ? "true" : "false");
        }
        char line[768];
        snprintf(line, sizeof line,
                 "{\"bench\":\"mesh\",\"op\":\"%s\",\"pattern\":\"%s\",\"n\":%d,\"threads\":%d,"
                 "\"runs\":%d,\"ms\":%.3f,\"ms_1thread\":%.3f,\"voxels\":%lld,\"vertices\":%lld,"
                 "\"triangles\":%lld,\"mtri_per_s\":%.2f%s}",
                 meth ? "cuberille" : "mc", pattern, n, bvox_threads(), runs, ms, ms1,
                 (long long)bvox_volume_count(v), (long long)m->nvertices,
                 (long long)m->ntriangles, (double)m->ntriangles / (ms * 1e3), ref);
        emit(line);
        bvox_mesh_destroy(m);
    }
}

static bvox_volume *make_sphere(int n)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    bvox_shape s = {.kind = BVOX_SHAPE_SPHERE,
                    .center = {(n - 1) / 2.0, (n - 1) / 2.0, (n - 1) / 2.0},
                    .radius = 0.4 * n};
    bvox_shape_draw(v, &s, BVOX_CSG_UNION);
    return v;
}

static void save(const options *o, const bvox_volume *v, const char *pattern, int n)
{
    if (!o->save) return;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s_%d.nii", o->save, pattern, n);
    if (bvox_write(path, v, NULL) != BVOX_OK) fprintf(stderr, "bench_mesh: %s\n", bvox_errmsg());
}

static int parse_sizes(const char *s, options *o)
{
    o->nsizes = 0;
    while (*s && o->nsizes < 8) {
        char *end;
        long v = strtol(s, &end, 10);
        if (end == s || v < 8 || v > 2048) return -1;
        o->sizes[o->nsizes++] = (int)v;
        s = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') return -1;
    }
    return o->nsizes ? 0 : -1;
}

int main(int argc, char **argv)
{
    options o = {5, 0, 1, 2, 0, {256, 512}, NULL, NULL, {0, {0}}};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            o.runs = 1;
            o.nsizes = 1;
            o.sizes[0] = 48;
        } else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) {
            if (parse_sizes(argv[++i], &o)) {
                fprintf(stderr, "bench_mesh: bad --sizes\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            o.runs = atoi(argv[++i]);
            if (o.runs < 1) o.runs = 1;
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            o.threads = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--threads-list") && i + 1 < argc) {
            if (!thread_list_parse(argv[++i], &o.tl)) {
                fprintf(stderr, "bench_mesh: bad --threads-list\n");
                return 2;
            }
        } else if (!strcmp(argv[i], "--no-ref")) {
            o.ref = 0;
        } else if (!strcmp(argv[i], "--bunny") && i + 1 < argc) {
            o.bunny = argv[++i];
        } else if (!strcmp(argv[i], "--save") && i + 1 < argc) {
            o.save = argv[++i];
        } else if (!strcmp(argv[i], "--peers")) {
            o.peers = 1;
        } else {
            fprintf(stderr,
                    "usage: bench_mesh [--quick] [--sizes 256,512] [--runs N] [--threads T] "
                    "[--threads-list 1,2,4,8,16] [--no-ref] [--bunny PATH] [--save DIR] [--peers]\n");
            return 2;
        }
    }
    if (o.threads > 0) bvox_set_threads(o.threads);
    if (!o.tl.n) o.tl = thread_list_default();
    char tmpdir[] = "/tmp/bench_mesh.XXXXXX";
    if (o.peers && !o.save) {
        if (!mkdtemp(tmpdir)) return 1;
        o.save = tmpdir;
    }
    if (o.save) {
        mkdir(o.save, 0777);
        char path[1024];
        snprintf(path, sizeof path, "%s/bvox.jsonl", o.save);
        jsonl = fopen(path, "w");
    }
    const char *bunny_path = o.bunny ? o.bunny : BVOX_TEST_MESH_DIR "/bunny00.off";
    bvox_mesh *bunny = NULL;
    if (bvox_mesh_read(bunny_path, NULL, &bunny) != BVOX_OK) {
        fprintf(stderr, "bench_mesh: no bunny (%s): bunny cases skipped\n", bvox_errmsg());
        bunny = NULL;
    } else if (o.save) {
        char path[1024];
        snprintf(path, sizeof path, "%s/bunny.stl", o.save);
        bvox_mesh_write(path, bunny, NULL, 0);
    }
    for (int ti = 0; ti < o.tl.n; ti++) {
        bvox_set_threads(o.tl.t[ti]);
        if (ti) o.ref = 0; /* the reference once, on the first count's lines */
        for (int si = 0; si < o.nsizes; si++) {
            int n = o.sizes[si];
            bvox_volume *v = make_sphere(n);
            if (!v) return 1;
            if (!ti) save(&o, v, "sphere", n);
            bench_meshing(&o, v, "sphere", n);
            bvox_volume_destroy(v);
            if (!bunny) continue;
            /* voxelizing the bunny at n */
            bvox_voxelize_opts vo;
            memset(&vo, 0, sizeof vo);
            vo.res = n;
            double t[64];
            int runs = o.runs > 64 ? 64 : o.runs;
            bvox_volume *bv = NULL;
            bvox_mesh_voxelize(bunny, &vo, &bv, NULL);
            for (int i = 0; i < runs; i++) {
                bvox_volume_destroy(bv);
                bv = NULL;
                double s = now_ms();
                bvox_mesh_voxelize(bunny, &vo, &bv, NULL);
                t[i] = now_ms() - s;
            }
            if (!bv) continue;
            char line[512];
            bvox_dims d = bvox_volume_dims(bv);
            snprintf(line, sizeof line,
                     "{\"bench\":\"mesh\",\"op\":\"voxelize\",\"pattern\":\"bunny\",\"n\":%d,"
                     "\"threads\":%d,\"runs\":%d,\"ms\":%.3f,\"dims\":[%d,%d,%d],\"voxels\":%lld,"
                     "\"triangles_in\":%lld}",
                     n, bvox_threads(), runs, median(t, runs), d.nx, d.ny, d.nz,
                     (long long)bvox_volume_count(bv), (long long)bunny->ntriangles);
            emit(line);
            bvox_volume_destroy(bv);
            bv = NULL;
            /* the volume to mesh: the bunny at n - 2 with a layer of 0s around,
             * padded to n^3, so that VTK and skimage (which do not close the
             * surface at the array's border) mesh the same closed object */
            vo.res = n - 2;
            if (bvox_mesh_voxelize(bunny, &vo, &bv, NULL) != BVOX_OK) continue;
            d = bvox_volume_dims(bv);
            int32_t before[3] = {1, 1, 1}, after[3] = {n - 1 - d.nx, n - 1 - d.ny, n - 1 - d.nz};
            bvox_volume *cube = NULL;
            if (bvox_volume_pad(bv, before, after, &cube) == BVOX_OK) {
                if (!ti) save(&o, cube, "bunny", n);
                bench_meshing(&o, cube, "bunny", n);
                bvox_volume_destroy(cube);
            }
            bvox_volume_destroy(bv);
        }
    }
    bvox_set_threads(o.tl.t[0]);
    bvox_mesh_destroy(bunny);
    if (jsonl) fclose(jsonl);
    int rc = 0;
    if (o.peers) {
        char cmd[2048];
        snprintf(cmd, sizeof cmd,
                 "/usr/bin/python3 %s/../../bench/compare_vtk.py %s --bench %s/bvox.jsonl "
                 "--runs %d --threads %d",
                 BVOX_TEST_DATA_DIR, o.save, o.save, o.runs, bvox_threads() < 2 ? 1 : 2);
        fflush(stdout);
        rc = system(cmd) == 0 ? 0 : 1;
        if (o.save == tmpdir) {
            snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
            if (system(cmd) != 0) rc = 1;
        }
    }
    return rc;
}
