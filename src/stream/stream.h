/*
 * stream.h — the out-of-core operations: a volume larger than the memory
 * budget, read in slabs along z from a bvox__slab_source, each slab handed to
 * the same in-memory kernel as a whole volume would be, and the per-slab
 * answers added up so that they equal the in-memory answer exactly:
 *
 *   stream_plan.c     when to stream and how deep a slab may be;
 *   stream_measure.c  count and bounding box (info), and every measure of
 *                     bvox_measure: integer scans of slabs that overlap by one
 *                     slice, added with inclusion-exclusion (the scan's
 *                     sums are over 2x2x2 windows, so scan(A) + scan(B) -
 *                     scan(A and B's shared slice) is the scan of the union);
 *   stream_cc.c       connected components: each slab labelled, labels that
 *                     meet on the shared slice joined by a union-find;
 *   stream_map.c      morphology and CSG: each slab with the halo the
 *                     operation reaches, cut back to its core, written out;
 *   stream_mesh.c     marching cubes: each cell's triangles from one slab,
 *                     vertices welded across the seams, handed on (to a
 *                     file) slab by slab; stream_mesh_info.c measures the
 *                     mesh as it passes.
 */
#ifndef BVOX_STREAM_STREAM_H
#define BVOX_STREAM_STREAM_H

#include "stream/slab_source.h"

/* ---- stream_plan.c ---- */

/* True when a volume of dims would not fit the memory budget to be worked on
 * in memory (its words and the copies an operation takes). */
bool bvox__stream_needed(bvox_dims dims);
/* Slab depth: a multiple of align (at least align, at most nz rounded up),
 * as deep as the budget allows for slabs of depth + 2 * halo slices of which
 * `copies` are held at once, beside what the source's reader and `extra`
 * (a sink's buffers) hold. */
int32_t bvox__stream_depth(const bvox__slab_source *src, int32_t halo, int32_t align, int copies,
                           size_t extra);
/* Test hook: slabs no deeper than cap slices (rounded down to the alignment,
 * at least one alignment step); 0 lifts it. */
void bvox__stream_set_depth_cap(int32_t cap);

/* ---- stream_cc.c ---- */

/* Components of the 1-voxels (or, with background, of the 0-voxels), conn
 * 6/18/26, fed slab after slab. Each slab but the last ends with the first
 * slice of the next one (slabs overlap by one slice). With exclude_border,
 * components touching the border of the whole volume are not counted (the
 * cavities of the background). */
typedef struct bvox__stream_cc bvox__stream_cc;
bvox_status bvox__stream_cc_begin(bvox_dims dims, int conn, bool background, bool exclude_border,
                                  bool want_items, bvox__stream_cc **out);
/* slab holds slices z0 .. z0 + slab->nz - 1 of the volume. */
bvox_status bvox__stream_cc_add(bvox__stream_cc *cc, const bvox_volume *slab, int32_t z0);
/* The count, and (want_items) the components as bvox_components_find
 * gives them: largest first, ties by the first voxel in column order, the
 * volume from spacing. *items is bvox__mem_alloc'd (free it). Releases cc. */
bvox_status bvox__stream_cc_finish(bvox__stream_cc *cc, const double spacing[3], int64_t *count,
                                   bvox_component **items);
void bvox__stream_cc_abort(bvox__stream_cc *cc);

/* Components of a source (one pass). */
bvox_status bvox__stream_components(const bvox__slab_source *src, int conn, int64_t *count,
                                    bvox_component **items);

/* ---- stream_measure.c ---- */

/* What bvox_info_compute gives, slab by slab. */
bvox_status bvox__stream_info(const bvox__slab_source *src, bvox_info *out);
/* What bvox_measure gives, exactly, slab by slab. */
bvox_status bvox__stream_measure(const bvox__slab_source *src, bvox_measures *out);

/* ---- stream_map.c ---- */

/* out = fn(in slabs): called per slab with the slabs of nsrc sources (same
 * dimensions) read halo slices beyond the core on each side (clipped to the
 * volume); the result (same dims as the slabs) is cut to the core and put
 * into sink. */
typedef bvox_status (*bvox__slab_fn)(void *ctx, bvox_volume *const *in, int nsrc,
                                     bvox_volume **out);
