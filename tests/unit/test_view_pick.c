/* test_view_pick.c — picking (viewer/pick.c): the voxel walk from a ray to
 * the first 1-voxel against an exact brute-force reference (every 1-voxel's
 * box clipped against the ray, the nearest entry wins) on random volumes
 * with unequal spacing and random rays, axis-parallel rays included; and a
 * pixel of the 3D pane picks a voxel exactly where the cast shows one, at
 * the depth the pre-image holds for that pixel. */
#include "harness.h"
#include "view.h"

#include <string.h>

static double urand(void) { return (double)(harness_rand() % 1000000) / 1000000.0; }

/* The nearest box entry along the ray (t >= 0 part), or 0 if none; *second
 * gets the next nearest entry (to skip rays that graze a shared edge). */
static int brute(const bvox_volume *v, const double sp[3], const double p0[3], const double d[3],
                 int32_t hit[3], double *best, double *second)
{
    bvox_dims n = bvox_volume_dims(v);
    *best = *second = INFINITY;
    int found = 0;
    for (int32_t z = 0; z < n.nz; z++)
        for (int32_t y = 0; y < n.ny; y++)
            for (int32_t x = 0; x < n.nx; x++) {
                if (!bvox_volume_get(v, x, y, z)) continue;
                int32_t c[3] = {x, y, z};
                double t0 = 0, t1 = INFINITY;
                int miss = 0;
                for (int a = 0; a < 3 && !miss; a++) {
                    double lo = (c[a] - 0.5) * sp[a], hi = (c[a] + 0.5) * sp[a];
                    if (d[a] == 0) {
                        miss = p0[a] < lo || p0[a] >= hi;
                        continue;
                    }
                    double ta = (lo - p0[a]) / d[a], tb = (hi - p0[a]) / d[a];
                    if (ta > tb) { double s = ta; ta = tb; tb = s; }
                    t0 = ta > t0 ? ta : t0;
                    t1 = tb < t1 ? tb : t1;
                }
                if (miss || t0 > t1) continue;
                if (t0 < *best) {
                    *second = *best;
                    *best = t0;
                    memcpy(hit, c, sizeof c);
                    found = 1;
                } else if (t0 < *second) {
                    *second = t0;
                }
            }
    return found;
}

TEST(walk_matches_brute_force)
{
    const double sp[3] = {1.0, 1.5, 0.75};
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){13, 9, 70}, &v));
    for (int32_t z = 0; z < 70; z++)
        for (int32_t y = 0; y < 9; y++)
            for (int32_t x = 0; x < 13; x++)
                if (harness_rand() % 23 == 0) CHECK_OK(bvox_volume_set(v, x, y, z, 1));
    int hits = 0, misses = 0;
    for (int i = 0; i < 3000; i++) {
        double c[3] = {6 * sp[0], 4 * sp[1], 35 * sp[2]};
        double d[3] = {urand() - 0.5, urand() - 0.5, urand() - 0.5};
        if (i % 10 == 0) d[0] = d[1] = 0; /* along z */
        if (i % 10 == 1) d[1] = d[2] = 0; /* along x */
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (len < 1e-3) continue;
        for (int a = 0; a < 3; a++) d[a] /= len;
        double p0[3];
        for (int a = 0; a < 3; a++) /* start outside, aimed near the middle */
            p0[a] = c[a] - 60 * d[a] + (urand() - 0.5) * 10;
        int32_t want[3], got[3];
        double best, second;
        int w = brute(v, sp, p0, d, want, &best, &second);
        int g = vw_pick_ray(v, sp, p0, d, got);
        if (w && second - best < 1e-9) continue; /* a tie on a shared face: either is right */
        CHECK_EQ(g, w);
        if (w) {
            CHECK(got[0] == want[0] && got[1] == want[1] && got[2] == want[2]);
            hits++;
        } else {
            misses++;
        }
    }
    CHECK(hits > 1000 && misses > 50);
    bvox_volume_destroy(v);
    return 0;
}

TEST(pane_pick_is_what_is_shown)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){30, 26, 40}, &v));
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_TORUS;
    s.center[0] = 15, s.center[1] = 13, s.center[2] = 20;
    s.axis[0] = 0.3, s.axis[1] = 1, s.axis[2] = 0.2;
    s.radius = 9, s.minor_radius = 3.5;
    CHECK_OK(bvox_shape_draw(v, &s, BVOX_CSG_UNION));
    CHECK_OK(bvox_volume_set_spacing(v, 1, 1, 0.8, "mm"));
    vw_state *st;
    CHECK_OK(vw_open(v, 160, 120, &st));
    for (int view = 0; view < 3; view++) {
        if (view == 1) vw_set_axis_view(st, BVOX_VIEW_NEG_Y);
        if (view == 2) vw_trackball(st->R, 80, 60, 101, 77, 160, 120);
        st->need_cast = 1;
        CHECK_OK(vw_render(st));
        const vw_3d *p = &st->view3d;
        int shown = 0;
        for (int y = 0; y < p->h; y++)
            for (int x = 0; x < p->w; x++) {
                int32_t hit[3];
                int g = vw_pick(st, x, y, hit);
                int32_t d = p->depth[(size_t)y * (size_t)p->w + (size_t)x];
                CHECK_EQ(g, d >= 0);
                if (!g) continue;
                shown++;
                /* the hit box's entry depth, in the cast's pixel units */
                double p0[3], dir[3], t0 = 0, t1 = INFINITY;
                vw_pixel_ray(p, x, y, p0, dir);
                for (int a = 0; a < 3; a++) {
                    if (fabs(dir[a]) < 1e-12) continue;
                    double lo = (hit[a] - 0.5) * st->sp[a], hi = (hit[a] + 0.5) * st->sp[a];
                    double ta = (lo - p0[a]) / dir[a], tb = (hi - p0[a]) / dir[a];
                    if (ta > tb) { double q = ta; ta = tb; tb = q; }
                    t0 = ta > t0 ? ta : t0;
                    t1 = tb < t1 ? tb : t1;
                }
                CHECK(t0 <= t1 + 1e-9);
                CHECK_NEAR(t0 / p->step, d + 0.5, 0.5 + 1e-3);
            }
        CHECK(shown > 500);
    }
    vw_close(st);
    return 0;
}
