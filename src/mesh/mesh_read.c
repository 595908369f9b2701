/*
 * mesh_read.c — mesh file dispatch (by format name, extension or content)
 * to the readers read_stl.c, read_obj.c, read_ply.c and read_off.c.
 */
#include "io/io.h"
#include "mesh_private.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *sniff(const uint8_t *d, size_t n)
{
    size_t i = 0;
    while (i < n && (d[i] == ' ' || d[i] == '\t' || d[i] == '\r' || d[i] == '\n')) i++;
    if (n - i >= 3 && !memcmp(d + i, "ply", 3)) return "ply";
    if (n - i >= 3 && (!memcmp(d + i, "OFF", 3) || (n - i >= 4 && !memcmp(d + i + 1, "OFF", 3))))
        return "off";
    if (n >= 84) {
        uint32_t k = (uint32_t)d[80] | (uint32_t)d[81] << 8 | (uint32_t)d[82] << 16 |
                     (uint32_t)d[83] << 24;
        if ((uint64_t)k * 50 + 84 == n) return "stl";
    }
    if (n - i >= 5 && !memcmp(d + i, "solid", 5)) return "stl";
    /* OBJ: a line starting with "v " */
    for (size_t j = 0; j + 2 < n && j < 65536; j++)
        if ((j == 0 || d[j - 1] == '\n') && d[j] == 'v' && (d[j + 1] == ' ' || d[j + 1] == '\t'))
            return "obj";
    return NULL;
}

bvox_status bvox_mesh_read_memory(const void *data, size_t size, const char *name,
                                  const char *format, bvox_mesh **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_read_memory: out is NULL");
    *out = NULL;
    if (!data && size) return bvox__fail(BVOX_EINVAL, "bvox_mesh_read_memory: data is NULL");
    if (!name) name = "(memory)";
    const uint8_t *d = data ? data : (const uint8_t *)"";
    const char *f = format ? format : sniff(d, size);
    if (!f)
        return bvox__fail(BVOX_EFORMAT, "%s: not a mesh file bvox can read (STL, OBJ, PLY, OFF)",
                          name);
    bvox_status (*rd)(const uint8_t *, size_t, const char *, bvox_mesh *) =
        !strcmp(f, "stl") ? bvox__mesh_read_stl
        : !strcmp(f, "obj") ? bvox__mesh_read_obj
        : !strcmp(f, "ply") ? bvox__mesh_read_ply
        : !strcmp(f, "off") ? bvox__mesh_read_off
                            : NULL;
    if (!rd) return bvox__fail(BVOX_EINVAL, "unknown mesh format '%s' (stl, obj, ply, off)", f);
    bvox_mesh *m;
    bvox_status st = bvox_mesh_create(&m);
    if (st) return st;
    st = rd(d, size, name, m);
    if (st) {
        /* the building calls (bvox_mesh_add_vertex: a coordinate out of range)
         * fail only because of the file's content, and do not name it */
        if (st == BVOX_EINVAL) st = BVOX_EFORMAT;
        bvox__error_prefix(name);
        bvox_mesh_destroy(m);
        return st;
    }
    *out = m;
    return BVOX_OK;
}

bvox_status bvox_mesh_read(const char *path, const char *format, bvox_mesh **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_read: out is NULL");
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "bvox_mesh_read: path is NULL");
    bvox__bytes b;
    bvox_status st = bvox__read_file(path, &b);
    if (st) return st;
    const char *f = format ? format : bvox_mesh_format_for_path(path);
    st = bvox_mesh_read_memory(b.data, b.size, path, f, out);
    /* a wrong extension: try the content */
    if (st == BVOX_EFORMAT && !format && f) {
        const char *g = sniff(b.data, b.size);
        if (g && strcmp(g, f)) {
            char keep[512];
            snprintf(keep, sizeof keep, "%s", bvox_errmsg());
            st = bvox_mesh_read_memory(b.data, b.size, path, g, out);
            if (st) bvox__fail(st, "%s", keep);
        }
    }
    bvox__bytes_release(&b);
    if (!st) BVOX_CHECK_MESH(*out);
    return st;
}
