/*
 * test_progress.c — the progress callback (bvox_set_progress): for each long
 * operation, a run without cancelling counts the calls and checks that the
 * fractions never go back, stay in 0..1 and end with exactly one 1; then the
 * callback cancels at its k-th call for every k before the last, and each
 * such run must return BVOX_ECANCELED with a message, hand nothing out, give
 * back every budgeted byte and leave no output file; the call that cancels at
 * the last (the final 1) must succeed. Results with a callback are the same
 * as without (the work runs in blocks only then).
 */
#include "harness.h"
#include "internal.h"

#include "bvox/contours.h"
#include "bvox/mesh.h"
#include "bvox/recon.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct recorder {
    int calls, cancel_at, bad, ones;
    double last;
    char stage[32];
} recorder;

static int record(double fraction, const char *stage, void *user)
{
    recorder *r = user;
    r->calls++;
    if (!(fraction >= r->last) || fraction > 1 || !stage || !stage[0]) r->bad++;
    if (fraction == 1) r->ones++;
    r->last = fraction;
    snprintf(r->stage, sizeof r->stage, "%s", stage ? stage : "");
    return r->calls == r->cancel_at;
}

/* An operation: runs once; on success frees what it made. out_made: set
 * when the call handed out a result (must not happen when it fails). */
typedef bvox_status (*op_fn)(int *out_made);

static bvox_volume *fixture;  /* a ball with a cavity, 70 x 300 x 90 */
static const char *out_file;  /* the file an op writes, checked absent after a cancel */

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* 0 when the contract holds; prints what broke. */
static int sweep(const char *what, op_fn op)
{
    recorder r = {0};
    bvox_set_progress_interval(0);
    bvox_set_progress(record, &r);
    int made = 0;
    bvox_status st = op(&made);
    int total = r.calls;
    int rc = 0;
    if (st != BVOX_OK || !made) {
        fprintf(stderr, "%s: the run without cancel failed: %s %s (made %d)\n", what,
                bvox_status_name(st), bvox_errmsg(), made);
        rc = 1;
    } else if (r.bad || r.ones != 1 || r.last != 1 || total < 2) {
        fprintf(stderr, "%s: %d calls, %d out of order, %d ones, last %g\n", what, total, r.bad,
                r.ones, r.last);
        rc = 1;
    }
    if (out_file) unlink(out_file);
    size_t base = bvox_memory_in_use();
    for (int k = 1; !rc && k <= total; k++) {
        r = (recorder){.cancel_at = k};
        made = 0;
        bvox__clear_error();
        st = op(&made);
        if (k == total) { /* the final call's answer is ignored: the work is done */
            if (st != BVOX_OK || !made) {
                fprintf(stderr, "%s: cancel at the final call failed the call\n", what);
                rc = 1;
            }
            if (out_file) unlink(out_file);
            break;
        }
        if (st != BVOX_ECANCELED || made || !strstr(bvox_errmsg(), "cancel")) {
            fprintf(stderr, "%s: cancel at call %d of %d gave %s (%s), result %s\n", what, k,
                    total, bvox_status_name(st), bvox_errmsg(), made ? "handed out" : "none");
            rc = 1;
        }
        if (r.calls != k) {
            fprintf(stderr, "%s: called %d times after cancelling at %d\n", what, r.calls, k);
            rc = 1;
        }
        if (bvox_memory_in_use() != base) {
            fprintf(stderr, "%s: cancel at %d kept %zu budgeted bytes\n", what, k,
                    bvox_memory_in_use() - base);
            rc = 1;
        }
        if (out_file && exists(out_file)) {
            fprintf(stderr, "%s: cancel at %d left %s\n", what, k, out_file);
            rc = 1;
        }
    }
    bvox_set_progress(NULL, NULL);
    bvox_set_progress_interval(0.005);
    return rc;
}

#define SWEEP(op) CHECK(sweep(#op, op) == 0)

static int make_fixture(void)
{
    if (fixture) return 0;
    if (bvox_volume_create((bvox_dims){70, 300, 90}, &fixture)) return 1;
    bvox_shape s = {.kind = BVOX_SHAPE_ELLIPSOID, .center = {35, 150, 45},
                    .semi_axes = {30, 120, 40}};
    bvox_shape hole = {.kind = BVOX_SHAPE_SPHERE, .center = {35, 150, 45}, .radius = 10};
    bvox_shape speck = {.kind = BVOX_SHAPE_SPHERE, .center = {3, 3, 3}, .radius = 1.5};
    return bvox_shape_draw(fixture, &s, BVOX_CSG_UNION) ||
           bvox_shape_draw(fixture, &hole, BVOX_CSG_DIFFERENCE) ||
           bvox_shape_draw(fixture, &speck, BVOX_CSG_UNION);
}

