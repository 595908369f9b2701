"""_render.py — the display pipeline (cast, shade, zoom, filter, cut) into an
(h, w, 3) uint8 NumPy array, and PNG output of such arrays."""
import os

import numpy as np

from ._lib import InvalidArgument, check, ffi, lib


def _image_to_numpy(img):
    """(h, w, 3) uint8, or (h, w, 4) for a transparent background."""
    h, w, ch = img.height, img.width, img.channels
    a = np.frombuffer(ffi.buffer(img.pixels, h * w * ch), dtype=np.uint8).reshape(h, w, ch)
    a = a.copy()
    return np.repeat(a, 3, axis=2) if ch == 1 else a


def _rgb(color):
    """(r, g, b) from "#rrggbb", "#rgb" or three 0..255 integers."""
    if isinstance(color, str):
        c = color.lstrip("#")
        if color.startswith("#") and len(c) in (3, 6) and all(
                ch in "0123456789abcdefABCDEF" for ch in c):
            if len(c) == 3:
                c = "".join(ch * 2 for ch in c)
            return tuple(int(c[i:i + 2], 16) for i in (0, 2, 4))
        raise ValueError("bvox: a colour is '#rrggbb', '#rgb' or (r, g, b), not %r" % color)
    t = tuple(int(v) for v in color)
    if len(t) != 3 or not all(0 <= v <= 255 for v in t):
        raise ValueError("bvox: a colour is three values 0..255, not %r" % (color,))
    return t


def _annotate(opts, color, background, scale_bar, axes, title, keep):
    """The colour and annotation fields of bvox_render_opts (issue 18)."""
    if color is not None:
        opts.color_set = 1
        opts.color = list(_rgb(color))
    if background is not None:
        if background == "transparent":
            opts.transparent = 1
        else:
            opts.background = list(_rgb(background))
    opts.scale_bar = 1 if scale_bar else 0
    opts.axes = 1 if axes else 0
    if title is not None:
        keep.append(ffi.new("char[]", str(title).encode()))
        opts.title = keep[-1]


def render(vol, view="iso", *, shade="binary+depth", width=0, height=0, scale=0.0, zoom=1,
           average=False, filter=None, cut=None, keep_above=True, light=None, path=None,
           smooth_radius=0, ao=False, shadows=False, supersample=1, color=None,
           background=None, scale_bar=False, axes=False, title=None):
    """Render a volume. view: "+z", "-x", ... (one pixel per voxel column),
    "iso", "iso+x-y+z" or "AZ,EL" degrees (a parallel projection of
    width x height pixels, 512 when 0, scaled to fit unless scale, pixels per
    unit, is given); shade "depth", "binary", "gradient", "binary+depth",
    "smooth" (normals from the occupancy around the hit voxel, over a ball of
    smooth_radius 1..3, 0: 2), "binary-preimage", "enlarged-gradient" (the
    paper's pre-image operators; the latter doubles the size); ao, shadows:
    ambient occlusion and cast shadows; supersample N (1..4): N x N rays a
    pixel, averaged (an axis view becomes a projection);
    zoom 1/2/4/8; average: a further x2 with pixel averaging; filter
    "highpass", "smooth", "laplacian", "sobel"; cut (a, b, c, d): the plane
    a x + b y + c z + d = 0, keeping the side >= 0 (keep_above) with its cut
    face tinted; light (azimuth, elevation) in degrees; color ("#rrggbb" or
    (r, g, b)) for the object (its cut face a lighter tone); background a
    colour or "transparent" (then an (h, w, 4) RGBA array); scale_bar, axes
    and title annotate the picture. With path, also written as PNG. Returns
    an (h, w, 3) uint8 array."""
    opts, keep = _opts(view, shade, width, height, scale, zoom, average, filter, cut,
                       keep_above, light, smooth_radius, ao, shadows, supersample)
    _annotate(opts, color, background, scale_bar, axes, title, keep)
    out = ffi.new("bvox_image **")
    check(lib.bvox_render(vol._p, opts, out, ffi.NULL))
    return _finish(out, path)


def render_objects(vols, colors, view="iso", *, path=None, background=None, scale_bar=False,
                   axes=False, title=None, **kw):
    """Several volumes of one grid in one picture, each in its colour
    (colors: one "#rrggbb" or (r, g, b) per volume), composited by depth;
    the other options as for render. Returns an (h, w, 3) uint8 array."""
    vols = list(vols)
    cols = [_rgb(c) for c in colors]
    if not vols or len(cols) != len(vols):
        raise ValueError("bvox: render_objects needs one colour per volume (%d volumes, "
                         "%d colours)" % (len(vols), len(cols)))
    opts, keep = _opts(view, **kw)
    _annotate(opts, None, background, scale_bar, axes, title, keep)
    ptrs = ffi.new("bvox_volume *[]", [v._p for v in vols])
    carr = ffi.new("uint8_t[][3]", cols)
    out = ffi.new("bvox_image **")
    check(lib.bvox_render_objects(ptrs, carr, len(vols), opts, out))
    return _finish(out, path)


def _finish(out, path):
    img = ffi.gc(out[0], lib.bvox_image_destroy)
    if path is not None:
        check(lib.bvox_image_write_png(img, os.fsencode(path)))
    arr = _image_to_numpy(img)
    ffi.release(img)
    return arr


def _opts(view, shade="binary+depth", width=0, height=0, scale=0.0, zoom=1, average=False,
          filter=None, cut=None, keep_above=True, light=None, smooth_radius=0, ao=False,
          shadows=False, supersample=1):
    opts = ffi.new("bvox_render_opts *", lib.bvox_render_opts_default())
    check(lib.bvox_render_parse_view(str(view).encode(), opts))
    s = lib.bvox_shade_mode_parse(shade.encode())
    if s < 0:
        raise ValueError("bvox: unknown shading %r" % shade)
    opts.shade = s
    # an axis view given a size becomes the projection with the same image
    # axes (bvox_render_opts)
    opts.proj.width, opts.proj.height = int(width), int(height)
    opts.proj.scale = float(scale)
    opts.zoom = int(zoom)
    opts.average = 1 if average else 0
    if filter is not None:
        f = lib.bvox_filter_parse(filter.encode())
        if f < 0:
            raise ValueError("bvox: unknown filter %r" % filter)
        opts.filter = f
    if cut is not None:
        opts.cut = 1
        opts.plane = [float(v) for v in cut]
        opts.keep_above = 1 if keep_above else 0
    if light is not None:
        opts.light.azimuth, opts.light.elevation = (float(v) for v in light)
    opts.smooth_radius = int(smooth_radius)
    opts.ao = 1 if ao else 0
    opts.shadows = 1 if shadows else 0
    opts.supersample = int(supersample)
    return opts, []


def write_png(path, image):
    """Write an (h, w) gray or (h, w, 3) RGB uint8 array as PNG (through a
    temporary file renamed on success)."""
    a = np.asarray(image)
    if a.dtype != np.uint8:
        raise TypeError("bvox: write_png needs uint8 samples, not %s" % a.dtype)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 3) or 0 in a.shape:
        raise ValueError("bvox: write_png needs an (h, w) or (h, w, 3) array, got %r"
                         % (a.shape,))
    out = ffi.new("bvox_image **")
    check(lib.bvox_image_create(a.shape[1], a.shape[0], a.shape[2], 8, out))
    img = ffi.gc(out[0], lib.bvox_image_destroy)
    ffi.memmove(img.pixels, np.ascontiguousarray(a).tobytes(), a.size)
    try:
        check(lib.bvox_image_write_png(img, os.fsencode(path)))
    finally:
        ffi.release(img)
