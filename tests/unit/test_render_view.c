/* test_render_view.c — arbitrary parallel projections (splatting boundary
 * voxels) against a brute-force reference written here: every pixel's centre
 * ray clipped against every 1-voxel's box, the frame and the fit computed from
 * the formulas documented in bvox.h. Also: the az 0 / el 0 view equals the +z
 * axis view, results do not depend on the thread count, the boundary count,
 * bad input and allocation failures. */
#include "harness.h"
#include "ref/voxref.h"
#include "render/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct ref_view {
    int w, h;
    double r[3], dn[3], d[3], c[3], rho, scale;
} ref_view;

static void ref_setup(const voxref *v, const double sp[3], double az, double el, int w, int h,
                      ref_view *rv)
{
    const double k = 3.14159265358979323846 / 180.0;
    az *= k, el *= k;
    double d[3] = {sin(az) * cos(el), sin(el), cos(az) * cos(el)}, r[3] = {cos(az), 0, -sin(az)};
    memcpy(rv->d, d, sizeof d);
    memcpy(rv->r, r, sizeof r);
    rv->dn[0] = d[1] * r[2] - d[2] * r[1];
    rv->dn[1] = d[2] * r[0] - d[0] * r[2];
    rv->dn[2] = d[0] * r[1] - d[1] * r[0];
    bvox_box b;
    voxref_bbox(v, &b);
    const int32_t *lo = &b.x0, *hi = &b.x1;
    double e2 = 0;
    for (int a = 0; a < 3; a++) {
        rv->c[a] = (lo[a] + hi[a] - 1) * 0.5 * sp[a];
        e2 += pow((hi[a] - lo[a]) * sp[a], 2);
    }
    rv->rho = 0.5 * sqrt(e2);
    rv->w = w, rv->h = h;
    rv->scale = (w < h ? w : h) / (2 * rv->rho);
}

/* Depth (pixel units from the sphere's front) of the first voxel on the ray of
 * pixel (px, py), -1 if none; *idx gets its normal index. */
static double ref_ray(const voxref *v, const double sp[3], const ref_view *rv, int px, int py,
                      int *idx)
{
    double u = (px + 0.5 - rv->w * 0.5) / rv->scale, vv = (py + 0.5 - rv->h * 0.5) / rv->scale;
    double o[3];
    for (int a = 0; a < 3; a++) o[a] = rv->c[a] + u * rv->r[a] + vv * rv->dn[a] - rv->rho * rv->d[a];
    double best = INFINITY;
    for (int z = 0; z < v->nz; z++)
        for (int y = 0; y < v->ny; y++)
            for (int x = 0; x < v->nx; x++) {
                if (!voxref_get(v, x, y, z)) continue;
                const int p[3] = {x, y, z};
                double t0 = -INFINITY, t1 = INFINITY;
                for (int a = 0; a < 3; a++) {
                    double lo = (p[a] - 0.5) * sp[a] - o[a], hi = (p[a] + 0.5) * sp[a] - o[a];
                    if (fabs(rv->d[a]) < 1e-12) {
                        if (lo > 0 || hi <= 0) t0 = INFINITY;
                        continue;
                    }
                    double a0 = lo / rv->d[a], a1 = hi / rv->d[a];
                    if (a0 > a1) { double t = a0; a0 = a1; a1 = t; }
                    if (a0 > t0) t0 = a0;
                    if (a1 < t1) t1 = a1;
                }
                if (t0 <= t1 && t0 < best) {
                    best = t0;
                    int n[3] = {voxref_get(v, x - 1, y, z) - voxref_get(v, x + 1, y, z),
                                voxref_get(v, x, y - 1, z) - voxref_get(v, x, y + 1, z),
                                voxref_get(v, x, y, z - 1) - voxref_get(v, x, y, z + 1)};
                    *idx = (n[0] + 1) * 9 + (n[1] + 1) * 3 + n[2] + 1;
                }
            }
    return isinf(best) ? -1 : best * rv->scale;
}

/* zoom > 0: that many times the fitting scale (footprints of many pixels,
 * the object clipped by the image edges) */
