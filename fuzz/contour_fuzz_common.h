/*
 * contour_fuzz_common.h — what the contour fuzz targets do with a stack that
 * read successfully: check the model's invariants (counts, at least 3 finite
 * points per contour, parents in range), run the geometry (crossing check,
 * nesting-independent area, simplification of a copy) and, under a small
 * memory budget, bvox_stack_to_volume, whose result must pass
 * bvox_volume_check. Header-only: each target is one .c file.
 */
#ifndef BVOX_CONTOUR_FUZZ_COMMON_H
#define BVOX_CONTOUR_FUZZ_COMMON_H

#include "bvox.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void exercise_stack(const bvox_contour_stack *s)
{
    if (!(s->pixel > 0) || !(s->spacing > 0) || s->nsections < 0) abort();
    for (int32_t i = 0; i < s->nsections; i++) {
        const bvox_section *sec = &s->sections[i];
        if (!isfinite(sec->z) || sec->ncontours < 0 || sec->nmarkers < 0) abort();
        for (int32_t c = 0; c < sec->ncontours; c++) {
            const bvox_contour *ct = &sec->contours[c];
            if (ct->npoints < 3 || ct->parent < -1 || ct->parent >= sec->ncontours) abort();
            for (int32_t k = 0; k < ct->npoints; k++)
                if (!isfinite(ct->points[k].x) || !isfinite(ct->points[k].y)) abort();
            if (ct->npoints <= 4096) {
                bvox_point2 *copy = malloc((size_t)ct->npoints * sizeof *copy);
                if (!copy) abort();
                memcpy(copy, ct->points, (size_t)ct->npoints * sizeof *copy);
                bvox_contour cc = {copy, ct->npoints, 0, -1};
                if (bvox_contour_simplify(&cc, 0.5) != BVOX_OK || cc.npoints < 3) abort();
                free(copy);
            }
        }
        (void)bvox_section_check_simple(sec, i);
    }
    bvox_set_memory_budget((size_t)16 << 20);
    bvox_volume *v = NULL;
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.z_spacing = s->spacing; /* not isotropic: keep the fuzzer fast */
    if (bvox_stack_to_volume(s, &o, &v) == BVOX_OK) {
        if (bvox_volume_check(v) != BVOX_OK) abort();
        bvox_volume_destroy(v);
    } else if (v != NULL) {
        abort();
    }
}

#endif
