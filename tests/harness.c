/* harness.c — the runner behind harness.h (see there). */
#include "harness.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <stdbool.h>
#include <unistd.h>

#define MAX_CASES 512

static struct {
    const char *name;
    harness_fn fn;
} cases[MAX_CASES];
static int ncases;
static char tmpdir[512];
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

void harness_register(const char *name, harness_fn fn)
{
    if (ncases < MAX_CASES) cases[ncases++] = (typeof(cases[0])){name, fn};
}

const char *harness_tmpdir(void)
{
    if (!tmpdir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/bvox-test-XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(tmpdir)) {
            perror("mkdtemp");
            exit(2);
        }
    }
    return tmpdir;
}

const char *harness_path(const char *name)
{
    static char slots[8][1024];
    static int next;
    char *p = slots[next++ & 7];
    snprintf(p, 1024, "%s/%s", harness_tmpdir(), name);
    return p;
}

uint64_t harness_rand(void)
{
    uint64_t x = rng_state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return rng_state = x;
}

const char *harness_data_dir(void)
{
#ifdef BVOX_TEST_DATA_DIR
    return BVOX_TEST_DATA_DIR;
#else
    return "tests/data";
#endif
}

const char *harness_golden_path(const char *name)
{
    static char path[4096];
    const char *dir = getenv("BVOX_GOLDEN_DIR");
    snprintf(path, sizeof path, "%s/%s", dir && *dir ? dir : harness_data_dir(), name);
    return path;
}

int harness_golden_update(const bvox_image *img, const char *name)
{
    const char *mode = getenv("BVOX_UPDATE_GOLDEN");
    if (!mode || !*mode || !strcmp(mode, "0")) return 0;
    const char *path = harness_golden_path(name);
    bvox_status st = bvox_image_write_png(img, path);
    if (st) fprintf(stderr, "golden %s: could not write it: %s\n", path, bvox_errmsg());
    else
        fprintf(stderr, "golden %s updated; inspect and commit it, then re-run without "
                        "BVOX_UPDATE_GOLDEN (this run fails on purpose)\n",
                path);
    return 1;
}

int harness_golden_compare(bvox_image *img, const char *name, double max_mean, int max_worst)
{
    char path[160];
    snprintf(path, sizeof path, "golden/%s.png", name);
    if (harness_golden_update(img, path)) {
        bvox_image_destroy(img);
        return 1;
    }
    bvox_image *gold = NULL;
    int rc = 1;
    if (bvox_image_read_png(harness_golden_path(path), &gold)) {
        fprintf(stderr, "golden %s: %s\n", path, bvox_errmsg());
    } else if (gold->width != img->width || gold->height != img->height ||
               gold->channels != img->channels || gold->bits != 8 || img->bits != 8) {
        fprintf(stderr, "golden %s: %d x %d x %d, the picture %d x %d x %d\n", path,
                gold->width, gold->height, gold->channels, img->width, img->height,
                img->channels);
    } else {
        size_t n = (size_t)gold->width * gold->height * gold->channels;
        double sum = 0;
        int worst = 0;
        for (size_t i = 0; i < n; i++) {
            int d = abs((int)gold->pixels[i] - (int)img->pixels[i]);
            sum += d;
            worst = d > worst ? d : worst;
        }
        fprintf(stderr, "%s: mean absolute difference %.4f, largest %d\n", name,
                sum / (double)n, worst);
        rc = sum / (double)n <= max_mean && worst <= max_worst ? 0 : 1;
        if (rc) fprintf(stderr, "golden %s: more than %g mean or %d largest\n", path, max_mean,
                        max_worst);
    }
    bvox_image_destroy(gold);
    bvox_image_destroy(img);
    return rc;
}

static void remove_tree(const char *path)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", path);
}

static int run_case(int i)
{
    rng_state = 0x9e3779b97f4a7c15ull;
    for (const char *c = cases[i].name; *c; c++) rng_state = rng_state * 31 + (uint8_t)*c;
    int rc = cases[i].fn();
    if (tmpdir[0]) {
        if (rc == 0) remove_tree(tmpdir);
        else fprintf(stderr, "scratch files kept in %s\n", tmpdir);
        tmpdir[0] = '\0';
    }
    printf("%s %s\n", rc ? "FAIL" : "ok  ", cases[i].name);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "--list")) {
        for (int i = 0; i < ncases; i++) printf("%s\n", cases[i].name);
        return 0;
    }
    int failed = 0, ran = 0;
    for (int i = 0; i < ncases; i++) {
        bool wanted = argc <= 1;
        for (int a = 1; a < argc; a++)
            if (!strcmp(argv[a], cases[i].name)) wanted = true;
        if (!wanted) continue;
        ran++;
        failed += run_case(i) != 0;
    }
    if (argc > 1 && ran == 0) {
        fprintf(stderr, "no test case named %s\n", argv[1]);
        return 2;
    }
    return failed ? 1 : 0;
}

int harness_count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

/* Triangles as sorted rows of 9 coordinates, each rotated (orientation
 * kept) to start at its smallest vertex: equal meshes up to order. */
static int cmp_doubles(const double *p, const double *q, int n)
{
    for (int i = 0; i < n; i++)
        if (p[i] != q[i]) return p[i] < q[i] ? -1 : 1;
    return 0;
}

static int cmp9(const void *a, const void *b) { return cmp_doubles(a, b, 9); }

double *harness_mesh_canon(const bvox_mesh *m)
{
    double *t = malloc((size_t)(m->ntriangles ? m->ntriangles : 1) * 9 * sizeof *t);
    for (int64_t k = 0; k < m->ntriangles; k++) {
        const double *v[3];
        for (int i = 0; i < 3; i++) v[i] = &m->vertices[3 * m->triangles[3 * k + i]];
        int s = 0;
        for (int i = 1; i < 3; i++)
            if (cmp_doubles(v[i], v[s], 3) < 0) s = i;
        for (int i = 0; i < 3; i++) memcpy(&t[9 * k + 3 * i], v[(s + i) % 3], 3 * sizeof(double));
    }
    qsort(t, (size_t)m->ntriangles, 9 * sizeof *t, cmp9);
    return t;
}
