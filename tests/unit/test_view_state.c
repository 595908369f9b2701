/* test_view_state.c — the viewer's state without a window (viewer/): the
 * camera math (axis and isometric frames are right-handed rotations with the
 * stated view and up; a trackball drag turns about the screen axis at right
 * angles to it, keeps R orthonormal and is undone by the drag back), the cut
 * plane carried into world coordinates through the geometry, what keys do
 * (shading cycle, views, mosaic planes, cut on/off, zoom), and the paper's
 * split: a light change re-applies the table only (no cast: the cast counter
 * does not move, the object's pixels stay where they are but change
 * brightness), a turn casts again. */
#include "harness.h"
#include "render/render.h"
#include "view.h"

#include <stdlib.h>
#include <string.h>

static double det3(const double R[9])
{
    return R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
           R[2] * (R[3] * R[7] - R[4] * R[6]);
}

static int orthonormal(const double R[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = R[i * 3] * R[j * 3] + R[i * 3 + 1] * R[j * 3 + 1] + R[i * 3 + 2] * R[j * 3 + 2];
            if (fabs(d - (i == j)) > 1e-9) return 0;
        }
    return fabs(det3(R) - 1) < 1e-9;
}

static vw_state *open_ball(int n, double r, int w, int h)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_SPHERE;
    s.center[0] = s.center[1] = s.center[2] = (n - 1) / 2.0;
    s.radius = r;
    bvox_shape_draw(v, &s, BVOX_CSG_UNION);
    vw_state *st;
    if (vw_open(v, w, h, &st)) return NULL;
    return st;
}

TEST(axis_and_iso_frames)
{
    vw_state *s = open_ball(16, 5, 64, 64);
    CHECK(s);
    for (int view = 0; view < 6; view++) {
        vw_set_axis_view(s, (bvox_view)view);
        CHECK(orthonormal(s->R)); /* a rotation: never a mirror image */
        int axis = view / 2;
        double sign = view % 2 ? -1 : 1;
        CHECK_NEAR(s->R[6 + axis], sign, 1e-12);
        if (axis == 2) CHECK_NEAR(s->R[3 + 1], 1, 1e-12); /* +-z: y down */
        else CHECK_NEAR(s->R[3 + 2], -1, 1e-12);          /* +-x, +-y: z up */
    }
    vw_set_axis_view(s, BVOX_VIEW_POS_Z); /* +z: right = x, down = y (as bvox_cast_axis) */
    CHECK_NEAR(s->R[0], 1, 1e-12);
    CHECK_NEAR(s->R[4], 1, 1e-12);
    for (int c = 0; c < 8; c++) {
        vw_set_iso_view(s, c);
        CHECK(orthonormal(s->R));
        for (int a = 0; a < 3; a++) CHECK_NEAR(s->R[6 + a], (c >> a & 1 ? -1 : 1) / sqrt(3.0), 1e-12);
        CHECK(s->R[3 + 2] < 0); /* z up on the screen */
        CHECK_NEAR(s->R[2], 0, 1e-12); /* right is horizontal */
    }
    vw_close(s);
    return 0;
}

TEST(trackball)
{
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, R0[9];
    memcpy(R0, R, sizeof R);
    vw_trackball(R, 100, 100, 100, 100, 200, 200); /* no motion: no turn */
    for (int i = 0; i < 9; i++) CHECK_NEAR(R[i], R0[i], 1e-15);
    /* a drag to the right through the centre turns about the screen's
     * vertical (down) axis: the down row stays, the others turn */
    vw_trackball(R, 100, 100, 120, 100, 200, 200);
    CHECK(orthonormal(R));
    for (int a = 0; a < 3; a++) CHECK_NEAR(R[3 + a], R0[3 + a], 1e-12);
    double angle = acos(R[0]);
    CHECK(angle > 0.1 && angle < 0.3);
    /* the object's front follows the pointer to the right, so its +x end
     * turns away from the viewer: its eye depth (view row . x) grows */
    CHECK(R[6] > 0);
    /* dragging back restores the frame */
    vw_trackball(R, 120, 100, 100, 100, 200, 200);
    for (int i = 0; i < 9; i++) CHECK_NEAR(R[i], R0[i], 1e-12);
    /* a vertical drag: about the right axis */
    vw_trackball(R, 100, 100, 100, 130, 200, 200);
    CHECK(orthonormal(R));
    for (int a = 0; a < 3; a++) CHECK_NEAR(R[a], R0[a], 1e-12);
    /* many random drags keep R a rotation */
    for (int i = 0; i < 200; i++)
        vw_trackball(R, (double)(harness_rand() % 400), (double)(harness_rand() % 400),
                     (double)(harness_rand() % 400), (double)(harness_rand() % 400), 400, 300);
    CHECK(orthonormal(R));
    return 0;
}

