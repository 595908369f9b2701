/* test_view_measure.c — the viewer's desktop features without a window
 * (viewer/measure.c, labels.c, view_state.c): the ruler's length in
 * physical units on anisotropic voxels (hand-computed), the selection box's
 * volume against a voxel-by-voxel count (and counted again after an edit),
 * the scale bar's round lengths, a resize (canvas, panes and the 3D pane's
 * pre-image follow; the object stays centred), a dropped file replacing the
 * model (and a bad one keeping it, with a message), and a label volume shown
 * in its table's colours with a click naming the label. */
#include "harness.h"
#include "view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static vw_state *open_ball(int n, double r, const double sp[3], int w, int h)
{
    bvox_volume *v;
    if (bvox_volume_create((bvox_dims){n, n, n}, &v)) return NULL;
    if (sp && bvox_volume_set_spacing(v, sp[0], sp[1], sp[2], "um")) return NULL;
    bvox_shape s;
    memset(&s, 0, sizeof s);
    s.kind = BVOX_SHAPE_SPHERE;
    for (int a = 0; a < 3; a++) s.center[a] = (n - 1) / 2.0 * (sp ? sp[a] : 1);
    s.radius = r;
    bvox_shape_draw(v, &s, BVOX_CSG_UNION);
    vw_state *st;
    if (vw_open(v, w, h, &st)) return NULL;
    return st;
}

static void press(vw_state *s, int key, unsigned mods)
{
    vw_event e = {.type = VW_EV_KEY, .key = key, .mods = mods};
    vw_handle(s, &e);
}

TEST(ruler_physical_length)
{
    const double sp[3] = {2, 3, 5};
    vw_state *s = open_ball(16, 10, sp, 64, 64);
    CHECK(s);
    CHECK_NEAR(vw_ruler_length(s), -1, 0);
    s->cursor[0] = 1, s->cursor[1] = 2, s->cursor[2] = 3;
    press(s, 'g', 0);
    CHECK_EQ(s->ruler_n, 1);
    CHECK_NEAR(vw_ruler_length(s), -1, 0);
    s->cursor[0] = 4, s->cursor[1] = 6, s->cursor[2] = 7;
    press(s, 'g', 0);
    CHECK_EQ(s->ruler_n, 2);
    /* (3 * 2, 4 * 3, 4 * 5) um = (6, 12, 20): sqrt(36 + 144 + 400) */
    CHECK_NEAR(vw_ruler_length(s), sqrt(580.0), 1e-12);
    CHECK(strstr(s->status, "ruler 24.0832 um"));
    CHECK_OK(vw_render(s));
    press(s, 'g', 0); /* a third point starts a new ruler */
    CHECK_EQ(s->ruler_n, 1);
    vw_close(s);
    return 0;
}

TEST(selection_volume)
{
    const double sp[3] = {0.5, 0.5, 2};
    vw_state *s = open_ball(20, 4.2, sp, 64, 64);
    CHECK(s);
    int64_t count;
    double vol;
    CHECK_OK(vw_selection_volume(s, &count, &vol));
    CHECK_EQ(count, 0); /* no box */
    s->cursor[0] = 3, s->cursor[1] = 12, s->cursor[2] = 9;
    press(s, 'b', 0);
    s->cursor[0] = 11, s->cursor[1] = 5, s->cursor[2] = 14;
    press(s, 'b', VW_MOD_SHIFT);
    int64_t want = 0;
    for (int z = 9; z <= 14; z++)
        for (int y = 5; y <= 12; y++)
            for (int x = 3; x <= 11; x++) want += bvox_volume_get(s->model, x, y, z);
    CHECK(want > 50);
    CHECK_OK(vw_selection_volume(s, &count, &vol));
    CHECK_EQ(count, want);
    CHECK_NEAR(vol, want * 0.5 * 0.5 * 2, 1e-9);
    bvox_box b;
    CHECK(vw_selection_box(s, &b));
    CHECK(b.x0 == 3 && b.x1 == 12 && b.y0 == 5 && b.y1 == 13 && b.z0 == 9 && b.z1 == 15);
    /* removing the box empties it: counted again */
    CHECK_OK(vw_edit_box(s, 0));
    CHECK_OK(vw_selection_volume(s, &count, &vol));
    CHECK_EQ(count, 0);
    CHECK_OK(vw_render(s)); /* the overlay line with the box */
    vw_close(s);
    return 0;
}

