/*
 * input.c — what each key and mouse gesture does to the view state: camera
 * (trackball, axis and isometric views, zoom, pan), light, shading mode, cut
 * plane, layout, cursor, selection, brush and primitive; edits through
 * edits.c, picking through frame.c. No drawing and no SDL here: an event
 * changes numbers and sets the dirty flags that tell frame.c what to
 * recompute (a light change only the table).
 */
#include "view.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double deg = 3.14159265358979323846 / 180.0;

/* ------------------------------------------------------------ actions */

static void say(vw_state *s, const char *fmt, const char *arg)
{
    snprintf(s->status, sizeof s->status, fmt, arg);
}

static void clamp_cursor(vw_state *s)
{
    const int32_t n[3] = {s->dims.nx, s->dims.ny, s->dims.nz};
    for (int a = 0; a < 3; a++) {
        if (s->cursor[a] < 0) s->cursor[a] = 0;
        if (s->cursor[a] >= n[a]) s->cursor[a] = n[a] - 1;
    }
}

static void report(vw_state *s, bvox_status st, const char *what)
{
    if (st) snprintf(s->status, sizeof s->status, "%s failed: %.100s", what, bvox_errmsg());
    if (st && s->log) fprintf(s->log, "view: %s failed: %s\n", what, bvox_errmsg());
}

static void cut_toggle(vw_state *s)
{
    s->cut = !s->cut;
    if (s->cut) { /* a new plane through the centre, facing the viewer: the far side kept */
        memcpy(s->cut_n, s->R + 6, sizeof s->cut_n);
        s->cut_s = 0;
        s->keep_above = 1;
    }
    s->need_surface = 1;
    say(s, "%s", s->cut ? "cut plane on" : "cut plane off");
}

