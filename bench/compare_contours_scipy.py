#!/usr/bin/python3
"""compare_contours_scipy.py — the peer of bench_contours.c: the same contour
stack to model, done with scikit-image and SciPy, on the very stack the bench
wrote (bench_contours --save DIR writes DIR/stack.json and DIR/model.nii),
so both tools see the same contours.

    bench_contours --save DIR > DIR/bvox.jsonl
    /usr/bin/python3 bench/compare_contours_scipy.py DIR [--bench DIR/bvox.jsonl] [--runs N]

Steps, as bvox_stack_to_volume does them (isotropic voxels of the pixel size,
sections at their z, each end section extended by half a spacing):
  scan:   skimage.draw.polygon2mask per contour (pixel centres; vertices moved
          by -0.5 since skimage puts centres on integers), XORed (even-odd);
  edt:    scipy.ndimage.distance_transform_edt of the section and of its
          complement: signed distance, negative inside;
  blend:  slice at z between sections a and b inside where
          (1 - t) d_a + t d_b <= 0.
Prints one JSON line: the median time of each step and of the whole
("scipy_ms"), bvox's median from the bench's "interpolate" line (with
--bench) and "speedup" = scipy_ms / bvox_ms, and how many voxels differ from
bvox's model (polygon edge rules and float rounding may differ on a few).
SciPy and scikit-image run on one thread; the bench's "threads" is copied.
Needs numpy, scipy, scikit-image (Debian: python3-scipy python3-skimage; use
/usr/bin/python3 if another python3 comes first in PATH).
"""
import argparse
import json
import math
import os
import sys

try:
    import numpy as np
    from scipy import ndimage
    from skimage.draw import polygon2mask
except ImportError as e:
    sys.exit("compare_contours_scipy.py: %s (apt-get install python3-scipy python3-skimage, "
             "and run it with /usr/bin/python3)" % e)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # compare_common, from any cwd
from compare_common import json_lines, read_nifti_u8, timed  # noqa: E402


def scan(stack):
    w, h = stack["width"], stack["height"]
    out = []
    for sec in stack["sections"]:
        m = np.zeros((h, w), dtype=bool)
        for c in sec["contours"]:
            rc = np.array([[p[1] - 0.5, p[0] - 0.5] for p in c])
            m ^= polygon2mask((h, w), rc)
        out.append(m)
    return out


def edt(masks):
    out = []
    for m in masks:
        inside = ndimage.distance_transform_edt(m) if (~m).any() else np.full(m.shape, 1e9)
        outside = ndimage.distance_transform_edt(~m) if m.any() else np.full(m.shape, 1e9)
        out.append(np.where(m, -inside, outside).astype(np.float32))
    return out


def blend(stack, masks, dists):
    zs = [s["z"] for s in stack["sections"]]
    dz = stack["pixel"]
    length = zs[-1] - zs[0] + stack["spacing"]
    nz = max(1, int(math.floor(length / dz + 0.5)))
    zmid = (zs[0] + zs[-1]) / 2
    vol = np.zeros((nz,) + masks[0].shape, dtype=bool)
    for k in range(nz):
        z = zmid + (k - (nz - 1) / 2) * dz
        if z <= zs[0]:
            vol[k] = masks[0]
            continue
        if z >= zs[-1]:
            vol[k] = masks[-1]
            continue
        b = next(i for i in range(len(zs)) if zs[i] > z)
        a = b - 1
        t = (z - zs[a]) / (zs[b] - zs[a])
        eps = 1e-9
        if t <= eps:
            vol[k] = masks[a]
        elif t >= 1 - eps:
            vol[k] = masks[b]
        else:
            vol[k] = (np.float32(1 - t) * dists[a] + np.float32(t) * dists[b]) <= 0
    return vol


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--bench")
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    stack = json.load(open(os.path.join(a.dir, "stack.json")))
    scan_ms, masks = timed(a.runs, lambda: scan(stack))
    edt_ms, dists = timed(a.runs, lambda: edt(masks))
    blend_ms, vol = timed(a.runs, lambda: blend(stack, masks, dists))
    ours = read_nifti_u8(os.path.join(a.dir, "model.nii")) != 0
    line = {"bench": "contours_scipy", "sections": len(masks), "size": stack["width"],
            "scan_ms": round(scan_ms, 3), "edt_ms": round(edt_ms, 3),
            "blend_ms": round(blend_ms, 3), "scipy_ms": round(scan_ms + edt_ms + blend_ms, 3),
            "voxels": int(vol.sum()), "shape_equal": vol.shape == ours.shape}
    if vol.shape == ours.shape:
        line["voxels_differing"] = int((vol != ours).sum())
    if a.bench:
        for o in json_lines(a.bench):
            if o.get("case") == "interpolate":
                line["bvox_ms"] = o["median_ms"]
                line["threads"] = o["threads"]
                line["speedup"] = round(line["scipy_ms"] / o["median_ms"], 1)
    print(json.dumps(line))


if __name__ == "__main__":
    main()
