#!/usr/bin/python3
"""compare_vtk.py — the same meshing and voxelization as bench_mesh.c, done
with VTK and scikit-image, on the very volumes and mesh the bench wrote
(bench_mesh --save DIR writes DIR/<pattern>_<n>.nii, uint8 0/1, and
DIR/bunny.stl), so every tool sees the same voxels.

    bench_mesh --save DIR > DIR/bvox.jsonl     (or: bench_mesh --peers)
    /usr/bin/python3 bench/compare_vtk.py DIR [--bench DIR/bvox.jsonl] [--runs N] [--threads T]

Prints one JSON line per tool, volume and operation:
  peer "vtk_discrete_flying_edges": vtkDiscreteFlyingEdges3D, label 1 (op "mc");
  peer "vtk_flying_edges":          vtkFlyingEdges3D at 0.5 (op "mc");
  peer "skimage":                   skimage.measure.marching_cubes at 0.5 (op "mc");
  peer "vtk_stencil":               vtkPolyDataToImageStencil + vtkImageStencil on
                                    the bvox grid of the bunny (op "voxelize").
Each line has the peer's median of `runs` runs after a warm-up ("peer_ms";
scikit-image at n >= 512 runs once), its triangle or voxel count, and with
--bench bvox's median from the bench's line of the same op, n and pattern
("bvox_ms") and "speedup" = peer_ms / bvox_ms. VTK runs with T threads
(vtkSMPTools, default 2); scikit-image on one. Needs numpy, vtk, skimage
(Debian: python3-vtk9 python3-skimage; run with /usr/bin/python3 if another
python3 comes first in PATH); a missing package skips its lines with a note.
"""
import argparse
import glob
import json
import math
import os
import re
import sys

try:
    import numpy as np
except ImportError as e:
    sys.exit("compare_vtk.py: %s (apt-get install python3-numpy; use /usr/bin/python3)" % e)
try:
    import vtk
    from vtk.util import numpy_support
except ImportError as e:
    vtk = None
    print("compare_vtk.py: no VTK (%s): apt-get install python3-vtk9" % e, file=sys.stderr)
try:
    from skimage import measure as skmeasure
except ImportError as e:
    skmeasure = None
    print("compare_vtk.py: no scikit-image (%s): apt-get install python3-skimage" % e,
          file=sys.stderr)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # compare_common, from any cwd
from compare_common import bench_by_op, read_nifti_u8, timed  # noqa: E402


def vtk_image(a):
    nz, ny, nx = a.shape
    img = vtk.vtkImageData()
    img.SetDimensions(nx, ny, nz)
    arr = numpy_support.numpy_to_vtk(a.ravel(), deep=1, array_type=vtk.VTK_UNSIGNED_CHAR)
    img.GetPointData().SetScalars(arr)
    return img


def vtk_mc(img, discrete):
    f = vtk.vtkDiscreteFlyingEdges3D() if discrete else vtk.vtkFlyingEdges3D()
    f.SetInputData(img)
    f.SetValue(0, 1 if discrete else 0.5)
    if not discrete:
        f.ComputeNormalsOff()
        f.ComputeGradientsOff()
    f.ComputeScalarsOff()
    f.Update()
    return f.GetOutput().GetNumberOfPolys()


def vtk_voxelize(stl, n):
    """The bunny on the grid bvox_mesh_voxelize uses at res n."""
    r = vtk.vtkSTLReader()
    r.SetFileName(stl)
    r.Update()
    poly = r.GetOutput()
    b = poly.GetBounds()
    lo, hi = [b[0], b[2], b[4]], [b[1], b[3], b[5]]
    ext = [h - l for l, h in zip(lo, hi)]
    s = max(ext) / n
    dims = [max(1, math.ceil(e / s - 1e-9)) for e in ext]
    origin = [l + 0.5 * (e - d * s) + 0.5 * s for l, e, d in zip(lo, ext, dims)]

    def run():
        img = vtk.vtkImageData()
        img.SetDimensions(*dims)
        img.SetSpacing(s, s, s)
        img.SetOrigin(*origin)
        img.AllocateScalars(vtk.VTK_UNSIGNED_CHAR, 1)
        img.GetPointData().GetScalars().Fill(1)
        st = vtk.vtkPolyDataToImageStencil()
        st.SetInputData(poly)
        st.SetOutputOrigin(*origin)
        st.SetOutputSpacing(s, s, s)
        st.SetOutputWholeExtent(img.GetExtent())
        sten = vtk.vtkImageStencil()
        sten.SetInputData(img)
        sten.SetStencilConnection(st.GetOutputPort())
        sten.ReverseStencilOff()
        sten.SetBackgroundValue(0)
        sten.Update()
        out = numpy_support.vtk_to_numpy(sten.GetOutput().GetPointData().GetScalars())
        return int(np.count_nonzero(out))

    return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", help="folder where bench_mesh --save wrote its files")
    ap.add_argument("--bench", help="bench_mesh's output (JSON lines) to compare with")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()

    bvox = bench_by_op(args.bench) if args.bench and os.path.exists(args.bench) else {}
    if vtk is not None:
        vtk.vtkSMPTools.Initialize(args.threads)

    def report(peer, op, pattern, n, ms, count, key, runs, threads):
        o = {"peer": peer, "op": op, "pattern": pattern, "n": n, "peer_ms": round(ms, 3),
             "runs": runs, "threads": threads, key: count}
        b = bvox.get((op, n, pattern))
        if b:
            o["bvox_ms"] = b["ms"]
            o["bvox_threads"] = b.get("threads")
            o["bvox_" + key] = b.get(key, b.get("voxels"))
            o["speedup"] = round(ms / b["ms"], 2) if b["ms"] > 0 else None
        print(json.dumps(o), flush=True)

    files = sorted(glob.glob(os.path.join(args.dir, "*_*.nii")),
                   key=lambda p: (int(re.search(r"_(\d+)\.nii$", p).group(1)), p))
    for path in files:
        m = re.match(r"(\w+?)_(\d+)\.nii$", os.path.basename(path))
        if not m:
            continue
        pattern, n = m.group(1), int(m.group(2))
        a = read_nifti_u8(path)
        if vtk is not None:
            img = vtk_image(a)
            for peer, disc in (("vtk_discrete_flying_edges", True), ("vtk_flying_edges", False)):
                ms, nt = timed(args.runs, lambda: vtk_mc(img, disc))
                report(peer, "mc", pattern, n, ms, nt, "triangles", args.runs, args.threads)
        if skmeasure is not None:
            f = a.astype(np.float32)
            runs = 1 if n >= 512 else args.runs
            ms, res = timed(runs, lambda: skmeasure.marching_cubes(f, 0.5))
            report("skimage", "mc", pattern, n, ms, len(res[1]), "triangles", runs, 1)
        if vtk is not None and pattern == "bunny":
            stl = os.path.join(args.dir, "bunny.stl")
            if os.path.exists(stl):
                ms, cnt = timed(args.runs, vtk_voxelize(stl, n))
                report("vtk_stencil", "voxelize", "bunny", n, ms, cnt, "voxels", args.runs,
                       args.threads)


if __name__ == "__main__":
    main()
