/*
 * test_check.c — the debug-build invariant checks (src/core/check.h): each
 * checker names a broken invariant and passes a sound object, and a public
 * operation given a broken volume aborts in a debug build (NDEBUG unset)
 * and runs on in a release build, where the checks compile to nothing.
 */
#include "harness.h"
#include "internal.h"

#include "bvox/mesh.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

TEST(volume_checker)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 4, 70}, &v));
    bvox_volume_fill(v, 1);
    CHECK(bvox__volume_broken(v) == NULL);
    CHECK(bvox__volume_broken(NULL) == NULL);
    v->words[2 * v->wpc + 1] |= (uint64_t)1 << 6; /* z = 70: beyond nz */
    CHECK(strstr(bvox__volume_broken(v), "tail bits"));
    v->words[2 * v->wpc + 1] &= v->tail_mask;
    CHECK(bvox__volume_broken(v) == NULL);
    uint64_t mask = v->tail_mask;
    v->tail_mask = ~(uint64_t)0;
    CHECK(strstr(bvox__volume_broken(v), "tail mask"));
    v->tail_mask = mask;
    v->nwords--;
    CHECK(strstr(bvox__volume_broken(v), "word counts"));
    v->nwords++;
    v->geom.spacing[1] = 0;
    CHECK(strstr(bvox__volume_broken(v), "voxel size"));
    v->geom.spacing[1] = 1;
    CHECK(bvox__volume_broken(v) == NULL);
    bvox_volume_destroy(v);
    return 0;
}

TEST(image_mesh_stack_checkers)
{
    bvox_image *img;
    CHECK_OK(bvox_image_create(5, 3, 3, 16, &img));
    CHECK(bvox__image_broken(img) == NULL);
    img->bits = 8; /* samples are in pixels16 */
    CHECK(strstr(bvox__image_broken(img), "8-bit"));
    img->bits = 16;
    img->channels = 2;
    CHECK(strstr(bvox__image_broken(img), "channels"));
    img->channels = 3;
    bvox_image_destroy(img);

    bvox_mesh *m;
    CHECK_OK(bvox_mesh_create(&m));
    for (int i = 0; i < 3; i++) CHECK_OK(bvox_mesh_add_vertex(m, i, i * i, 1));
    CHECK_OK(bvox_mesh_add_triangle(m, 0, 1, 2));
    CHECK(bvox__mesh_broken(m) == NULL);
    m->triangles[1] = 3;
    CHECK(strstr(bvox__mesh_broken(m), "vertex that does not exist"));
    m->triangles[1] = 1;
    m->nvertices = m->vcap + 1;
    CHECK(strstr(bvox__mesh_broken(m), "capacity"));
    m->nvertices = 3;
    CHECK(bvox__mesh_broken(m) == NULL);
    bvox_mesh_destroy(m);

    bvox_contour_stack *s;
    CHECK_OK(bvox_stack_create(&s));
    bvox_section *sec;
    CHECK_OK(bvox_stack_add_section(s, 0, "a", &sec));
    const bvox_point2 tri[3] = {{0, 0}, {4, 0}, {0, 4}};
    CHECK_OK(bvox_section_add_contour(sec, tri, 3, 0, -1));
    CHECK_OK(bvox_section_add_contour(sec, tri, 3, 1, 0));
    CHECK(bvox__stack_broken(s) == NULL);
    sec->contours[1].parent = 1; /* its own parent */
    CHECK(strstr(bvox__stack_broken(s), "parent"));
    sec->contours[1].parent = 0;
    CHECK(bvox__stack_broken(s) == NULL);
    bvox_stack_destroy(s);
    return 0;
}

/* In a child: a volume whose tail bit is set (which no operation may
 * produce) given to a public operation. Returns the child's wait status. */
static int run_on_broken_volume(void)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        bvox_volume *v, *d;
        if (bvox_volume_create((bvox_dims){4, 4, 10}, &v)) _exit(3);
        v->words[0] |= (uint64_t)1 << 20; /* beyond nz = 10 */
        /* keep the expected abort quiet: it is the point of the test */
        if (!freopen("/dev/null", "w", stderr)) _exit(4);
        bvox_status st = bvox_morph_dilate(v, 6, &d);
        if (st == BVOX_OK) bvox_volume_destroy(d);
        bvox_volume_destroy(v);
        _exit(0);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
    return status;
}

TEST(boundary_checks_debug_only)
{
    int status = run_on_broken_volume();
    CHECK(status != -1);
#ifdef NDEBUG
    /* release: no check runs, the operation returns normally */
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
#else
    /* debug: the entry check of bvox_morph_dilate aborts */
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT);
#endif
    return 0;
}

TEST(assert_macro)
{
    int evaluated = 0;
    BVOX_ASSERT(++evaluated == 1);
#ifdef NDEBUG
    CHECK_EQ(evaluated, 0); /* compiled out: not even evaluated */
#else
    CHECK_EQ(evaluated, 1);
#endif
    return 0;
}
