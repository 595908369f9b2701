/* test_contours.c — the contour stack model (contour_stack.c), scan
 * conversion (contour_scan.c) against a per-pixel exact reference, the signed
 * distance map (contour_edt.c) against brute force, and bvox_stack_to_volume
 * (stack_volume.c): nearest-section copies, shape-based interpolation of
 * concentric discs, extents, geometry, threads, errors. */
#include "harness.h"
#include "recon/contour_internal.h"
#include "ref/contourref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int64_t rnd(int64_t lo, int64_t hi) /* inclusive */
{
    return lo + (int64_t)(harness_rand() % (uint64_t)(hi - lo + 1));
}

TEST(stack_model)
{
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_create(&s));
    CHECK(s->pixel == 1 && s->spacing == 1 && s->nsections == 0 && s->unit[0] == 0);
    bvox_point2 tri[3] = {{0, 0}, {4, 0}, {0, 3}};
    for (int i = 0; i < 40; i++) { /* many appends: growth */
        bvox_section *sec = NULL;
        CHECK_OK(bvox_stack_add_section(s, i * 2.5, i % 2 ? "name" : NULL, &sec));
        CHECK(sec == &s->sections[i]);
        for (int c = 0; c < i % 7; c++) CHECK_OK(bvox_section_add_contour(sec, tri, 3, c > 0, c > 0 ? 0 : -1));
        for (int m = 0; m < i % 5; m++) CHECK_OK(bvox_section_add_marker(sec, (bvox_point2){m, -m}));
    }
    CHECK_EQ(s->nsections, 40);
    for (int i = 0; i < 40; i++) {
        CHECK_EQ(s->sections[i].ncontours, i % 7);
        CHECK_EQ(s->sections[i].nmarkers, i % 5);
        CHECK(s->sections[i].z == i * 2.5);
        CHECK((s->sections[i].name != NULL) == (i % 2));
        if (i % 7 > 1) CHECK(s->sections[i].contours[1].hole == 1 && s->sections[i].contours[1].parent == 0);
        if (i % 7) CHECK(s->sections[i].contours[0].points[1].x == 4);
        if (i % 5 > 2) CHECK(s->sections[i].markers[2].y == -2);
    }
    bvox_section *sec = &s->sections[0];
    CHECK_STATUS(bvox_section_add_contour(sec, tri, 2, 0, -1), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "at least 3 points") != NULL);
    bvox_point2 bad[3] = {{0, 0}, {NAN, 0}, {0, 3}};
    CHECK_STATUS(bvox_section_add_contour(sec, bad, 3, 0, -1), BVOX_EINVAL);
    CHECK_STATUS(bvox_section_add_contour(sec, tri, 3, 0, 5), BVOX_EINVAL);
    CHECK_STATUS(bvox_section_add_marker(sec, (bvox_point2){INFINITY, 0}), BVOX_EINVAL);
    CHECK_STATUS(bvox_stack_add_section(s, NAN, NULL, NULL), BVOX_EINVAL);
    CHECK_EQ(s->nsections, 40);
    bvox_stack_destroy(s);
    bvox_stack_destroy(NULL);
    return 0;
}

/* Random polygons on the quarter-pixel grid, with many vertices exactly on
 * scanlines (y = j + 0.5), on pixel centres, horizontal edges and
 * self-intersections; holes are just more polygons (even-odd). */
typedef struct rpoly {
    int64_t x4[64], y4[64];
    int n;
} rpoly;

static void random_polys(rpoly *p, int np, int w, int h)
{
    for (int k = 0; k < np; k++) {
        p[k].n = (int)rnd(3, 40);
        for (int i = 0; i < p[k].n; i++) {
            int64_t x = rnd(-12, 4 * w + 12), y = rnd(-12, 4 * h + 12);
            switch (harness_rand() % 4) {
            case 0: y = 4 * (y / 4) + 2; break;           /* on a scanline */
            case 1: x = 4 * (x / 4) + 2; y = 4 * (y / 4) + 2; break; /* a centre */
            case 2: if (i > 0) y = p[k].y4[i - 1]; break; /* horizontal edge */
            default: break;
            }
            p[k].x4[i] = x;
            p[k].y4[i] = y;
        }
    }
}

