/*
 * test_alloc_faults.c — SQLite-style out-of-memory sweep over the whole
 * library. Every allocation goes through the one seam (src/core/alloc.c), so
 * for each reader, writer and operation the n-th allocation is failed for
 * n = 1, 2, ... until the call succeeds without reaching allocation n (a
 * failure the call absorbs, such as a retried allocation, does not end the
 * sweep). Each failed call must return
 * BVOX_ENOMEM with a message, leave its out-parameters NULL, give back every
 * budgeted byte (bvox_memory_in_use), leave no file in its output folder, and
 * leak nothing (the ASan build's leak checker runs at the end of each case).
 * The call that finally succeeds is checked against the answer of a run
 * without faults, so a sweep cannot pass by never reaching the real work.
 */
#include "harness.h"
#include "internal.h"

#include "bvox/contours.h"
#include "bvox/mesh.h"
#include "bvox/recon.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* An operation under test: runs the call once; on success checks and frees
 * what it made and returns BVOX_OK; on failure checks that nothing was handed
 * out and returns the call's status. OP_BROKEN marks a broken contract. */
typedef bvox_status (*fault_op)(void);
#define OP_BROKEN ((bvox_status)-1000)
#define OUT_IS_NULL(st, p)                                                             \
    do {                                                                               \
        if ((st) != BVOX_OK && (p) != NULL) {                                          \
            fprintf(stderr, "%s: failed with %s but *out is not NULL\n", __func__,     \
                    bvox_status_name(st));                                             \
            return OP_BROKEN;                                                          \
        }                                                                              \
    } while (0)
#define OP_CHECK(cond)                                                                 \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            fprintf(stderr, "%s:%d: %s after success: %s\n", __FILE__, __LINE__,       \
                    __func__, #cond);                                                  \
            return OP_BROKEN;                                                          \
        }                                                                              \
    } while (0)

/* Remove dir's files and folders one level deep (outputs of a successful run). */
static void dir_clear(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    char p[4096];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat sb;
        if (stat(p, &sb) == 0 && S_ISDIR(sb.st_mode)) {
            dir_clear(p);
            rmdir(p);
        } else {
            unlink(p);
        }
    }
    closedir(d);
}

/* A fresh, empty output folder for a writer. */
static const char *outdir(const char *name)
{
    const char *p = harness_path(name);
    mkdir(p, 0755);
    dir_clear(p);
    return p;
}

static char out_path_buf[8][4096];
static const char *in_out(const char *dir, const char *name)
{
    static int slot;
    char *b = out_path_buf[slot++ & 7];
    snprintf(b, 4096, "%s/%s", dir, name);
    return b;
}

/* The sweep. out: the folder the call writes into (must stay empty while the
 * call fails), or NULL. Returns 0 when every failure was clean and the call
 * finally succeeded. */
static int sweep(const char *what, fault_op op, const char *out)
{
    size_t base = bvox_memory_in_use();
    long failures = 0, absorbed = 0;
    for (long n = 1; n <= 200000; n++) {
        bvox__clear_error();
        bvox__alloc_fail_after(n);
        bvox_status st = op();
        /* was allocation n reached (and so failed) in this run? */
        int injected = bvox__alloc_fail_pending() == 0;
        bvox__alloc_fail_after(0);
        if (st == OP_BROKEN) {
            fprintf(stderr, "%s: broken contract with allocation %ld failed\n", what, n);
            return 1;
        }
        if (bvox_memory_in_use() != base) {
            fprintf(stderr, "%s: allocation %ld failed: %zu budgeted bytes not given back\n",
                    what, n, bvox_memory_in_use() - base);
            return 1;
        }
        if (st == BVOX_OK && injected) {
            /* a failure the call may absorb (a retried or optional
             * allocation): go on, the later allocations are still to test */
            absorbed++;
            if (out) dir_clear(out);
            continue;
        }
        if (st == BVOX_OK) {
            if (failures + absorbed == 0) {
                fprintf(stderr, "%s: succeeded with its first allocation failed: "
                                "it allocates nothing, so the sweep tests nothing\n", what);
                return 1;
            }
            if (out) dir_clear(out);
            printf("%s: %ld allocations failed in turn, all clean (%ld absorbed)\n", what,
                   failures + absorbed, absorbed);
            return 0;
        }
        if (!injected) {
            fprintf(stderr, "%s: failed with %s although allocation %ld was never reached: %s\n",
                    what, bvox_status_name(st), n, bvox_errmsg());
            return 1;
        }
        failures++;
        if (st != BVOX_ENOMEM) {
            fprintf(stderr, "%s: allocation %ld failed gave %s, not ENOMEM: %s\n", what, n,
                    bvox_status_name(st), bvox_errmsg());
            return 1;
        }
        if (!bvox_errmsg()[0]) {
            fprintf(stderr, "%s: allocation %ld failed gave ENOMEM without a message\n", what, n);
            return 1;
        }
        if (out && harness_count_entries(out) != 0) {
            fprintf(stderr, "%s: allocation %ld failed left %d entries in %s\n", what, n,
                    harness_count_entries(out), out);
            return 1;
        }
    }
    fprintf(stderr, "%s: never succeeded\n", what);
    return 1;
}
#define SWEEP(op, out) CHECK(sweep(#op, op, out) == 0)

/* ------------------------------------------------------------ fixtures */