static int compare_with_ref(const voxref *v, const double sp[3], double az, double el, int w, int h,
                            double zoom)
{
    ref_view rv;
    ref_setup(v, sp, az, el, w, h, &rv);
    if (zoom > 0) rv.scale *= zoom;
    bvox_volume *vol = voxref_to_volume(v);
    CHECK(vol != NULL);
    CHECK_OK(bvox_volume_set_spacing(vol, sp[0], sp[1], sp[2], NULL));
    bvox_projection pr = BVOX_PROJECTION_INIT;
    pr.azimuth = az, pr.elevation = el, pr.width = w, pr.height = h;
    pr.scale = zoom > 0 ? rv.scale : 0;
    bvox_preimage *p;
    CHECK_OK(bvox_cast_projection(vol, &pr, &p));
    bvox_volume_destroy(vol);
    CHECK_NEAR(p->depth_step, 1 / rv.scale, 1e-9);
    double maxsp = fmax(sp[0], fmax(sp[1], sp[2]));
    int cover_diff = 0, code_diff = 0, hits = 0;
    for (int py = 0; py < h; py++)
        for (int px = 0; px < w; px++) {
            int idx = -1;
            double want = ref_ray(v, sp, &rv, px, py, &idx);
            int got = p->depth[py * w + px];
            if ((want < 0) != (got < 0)) {
                cover_diff++;
                continue;
            }
            if (want < 0) continue;
            hits++;
            /* within one voxel (in practice within one depth unit) */
            if (fabs(got - want) * p->depth_step > maxsp || fabs(got - want) > 1.0) {
                fprintf(stderr, "az %g el %g pixel (%d, %d): depth %d, reference %.3f\n", az, el,
                        px, py, got, want);
                return 1;
            }
            code_diff += (p->code[py * w + px] & 31) != idx;
        }
    bvox_preimage_destroy(p);
    if (getenv("RENDER_VERBOSE")) fprintf(stderr, "az %g el %g: cover %d code %d hits %d\n", az, el, cover_diff, code_diff, hits);
    /* rays grazing a voxel edge may go either way */
    if (cover_diff > w * h / 200 || code_diff > hits / 50 || hits < w * h / 25) {
        fprintf(stderr, "az %g el %g: %d coverage and %d code differences, %d hits\n", az, el,
                cover_diff, code_diff, hits);
        return 1;
    }
    return 0;
}

TEST(projection_matches_reference)
{
    static const double angles[][2] = {{0, 0},  {30, 20},  {-75, 40}, {180, -10},
                                       {90, 0}, {45, 35.264}, {123, -67}};
    const double iso[3] = {1, 1, 1}, thick[3] = {1, 0.8, 2.5};
    /* a random blob (density 0.35) and a sphere with a box cut out */
    voxref *rnd = voxref_create(9, 7, 11);
    voxref_random(rnd, 35, 100, harness_rand);
    voxref *sph = voxref_create(14, 12, 13);
    for (int z = 0; z < 13; z++)
        for (int y = 0; y < 12; y++)
            for (int x = 0; x < 14; x++)
                *voxref_at(sph, x, y, z) = (x - 6.5) * (x - 6.5) + (y - 5.5) * (y - 5.5) +
                                               (z - 6) * (z - 6) <= 30 &&
                                           !(x > 7 && y < 5);
    for (int a = 0; a < 7; a++) {
        CHECK_EQ(compare_with_ref(rnd, iso, angles[a][0], angles[a][1], 72, 64, 0), 0);
        CHECK_EQ(compare_with_ref(sph, thick, angles[a][0], angles[a][1], 64, 72, 0), 0);
    }
    CHECK_EQ(compare_with_ref(rnd, iso, 20, 30, 64, 64, 3.0), 0);
    CHECK_EQ(compare_with_ref(sph, thick, -40, 15, 64, 64, 2.5), 0);
    voxref_destroy(rnd);
    voxref_destroy(sph);
    return 0;
}