TEST(cut_plane_world)
{
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){20, 30, 40}, &v));
    bvox_volume_fill(v, 1);
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.5, g.spacing[1] = 2, g.spacing[2] = 1.5;
    g.origin[0] = 10, g.origin[1] = -3, g.origin[2] = 7;
    /* direction: x and y swapped (a proper rotation about z by 90 degrees) */
    double D[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    memcpy(g.direction, D, sizeof D);
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    vw_state *s;
    CHECK_OK(vw_open(v, 64, 64, &s));
    vw_event ev = {.type = VW_EV_KEY, .key = 'c'};
    vw_handle(s, &ev);
    CHECK(s->cut);
    s->cut_s = 3.25;
    double m[3], e, pl[4];
    vw_cut_plane_local(s, m, &e);
    vw_cut_plane_world(s, pl);
    /* any local point q maps to world w = origin + D q with the same value */
    for (int i = 0; i < 20; i++) {
        double q[3] = {(double)(harness_rand() % 100) / 7, (double)(harness_rand() % 100) / 3,
                       (double)(harness_rand() % 100) / 5};
        double w[3];
        for (int r = 0; r < 3; r++) w[r] = g.origin[r] + D[r * 3] * q[0] + D[r * 3 + 1] * q[1] + D[r * 3 + 2] * q[2];
        double fl = m[0] * q[0] + m[1] * q[1] + m[2] * q[2] + e;
        double fw = pl[0] * w[0] + pl[1] * w[1] + pl[2] * w[2] + pl[3];
        CHECK_NEAR(fl, fw, 1e-9);
    }
    /* the plane passes cut_s from the centre along the normal */
    double p0[3];
    for (int a = 0; a < 3; a++) p0[a] = s->center[a] + s->cut_s * m[a];
    CHECK_NEAR(m[0] * p0[0] + m[1] * p0[1] + m[2] * p0[2] + e, 0, 1e-9);
    /* applying the cut keeps exactly what bvox_cut_plane keeps, and undo restores */
    bvox_volume *ref;
    CHECK_OK(bvox_volume_copy(s->model, &ref));
    CHECK_OK(bvox_cut_plane(ref, pl[0], pl[1], pl[2], pl[3], 1, NULL));
    ev.key = 'a';
    vw_handle(s, &ev);
    CHECK(bvox_volume_equal(s->model, ref));
    CHECK(!s->cut);
    CHECK(bvox_volume_count(ref) < 20 * 30 * 40);
    ev.key = 'z', ev.mods = VW_MOD_CTRL;
    vw_handle(s, &ev);
    CHECK_EQ(bvox_volume_count(s->model), 20 * 30 * 40);
    CHECK_EQ(s->count, 20 * 30 * 40);
    ev.key = 'y';
    vw_handle(s, &ev);
    CHECK(bvox_volume_equal(s->model, ref));
    bvox_volume_destroy(ref);
    vw_close(s);
    return 0;
}

static int key(vw_state *s, int k, unsigned mods)
{
    vw_event ev = {.type = VW_EV_KEY, .key = k, .mods = mods};
    vw_handle(s, &ev);
    return 0;
}