TEST(scan_vs_reference)
{
    for (int trial = 0; trial < 300; trial++) {
        int w = (int)rnd(1, 150), h = (int)rnd(1, 40);
        int np = (int)rnd(1, 4);
        rpoly polys[4];
        random_polys(polys, np, w, h);
        bvox_section sec;
        memset(&sec, 0, sizeof sec);
        bvox_contour cts[4];
        bvox_point2 pts[4][64];
        contourref_poly rp[4];
        for (int k = 0; k < np; k++) {
            for (int i = 0; i < polys[k].n; i++)
                pts[k][i] = (bvox_point2){polys[k].x4[i] / 4.0, polys[k].y4[i] / 4.0};
            cts[k] = (bvox_contour){pts[k], polys[k].n, 0, -1};
            rp[k] = (contourref_poly){polys[k].x4, polys[k].y4, polys[k].n};
        }
        sec.contours = cts;
        sec.ncontours = np;
        /* a window that may cut the polygons, offset from the origin */
        int32_t x0 = (int32_t)rnd(-3, 5), y0 = (int32_t)rnd(-3, 5);
        int32_t nx = (int32_t)rnd(1, w + 3), ny = (int32_t)rnd(1, h + 3);
        size_t wpr = ((size_t)nx + 63) / 64 + (size_t)rnd(0, 1);
        uint64_t *bits = malloc((size_t)ny * wpr * 8);
        memset(bits, 0xA5, (size_t)ny * wpr * 8);
        bvox__scan_section(&sec, x0, y0, nx, ny, wpr, bits);
        for (int32_t j = 0; j < ny; j++) {
            for (int32_t i = 0; i < (int32_t)(wpr * 64); i++) {
                int got = (int)((bits[(size_t)j * wpr + (size_t)i / 64] >> (i % 64)) & 1);
                int want = i < nx ? contourref_inside(rp, np, x0 + i, y0 + j) : 0;
                if (got != want) {
                    fprintf(stderr, "trial %d pixel (%d, %d) of %dx%d at (%d, %d): got %d\n", trial,
                            (int)i, (int)j, (int)nx, (int)ny, (int)x0, (int)y0, got);
                    free(bits);
                    return 1;
                }
            }
        }
        free(bits);
    }
    return 0;
}

TEST(polygon_contains_matches_scan)
{
    for (int trial = 0; trial < 100; trial++) {
        rpoly p;
        random_polys(&p, 1, 20, 20);
        bvox_point2 pts[64];
        for (int i = 0; i < p.n; i++) pts[i] = (bvox_point2){p.x4[i] / 4.0, p.y4[i] / 4.0};
        contourref_poly rp = {p.x4, p.y4, p.n};
        for (int j = -2; j < 22; j++)
            for (int i = -2; i < 22; i++)
                CHECK_EQ(bvox_polygon_contains(pts, p.n, (bvox_point2){i + 0.5, j + 0.5}),
                         contourref_inside(&rp, 1, i, j));
    }
    return 0;
}

