#!/usr/bin/env python3
"""atlas_region.py — one region of a brain atlas: read it, measure it, mesh
it and render it, with the bvox Python package.

    python3 examples/python/atlas_region.py [ATLAS] [LABEL] [-o OUTDIR]

Defaults: Debian's mricron-data AAL atlas and label 37 (Hippocampus_L, as
named in aal.nii.txt beside it). Writes OUTDIR/region.stl (the marching-cubes
surface) and OUTDIR/region.png (an isometric view) and prints the measures.
From a build tree: BVOX_LIBRARY=build/libbvox.so.0 PYTHONPATH=python python3 ...
"""
import argparse
import os

import bvox


def region_name(atlas, label):
    """The label's name from the atlas's text table ("37 Hippocampus_L 4101")."""
    table = atlas.replace(".nii.gz", ".nii.txt")
    if os.path.exists(table):
        with open(table) as f:
            for line in f:
                parts = line.split()
                if len(parts) >= 2 and parts[0] == str(label):
                    return parts[1]
    return "label %d" % label


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("atlas", nargs="?", default="/usr/share/mricron/templates/aal.nii.gz")
    ap.add_argument("label", nargs="?", type=int, default=37)
    ap.add_argument("-o", "--outdir", default=".")
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)

    region = bvox.read(args.atlas, label=args.label)  # a binary volume of that label
    m = region.measure()                              # the keys of `bvox measure --json`
    unit = m["unit"] or "voxel"
    print("%s (%s): %d voxels of %s %s" % (region_name(args.atlas, args.label), args.atlas,
                                           m["count"], " x ".join("%g" % s for s in
                                                                  m["voxel_size"]), unit))
    ml = "" if m["volume_mm3"] is None else " (%.3f ml)" % (m["volume_mm3"] / 1000)
    print("volume      %.1f %s%s" % (m["volume"], m["volume_unit"], ml))
    print("surface     %.1f %s (Crofton estimate)" % (m["surface_area"], m["area_unit"]))
    print("sphericity  %.3f" % m["sphericity"])
    print("centroid    %s %s" % (", ".join("%.1f" % c for c in m["centroid"]), unit))
    print("components  %d, tunnels %d, cavities %d" % (m["components"], m["tunnels"],
                                                       m["cavities"]))

    vertices, faces = region.mesh(method="mc", smooth=10)
    stl = os.path.join(args.outdir, "region.stl")
    bvox.write_mesh(stl, vertices, faces)
    info = bvox.mesh_info(vertices, faces)
    print("mesh        %d vertices, %d triangles, %.1f %s enclosed -> %s"
          % (len(vertices), len(faces), info["volume"], m["volume_unit"], stl))

    png = os.path.join(args.outdir, "region.png")
    image = region.crop(*region.bbox()).pad(2).render("iso", width=512, height=512, path=png)
    print("render      %d x %d pixels -> %s" % (image.shape[1], image.shape[0], png))


if __name__ == "__main__":
    main()