TEST(keys)
{
    vw_state *s = open_ball(24, 8, 400, 400);
    CHECK(s);
    vw_shade first = s->shade;
    int seen = 0;
    for (int i = 0; i < VW_NSHADE; i++) {
        seen |= 1 << s->shade;
        key(s, 's', 0);
    }
    CHECK_EQ(seen, (1 << VW_NSHADE) - 1); /* every mode, then back */
    CHECK_EQ(s->shade, first);
    key(s, 's', VW_MOD_SHIFT);
    CHECK_EQ(s->shade, (first + VW_NSHADE - 1) % VW_NSHADE);
    key(s, '3', 0); /* +y */
    CHECK_NEAR(s->R[7], 1, 1e-12);
    double z = s->zoom;
    key(s, '+', 0);
    CHECK(s->zoom > z);
    vw_event wheel = {.type = VW_EV_WHEEL, .wheel = -3};
    vw_handle(s, &wheel);
    CHECK(s->zoom < z);
    key(s, 'm', 0);
    CHECK_EQ(s->layout, VW_LAYOUT_MOSAIC);
    key(s, '1', 0);
    key(s, '8', 0);
    CHECK_EQ(s->planes, 0x7e);
    key(s, 'm', 0);
    key(s, 'o', 0);
    CHECK_EQ(s->layout, VW_LAYOUT_ORTHO);
    vw_rect r[4];
    vw_pane_kind k[4];
    CHECK_EQ(vw_panes(s, r, k), 4);
    CHECK_EQ(k[0], VW_PANE_3D);
    /* clicking in the xy slice moves the cursor's x and y, keeps z */
    CHECK_OK(vw_render(s));
    int32_t z0 = s->cursor[2];
    /* a slice's image is centred in its pane below a 16-pixel label, here
     * 24 voxels of 7.33 pixels (176 pixels): +-86 from the centre is inside */
    int cx = r[1].x + r[1].w / 2, cy = r[1].y + 16 + (r[1].h - 16) / 2;
    vw_event down = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = cx - 80, .y = cy + 80};
    vw_handle(s, &down);
    down.type = VW_EV_UP;
    vw_handle(s, &down);
    CHECK_EQ(s->cursor[2], z0);
    CHECK(s->cursor[0] <= 1 && s->cursor[1] >= 22);
    /* the xz slice shows z upwards: its bottom row is z = 0 */
    cx = r[2].x + r[2].w / 2, cy = r[2].y + 16 + (r[2].h - 16) / 2;
    vw_event down2 = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = cx + 86, .y = cy + 86};
    vw_handle(s, &down2);
    CHECK(s->cursor[0] >= 22);
    CHECK_EQ(s->cursor[2], 0);
    CHECK(s->cursor[1] >= 22); /* y kept from the xy click */
    /* ctrl+drag in the xy slice selects a rectangle through all of z */
    cx = r[1].x + r[1].w / 2, cy = r[1].y + 16 + (r[1].h - 16) / 2;
    vw_event sel = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .mods = VW_MOD_CTRL, .x = cx - 80, .y = cy - 80};
    vw_handle(s, &sel);
    sel.type = VW_EV_MOTION, sel.x = cx + 80, sel.y = cy;
    vw_handle(s, &sel);
    sel.type = VW_EV_UP;
    vw_handle(s, &sel);
    CHECK_EQ(s->sel_n, 2);
    CHECK(s->sel[0][0] == 1 && s->sel[0][1] == 1 && s->sel[0][2] == 0);
    CHECK(s->sel[1][0] == 22 && s->sel[1][1] == 12 && s->sel[1][2] == 23);
    key(s, VW_KEY_ESCAPE, 0);
    CHECK_EQ(s->sel_n, 0);
    key(s, 'c', 0);
    CHECK(s->cut);
    double n0[3];
    memcpy(n0, s->cut_n, sizeof n0);
    key(s, 't', 0);
    CHECK(fabs(s->cut_n[0] - n0[0]) + fabs(s->cut_n[1] - n0[1]) + fabs(s->cut_n[2] - n0[2]) > 0.05);
    CHECK_NEAR(s->cut_n[0] * s->cut_n[0] + s->cut_n[1] * s->cut_n[1] + s->cut_n[2] * s->cut_n[2], 1, 1e-12);
    double c0 = s->cut_s;
    key(s, VW_KEY_PAGEUP, VW_MOD_SHIFT);
    CHECK_NEAR(s->cut_s, c0 - 1, 1e-12); /* one voxel */
    key(s, 'f', 0);
    CHECK(!s->keep_above);
    CHECK_OK(vw_render(s));
    key(s, 'h', 0);
    CHECK(s->help);
    CHECK_OK(vw_render(s));
    key(s, 'x', 0); /* any key closes the help, and does nothing else */
    CHECK(!s->help);
    CHECK(!s->brush_add);
    key(s, 'q', 0);
    CHECK(s->quit);
    vw_close(s);
    return 0;
}

