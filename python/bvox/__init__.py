"""bvox — binary voxel models from Python, over the libbvox shared library.

    import bvox, numpy as np
    vol = bvox.Volume.from_numpy(mask, spacing=(0.5, 0.5, 2.0), unit="mm")
    vol = bvox.read("atlas.nii.gz", label=37)
    closed = vol.dilate(conn=26).erode(conn=26)
    labels, comps = vol.components(conn=26)
    m = vol.measure()                       # keys of `bvox measure --json`
    verts, faces = vol.mesh()
    rgb = vol.render("iso")                 # (h, w, 3) uint8
    mask = vol.to_numpy()                   # bool [x, y, z]

Arrays are indexed [x, y, z] (as nibabel gives them). Errors raise
bvox.Error subclasses with the library's message (e.status_name says which).
Calls into the library release the GIL. As the C API documents: different
volumes may be used from different threads at once, and read-only calls may
share a volume; calls that change a volume need it alone.
"""
import os

from . import _progress
from ._lib import (Canceled, Error, FormatError, InvalidArgument, IOFailure, NotFound, OutOfMemory,
                   TooBig, Unsupported, check, cstr, ffi, lib)
from ._mesh import mesh_info, read_mesh, voxelize, write_mesh
from ._recon import Contours, read_contours, reconstruct
from ._render import render, render_objects, write_png
from ._volume import Volume, _binarize

__all__ = ["Canceled", "Volume", "Contours", "read_contours", "reconstruct", "read", "csg", "demo", "render", "render_objects", "write_png", "voxelize", "read_mesh",
           "write_mesh", "mesh_info", "Error", "InvalidArgument", "OutOfMemory", "IOFailure",
           "FormatError", "TooBig", "NotFound", "Unsupported", "version", "memory_in_use", "memory_trim",
           "memory_budget", "set_memory_budget", "threads", "set_threads", "library_path"]

__version__ = ffi.string(lib.bvox_version()).decode()


def version():
    """The library's version ("0.1.0")."""
    return __version__


def library_path():
    """Where the loaded libbvox came from ($BVOX_LIBRARY or the search)."""
    return os.environ.get("BVOX_LIBRARY") or "libbvox.so.0"


def read(path, *, format=None, threshold=None, range=None, label=None, nonzero=None,
         otsu=False, dims=None, dtype=None, big_endian=False, offset=0, spacing=None,
         unit=None, progress=None):
    """Read a volume file (NIfTI, TIFF, binvox, PNG slices folder, raw) with
    the command's read options: threshold, range=(lo, hi), label, nonzero,
    otsu; format forces a reader. Raw files need dims=(nx, ny, nz) and dtype
    (bvox's names "u8", "i16", "f32", ... or a NumPy dtype such as np.int16),
    with offset (bytes of header), big_endian, spacing and unit. progress:
    a callable(fraction, stage) called while reading (see bvox._progress)."""
    opts = ffi.new("bvox_read_opts *")
    keep = []
    if format:
        keep.append(cstr(format))
        opts.format = keep[-1]
    opts.binarize = _binarize(threshold, range, label, nonzero, otsu)[0]
    if dims is not None:
        opts.raw_dims = tuple(int(d) for d in dims)
    if dtype is not None:
        opts.raw_dtype = _raw_dtype(dtype)
    opts.raw_big_endian = 1 if big_endian else 0
    opts.raw_offset = int(offset)
    if spacing is not None:  # a raw file's voxel size, and any other file's override
        opts.raw_spacing = [float(s) for s in spacing]
        opts.spacing = [float(s) for s in spacing]
    if unit is not None:
        keep.append(cstr(unit))
        opts.raw_unit = keep[-1]
        opts.unit = keep[-1]
    out = ffi.new("bvox_volume **")
    _progress.call(progress, lib.bvox_read, os.fsencode(path), opts, out)
    return Volume._own(out[0])


def _raw_dtype(dtype):
    """bvox's names first ("u8" is uint8 here, as in `bvox convert --type`),
    then anything NumPy takes for a dtype."""
    from ._volume import _DTYPES
    import numpy as np
    if isinstance(dtype, str):
        k = lib.bvox_dtype_parse(dtype.encode())
        if k >= 0:
            return k
    try:
        dt = np.dtype(dtype)
    except TypeError:
        raise TypeError("bvox: unknown dtype %r" % (dtype,)) from None
    if dt.newbyteorder("=") not in _DTYPES or dt == np.bool_:
        raise TypeError("bvox: raw files hold integers or float32/float64, not %s" % dt)
    return _DTYPES[dt.newbyteorder("=")]


def demo():
    """The built-in specimen of `bvox demo` (256 x 256 x 128 voxels of
    10 x 10 x 25 um)."""
    out = ffi.new("bvox_volume **")
    check(lib.bvox_demo_specimen(out))
    return Volume._own(out[0])


def csg(expr, shape=None, *, spacing=None, unit=None, origin=None, **volumes):
    """Evaluate a set-operation expression (the language of `bvox csg`):
    "a + b * c - sphere(r=3)" with '+' union, '*' intersection, '-'
    difference, '^' xor, '~' complement, '@i,j,k' offsets and the shapes
    sphere/ellipsoid/box/cylinder/cone/torus/halfspace. A name given as a
    keyword argument is that Volume; any other operand is read as a file.
    The grid is the first operand's, or shape (nx, ny, nz) with spacing,
    unit and origin when there is none."""
    opts = ffi.new("bvox_csg_eval_opts *", lib.bvox_csg_eval_opts_default())
    if shape is not None:
        opts.dims = tuple(int(s) for s in shape)
        tmp = Volume((1, 1, 1), spacing=spacing, unit=unit, origin=origin)
        opts.geometry = lib.bvox_volume_geometry(tmp._p)[0]
        tmp.close()
    for name, v in volumes.items():
        if not isinstance(v, Volume):
            raise TypeError("bvox: csg operand %s must be a bvox.Volume" % name)
    errors = []

    @ffi.callback("int(void *, const char *, bvox_volume **)")
    def load(ctx, name, out):
        key = ffi.string(name).decode("utf-8", "surrogateescape")
        try:
            if key in volumes:
                return lib.bvox_volume_copy(volumes[key]._p, out)
            return lib.bvox_read(ffi.string(name), ffi.NULL, out)
        except Exception as e:  # never let an exception cross into C
            errors.append(e)
            return 1

    opts.load = load
    out = ffi.new("bvox_volume **")
    status = lib.bvox_csg_eval(expr.encode(), opts, out)
    if errors:
        raise errors[0]
    check(status)
    return Volume._own(out[0])


def memory_in_use():
    """Bytes the library holds now through its budgeted allocator (the words
    of every live volume, buffers of running operations)."""
    return int(lib.bvox_memory_in_use())


def memory_trim():
    """Return to the system the large buffers the library keeps after they
    are freed (for the next operation to reuse; not counted in
    memory_in_use)."""
    lib.bvox_memory_trim()


def memory_budget():
    return int(lib.bvox_memory_budget())


def set_memory_budget(nbytes):
    """Cap the library's large buffers (0: the default, half of memory)."""
    lib.bvox_set_memory_budget(int(nbytes))


def threads():
    return int(lib.bvox_threads())


def set_threads(n):
    lib.bvox_set_threads(int(n))