static void key(vw_state *s, int k, unsigned mods)
{
    const int shift = mods & VW_MOD_SHIFT, ctrl = mods & VW_MOD_CTRL;
    if (s->help && k != 'h' && k != '?' && k != VW_KEY_F1 && k != 'q') {
        s->help = 0; /* any key closes the help */
        return;
    }
    if (ctrl) {
        switch (k) {
        case 'z': report(s, vw_undo(s, shift ? 1 : 0), "undo"); return;
        case 'y': report(s, vw_undo(s, 1), "redo"); return;
        case 's': report(s, vw_save(s, s->save_path), "save"); return;
        case 'p': k = VW_KEY_F12; break; /* a screenshot, as f12 */
        default: return;
        }
    }
    if (s->layout == VW_LAYOUT_MOSAIC && k >= '1' && k <= '8') {
        s->planes ^= (uint8_t)(1u << (k - '1'));
        s->need_mosaic = 1;
        return;
    }
    switch (k) {
    case 'q': s->quit = 1; break;
    case 'h': case '?': case VW_KEY_F1: s->help = !s->help; break;
    case 'v': s->overlay = !s->overlay; break;
    case '1': case '2': case '3': case '4': case '5': case '6':
        vw_set_axis_view(s, (bvox_view)(k - '1'));
        say(s, "view %s", bvox_view_name((bvox_view)(k - '1')));
        break;
    case 'i':
        s->iso = (s->iso + (shift ? 7 : 1)) & 7;
        vw_set_iso_view(s, s->iso);
        say(s, "%s", "isometric view");
        break;
    case 'r':
        s->zoom = 1;
        vw_set_iso_view(s, s->iso);
        break;
    case '+': case '=': s->zoom *= 1.25; s->need_cast = 1; break;
    case '-': s->zoom /= 1.25; s->need_cast = 1; break;
    case VW_KEY_LEFT: s->light.azimuth += 15; s->need_lut = 1; break;
    case VW_KEY_RIGHT: s->light.azimuth -= 15; s->need_lut = 1; break;
    case VW_KEY_UP: s->light.elevation += 10; s->need_lut = 1; break;
    case VW_KEY_DOWN: s->light.elevation -= 10; s->need_lut = 1; break;
    case 'l': s->light = (bvox_light)BVOX_LIGHT_INIT; s->need_lut = 1; break;
    case 's':
        s->shade = (vw_shade)((s->shade + (shift ? VW_NSHADE - 1 : 1)) % VW_NSHADE);
        s->need_code = 1;
        break;
    case 'c': cut_toggle(s); break;
    case VW_KEY_PAGEUP: case VW_KEY_PAGEDOWN:
        if (!s->cut) break;
        s->cut_s += (k == VW_KEY_PAGEUP ? -1 : 1) * (shift ? vw_min_spacing(s) : s->radius * 0.05);
        s->need_surface = 1;
        break;
    case 't': if (s->cut) vw_cut_tilt(s, s->R, (shift ? -5 : 5) * deg); break;
    case 'y': if (s->cut) vw_cut_tilt(s, s->R + 3, (shift ? -5 : 5) * deg); break;
    case 'f': if (s->cut) s->keep_above = !s->keep_above, s->need_surface = 1; break;
    case 'a': if (s->cut) report(s, vw_apply_cut(s), "cut"); break;
    case 'o': s->layout = s->layout == VW_LAYOUT_ORTHO ? VW_LAYOUT_3D : VW_LAYOUT_ORTHO; s->need_cast = 1; break;
    case 'm': s->layout = s->layout == VW_LAYOUT_MOSAIC ? VW_LAYOUT_3D : VW_LAYOUT_MOSAIC; s->need_cast = 1; break;
    case 'n':
        s->mosaic_display = (bvox_mosaic_display)((s->mosaic_display + 1) % 3);
        s->need_mosaic = 1;
        break;
    case 'e': s->brush = !s->brush; say(s, "%s", s->brush ? "brush on" : "brush off"); break;
    case 'x': s->brush_add = !s->brush_add; break;
    case '[': if (s->brush_radius > 0) s->brush_radius--; break;
    case ']': if (s->brush_radius < 256) s->brush_radius++; break;
    case 'b':
        if (shift) {
            memcpy(s->sel[1], s->cursor, sizeof s->sel[1]);
            if (s->sel_n < 1) memcpy(s->sel[0], s->cursor, sizeof s->sel[0]);
            s->sel_n = 2;
        } else {
            memcpy(s->sel[0], s->cursor, sizeof s->sel[0]);
            memcpy(s->sel[1], s->cursor, sizeof s->sel[1]);
            s->sel_n = 1;
        }
        break;
    case VW_KEY_DELETE: case VW_KEY_BACKSPACE: if (s->sel_n) report(s, vw_edit_box(s, 0), "remove box"); break;
    case 'k': if (s->sel_n) report(s, vw_edit_box(s, 1), "keep box"); break;
    case VW_KEY_ESCAPE: s->sel_n = 0; s->prim = VW_PRIM_NONE; break;
    case 'p': s->prim = (vw_prim)((s->prim + 1) % VW_NPRIM); break;
    case ',': if (s->prim_size > 1) s->prim_size--; break;
    case '.': if (s->prim_size < 4096) s->prim_size++; break;
    case 'u': if (s->prim) report(s, vw_apply_primitive(s, BVOX_CSG_UNION), "union"); break;
    case 'd': if (s->prim) report(s, vw_apply_primitive(s, BVOX_CSG_DIFFERENCE), "difference"); break;
    case 'g': /* the ruler: a point at the cursor; a third starts again */
        if (s->ruler_n == 2) s->ruler_n = 0;
        memcpy(s->ruler[s->ruler_n++], s->cursor, sizeof s->cursor);
        if (s->ruler_n == 2) {
            snprintf(s->status, sizeof s->status, "ruler %.6g %s", vw_ruler_length(s),
                     s->geom.unit[0] ? s->geom.unit : "units");
            if (s->log) fprintf(s->log, "view: ruler %.9g %s\n", vw_ruler_length(s), s->geom.unit);
        }
        break;
    default: break;
    }
    if (k == VW_KEY_F12) {
        char path[64];
        snprintf(path, sizeof path, "bvox-view-%03d.png", s->shot_seq++);
        report(s, vw_screenshot(s, path), "screenshot");
    }
    if (s->light.elevation > 90) s->light.elevation = 90;
    if (s->light.elevation < -90) s->light.elevation = -90;
    s->light.azimuth = fmod(s->light.azimuth + 360.0, 360.0);
}

enum { DRAG_NONE, DRAG_ROTATE, DRAG_PAN, DRAG_LIGHT, DRAG_BRUSH, DRAG_CURSOR, DRAG_SELECT };