static int count_object(const vw_state *s, uint8_t bg0)
{
    int n = 0;
    for (size_t i = 0; i < (size_t)s->width * (size_t)s->height; i++) n += s->rgb[i * 3] != bg0;
    return n;
}

TEST(light_is_table_only)
{
    vw_state *s = open_ball(40, 14, 128, 128);
    CHECK(s);
    s->overlay = 0;
    for (int mode = 0; mode < VW_NSHADE; mode++) {
        s->shade = (vw_shade)mode;
        s->need_code = 1;
        CHECK_OK(vw_render(s));
        uint8_t *before = malloc((size_t)128 * 128 * 3);
        CHECK(before);
        memcpy(before, s->rgb, (size_t)128 * 128 * 3);
        long casts = bvox__render_cast_count();
        key(s, VW_KEY_LEFT, 0);
        key(s, VW_KEY_UP, 0);
        CHECK_OK(vw_render(s));
        CHECK_EQ(bvox__render_cast_count(), casts); /* no cast for a light change */
        int changed = 0, moved = 0;
        for (size_t i = 0; i < (size_t)128 * 128; i++) {
            int bg_a = before[i * 3] == 22 && before[i * 3 + 1] == 26, bg_b = s->rgb[i * 3] == 22 && s->rgb[i * 3 + 1] == 26;
            moved += bg_a != bg_b;
            changed += memcmp(before + i * 3, s->rgb + i * 3, 3) != 0;
        }
        CHECK_EQ(moved, 0);                     /* the object did not move */
        if (mode != VW_SHADE_DEPTH) CHECK(changed > 500); /* but it is lit differently */
        else CHECK_EQ(changed, 0);              /* depth shading ignores the light */
        free(before);
    }
    int n0 = count_object(s, 22);
    CHECK(n0 > 128 * 128 / 4);
    long casts = bvox__render_cast_count();
    vw_event d = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = 64, .y = 64};
    vw_handle(s, &d);
    d.type = VW_EV_MOTION, d.x = 90;
    vw_handle(s, &d);
    d.type = VW_EV_UP;
    vw_handle(s, &d);
    CHECK_OK(vw_render(s));
    CHECK_EQ(bvox__render_cast_count(), casts + 1); /* a turn casts */
    vw_close(s);
    return 0;
}