/* 21 x 18 x 70 (nz > 64: two words per column): a ball with a cavity, a
 * box and a loose voxel (two components at 6-connectivity, a hole). */
static bvox_volume *fixture;
static int64_t fixture_count;

static int make_fixture(void)
{
    CHECK_OK(bvox_volume_create((bvox_dims){21, 18, 70}, &fixture));
    bvox_shape s = {0};
    s.kind = BVOX_SHAPE_SPHERE;
    s.center[0] = 10; s.center[1] = 9; s.center[2] = 40;
    s.radius = 7.5;
    CHECK_OK(bvox_shape_draw(fixture, &s, BVOX_CSG_UNION));
    s.radius = 2.5;
    CHECK_OK(bvox_shape_draw(fixture, &s, BVOX_CSG_DIFFERENCE));
    bvox_volume_fill_box(fixture, (bvox_box){2, 2, 3, 8, 6, 14}, 1);
    CHECK_OK(bvox_volume_set(fixture, 18, 16, 66, 1));
    fixture_count = bvox_volume_count(fixture);
    CHECK(fixture_count > 1000);
    return 0;
}

static int same_as_fixture(const bvox_volume *v)
{
    bvox_dims d = bvox_volume_dims(v);
    return d.nx == 21 && d.ny == 18 && d.nz == 70 && bvox_volume_check(v) == BVOX_OK &&
           bvox_volume_count(v) == fixture_count &&
           bvox_volume_count_and(v, fixture) == fixture_count;
}

/* ------------------------------------------------------- read and write */

static const char *wdir;        /* writers' output folder */
static const char *wname;       /* the file (or folder) inside it */
static const char *wformat;     /* NULL: by extension */
static const char *rpath;       /* readers' input */
static bvox_read_opts ropts;

static bvox_status op_write(void)
{
    bvox_write_opts o = BVOX_WRITE_OPTS_INIT;
    o.format = wformat;
    bvox_status st = bvox_write(in_out(wdir, wname), fixture, &o);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 1);
    return st;
}

static bvox_status op_read(void)
{
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = bvox_read(rpath, &ropts, &v);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(same_as_fixture(v));
    bvox_volume_destroy(v);
    return BVOX_OK;
}

static uint8_t *mem_data;
static size_t mem_size;

static bvox_status op_read_memory(void)
{
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = bvox_read_memory(mem_data, mem_size, "mem", &ropts, &v);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(same_as_fixture(v));
    bvox_volume_destroy(v);
    return BVOX_OK;
}

static int load_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    fseek(f, 0, SEEK_END);
    mem_size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    mem_data = (uint8_t *)bvox__mem_alloc(mem_size);
    CHECK(mem_data != NULL);
    CHECK_EQ(fread(mem_data, 1, mem_size, f), mem_size);
    fclose(f);
    return 0;
}

/* Write name (format) into a fresh folder under every failure, then read it
 * back under every failure, from the file and (for files) from memory. */
static int format_case(const char *name, const char *format, int memory)
{
    CHECK(make_fixture() == 0);
    wdir = outdir("out");
    wname = name;
    wformat = format;
    SWEEP(op_write, wdir);
    CHECK_OK(bvox_write(in_out(wdir, name), fixture, &(bvox_write_opts){format, 8}));
    rpath = in_out(wdir, name);
    ropts = (bvox_read_opts)BVOX_READ_OPTS_INIT;
    ropts.format = format;
    if (!strcmp(name, "v.raw")) {
        ropts.raw_dims = (bvox_dims){21, 18, 70};
        ropts.raw_dtype = BVOX_DT_U8;
    }
    SWEEP(op_read, NULL);
    if (memory) {
        CHECK(load_file(rpath) == 0);
        if (!ropts.format) ropts.format = bvox_format_for_path(rpath);
        SWEEP(op_read_memory, NULL);
        free(mem_data);
    }
    bvox_volume_destroy(fixture);
    return 0;
}

TEST(nifti) { return format_case("v.nii", NULL, 1); }
TEST(nifti_gz) { return format_case("v.nii.gz", NULL, 1); }
TEST(binvox) { return format_case("v.binvox", NULL, 1); }
TEST(tiff) { return format_case("v.tif", NULL, 1); }
TEST(raw) { return format_case("v.raw", NULL, 1); }
TEST(png_slices) { return format_case("slices", "png", 0); }
TEST(metaimage) { return format_case("v.mha", NULL, 1); }
TEST(nrrd_gzip) { return format_case("v.nrrd", NULL, 1); }
TEST(zarr) { return format_case("v.zarr", NULL, 0); }

static uint32_t *labels;

static bvox_status op_write_labels(void)
{
    bvox_status st = bvox_write_labels_nifti(in_out(wdir, "l.nii.gz"), fixture, labels);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 1);
    return st;
}

TEST(labels_nifti)
{
    CHECK(make_fixture() == 0);
    size_t n = (size_t)21 * 18 * 70;
    labels = (uint32_t *)bvox__mem_zalloc(n, sizeof *labels);
    CHECK(labels != NULL);
    for (size_t i = 0; i < n; i += 7) labels[i] = (uint32_t)(i % 5);
    wdir = outdir("out");
    SWEEP(op_write_labels, wdir);
    free(labels);
    bvox_volume_destroy(fixture);
    return 0;
}