/* ---- the operations ---- */

static bvox_status vol_result(bvox_status st, bvox_volume *v, int *made)
{
    *made = v != NULL;
    bvox_volume_destroy(v);
    return st;
}

static bvox_status op_dilate26(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_dilate(fixture, 26, &v);
    return vol_result(st, v, made);
}
static bvox_status op_erode6(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_erode(fixture, 6, &v);
    return vol_result(st, v, made);
}
static bvox_status op_dilate_ball(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_dilate_ball(fixture, 2.5, &v);
    return vol_result(st, v, made);
}
static bvox_status op_open(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_open(fixture, 18, 0, &v);
    return vol_result(st, v, made);
}
static bvox_status op_close(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_close(fixture, 0, 2, &v);
    return vol_result(st, v, made);
}
static bvox_status op_fill(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_fill_holes(fixture, &v);
    return vol_result(st, v, made);
}
static bvox_status op_hollow(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_hollow(fixture, 2, &v);
    return vol_result(st, v, made);
}
static bvox_status op_islands(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_morph_remove_islands(fixture, 26, 100, &v);
    return vol_result(st, v, made);
}
static bvox_status op_components(int *made)
{
    bvox_components *c = NULL;
    bvox_status st = bvox_components_find(fixture, 26, &c);
    *made = c != NULL;
    bvox_components_destroy(c);
    return st;
}
static bvox_status op_measure(int *made)
{
    bvox_measures m;
    bvox_status st = bvox_measure(fixture, &m);
    *made = st == BVOX_OK && m.count == bvox_volume_count(fixture);
    return st;
}
static bvox_status mesh_with(bvox_mesh_method method, int smooth, int *made)
{
    bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
    o.method = method;
    o.smooth = smooth;
    bvox_mesh *m = NULL;
    bvox_status st = bvox_mesh_from_volume(fixture, &o, &m);
    *made = m != NULL;
    bvox_mesh_destroy(m);
    return st;
}
static bvox_status op_mesh_mc_smooth(int *made) { return mesh_with(BVOX_MESH_MC, 3, made); }
static bvox_status op_mesh_cuberille(int *made) { return mesh_with(BVOX_MESH_CUBERILLE, 0, made); }

static const char *in_file;
static bvox_status op_read(int *made)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_read(in_file, NULL, &v);
    if (v && !bvox_volume_equal(v, fixture)) st = BVOX_EINVAL;
    return vol_result(st, v, made);
}
static bvox_status op_write(int *made)
{
    bvox_status st = bvox_write(out_file, fixture, NULL);
    *made = st == BVOX_OK && exists(out_file);
    return st;
}
static bvox_status op_turntable(int *made)
{
    bvox_render_opts ro = bvox_render_opts_default();
    ro.proj.width = ro.proj.height = 48;
    bvox_status st = bvox_render_turntable(fixture, &ro, 5, out_file);
    *made = st == BVOX_OK && exists(out_file);
    return st;
}
static bvox_status op_reconstruct(int *made)
{
    bvox_volume *v = NULL;
    bvox_recon_opts o = bvox_recon_opts_default();
    const char *inputs[] = {in_file};
    bvox_status st = bvox_reconstruct(inputs, 1, &o, &v, NULL, NULL);
    if (v && bvox_volume_count(v) != bvox_volume_count(fixture)) st = BVOX_EINVAL;
    return vol_result(st, v, made);
}

TEST(morphology_cancels_cleanly)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_dilate26);
    SWEEP(op_erode6);
    SWEEP(op_dilate_ball);
    SWEEP(op_open);
    SWEEP(op_close);
    SWEEP(op_fill);
    SWEEP(op_hollow);
    SWEEP(op_islands);
    return 0;
}

TEST(components_measure_cancel_cleanly)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_components);
    SWEEP(op_measure);
    return 0;
}

TEST(mesh_cancels_cleanly)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_mesh_mc_smooth);
    SWEEP(op_mesh_cuberille);
    return 0;
}

TEST(read_write_cancel_cleanly)
{
    CHECK(make_fixture() == 0);
    static const char *const names[] = {"p.nii.gz", "p.nii", "p.tif"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[4096];
        snprintf(path, sizeof path, "%s", harness_path(names[i]));
        out_file = path;
        SWEEP(op_write);
        out_file = NULL;
        CHECK_OK(bvox_write(path, fixture, NULL));
        in_file = path;
        SWEEP(op_read);
        in_file = NULL;
        unlink(path);
    }
    return 0;
}