TEST(edt_vs_bruteforce)
{
    for (int trial = 0; trial < 120; trial++) {
        int nx = (int)rnd(1, 70), ny = (int)rnd(1, 30);
        int mode = trial % 4; /* 0 random, 1 sparse, 2 all 0, 3 all 1 */
        uint8_t *ref = malloc((size_t)nx * ny);
        size_t wpr = ((size_t)nx + 63) / 64;
        uint64_t *bits = calloc((size_t)ny * wpr, 8);
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                int v = mode == 0 ? (int)(harness_rand() % 2)
                        : mode == 1 ? harness_rand() % 97 == 0
                                    : mode == 3;
                ref[y * nx + x] = (uint8_t)v;
                if (v) bits[(size_t)y * wpr + x / 64] |= 1ull << (x % 64);
            }
        double *tmp = malloc(bvox__edt_scratch_doubles(nx, ny) * sizeof(double));
        float *out = malloc((size_t)nx * ny * sizeof(float));
        float cap = (float)(nx + ny + 2);
        bvox__signed_edt(bits, wpr, nx, ny, cap, tmp, out);
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                double want = contourref_signed_distance(ref, nx, ny, x, y, cap);
                if (fabs(out[y * nx + x] - want) > 1e-5 * fabs(want) + 1e-6) {
                    fprintf(stderr, "trial %d (%d,%d) of %dx%d: %g vs %g\n", trial, x, y, nx, ny,
                            (double)out[y * nx + x], want);
                    return 1;
                }
            }
        free(ref);
        free(bits);
        free(tmp);
        free(out);
    }
    return 0;
}

static bvox_status add_circle(bvox_section *sec, double cx, double cy, double r, int n, int hole)
{
    bvox_point2 *p = malloc((size_t)n * sizeof *p);
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n * (hole ? -1 : 1);
        p[i] = (bvox_point2){cx + r * cos(a), cy + r * sin(a)};
    }
    bvox_status st = bvox_section_add_contour(sec, p, n, hole, hole ? 0 : -1);
    free(p);
    return st;
}

static int64_t slice_count(const bvox_volume *v, int32_t z)
{
    bvox_dims d = bvox_volume_dims(v);
    int64_t n = 0;
    for (int32_t y = 0; y < d.ny; y++)
        for (int32_t x = 0; x < d.nx; x++) n += bvox_volume_get(v, x, y, z);
    return n;
}

/* Two concentric discs r1 at z = 0 and r2 at z = 40: the interpolated slices
 * are discs whose radius goes linearly from r1 to r2 (the zero level of the
 * blend of two cone-shaped distance maps). */
TEST(interpolate_discs)
{
    for (int threads = 1; threads <= 2; threads++) {
        bvox_set_threads(threads);
        bvox_contour_stack *s = NULL;
        CHECK_OK(bvox_stack_create(&s));
        s->pixel = 0.5;
        s->spacing = 20;
        s->width = 100;
        s->height = 90;
        strcpy(s->unit, "um");
        bvox_section *sec;
        const double r1 = 10, r2 = 30;
        CHECK_OK(bvox_stack_add_section(s, 40, "top", &sec)); /* out of order on purpose */
        CHECK_OK(add_circle(sec, 50, 45, r2, 400, 0));
        CHECK_OK(bvox_stack_add_section(s, 20, "bottom", &sec));
        CHECK_OK(add_circle(sec, 50, 45, r1, 400, 0));
        bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
        o.z_spacing = 1;
        bvox_volume *v = NULL;
        CHECK_OK(bvox_stack_to_volume(s, &o, &v));
        CHECK_OK(bvox_volume_check(v));
        bvox_dims d = bvox_volume_dims(v);
        CHECK_EQ(d.nx, 100);
        CHECK_EQ(d.ny, 90);
        CHECK_EQ(d.nz, 40); /* (40 - 20 + 20) / 1 */
        const bvox_geometry *g = bvox_volume_geometry(v);
        CHECK(g->spacing[0] == 0.5 && g->spacing[1] == 0.5 && g->spacing[2] == 1);
        CHECK(strcmp(g->unit, "um") == 0);
        CHECK_NEAR(g->origin[0], 0.25, 1e-12);
        CHECK_NEAR(g->origin[2], 10.5, 1e-9); /* 20 - 10 + 0.5 */
        for (int32_t k = 0; k < d.nz; k++) {
            double z = g->origin[2] + k * g->spacing[2];
            double r = z <= 20 ? r1 : z >= 40 ? r2 : r1 + (r2 - r1) * (z - 20) / 20;
            double rad = sqrt((double)slice_count(v, k) / M_PI);
            CHECK_NEAR(rad, r, 0.75);
            /* a disc: the centre pixel and none beyond r + 1 */
            CHECK(bvox_volume_get(v, 50, 45, k) == 1);
            CHECK(bvox_volume_get(v, 50 + (int)ceil(r + 1.5), 45, k) == 0);
        }
        /* nearest-section copies */
        o.interpolate = 0;
        bvox_volume *w = NULL;
        CHECK_OK(bvox_stack_to_volume(s, &o, &w));
        int64_t c1 = slice_count(w, 0), c2 = slice_count(w, d.nz - 1);
        for (int32_t k = 0; k < d.nz; k++) {
            double z = g->origin[2] + k * g->spacing[2];
            CHECK_EQ(slice_count(w, k), z <= 30 ? c1 : c2);
        }
        bvox_volume_destroy(w);
        bvox_volume_destroy(v);
        bvox_stack_destroy(s);
    }
    bvox_set_threads(0);
    return 0;
}

