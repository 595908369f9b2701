/* bvox/mesh.h — (filled in by its issue). Included by bvox.h. */
#ifndef BVOX_MESH_H
#define BVOX_MESH_H

#endif /* BVOX_MESH_H */