TEST(projection_front_equals_axis_view)
{
    voxref *r = voxref_create(16, 12, 20);
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *vol = voxref_to_volume(r);
    bvox_box b;
    CHECK(voxref_bbox(r, &b));
    CHECK(b.x0 == 0 && b.y0 == 0 && b.z0 == 0 && b.x1 == 16 && b.y1 == 12 && b.z1 == 20);
    voxref_destroy(r);
    bvox_projection pr = BVOX_PROJECTION_INIT;
    pr.width = 16, pr.height = 12, pr.scale = 1;
    bvox_preimage *p, *q;
    CHECK_OK(bvox_cast_projection(vol, &pr, &p));
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, &q));
    /* entry at z - 0.5, measured from the sphere front at c_z - rho */
    int offset = (int)floor(0.5 * sqrt(16 * 16 + 12 * 12 + 20 * 20) - 9.5 - 0.5);
    for (int i = 0; i < 16 * 12; i++) {
        CHECK_EQ(p->depth[i] < 0, q->depth[i] < 0);
        if (q->depth[i] < 0) continue;
        CHECK_EQ(p->depth[i], q->depth[i] + offset);
        CHECK_EQ(p->code[i] & 31, q->code[i] & 31);
    }
    /* the same through an explicit matrix (rows right, down, view), here
     * given unnormalised */
    pr.use_matrix = 1;
    const double m[9] = {2, 0, 0, 0, 3, 0, 0, 0, 0.5};
    memcpy(pr.matrix, m, sizeof m);
    bvox_preimage *p2;
    CHECK_OK(bvox_cast_projection(vol, &pr, &p2));
    CHECK(memcmp(p2->depth, p->depth, 16 * 12 * 4) == 0);
    CHECK(memcmp(p2->code, p->code, 16 * 12) == 0);
    bvox_preimage_destroy(p2);
    bvox_preimage_destroy(p);
    bvox_preimage_destroy(q);
    bvox_volume_destroy(vol);
    return 0;
}

/* The banded path (several threads, enough front-facing voxels to bucket)
 * against the brute-force reference directly, not only through the
 * single-thread cast: a random blob of about 21 000 1-voxels, 3 and 16
 * threads, a fitted view and a zoomed one (the reference's depth tolerance
 * needs pixels no larger than voxels). */
TEST(projection_banded_matches_reference)
{
    const double iso[3] = {1, 1, 1};
    voxref *rnd = voxref_create(40, 38, 40);
    voxref_random(rnd, 35, 100, harness_rand);
    bvox_volume *vol = voxref_to_volume(rnd);
    bvox_surface *s;
    CHECK_OK(bvox_surface_build(vol, &s));
    CHECK(bvox_surface_count(s) > 20000); /* enough to bucket (16384 front-facing) */
    bvox_surface_destroy(s);
    bvox_volume_destroy(vol);
    int saved = bvox_threads();
    bvox_set_threads(3);
    CHECK_EQ(compare_with_ref(rnd, iso, 30, 20, 70, 72, 0), 0);
    bvox_set_threads(16);
    CHECK_EQ(compare_with_ref(rnd, iso, -110, 55, 48, 40, 2.5), 0);
    bvox_set_threads(saved);
    voxref_destroy(rnd);
    return 0;
}

/* Casts s with every projection of a list at 1 thread (one z-buffer, every
 * entry splatted in turn: the path projection_matches_reference checks) and
 * at 2, 3 and 16 threads (entries bucketed by bands of rows, each band
 * splatted alone), each at every SIMD level this CPU has (the AVX2 splat
 * kernel does the portable one's arithmetic four pixels at a time): the
 * pre-images must be identical to the portable kernel's at 1 thread. */