TEST(edits_through_the_state)
{
    vw_state *s = open_ball(32, 10, 128, 128);
    CHECK(s);
    bvox_volume *orig;
    CHECK_OK(bvox_volume_copy(s->model, &orig));
    int64_t n0 = bvox_volume_count(orig);
    /* box selection: remove, undo, keep */
    s->cursor[0] = 10, s->cursor[1] = 10, s->cursor[2] = 10;
    key(s, 'b', 0);
    s->cursor[0] = 20, s->cursor[1] = 21, s->cursor[2] = 22;
    key(s, 'b', VW_MOD_SHIFT);
    key(s, VW_KEY_DELETE, 0);
    bvox_volume *ref;
    CHECK_OK(bvox_volume_copy(orig, &ref));
    bvox_volume_fill_box(ref, (bvox_box){10, 10, 10, 21, 22, 23}, 0);
    CHECK(bvox_volume_equal(s->model, ref));
    key(s, 'z', VW_MOD_CTRL);
    CHECK(bvox_volume_equal(s->model, orig));
    bvox_volume_destroy(ref);
    key(s, 'k', 0); /* keep: what is left is the box's content */
    CHECK_OK(bvox_volume_crop(orig, (bvox_box){10, 10, 10, 21, 22, 23}, &ref));
    CHECK_EQ(bvox_volume_count(s->model), bvox_volume_count(ref));
    bvox_volume_destroy(ref);
    CHECK_OK(bvox_volume_copy(s->model, &ref));
    bvox_volume_fill_box(ref, (bvox_box){10, 10, 10, 21, 22, 23}, 0);
    CHECK_EQ(bvox_volume_count(ref), 0);
    bvox_volume_destroy(ref);
    key(s, 'z', VW_MOD_CTRL);
    CHECK(bvox_volume_equal(s->model, orig));
    /* a primitive: union of a box at the cursor, exactly bvox_shape_draw's */
    key(s, 'p', 0);
    key(s, 'p', 0);
    CHECK_EQ(s->prim, VW_PRIM_BOX);
    s->prim_size = 3;
    s->cursor[0] = 2, s->cursor[1] = 2, s->cursor[2] = 2;
    key(s, 'u', 0);
    CHECK_OK(bvox_volume_copy(orig, &ref));
    bvox_volume_fill_box(ref, (bvox_box){0, 0, 0, 6, 6, 6}, 1);
    CHECK(bvox_volume_equal(s->model, ref));
    CHECK_EQ(s->count, bvox_volume_count(ref));
    bvox_volume_destroy(ref);
    key(s, 'd', 0); /* difference of the same box */
    CHECK_OK(bvox_volume_copy(orig, &ref));
    bvox_volume_fill_box(ref, (bvox_box){0, 0, 0, 6, 6, 6}, 0);
    CHECK(bvox_volume_equal(s->model, ref));
    bvox_volume_destroy(ref);
    key(s, 'z', VW_MOD_CTRL);
    key(s, 'z', VW_MOD_CTRL);
    CHECK(bvox_volume_equal(s->model, orig));
    /* the brush in the +z view: a stroke is one undo step */
    key(s, VW_KEY_ESCAPE, 0);
    key(s, '5', 0);
    key(s, 'e', 0);
    CHECK_OK(vw_render(s));
    vw_event d = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = 64, .y = 64};
    vw_handle(s, &d);
    CHECK_OK(vw_render(s));
    d.type = VW_EV_MOTION, d.x = 70;
    vw_handle(s, &d);
    d.type = VW_EV_UP;
    vw_handle(s, &d);
    CHECK(bvox_volume_count(s->model) < n0);
    CHECK_EQ(bvox_journal_steps(s->journal), 1);
    key(s, 'z', VW_MOD_CTRL);
    CHECK(bvox_volume_equal(s->model, orig));
    CHECK_EQ(s->count, n0);
    bvox_volume_destroy(orig);
    vw_close(s);
    return 0;
}

