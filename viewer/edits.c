/*
 * edits.c — the viewer's edits, each recorded in the undo journal first
 * (bvox_journal_record saves the words of the box the edit may change,
 * bvox_journal_sync turns them into XOR deltas): memory grows with the
 * edited boxes, never with the volume. After an edit the displayed volume's
 * surface is brought up to date in the changed box only
 * (bvox_surface_update; rebuilt when a cut is shown), the count and the
 * mosaic refreshed.
 */
#include "view.h"

#include <math.h>
#include <string.h>

void vw_model_changed(vw_state *s, const bvox_box *changed)
{
    s->count = bvox_volume_count(s->model);
    s->sel_count_ok = 0; /* the selection's volume is counted again */
    s->need_surface = 1;
    s->need_mosaic = 1;
    if (!changed || s->dirty_state == 2) {
        s->dirty_state = 2;
        return;
    }
    bvox_box c = *changed, *d = &s->dirty;
    if (c.x0 >= c.x1 || c.y0 >= c.y1 || c.z0 >= c.z1) return; /* nothing */
    if (s->dirty_state == 0) {
        *d = c;
    } else {
        d->x0 = c.x0 < d->x0 ? c.x0 : d->x0, d->x1 = c.x1 > d->x1 ? c.x1 : d->x1;
        d->y0 = c.y0 < d->y0 ? c.y0 : d->y0, d->y1 = c.y1 > d->y1 ? c.y1 : d->y1;
        d->z0 = c.z0 < d->z0 ? c.z0 : d->z0, d->z1 = c.z1 > d->z1 ? c.z1 : d->z1;
    }
    s->dirty_state = 1;
}

/* The index box around a physical centre c with half extents ext. */
static bvox_box box_around(const vw_state *s, const double c[3], const double ext[3])
{
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        double i = (c[a] - s->geom.origin[a]) / s->sp[a], e = ext[a] / s->sp[a];
        double l = floor(i - e) - 1, h = ceil(i + e) + 2;
        lo[a] = l < -1 ? -1 : l > 70000 ? 70000 : (int32_t)l;
        hi[a] = h < -1 ? -1 : h > 70000 ? 70000 : (int32_t)h;
    }
    return (bvox_box){lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
}

static bvox_status journalled_shape(vw_state *s, const bvox_shape *sh, bvox_csg_op op,
                                    const double ext[3])
{
    bvox_box b = box_around(s, sh->center, ext);
    int own = !s->stroke;
    if (own) bvox_journal_begin(s->journal);
    bvox_status st = bvox_journal_record(s->journal, s->model, b);
    if (!st) st = bvox_shape_draw(s->model, sh, op);
    if (!st) st = bvox_journal_sync(s->journal, s->model);
    if (own) bvox_journal_end(s->journal);
    vw_model_changed(s, &b);
    return st;
}

bvox_status vw_brush(vw_state *s, const int32_t at[3])
{
    bvox_shape sh;
    memset(&sh, 0, sizeof sh);
    sh.kind = BVOX_SHAPE_SPHERE;
    sh.radius = s->brush_radius * vw_min_spacing(s);
    for (int a = 0; a < 3; a++) sh.center[a] = s->geom.origin[a] + at[a] * s->sp[a];
    double ext[3] = {sh.radius, sh.radius, sh.radius};
    bvox_status st = journalled_shape(s, &sh, s->brush_add ? BVOX_CSG_UNION : BVOX_CSG_DIFFERENCE, ext);
    if (!st && s->log)
        fprintf(s->log, "view: brush %s r=%d at %d,%d,%d\n", s->brush_add ? "add" : "remove",
                s->brush_radius, (int)at[0], (int)at[1], (int)at[2]);
    return st;
}

bvox_status vw_apply_primitive(vw_state *s, bvox_csg_op op)
{
    static const char *const names[] = {"", "sphere", "box", "cylinder"};
    bvox_shape sh;
    vw_primitive_shape(s, &sh);
    double e = sh.kind == BVOX_SHAPE_CYLINDER ? sh.radius + sh.height / 2
               : sh.kind == BVOX_SHAPE_BOX    ? sh.semi_axes[0] * sqrt(3.0)
                                              : sh.radius;
    double ext[3] = {e, e, e};
    bvox_status st = journalled_shape(s, &sh, op, ext);
    if (!st && s->log)
        fprintf(s->log, "view: %s %s %d at %d,%d,%d\n", op == BVOX_CSG_UNION ? "union" : "difference",
                names[s->prim], s->prim_size, (int)s->cursor[0], (int)s->cursor[1], (int)s->cursor[2]);
    snprintf(s->status, sizeof s->status, "%s %s", op == BVOX_CSG_UNION ? "union" : "difference",
             names[s->prim]);
    return st;
}

