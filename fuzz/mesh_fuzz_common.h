/*
 * mesh_fuzz_common.h — what the mesh reader fuzz targets (fuzz_obj.c,
 * fuzz_off.c, fuzz_ply.c, fuzz_stl.c) do with one input: read it as a mesh
 * of the given format under a small memory budget (so that absurd counts
 * are refused quickly); a successful read must give indices in range and
 * finite coordinates, and is then measured and voxelized at a tiny
 * resolution (the voxelizer must cope with whatever the reader accepts); a
 * failed read leaves *out NULL; every budgeted byte is released afterwards.
 * Header-only: each target is one .c file.
 */
#ifndef BVOX_MESH_FUZZ_COMMON_H
#define BVOX_MESH_FUZZ_COMMON_H

#include "bvox.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

static int mesh_fuzz_one(const uint8_t *data, size_t size, const char *name, const char *format)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_mesh *m = NULL;
    if (bvox_mesh_read_memory(data, size, name, format, &m) == BVOX_OK) {
        for (int64_t i = 0; i < 3 * m->ntriangles; i++)
            if (m->triangles[i] < 0 || m->triangles[i] >= m->nvertices) abort();
        for (int64_t i = 0; i < 3 * m->nvertices; i++)
            if (!isfinite(m->vertices[i])) abort();
        bvox_mesh_info info;
        if (bvox_mesh_measure(m, &info) != BVOX_OK) abort();
        bvox_voxelize_opts o = {0};
        o.res = 12;
        bvox_volume *v = NULL;
        if (bvox_mesh_voxelize(m, &o, &v, NULL) == BVOX_OK) {
            if (bvox_volume_check(v) != BVOX_OK) abort();
            bvox_volume_destroy(v);
        } else if (v != NULL) {
            abort();
        }
        bvox_mesh_destroy(m);
    } else if (m != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}

#endif