static int cast_thread_independent(const bvox_surface *s)
{
    static const struct { double az, el, scale; int w, h, matrix; } views[] = {
        {33, 21, 0, 150, 130, 0},   {0, 0, 0, 97, 301, 0},   {-120, 64, 0, 1024, 40, 0},
        {200, -35, 3.7, 200, 180, 0}, {45, 35.264, 0, 7, 5, 0}, {0, 0, 0, 128, 128, 1},
        {10, 80, 0.4, 333, 257, 0}};
    const int threads[] = {2, 3, 16};
    int saved = bvox_threads();
    bvox_simd saved_simd = bvox_simd_active();
    for (size_t k = 0; k < sizeof views / sizeof *views; k++) {
        bvox_projection pr = BVOX_PROJECTION_INIT;
        pr.azimuth = views[k].az, pr.elevation = views[k].el, pr.scale = views[k].scale;
        pr.width = views[k].w, pr.height = views[k].h;
        if (views[k].matrix) { /* view along x, rows along z: parallel axes */
            const double m[9] = {0, 0, 1, 0, 1, 0, 1, 0, 0};
            pr.use_matrix = 1;
            memcpy(pr.matrix, m, sizeof m);
        }
        size_t n = (size_t)pr.width * (size_t)pr.height;
        bvox_preimage *a, *b;
        bvox_set_threads(1);
        CHECK_OK(bvox_simd_set(BVOX_SIMD_GENERIC));
        CHECK_OK(bvox_surface_cast(s, &pr, &a));
        int64_t hits = 0;
        for (size_t i = 0; i < n; i++) hits += a->depth[i] >= 0;
        CHECK(hits > 0);
        for (int lv = BVOX_SIMD_GENERIC; lv <= BVOX_SIMD_AVX512; lv++) {
            if (!bvox_simd_supported((bvox_simd)lv)) continue;
            CHECK_OK(bvox_simd_set((bvox_simd)lv));
            for (size_t t = 0; t <= sizeof threads / sizeof *threads; t++) {
                int nt = t ? threads[t - 1] : 1;
                bvox_set_threads(nt);
                CHECK_OK(bvox_surface_cast(s, &pr, &b));
                if (memcmp(a->depth, b->depth, n * 4) || memcmp(a->code, b->code, n)) {
                    fprintf(stderr, "view %zu, simd %s, %d threads: pre-images differ\n", k,
                            bvox_simd_name((bvox_simd)lv), nt);
                    return 1;
                }
                bvox_preimage_destroy(b);
            }
        }
        CHECK_OK(bvox_simd_set(saved_simd));
        bvox_preimage_destroy(a);
    }
    bvox_set_threads(saved);
    return 0;
}

TEST(projection_thread_independent)
{
    voxref *r = voxref_create(64, 70, 66);
    voxref_random(r, 1, 2, harness_rand);
    bvox_volume *vol = voxref_to_volume(r);
    voxref_destroy(r);
    bvox_surface *s;
    CHECK_OK(bvox_surface_build(vol, &s));
    CHECK(bvox_surface_count(s) > 65536);
    CHECK_EQ(cast_thread_independent(s), 0);
    bvox_surface_destroy(s);
    /* thick sections: a sphere of anisotropic voxels */
    bvox_volume_destroy(vol);
    CHECK_OK(bvox_volume_create((bvox_dims){90, 80, 40}, &vol));
    bvox_geometry g = *bvox_volume_geometry(vol);
    g.spacing[2] = 2.5;
    CHECK_OK(bvox_volume_set_geometry(vol, &g));
    bvox_shape sph = {BVOX_SHAPE_ELLIPSOID, {45, 40, 20}, {40, 36, 18}, {0, 0, 0}, 0, 0, 0};
    CHECK_OK(bvox_shape_draw(vol, &sph, BVOX_CSG_UNION));
    CHECK_OK(bvox_surface_build(vol, &s));
    CHECK_EQ(cast_thread_independent(s), 0);
    bvox_surface_destroy(s);
    bvox_volume_destroy(vol);
    return 0;
}

/* The AAL atlas (mricron-data): a real object, bucketed over threads, gives
 * the single-threaded pre-image. */
TEST(realdata_projection_thread_independent)
{
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    bvox_volume *vol;
    CHECK_OK(bvox_read("/usr/share/mricron/templates/aal.nii.gz", &ro, &vol));
    bvox_surface *s;
    CHECK_OK(bvox_surface_build(vol, &s));
    CHECK(bvox_surface_count(s) > 65536);
    CHECK_EQ(cast_thread_independent(s), 0);
    bvox_surface_destroy(s);
    bvox_volume_destroy(vol);
    return 0;
}

/* The entries of v's surface against a brute-force list: exactly the
 * boundary voxels, each once, with its 6 neighbour bits, grouped by class in
 * class_start's ranges and in (y, x, z) order within a class. */
