/* test_view_cutface.c — the cut face in the viewer's 3D pane against the
 * truth. For each pixel the voxel it shows (vw_pick: the first box its ray
 * meets) and the face of that box the ray enters through are known; that
 * face is on the cut exactly when the voxel behind it was in the model
 * before the cut (the cut removed it). The pixels the shading stage marks
 * as cut face (bvox_shade_codes' codes BVOX_SCODE_CUT..) are compared with
 * that, over 12 views and tilted planes: none is missed, and the extra ones
 * (the old surface right beside the plane, which a depth to one step cannot
 * tell apart) are fewer than 4 % and fewer than the viewer's former rule
 * (|m . p + e| <= one voxel + one step at the front of the step) marked. */
#include "harness.h"
#include "view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct tally {
    long truth, marked, both;      /* the rule of the library (shading codes) */
    long old_marked, old_both;     /* the viewer's former rule: |m.p + e| <= shift + step at depth d */
} tally;

static int count_view(vw_state *s, tally *t)
{
    CHECK_OK(vw_render(s));
    const vw_3d *v = &s->view3d;
    double m[3], e;
    vw_cut_plane_local(s, m, &e);
    double shift = 0;
    for (int a = 0; a < 3; a++) shift = fmax(shift, fabs(m[a]) * s->sp[a]);
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            size_t i = (size_t)y * (size_t)v->w + (size_t)x;
            int32_t d = v->depth[i];
            if (d < 0) continue;
            double p0[3], dir[3];
            int32_t hit[3];
            vw_pixel_ray(v, x, y, p0, dir);
            if (!vw_pick_ray(s->cut_copy, s->sp, p0, dir, hit)) continue;
            /* the entry face: the axis whose slab the ray enters last */
            int fa = -1;
            double best = -INFINITY;
            for (int a = 0; a < 3; a++) {
                if (fabs(dir[a]) < 1e-12) continue;
                double face = (hit[a] - 0.5 * (dir[a] > 0 ? 1 : -1)) * s->sp[a];
                double ta = (face - p0[a]) / dir[a];
                if (ta > best) best = ta, fa = a;
            }
            CHECK(fa >= 0);
            int32_t q[3] = {hit[0], hit[1], hit[2]};
            q[fa] -= dir[fa] > 0 ? 1 : -1;
            int truth = q[fa] >= 0 && q[fa] < (fa == 0 ? s->dims.nx : fa == 1 ? s->dims.ny : s->dims.nz) &&
                        bvox_volume_get(s->model, q[0], q[1], q[2]);
            int marked = v->code[i] >= BVOX_SCODE_CUT && v->code[i] < BVOX_SCODE_BACKGROUND;
            double f = e;
            for (int a = 0; a < 3; a++)
                f += m[a] * (v->origin[a] + (x * v->eye[a] + y * v->eye[3 + a]) * v->pixel +
                             d * v->step * v->eye[6 + a]);
            int old = fabs(f) <= shift + v->step;
            t->truth += truth, t->marked += marked, t->both += truth && marked;
            t->old_marked += old, t->old_both += truth && old;
        }
    return 0;
}

TEST(cut_face_against_truth)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){64, 64, 64}, &vol));
    bvox_shape sh;
    memset(&sh, 0, sizeof sh);
    sh.kind = BVOX_SHAPE_SPHERE, sh.center[0] = sh.center[1] = sh.center[2] = 31.5, sh.radius = 18;
    CHECK_OK(bvox_shape_draw(vol, &sh, BVOX_CSG_UNION));
    vw_state *s;
    CHECK_OK(vw_open(vol, 320, 320, &s));
    tally t = {0, 0, 0, 0, 0};
    for (int k = 0; k < 12; k++) {
        vw_set_axis_view(s, BVOX_VIEW_POS_Z);
        s->cut = 1, s->keep_above = 1, s->cut_s = 1.0 * (k % 3);
        memcpy(s->cut_n, s->R + 6, sizeof s->cut_n);
        const double axis[3] = {cos(k * 0.7), sin(k * 0.7), 0};
        vw_cut_tilt(s, axis, 0.05 * k); /* the plane a little tilted */
        vw_rotate(s->R, axis, 0.15 + 0.08 * k); /* and seen obliquely */
        s->need_surface = 1;
        CHECK(!count_view(s, &t));
    }
    fprintf(stderr, "truth %ld; library rule: marked %ld, right %ld (missed %ld, extra %ld); "
                    "former viewer rule: marked %ld, right %ld (missed %ld, extra %ld)\n",
            t.truth, t.marked, t.both, t.truth - t.both, t.marked - t.both, t.old_marked, t.old_both,
            t.truth - t.old_both, t.old_marked - t.old_both);
    CHECK(t.truth > 100000);
    CHECK_EQ(t.both, t.truth);                    /* no exposed face missed */
    CHECK(t.marked - t.both <= t.truth * 4 / 100); /* a thin rim of the old surface */
    CHECK(t.marked - t.both < t.old_marked - t.old_both);
    vw_close(s);
    return 0;
}
