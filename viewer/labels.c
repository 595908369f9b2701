/*
 * labels.c — a label volume (an atlas, a segmentation) in the viewer: the
 * model is the union of its objects, and the 3D pane colours each object
 * pixel by the label of the voxel it shows, in the lookup table's colour
 * (a fixed palette for labels the table lacks or gives no colour), with the
 * shading's brightness kept. Picking names the label (input.c).
 *
 * The label of a voxel comes from a dense map of object indices (16 bits a
 * voxel, budgeted: labels are at most BVOX_LABELS_MAX_DEFAULT), built once
 * from the objects' crops; the voxel a pixel shows is found from its depth
 * (the entry point in the middle of its depth step), stepping on along the
 * ray by half a voxel when that lands beside the object (a grazing ray).
 */
#include "view.h"
#include "core/alloc.h" /* the allocation seam: the one header of src/ the viewer uses */

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct vw_labels {
    uint16_t *map;      /* per voxel (x fastest): 0 background, else 1 + object */
    size_t map_bytes;
    int64_t n;
    int64_t *label;     /* per object */
    uint16_t *pix;      /* per pixel of the 3D pane: the map's value it shows */
    int pw, ph;         /* its size; 0: not made for the current cast */
    uint8_t (*rgb)[3];
    char (*name)[96];
};

void vw_labels_free(vw_labels *l)
{
    if (!l) return;
    bvox__free(l->map, l->map_bytes);
    free(l->pix);
    free(l->label);
    free(l->rgb);
    free(l->name);
    free(l);
}

bvox_status vw_labels_model(const bvox_labelset *set, bvox_volume **out)
{
    *out = NULL;
    bvox_volume *v = NULL;
    bvox_status st = bvox_volume_create(set->dims, &v);
    if (!st) st = bvox_volume_set_geometry(v, &set->geometry);
    for (int64_t i = 0; i < set->n && !st; i++) {
        const bvox_label_object *o = &set->objects[i];
        const int32_t off[3] = {o->crop.x0, o->crop.y0, o->crop.z0};
        st = bvox_csg_apply(v, BVOX_CSG_UNION, o->volume, off);
    }
    if (st) {
        bvox_volume_destroy(v);
        return st;
    }
    *out = v;
    return BVOX_OK;
}

/* A colour for a label without one: hues a golden angle apart, not too
 * pale nor too dark, so neighbouring labels differ. */
static void palette(int64_t label, uint8_t rgb[3])
{
    double h = fmod((double)label * 0.618033988749895, 1.0) * 6, s = 0.6, v = 0.95;
    int i = (int)h;
    double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double r, g, b;
    switch (i % 6) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
    }
    rgb[0] = (uint8_t)lround(r * 255), rgb[1] = (uint8_t)lround(g * 255), rgb[2] = (uint8_t)lround(b * 255);
}

bvox_status vw_set_labels(vw_state *s, const bvox_labelset *set, const bvox_label_table *table)
{
    if (set->n > 65535 || set->dims.nx != s->dims.nx || set->dims.ny != s->dims.ny ||
        set->dims.nz != s->dims.nz)
        return BVOX_EINVAL;
    vw_labels *l = bvox__mem_zalloc(1, sizeof *l);
    if (!l) return BVOX_ENOMEM;
    size_t nvox = (size_t)s->dims.nx * (size_t)s->dims.ny * (size_t)s->dims.nz;
    bvox_status st = BVOX_OK;
    l->map = bvox__alloc(nvox * sizeof *l->map, true, "the viewer's label map", &st);
    if (l->map) l->map_bytes = nvox * sizeof *l->map;
    l->n = set->n;
    l->label = bvox__mem_zalloc((size_t)set->n + 1, sizeof *l->label);
    l->rgb = bvox__mem_zalloc((size_t)set->n + 1, sizeof *l->rgb);
    l->name = bvox__mem_zalloc((size_t)set->n + 1, sizeof *l->name);
    if (!l->map || !l->label || !l->rgb || !l->name) {
        vw_labels_free(l);
        return st ? st : BVOX_ENOMEM;
    }
    const size_t nx = (size_t)s->dims.nx, nxy = nx * (size_t)s->dims.ny;
    for (int64_t i = 0; i < set->n; i++) {
        const bvox_label_object *o = &set->objects[i];
        l->label[i] = o->label;
        const bvox_label_entry *e = table ? bvox_label_table_find(table, o->label) : NULL;
        if (e && e->has_color) memcpy(l->rgb[i], e->rgba, 3);
        else palette(o->label, l->rgb[i]);
        if (e) snprintf(l->name[i], sizeof l->name[i], "%s", e->name);
        const bvox_box c = o->crop;
        for (int32_t z = c.z0; z < c.z1; z++)
            for (int32_t y = c.y0; y < c.y1; y++)
                for (int32_t x = c.x0; x < c.x1; x++)
                    if (bvox_volume_get(o->volume, x - c.x0, y - c.y0, z - c.z0))
                        l->map[(size_t)z * nxy + (size_t)y * nx + (size_t)x] = (uint16_t)(i + 1);
    }
    vw_labels_free(s->labels);
    s->labels = l;
    s->need_lut = 1;
    return BVOX_OK;
}

