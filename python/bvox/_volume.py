"""_volume.py — bvox.Volume: one binary volume owned by the library, with
NumPy arrays in and out (index order [x, y, z], as nibabel gives it).

Arrays cross without a byte-per-voxel copy on the bvox side: from_numpy packs
the caller's array in place into the volume's words (one bit per voxel), and
to_numpy unpacks the words straight into the NumPy array it returns. A
C-ordered [x, y, z] array (z fastest, NumPy's default) is the fastest order,
since a voxel column of the volume is then a run of the array.
"""
import os
import weakref

import numpy as np

from ._lib import InvalidArgument, check, cstr, ffi, lib
from . import _progress

_DTYPES = {
    np.dtype(np.bool_): 0, np.dtype(np.uint8): 0, np.dtype(np.int8): 1,
    np.dtype(np.uint16): 2, np.dtype(np.int16): 3, np.dtype(np.uint32): 4,
    np.dtype(np.int32): 5, np.dtype(np.uint64): 6, np.dtype(np.int64): 7,
    np.dtype(np.float32): 8, np.dtype(np.float64): 9,
}
ORDER_X_FASTEST, ORDER_Z_FASTEST = 0, 1
_CONN = (6, 18, 26)
_OPS = {"union": 0, "intersection": 1, "difference": 2, "xor": 3, "replace": 4}


def _binarize(threshold=None, range=None, label=None, nonzero=None, otsu=False):
    """The read options' binarisation (at most one of them) as a bvox_binarize."""
    given = [k for k, v in (("threshold", threshold), ("range", range), ("label", label),
                            ("nonzero", nonzero)) if v is not None and v is not False]
    if otsu:
        given.append("otsu")
    if len(given) > 1:
        raise ValueError("bvox: give at most one of threshold, range, label, nonzero, otsu "
                         "(got %s)" % ", ".join(given))
    b = ffi.new("bvox_binarize *")
    if threshold is not None:
        b.mode, b.threshold = 1, float(threshold)
    elif range is not None:
        lo, hi = range
        b.mode, b.lo, b.hi = 2, float(lo), float(hi)
    elif label is not None:
        b.mode, b.label = 4, float(label)
    elif otsu:
        b.mode = 3
    else:
        b.mode = 0
    return b


def _conn(conn):
    if conn not in _CONN:
        raise ValueError("bvox: conn must be 6, 18 or 26, not %r" % (conn,))
    return conn


def _triple(v, what, kind=float):
    try:
        t = tuple(kind(x) for x in v)
    except TypeError:
        t = (kind(v),) * 3
    if len(t) != 3:
        raise ValueError("bvox: %s needs 3 values, got %d" % (what, len(t)))
    return t


