/*
 * bvox/mesh.h — triangle meshes: volume -> watertight mesh (marching cubes,
 * cuberille), Taubin smoothing, mesh measures, mesh files (STL binary/ASCII,
 * PLY ascii/binary, OBJ, OFF) and mesh -> volume (voxelization). Included by
 * bvox.h; do not include it alone.
 *
 * Coordinates are world coordinates as bvox_geometry defines them: the
 * centre of voxel (i, j, k) is origin + direction * (i*sx, j*sy, k*sz).
 * Triangles are counter-clockwise seen from outside (outward normals, a
 * positive signed volume). Vertices are shared between triangles.
 */
#ifndef BVOX_MESH_H
#define BVOX_MESH_H

/* An indexed triangle mesh. The arrays belong to the mesh (budgeted
 * allocations); read them freely, change them only through the functions
 * below (or in place, keeping indices < nvertices). */
typedef struct bvox_mesh {
    double *vertices;   /* 3 * nvertices: x, y, z */
    int32_t *triangles; /* 3 * ntriangles vertex indices */
    int64_t nvertices;
    int64_t ntriangles;
    int64_t vcap, tcap; /* allocated capacity (vertices, triangles) */
} bvox_mesh;

/* An empty mesh. Destroy with bvox_mesh_destroy (accepts NULL). */
BVOX_API bvox_status bvox_mesh_create(bvox_mesh **out);
BVOX_API void bvox_mesh_destroy(bvox_mesh *mesh);
/* Make room for at least nv vertices and nt triangles (counts are limited
 * to INT32_MAX). */
BVOX_API bvox_status bvox_mesh_reserve(bvox_mesh *mesh, int64_t nv, int64_t nt);
/* The largest coordinate magnitude a vertex may have: measures multiply up
 * to four coordinate differences, which must stay finite. */
#define BVOX_MESH_COORD_MAX 1e60
/* Append a vertex (finite coordinates, |c| <= BVOX_MESH_COORD_MAX; else
 * BVOX_EINVAL) / a triangle (indices < nvertices). */
BVOX_API bvox_status bvox_mesh_add_vertex(bvox_mesh *mesh, double x, double y, double z);
BVOX_API bvox_status bvox_mesh_add_triangle(bvox_mesh *mesh, int32_t a, int32_t b, int32_t c);

/* ---------------------------------------------------- volume -> mesh */

typedef enum bvox_mesh_method {
    /* Marching cubes on the binary volume (iso 0.5: vertices at edge
     * midpoints). The case table is generated from one rule, "the 1-voxels
     * are 6-connected": on a face whose diagonal corners are 1 and 0, the
     * contour cuts off each 1-corner. The same rule on both sides of every
     * face makes the mesh of ANY volume a closed 2-manifold. */
    BVOX_MESH_MC = 0,
    /* Cuberille: two triangles per exposed voxel face (Artzy, Frieder and
     * Herman); its volume is the voxel volume exactly. Where voxels touch
     * only along an edge or at a corner, the corner vertex is duplicated,
     * one copy per surface sheet (the sheets of the marching-cubes rule
     * above), so every edge is shared by exactly two triangles. */
    BVOX_MESH_CUBERILLE = 1
} bvox_mesh_method;

typedef struct bvox_mesh_opts {
    bvox_mesh_method method;
    int smooth;    /* Taubin iterations (0: none) */
    double lambda; /* 0: 0.5 */
    double mu;     /* 0: -0.53 */
} bvox_mesh_opts;

#define BVOX_MESH_OPTS_INIT { BVOX_MESH_MC, 0, 0.5, -0.53 }

/* The surface of the 1-voxels (the volume is treated as surrounded by 0s,
 * so the mesh is always closed). opts may be NULL (marching cubes). */
BVOX_API bvox_status bvox_mesh_from_volume(const bvox_volume *vol, const bvox_mesh_opts *opts,
                                           bvox_mesh **out);

/* Taubin lambda/mu smoothing (a shrink step lambda > 0, an inflate step
 * mu < -lambda) over the shared-vertex adjacency, uniform weights; the
 * enclosed volume is nearly preserved. */
BVOX_API bvox_status bvox_mesh_smooth(bvox_mesh *mesh, int iterations, double lambda, double mu);

/* ------------------------------------------------------------- measures */