TEST(turntable_cancels_cleanly)
{
    CHECK(make_fixture() == 0);
    char path[4096];
    snprintf(path, sizeof path, "%s", harness_path("turn.gif"));
    out_file = path;
    SWEEP(op_turntable);
    out_file = NULL;
    return 0;
}

TEST(reconstruct_cancels_cleanly)
{
    CHECK(make_fixture() == 0);
    bvox_contour_stack *stack = NULL;
    CHECK_OK(bvox_volume_to_contours(fixture, 2, &stack));
    char path[4096];
    snprintf(path, sizeof path, "%s", harness_path("stack.json"));
    CHECK_OK(bvox_stack_write_json(path, stack));
    bvox_stack_destroy(stack);
    in_file = path;
    SWEEP(op_reconstruct);
    in_file = NULL;
    return 0;
}

/* Blocks run one after the other with a callback: the same voxels. */
static int quiet(double fraction, const char *stage, void *user) { return 0; }

TEST(same_result_with_callback)
{
    CHECK(make_fixture() == 0);
    bvox_volume *a = NULL, *b = NULL, *c = NULL, *d = NULL;
    CHECK_OK(bvox_morph_dilate(fixture, 26, &a));
    CHECK_OK(bvox_morph_erode_ball(fixture, 3, &c));
    bvox_set_progress(quiet, NULL);
    CHECK_OK(bvox_morph_dilate(fixture, 26, &b));
    CHECK_OK(bvox_morph_erode_ball(fixture, 3, &d));
    bvox_set_progress(NULL, NULL);
    CHECK(bvox_volume_equal(a, b));
    CHECK(bvox_volume_equal(c, d));
    CHECK(bvox_volume_count(a) > bvox_volume_count(fixture));
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    bvox_volume_destroy(c);
    bvox_volume_destroy(d);
    return 0;
}

/* The callback belongs to the thread that set it, and a nested call (open =
 * erode + dilate) shows one bar: its inner calls give no final 1 of their own. */
TEST(one_bar_for_a_nested_call)
{
    CHECK(make_fixture() == 0);
    recorder r = {0};
    bvox_set_progress_interval(0);
    bvox_set_progress(record, &r);
    bvox_volume *v = NULL;
    CHECK_OK(bvox_morph_open(fixture, 6, 0, &v));
    bvox_set_progress(NULL, NULL);
    bvox_set_progress_interval(0.005);
    CHECK_EQ(r.ones, 1);
    CHECK_EQ(r.bad, 0);
    CHECK(r.calls >= 4);
    CHECK(strcmp(r.stage, "open") == 0);
    bvox_volume_destroy(v);
    CHECK(strcmp(bvox_status_name(BVOX_ECANCELED), "BVOX_ECANCELED") == 0);
    return 0;
}

/* bvox__bands: one band without a callback; the nfixed equal bands with
 * interval 0 (what the sweeps above rely on: the same calls every run); with
 * an interval, bands of about a quarter of a second, so work that takes
 * microseconds is the first fixed band and then the rest at once. */
static int band_count(int64_t total, int64_t nfixed, int64_t *first_end)
{
    bvox__bands b;
    bvox__bands_begin(&b, total, nfixed);
    int n = 0;
    for (int64_t lo = 0, hi; lo < total; lo = hi) {
        hi = bvox__bands_next(&b, lo);
        if (hi <= lo || hi > total) return -1;
        if (n++ == 0) *first_end = hi;
    }
    return n;
}

TEST(bands_sized_by_time)
{
    int64_t first = 0;
    CHECK_EQ(band_count(1000, 16, &first), 1); /* no callback */
    CHECK_EQ(first, 1000);
    bvox_set_progress(quiet, NULL);
    bvox_set_progress_interval(0);
    CHECK_EQ(band_count(1000, 16, &first), 16);
    CHECK_EQ(first, 62);
    CHECK_EQ(band_count(5, 16, &first), 5); /* never an empty band */
    bvox_set_progress_interval(0.005);
    int n = band_count(1000, 16, &first);
    CHECK_EQ(first, 62);
    /* 2 unless this process was held off the CPU for tens of ms */
    CHECK(n >= 2 && n <= 4);
    CHECK_EQ(band_count(1000, 1, &first), 1);
    bvox_set_progress(NULL, NULL);
    return 0;
}