/* labelio: bvox_write_labels into a .seg.nrrd (header built in memory) and
 * a .mhd (two files: both or neither). */
static const char *labels_name;
static int labels_files;

static bvox_status op_write_labels_any(void)
{
    bvox_status st = bvox_write_labels(in_out(wdir, labels_name), fixture, labels, -1, NULL);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == labels_files);
    return st;
}

static int labels_any_case(const char *name, int files)
{
    CHECK(make_fixture() == 0);
    size_t n = (size_t)21 * 18 * 70;
    labels = (uint32_t *)bvox__mem_zalloc(n, sizeof *labels);
    CHECK(labels != NULL);
    for (size_t i = 0; i < n; i += 7) labels[i] = (uint32_t)(i % 5);
    labels_name = name;
    labels_files = files;
    wdir = outdir("out");
    SWEEP(op_write_labels_any, wdir);
    free(labels);
    bvox_volume_destroy(fixture);
    return 0;
}

TEST(labels_seg_nrrd) { return labels_any_case("l.seg.nrrd", 1); }
TEST(labels_mhd) { return labels_any_case("l.mhd", 2); }

/* labelio: bvox_interpolate_labels on two labels annotated every 4th slice
 * of 20 x 16 x 70: every failed allocation ENOMEM, nothing kept; success
 * gives the answer without faults. */
static uint32_t *ilab_in, *ilab_work, *ilab_want;
#define ILAB_N ((size_t)20 * 16 * 70)

static bvox_status op_interpolate_labels(void)
{
    memcpy(ilab_work, ilab_in, ILAB_N * sizeof *ilab_work);
    bvox_status st = bvox_interpolate_labels((bvox_dims){20, 16, 70}, ilab_work, NULL);
    if (st == BVOX_OK) OP_CHECK(!memcmp(ilab_work, ilab_want, ILAB_N * sizeof *ilab_work));
    return st;
}

TEST(interpolate_labels)
{
    ilab_in = calloc(ILAB_N, sizeof *ilab_in);
    ilab_work = calloc(ILAB_N, sizeof *ilab_work);
    ilab_want = calloc(ILAB_N, sizeof *ilab_want);
    CHECK(ilab_in && ilab_work && ilab_want);
    for (int z = 2; z < 68; z += 4)
        for (int y = 2; y < 14; y++)
            for (int x = 2; x < 18; x++)
                if ((x - 10) * (x - 10) + (y - 8) * (y - 8) < 30 + z % 7)
                    ilab_in[((size_t)z * 16 + y) * 20 + x] = x < 9 + z % 3 ? 1 : 2;
    memcpy(ilab_want, ilab_in, ILAB_N * sizeof *ilab_want);
    CHECK_OK(bvox_interpolate_labels((bvox_dims){20, 16, 70}, ilab_want, NULL));
    SWEEP(op_interpolate_labels, NULL);
    free(ilab_in);
    free(ilab_work);
    free(ilab_want);
    return 0;
}

/* ----------------------------------------------------------- operations */

static bvox_volume *result;     /* the answer without faults */
typedef bvox_status (*vol_fn)(const bvox_volume *in, bvox_volume **out);
static vol_fn vfn;

static bvox_status op_volume(void)
{
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = vfn(fixture, &v);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(bvox_volume_check(v) == BVOX_OK);
    OP_CHECK(bvox_volume_equal(v, result));
    bvox_volume_destroy(v);
    return BVOX_OK;
}

static int volume_case(vol_fn fn)
{
    CHECK(make_fixture() == 0);
    CHECK_OK(fn(fixture, &result));
    vfn = fn;
    SWEEP(op_volume, NULL);
    bvox_volume_destroy(result);
    bvox_volume_destroy(fixture);
    return 0;
}