typedef struct bvox_mesh_info {
    int64_t vertices, triangles;
    double volume;       /* sum of signed tetrahedra (origin, a, b, c) */
    double area;
    double bbox_min[3], bbox_max[3]; /* zeros for an empty mesh */
    int64_t edges;           /* distinct undirected edges */
    int64_t boundary_edges;  /* used by one triangle */
    int64_t nonmanifold_edges; /* used by more than two triangles */
    int64_t inconsistent_edges; /* two triangles traverse it the same way */
    int64_t degenerate_triangles; /* a repeated vertex index */
    int watertight;          /* every edge in exactly two triangles, no degenerate */
} bvox_mesh_info;

BVOX_API bvox_status bvox_mesh_measure(const bvox_mesh *mesh, bvox_mesh_info *info);

/* ------------------------------------------------------------------ files */

/* Read "stl" (binary or ASCII), "obj", "ply" (ascii, binary little/big
 * endian) or "off"; format NULL: by extension, else by content. STL
 * triangles' coincident corners are welded (exact equality); polygons are
 * triangulated as fans. Bad input (truncated, NaN, index out of range,
 * absurd counts) is BVOX_EFORMAT with a message naming the file. */
BVOX_API bvox_status bvox_mesh_read(const char *path, const char *format, bvox_mesh **out);
BVOX_API bvox_status bvox_mesh_read_memory(const void *data, size_t size, const char *name,
                                           const char *format, bvox_mesh **out);
/* "stl", "ply", "obj", "off" for a path's extension, or NULL. */
BVOX_API const char *bvox_mesh_format_for_path(const char *path);

/* Write as "stl" (binary; ascii != 0: ASCII), "ply" (binary little endian;
 * ascii: ASCII), "obj" or "off" (text); format NULL: by extension. Written
 * atomically (temporary file, renamed on success). */
BVOX_API bvox_status bvox_mesh_write(const char *path, const bvox_mesh *mesh, const char *format,
                                     int ascii);

/* A mesh file written piece by piece, for a mesh too large to hold at once
 * (e.g. one row of chunks after another): the same formats and records as
 * bvox_mesh_write, the counts the header needs filled in at the end (PLY,
 * OBJ and OFF headers are padded with spaces where readers ignore them;
 * PLY's and OFF's faces wait in a temporary file beside path until the
 * end). Atomic: the file appears at close(commit) or not at all.
 * open: format NULL: by path's extension; BVOX_EINVAL, BVOX_EIO,
 * BVOX_ENOTFOUND. *out is released by bvox_mesh_writer_close only.
 * add: a piece of nvertices vertices (x, y, z each) and ntriangles
 * triangles (indices into the piece). global[i] (NULL: all -1) is the index
 * in the file of piece vertex i when an earlier piece wrote it (a vertex
 * two pieces share), or -1: written now, taking the next index in piece
 * order. BVOX_EINVAL for a bad index (nothing of the piece written),
 * BVOX_ETOOBIG past the format's indices (PLY: 2^31 vertices; binary STL
 * 2^32 - 1 triangles), BVOX_EIO.
 * close: commit != 0 completes the file and renames it into place (after an
 * earlier failure it fails); 0 removes everything. Frees w (NULL accepted).
 * A writer is used by one thread at a time. */
typedef struct bvox_mesh_writer bvox_mesh_writer;
BVOX_API bvox_status bvox_mesh_writer_open(const char *path, const char *format, int ascii,
                                           bvox_mesh_writer **out);
BVOX_API bvox_status bvox_mesh_writer_add(bvox_mesh_writer *w, const double *vertices,
                                          int64_t nvertices, const int64_t *global,
                                          const int32_t *triangles, int64_t ntriangles);
/* Vertices and triangles written so far. */
BVOX_API void bvox_mesh_writer_counts(const bvox_mesh_writer *w, int64_t *nvertices,
                                      int64_t *ntriangles);
BVOX_API bvox_status bvox_mesh_writer_close(bvox_mesh_writer *w, int commit);

/* ------------------------------------------------------- mesh -> volume */