static int check_surface_entries(const voxref *r, const bvox_surface *s)
{
    int64_t want = 0;
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                want += voxref_get(r, x, y, z) &&
                        !(voxref_get(r, x - 1, y, z) && voxref_get(r, x + 1, y, z) &&
                          voxref_get(r, x, y - 1, z) && voxref_get(r, x, y + 1, z) &&
                          voxref_get(r, x, y, z - 1) && voxref_get(r, x, y, z + 1));
    CHECK_EQ(bvox_surface_count(s), want);
    CHECK_EQ(s->class_start[0], 0);
    CHECK_EQ(s->class_start[64], want);
    /* the runs of class k hold class_start's range of it, laid end to end */
    int64_t nruns_entries = 0;
    for (int64_t q = 0; q < s->class_run[64]; q++) nruns_entries += s->runs[q].n;
    CHECK_EQ(nruns_entries, want);
    for (unsigned k = 0; k < 64; k++) {
        int64_t in_class = 0;
        for (int64_t q = s->class_run[k]; q < s->class_run[k + 1]; q++) in_class += s->runs[q].n;
        CHECK_EQ(in_class, s->class_start[k + 1] - s->class_start[k]);
    }
    uint64_t *entries = malloc((size_t)(want ? want : 1) * sizeof *entries);
    CHECK(entries != NULL);
    bvox__surface_flatten(s, entries);
    for (unsigned k = 0; k < 64; k++)
        for (int64_t i = s->class_start[k]; i < s->class_start[k + 1]; i++) {
            uint64_t e = entries[i];
            int x = SURF_X(e), y = SURF_Y(e), z = SURF_Z(e);
            unsigned bits = (unsigned)voxref_get(r, x - 1, y, z) * NB_XM |
                            (unsigned)voxref_get(r, x + 1, y, z) * NB_XP |
                            (unsigned)voxref_get(r, x, y - 1, z) * NB_YM |
                            (unsigned)voxref_get(r, x, y + 1, z) * NB_YP |
                            (unsigned)voxref_get(r, x, y, z - 1) * NB_ZM |
                            (unsigned)voxref_get(r, x, y, z + 1) * NB_ZP;
            CHECK(voxref_get(r, x, y, z));
            CHECK_EQ(SURF_NB(e), k);
            CHECK_EQ(bits, k);
            if (i > s->class_start[k]) { /* strictly increasing: no voxel twice */
                uint64_t p = entries[i - 1];
                int64_t a = ((int64_t)SURF_Y(p) * r->nx + SURF_X(p)) * r->nz + SURF_Z(p);
                CHECK(a < ((int64_t)y * r->nx + x) * r->nz + z);
            }
        }
    free(entries);
    return 0;
}

/* Random volumes (sparse and dense, z spanning one word or several) and a
 * solid box (words that are whole faces of one class), at every SIMD level
 * and at 1, 3 and 16 threads. fill: 1-voxels per 10 at random, 0 for the box. */
TEST(surface_count)
{
    static const struct { int nx, ny, nz, fill; } cases[] = {
        {5, 7, 1, 7}, {9, 3, 64, 7}, {3, 7, 65, 7}, {11, 5, 130, 7}, {12, 10, 200, 9}, {9, 8, 150, 0},
        /* enough rows for several bands (8 rows or more each); one and two
         * columns a row (the row pass's end columns only) */
        {1, 40, 70, 7}, {2, 33, 64, 5}, {17, 45, 129, 8}, {6, 64, 1, 6},
        /* bands of more than a million voxels: each class in several
         * chunks, the chunks in several of the pool's blocks (surface.c) */
        {128, 16, 1100, 5}};
    const int threads[] = {1, 3, 16};
    int saved = bvox_threads();
    bvox_simd saved_simd = bvox_simd_active();
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        voxref *r = voxref_create(cases[k].nx, cases[k].ny, cases[k].nz);
        if (cases[k].fill)
            voxref_random(r, (unsigned)cases[k].fill, 10, harness_rand);
        else
            for (int z = 3; z < 140; z++)
                for (int y = 1; y < 7; y++)
                    for (int x = 2; x < 8; x++) *voxref_at(r, x, y, z) = 1;
        bvox_volume *vol = voxref_to_volume(r);
        for (int lv = BVOX_SIMD_GENERIC; lv <= BVOX_SIMD_AVX512; lv++) {
            if (!bvox_simd_supported((bvox_simd)lv)) continue;
            CHECK_OK(bvox_simd_set((bvox_simd)lv));
            for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
                bvox_set_threads(threads[t]);
                bvox_surface *s;
                CHECK_OK(bvox_surface_build(vol, &s));
                CHECK_EQ(check_surface_entries(r, s), 0);
                bvox_surface_destroy(s);
            }
        }
        bvox_volume_destroy(vol);
        voxref_destroy(r);
    }
    CHECK_OK(bvox_simd_set(saved_simd));
    bvox_set_threads(saved);
    return 0;
}

