/*
 * render_objects.c — several objects in one picture (issue 18 item 2, issue
 * 19 item 4): bvox_render_objects (volumes on one grid, one colour each) and
 * bvox_render_labels (a label volume in its table's colours).
 *
 * Composited by depth the cheap exact way: the union of the objects is cast
 * once (one surface, one pre-image), so the first voxel along each ray is
 * the nearest object's by construction; the pixel then takes the colour of
 * the object holding that voxel. Casting each object and keeping the
 * nearest depth would cast n times and, for projections, need every cast to
 * share one fit; the union gives the same picture (the faces where two
 * objects touch are hidden either way) at the cost of one. The shading is
 * the union's: a smooth normal near a contact sees both objects, as the eye
 * does.
 */
#include "scene.h"
#include "common/color.h"

#include <math.h>
#include <string.h>

typedef struct objects_ctx {
    const bvox_volume *const *vols;
    const uint8_t (*colors)[3];
    int n;
} objects_ctx;

static int objects_colour(const void *ctx, int32_t x, int32_t y, int32_t z, uint8_t rgb[3])
{
    const objects_ctx *c = ctx;
    for (int k = 0; k < c->n; k++)
        if (bvox_volume_get(c->vols[k], x, y, z)) {
            memcpy(rgb, c->colors[k], 3);
            return 1;
        }
    return 0;
}

bvox_status bvox_render_objects(const bvox_volume *const *vols, const uint8_t (*colors)[3], int n,
                                const bvox_render_opts *opts, bvox_image **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "render: no output");
    *out = NULL;
    if (!vols || !colors || !opts || n < 1 || n > 256)
        return bvox__fail(BVOX_EINVAL, "render: 1..256 volumes and their colours");
    for (int k = 0; k < n; k++) {
        if (!vols[k]) return bvox__fail(BVOX_EINVAL, "render: volume %d is missing", k + 1);
        BVOX_CHECK_VOLUME(vols[k]);
        const bvox_volume *a = vols[0], *b = vols[k];
        if (b->nx != a->nx || b->ny != a->ny || b->nz != a->nz)
            return bvox__fail(BVOX_EINVAL,
                              "render: volume %d is %d x %d x %d, volume 1 %d x %d x %d: "
                              "several volumes must share one grid",
                              k + 1, (int)b->nx, (int)b->ny, (int)b->nz, (int)a->nx, (int)a->ny,
                              (int)a->nz);
        for (int i = 0; i < 3; i++)
            if (fabs(b->geom.spacing[i] - a->geom.spacing[i]) > 1e-6 * a->geom.spacing[i])
                return bvox__fail(BVOX_EINVAL,
                                  "render: volume %d's voxel size differs from volume 1's: "
                                  "several volumes must share one grid",
                                  k + 1);
    }
    bvox_volume *u = NULL;
    bvox_status st = bvox_volume_copy(vols[0], &u);
    for (int k = 1; k < n && !st; k++) st = bvox_csg_apply(u, BVOX_CSG_UNION, vols[k], NULL);
    objects_ctx c = {vols, colors, n};
    if (!st) st = bvox__render_coloured(u, opts, objects_colour, &c, out, NULL);
    bvox_volume_destroy(u);
    return st;
}

/* ------------------------------------------------------------ label sets */

typedef struct labels_ctx {
    const bvox_labelset *set;
    uint8_t (*rgb)[3];
} labels_ctx;

static int labels_colour(const void *ctx, int32_t x, int32_t y, int32_t z, uint8_t rgb[3])
{
    const labels_ctx *c = ctx;
    for (int64_t k = 0; k < c->set->n; k++) {
        const bvox_label_object *ob = &c->set->objects[k];
        const bvox_box *b = &ob->crop;
        if (x < b->x0 || y < b->y0 || z < b->z0 || x >= b->x1 || y >= b->y1 || z >= b->z1) continue;
        if (bvox_volume_get(ob->volume, x - b->x0, y - b->y0, z - b->z0)) {
            memcpy(rgb, c->rgb[k], 3);
            return 1;
        }
    }
    return 0;
}

bvox_status bvox_render_labels(const bvox_labelset *set, const bvox_label_table *table,
                               const bvox_render_opts *opts, bvox_image **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "render: no output");
    *out = NULL;
    if (!set || !opts) return bvox__fail(BVOX_EINVAL, "render: missing label set or options");
    if (set->n < 1) return bvox__fail(BVOX_EINVAL, "render: the label volume has no labels");
    bvox_status st = BVOX_OK;
    const size_t bytes = (size_t)set->n * 3;
    uint8_t (*rgb)[3] = bvox__alloc(bytes, false, "label colours", &st);
    if (!rgb) return st;
    for (int64_t k = 0; k < set->n; k++) {
        const bvox_label_entry *e = table ? bvox_label_table_find(table, set->objects[k].label) : NULL;
        if (e && e->has_color) memcpy(rgb[k], e->rgba, 3);
        else bvox__label_color(set->objects[k].label, rgb[k]);
    }
    bvox_volume *u = NULL;
    st = bvox_volume_create(set->dims, &u);
    if (!st) st = bvox_volume_set_geometry(u, &set->geometry);
    for (int64_t k = 0; k < set->n && !st; k++) {
        const bvox_box *b = &set->objects[k].crop;
        const int32_t off[3] = {b->x0, b->y0, b->z0};
        st = bvox_csg_apply(u, BVOX_CSG_UNION, set->objects[k].volume, off);
    }
    labels_ctx c = {set, rgb};
    if (!st) st = bvox__render_coloured(u, opts, labels_colour, &c, out, NULL);
    bvox_volume_destroy(u);
    bvox__free(rgb, bytes);
    return st;
}