typedef struct bvox_voxelize_opts {
    int32_t res;       /* voxels along the longest side of the bounding box */
    double voxel_size; /* or the voxel size (world units); exactly one > 0 */
    int shell;         /* 1: only the voxels the surface passes through */
    char unit[16];     /* unit of the output geometry ("" unknown) */
    /* Or (res and voxel_size 0) anisotropic voxels: spacing[0..2] > 0, the
     * grid covering the bounding box as above, per axis. */
    double spacing[3];
    /* Or (res, voxel_size and spacing 0) a given grid, e.g. an existing
     * image's (bvox voxelize --like): grid_dims voxels of grid->spacing, voxel
     * (0,0,0)'s centre at grid->origin, axes grid->direction; the output
     * takes the grid's geometry (and its unit when unit is ""). Parts of the
     * mesh outside the grid are cut off. */
    const bvox_geometry *grid;
    bvox_dims grid_dims;
} bvox_voxelize_opts;

typedef struct bvox_voxelize_report {
    int closed;            /* 1: a closed (watertight) mesh: exact parity along z */
    int64_t open_edges;    /* edges not shared by exactly two triangles */
    const char *method;    /* "parity-z", "vote-xyz" (open mesh) or "shell" */
} bvox_voxelize_report;

/* A voxel is inside when its centre is inside the mesh. The grid covers the
 * mesh's bounding box, centred on it, with voxel centres at origin + i*s, so
 * a box meshed back (cuberille or marching cubes) lands on its original
 * faces. Inside test: rays along z through the voxel centres, crossings found
 * with exact 2D orientation tests on coordinates snapped to a 2^-20 voxel
 * grid, ties broken by a symbolic perturbation of the ray (simulation of
 * simplicity), parity per ray. A mesh that is not closed is voxelized along x,
 * y and z and each voxel gets the majority vote. report may be NULL. */
BVOX_API bvox_status bvox_mesh_voxelize(const bvox_mesh *mesh, const bvox_voxelize_opts *opts,
                                        bvox_volume **out, bvox_voxelize_report *report);
/* The dimensions bvox_mesh_voxelize would give, with the same checks of the
 * mesh and options, computed from the bounding box alone (nothing is
 * allocated): to refuse an output that cannot hold them before the work. */
BVOX_API bvox_status bvox_mesh_voxelize_dims(const bvox_mesh *mesh,
                                             const bvox_voxelize_opts *opts, bvox_dims *dims);

/* ------------------------------------------------- label sets -> meshes */

/* The cuberille surface of object `index` of a label set, in world
 * coordinates. Two labels that touch share their boundary exactly: every
 * voxel face between them is a triangle pair of both meshes, with bitwise
 * equal vertices and opposite orientations (no gap, no overlap). */
BVOX_API bvox_status bvox_labelset_mesh(const bvox_labelset *set, int64_t index, bvox_mesh **out);
/* "LABEL_NAME.EXT" (NAME reduced to letters, digits, '-', '_', '.'; runs of
 * anything else become one '_'; at most 64 characters) or "LABEL.EXT"
 * without a name, into buf. */
BVOX_API void bvox_label_file_name(int64_t label, const char *name, const char *ext, char *buf,
                          size_t size);
/* One mesh file per listed object (indices into set->objects; names[i] its
 * name or NULL; names may be NULL) in folder dir, named by
 * bvox_label_file_name, format "stl", "ply", "obj" or "off". The folder is
 * written under a temporary name and renamed into place only when every
 * mesh is written. */
BVOX_API bvox_status bvox_labelset_write_meshes(const bvox_labelset *set, const int64_t *indices,
                                       int64_t n, const char *const *names, const char *dir,
                                       const char *format, int ascii);
/* The listed objects' meshes (as bvox_labelset_mesh) in ONE file, one
 * coloured object per label: path ending in .ply (binary, or ascii != 0:
 * vertex and face colours, a face property `label`) or .obj (an `o`/`g`
 * LABEL_NAME and `usemtl label_LABEL` per object; the materials' Kd in
 * BASE.mtl beside it). names[i] (or NULL; names may be NULL) names object
 * indices[i]; rgb holds 3 bytes per listed object (NULL: a colour of bvox's
 * choosing per label). Touching labels share their boundary faces as in
 * bvox_labelset_mesh. Written through temporary files: on failure nothing
 * is left. BVOX_EINVAL for another extension or a bad index. */
BVOX_API bvox_status bvox_labelset_write_mesh_file(const bvox_labelset *set,
                                                   const int64_t *indices, int64_t n,
                                                   const char *const *names,
                                                   const unsigned char *rgb, const char *path,
                                                   int ascii);

#endif /* BVOX_MESH_H */
