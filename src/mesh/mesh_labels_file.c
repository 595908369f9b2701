/*
 * mesh_labels_file.c — the meshes of several labels in ONE file, one
 * coloured object per label (`bvox mesh IN --labels ... -o out.ply|out.obj`):
 *  - PLY: the objects' vertices one after the other, each with the red,
 *    green, blue of its label, and every face with its colour and its
 *    `label` (an int property), so that a viewer colours by either and a
 *    script can split the objects again; a "comment object LABEL NAME" line
 *    per object in the header.
 *  - OBJ: per label an `o` and a `g` named LABEL_NAME (bvox_label_file_name
 *    without the extension) and `usemtl label_LABEL`; the materials (Kd: the
 *    colour) in BASE.mtl beside it, written first, named by `mtllib`.
 * Each object is the label's own closed cuberille mesh
 * (bvox_labelset_mesh), so two labels that touch both hold their common
 * faces, with bitwise-equal vertices and opposite orientations: no gap, no
 * overlap. The meshes are made once and kept until the file is written (the
 * PLY header needs the counts first).
 */
#include "io/io.h"
#include "mesh_private.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A colour for a label without one: hues around the circle by the golden
 * angle (neighbouring labels far apart), full saturation, bright. */
static void default_color(int64_t label, unsigned char rgb[3])
{
    double h = (double)((uint64_t)label * 0x9E3779B97F4A7C15ull >> 11) / (double)(1ull << 53);
    double s = 0.65, v = 0.95, f = h * 6 - (int)(h * 6);
    double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    double c[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    int k = (int)(h * 6) % 6;
    for (int i = 0; i < 3; i++) rgb[i] = (unsigned char)(c[k][i] * 255 + 0.5);
}

static void color_of(const unsigned char *rgb, int64_t i, int64_t label, unsigned char out[3])
{
    if (rgb) memcpy(out, rgb + 3 * i, 3);
    else default_color(label, out);
}

/* "LABEL_NAME" for the object names of OBJ and PLY comments. */
static void object_name(int64_t label, const char *name, char *buf, size_t size)
{
    bvox_label_file_name(label, name, "x", buf, size);
    size_t n = strlen(buf);
    if (n >= 2) buf[n - 2] = '\0'; /* drop ".x" */
}

static void write_ply(bvox__mesh_out *o, const bvox_labelset *set, const int64_t *idx,
                      int64_t n, const char *const *names, const unsigned char *rgb,
                      bvox_mesh *const *m, int ascii)
{
    int64_t nv = 0, nt = 0;
    for (int64_t i = 0; i < n; i++) {
        nv += m[i]->nvertices;
        nt += m[i]->ntriangles;
    }
    bvox__mesh_out_printf(o, "ply\nformat %s 1.0\ncomment written by bvox %s\n",
                          ascii ? "ascii" : "binary_little_endian", bvox_version());
    for (int64_t i = 0; i < n; i++) {
        char on[96];
        object_name(set->objects[idx[i]].label, names ? names[i] : NULL, on, sizeof on);
        bvox__mesh_out_printf(o, "comment object %s: %lld vertices, %lld faces\n", on,
                              (long long)m[i]->nvertices, (long long)m[i]->ntriangles);
    }
    bvox__mesh_out_printf(o,
                          "element vertex %lld\nproperty double x\nproperty double y\n"
                          "property double z\nproperty uchar red\nproperty uchar green\n"
                          "property uchar blue\nelement face %lld\n"
                          "property list uchar int vertex_indices\nproperty uchar red\n"
                          "property uchar green\nproperty uchar blue\nproperty int label\n"
                          "end_header\n",
                          (long long)nv, (long long)nt);
    for (int64_t i = 0; i < n; i++) {
        unsigned char c[3];
        color_of(rgb, i, set->objects[idx[i]].label, c);
        for (int64_t v = 0; v < m[i]->nvertices; v++) {
            const double *p = m[i]->vertices + 3 * v;
            if (ascii) {
                bvox__mesh_out_printf(o, "%.17g %.17g %.17g %u %u %u\n", p[0], p[1], p[2], c[0],
                                      c[1], c[2]);
            } else {
                for (int k = 0; k < 3; k++) bvox__mesh_out_f64(o, p[k]);
                bvox__mesh_out_put(o, c, 3);
            }
        }
    }
    int64_t base = 0;
    for (int64_t i = 0; i < n; i++) {
        unsigned char c[3];
        int64_t label = set->objects[idx[i]].label;
        color_of(rgb, i, label, c);
        for (int64_t t = 0; t < m[i]->ntriangles; t++) {
            const int32_t *tr = m[i]->triangles + 3 * t;
            int64_t a = base + tr[0], b = base + tr[1], d = base + tr[2];
            if (ascii) {
                bvox__mesh_out_printf(o, "3 %lld %lld %lld %u %u %u %lld\n", (long long)a,
                                      (long long)b, (long long)d, c[0], c[1], c[2],
                                      (long long)label);
            } else {
                uint8_t three = 3;
                bvox__mesh_out_put(o, &three, 1);
                bvox__mesh_out_le32(o, (uint32_t)a);
                bvox__mesh_out_le32(o, (uint32_t)b);
                bvox__mesh_out_le32(o, (uint32_t)d);
                bvox__mesh_out_put(o, c, 3);
                bvox__mesh_out_le32(o, (uint32_t)(int32_t)label);
            }
        }
        base += m[i]->nvertices;
    }
}

static void write_obj(bvox__mesh_out *o, const bvox_labelset *set, const int64_t *idx,
                      int64_t n, const char *const *names, bvox_mesh *const *m,
                      const char *mtl_base)
{
    bvox__mesh_out_printf(o, "# written by bvox %s: %lld labels\nmtllib %s\n", bvox_version(),
                          (long long)n, mtl_base);
    int64_t base = 1; /* OBJ counts vertices from 1, across the whole file */
    for (int64_t i = 0; i < n; i++) {
        char on[96];
        int64_t label = set->objects[idx[i]].label;
        object_name(label, names ? names[i] : NULL, on, sizeof on);
        bvox__mesh_out_printf(o, "o %s\ng %s\nusemtl label_%lld\n", on, on, (long long)label);
        for (int64_t v = 0; v < m[i]->nvertices; v++) {
            const double *p = m[i]->vertices + 3 * v;
            bvox__mesh_out_printf(o, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
        }
        for (int64_t t = 0; t < m[i]->ntriangles; t++) {
            const int32_t *tr = m[i]->triangles + 3 * t;
            bvox__mesh_out_printf(o, "f %lld %lld %lld\n", (long long)(base + tr[0]),
                                  (long long)(base + tr[1]), (long long)(base + tr[2]));
        }
        base += m[i]->nvertices;
    }
}

static bvox_status write_mtl(const char *path, const bvox_labelset *set, const int64_t *idx,
                             int64_t n, const char *const *names, const unsigned char *rgb)
{
    bvox__mesh_out o;
    bvox_status st = bvox__mesh_out_open(&o, path);
    if (st) return st;
    bvox__mesh_out_printf(&o, "# written by bvox %s: one material per label\n", bvox_version());
    for (int64_t i = 0; i < n; i++) {
        unsigned char c[3];
        int64_t label = set->objects[idx[i]].label;
        color_of(rgb, i, label, c);
        char on[96];
        object_name(label, names ? names[i] : NULL, on, sizeof on);
        bvox__mesh_out_printf(&o,
                              "\n# %s\nnewmtl label_%lld\nKa 0 0 0\nKd %.6g %.6g %.6g\n"
                              "Ks 0 0 0\nd 1\nillum 1\n",
                              on, (long long)label, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
    }
    return bvox__mesh_out_close(&o, true);
}

bvox_status bvox_labelset_write_mesh_file(const bvox_labelset *set, const int64_t *indices,
                                          int64_t n, const char *const *names,
                                          const unsigned char *rgb, const char *path,
                                          int ascii)
{
    bvox__clear_error();
    if (!set || !path || (n > 0 && !indices))
        return bvox__fail(BVOX_EINVAL, "bvox_labelset_write_mesh_file: NULL argument");
    const char *format = bvox_mesh_format_for_path(path);
    if (!format || (strcmp(format, "ply") && strcmp(format, "obj")))
        return bvox__fail(BVOX_EINVAL,
                          "%s: one file with a coloured object per label is .ply or .obj "
                          "(STL and OFF hold no colours: write a folder of meshes instead)",
                          path);
    for (int64_t i = 0; i < n; i++)
        if (indices[i] < 0 || indices[i] >= set->n)
            return bvox__fail(BVOX_EINVAL, "bvox_labelset_write_mesh_file: no object %lld",
                              (long long)indices[i]);
    bvox_mesh **m = n ? bvox__mem_zalloc((size_t)n, sizeof *m) : NULL;
    if (n && !m) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    bvox_status st = BVOX_OK;
    int64_t nv = 0;
    for (int64_t i = 0; i < n && !st; i++) {
        st = bvox_labelset_mesh(set, indices[i], &m[i]);
        if (!st) nv += m[i]->nvertices;
    }
    if (!st && nv > INT32_MAX)
        st = bvox__fail(BVOX_ETOOBIG, "%s: %lld vertices: more than a PLY/OBJ index holds here",
                        path, (long long)nv);
    char *mtl = NULL;
    if (!st && !strcmp(format, "obj")) {
        /* BASE.mtl beside BASE.obj, written first so the OBJ never names a
         * missing file */
        size_t len = strlen(path);
        mtl = bvox__mem_alloc(len + 1);
        if (!mtl) st = bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
        else {
            memcpy(mtl, path, len - 3);
            memcpy(mtl + len - 3, "mtl", 4);
            st = write_mtl(mtl, set, indices, n, names, rgb);
        }
    }
    if (!st) {
        bvox__mesh_out o;
        st = bvox__mesh_out_open(&o, path);
        if (!st) {
            if (mtl) {
                const char *slash = strrchr(mtl, '/');
                write_obj(&o, set, indices, n, names, m, slash ? slash + 1 : mtl);
            } else {
                write_ply(&o, set, indices, n, names, rgb, m, ascii);
            }
            st = bvox__mesh_out_close(&o, true);
        }
        if (st && mtl) unlink(mtl);
    }
    for (int64_t i = 0; i < n; i++) bvox_mesh_destroy(m ? m[i] : NULL);
    free(m);
    free(mtl);
    return st;
}
