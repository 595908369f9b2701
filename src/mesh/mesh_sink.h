/*
 * mesh_sink.h — a mesh file written piece by piece (mesh_sink.c), for a mesh
 * too large to hold: vertices and triangles are handed over as they are made
 * and written at once, the counts the header needs are filled in at the end.
 * Same formats and bytes as bvox_mesh_write (STL, PLY, OBJ, OFF; ASCII STL
 * and PLY with ascii), but for padding spaces in the header where readers
 * ignore them (PLY's comment, OBJ's first comment line, OFF's count line).
 * Atomic as every writer: the file appears complete at close(commit) or
 * not at all.
 */
#ifndef BVOX_MESH_MESH_SINK_H
#define BVOX_MESH_MESH_SINK_H

#include "internal.h"

typedef struct bvox__mesh_sink bvox__mesh_sink;

/* What an open sink holds of the memory budget: two 1 MiB output blocks
 * (checked against mesh_private.h's block size in mesh_sink.c). */
#define BVOX__MESH_SINK_BYTES ((size_t)2 << 20)

/* format NULL: by path's extension. BVOX_EINVAL for an unknown format, the
 * sink's errors (BVOX_EIO, BVOX_ENOTFOUND) for the path. */
bvox_status bvox__mesh_sink_open(const char *path, const char *format, int ascii,
                                 bvox__mesh_sink **out);
/* The next vertex (its index: the number of vertices added before).
 * BVOX_ETOOBIG past what the format indexes (PLY: 2^31 vertices). */
bvox_status bvox__mesh_sink_vertex(bvox__mesh_sink *s, const double p[3]);
/* A triangle of vertices added before, with their positions (STL stores
 * positions, not indices). BVOX_ETOOBIG past 2^32 - 1 for binary STL. */
bvox_status bvox__mesh_sink_triangle(bvox__mesh_sink *s, const int64_t idx[3],
                                     const double *const p[3]);
/* commit: complete the header and rename the file into place; otherwise (or
 * after any failure) remove what was written. Frees s (NULL accepted). */
bvox_status bvox__mesh_sink_close(bvox__mesh_sink *s, bool commit);

#endif