bvox_status vw_edit_box(vw_state *s, int keep)
{
    bvox_box b;
    int32_t *lo = &b.x0, *hi = &b.x1;
    for (int a = 0; a < 3; a++) {
        lo[a] = s->sel[0][a] < s->sel[1][a] ? s->sel[0][a] : s->sel[1][a];
        hi[a] = (s->sel[0][a] > s->sel[1][a] ? s->sel[0][a] : s->sel[1][a]) + 1;
    }
    bvox_box rec = b;
    if (keep && !bvox_volume_bbox(s->model, &rec)) return BVOX_OK; /* empty: nothing to clear */
    bvox_journal_begin(s->journal);
    bvox_status st = bvox_journal_record(s->journal, s->model, rec);
    if (!st) st = keep ? bvox_edit_keep_box(s->model, b, NULL) : bvox_edit_fill_box(s->model, b, 0, NULL);
    if (!st) st = bvox_journal_sync(s->journal, s->model);
    bvox_journal_end(s->journal);
    vw_model_changed(s, &rec);
    if (!st && s->log)
        fprintf(s->log, "view: %s box %d:%d,%d:%d,%d:%d\n", keep ? "keep" : "remove", (int)b.x0,
                (int)b.x1 - 1, (int)b.y0, (int)b.y1 - 1, (int)b.z0, (int)b.z1 - 1);
    snprintf(s->status, sizeof s->status, "%s box", keep ? "kept" : "removed");
    return st;
}

bvox_status vw_apply_cut(vw_state *s)
{
    double pl[4];
    vw_cut_plane_world(s, pl);
    bvox_box rec;
    bvox_status st = BVOX_OK;
    if (bvox_volume_bbox(s->model, &rec)) {
        bvox_journal_begin(s->journal);
        st = bvox_journal_record(s->journal, s->model, rec);
        if (!st) st = bvox_cut_plane(s->model, pl[0], pl[1], pl[2], pl[3], s->keep_above, NULL);
        if (!st) st = bvox_journal_sync(s->journal, s->model);
        bvox_journal_end(s->journal);
    }
    s->cut = 0;
    vw_model_changed(s, NULL);
    if (!st && s->log)
        fprintf(s->log, "view: cut %.17g,%.17g,%.17g,%.17g keep %s\n", pl[0], pl[1], pl[2], pl[3],
                s->keep_above ? "above" : "below");
    snprintf(s->status, sizeof s->status, "cut applied");
    return st;
}

bvox_status vw_undo(vw_state *s, int redo)
{
    if (s->stroke) {
        bvox_journal_end(s->journal);
        s->stroke = 0;
    }
    int done;
    bvox_box changed;
    bvox_status st = redo ? bvox_journal_redo(s->journal, s->model, &done, &changed)
                          : bvox_journal_undo(s->journal, s->model, &done, &changed);
    if (st) return st;
    if (done) vw_model_changed(s, &changed);
    snprintf(s->status, sizeof s->status, "%s%s", redo ? "redo" : "undo", done ? "" : ": nothing to do");
    if (s->log && done) fprintf(s->log, "view: %s\n", redo ? "redo" : "undo");
    return BVOX_OK;
}

bvox_status vw_save(vw_state *s, const char *path)
{
    bvox_status st = bvox_write(path, s->model, NULL);
    if (st) return st;
    snprintf(s->status, sizeof s->status, "saved %.120s", path);
    if (s->log) fprintf(s->log, "view: saved %s (%lld voxels)\n", path, (long long)s->count);
    return BVOX_OK;
}

bvox_status vw_screenshot(vw_state *s, const char *path)
{
    bvox_image *img;
    bvox_status st = vw_canvas_image(s, &img);
    if (st) return st;
    if (s->readback && s->readback(s->readback_ctx, img->pixels, s->width, s->height) != 0) {
        /* the window could not be read: the canvas it was given is the same picture */
        memcpy(img->pixels, s->rgb, (size_t)s->width * (size_t)s->height * 3);
    }
    st = bvox_image_write_png(img, path);
    bvox_image_destroy(img);
    if (!st && s->log) fprintf(s->log, "view: screenshot %s\n", path);
    return st;
}
