/* test_threads.c — the thread-safety promise of bvox.h under stress: 8
 * threads at once read, write, measure, mesh, dilate and label volumes of
 * their own, and measure, mesh, dilate and label two volumes they all share
 * as const; every result must equal the one computed alone beforehand, and
 * each thread's error message must be its own. The library's worker pool
 * runs inside every call too (2 workers), so the calls' own threads overlap
 * the 8. scripts/test.sh runs this under ThreadSanitizer (build-tsan/), which
 * turns any data race into a failure; in the other builds it checks the
 * answers. */
#include "harness.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "bvox/mesh.h"
#include "internal.h"

#define NTHREADS 8
#define ROUNDS 3

typedef struct {
    int64_t count, area_faces, components, euler, mesh_triangles, dilated_count;
} answers;

/* What the threads compute, on one volume. */
static int compute(const bvox_volume *v, answers *a, bvox_volume **dilated)
{
    bvox_measures m;
    if (bvox_measure(v, &m)) return 1;
    a->count = bvox_volume_count(v);
    a->area_faces = (int64_t)(m.area * 1000.0);
    a->euler = m.euler;
    bvox_components *c = NULL;
    if (bvox_components_find(v, 26, &c)) return 1;
    a->components = bvox_components_count(c);
    bvox_components_destroy(c);
    bvox_mesh *mesh = NULL;
    if (bvox_mesh_from_volume(v, NULL, &mesh)) return 1;
    a->mesh_triangles = mesh->ntriangles;
    bvox_mesh_destroy(mesh);
    bvox_volume *d = NULL;
    if (bvox_morph_dilate(v, 18, &d)) return 1;
    a->dilated_count = bvox_volume_count(d);
    if (dilated) *dilated = d;
    else bvox_volume_destroy(d);
    return 0;
}

/* A volume of its own for thread t: a few balls and a box that depend on t,
 * at an awkward size (nz not a multiple of 64). */
static bvox_volume *own_volume(int t)
{
    bvox_volume *v = NULL;
    if (bvox_volume_create((bvox_dims){37 + t, 29, 70 + 3 * t}, &v)) return NULL;
    for (int k = 0; k < 3; k++) {
        bvox_shape s = {BVOX_SHAPE_SPHERE, {8.0 + 9 * k, 12.0 + t % 3, 15.0 + 17 * k},
                        {0, 0, 0}, {0, 0, 0}, 4.0 + (t + k) % 4, 0, 0};
        bvox_shape_draw(v, &s, BVOX_CSG_UNION);
    }
    bvox_shape b = {BVOX_SHAPE_BOX, {18, 14, 60}, {6, 3 + t % 2, 5}, {0, 0, 0}, 0, 0, 0};
    bvox_shape_draw(v, &b, BVOX_CSG_UNION);
    return v;
}

typedef struct {
    int t;
    const bvox_volume *shared[2];
    const answers *shared_want; /* [2] */
    const bvox_volume *shared_dilated[2];
    answers own_want;
    char path[1100], missing[1100]; /* made by the main thread: harness_path is not thread-safe */
    int failed; /* line of the first failure, 0 if none */
} job;

#define TCHECK(cond)                                                                   \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            j->failed = __LINE__;                                                      \
            return NULL;                                                               \
        }                                                                              \
    } while (0)

static void *worker(void *arg)
{
    job *j = arg;
    const char *path = j->path, *missing = j->missing;
    for (int round = 0; round < ROUNDS; round++) {
        /* its own volume: write, read back, compute */
        bvox_volume *v = own_volume(j->t);
        TCHECK(v != NULL);
        TCHECK(bvox_write(path, v, NULL) == BVOX_OK);
        bvox_volume *back = NULL;
        TCHECK(bvox_read(path, NULL, &back) == BVOX_OK);
        TCHECK(bvox_volume_equal(back, v));
        answers a;
        TCHECK(compute(back, &a, NULL) == 0);
        TCHECK(memcmp(&a, &j->own_want, sizeof a) == 0);
        bvox_volume_destroy(back);
        bvox_volume_destroy(v);
        /* the shared const volumes */
        for (int s = 0; s < 2; s++) {
            bvox_volume *d = NULL;
            TCHECK(compute(j->shared[s], &a, &d) == 0);
            TCHECK(memcmp(&a, &j->shared_want[s], sizeof a) == 0);
            TCHECK(bvox_volume_equal(d, j->shared_dilated[s]));
            bvox_volume_destroy(d);
        }
        /* a failure's message stays in this thread */
        TCHECK(bvox_read(missing, NULL, &back) == BVOX_ENOTFOUND);
        TCHECK(strstr(bvox_errmsg(), missing) != NULL);
    }
    return NULL;
}