/* A disc with a hole, an empty section in between: sections copied at their z
 * (z_spacing = spacing), holes kept, more than 64 slices. */
TEST(stack_volume_sections_exact)
{
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_create(&s));
    s->spacing = 2;
    const int n = 150;
    for (int i = 0; i < n; i++) {
        bvox_section *sec;
        CHECK_OK(bvox_stack_add_section(s, 3 + 2.0 * i, NULL, &sec));
        if (i % 10 == 5) continue; /* an empty section */
        CHECK_OK(add_circle(sec, 30 + i % 7, 20, 12, 64, 0));
        CHECK_OK(add_circle(sec, 30 + i % 7, 20, 5, 32, 1));
    }
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.z_spacing = 2;
    o.margin = 3;
    bvox_volume *v = NULL;
    CHECK_OK(bvox_stack_to_volume(s, &o, &v));
    CHECK_OK(bvox_volume_check(v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nz, n);
    /* bounds: x in [18 - 3, 42 + 3 + ...] */
    const bvox_geometry *g = bvox_volume_geometry(v);
    int32_t x0 = (int32_t)floor(g->origin[0] - 0.5);
    int32_t y0 = (int32_t)floor(g->origin[1] - 0.5);
    CHECK_EQ(x0, (int32_t)floor(30 - 12.0) - 3);
    CHECK_EQ(y0, (int32_t)floor(20 - 12.0) - 3);
    CHECK_NEAR(g->origin[2], 3, 1e-9);
    size_t wpr = ((size_t)d.nx + 63) / 64;
    uint64_t *bits = malloc((size_t)d.ny * wpr * 8);
    for (int i = 0; i < n; i++) {
        bvox__scan_section(&s->sections[i], x0, y0, d.nx, d.ny, wpr, bits);
        for (int32_t y = 0; y < d.ny; y++)
            for (int32_t x = 0; x < d.nx; x++)
                CHECK_EQ(bvox_volume_get(v, x, y, i), (int)((bits[(size_t)y * wpr + x / 64] >> (x % 64)) & 1));
        if (i % 10 != 5) CHECK(bvox_volume_get(v, 30 + i % 7 - x0, 20 - y0, i) == 0); /* the hole */
        if (i % 10 != 5) CHECK(bvox_volume_get(v, 30 + i % 7 + 8 - x0, 20 - y0, i) == 1);
    }
    free(bits);
    bvox_volume_destroy(v);
    bvox_stack_destroy(s);
    return 0;
}

