/* test_contours_model.c — model -> contours (model_contours.c): the round
 * trip volume -> contours -> bvox_stack_to_volume (nearest, same spacing) is
 * the identity on random volumes along every axis; orientation and nesting of
 * hand-made slices (a ring, diagonal pixels, a pixel in a hole); anisotropic
 * slices. And the contour geometry of contour_geom.c: area, point in polygon,
 * closing, smoothing, Douglas-Peucker, crossing check, 2-D maps. */
#include "harness.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

static bvox_volume *random_volume(int nx, int ny, int nz, unsigned num, unsigned den)
{
    voxref *r = voxref_create(nx, ny, nz);
    voxref_random(r, num, den, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    voxref_destroy(r);
    return v;
}

/* The voxels of v again from its contours across axis, compared per voxel. */
static int round_trip(const bvox_volume *v, int axis)
{
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_volume_to_contours(v, axis, &s));
    bvox_dims d = bvox_volume_dims(v);
    const int32_t dims[3] = {d.nx, d.ny, d.nz};
    CHECK_EQ(s->nsections, dims[axis]);
    for (int32_t i = 0; i < s->nsections; i++)
        for (int32_t c = 0; c < s->sections[i].ncontours; c++) {
            const bvox_contour *ct = &s->sections[i].contours[c];
            double a = bvox_polygon_signed_area(ct->points, ct->npoints);
            CHECK(ct->hole ? a < 0 : a > 0);
            if (ct->hole) {
                CHECK(ct->parent >= 0 && ct->parent < c);
                CHECK(!s->sections[i].contours[ct->parent].hole);
            }
        }
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.interpolate = 0;
    o.z_spacing = s->spacing;
    bvox_volume *w = NULL;
    CHECK_OK(bvox_stack_to_volume(s, &o, &w));
    CHECK_OK(bvox_volume_check(w));
    bvox_dims e = bvox_volume_dims(w);
    const int32_t edims[3] = {e.nx, e.ny, e.nz};
    int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
    CHECK_EQ(edims[0], dims[ua]);
    CHECK_EQ(edims[1], dims[va]);
    CHECK_EQ(edims[2], dims[axis]);
    const bvox_geometry *g = bvox_volume_geometry(v), *h = bvox_volume_geometry(w);
    CHECK_NEAR(h->origin[2], g->origin[axis], 1e-9);
    /* the in-plane position survives too (the stack's origin) */
    CHECK_NEAR(h->origin[0], g->origin[ua], 1e-9);
    CHECK_NEAR(h->origin[1], g->origin[va], 1e-9);
    CHECK(h->spacing[2] == g->spacing[axis] && h->spacing[0] == g->spacing[ua]);
    for (int32_t k = 0; k < dims[axis]; k++)
        for (int32_t b = 0; b < dims[va]; b++)
            for (int32_t a = 0; a < dims[ua]; a++) {
                int32_t p[3];
                p[axis] = k;
                p[ua] = a;
                p[va] = b;
                if (bvox_volume_get(v, p[0], p[1], p[2]) != bvox_volume_get(w, a, b, k)) {
                    fprintf(stderr, "axis %d: voxel (%d, %d, %d) differs\n", axis, p[0], p[1], p[2]);
                    return 1;
                }
            }
    bvox_volume_destroy(w);
    bvox_stack_destroy(s);
    return 0;
}

TEST(round_trip_random)
{
    static const int sizes[][3] = {{1, 1, 1}, {7, 5, 3}, {13, 9, 70}, {66, 3, 5}, {20, 20, 129}};
    static const unsigned dens[][2] = {{1, 2}, {1, 8}, {7, 8}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        for (size_t k = 0; k < 3; k++) {
            bvox_volume *v = random_volume(sizes[i][0], sizes[i][1], sizes[i][2], dens[k][0], dens[k][1]);
            CHECK(v != NULL);
            CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.5, 0.5, "mm"));
            for (int axis = 0; axis < 3; axis++)
                if (round_trip(v, axis)) {
                    fprintf(stderr, "size %zu density %zu\n", i, k);
                    return 1;
                }
            bvox_volume_destroy(v);
        }
    return 0;
}