static bvox_status dilate6(const bvox_volume *in, bvox_volume **out) { return bvox_morph_dilate(in, 6, out); }
static bvox_status erode26(const bvox_volume *in, bvox_volume **out) { return bvox_morph_erode(in, 26, out); }
static bvox_status dilate_ball(const bvox_volume *in, bvox_volume **out) { return bvox_morph_dilate_ball(in, 2.5, out); }
static bvox_status erode_ball(const bvox_volume *in, bvox_volume **out) { return bvox_morph_erode_ball(in, 1.8, out); }
static bvox_status open18(const bvox_volume *in, bvox_volume **out) { return bvox_morph_open(in, 18, 0, out); }
static bvox_status close_ball(const bvox_volume *in, bvox_volume **out) { return bvox_morph_close(in, 0, 2.0, out); }
static bvox_status fill_holes(const bvox_volume *in, bvox_volume **out) { return bvox_morph_fill_holes(in, out); }
static bvox_status hollow(const bvox_volume *in, bvox_volume **out) { return bvox_morph_hollow(in, 1.5, out); }
static bvox_status islands(const bvox_volume *in, bvox_volume **out) { return bvox_morph_remove_islands(in, 6, 2, out); }
static bvox_status copy(const bvox_volume *in, bvox_volume **out) { return bvox_volume_copy(in, out); }
static bvox_status crop(const bvox_volume *in, bvox_volume **out)
{
    return bvox_volume_crop(in, (bvox_box){1, 2, 3, 20, 17, 69}, out);
}
static bvox_status pad(const bvox_volume *in, bvox_volume **out)
{
    const int32_t before[3] = {1, 2, 3}, after[3] = {3, 2, 60};
    return bvox_volume_pad(in, before, after, out);
}
static bvox_status keep_largest(const bvox_volume *in, bvox_volume **out)
{
    bvox_components *c;
    *out = NULL;
    bvox_status st = bvox_components_find(in, 26, &c);
    if (st) return st;
    st = bvox_components_keep(c, 1, out);
    bvox_components_destroy(c);
    return st;
}
static bvox_status csg_expr(const bvox_volume *in, bvox_volume **out)
{
    (void)in;
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = (bvox_dims){21, 18, 70};
    return bvox_csg_eval("(sphere(r=6) - box(size=3)) ^ ~cylinder(r=2, h=30) + "
                         "torus(R=5, r=1.5, at=10,9,20) * halfspace(n=1,0,0, d=-8)",
                         &o, out);
}
static bvox_status cut(const bvox_volume *in, bvox_volume **out)
{
    bvox_status st = bvox_volume_copy(in, out);
    if (st) return st;
    st = bvox_cut_plane(*out, 1, 0.5, 0.25, -20, 1, NULL);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

TEST(morph_dilate) { return volume_case(dilate6); }
TEST(morph_erode) { return volume_case(erode26); }
TEST(morph_dilate_ball) { return volume_case(dilate_ball); }
TEST(morph_erode_ball) { return volume_case(erode_ball); }
TEST(morph_open) { return volume_case(open18); }
TEST(morph_close) { return volume_case(close_ball); }
TEST(morph_fill_holes) { return volume_case(fill_holes); }
TEST(morph_hollow) { return volume_case(hollow); }
TEST(morph_remove_islands) { return volume_case(islands); }
TEST(volume_copy_crop_pad)
{
    if (volume_case(copy)) return 1;
    if (volume_case(crop)) return 1;
    return volume_case(pad);
}
TEST(components_keep) { return volume_case(keep_largest); }
TEST(csg_eval) { return volume_case(csg_expr); }
TEST(cut_plane) { return volume_case(cut); }

static bvox_status op_measure(void)
{
    bvox_measures m;
    bvox_status st = bvox_measure(fixture, &m);
    if (st) return st;
    OP_CHECK(m.count == fixture_count);
    bvox_measures *per = (bvox_measures *)1;
    int64_t n = -1;
    st = bvox_measure_components(fixture, 6, &per, &n);
    OUT_IS_NULL(st, per);
    if (st) return st;
    OP_CHECK(n == 3);
    OP_CHECK(per[0].count + per[1].count + per[2].count == fixture_count);
    bvox_free(per);
    bvox_info info;
    st = bvox_info_compute(fixture, &info);
    if (st) return st;
    return BVOX_OK;
}

TEST(measure)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_measure, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

static bvox_status op_components(void)
{
    bvox_components *c = (bvox_components *)1;
    bvox_status st = bvox_components_find(fixture, 6, &c);
    OUT_IS_NULL(st, c);
    if (st) return st;
    OP_CHECK(bvox_components_count(c) == 3);
    bvox_components_destroy(c);
    return BVOX_OK;
}

TEST(components)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_components, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

/* ---------------------------------------------------------------- meshes */

static bvox_mesh_method mmethod;
static int64_t mesh_nt;

static bvox_status op_mesh(void)
{
    bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
    o.method = mmethod;
    o.smooth = 2;
    bvox_mesh *m = (bvox_mesh *)1;
    bvox_status st = bvox_mesh_from_volume(fixture, &o, &m);
    OUT_IS_NULL(st, m);
    if (st) return st;
    bvox_mesh_info info;
    st = bvox_mesh_measure(m, &info);
    if (st == BVOX_OK) OP_CHECK(m->ntriangles == mesh_nt && info.watertight);
    bvox_mesh_destroy(m);
    return st;
}

static int mesh_case(bvox_mesh_method method)
{
    CHECK(make_fixture() == 0);
    bvox_mesh *m;
    bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
    o.method = method;
    CHECK_OK(bvox_mesh_from_volume(fixture, &o, &m));
    mesh_nt = m->ntriangles;
    bvox_mesh_destroy(m);
    mmethod = method;
    SWEEP(op_mesh, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

TEST(mesh_marching_cubes) { return mesh_case(BVOX_MESH_MC); }
TEST(mesh_cuberille) { return mesh_case(BVOX_MESH_CUBERILLE); }

static bvox_mesh *mesh;
static const char *mformat;
static int mascii;

static bvox_status op_mesh_write(void)
{
    char name[32];
    snprintf(name, sizeof name, "m.%s", mformat);
    bvox_status st = bvox_mesh_write(in_out(wdir, name), mesh, mformat, mascii);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 1);
    return st;
}

static bvox_status op_mesh_read(void)
{
    bvox_mesh *m = (bvox_mesh *)1;
    bvox_status st = bvox_mesh_read(rpath, mformat, &m);
    OUT_IS_NULL(st, m);
    if (st) return st;
    OP_CHECK(m->ntriangles == mesh->ntriangles);
    bvox_mesh_destroy(m);
    return BVOX_OK;
}

static bvox_status op_voxelize(void)
{
    bvox_voxelize_opts o = {0};
    o.voxel_size = 1.0;
    bvox_volume *v = (bvox_volume *)1;
    bvox_voxelize_report rep;
    bvox_status st = bvox_mesh_voxelize(mesh, &o, &v, &rep);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(rep.closed && bvox_volume_count(v) == fixture_count);
    bvox_volume_destroy(v);
    return BVOX_OK;
}

TEST(mesh_files_and_voxelize)
{
    static const char *formats[] = {"stl", "ply", "obj", "off"};
    CHECK(make_fixture() == 0);
    bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
    mo.method = BVOX_MESH_CUBERILLE;
    CHECK_OK(bvox_mesh_from_volume(fixture, &mo, &mesh));
    SWEEP(op_voxelize, NULL);
    for (int f = 0; f < 4; f++) {
        for (mascii = 0; mascii <= 1; mascii++) {
            mformat = formats[f];
            wdir = outdir("out");
            SWEEP(op_mesh_write, wdir);
            char name[32];
            snprintf(name, sizeof name, "m.%s", mformat);
            CHECK_OK(bvox_mesh_write(in_out(wdir, name), mesh, mformat, mascii));
            rpath = in_out(wdir, name);
            SWEEP(op_mesh_read, NULL);
        }
    }
    bvox_mesh_destroy(mesh);
    bvox_volume_destroy(fixture);
    return 0;
}

/* -------------------------------------------------------------- contours */

static bvox_contour_stack *stack;

/* Same sections, contours, points, holes and nesting (an absorbed failure
 * must not change the answer). */
static int same_stack(const bvox_contour_stack *a, const bvox_contour_stack *b)
{
    if (a->nsections != b->nsections) return 0;
    for (int32_t i = 0; i < a->nsections; i++) {
        const bvox_section *p = &a->sections[i], *q = &b->sections[i];
        if (p->ncontours != q->ncontours || p->nmarkers != q->nmarkers) return 0;
        for (int32_t k = 0; k < p->ncontours; k++) {
            const bvox_contour *c = &p->contours[k], *d = &q->contours[k];
            if (c->npoints != d->npoints || c->hole != d->hole || c->parent != d->parent ||
                memcmp(c->points, d->points, (size_t)c->npoints * sizeof *c->points))
                return 0;
        }
    }
    return 1;
}

static bvox_status op_to_contours(void)
{
    bvox_contour_stack *s = (bvox_contour_stack *)1;
    bvox_status st = bvox_volume_to_contours(fixture, 2, &s);
    OUT_IS_NULL(st, s);
    if (st) return st;
    OP_CHECK(same_stack(s, stack));
    bvox_stack_destroy(s);
    return BVOX_OK;
}

static bvox_status op_stack_to_volume(void)
{
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    bvox_volume *v = (bvox_volume *)1;
    bvox_status st = bvox_stack_to_volume(stack, &o, &v);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(bvox_volume_equal(v, result));
    bvox_volume_destroy(v);
    return BVOX_OK;
}

static int svg_dir;

static bvox_status op_stack_write(void)
{
    bvox_status st = svg_dir ? bvox_stack_write_svg_dir(in_out(wdir, "svg"), stack)
                             : bvox_stack_write_json(in_out(wdir, "s.json"), stack);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 1);
    return st;
}

static bvox_contour_stack *read_back; /* what the reader gives without faults */

static bvox_status op_stack_read(void)
{
    bvox_contour_stack *s = (bvox_contour_stack *)1;
    bvox_status st = bvox_stack_read(rpath, &s);
    OUT_IS_NULL(st, s);
    if (st) return st;
    OP_CHECK(same_stack(s, read_back));
    bvox_stack_destroy(s);
    return BVOX_OK;
}

TEST(contours)
{
    CHECK(make_fixture() == 0);
    CHECK_OK(bvox_volume_to_contours(fixture, 2, &stack));
    CHECK(stack->nsections > 10);
    SWEEP(op_to_contours, NULL);
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    CHECK_OK(bvox_stack_to_volume(stack, &o, &result));
    SWEEP(op_stack_to_volume, NULL);
    bvox_volume_destroy(result);
    for (svg_dir = 0; svg_dir <= 1; svg_dir++) {
        wdir = outdir("out");
        SWEEP(op_stack_write, wdir);
        CHECK_OK(op_stack_write());
        rpath = in_out(wdir, svg_dir ? "svg" : "s.json");
        CHECK_OK(bvox_stack_read(rpath, &read_back));
        CHECK(read_back->nsections == stack->nsections);
        SWEEP(op_stack_read, NULL);
        bvox_stack_destroy(read_back);
    }
    bvox_stack_destroy(stack);
    bvox_volume_destroy(fixture);
    return 0;
}

/* --------------------------------------------------------- reconstruction */

static const char *recon_in;

static bvox_status op_reconstruct(void)
{
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    o.min_area = 4;
    bvox_volume *v = (bvox_volume *)1;
    bvox_contour_stack *s = (bvox_contour_stack *)1;
    bvox_recon_report *r = (bvox_recon_report *)1;
    bvox_status st = bvox_reconstruct(&recon_in, 1, &o, &v, &s, &r);
    OUT_IS_NULL(st, v);
    OUT_IS_NULL(st, s);
    OUT_IS_NULL(st, r);
    if (st) return st;
    OP_CHECK(r->nsections == 4 && r->aligned && bvox_volume_count(v) > 0);
    OP_CHECK(bvox_volume_equal(v, result));
    bvox_volume_destroy(v);
    bvox_stack_destroy(s);
    bvox_recon_report_destroy(r);
    return BVOX_OK;
}

/* Four 80 x 64 sections: a dark disc shrinking section by section and three
 * dark marker dots, shifted a little from section to section. */
static int write_sections(const char *dir)
{
    for (int k = 0; k < 4; k++) {
        bvox_image *img;
        CHECK_OK(bvox_image_create(80, 64, 1, 8, &img));
        double dx = k, dy = -0.5 * k, r = 14 - 2 * k;
        const double mk[3][2] = {{8, 8}, {70, 10}, {12, 56}};
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 80; x++) {
                double px = x + 0.5 - dx, py = y + 0.5 - dy;
                int dark = hypot(px - 40, py - 32) <= r;
                for (int m = 0; m < 3; m++) dark |= hypot(px - mk[m][0], py - mk[m][1]) <= 2.5;
                img->pixels[y * 80 + x] = dark ? 30 : 220;
            }
        char name[32];
        snprintf(name, sizeof name, "s%d.png", k + 1);
        CHECK_OK(bvox_image_write_png(img, in_out(dir, name)));
        bvox_image_destroy(img);
    }
    return 0;
}

