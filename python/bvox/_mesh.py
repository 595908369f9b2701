"""_mesh.py — triangle meshes as NumPy arrays: volume -> mesh (marching cubes
or cuberille), mesh -> volume (voxelize), mesh files in and out."""
import os

import numpy as np

from ._lib import check, cstr, ffi, lib

_METHODS = {"mc": 0, "marching-cubes": 0, "cuberille": 1}


def _to_numpy(mesh):
    nv, nt = mesh.nvertices, mesh.ntriangles
    v = np.frombuffer(ffi.buffer(mesh.vertices, nv * 24), dtype=np.float64).reshape(nv, 3)
    f = np.frombuffer(ffi.buffer(mesh.triangles, nt * 12), dtype=np.int32).reshape(nt, 3)
    return v.copy(), f.copy()


def _from_numpy(vertices, faces):
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError("bvox: vertices must be an (n, 3) array, got %r" % (v.shape,))
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError("bvox: faces must be an (m, 3) array, got %r" % (f.shape,))
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError("bvox: a face refers to a vertex that does not exist")
    f = np.ascontiguousarray(f, dtype=np.int32)
    out = ffi.new("bvox_mesh **")
    check(lib.bvox_mesh_create(out))
    mesh = ffi.gc(out[0], lib.bvox_mesh_destroy)
    check(lib.bvox_mesh_reserve(mesh, len(v), len(f)))
    ffi.memmove(mesh.vertices, v.tobytes(), v.nbytes)
    ffi.memmove(mesh.triangles, f.tobytes(), f.nbytes)
    mesh.nvertices, mesh.ntriangles = len(v), len(f)
    return mesh


def mesh_from_volume(vol, method="mc", smooth=0, progress=None):
    if method not in _METHODS:
        raise ValueError("bvox: mesh method is 'mc' or 'cuberille', not %r" % (method,))
    opts = ffi.new("bvox_mesh_opts *", {"method": _METHODS[method], "smooth": int(smooth),
                                        "lambda": 0.5, "mu": -0.53})
    out = ffi.new("bvox_mesh **")
    from ._progress import call
    call(progress, lib.bvox_mesh_from_volume, vol._p, opts, out)
    mesh = ffi.gc(out[0], lib.bvox_mesh_destroy)
    result = _to_numpy(mesh)
    ffi.release(mesh)
    return result


def mesh_info(vertices, faces):
    """Volume, area, bounding box and edge topology of a mesh (a dict)."""
    mesh = _from_numpy(vertices, faces)
    info = ffi.new("bvox_mesh_info *")
    check(lib.bvox_mesh_measure(mesh, info))
    ffi.release(mesh)
    return {"vertices": info.vertices, "triangles": info.triangles, "volume": info.volume,
            "area": info.area, "surface_area": info.area, "bbox_min": list(info.bbox_min), "bbox_max": list(info.bbox_max),
            "edges": info.edges, "boundary_edges": info.boundary_edges,
            "nonmanifold_edges": info.nonmanifold_edges,
            "inconsistent_edges": info.inconsistent_edges,
            "degenerate_triangles": info.degenerate_triangles,
            "watertight": bool(info.watertight)}


def read_mesh(path, format=None):
    """(vertices, faces) of an STL, PLY, OBJ or OFF file."""
    out = ffi.new("bvox_mesh **")
    fmt = cstr(format) if format else ffi.NULL
    check(lib.bvox_mesh_read(os.fsencode(path), fmt, out))
    mesh = ffi.gc(out[0], lib.bvox_mesh_destroy)
    result = _to_numpy(mesh)
    ffi.release(mesh)
    return result


def write_mesh(path, vertices, faces, format=None, ascii=False):
    """Write a mesh as STL, PLY or OBJ (by the extension unless format)."""
    mesh = _from_numpy(vertices, faces)
    fmt = cstr(format) if format else ffi.NULL
    try:
        check(lib.bvox_mesh_write(os.fsencode(path), mesh, fmt, 1 if ascii else 0))
    finally:
        ffi.release(mesh)


def voxelize(vertices, faces, res=None, voxel_size=None, shell=False, unit=""):
    """The voxels inside a closed mesh (or its shell): a bvox.Volume whose
    longest side has res voxels, or whose voxels are voxel_size wide (give
    exactly one). Returns (volume, report dict: closed, open_edges, method)."""
    from ._volume import Volume
    if (res is None) == (voxel_size is None):
        raise ValueError("bvox: voxelize needs exactly one of res and voxel_size")
    mesh = _from_numpy(vertices, faces)
    opts = ffi.new("bvox_voxelize_opts *")
    opts.res = int(res or 0)
    opts.voxel_size = float(voxel_size or 0.0)
    opts.shell = 1 if shell else 0
    u = unit.encode()
    if len(u) >= 16:
        raise ValueError("bvox: unit %r is too long" % unit)
    opts.unit = u
    out = ffi.new("bvox_volume **")
    rep = ffi.new("bvox_voxelize_report *")
    try:
        check(lib.bvox_mesh_voxelize(mesh, opts, out, rep))
    finally:
        ffi.release(mesh)
    report = {"closed": bool(rep.closed), "open_edges": rep.open_edges,
              "method": ffi.string(rep.method).decode() if rep.method else None}
    return Volume._own(out[0]), report
