/*
 * measure.c — the viewer's measurements in physical units: the ruler between
 * two marked voxels, the volume of the object inside the selection box, and
 * the round length of the 3D pane's scale bar. On view_state.c only.
 */
#include "view.h"

#include <math.h>
#include <string.h>

double vw_ruler_length(const vw_state *s)
{
    if (s->ruler_n < 2) return -1;
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double d = (s->ruler[1][a] - s->ruler[0][a]) * s->sp[a];
        d2 += d * d;
    }
    return sqrt(d2);
}

int vw_selection_box(const vw_state *s, bvox_box *b)
{
    if (!s->sel_n) return 0;
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = s->sel[0][a] < s->sel[1][a] ? s->sel[0][a] : s->sel[1][a];
        hi[a] = (s->sel[0][a] > s->sel[1][a] ? s->sel[0][a] : s->sel[1][a]) + 1;
    }
    *b = (bvox_box){lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
    return 1;
}

bvox_status vw_selection_volume(vw_state *s, int64_t *count, double *volume)
{
    bvox_box b;
    *count = 0;
    *volume = 0;
    if (!vw_selection_box(s, &b)) return BVOX_OK;
    if (!s->sel_count_ok || memcmp(s->sel_counted, s->sel, sizeof s->sel)) {
        /* a crop is a word copy of the box's columns: cheap next to a frame,
         * and done once per new box or edit */
        bvox_volume *c = NULL;
        bvox_status st = bvox_volume_crop(s->model, b, &c);
        if (st) return st;
        s->sel_count = bvox_volume_count(c);
        bvox_volume_destroy(c);
        memcpy(s->sel_counted, s->sel, sizeof s->sel);
        s->sel_count_ok = 1;
    }
    *count = s->sel_count;
    *volume = (double)s->sel_count * s->sp[0] * s->sp[1] * s->sp[2];
    return BVOX_OK;
}

double vw_scale_bar_length(double units_per_px, int max_px)
{
    if (!(units_per_px > 0) || max_px < 1) return 0;
    double most = units_per_px * max_px;
    double p = pow(10, floor(log10(most)));
    static const double steps[] = {5, 2, 1};
    for (int i = 0; i < 3; i++)
        if (steps[i] * p <= most * (1 + 1e-12)) return steps[i] * p;
    return p; /* not reached: p <= most */
}