TEST(reconstruct)
{
    recon_in = outdir("sections");
    CHECK(write_sections(recon_in) == 0);
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    o.min_area = 4;
    CHECK_OK(bvox_reconstruct(&recon_in, 1, &o, &result, NULL, NULL));
    SWEEP(op_reconstruct, NULL);
    bvox_volume_destroy(result);
    return 0;
}

/* ---------------------------------------------------------------- render */

static bvox_render_opts ropt;
static bvox_image *rimage;

static int same_image(const bvox_image *a, const bvox_image *b)
{
    return a->width == b->width && a->height == b->height && a->channels == b->channels &&
           a->bits == b->bits && a->bits == 8 &&
           !memcmp(a->pixels, b->pixels, (size_t)a->width * a->height * a->channels);
}

static bvox_status op_render(void)
{
    bvox_image *img = (bvox_image *)1;
    bvox_preimage *pre = (bvox_preimage *)1;
    bvox_status st = bvox_render(fixture, &ropt, &img, &pre);
    OUT_IS_NULL(st, img);
    OUT_IS_NULL(st, pre);
    if (st) return st;
    OP_CHECK(same_image(img, rimage));
    bvox_image_destroy(img);
    bvox_preimage_destroy(pre);
    return BVOX_OK;
}

static int render_case(const char *view, int cut, bvox_stereo stereo)
{
    CHECK(make_fixture() == 0);
    ropt = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view(view, &ropt));
    ropt.zoom = 2;
    ropt.average = 1;
    ropt.filter = 0;
    ropt.cut = cut;
    ropt.plane[0] = 1; ropt.plane[3] = -10;
    ropt.stereo = stereo;
    if (!ropt.axis_view || stereo) ropt.proj.width = ropt.proj.height = 48;
    CHECK_OK(bvox_render(fixture, &ropt, &rimage, NULL));
    SWEEP(op_render, NULL);
    bvox_image_destroy(rimage);
    bvox_volume_destroy(fixture);
    return 0;
}