static int pane_at(const vw_state *s, int x, int y, vw_rect *r, vw_pane_kind *kind)
{
    vw_rect rects[4];
    vw_pane_kind kinds[4];
    int n = vw_panes(s, rects, kinds);
    for (int i = 0; i < n; i++)
        if (x >= rects[i].x && y >= rects[i].y && x < rects[i].x + rects[i].w &&
            y < rects[i].y + rects[i].h) {
            *r = rects[i];
            *kind = kinds[i];
            return 1;
        }
    return 0;
}

/* A file dropped on the window: read it (as `bvox view FILE` would, 1 where
 * nonzero) and show it instead of the model. A failure keeps the model and
 * says why. */
static void open_dropped(vw_state *s, const char *path)
{
    bvox_volume *vol = NULL;
    bvox_status st = bvox_read(path, NULL, &vol);
    if (!st) st = vw_replace_model(s, vol);
    if (st) {
        snprintf(s->status, sizeof s->status, "cannot open the dropped file: %.110s", bvox_errmsg());
        if (s->log) fprintf(s->log, "view: cannot open %s: %s\n", path, bvox_errmsg());
        return;
    }
    snprintf(s->status, sizeof s->status, "opened %.140s", path);
    if (s->log)
        fprintf(s->log, "view: opened %s (%dx%dx%d, %lld voxels)\n", path, (int)s->dims.nx,
                (int)s->dims.ny, (int)s->dims.nz, (long long)s->count);
}

/* The status line after a click that moved the cursor: the voxel, and the
 * label it belongs to in a label volume. */
static void say_cursor(vw_state *s)
{
    const int32_t *c = s->cursor;
    const char *name = "";
    int64_t lab = vw_label_at(s, c, &name, NULL);
    if (lab)
        snprintf(s->status, sizeof s->status, "cursor %d,%d,%d: label %lld %.80s", (int)c[0], (int)c[1],
                 (int)c[2], (long long)lab, name);
    else snprintf(s->status, sizeof s->status, "cursor %d,%d,%d", (int)c[0], (int)c[1], (int)c[2]);
    if (s->labels && s->log)
        fprintf(s->log, "view: picked %d,%d,%d label %lld%s%s\n", (int)c[0], (int)c[1], (int)c[2],
                (long long)lab, name[0] ? " " : "", name);
}

static void brush_at(vw_state *s, int x, int y)
{
    int32_t hit[3];
    if (!vw_pick(s, x, y, hit)) return;
    memcpy(s->cursor, hit, sizeof hit);
    report(s, vw_brush(s, hit), "brush");
}