bvox_status bvox__stream_map(const bvox__slab_source *const *src, int nsrc, int32_t halo,
                             int copies, bvox__slab_fn fn, void *ctx, bvox__slab_sink *sink);

/* Morphology by slabs: op 0 dilate, 1 erode, 2 open, 3 close; radius > 0
 * selects the ball (as bvox_morph_dilate_ball...), else the conn
 * neighbourhood. */
typedef enum bvox__stream_morph_op {
    BVOX__SM_DILATE, BVOX__SM_ERODE, BVOX__SM_OPEN, BVOX__SM_CLOSE
} bvox__stream_morph_op;
bvox_status bvox__stream_morph(const bvox__slab_source *src, bvox__stream_morph_op op, int conn,
                               double radius, bvox__slab_sink *sink);
/* a OP b, slab by slab (same dimensions). */
bvox_status bvox__stream_csg(const bvox__slab_source *a, const bvox__slab_source *b,
                             bvox_csg_op op, bvox__slab_sink *sink);

/* ---- stream_mesh_info.c ---- */

/* bvox_mesh_measure's answers for a mesh handed over slab by slab: each
 * vertex once, each triangle with its vertices' positions and whether each
 * lies in the slab's top seam plane (shared with the next slab); then the
 * end of each slab. The volume is summed from the centre of the volume's
 * box (not the mesh's): equal but for rounding. */
typedef struct bvox__mesh_tally bvox__mesh_tally;
/* edges false: no edge counts (edges, boundary, nonmanifold, inconsistent
 * and watertight stay 0), which cost 48 bytes per triangle of a slab. */
bvox_status bvox__mesh_tally_begin(const bvox__slab_source *src, bool edges,
                                   bvox__mesh_tally **out);
void bvox__mesh_tally_vertex(bvox__mesh_tally *t, const double p[3]);
bvox_status bvox__mesh_tally_triangle(bvox__mesh_tally *t, const int64_t idx[3],
                                      const double *const p[3], const bool top[3]);
/* Room for a slab's ncur half-edges counted at its end and ncarry carried
 * to the next slab (both ends in the seam), before it is handed over, so
 * that a slab too large for the budget fails before anything is written. */
bvox_status bvox__mesh_tally_reserve(bvox__mesh_tally *t, int64_t ncur, int64_t ncarry);
bvox_status bvox__mesh_tally_slab_done(bvox__mesh_tally *t, bool last);
bvox_status bvox__mesh_tally_finish(bvox__mesh_tally *t, bvox_mesh_info *info);
void bvox__mesh_tally_release(bvox__mesh_tally *t); /* NULL accepted */

/* ---- stream_mesh.c ---- */

/* Where the slabs' vertices and triangles go, in order: vertex i is the
 * i-th vertex handed on; a triangle refers to vertices handed on before it
 * and comes with their positions. */
typedef struct bvox__mesh_emit {
    bvox_status (*vertex)(void *ctx, const double p[3]);
    bvox_status (*triangle)(void *ctx, const int64_t idx[3], const double *const p[3]);
    void *ctx;
    size_t bytes; /* what it holds of the budget (buffers), for the slab depth */
} bvox__mesh_emit;

/* The marching-cubes mesh of the source (bvox_mesh_from_volume with the
 * default options), slab by slab, handed to emit as each slab is done (and
 * to tally when not NULL): the same triangles and vertices as in memory, up
 * to their order. Holds one slab's mesh and one seam's vertices; a slab
 * whose mesh is over the budget is retried thinner. Needs the identity
 * direction. */
bvox_status bvox__stream_mesh_emit(const bvox__slab_source *src, const bvox__mesh_emit *emit,
                                   bvox__mesh_tally *tally);
/* The same into a mesh in memory. */
bvox_status bvox__stream_mesh(const bvox__slab_source *src, bvox_mesh **out);
/* The same into the file path (format as bvox_mesh_write's, NULL: by the
 * extension; ascii for STL and PLY), written as it is made (mesh_sink.h):
 * atomic, nothing left on failure. info (NULL: not wanted) gets what
 * bvox_mesh_measure would say of the mesh, the edge counts and watertight
 * only with edges. */
bvox_status bvox__stream_mesh_write(const bvox__slab_source *src, const char *path,
                                    const char *format, int ascii, bvox_mesh_info *info,
                                    bool edges);

#endif /* BVOX_STREAM_STREAM_H */