class Volume:
    """A binary volume of shape (nx, ny, nz) with its voxel size (spacing),
    unit and origin. Volume((nx, ny, nz)) makes an all-zero one.

    Operators make new volumes: a | b, a & b, a - b, a ^ b, ~a; in place:
    a |= b etc. Methods union/intersection/difference/xor take an offset
    (voxels) placing the second operand. close() releases the words now (a
    `with` block does it at the end); using a closed volume raises ValueError.
    """

    __slots__ = ("_cdata", "_views", "__weakref__")

    def __init__(self, shape=None, *, spacing=None, unit=None, origin=None, _cdata=None):
        self._views = weakref.WeakSet()
        if _cdata is None:
            if shape is None:
                raise TypeError("bvox: Volume(shape) needs the shape (nx, ny, nz)")
            nx, ny, nz = _dims(shape)
            out = ffi.new("bvox_volume **")
            check(lib.bvox_volume_create((nx, ny, nz), out))
            _cdata = out[0]
        self._cdata = ffi.gc(_cdata, lib.bvox_volume_destroy)
        if spacing is not None or unit is not None or origin is not None:
            self.set_geometry(spacing=spacing, unit=unit, origin=origin)

    @classmethod
    def _own(cls, cdata):
        return cls(_cdata=cdata)

    # ----------------------------------------------------------- life cycle
    @property
    def _p(self):
        if self._cdata is None:
            raise ValueError("bvox: this volume was closed")
        return self._cdata

    def close(self):
        """Release the volume's words now. Refused (BufferError) while a
        vol.words view is alive; closing twice is harmless."""
        if self._cdata is None:
            return
        if len(self._views):
            raise BufferError("bvox: cannot close a volume while a vol.words view of it exists")
        ffi.release(self._cdata)
        self._cdata = None

    @property
    def closed(self):
        return self._cdata is None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        if self._cdata is None:
            return "<bvox.Volume (closed)>"
        g = self.geometry_dict()
        return "<bvox.Volume %dx%dx%d, %d set, voxel %s %s>" % (
            *self.shape, self.count(), "x".join("%g" % s for s in g["spacing"]),
            g["unit"] or "(no unit)")

    def copy(self):
        out = ffi.new("bvox_volume **")
        check(lib.bvox_volume_copy(self._p, out))
        return Volume._own(out[0])

    __copy__ = copy

    # --------------------------------------------------------------- arrays
    @classmethod
    def from_numpy(cls, array, spacing=None, unit=None, origin=None, *, threshold=None,
                   range=None, label=None, nonzero=None, otsu=False):
        """A volume from a 3-D array indexed [x, y, z]: bool, any integer or
        float type. Voxels are set where the sample is nonzero (default), >=
        threshold, within range=(lo, hi), == label, or above Otsu's threshold.
        C- or Fortran-ordered arrays are read in place; others are copied
        once into C order first."""
        if not isinstance(array, np.ndarray):
            array = np.asarray(array)
        if array.ndim != 3:
            raise ValueError("bvox: from_numpy needs a 3-D array [x, y, z], got %d-D"
                             % array.ndim)
        if 0 in array.shape:
            raise ValueError("bvox: from_numpy: the array has a zero dimension %r"
                             % (array.shape,))
        dt = array.dtype
        if dt.byteorder not in ("=", "|") and dt.newbyteorder("=") in _DTYPES:
            array = array.astype(dt.newbyteorder("="))  # a byte-swapped file mapping
            dt = array.dtype
        if dt not in _DTYPES:
            raise TypeError("bvox: from_numpy: unsupported dtype %s (bool, integers, "
                            "float32 or float64)" % dt)
        if array.flags.c_contiguous:
            order = ORDER_Z_FASTEST
        elif array.flags.f_contiguous:
            order = ORDER_X_FASTEST
        else:
            array = np.ascontiguousarray(array)
            order = ORDER_Z_FASTEST
        how = _binarize(threshold, range, label, nonzero, otsu)
        out = ffi.new("bvox_volume **")
        check(lib.bvox_volume_from_samples(_buffer(array, "char[]"),
                                           _DTYPES[dt], array.shape, order, how, out))
        vol = Volume._own(out[0])
        if spacing is not None or unit is not None or origin is not None:
            vol.set_geometry(spacing=spacing, unit=unit, origin=origin)
        return vol

    def to_numpy(self, order="C"):
        """The voxels as a bool array [x, y, z] (order "C": z fastest, or "F"),
        written straight from the words: no other copy is made."""
        if order not in ("C", "F"):
            raise ValueError("bvox: to_numpy order is 'C' or 'F'")
        arr = np.empty(self.shape, dtype=np.bool_, order=order)
        check(lib.bvox_volume_to_bytes(self._p, ORDER_Z_FASTEST if order == "C"
                                       else ORDER_X_FASTEST, _buffer(arr, "uint8_t[]")))
        return arr

    def __array__(self, dtype=None):
        a = self.to_numpy()
        return a if dtype is None else a.astype(dtype)

    @property
    def words(self):
        """The packed words, zero-copy and read-only, indexed [x, y, w]: bit
        (z % 64) of words[x, y, z // 64] is voxel (x, y, z); bits beyond nz
        are zero. The view keeps the volume alive (close() is refused while
        it exists) and sees in-place changes (|=, edits, cuts)."""
        p = self._p
        v = lib.bvox_volume_words(p)
        nx, ny, _ = self.shape
        owner = _WordsOwner(self, int(ffi.cast("uintptr_t", v.words)), ny, nx,
                            int(v.words_per_column))
        self._views.add(owner)
        arr = np.asarray(owner).transpose(1, 0, 2)
        return arr

    @classmethod
    def from_words(cls, words, nz, spacing=None, unit=None, origin=None):
        """A volume from packed words indexed [x, y, w], as vol.words gives
        them (bit z % 64 of words[x, y, z // 64]), for nz slices; copied once
        into the new volume. Bits beyond nz must be zero (ValueError)."""
        w = np.asarray(words)
        if w.dtype != np.uint64:
            raise TypeError("bvox: from_words needs uint64 words, not %s" % w.dtype)
        if w.ndim != 3 or 0 in w.shape:
            raise ValueError("bvox: from_words needs a non-empty [x, y, w] array, got shape %r"
                             % (w.shape,))
        native = np.ascontiguousarray(w.transpose(1, 0, 2))  # the library's [y][x][w]
        out = ffi.new("bvox_volume **")
        check(lib.bvox_volume_from_words((w.shape[0], w.shape[1], int(nz)),
                                         _buffer(native, "uint64_t[]"), native.size, out))
        vol = Volume._own(out[0])
        if spacing is not None or unit is not None or origin is not None:
            vol.set_geometry(spacing=spacing, unit=unit, origin=origin)
        return vol

    def __reduce__(self):
        """Pickling (multiprocessing, Dask) as the packed words: one bit per
        voxel, plus the geometry."""
        g = self.geometry_dict()
        return (_unpickle, (np.array(self.words), self.shape[2], g["spacing"], g["unit"],
                            g["origin"], g["direction"]))

    # ------------------------------------------------------------- geometry
    @property
    def shape(self):
        d = lib.bvox_volume_dims(self._p)
        return (d.nx, d.ny, d.nz)

    def geometry_dict(self):
        g = lib.bvox_volume_geometry(self._p)
        return {"spacing": tuple(g.spacing), "origin": tuple(g.origin),
                "direction": np.array(list(g.direction)).reshape(3, 3),
                "unit": ffi.string(g.unit).decode("utf-8", "replace")}

    @property
    def spacing(self):
        return tuple(lib.bvox_volume_geometry(self._p).spacing)

    @property
    def unit(self):
        return ffi.string(lib.bvox_volume_geometry(self._p).unit).decode("utf-8", "replace")

    @property
    def origin(self):
        return tuple(lib.bvox_volume_geometry(self._p).origin)

    @property
    def direction(self):
        return np.array(list(lib.bvox_volume_geometry(self._p).direction)).reshape(3, 3)

    @property
    def affine(self):
        """The 4x4 voxel-to-world matrix (as nibabel's img.affine)."""
        a = np.eye(4)
        a[:3, :3] = self.direction * np.array(self.spacing)[None, :]
        a[:3, 3] = self.origin
        return a

    def set_geometry(self, spacing=None, unit=None, origin=None, direction=None):
        """Change the voxel size, unit, origin or direction (None: unchanged)."""
        g = ffi.new("bvox_geometry *", lib.bvox_volume_geometry(self._p)[0])
        if spacing is not None:
            g.spacing = _triple(spacing, "spacing")
        if origin is not None:
            g.origin = _triple(origin, "origin")
        if direction is not None:
            d = np.asarray(direction, dtype=float)
            if d.shape != (3, 3):
                raise ValueError("bvox: direction is a 3x3 matrix")
            g.direction = list(d.ravel())
        if unit is not None:
            u = unit.encode()
            if len(u) >= 16:
                raise ValueError("bvox: unit %r is too long (at most 15 bytes)" % unit)
            g.unit = u
        check(lib.bvox_volume_set_geometry(self._p, g))

    # ------------------------------------------------------------- contents
    def count(self):
        """Number of 1-voxels (a popcount over the words)."""
        return int(lib.bvox_volume_count(self._p))

    def bbox(self):
        """((x0, y0, z0), (x1, y1, z1)) inclusive voxel indices of the 1-voxels,
        or None when empty."""
        b = ffi.new("bvox_box *")
        if not lib.bvox_volume_bbox(self._p, b):
            return None
        return (b.x0, b.y0, b.z0), (b.x1 - 1, b.y1 - 1, b.z1 - 1)

    def check(self):
        """Verify the invariants (tail bits zero); raises FormatError if broken."""
        check(lib.bvox_volume_check(self._p))

    def __eq__(self, other):
        if not isinstance(other, Volume):
            return NotImplemented
        return bool(lib.bvox_volume_equal(self._p, other._p))

    __hash__ = None

    def __getitem__(self, xyz):
        x, y, z = (int(i) for i in xyz)
        return bool(lib.bvox_volume_get(self._p, x, y, z))

    def __setitem__(self, xyz, value):
        x, y, z = (int(i) for i in xyz)
        check(lib.bvox_edit_voxel(self._p, x, y, z, 1 if value else 0, ffi.NULL))

    def fill(self, value=True):
        lib.bvox_volume_fill(self._p, 1 if value else 0)
        return self

    # ------------------------------------------------------------ set algebra
    def _apply(self, op, other, offset):
        if not isinstance(other, Volume):
            raise TypeError("bvox: set operations take a bvox.Volume, not %s"
                            % type(other).__name__)
        off = ffi.NULL if offset is None else ffi.new("int32_t[3]", _triple(offset, "offset",
                                                                            int))
        check(lib.bvox_csg_apply(self._p, _OPS[op], other._p, off))
        return self

    def union(self, other, offset=None):
        """self | other, other's voxel (x, y, z) placed on (x, y, z) + offset."""
        return self.copy()._apply("union", other, offset)

    def intersection(self, other, offset=None):
        return self.copy()._apply("intersection", other, offset)

    def difference(self, other, offset=None):
        return self.copy()._apply("difference", other, offset)

    def xor(self, other, offset=None):
        return self.copy()._apply("xor", other, offset)

    def paste(self, other, offset=None):
        """In place: other's voxels replace self's where they overlap."""
        return self._apply("replace", other, offset)

    def __or__(self, other):
        return self.union(other) if isinstance(other, Volume) else NotImplemented

    def __and__(self, other):
        return self.intersection(other) if isinstance(other, Volume) else NotImplemented

    def __sub__(self, other):
        return self.difference(other) if isinstance(other, Volume) else NotImplemented

    def __xor__(self, other):
        return self.xor(other) if isinstance(other, Volume) else NotImplemented

    def __ior__(self, other):
        return self._apply("union", other, None)

    def __iand__(self, other):
        return self._apply("intersection", other, None)

    def __isub__(self, other):
        return self._apply("difference", other, None)

    def __ixor__(self, other):
        return self._apply("xor", other, None)

    def __invert__(self):
        c = self.copy()
        lib.bvox_volume_complement(c._p)
        return c

    def complement(self):
        """In place complement (bits beyond nz stay zero)."""
        lib.bvox_volume_complement(self._p)
        return self

    # ------------------------------------------------------ shapes and edits
    def draw(self, kind, op="union", *, center=None, radius=0.0, semi_axes=(0, 0, 0),
             axis=(0, 0, 1), minor_radius=0.0, height=0.0):
        """Combine a shape in physical units into the volume, in place: kind
        "sphere", "ellipsoid", "box" (semi_axes = half sizes), "cylinder",
        "cone", "torus"; op "union", "difference", "intersection", "xor".
        center defaults to the centre of the grid."""
        k = lib.bvox_shape_kind_parse(kind.encode())
        if k < 0:
            raise ValueError("bvox: unknown shape %r" % kind)
        s = ffi.new("bvox_shape *")
        s.kind = k
        if center is None:
            sp, org = self.spacing, self.origin
            center = [org[i] + (n - 1) * sp[i] / 2 for i, n in enumerate(self.shape)]
        s.center = _triple(center, "center")
        s.semi_axes = _triple(semi_axes, "semi_axes")
        s.axis = _triple(axis, "axis")
        s.radius, s.minor_radius, s.height = radius, minor_radius, height
        check(lib.bvox_shape_draw(self._p, s, _OPS[op]))
        return self

    def fill_box(self, lo, hi, value=True):
        """Set (or clear) the voxels lo <= (x, y, z) <= hi (inclusive), in place;
        returns the inclusive box of the voxels that changed, or None."""
        b = _box(lo, hi)
        changed = ffi.new("bvox_box *")
        check(lib.bvox_edit_fill_box(self._p, b[0], 1 if value else 0, changed))
        return _changed(changed)

    def keep_box(self, lo, hi):
        """Clear every voxel outside lo..hi (inclusive), in place."""
        changed = ffi.new("bvox_box *")
        check(lib.bvox_edit_keep_box(self._p, _box(lo, hi)[0], changed))
        return _changed(changed)

    def cut(self, plane, keep_above=True):
        """Cut in place by the world plane a x + b y + c z + d = 0 (plane =
        (a, b, c, d)); keeps the side a x + b y + c z + d >= 0 unless
        keep_above is False."""
        a, b, c, d = (float(v) for v in plane)
        changed = ffi.new("bvox_box *")
        check(lib.bvox_cut_plane(self._p, a, b, c, d, 1 if keep_above else 0, changed))
        return _changed(changed)

    def crop(self, lo, hi):
        """New volume of the inclusive box lo..hi; the origin moves so that
        voxels keep their world position."""
        out = ffi.new("bvox_volume **")
        check(lib.bvox_volume_crop(self._p, _box(lo, hi)[0], out))
        return Volume._own(out[0])

    def pad(self, before, after=None):
        after = before if after is None else after
        out = ffi.new("bvox_volume **")
        check(lib.bvox_volume_pad(self._p, ffi.new("int32_t[3]", _triple(before, "before", int)),
                                  ffi.new("int32_t[3]", _triple(after, "after", int)), out))
        return Volume._own(out[0])

    # ------------------------------------------------------------ morphology
    def _unary(self, fn, *args, progress=None):
        out = ffi.new("bvox_volume **")
        _progress.call(progress, fn, self._p, *args, out)
        return Volume._own(out[0])

    # progress=callable(fraction, stage) on each: see bvox._progress
    def dilate(self, conn=26, *, progress=None):
        """Dilation by the 6-, 18- or 26-neighbourhood (outside counts as 0)."""
        return self._unary(lib.bvox_morph_dilate, _conn(conn), progress=progress)

    def erode(self, conn=26, *, progress=None):
        """Erosion by the 6-, 18- or 26-neighbourhood; the border erodes, as
        scipy.ndimage.binary_erosion does by default."""
        return self._unary(lib.bvox_morph_erode, _conn(conn), progress=progress)

    def dilate_ball(self, radius, *, progress=None):
        """Dilation by a ball of that physical radius (an ellipsoid in voxels
        when the voxels are anisotropic)."""
        return self._unary(lib.bvox_morph_dilate_ball, float(radius), progress=progress)

    def erode_ball(self, radius, *, progress=None):
        return self._unary(lib.bvox_morph_erode_ball, float(radius), progress=progress)

    def opening(self, conn=26, radius=0.0, *, progress=None):
        """Erode then dilate (a ball of radius when > 0, else conn). Named
        opening/closing because close() releases the volume."""
        return self._unary(lib.bvox_morph_open, _conn(conn), float(radius), progress=progress)

    def closing(self, conn=26, radius=0.0, *, progress=None):
        """Dilate then erode, on a padded copy so the border does not eat in."""
        return self._unary(lib.bvox_morph_close, _conn(conn), float(radius), progress=progress)

    def fill_holes(self, *, progress=None):
        return self._unary(lib.bvox_morph_fill_holes, progress=progress)

    def hollow(self, thickness, *, progress=None):
        return self._unary(lib.bvox_morph_hollow, float(thickness), progress=progress)

    def remove_islands(self, min_voxels, conn=26, *, progress=None):
        return self._unary(lib.bvox_morph_remove_islands, _conn(conn), int(min_voxels),
                           progress=progress)

    # ------------------------------------------------------------- measures
    def components(self, conn=26, *, progress=None):
        """(labels, comps): labels a uint32 array [x, y, z] (0 background,
        i + 1 for component i, largest first), comps a list of dicts with the
        keys of `bvox components --json`: voxels, volume, bbox {min, max}
        (inclusive voxel indices)."""
        from ._measure import component_dicts
        out = ffi.new("bvox_components **")
        _progress.call(progress, lib.bvox_components_find, self._p, _conn(conn), out)
        comps = ffi.gc(out[0], lib.bvox_components_destroy)
        nx, ny, nz = self.shape
        labels = np.empty((nz, ny, nx), dtype=np.uint32)  # x fastest in memory
        lib.bvox_components_labels(comps, _buffer(labels, "uint32_t[]"))
        result = component_dicts(comps)
        ffi.release(comps)
        return labels.transpose(2, 1, 0), result

    def largest_components(self, n=1, conn=26):
        """A volume holding the n largest conn-components."""
        out = ffi.new("bvox_components **")
        check(lib.bvox_components_find(self._p, _conn(conn), out))
        comps = ffi.gc(out[0], lib.bvox_components_destroy)
        res = ffi.new("bvox_volume **")
        check(lib.bvox_components_keep(comps, int(n), res))
        ffi.release(comps)
        return Volume._own(res[0])

    def measure(self, *, progress=None):
        """All measures as a dict with the keys of `bvox measure --json`."""
        from ._measure import measure_dict
        return measure_dict(self, progress=progress)

    def measure_components(self, conn=26):
        """measure() of every conn-component alone, largest first (the order
        of components()); bbox in this volume's voxel indices."""
        from ._measure import measure_components
        return measure_components(self, _conn(conn))

    # ------------------------------------------------------------ render, mesh
    def render(self, view="iso", **kw):
        """An (h, w, 3) uint8 image; see bvox.render for the options."""
        from ._render import render
        return render(self, view, **kw)

    def mesh(self, method="mc", smooth=0, *, progress=None):
        """(vertices, faces): a float64 (n, 3) array in physical units and an
        int32 (m, 3) array of vertex indices; "mc" (marching cubes, closed
        2-manifold) or "cuberille" (voxel faces); smooth: Taubin iterations."""
        from ._mesh import mesh_from_volume
        return mesh_from_volume(self, method, smooth, progress=progress)

    def contours(self, axis=2):
        """The outlines of every slice across axis (0 x, 1 y, 2 z): a
        bvox.Contours (list of sections with (n, 2) point arrays in pixels,
        holes marked); .to_volume() rebuilds the model, .write() saves it."""
        from ._recon import volume_contours
        return volume_contours(self, axis)

    def write(self, path, format=None, *, progress=None):
        """Write to a file (format by the extension unless given): through a
        temporary file renamed on success, never a partial file."""
        opts = ffi.new("bvox_write_opts *")
        keep = cstr(format) if format else ffi.NULL
        opts.format = keep
        opts.raw_bits = 8
        _progress.call(progress, lib.bvox_write, os.fsencode(path), self._p, opts)

    def write_labels(self, path, labels):
        """Write a label array [x, y, z] (as components() returns) as NIfTI
        with this volume's geometry."""
        labels = np.asarray(labels)
        if labels.shape != self.shape:
            raise ValueError("bvox: labels shape %r differs from the volume's %r"
                             % (labels.shape, self.shape))
        xf = np.asfortranarray(labels, dtype=np.uint32)
        check(lib.bvox_write_labels_nifti(os.fsencode(path), self._p,
                                          _buffer(xf, "uint32_t[]")))