TEST(scale_bar_lengths)
{
    CHECK_NEAR(vw_scale_bar_length(0.37, 100), 20, 0);   /* at most 37: 20 */
    CHECK_NEAR(vw_scale_bar_length(1, 100), 100, 0);     /* exactly 100 */
    CHECK_NEAR(vw_scale_bar_length(3, 100), 200, 0);     /* at most 300: 200 */
    CHECK_NEAR(vw_scale_bar_length(0.01, 250), 2, 1e-15); /* at most 2.5: 2 */
    CHECK_NEAR(vw_scale_bar_length(7, 100), 500, 0);     /* at most 700: 500 */
    CHECK_NEAR(vw_scale_bar_length(0, 100), 0, 0);
    CHECK_NEAR(vw_scale_bar_length(1, 0), 0, 0);
    return 0;
}

/* The centre of the object's pixels below the overlay's rows. */
static void object_centre(const vw_state *s, double *cx, double *cy)
{
    double sx = 0, sy = 0, n = 0;
    for (int y = 80; y < s->height; y++)
        for (int x = 0; x < s->width; x++) {
            const uint8_t *p = s->rgb + ((size_t)y * s->width + x) * 3;
            if (p[0] == 22 && p[1] == 26 && p[2] == 34) continue;
            if (y > s->height - 60 && x < s->width / 2) continue; /* the scale bar */
            sx += x, sy += y, n++;
        }
    *cx = n ? sx / n : -1, *cy = n ? sy / n : -1;
}

TEST(resize_relays_panes)
{
    vw_state *s = open_ball(32, 9, NULL, 200, 200);
    CHECK(s);
    s->overlay = 0;
    CHECK_OK(vw_render(s));
    CHECK(s->view3d.w == 200 && s->view3d.h == 200);
    vw_event e = {.type = VW_EV_RESIZE, .x = 360, .y = 240};
    vw_handle(s, &e);
    CHECK(s->width == 360 && s->height == 240);
    CHECK_OK(vw_render(s));
    CHECK(s->view3d.w == 360 && s->view3d.h == 240); /* the pre-image follows the pane */
    double cx, cy;
    object_centre(s, &cx, &cy);
    CHECK_NEAR(cx, 180, 3);
    CHECK_NEAR(cy, 120 + 0, 45); /* rows above 80 are skipped: the centre moves down a bit */
    /* the four panes tile the new canvas */
    press(s, 'o', 0);
    vw_rect r[4];
    vw_pane_kind k[4];
    CHECK_EQ(vw_panes(s, r, k), 4);
    int64_t area = 0;
    for (int i = 0; i < 4; i++) area += (int64_t)r[i].w * r[i].h;
    CHECK_EQ(area, 360 * 240);
    CHECK_OK(vw_render(s));
    CHECK(s->view3d.w == 180 && s->view3d.h == 120);
    /* refused sizes change nothing */
    e.x = 20;
    vw_handle(s, &e);
    CHECK(s->width == 360 && s->height == 240);
    vw_close(s);
    return 0;
}

TEST(drop_opens_file)
{
    vw_state *s = open_ball(16, 5, NULL, 96, 96);
    CHECK(s);
    s->cursor[0] = 2;
    press(s, 'g', 0);
    bvox_volume *v;
    CHECK_OK(bvox_volume_create((bvox_dims){10, 20, 30}, &v));
    CHECK_OK(bvox_volume_set_spacing(v, 1, 2, 3, "mm"));
    bvox_shape b;
    memset(&b, 0, sizeof b);
    b.kind = BVOX_SHAPE_BOX;
    b.center[0] = 4.5, b.center[1] = 19, b.center[2] = 43.5;
    b.semi_axes[0] = 2, b.semi_axes[1] = 4, b.semi_axes[2] = 6;
    CHECK_OK(bvox_shape_draw(v, &b, BVOX_CSG_UNION));
    int64_t want = bvox_volume_count(v);
    const char *path = harness_path("dropped.nii");
    CHECK_OK(bvox_write(path, v, NULL));
    bvox_volume_destroy(v);
    vw_event e = {.type = VW_EV_DROP, .path = path};
    vw_handle(s, &e);
    CHECK(s->dims.nx == 10 && s->dims.ny == 20 && s->dims.nz == 30);
    CHECK_EQ(s->count, want);
    CHECK_EQ(bvox_volume_count(s->model), want);
    CHECK_NEAR(s->sp[2], 3, 1e-6);
    CHECK_EQ(s->ruler_n, 0); /* marks of the old model are gone */
    CHECK(strstr(s->status, "opened"));
    CHECK_OK(vw_render(s));
    /* a file that is not a volume: the model stays, the status says why */
    e.path = harness_path("no-such-file.nii");
    vw_handle(s, &e);
    CHECK(s->dims.nx == 10 && s->count == want);
    CHECK(strstr(s->status, "cannot open the dropped file"));
    CHECK_OK(vw_render(s));
    vw_close(s);
    return 0;
}

