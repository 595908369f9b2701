"""_recon.py — contour stacks and reconstruction from serial sections, with
sections as plain Python data: a list of dicts {"z": position, "name": str or
None, "contours": [{"points": (n, 2) float array in pixels, "hole": bool,
"parent": int}], "markers": (k, 2) array}, the stack's pixel size, section
spacing, unit and origin kept in a Contours object."""
import os

import numpy as np

from ._lib import check, cstr, ffi, lib


class Contours(list):
    """A list of sections (dicts, see the module) plus the stack's geometry:
    pixel, spacing, unit, width, height, origin."""

    def __init__(self, sections=(), pixel=1.0, spacing=1.0, unit="", width=0, height=0,
                 origin=(0.0, 0.0)):
        super().__init__(sections)
        self.pixel, self.spacing, self.unit = float(pixel), float(spacing), unit
        self.width, self.height, self.origin = int(width), int(height), tuple(origin)

    def __repr__(self):
        n = sum(len(s["contours"]) for s in self)
        return "<bvox.Contours %d sections, %d contours, pixel %g %s>" % (
            len(self), n, self.pixel, self.unit or "(no unit)")

    def to_volume(self, z_spacing=0.0, interpolate=True, margin=1):
        """Scan-convert (even-odd, holes kept) into a bvox.Volume with slices
        z_spacing apart (0: isotropic), shape-based interpolation between
        sections (interpolate) or nearest section."""
        from ._volume import Volume
        stack = _to_stack(self)
        opts = ffi.new("bvox_stack_volume_opts *", lib.bvox_stack_volume_opts_default())
        opts.z_spacing, opts.interpolate, opts.margin = float(z_spacing), int(bool(interpolate)), \
            int(margin)
        out = ffi.new("bvox_volume **")
        try:
            check(lib.bvox_stack_to_volume(stack, opts, out))
        finally:
            ffi.release(stack)
        return Volume._own(out[0])

    def write(self, path):
        """A JSON stack file (path ending .json) or a folder of SVG files."""
        stack = _to_stack(self)
        try:
            p = os.fsencode(path)
            if str(path).endswith(".json"):
                check(lib.bvox_stack_write_json(p, stack))
            else:
                check(lib.bvox_stack_write_svg_dir(p, stack))
        finally:
            ffi.release(stack)


def _points(p, n):
    return np.frombuffer(ffi.buffer(p, n * 16), dtype=np.float64).reshape(n, 2).copy() \
        if n else np.zeros((0, 2))


def _from_stack(st):
    c = Contours(pixel=st.pixel, spacing=st.spacing,
                 unit=ffi.string(st.unit).decode("utf-8", "replace"), width=st.width,
                 height=st.height, origin=tuple(st.origin))
    for i in range(st.nsections):
        s = st.sections[i]
        c.append({"z": s.z, "name": ffi.string(s.name).decode("utf-8", "replace")
                  if s.name != ffi.NULL else None,
                  "contours": [{"points": _points(s.contours[k].points, s.contours[k].npoints),
                                "hole": bool(s.contours[k].hole),
                                "parent": s.contours[k].parent} for k in range(s.ncontours)],
                  "markers": _points(s.markers, s.nmarkers)})
    return c


def _to_stack(c):
    out = ffi.new("bvox_contour_stack **")
    check(lib.bvox_stack_create(out))
    st = ffi.gc(out[0], lib.bvox_stack_destroy)
    u = (getattr(c, "unit", "") or "").encode()
    if len(u) >= 16:
        raise ValueError("bvox: unit %r is too long" % c.unit)
    st.unit = u
    st.pixel, st.spacing = getattr(c, "pixel", 1.0), getattr(c, "spacing", 1.0)
    st.width, st.height = getattr(c, "width", 0), getattr(c, "height", 0)
    st.origin = list(getattr(c, "origin", (0.0, 0.0)))
    for s in c:
        sec = ffi.new("bvox_section **")
        name = cstr(s["name"]) if s.get("name") else ffi.NULL
        check(lib.bvox_stack_add_section(st, float(s["z"]), name, sec))
        for k in s.get("contours", ()):
            pts = np.ascontiguousarray(k["points"], dtype=np.float64)
            if pts.ndim != 2 or pts.shape[1] != 2:
                raise ValueError("bvox: contour points must be an (n, 2) array")
            check(lib.bvox_section_add_contour(
                sec[0], ffi.cast("bvox_point2 *", ffi.from_buffer(pts)), len(pts),
                1 if k.get("hole") else 0, int(k.get("parent", -1))))
        for m in np.asarray(s.get("markers", np.zeros((0, 2))), dtype=float).reshape(-1, 2):
            check(lib.bvox_section_add_marker(sec[0], (float(m[0]), float(m[1]))))
    return st