TEST(render_axis) { return render_case("+z", 0, BVOX_STEREO_NONE); }
TEST(render_axis_cut) { return render_case("-x", 1, BVOX_STEREO_NONE); }
TEST(render_projection_cut) { return render_case("iso", 1, BVOX_STEREO_NONE); }
TEST(render_stereo) { return render_case("30,20", 0, BVOX_STEREO_SBS); }

/* issue 18: the shading modes with per-pixel normals, the depth cues and
 * supersampling, through every allocation they make (the moment caches'
 * failures are absorbed: the same picture, only slower) */
static int render_shading_case(const char *view, bvox_shade_mode shade, int cues)
{
    CHECK(make_fixture() == 0);
    ropt = bvox_render_opts_default();
    CHECK_OK(bvox_render_parse_view(view, &ropt));
    ropt.shade = shade;
    ropt.cut = 1;
    ropt.plane[0] = 1; ropt.plane[3] = -10;
    ropt.ao = ropt.shadows = cues;
    ropt.supersample = cues ? 2 : 0;
    if (!ropt.axis_view) ropt.proj.width = ropt.proj.height = 24;
    CHECK_OK(bvox_render(fixture, &ropt, &rimage, NULL));
    SWEEP(op_render, NULL);
    bvox_image_destroy(rimage);
    bvox_volume_destroy(fixture);
    return 0;
}
TEST(render_smooth_cues) { return render_shading_case("iso", BVOX_SHADE_SMOOTH, 1); }
TEST(render_enlarged_gradient) { return render_shading_case("+z", BVOX_SHADE_ENLARGED_GRADIENT, 0); }

static bvox_status op_sheet(void)
{
    bvox_image *img = (bvox_image *)1;
    bvox_status st = bvox_render_sheet(fixture, &ropt, &img);
    OUT_IS_NULL(st, img);
    if (st) return st;
    OP_CHECK(same_image(img, rimage));
    bvox_image_destroy(img);
    return BVOX_OK;
}

static bvox_status op_mosaic(void)
{
    bvox_image *img = (bvox_image *)1;
    bvox_status st = bvox_mosaic(fixture, NULL, &img);
    OUT_IS_NULL(st, img);
    if (st) return st;
    OP_CHECK(same_image(img, rimage));
    bvox_image_destroy(img);
    return BVOX_OK;
}