TEST(stack_volume_errors)
{
    bvox_contour_stack *s = NULL;
    bvox_volume *v = (bvox_volume *)&s; /* must come back NULL */
    CHECK_OK(bvox_stack_create(&s));
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_EINVAL);
    CHECK(v == NULL);
    bvox_section *sec;
    CHECK_OK(bvox_stack_add_section(s, 0, "a", &sec));
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_EINVAL); /* no extent */
    CHECK(strstr(bvox_errmsg(), "extent") != NULL);
    CHECK_OK(add_circle(sec, 5, 5, 3, 12, 0));
    CHECK_OK(bvox_stack_add_section(s, 0, "b", &sec));
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "'a'") && strstr(bvox_errmsg(), "'b'") && strstr(bvox_errmsg(), "same z"));
    sec->z = 1e9;
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_ETOOBIG);
    sec->z = 1;
    s->pixel = 0;
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_EINVAL);
    s->pixel = 1;
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.z_spacing = -1;
    CHECK_STATUS(bvox_stack_to_volume(s, &o, &v), BVOX_EINVAL);
    s->width = 70000;
    s->height = 5;
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_ETOOBIG);
    s->width = 20;
    bvox_set_memory_budget(1024);
    CHECK_STATUS(bvox_stack_to_volume(s, NULL, &v), BVOX_ETOOBIG);
    bvox_set_memory_budget(0);
    for (long k = 1; k < 8; k++) {
        bvox__alloc_fail_after(k);
        bvox_status st = bvox_stack_to_volume(s, NULL, &v);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            bvox_volume_destroy(v);
            break;
        }
        CHECK(v == NULL);
        CHECK_EQ(bvox_memory_in_use(), 0);
    }
    CHECK_OK(bvox_stack_to_volume(s, NULL, &v));
    CHECK_EQ(bvox_volume_dims(v).nz, 2);
    bvox_volume_destroy(v);
    bvox_stack_destroy(s);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Sections without contours (width/height given) and interpolation: an empty
 * model of the right size (found by fuzzing: no distance maps at all). */