/* The surface keeps its build's lists (surface.c): what it holds in the
 * memory budget stays near its entries' bytes however many bands the build
 * had (one partly used 8 MiB block per band would be 64 MiB and more at 16
 * threads), and all of it comes back on destroy. */
TEST(surface_memory)
{
    const int n = 384;
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){n, n, n}, &vol));
    bvox_shape ball = {BVOX_SHAPE_SPHERE, {(n - 1) / 2.0, (n - 1) / 2.0, (n - 1) / 2.0},
                       {0, 0, 0}, {0, 0, 0}, n * 0.45, 0, 0};
    CHECK_OK(bvox_shape_draw(vol, &ball, BVOX_CSG_UNION));
    int saved = bvox_threads();
    const int threads[] = {1, 2, 16};
    for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
        bvox_set_threads(threads[t]);
        size_t before = bvox_memory_in_use();
        bvox_surface *s;
        CHECK_OK(bvox_surface_build(vol, &s));
        size_t held = bvox_memory_in_use() - before;
        size_t entries = (size_t)bvox_surface_count(s) * sizeof(uint64_t);
        CHECK(bvox_surface_count(s) > 300000);
        CHECK(held >= entries);
        CHECK(held <= entries * 3 / 2 + ((size_t)1 << 20));
        bvox_surface_destroy(s);
        CHECK_EQ(bvox_memory_in_use(), before);
    }
    bvox_set_threads(saved);
    bvox_volume_destroy(vol);
    return 0;
}

TEST(projection_errors)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){8, 8, 8}, &vol));
    bvox_preimage *p;
    /* an empty volume casts to an all-background image */
    bvox_projection pr = BVOX_PROJECTION_INIT;
    pr.width = 20, pr.height = 10;
    CHECK_OK(bvox_cast_projection(vol, &pr, &p));
    for (int i = 0; i < 200; i++) CHECK_EQ(p->depth[i], -1);
    bvox_preimage_destroy(p);
    bvox_volume_fill_box(vol, (bvox_box){2, 2, 2, 6, 6, 6}, 1);
    pr.use_matrix = 1;
    const double bad[9] = {1, 0, 0, 2, 0, 0, 0, 0, 1};
    memcpy(pr.matrix, bad, sizeof bad);
    CHECK_STATUS(bvox_cast_projection(vol, &pr, &p), BVOX_EINVAL);
    CHECK(p == NULL);
    pr = (bvox_projection)BVOX_PROJECTION_INIT;
    pr.scale = -1;
    CHECK_STATUS(bvox_cast_projection(vol, &pr, &p), BVOX_EINVAL);
    pr.scale = 0, pr.width = -5;
    CHECK_STATUS(bvox_cast_projection(vol, &pr, &p), BVOX_EINVAL);
    pr.width = 0, pr.azimuth = NAN;
    CHECK_STATUS(bvox_cast_projection(vol, &pr, &p), BVOX_EINVAL);
    pr.azimuth = 10;
    pr.scale = 1e12; /* absurd zoom: one voxel fills everything, no overflow */
    CHECK_OK(bvox_cast_projection(vol, &pr, &p));
    bvox_preimage_destroy(p);
    pr.scale = 0;
    for (long k = 1; k <= 6; k++) {
        bvox__alloc_fail_after(k);
        bvox_status st = bvox_cast_projection(vol, &pr, &p);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            bvox_preimage_destroy(p);
            continue;
        }
        CHECK_EQ(st, BVOX_ENOMEM);
        CHECK(p == NULL);
    }
    bvox_volume_destroy(vol);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