static const char *turn_name;

static bvox_status op_turntable(void)
{
    bvox_status st = bvox_render_turntable(fixture, &ropt, 3, in_out(wdir, turn_name));
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == (strstr(turn_name, ".gif") ? 1 : 3));
    return st;
}

static bvox_status op_png_write(void)
{
    bvox_status st = bvox_image_write_png(rimage, in_out(wdir, "i.png"));
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 1);
    return st;
}

TEST(render_sheet_mosaic_turntable)
{
    CHECK(make_fixture() == 0);
    ropt = bvox_render_opts_default();
    ropt.proj.width = ropt.proj.height = 40;
    CHECK_OK(bvox_render_sheet(fixture, &ropt, &rimage));
    SWEEP(op_sheet, NULL);
    wdir = outdir("out");
    SWEEP(op_png_write, wdir);
    bvox_image_destroy(rimage);
    CHECK_OK(bvox_mosaic(fixture, NULL, &rimage));
    SWEEP(op_mosaic, NULL);
    bvox_image_destroy(rimage);
    ropt.cut = 1;
    ropt.plane[2] = 1; ropt.plane[3] = -40;
    turn_name = "spin.gif";
    SWEEP(op_turntable, wdir);
    turn_name = "spin.png";
    SWEEP(op_turntable, wdir);
    bvox_volume_destroy(fixture);
    return 0;
}

/* ------------------------------------------------ more of the library */

static bvox_status op_demo_pictures(void)
{
    bvox_status st = bvox_demo_pictures(fixture, wdir);
    if (st == BVOX_OK) OP_CHECK(harness_count_entries(wdir) == 9); /* 4 + 2 smooth + 3 pre-image */
    return st;
}

TEST(demo_pictures)
{
    CHECK(make_fixture() == 0);
    wdir = outdir("out");
    SWEEP(op_demo_pictures, wdir);
    bvox_volume_destroy(fixture);
    return 0;
}

/* A journalled edit session: two steps, undo both, redo one. */
static bvox_status op_journal(void)
{
    bvox_volume *v;
    bvox_status st = bvox_volume_copy(fixture, &v);
    if (st) return st;
    bvox_journal *j = (bvox_journal *)1;
    st = bvox_journal_create(bvox_volume_dims(v), 0, &j);
    OUT_IS_NULL(st, j);
    const bvox_box a = {0, 0, 0, 10, 9, 40}, b = {5, 5, 30, 21, 18, 70};
    if (!st) {
        bvox_journal_begin(j);
        st = bvox_journal_record(j, v, a);
        if (!st) st = bvox_edit_fill_box(v, a, 1, NULL);
        if (!st) st = bvox_journal_sync(j, v);
        bvox_journal_end(j);
    }
    if (!st) {
        bvox_journal_begin(j);
        st = bvox_journal_record(j, v, b);
        if (!st) st = bvox_edit_keep_box(v, (bvox_box){0, 0, 0, 21, 18, 50}, NULL);
        if (!st) st = bvox_journal_sync(j, v);
        bvox_journal_end(j);
    }
    int done = 0;
    for (int k = 0; k < 2 && !st; k++) st = bvox_journal_undo(j, v, &done, NULL);
    if (!st) OP_CHECK(same_as_fixture(v));
    if (!st) st = bvox_journal_redo(j, v, &done, NULL);
    if (!st) OP_CHECK(done && bvox_volume_count(v) > fixture_count);
    bvox_journal_destroy(j == (bvox_journal *)1 ? NULL : j);
    bvox_volume_destroy(v);
    return st;
}

TEST(journal_edits)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_journal, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

/* Surface built, updated after an edit, rebuilt, cast; shaded, filtered,
 * zoomed. */
static bvox_status op_surface_images(void)
{
    bvox_volume *v;
    bvox_status st = bvox_volume_copy(fixture, &v);
    if (st) return st;
    bvox_surface *s = (bvox_surface *)1;
    st = bvox_surface_build(v, &s);
    OUT_IS_NULL(st, s);
    if (st) s = NULL;
    if (!st) st = bvox_edit_fill_box(v, (bvox_box){3, 3, 50, 9, 9, 60}, 1, NULL);
    if (!st) st = bvox_surface_update(s, v, (bvox_box){3, 3, 50, 9, 9, 60});
    if (!st) st = bvox_surface_rebuild(s, v);
    bvox_preimage *pre = NULL;
    bvox_projection proj = BVOX_PROJECTION_INIT;
    proj.azimuth = 30, proj.elevation = 20, proj.width = 40, proj.height = 36;
    if (!st) st = bvox_surface_cast(s, &proj, &pre);
    bvox_image *img[6] = {NULL};
    bvox_light light = BVOX_LIGHT_INIT;
    const int32_t k[9] = {0, -1, 0, -1, 5, -1, 0, -1, 0};
    if (!st) st = bvox_shade_gradient(pre, BVOX_GRADIENT_SOBEL, &light, &img[0]);
    if (!st) st = bvox_image_colormap(img[0], BVOX_CMAP_BONE, &img[1]);
    if (!st) st = bvox_image_zoom(img[1], 2, &img[2]);
    if (!st) st = bvox_image_zoom2_average(img[2], &img[3]);
    if (!st) st = bvox_image_convolve(img[3], k, 1, 0, &img[4]);
    if (!st) st = bvox_image_pan(img[4], 3, -2, &img[5]);
    if (!st) OP_CHECK(img[5]->width == 160 && img[5]->channels == 3);
    for (int i = 0; i < 6; i++) bvox_image_destroy(img[i]);
    bvox_preimage_destroy(pre);
    bvox_surface_destroy(s);
    bvox_volume_destroy(v);
    return st;
}