TEST(round_trip_anisotropic_z)
{
    /* square slices across z, with sz different: still exact */
    bvox_volume *v = random_volume(17, 11, 9, 1, 3);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = g.spacing[1] = 2;
    g.spacing[2] = 7;
    g.origin[0] = 12.25;
    g.origin[1] = -5;
    g.origin[2] = -3.5;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    CHECK(round_trip(v, 2) == 0);
    /* across x the pixels are 2 x 7: v scaled by 3.5, shape kept */
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_volume_to_contours(v, 0, &s));
    CHECK_EQ(s->height, 32); /* ceil(9 * 3.5) */
    CHECK(s->pixel == 2 && s->spacing == 2);
    double area = 0;
    for (int32_t i = 0; i < s->nsections; i++)
        for (int32_t c = 0; c < s->sections[i].ncontours; c++)
            area += bvox_polygon_signed_area(s->sections[i].contours[c].points,
                                             s->sections[i].contours[c].npoints);
    CHECK_NEAR(area, bvox_volume_count(v) * 3.5, 1e-6); /* pixels of 2 x 2: each voxel 3.5 */
    bvox_stack_destroy(s);
    bvox_volume_destroy(v);
    return 0;
}

TEST(contours_hand_made)
{
    /* slice z = 0: a 5x5 ring (hole 3x3 at the centre) with one pixel in the
     * hole; a pair of diagonal pixels; all on a 12 x 7 slice */
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){12, 7, 1}, &v));
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 5; x++)
            if (x == 0 || y == 0 || x == 4 || y == 4) bvox_volume_set(v, x, y, 0, 1);
    bvox_volume_set(v, 2, 2, 0, 1);
    bvox_volume_set(v, 7, 1, 0, 1);
    bvox_volume_set(v, 8, 2, 0, 1);
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_volume_to_contours(v, 2, &s));
    CHECK_EQ(s->nsections, 1);
    const bvox_section *sec = &s->sections[0];
    CHECK_EQ(sec->ncontours, 5); /* ring outer, ring hole, centre pixel, 2 diagonal pixels */
    int outer = 0, holes = 0;
    double total = 0;
    for (int c = 0; c < sec->ncontours; c++) {
        double a = bvox_polygon_signed_area(sec->contours[c].points, sec->contours[c].npoints);
        total += a;
        if (sec->contours[c].hole) {
            holes++;
            CHECK_NEAR(a, -9, 0);
            CHECK_EQ(sec->contours[c].npoints, 4);
            CHECK_EQ(sec->contours[sec->contours[c].parent].npoints, 4);
            CHECK_NEAR(bvox_polygon_signed_area(sec->contours[sec->contours[c].parent].points, 4), 25, 0);
        } else {
            outer++;
            CHECK(a == 25 || a == 1);
        }
    }
    CHECK_EQ(outer, 4);
    CHECK_EQ(holes, 1);
    CHECK_NEAR(total, 16 + 1 + 2, 0); /* the voxel count */
    CHECK_EQ(bvox_volume_count(v), 19);
    bvox_stack_destroy(s);
    bvox_volume_destroy(v);
    return 0;
}

TEST(geometry_area_contains)
{
    bvox_point2 sq[4] = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
    CHECK_NEAR(bvox_polygon_signed_area(sq, 4), 12, 0);
    bvox_point2 rev[4] = {{0, 0}, {0, 3}, {4, 3}, {4, 0}};
    CHECK_NEAR(bvox_polygon_signed_area(rev, 4), -12, 0);
    CHECK(bvox_polygon_contains(sq, 4, (bvox_point2){1, 1}));
    CHECK(!bvox_polygon_contains(sq, 4, (bvox_point2){5, 1}));
    /* half-open: on a vertical edge the region on its left owns the point
     * (the right edge is in, the left edge out); on a horizontal edge the
     * region below it (larger y: the top edge is in, the bottom edge out) */
    CHECK(!bvox_polygon_contains(sq, 4, (bvox_point2){0, 1}));
    CHECK(bvox_polygon_contains(sq, 4, (bvox_point2){4, 1}));
    CHECK(bvox_polygon_contains(sq, 4, (bvox_point2){1, 0}));
    CHECK(!bvox_polygon_contains(sq, 4, (bvox_point2){1, 3}));
    /* a section with a hole */
    bvox_point2 hole[4] = {{1, 1}, {1, 2}, {2, 2}, {2, 1}};
    bvox_contour cts[2] = {{sq, 4, 0, -1}, {hole, 4, 1, 0}};
    bvox_section sec = {0, NULL, cts, 2, NULL, 0};
    CHECK(!bvox_section_contains(&sec, (bvox_point2){1.5, 1.5}));
    CHECK(bvox_section_contains(&sec, (bvox_point2){3, 1.5}));
    return 0;
}