TEST(labels_in_colours)
{
    /* a 24 x 16 x 8 label volume: label 3 fills x < 12, label 7 x >= 12 of a
     * slab; the table makes 3 pure red and 7 pure blue */
    const int nx = 24, ny = 16, nz = 8;
    uint8_t *raw = calloc((size_t)nx * ny * nz, 1);
    CHECK(raw);
    for (int z = 2; z < 6; z++)
        for (int y = 3; y < 13; y++)
            for (int x = 2; x < 22; x++) raw[(z * ny + y) * nx + x] = x < 12 ? 3 : 7;
    bvox_read_opts o = BVOX_READ_OPTS_INIT;
    o.format = "raw";
    o.raw_dims = (bvox_dims){nx, ny, nz};
    o.raw_dtype = BVOX_DT_U8;
    bvox_labelset *set = NULL;
    CHECK_OK(bvox_labels_read_memory(raw, (size_t)nx * ny * nz, "labels.raw", &o, 0, &set));
    free(raw);
    const char lut[] = "3 left_part 255 0 0 255\n7 right_part 0 0 255 255\n";
    bvox_label_table *t = NULL;
    CHECK_OK(bvox_label_table_parse(lut, sizeof lut - 1, "lut.txt", &t));
    bvox_volume *model;
    CHECK_OK(vw_labels_model(set, &model));
    CHECK_EQ(bvox_volume_count(model), 20 * 10 * 4);
    vw_state *s;
    CHECK_OK(vw_open(model, 240, 240, &s));
    CHECK_OK(vw_set_labels(s, set, t));
    s->overlay = 0;
    vw_set_axis_view(s, BVOX_VIEW_POS_Z);
    CHECK_OK(vw_render(s));
    /* +z view: x to the right. Object pixels left of the middle are red,
     * right of it blue (brightness from the shading). */
    int red = 0, blue = 0, other = 0;
    for (int y = 0; y < 240; y++)
        for (int x = 0; x < 240; x++) {
            const uint8_t *p = s->rgb + ((size_t)y * 240 + x) * 3;
            if (p[0] == 22 && p[1] == 26 && p[2] == 34) continue;
            if (p[0] > 20 && p[1] == 0 && p[2] == 0) red += x < 120 ? 1 : -1000;
            else if (p[2] > 20 && p[0] == 0 && p[1] == 0) blue += x >= 120 ? 1 : -1000;
            else other++;
        }
    CHECK(red > 5000 && blue > 5000);
    CHECK(other < (red + blue) / 50); /* the rim at most */
    /* the label of a voxel, and a click names it */
    const char *name;
    uint8_t rgb[3];
    CHECK_EQ(vw_label_at(s, (int32_t[]){4, 5, 3}, &name, rgb), 3);
    CHECK(!strcmp(name, "left_part") && rgb[0] == 255 && rgb[2] == 0);
    CHECK_EQ(vw_label_at(s, (int32_t[]){0, 0, 0}, &name, NULL), 0);
    vw_event e = {.type = VW_EV_MOTION, .x = 180, .y = 120};
    vw_handle(s, &e);
    e.type = VW_EV_DOWN, e.button = VW_BUTTON_LEFT;
    vw_handle(s, &e);
    e.type = VW_EV_UP;
    vw_handle(s, &e);
    CHECK(strstr(s->status, "label 7 right_part"));
    CHECK_EQ(s->cursor[2], 2); /* the +z view looks along +z: the first voxel is the slab's bottom */
    /* the slices too: the xy pane (top right) shows both colours, left and right */
    press(s, 'o', 0);
    CHECK_OK(vw_render(s));
    int sred = 0, sblue = 0;
    for (int y = 20; y < 120; y++)
        for (int x = 120; x < 240; x++) {
            const uint8_t *p = s->rgb + ((size_t)y * 240 + x) * 3;
            /* the cursor lines blend in yellow: pure colours only */
            if (p[0] == 255 && p[1] == 0 && p[2] == 0) sred += x < 180 ? 1 : -1000;
            if (p[0] == 0 && p[1] == 0 && p[2] == 255) sblue += x >= 180 ? 1 : -1000;
        }
    CHECK(sred > 200 && sblue > 200);
    vw_close(s);
    bvox_labelset_destroy(set);
    bvox_label_table_destroy(t);
    return 0;
}
