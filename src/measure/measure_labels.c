/*
 * measure_labels.c — bvox_measure of one object of a label set, reported in
 * the label volume's frame. The object's crop is its bounding box grown by
 * one voxel (labels_read.c): every 2x2x2 configuration that touches the
 * object, every face and every background voxel next to it lies inside, and
 * the outside counts as background in both, so counts, areas and topology
 * are those of the whole volume holding only that label. Only positions
 * change: the crop's origin is moved along the volume's axes (world
 * positions kept), while measures place voxel (i, j, k) at origin + (i*sx,
 * j*sy, k*sz) without the direction, so the shift is undone here.
 */
#include "internal.h"

bvox_status bvox_labelset_measure(const bvox_labelset *set, int64_t index, bvox_measures *out)
{
    bvox__clear_error();
    if (!set || !out || index < 0 || index >= set->n)
        return bvox__fail(BVOX_EINVAL, "bvox_labelset_measure: no object %lld",
                          (long long)index);
    const bvox_label_object *o = &set->objects[index];
    bvox_status st = bvox_measure(o->volume, out);
    if (st) return st;
    if (out->count == 0) return BVOX_OK;
    const bvox_geometry *g = &set->geometry, *cg = &o->volume->geom;
    int32_t off[3] = {o->crop.x0, o->crop.y0, o->crop.z0};
    for (int a = 0; a < 3; a++) {
        double delta = g->origin[a] + off[a] * g->spacing[a] - cg->origin[a];
        out->centroid[a] += delta;
        out->extent_min[a] += delta;
        out->extent_max[a] += delta;
    }
    out->bbox.x0 += off[0];
    out->bbox.x1 += off[0];
    out->bbox.y0 += off[1];
    out->bbox.y1 += off[1];
    out->bbox.z0 += off[2];
    out->bbox.z1 += off[2];
    return BVOX_OK;
}