TEST(geometry_close_smooth_simplify)
{
    bvox_point2 pts[8] = {{0, 0}, {0, 0}, {4, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 4}, {0, 0}};
    bvox_point2 *p = malloc(sizeof pts);
    memcpy(p, pts, sizeof pts);
    bvox_contour c = {p, 8, 0, -1};
    CHECK_OK(bvox_contour_close(&c));
    CHECK_EQ(c.npoints, 4);
    CHECK(p[1].x == 4 && p[1].y == 0 && p[3].x == 0 && p[3].y == 4);
    bvox_point2 two[4] = {{1, 1}, {1, 1}, {2, 2}, {1, 1}};
    bvox_contour d = {two, 4, 0, -1};
    CHECK_STATUS(bvox_contour_close(&d), BVOX_EFORMAT);
    CHECK_EQ(d.npoints, 4); /* unchanged */
    free(p);

    /* a noisy circle of radius 20: smoothing keeps the area, moves points
     * towards the circle */
    int n = 360;
    bvox_point2 *q = malloc((size_t)n * sizeof *q);
    for (int i = 0; i < n; i++) {
        double a = 2 * M_PI * i / n, r = 20 + ((harness_rand() % 2001) / 1000.0 - 1);
        q[i] = (bvox_point2){50 + r * cos(a), 50 + r * sin(a)};
    }
    bvox_contour e = {q, n, 0, -1};
    double a0 = bvox_polygon_signed_area(q, n), dev0 = 0, dev1 = 0;
    for (int i = 0; i < n; i++) dev0 += fabs(hypot(q[i].x - 50, q[i].y - 50) - 20);
    CHECK_OK(bvox_contour_smooth(&e, 3, 2));
    CHECK_NEAR(bvox_polygon_signed_area(q, n), a0, 1e-6 * a0);
    for (int i = 0; i < n; i++) dev1 += fabs(hypot(q[i].x - 50, q[i].y - 50) - 20);
    CHECK(dev1 < dev0 / 2);
    CHECK_STATUS(bvox_contour_smooth(&e, 0, 1), BVOX_EINVAL);

    /* simplification: every dropped point within tolerance of the result */
    bvox_point2 *orig = malloc((size_t)n * sizeof *orig);
    memcpy(orig, q, (size_t)n * sizeof *orig);
    for (int t = 0; t < 3; t++) {
        double tol = t == 0 ? 0.05 : t == 1 ? 0.5 : 100;
        memcpy(q, orig, (size_t)n * sizeof *q);
        e.npoints = n;
        CHECK_OK(bvox_contour_simplify(&e, tol));
        CHECK(e.npoints >= 3 && e.npoints <= n);
        if (t == 2) CHECK_EQ(e.npoints, 3);
        if (t == 1) CHECK(e.npoints < n / 3);
        /* distance of each original point to the simplified polygon */
        for (int i = 0; i < n; i++) {
            double best = HUGE_VAL;
            for (int k = 0; k < e.npoints; k++) {
                bvox_point2 a = q[k], b = q[(k + 1) % e.npoints];
                double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
                double u = l2 > 0 ? ((orig[i].x - a.x) * dx + (orig[i].y - a.y) * dy) / l2 : 0;
                u = u < 0 ? 0 : u > 1 ? 1 : u;
                double ex = a.x + u * dx - orig[i].x, ey = a.y + u * dy - orig[i].y;
                best = fmin(best, sqrt(ex * ex + ey * ey));
            }
            if (t < 2) CHECK(best <= tol + 1e-9);
        }
    }
    free(orig);
    free(q);
    return 0;
}