TEST(coarse_drag_then_full)
{
    vw_state *s = open_ball(48, 17, 160, 160);
    CHECK(s);
    s->overlay = 0;
    s->pan[0] = 13, s->pan[1] = -7;
    CHECK_OK(vw_render(s));
    CHECK(!s->view3d.coarse);
    uint8_t *full = malloc((size_t)160 * 160 * 3);
    CHECK(full);
    memcpy(full, s->rgb, (size_t)160 * 160 * 3);
    /* every cast counts as slow: a drag goes coarse, the release does not */
    s->coarse_ms = 1e-9;
    vw_event d = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = 80, .y = 80};
    vw_handle(s, &d);
    d.type = VW_EV_MOTION, d.x = 81; /* a tiny turn */
    vw_handle(s, &d);
    CHECK(s->coarse);
    CHECK_OK(vw_render(s));
    CHECK(s->view3d.coarse);
    /* the coarse picture is the same object at the same place: silhouettes
     * differ by at most a coarse pixel's width along the outline */
    int obj = 0, diff = 0;
    for (size_t i = 0; i < (size_t)160 * 160; i++) {
        int a = full[i * 3] != 22, b = s->rgb[i * 3] != 22;
        obj += a;
        diff += a != b;
    }
    CHECK(obj > 4000);
    CHECK(diff < obj / 10);
    int32_t hit[3];
    CHECK(vw_pick(s, 80 + 13, 80 - 7, hit)); /* the middle of the ball, panned */
    d.type = VW_EV_UP;
    vw_handle(s, &d);
    CHECK(!s->coarse);
    CHECK_OK(vw_render(s));
    CHECK(!s->view3d.coarse);
    free(full);
    vw_close(s);
    return 0;
}

/* The smooth mode (issue 18) on a voxelized ball seen along +z: its codes
 * are the gradient layout's 64 x 64 bins of the eye-frame normal's right
 * and up components, so each pixel's normal can be read back and compared
 * with the true sphere normal at that pixel (centre and radius of the
 * disc from its pixels). Inside 0.9 of the radius (the bins are coarse in
 * the viewing component at the rim) 95 % are within 10 degrees. The binary
 * mode of the same view has at most 27 normals x 8 cues distinct codes,
 * the smooth one hundreds (a sphere, not facets). */
TEST(smooth_mode_normals)
{
    vw_state *s = open_ball(64, 26, 256, 256);
    CHECK(s);
    s->overlay = 0;
    vw_set_axis_view(s, BVOX_VIEW_POS_Z);
    int distinct[2] = {0, 0};
    for (int pass = 0; pass < 2; pass++) {
        s->shade = pass ? VW_SHADE_SMOOTH : VW_SHADE_BINARY;
        s->need_code = 1;
        CHECK_OK(vw_render(s));
        const vw_3d *v = &s->view3d;
        CHECK(v->valid && v->w == 256 && v->h == 256);
        static uint8_t seen[BVOX_SCODES];
        memset(seen, 0, sizeof seen);
        double sx = 0, sy = 0, n = 0;
        for (int y = 0; y < v->h; y++)
            for (int x = 0; x < v->w; x++) {
                uint16_t c = v->code[(size_t)y * (size_t)v->w + (size_t)x];
                if (c >= BVOX_SCODE_CUT) continue;
                if (pass) CHECK(c < 4096); /* the gradient layout */
                distinct[pass] += !seen[c];
                seen[c] = 1;
                sx += x, sy += y, n++;
            }
        CHECK(n > 3000);
        if (!pass) continue;
        const double cx = sx / n, cy = sy / n, R = sqrt(n / 3.14159265358979323846);
        int inside = 0, good = 0;
        for (int y = 0; y < v->h; y++)
            for (int x = 0; x < v->w; x++) {
                uint16_t c = v->code[(size_t)y * (size_t)v->w + (size_t)x];
                double tr = (x + 0.5 - cx) / R, tu = -(y + 0.5 - cy) / R; /* rows go down */
                double rho2 = tr * tr + tu * tu;
                if (c >= BVOX_SCODE_CUT || rho2 > 0.81) continue;
                double nr = ((c % 64) + 0.5) / 32 - 1, nu = ((c / 64) + 0.5) / 32 - 1;
                double nz = sqrt(fmax(0, 1 - nr * nr - nu * nu)), tz = sqrt(1 - rho2);
                double cosang = nr * tr + nu * tu + nz * tz;
                inside++;
                good += cosang >= cos(10 * 3.14159265358979323846 / 180);
            }
        CHECK(inside > 2000);
        CHECK(good >= 0.95 * inside);
    }
    CHECK(distinct[0] <= 27 * 8);
    CHECK(distinct[1] > 300);
    vw_close(s);
    return 0;
}

