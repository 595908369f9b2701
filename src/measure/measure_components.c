/*
 * measure_components.c — bvox_measure for every connected component.
 *
 * Each component is cut out to its bounding box and measured alone, so the
 * cost is the sum of the components' box sizes, not the number of components
 * times the volume. Cutting out: the crop of the box holds the component and
 * possibly pieces of others. If its count is the component's, it is alone.
 * Otherwise the crop is labelled again: the component is still a component
 * there (cropping removes no voxel of it and joins nothing), one whose box is
 * the whole crop and whose size is known; when exactly one local component
 * fits that description it is the one. Only when two do (mirror-image
 * components sharing a box) does it fall back to bvox_components_keep on the
 * whole volume.
 */
#include "measure/measure.h"

#include <stdlib.h>

static bvox_status keep_rank(const bvox_components *comps, int64_t rank, bvox_volume **out)
{
    /* keep(rank + 1) minus keep(rank): exactly the component of that rank */
    bvox_volume *upto = NULL, *larger = NULL;
    bvox_status st = bvox_components_keep(comps, rank + 1, &upto);
    if (!st && rank > 0) st = bvox_components_keep(comps, rank, &larger);
    if (!st && larger) st = bvox_csg_apply(upto, BVOX_CSG_DIFFERENCE, larger, NULL);
    bvox_volume_destroy(larger);
    if (st) {
        bvox_volume_destroy(upto);
        return st;
    }
    *out = upto;
    return BVOX_OK;
}

/* The component alone, in a volume cropped to its box. */
static bvox_status isolate(const bvox_volume *vol, const bvox_components *comps, int64_t i,
                           int conn, bvox_volume **out)
{
    const bvox_component *c = bvox_components_get(comps, i);
    bvox_volume *crop = NULL;
    bvox_status st = bvox_volume_crop(vol, c->bbox, &crop);
    if (st) return st;
    if (bvox_volume_count(crop) == c->voxels) {
        *out = crop;
        return BVOX_OK;
    }
    bvox_components *local = NULL;
    st = bvox_components_find(crop, conn, &local);
    if (st) {
        bvox_volume_destroy(crop);
        return st;
    }
    bvox_dims d = bvox_volume_dims(crop);
    bvox_volume_destroy(crop);
    int64_t found = -1, matches = 0;
    for (int64_t j = 0; j < bvox_components_count(local); j++) {
        const bvox_component *lc = bvox_components_get(local, j);
        if (lc->voxels < c->voxels) break; /* sorted largest first */
        bvox_box b = lc->bbox;
        if (lc->voxels == c->voxels && b.x0 == 0 && b.y0 == 0 && b.z0 == 0 && b.x1 == d.nx &&
            b.y1 == d.ny && b.z1 == d.nz)
            found = j, matches++;
    }
    if (matches == 1) {
        st = keep_rank(local, found, out);
        bvox_components_destroy(local);
        return st;
    }
    bvox_components_destroy(local);
    bvox_volume *whole = NULL;
    st = keep_rank(comps, i, &whole);
    if (st) return st;
    st = bvox_volume_crop(whole, c->bbox, out);
    bvox_volume_destroy(whole);
    return st;
}

bvox_status bvox_measure_components(const bvox_volume *vol, int conn,
                                    bvox_measures **per_component, int64_t *n)
{
    *per_component = NULL;
    *n = 0;
    bvox__clear_error();
    bvox_components *comps = NULL;
    bvox_status st = bvox_components_find(vol, conn, &comps);
    if (st) return st;
    int64_t k = bvox_components_count(comps);
    if (k == 0) {
        bvox_components_destroy(comps);
        return BVOX_OK;
    }
    bvox_measures *all = bvox__mem_zalloc((size_t)k, sizeof *all);
    if (!all) {
        bvox_components_destroy(comps);
        return bvox__fail(BVOX_ENOMEM, "out of memory for the measures of %lld components",
                          (long long)k);
    }
    double weight[BVOX__NDIR];
    bvox__crofton_weights(vol->geom.spacing, weight);
    for (int64_t i = 0; i < k && !st; i++) {
        bvox_volume *one = NULL;
        st = isolate(vol, comps, i, conn, &one);
        if (st) break;
        bvox_box b = bvox_components_get(comps, i)->bbox;
        int32_t shift[3] = {b.x0, b.y0, b.z0};
        st = bvox__measure_with(one, weight, shift, &all[i]);
        bvox_volume_destroy(one);
    }
    bvox_components_destroy(comps);
    if (st) {
        free(all);
        return st;
    }
    *per_component = all;
    *n = k;
    return BVOX_OK;
}