TEST(geometry_crossings)
{
    bvox_point2 bow[4] = {{0, 0}, {4, 4}, {4, 0}, {0, 4}}; /* a bow tie */
    bvox_contour c = {bow, 4, 0, -1};
    bvox_section sec = {2.5, "s07.png", &c, 1, NULL, 0};
    CHECK_STATUS(bvox_section_check_simple(&sec, 6), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "s07.png") && strstr(bvox_errmsg(), "crosses itself"));
    CHECK(strstr(bvox_errmsg(), "2.00, 2.00") != NULL);
    bvox_point2 sq[4] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    bvox_point2 sq2[4] = {{2, 2}, {6, 2}, {6, 6}, {2, 6}};
    bvox_point2 corner[4] = {{4, 4}, {5, 4}, {5, 5}, {4, 5}}; /* touches sq at a corner */
    bvox_contour two[3] = {{sq, 4, 0, -1}, {corner, 4, 0, -1}, {sq2, 4, 0, -1}};
    bvox_section s2 = {0, NULL, two, 2, NULL, 0};
    CHECK_OK(bvox_section_check_simple(&s2, 0));
    s2.ncontours = 3;
    CHECK_STATUS(bvox_section_check_simple(&s2, 0), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "section 1") && strstr(bvox_errmsg(), "contours 1 and 3 cross"));
    /* collinear overlap of two contours sharing an edge */
    bvox_point2 right[4] = {{4, 1}, {8, 1}, {8, 3}, {4, 3}};
    bvox_contour ov[2] = {{sq, 4, 0, -1}, {right, 4, 0, -1}};
    bvox_section s3 = {0, NULL, ov, 2, NULL, 0};
    CHECK_STATUS(bvox_section_check_simple(&s3, 0), BVOX_EFORMAT);
    return 0;
}

TEST(geometry_xform)
{
    bvox_xform2 r = bvox_xform2_similarity(M_PI / 2, 2, 10, 20);
    bvox_point2 p = bvox_xform2_apply(&r, (bvox_point2){1, 0});
    CHECK_NEAR(p.x, 10, 1e-12);
    CHECK_NEAR(p.y, 22, 1e-12);
    bvox_xform2 inv, id;
    CHECK_OK(bvox_xform2_invert(&r, &inv));
    id = bvox_xform2_compose(&r, &inv);
    CHECK_NEAR(id.a, 1, 1e-12);
    CHECK_NEAR(id.b, 0, 1e-12);
    CHECK_NEAR(id.tx, 0, 1e-12);
    CHECK_NEAR(id.ty, 0, 1e-12);
    bvox_xform2 t = {1, 0, 0, 1, 5, 0};
    bvox_xform2 rt = bvox_xform2_compose(&t, &r); /* translate first, then r */
    p = bvox_xform2_apply(&rt, (bvox_point2){0, 0});
    CHECK_NEAR(p.x, 10, 1e-12);
    CHECK_NEAR(p.y, 30, 1e-12);
    bvox_xform2 sing = {1, 2, 2, 4, 0, 0};
    CHECK_STATUS(bvox_xform2_invert(&sing, &inv), BVOX_EINVAL);
    /* a section: contours and markers move, a mirror keeps the orientation */
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_create(&s));
    bvox_section *sec;
    CHECK_OK(bvox_stack_add_section(s, 0, NULL, &sec));
    bvox_point2 sq[4] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    CHECK_OK(bvox_section_add_contour(sec, sq, 4, 0, -1));
    CHECK_OK(bvox_section_add_marker(sec, (bvox_point2){1, 1}));
    bvox_xform2 mirror = {-1, 0, 0, 1, 10, 0};
    bvox_section_transform(sec, &mirror);
    CHECK_NEAR(bvox_polygon_signed_area(sec->contours[0].points, 4), 16, 0);
    CHECK_NEAR(sec->markers[0].x, 9, 0);
    bvox_section_transform(sec, &r);
    CHECK_NEAR(bvox_polygon_signed_area(sec->contours[0].points, 4), 64, 1e-9);
    bvox_stack_destroy(s);
    return 0;
}