def _unpickle(words, nz, spacing, unit, origin, direction):
    vol = Volume.from_words(words, nz)
    vol.set_geometry(spacing=spacing, unit=unit, origin=origin, direction=direction)
    return vol


class _WordsOwner:
    """Exposes a volume's words to NumPy (__array_interface__) and keeps the
    volume alive as long as any array made from it."""

    __slots__ = ("vol", "__array_interface__", "__weakref__")

    def __init__(self, vol, address, ny, nx, wpc):
        self.vol = vol
        self.__array_interface__ = {"shape": (ny, nx, wpc), "typestr": "<u8",
                                    "data": (address, True), "version": 3}


def _buffer(array, ctype):
    """A C pointer into a C- or Fortran-contiguous array's memory (no copy):
    cffi takes a flat view of it in memory order."""
    return ffi.from_buffer(ctype, array.reshape(-1, order="A"))


def _dims(shape):
    try:
        nx, ny, nz = (int(s) for s in shape)
    except (TypeError, ValueError):
        raise ValueError("bvox: shape must be (nx, ny, nz), got %r" % (shape,)) from None
    return nx, ny, nz


def _box(lo, hi):
    lo = _triple(lo, "lo", int)
    hi = _triple(hi, "hi", int)
    return ffi.new("bvox_box[1]", [(lo[0], lo[1], lo[2], hi[0] + 1, hi[1] + 1, hi[2] + 1)])


def _changed(b):
    if b.x1 <= b.x0 or b.y1 <= b.y0 or b.z1 <= b.z0:
        return None
    return (b.x0, b.y0, b.z0), (b.x1 - 1, b.y1 - 1, b.z1 - 1)