void vw_handle(vw_state *s, const vw_event *ev)
{
    assert(vw_state_ok(s));
    vw_rect r;
    vw_pane_kind kind;
    switch (ev->type) {
    case VW_EV_QUIT: s->quit = 1; break;
    case VW_EV_EXPOSE: break; /* the caller draws again */
    case VW_EV_RESIZE: report(s, vw_resize(s, ev->x, ev->y), "resize"); break;
    case VW_EV_DROP: if (ev->path) open_dropped(s, ev->path); break;
    case VW_EV_KEY: key(s, ev->key, ev->mods); break;
    case VW_EV_WHEEL:
        s->zoom *= pow(1.1, ev->wheel);
        if (s->zoom < 0.05) s->zoom = 0.05;
        if (s->zoom > 200) s->zoom = 200;
        s->need_cast = 1;
        break;
    case VW_EV_DOWN:
        if (s->help) { s->help = 0; break; }
        s->drag_button = ev->button;
        s->last_x = s->press_x = ev->x;
        s->last_y = s->press_y = ev->y;
        s->moved = 0;
        s->drag_mode = DRAG_NONE;
        if (!pane_at(s, ev->x, ev->y, &r, &kind)) break;
        if (kind == VW_PANE_3D) {
            if (ev->button == VW_BUTTON_RIGHT) s->drag_mode = DRAG_PAN;
            else if (ev->button == VW_BUTTON_MIDDLE ||
                     (ev->button == VW_BUTTON_LEFT && (ev->mods & VW_MOD_SHIFT)))
                s->drag_mode = DRAG_LIGHT;
            else if (s->brush) {
                s->drag_mode = DRAG_BRUSH;
                bvox_journal_begin(s->journal);
                s->stroke = 1;
                brush_at(s, ev->x, ev->y);
            } else s->drag_mode = DRAG_ROTATE;
        } else if (kind != VW_PANE_MOSAIC && ev->button == VW_BUTTON_LEFT) {
            int32_t at[3];
            if (ev->mods & VW_MOD_CTRL) { /* a selection rectangle, through the whole depth */
                if (!vw_pick(s, ev->x, ev->y, at)) break;
                const int32_t n[3] = {s->dims.nx, s->dims.ny, s->dims.nz};
                int a = kind == VW_PANE_XY ? 2 : kind == VW_PANE_XZ ? 1 : 0;
                memcpy(s->sel[0], at, sizeof at);
                memcpy(s->sel[1], at, sizeof at);
                s->sel[0][a] = 0;
                s->sel[1][a] = n[a] - 1;
                s->sel_n = 2;
                s->drag_axis = a;
                s->drag_mode = DRAG_SELECT;
            } else if (s->brush) {
                s->drag_mode = DRAG_BRUSH;
                bvox_journal_begin(s->journal);
                s->stroke = 1;
                brush_at(s, ev->x, ev->y);
            } else {
                s->drag_mode = DRAG_CURSOR;
                int32_t hit[3];
                if (vw_pick(s, ev->x, ev->y, hit)) memcpy(s->cursor, hit, sizeof hit);
            }
        }
        break;
    case VW_EV_MOTION: {
        int dx = ev->x - s->last_x, dy = ev->y - s->last_y;
        if (abs(ev->x - s->press_x) + abs(ev->y - s->press_y) > 2) s->moved = 1;
        vw_rect rects[4];
        vw_pane_kind kinds[4];
        vw_panes(s, rects, kinds);
        switch (s->drag_mode) {
        case DRAG_ROTATE:
            if (s->coarse_ms > 0 && s->last_full_cast_ms > s->coarse_ms) s->coarse = 1;
            s->view_drag = 1;
            vw_trackball(s->R, s->last_x - rects[0].x, s->last_y - rects[0].y, ev->x - rects[0].x,
                         ev->y - rects[0].y, rects[0].w, rects[0].h);
            s->need_cast = 1;
            break;
        case DRAG_PAN:
            if (s->coarse_ms > 0 && s->last_full_cast_ms > s->coarse_ms) s->coarse = 1;
            s->view_drag = 1;
            s->pan[0] += dx;
            s->pan[1] += dy;
            s->need_cast = 1;
            break;
        case DRAG_LIGHT:
            s->light.azimuth = fmod(s->light.azimuth - dx * 0.5 + 360.0, 360.0);
            s->light.elevation -= dy * 0.5;
            if (s->light.elevation > 90) s->light.elevation = 90;
            if (s->light.elevation < -90) s->light.elevation = -90;
            s->need_lut = 1;
            break;
        case DRAG_BRUSH: brush_at(s, ev->x, ev->y); break;
        case DRAG_SELECT: {
            int32_t at[3];
            if (vw_pick(s, ev->x, ev->y, at))
                for (int a = 0; a < 3; a++)
                    if (a != s->drag_axis) s->sel[1][a] = at[a];
            break;
        }
        case DRAG_CURSOR: {
            int32_t hit[3];
            if (vw_pick(s, ev->x, ev->y, hit)) memcpy(s->cursor, hit, sizeof hit);
            break;
        }
        default: break;
        }
        s->last_x = ev->x;
        s->last_y = ev->y;
        break;
    }
    case VW_EV_UP:
        if (s->drag_mode == DRAG_ROTATE && !s->moved) { /* a click: the cursor */
            int32_t hit[3];
            if (vw_pick(s, ev->x, ev->y, hit)) {
                memcpy(s->cursor, hit, sizeof hit);
                say_cursor(s);
            }
        }
        if (s->drag_mode == DRAG_CURSOR) say_cursor(s);
        if (s->stroke) {
            bvox_journal_end(s->journal);
            s->stroke = 0;
        }
        if (s->coarse) { /* full quality on release */
            s->coarse = 0;
            s->need_cast = 1;
        }
        s->view_drag = 0;
        if (s->fast_codes) s->need_code = 1; /* the smooth codes again */
        s->drag_mode = DRAG_NONE;
        s->drag_button = 0;
        break;
    }
    clamp_cursor(s);
    assert(vw_state_ok(s));
}