TEST(surface_and_image_ops)
{
    CHECK(make_fixture() == 0);
    SWEEP(op_surface_images, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

/* CSG with file operands (read through bvox_read) and a placement. */
static bvox_status op_csg_files(void)
{
    bvox_volume *v = (bvox_volume *)1;
    char expr[4096];
    snprintf(expr, sizeof expr, "'%s' - '%s' @ 2,1,3 + sphere(r=3)", rpath, rpath);
    bvox_status st = bvox_csg_eval(expr, NULL, &v);
    OUT_IS_NULL(st, v);
    if (st) return st;
    OP_CHECK(bvox_volume_check(v) == BVOX_OK && bvox_volume_count(v) > 0);
    bvox_volume_destroy(v);
    return BVOX_OK;
}

TEST(csg_eval_files)
{
    CHECK(make_fixture() == 0);
    wdir = outdir("in");
    rpath = in_out(wdir, "a.nii.gz");
    CHECK_OK(bvox_write(rpath, fixture, NULL));
    SWEEP(op_csg_files, NULL);
    bvox_volume_destroy(fixture);
    return 0;
}

/* A gray 16-bit NIfTI (a label map) read with Otsu and with a label. */
TEST(nifti_gray_binarize)
{
    CHECK(make_fixture() == 0);
    size_t n = (size_t)21 * 18 * 70;
    labels = (uint32_t *)bvox__mem_zalloc(n, sizeof *labels);
    CHECK(labels != NULL);
    bvox_components *c;
    CHECK_OK(bvox_components_find(fixture, 6, &c));
    CHECK_EQ(bvox_components_count(c), 3);
    bvox_components_labels(c, labels);
    bvox_components_destroy(c);
    wdir = outdir("in");
    rpath = in_out(wdir, "labels.nii.gz");
    CHECK_OK(bvox_write_labels_nifti(rpath, fixture, labels));
    free(labels);
    ropts = (bvox_read_opts)BVOX_READ_OPTS_INIT;
    ropts.binarize.mode = BVOX_BIN_OTSU;
    SWEEP(op_read, NULL); /* labels 1..3 against 0: Otsu splits at 0 */
    CHECK(load_file(rpath) == 0);
    ropts.format = "nifti";
    SWEEP(op_read_memory, NULL);
    free(mem_data);
    bvox_volume_destroy(fixture);
    return 0;
}

/* A RECONSTRUCT series (NAME.ser and its section files NAME.1, NAME.2). */
static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    CHECK(fputs(text, f) >= 0);
    CHECK(fclose(f) == 0);
    return 0;
}

static int series_sections;

static bvox_status op_series(void)
{
    bvox_contour_stack *s = (bvox_contour_stack *)1;
    bvox_status st = bvox_stack_read(rpath, &s);
    OUT_IS_NULL(st, s);
    if (st) return st;
    OP_CHECK(s->nsections == series_sections && s->sections[0].ncontours == 2);
    OP_CHECK(same_stack(s, read_back));
    bvox_stack_destroy(s);
    return BVOX_OK;
}

TEST(reconstruct_series)
{
    wdir = outdir("series");
    CHECK(write_text(in_out(wdir, "rec.ser"), "<?xml version=\"1.0\"?>\n"
                     "<Series index=\"1\" viewport=\"0 0 0.00254\"/>\n") == 0);
    CHECK(write_text(in_out(wdir, "rec.1"), "<?xml version=\"1.0\"?>\n"
                     "<Section index=\"1\" thickness=\"0.05\">\n"
                     "<Transform dim=\"1\" xcoef=\" 0.5 1 0 0 0 0\" ycoef=\" 0.25 0 1 0 0 0\">\n"
                     "<Contour name=\"d001\" closed=\"true\" points=\"1 1, 2 1, 2 2, 1 2,\"/>\n"
                     "<Contour name=\"d002\" closed=\"true\" points=\"4 4, 6 4, 6 6, 4 6,\"/>\n"
                     "<Contour name=\"marker1\" points=\"3.5 3.25, 3.7 3.25, 3.6 3.45\"/>\n"
                     "</Transform></Section>\n") == 0);
    CHECK(write_text(in_out(wdir, "rec.2"), "<Section index=\"2\" thickness=\"0.05\">\n"
                     "<Transform dim=\"0\" xcoef=\" 0 1 0 0 0 0\" ycoef=\" 0 0 1 0 0 0\">\n"
                     "<Contour name=\"d001\" points=\"2 2, 4 2, 4 4, 2 4\"/>\n"
                     "</Transform></Section>\n") == 0);
    series_sections = 2;
    rpath = in_out(wdir, "rec.ser");
    CHECK_OK(bvox_stack_read(rpath, &read_back));
    SWEEP(op_series, NULL);
    bvox_stack_destroy(read_back);
    return 0;
}