TEST(stack_volume_all_empty)
{
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_create(&s));
    s->width = 9;
    s->height = 4;
    s->spacing = 3;
    CHECK_OK(bvox_stack_add_section(s, 0, NULL, NULL));
    CHECK_OK(bvox_stack_add_section(s, 3, NULL, NULL));
    bvox_volume *v = NULL;
    CHECK_OK(bvox_stack_to_volume(s, NULL, &v));
    CHECK_OK(bvox_volume_check(v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK_EQ(d.nx, 9);
    CHECK_EQ(d.ny, 4);
    CHECK_EQ(d.nz, 6);
    CHECK_EQ(bvox_volume_count(v), 0);
    bvox_volume_destroy(v);
    bvox_stack_destroy(s);
    return 0;
}

/* The whole interpolation against a brute-force reference: random polygons
 * (some running off the image), sections at uneven z, every output slice
 * compared with (1 - t) d_a + t d_b <= 0 computed from brute-force signed
 * distances over the whole image, in the same float arithmetic. This checks
 * the distance maps' box (and its clipping at the image border), the z rule
 * and the packing. */
TEST(interpolate_vs_bruteforce)
{
    int ran = 0;
    for (int trial = 0; trial < 12; trial++) {
        const int w = 23 + trial % 5, h = 17 + trial % 3, nsec = 3 + trial % 3;
        bvox_contour_stack *s = NULL;
        CHECK_OK(bvox_stack_create(&s));
        s->width = w;
        s->height = h;
        s->spacing = 2.5;
        double z = 1;
        for (int i = 0; i < nsec; i++) {
            bvox_section *sec;
            CHECK_OK(bvox_stack_add_section(s, z, NULL, &sec));
            z += 1.5 + (double)(harness_rand() % 4);
            /* a convex-ish blob, possibly past the border, and a hole */
            bvox_point2 p[12];
            double cx = (double)rnd(0, w), cy = (double)rnd(0, h), r = (double)rnd(3, 9);
            for (int k = 0; k < 12; k++) {
                double a = 2 * M_PI * k / 12;
                p[k] = (bvox_point2){round(4 * (cx + r * cos(a))) / 4, round(4 * (cy + r * sin(a))) / 4};
            }
            CHECK_OK(bvox_section_add_contour(sec, p, 12, 0, -1));
            if (trial % 2) {
                bvox_point2 q[4] = {{cx - 1, cy - 1}, {cx - 1, cy + 1}, {cx + 1, cy + 1}, {cx + 1, cy - 1}};
                CHECK_OK(bvox_section_add_contour(sec, q, 4, 1, 0));
            }
        }
        bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
        o.z_spacing = 0.5 + 0.25 * (trial % 3);
        bvox_volume *v = NULL;
        CHECK_OK(bvox_stack_to_volume(s, &o, &v));
        /* the reference */
        size_t wpr = ((size_t)w + 63) / 64;
        uint64_t *bits = malloc((size_t)h * wpr * 8);
        uint8_t *img = malloc((size_t)nsec * w * h);
        float *dist = malloc((size_t)nsec * w * h * sizeof(float));
        int skip = 0;
        for (int i = 0; i < nsec; i++) {
            bvox__scan_section(&s->sections[i], 0, 0, w, h, wpr, bits);
            int ones = 0;
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    img[(size_t)i * w * h + y * w + x] = (uint8_t)((bits[y * wpr + x / 64] >> (x % 64)) & 1);
                    ones += img[(size_t)i * w * h + y * w + x];
                }
            if (ones == 0 || ones == w * h) skip = 1; /* the cap would differ */
            for (int y = 0; y < h && !skip; y++)
                for (int x = 0; x < w; x++)
                    dist[(size_t)i * w * h + y * w + x] =
                        (float)contourref_signed_distance(img + (size_t)i * w * h, w, h, x, y, 1e9);
        }
        bvox_dims d = bvox_volume_dims(v);
        double first = s->sections[0].z, last = s->sections[nsec - 1].z, dz = o.z_spacing;
        int nz = (int)floor((last - first + s->spacing) / dz + 0.5);
        CHECK_EQ(d.nz, nz);
        for (int k = 0; k < nz && !skip; k++) {
            double zc = (first + last) / 2 + (k - (nz - 1) / 2.0) * dz;
            int a = 0;
            while (a + 1 < nsec && s->sections[a + 1].z <= zc) a++;
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    int want;
                    if (zc <= first || zc >= last || zc == s->sections[a].z) {
                        int i = zc <= first ? 0 : zc >= last ? nsec - 1 : a;
                        want = img[(size_t)i * w * h + y * w + x];
                    } else {
                        double za = s->sections[a].z, zb = s->sections[a + 1].z;
                        double t = (zc - za) / (zb - za);
                        float ta = (float)(1.0 - t), tb = (float)t;
                        want = ta * dist[(size_t)a * w * h + y * w + x] +
                                   tb * dist[(size_t)(a + 1) * w * h + y * w + x] <= 0.0f;
                    }
                    if (bvox_volume_get(v, x, y, k) != want) {
                        fprintf(stderr, "trial %d: voxel (%d, %d, %d) is %d\n", trial, x, y, k, !want);
                        return 1;
                    }
                }
        }
        ran += !skip;
        free(bits);
        free(img);
        free(dist);
        bvox_volume_destroy(v);
        bvox_stack_destroy(s);
    }
    CHECK(ran >= 8); /* most trials have no empty or full section */
    return 0;
}

/* ---- the crossing check (a sweep line) against testing every pair ---- */