TEST(stress_eight_threads)
{
    bvox_set_threads(2);
    bvox_volume *shared[2] = {own_volume(11), NULL};
    CHECK(shared[0] != NULL);
    CHECK_OK(bvox_volume_create((bvox_dims){40, 33, 130}, &shared[1]));
    bvox_shape torus = {BVOX_SHAPE_TORUS, {20, 16, 64}, {0, 0, 0}, {1, 1, 2}, 11, 4, 0};
    CHECK_OK(bvox_shape_draw(shared[1], &torus, BVOX_CSG_UNION));
    answers want[2];
    bvox_volume *dil[2];
    for (int s = 0; s < 2; s++) CHECK(compute(shared[s], &want[s], &dil[s]) == 0);
    CHECK_EQ(want[1].components, 1);
    CHECK_EQ(want[1].euler, 0); /* a torus: one tunnel */
    job jobs[NTHREADS];
    for (int t = 0; t < NTHREADS; t++) {
        jobs[t] = (job){t, {shared[0], shared[1]}, want, {dil[0], dil[1]}, {0}, "", "", 0};
        char name[64];
        snprintf(name, sizeof name, "t%d.nii.gz", t);
        snprintf(jobs[t].path, sizeof jobs[t].path, "%s", harness_path(name));
        snprintf(name, sizeof name, "missing-%d.nii", t);
        snprintf(jobs[t].missing, sizeof jobs[t].missing, "%s", harness_path(name));
        bvox_volume *v = own_volume(t);
        CHECK(v != NULL);
        CHECK(compute(v, &jobs[t].own_want, NULL) == 0);
        bvox_volume_destroy(v);
    }
    pthread_t th[NTHREADS];
    for (int t = 0; t < NTHREADS; t++) CHECK(pthread_create(&th[t], NULL, worker, &jobs[t]) == 0);
    for (int t = 0; t < NTHREADS; t++) pthread_join(th[t], NULL);
    for (int t = 0; t < NTHREADS; t++) {
        if (jobs[t].failed) fprintf(stderr, "thread %d failed at line %d\n", t, jobs[t].failed);
        CHECK_EQ(jobs[t].failed, 0);
    }
    for (int s = 0; s < 2; s++) {
        bvox_volume_destroy(shared[s]);
        bvox_volume_destroy(dil[s]);
    }
    bvox_set_threads(0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* The cache of large buffers (core/big_buffers.c) from 8 threads at once:
 * each fills the buffers it gets with its own byte and checks them before
 * freeing, so a buffer handed to two threads at once, or kept in the cache
 * while in use, shows as a wrong byte (and as a race under TSan). */
static void *buffer_worker(void *arg)
{
    job *j = arg;
    uint64_t r = 0x9e3779b97f4a7c15ull * (uint64_t)(j->t + 1);
    unsigned char mark = (unsigned char)(0x11 * (j->t + 1));
    for (int round = 0; round < 200; round++) {
        r ^= r << 13, r ^= r >> 7, r ^= r << 17;
        size_t bytes = ((size_t)256 << 10) * (1 + r % 12) + r % 4096;
        bvox_status st;
        unsigned char *p = bvox__alloc(bytes, round % 3 == 0, "stress buffer", &st);
        TCHECK(p != NULL);
        if (round % 3 == 0) TCHECK(p[0] == 0 && p[bytes / 2] == 0 && p[bytes - 1] == 0);
        memset(p, mark, bytes);
        for (size_t i = 0; i < bytes; i += 4093) TCHECK(p[i] == mark);
        TCHECK(p[bytes - 1] == mark);
        bvox__free(p, bytes);
    }
    return NULL;
}

TEST(big_buffers_from_eight_threads)
{
    job jobs[NTHREADS];
    pthread_t th[NTHREADS];
    for (int t = 0; t < NTHREADS; t++) {
        memset(&jobs[t], 0, sizeof jobs[t]);
        jobs[t].t = t;
        CHECK(pthread_create(&th[t], NULL, buffer_worker, &jobs[t]) == 0);
    }
    for (int t = 0; t < NTHREADS; t++) pthread_join(th[t], NULL);
    for (int t = 0; t < NTHREADS; t++) CHECK_EQ(jobs[t].failed, 0);
    CHECK_EQ(bvox_memory_in_use(), 0);
    bvox_memory_trim();
    return 0;
}
