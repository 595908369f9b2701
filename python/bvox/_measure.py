"""_measure.py — measures and components as dicts with exactly the keys of the
command's JSON output (`bvox measure --json`, `bvox components --json`), so a
script and a shell pipeline read the same names. Bounding boxes are inclusive
voxel indices, as there; "file" and "format" (the command's input) are left
out: a volume in memory has neither.
"""
import math

from ._lib import check, ffi, lib

# factor from unit^3 to mm^3 (cli/report.c), None for an unknown unit
_MM = {"nm": 1e-6, "um": 1e-3, "\u00b5m": 1e-3, "micron": 1e-3, "mm": 1.0, "cm": 10.0,
       "m": 1e3}


def _unit_power(unit, spacing, power):
    if unit:
        return "%s^%d" % (unit, power)
    if tuple(spacing) == (1.0, 1.0, 1.0):
        return "voxel^%d" % power
    return "units^%d" % power


def _bbox(b):
    return {"min": [b.x0, b.y0, b.z0], "max": [b.x1 - 1, b.y1 - 1, b.z1 - 1]}


def _bbox_physical(b, g):
    """World bounds of the bbox's voxels (their outer faces), min/max over the
    eight corners through the direction matrix, as the command computes them."""
    lo_i = (b.x0 - 0.5, b.y0 - 0.5, b.z0 - 0.5)
    hi_i = (b.x1 - 0.5, b.y1 - 0.5, b.z1 - 0.5)
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for c in range(8):
        p = [(hi_i[k] if (c >> k) & 1 else lo_i[k]) * g.spacing[k] for k in range(3)]
        for a in range(3):
            w = g.origin[a] + sum(g.direction[a * 3 + k] * p[k] for k in range(3))
            lo[a], hi[a] = min(lo[a], w), max(hi[a], w)
    return {"min": lo, "max": hi}


def _matrix(v):
    return [list(v[0:3]), list(v[3:6]), list(v[6:9])]


def measure_dict(vol, progress=None):
    from ._progress import call
    p = vol._p
    m = ffi.new("bvox_measures *")
    call(progress, lib.bvox_measure, p, m)
    return _as_dict(vol, m)


def measure_components(vol, conn):
    """One measure dict per conn-component, largest first; each measured
    alone (bbox in the volume's indices, components 1)."""
    arr = ffi.new("bvox_measures **")
    n = ffi.new("int64_t *")
    check(lib.bvox_measure_components(vol._p, conn, arr, n))
    items = ffi.gc(arr[0], lib.bvox_free) if arr[0] != ffi.NULL else None
    out = [_as_dict(vol, items[i]) for i in range(n[0])]
    if items is not None:
        ffi.release(items)
    return out


def _as_dict(vol, m):
    p = vol._p
    g = lib.bvox_volume_geometry(p)
    unit = ffi.string(g.unit).decode("utf-8", "replace")
    d = lib.bvox_volume_dims(p)
    empty = m.count == 0
    k = _MM.get(unit)
    return {
        "dims": [d.nx, d.ny, d.nz],
        "voxel_size": list(g.spacing),
        "spacing": list(g.spacing),
        "unit": unit,
        "origin": list(g.origin),
        "count": m.count,
        "voxels": m.count,
        "volume": m.volume,
        "volume_unit": _unit_power(unit, g.spacing, 3),
        "volume_mm3": m.volume * k ** 3 if k else None,
        "bbox": None if empty else _bbox(m.bbox),
        "bbox_physical": None if empty else _bbox_physical(m.bbox, g),
        "surface_area": m.area,
        "surface_area_faces": m.area_faces,
        "area_unit": _unit_power(unit, g.spacing, 2),
        "faces": list(m.faces),
        "centroid": None if empty else list(m.centroid),
        "principal_axes": None if empty else _matrix(m.principal_axes),
        "principal_moments": list(m.principal_moments),
        "principal_inertia": list(m.principal_inertia),
        "covariance": _matrix(m.covariance),
        "inertia": _matrix(m.inertia),
        "equivalent_diameter": m.equivalent_diameter,
        "sphericity": None if empty else m.sphericity,
        "components": m.components,
        "component_count": m.components,
        "cavities": m.cavities,
        "cavities_6": m.cavities,
        "cavities_26": m.cavities_26,
        "tunnels": m.tunnels,
        "euler": m.euler,
    }


def component_dicts(comps):
    n = lib.bvox_components_count(comps)
    out = []
    for i in range(n):
        c = lib.bvox_components_get(comps, i)
        out.append({"voxels": c.voxels, "volume": c.volume, "bbox": _bbox(c.bbox)})
    return out