static double orient3(bvox_point2 a, bvox_point2 b, bvox_point2 c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* The rule, pair by pair: a proper crossing, or a collinear overlap of
 * positive length; touching at a point is not a crossing. */
static int pair_crosses(bvox_point2 a, bvox_point2 b, bvox_point2 c, bvox_point2 d)
{
    double o1 = orient3(a, b, c), o2 = orient3(a, b, d), o3 = orient3(c, d, a),
           o4 = orient3(c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) return 1;
    if (o1 != 0 || o2 != 0 || o3 != 0 || o4 != 0) return 0;
    int ux = fabs(b.x - a.x) >= fabs(b.y - a.y);
    double a0 = ux ? a.x : a.y, a1 = ux ? b.x : b.y, c0 = ux ? c.x : c.y, c1 = ux ? d.x : d.y;
    double lo = fmax(fmin(a0, a1), fmin(c0, c1)), hi = fmin(fmax(a0, a1), fmax(c0, c1));
    return hi > lo;
}

static int all_pairs_cross(const bvox_section *sec)
{
    for (int32_t c = 0; c < sec->ncontours; c++)
        for (int32_t e = 0; e < sec->contours[c].npoints; e++)
            for (int32_t c2 = c; c2 < sec->ncontours; c2++)
                for (int32_t e2 = c2 == c ? e + 1 : 0; e2 < sec->contours[c2].npoints; e2++) {
                    const bvox_contour *k = &sec->contours[c], *k2 = &sec->contours[c2];
                    int32_t n = k->npoints, d = e2 - e;
                    if (c == c2 && (d == 1 || d == n - 1)) continue;
                    if (pair_crosses(k->points[e], k->points[(e + 1) % n], k2->points[e2],
                                     k2->points[(e2 + 1) % k2->npoints]))
                        return 1;
                }
    return 0;
}

/* Random polygons on a small integer grid: plenty of shared x, verticals,
 * collinear edges, touching vertices and T-junctions. */
TEST(check_simple_matches_every_pair)
{
    uint32_t r = 12345;
    int disagree = 0, crossing = 0, simple = 0;
    for (int trial = 0; trial < 40000 && disagree < 5; trial++) {
        bvox_section sec;
        memset(&sec, 0, sizeof sec);
        bvox_contour ct[2];
        bvox_point2 pts[2][20];
        uint32_t grid = trial % 2 ? 5 : 9, most = trial % 2 ? 8 : 17;
        int nc = 1 + (trial % 3 == 0);
        for (int c = 0; c < nc; c++) {
            r = r * 1103515245u + 12345u;
            int n = 3 + (int)((r >> 16) % most);
            for (int i = 0; i < n; i++) {
                r = r * 1103515245u + 12345u;
                pts[c][i].x = (double)((r >> 16) % grid);
                r = r * 1103515245u + 12345u;
                pts[c][i].y = (double)((r >> 16) % grid);
            }
            ct[c] = (bvox_contour){pts[c], n, 0, -1};
        }
        sec.contours = ct;
        sec.ncontours = nc;
        int want = all_pairs_cross(&sec);
        bvox_status st = bvox_section_check_simple(&sec, 0);
        int got = st == BVOX_EFORMAT;
        if (got != want) {
            fprintf(stderr, "trial %d: all pairs say %d, the sweep %d (%s)\n", trial, want, got,
                    bvox_errmsg());
            disagree++;
        }
        crossing += want;
        simple += !want;
    }
    CHECK_EQ(disagree, 0);
    CHECK(crossing > 1000 && simple > 1000); /* both kinds were tried */
    return 0;
}

/* A simple serpentine of 100000 points whose horizontal edges all span the
 * picture: every pair of them overlaps in x, so the previous check tested
 * ~1.25e9 pairs (25 s). Work bound: the pairs the sweep tests. Then one
 * point moved to make it cross is found. */
TEST(check_simple_long_path_work_bound)
{
    const int rows = 49999;
    int n = 2 * rows + 2;
    bvox_point2 *p = malloc((size_t)n * sizeof *p);
    int k = 0;
    for (int i = 0; i < rows; i++) {
        double x0 = i % 2 ? 1000 : 1, x1 = i % 2 ? 1 : 1000;
        p[k++] = (bvox_point2){x0, i};
        p[k++] = (bvox_point2){x1, i};
    }
    p[k++] = (bvox_point2){0, rows - 1}; /* down the left side, back to (1, 0) */
    p[k++] = (bvox_point2){0, 0};
    bvox_section sec;
    memset(&sec, 0, sizeof sec);
    bvox_contour ct = {p, n, 0, -1};
    sec.contours = &ct;
    sec.ncontours = 1;
    CHECK_OK(bvox_section_check_simple(&sec, 0));
    CHECK(bvox__check_simple_tests() < (uint64_t)4 * (uint64_t)n);
    p[2 * 20000 + 1].y = 20001.5; /* row 20000's far end, pulled across row 20001 */
    CHECK_STATUS(bvox_section_check_simple(&sec, 0), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "crosses itself") != NULL);
    free(p);
    return 0;
}