def volume_contours(vol, axis=2):
    """The boundaries of every slice across axis (0 x, 1 y, 2 z) as Contours."""
    if axis not in (0, 1, 2):
        raise ValueError("bvox: axis is 0, 1 or 2")
    out = ffi.new("bvox_contour_stack **")
    check(lib.bvox_volume_to_contours(vol._p, axis, out))
    st = ffi.gc(out[0], lib.bvox_stack_destroy)
    c = _from_stack(st)
    ffi.release(st)
    return c


def read_contours(path):
    """A contour stack file: JSON, a folder of SVG, Reconstruct's XML series."""
    out = ffi.new("bvox_contour_stack **")
    check(lib.bvox_stack_read(os.fsencode(path), out))
    st = ffi.gc(out[0], lib.bvox_stack_destroy)
    c = _from_stack(st)
    ffi.release(st)
    return c


def _image(a):
    a = np.asarray(a)
    if a.dtype != np.uint8:
        raise TypeError("bvox: section images must be uint8, not %s" % a.dtype)
    if a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] not in (1, 3)) or 0 in a.shape:
        raise ValueError("bvox: a section image is (h, w) or (h, w, 3), got %r" % (a.shape,))
    ch = 1 if a.ndim == 2 else a.shape[2]
    out = ffi.new("bvox_image **")
    check(lib.bvox_image_create(a.shape[1], a.shape[0], ch, 8, out))
    img = ffi.gc(out[0], lib.bvox_image_destroy)
    ffi.memmove(img.pixels, np.ascontiguousarray(a).tobytes(), a.size)
    return img


def reconstruct(inputs, *, threshold=None, dark=True, smooth=1, min_area=16, background=None,
                estimate_background=True, markers=0, align=True, pixel=0.0, spacing=0.0,
                unit="", z_spacing=0.0, interpolate=True, contour_smooth=0, simplify=0.0,
                progress=None, contours=False):
    """Serial sections -> model, as `bvox reconstruct`. inputs: a folder of
    section images, a list of image paths, a contour stack file, or a list of
    uint8 NumPy images (h, w) / (h, w, 3) in stack order. threshold None:
    Otsu per section; dark: the object is darker than the background;
    smooth: median radius; min_area: specks and holes removed (pixels);
    markers: reference markers to find per section (0: none); pixel, spacing,
    unit: the geometry; z_spacing: output slices (0: isotropic). progress:
    a callable(step_name, done, total). Returns the Volume, or (Volume,
    Contours) with contours=True."""
    from ._volume import Volume
    opts = ffi.new("bvox_recon_opts *", lib.bvox_recon_opts_default())
    keep = []
    if background is not None:
        keep.append(cstr(background))
        opts.background = keep[-1]
    opts.estimate_background = int(bool(estimate_background))
    opts.threshold = -1.0 if threshold is None else float(threshold)
    opts.dark = int(bool(dark))
    opts.smooth, opts.min_area = int(smooth), int(min_area)
    opts.markers.count = int(markers)
    opts.align = int(bool(align))
    opts.pixel, opts.spacing = float(pixel), float(spacing)
    u = unit.encode()
    if len(u) >= 16:
        raise ValueError("bvox: unit %r is too long" % unit)
    opts.unit = u
    opts.z_spacing, opts.interpolate = float(z_spacing), int(bool(interpolate))
    opts.contour_smooth, opts.simplify = int(contour_smooth), float(simplify)
    errors = []
    if progress is not None:
        @ffi.callback("void(void *, bvox_recon_step, int32_t, int32_t)")
        def cb(ctx, step, done, total):
            try:
                progress(ffi.string(lib.bvox_recon_step_name(step)).decode(), done, total)
            except Exception as e:  # never across C; raised after the call
                errors.append(e)
        keep.append(cb)
        opts.progress = cb
    vol = ffi.new("bvox_volume **")
    stack = ffi.new("bvox_contour_stack **") if contours else ffi.NULL
    if isinstance(inputs, (str, bytes, os.PathLike)):
        inputs = [inputs]
    inputs = list(inputs)
    if inputs and all(isinstance(i, np.ndarray) for i in inputs):
        imgs = [_image(a) for a in inputs]
        arr = ffi.new("bvox_image *[]", imgs)
        status = lib.bvox_reconstruct_images(arr, ffi.NULL, len(imgs), opts, vol, stack,
                                             ffi.NULL)
    else:
        paths = [cstr(p) for p in inputs]
        arr = ffi.new("char *[]", paths)
        status = lib.bvox_reconstruct(arr, len(paths), opts, vol, stack, ffi.NULL)
    if errors:
        if status == 0:
            lib.bvox_volume_destroy(vol[0])
            if contours:
                lib.bvox_stack_destroy(stack[0])
        raise errors[0]
    check(status)
    v = Volume._own(vol[0])
    if not contours:
        return v
    st = ffi.gc(stack[0], lib.bvox_stack_destroy)
    c = _from_stack(st)
    ffi.release(st)
    return v, c