/* On a machine where the smooth codes are slow (here: every one counts as
 * slow), a turn drag shows the gradient mode's codes (same bins, same
 * table: the picture stays lit the same way, only from the depth map) and
 * the release makes the smooth codes again, equal to those of a frame drawn
 * without any drag. */
TEST(smooth_drag_then_full)
{
    vw_state *s = open_ball(48, 17, 160, 160);
    CHECK(s);
    s->overlay = 0;
    s->shade = VW_SHADE_SMOOTH;
    CHECK_OK(vw_render(s));
    CHECK(!s->fast_codes && s->last_smooth_ms > 0);
    const size_t n = (size_t)160 * 160;
    uint16_t *before = malloc(n * sizeof *before), *after = malloc(n * sizeof *after);
    CHECK(before && after);
    s->coarse_ms = 1e-9;
    vw_event d = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = 80, .y = 80};
    vw_handle(s, &d);
    d.type = VW_EV_MOTION, d.x = 84;
    vw_handle(s, &d);
    s->coarse = 0; /* the cast at full size: only the codes differ */
    CHECK_OK(vw_render(s));
    CHECK(s->fast_codes);
    memcpy(before, s->view3d.code, n * sizeof *before);
    d.type = VW_EV_UP;
    vw_handle(s, &d);
    CHECK(s->need_code);
    CHECK_OK(vw_render(s));
    CHECK(!s->fast_codes);
    memcpy(after, s->view3d.code, n * sizeof *after);
    int obj = 0, differ = 0;
    for (size_t i = 0; i < n; i++) {
        CHECK_EQ(before[i] >= BVOX_SCODE_CUT, after[i] >= BVOX_SCODE_CUT); /* same silhouette */
        obj += after[i] < BVOX_SCODE_CUT;
        differ += before[i] != after[i];
    }
    CHECK(obj > 4000);
    CHECK(differ > obj / 4); /* the drag's codes were the stand-in */
    s->need_code = 1;        /* a frame without a drag: the same smooth codes */
    CHECK_OK(vw_render(s));
    CHECK(!memcmp(after, s->view3d.code, n * sizeof *after));
    free(before), free(after);
    vw_close(s);
    return 0;
}

/* A turn in the smooth mode keeps to drag_frame_ms (60 Hz by default): when
 * the last smooth frame (its full cast plus its codes) took longer, the drag
 * shows the stand-in codes even where the codes alone are under coarse_ms;
 * when it fits, the drag stays smooth. */
static int drag_codes_with_budget(double frame_ms)
{
    vw_state *s = open_ball(48, 17, 160, 160);
    if (!s) return -1;
    s->overlay = 0;
    s->shade = VW_SHADE_SMOOTH;
    s->coarse_ms = 1e9; /* the codes alone never count as slow */
    s->drag_frame_ms = frame_ms;
    int fast = -1;
    if (!vw_render(s) && !s->fast_codes && s->last_smooth_ms > 0) {
        vw_event d = {.type = VW_EV_DOWN, .button = VW_BUTTON_LEFT, .x = 80, .y = 80};
        vw_handle(s, &d);
        d.type = VW_EV_MOTION, d.x = 84;
        vw_handle(s, &d);
        s->coarse = 0;
        if (!vw_render(s)) fast = s->fast_codes;
        d.type = VW_EV_UP;
        vw_handle(s, &d);
        if (fast >= 0 && (vw_render(s) || s->fast_codes)) fast = -1; /* smooth again */
    }
    vw_close(s);
    return fast;
}

TEST(smooth_drag_keeps_frame_budget)
{
    CHECK_EQ(drag_codes_with_budget(1e-9), 1); /* over budget: stand-in codes */
    CHECK_EQ(drag_codes_with_budget(1e9), 0);  /* within it: smooth while turning */
    vw_state *s = open_ball(16, 5, 64, 64);
    CHECK(s);
    CHECK(s->drag_frame_ms > 16 && s->drag_frame_ms < 17); /* the default: 60 Hz */
    vw_close(s);
    return 0;
}