static int map_at(const vw_state *s, const int32_t v[3])
{
    if (v[0] < 0 || v[1] < 0 || v[2] < 0 || v[0] >= s->dims.nx || v[1] >= s->dims.ny ||
        v[2] >= s->dims.nz)
        return 0;
    return s->labels->map[((size_t)v[2] * (size_t)s->dims.ny + (size_t)v[1]) * (size_t)s->dims.nx +
                          (size_t)v[0]];
}

int64_t vw_label_at(const vw_state *s, const int32_t v[3], const char **name, uint8_t rgb[3])
{
    int k = s->labels ? map_at(s, v) : 0;
    if (name) *name = k ? s->labels->name[k - 1] : "";
    if (rgb && k) memcpy(rgb, s->labels->rgb[k - 1], 3);
    return k ? s->labels->label[k - 1] : 0;
}

void vw_labels_pixels(vw_state *s)
{
    const vw_3d *v = &s->view3d;
    vw_labels *l = s->labels;
    if (!l || !v->valid) return;
    const int w = v->w, h = v->h;
    if (l->pw != w || l->ph != h) {
        free(l->pix);
        l->pw = l->ph = 0;
        l->pix = bvox__mem_alloc((size_t)w * (size_t)h * sizeof *l->pix);
        if (!l->pix) return; /* shown without colours */
        l->pw = w, l->ph = h;
    }
    /* everything in voxel index units, so a pixel costs three multiply-adds
     * and a truncation per try: q = o + x ex + y ey + (depth + 0.5) ez,
     * plus 0.5 so that truncating a positive q rounds it */
    double o[3], ex[3], ey[3], ez[3], half[3];
    const double hv = 0.5 * vw_min_spacing(s);
    for (int a = 0; a < 3; a++) {
        o[a] = v->origin[a] / s->sp[a] + 0.5;
        ex[a] = v->eye[a] * v->pixel / s->sp[a];
        ey[a] = v->eye[3 + a] * v->pixel / s->sp[a];
        ez[a] = v->eye[6 + a] * v->step / s->sp[a];
        half[a] = v->eye[6 + a] * hv / s->sp[a];
    }
    const double n[3] = {s->dims.nx, s->dims.ny, s->dims.nz};
    const size_t nx = (size_t)s->dims.nx, nxy = nx * (size_t)s->dims.ny;
    const uint16_t *map = l->map;
    for (int y = 0; y < h; y++) {
        const int32_t *depth = v->depth + (size_t)y * (size_t)v->w;
        uint16_t *out = l->pix + (size_t)y * (size_t)w;
        for (int x = 0; x < w; x++) {
            int k = 0;
            if (depth[x] >= 0) {
                double q[3], t = depth[x] + 0.5;
                for (int a = 0; a < 3; a++) q[a] = o[a] + x * ex[a] + y * ey[a] + t * ez[a];
                for (int tries = 0; tries < 4 && !k; tries++) {
                    if (q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < n[0] && q[1] < n[1] && q[2] < n[2])
                        k = map[(size_t)q[2] * nxy + (size_t)q[1] * nx + (size_t)q[0]];
                    for (int a = 0; a < 3; a++) q[a] += half[a];
                }
            }
            out[x] = (uint16_t)k;
        }
    }
}

void vw_labels_tint(vw_state *s, vw_rect r)
{
    const vw_3d *v = &s->view3d;
    const vw_labels *l = s->labels;
    if (!l || !v->valid || l->pw != v->w || l->ph != v->h) return;
    const int w = v->w < r.w ? v->w : r.w, h = v->h < r.h ? v->h : r.h;
    for (int y = 0; y < h; y++) {
        const uint16_t *lab = l->pix + (size_t)y * (size_t)l->pw;
        uint8_t *px = s->rgb + ((size_t)(r.y + y) * (size_t)s->width + (size_t)r.x) * 3;
        for (int x = 0; x < w; x++, px += 3) {
            int k = lab[x];
            if (!k) continue;
            const uint8_t *c = s->labels->rgb[k - 1];
            /* the shading's brightness (gray, or the cut face's tint) times the colour */
            for (int a = 0; a < 3; a++) px[a] = (uint8_t)((px[a] * (unsigned)c[a] + 127) / 255);
        }
    }
}
