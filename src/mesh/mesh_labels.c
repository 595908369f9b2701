/*
 * mesh_labels.c — one surface mesh per label of a label set, such that two
 * labels that touch share their boundary exactly: no gap, no overlap.
 *
 * Cuberille is the method: a face between a voxel of label A and one of
 * label B is a face of both meshes (opposite orientations), which marching
 * cubes on each binary label cannot give at triple junctions. Bit-exact
 * sharing also needs the same arithmetic for the same corner: each crop is
 * meshed in index space (origin 0, unit spacing, no direction: corners are
 * exact half-integers), moved by its crop offset (exact) and only then
 * mapped to the world through the label volume's geometry, the same
 * expression for every label. Smoothing would move shared vertices
 * differently in each mesh, so there is none here.
 *
 * The folder output goes through the folder sink (a temporary folder,
 * renamed into place when every mesh is written).
 */
#include "io/io.h"
#include "mesh_private.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bvox_status bvox_labelset_mesh(const bvox_labelset *set, int64_t index, bvox_mesh **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_labelset_mesh: out is NULL");
    *out = NULL;
    if (!set || index < 0 || index >= set->n)
        return bvox__fail(BVOX_EINVAL, "bvox_labelset_mesh: no object %lld", (long long)index);
    const bvox_label_object *o = &set->objects[index];
    struct bvox_volume view = *o->volume; /* shares the words: read only */
    view.geom = bvox_geometry_default();
    bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
    mo.method = BVOX_MESH_CUBERILLE;
    bvox_mesh *m;
    bvox_status st = bvox_mesh_from_volume(&view, &mo, &m);
    if (st) return st;
    const double off[3] = {o->crop.x0, o->crop.y0, o->crop.z0};
    for (int64_t v = 0; v < m->nvertices; v++) {
        double *p = m->vertices + 3 * v;
        bvox__grid_world(&set->geometry, p[0] + off[0], p[1] + off[1], p[2] + off[2], p);
    }
    if (bvox__geometry_mirrored(&set->geometry)) /* keep the normals outward */
        for (int64_t t = 0; t < m->ntriangles; t++) {
            int32_t *tri = m->triangles + 3 * t, s = tri[1];
            tri[1] = tri[2];
            tri[2] = s;
        }
    *out = m;
    return BVOX_OK;
}

void bvox_label_file_name(int64_t label, const char *name, const char *ext, char *buf,
                          size_t size)
{
    char clean[65];
    size_t n = 0;
    for (const char *s = name ? name : ""; *s && n < sizeof clean - 1; s++) {
        unsigned char c = (unsigned char)*s;
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '-' || c == '_' || c == '.';
        char r = ok ? (char)c : '_';
        if (r == '_' && n > 0 && clean[n - 1] == '_') continue; /* one '_' per run */
        if (n == 0 && r == '.') r = '_';                        /* never a hidden file */
        clean[n++] = r;
    }
    while (n > 0 && clean[n - 1] == '_') n--;
    clean[n] = '\0';
    if (n) snprintf(buf, size, "%lld_%s.%s", (long long)label, clean, ext);
    else snprintf(buf, size, "%lld.%s", (long long)label, ext);
}

bvox_status bvox_labelset_write_meshes(const bvox_labelset *set, const int64_t *indices,
                                       int64_t n, const char *const *names, const char *dir,
                                       const char *format, int ascii)
{
    bvox__clear_error();
    if (!set || !dir || !format || (n > 0 && !indices))
        return bvox__fail(BVOX_EINVAL, "bvox_labelset_write_meshes: NULL argument");
    if (strcmp(format, "stl") && strcmp(format, "ply") && strcmp(format, "obj") &&
        strcmp(format, "off"))
        return bvox__fail(BVOX_EINVAL, "mesh format must be stl, ply, obj or off, not '%s'",
                          format);
    for (int64_t i = 0; i < n; i++)
        if (indices[i] < 0 || indices[i] >= set->n)
            return bvox__fail(BVOX_EINVAL, "bvox_labelset_write_meshes: no object %lld",
                              (long long)indices[i]);
    bvox__dir_sink ds;
    bvox_status st = bvox__dir_sink_open(dir, BVOX__DIR_LABEL_MESHES, false, &ds);
    if (st) return st;
    const char *tmp = ds.tmp;
    size_t cap = strlen(tmp) + 128;
    char *path = bvox__mem_alloc(cap);
    if (!path) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    for (int64_t i = 0; i < n && !st; i++) {
        int64_t k = indices[i];
        char file[96];
        bvox_label_file_name(set->objects[k].label, names ? names[i] : NULL, format, file,
                             sizeof file);
        snprintf(path, cap, "%s/%s", tmp, file);
        bvox_mesh *m;
        st = bvox_labelset_mesh(set, k, &m);
        if (!st) st = bvox_mesh_write(path, m, format, ascii);
        bvox_mesh_destroy(m);
    }
    free(path);
    if (!st) st = bvox__dir_sink_commit(&ds);
    else bvox__dir_sink_abort(&ds);
    return st;
}
