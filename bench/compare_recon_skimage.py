#!/usr/bin/python3
"""compare_recon_skimage.py — the peer of bench_recon.c: the per-section image
steps of bvox_reconstruct done with scikit-image, SciPy and NumPy on the very
section images the bench wrote (bench_recon --save DIR writes DIR/s1.png ...).

    mkdir -p DIR && bench_recon --save DIR > DIR/bvox.jsonl
    /usr/bin/python3 bench/compare_recon_skimage.py DIR [--bench DIR/bvox.jsonl] [--runs N]

Steps, as bvox does them per section:
  background: a quadratic surface a + bx + cy + dx^2 + exy + fy^2 fitted
              (numpy.linalg.lstsq) to a 64 x 64 grid of samples, first those
              above Otsu's threshold, then 4 refits keeping samples within 3
              robust sigmas (median, MAD) below the fit; the section divided
              by it (flat field) times its mean;
  threshold:  skimage.filters.threshold_otsu, object = value <= t;
  smooth:     scipy.ndimage.median_filter, 3 x 3 (majority on 0/1);
  markers:    dark pixels (halfway between the median and the 0.05 %
              level), skimage.measure.label (8-connected) and regionprops
              (area, centroid, farthest pixel), the 4 roundest of a marker's
              size, erased from the mask;
  specks:     skimage.morphology.remove_small_objects / remove_small_holes (16);
  contours:   skimage.measure.find_contours at 0.5 (marching squares: the same
              purpose, sub-pixel outlines instead of pixel edges).
Prints one JSON line: the median time of each step over the runs for all
sections, their total ("peer_ms"), bvox's one-thread per-section time
("bvox_ms": sections_ms of the bench's pipeline_1thread line, with --bench),
"speedup" = peer_ms / bvox_ms, and the object pixels of both (the masks
should agree to a fraction of a percent). One thread, as SciPy runs.
Needs numpy, scipy, scikit-image (Debian: python3-scipy
python3-skimage; use /usr/bin/python3 if another python3 comes first).
"""
import argparse
import glob
import json
import os
import re
import statistics
import sys
import time

try:
    from skimage.io import imread
    import numpy as np
    from scipy import ndimage
    from skimage.filters import threshold_otsu
    from skimage.measure import find_contours, label, regionprops
    from skimage.morphology import remove_small_holes, remove_small_objects
except ImportError as e:
    sys.exit("compare_recon_skimage.py: %s (apt-get install python3-scipy python3-skimage, "
             "and run it with /usr/bin/python3)" % e)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # compare_common, from any cwd
from compare_common import json_lines  # noqa: E402


def background(img):
    h, w = img.shape
    step = max(1, min(w, h) // 64)
    ys, xs = np.mgrid[step // 2:h:step, step // 2:w:step]
    s = 2.0 / max(w, h)
    u = ((xs + 0.5 - w / 2) * s).ravel()
    v = ((ys + 0.5 - h / 2) * s).ravel()
    g = img[ys, xs].ravel().astype(float)
    a = np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=1)
    keep = g > threshold_otsu(img)
    coef = None
    for it in range(5):
        coef = np.linalg.lstsq(a[keep], g[keep], rcond=None)[0]
        if it == 4:
            break
        res = g - a @ coef
        med = np.median(res[keep])
        mad = 1.4826 * np.median(np.abs(res[keep] - med)) + 0.5
        keep = res >= med - 3 * mad
    yy, xx = np.mgrid[0:h, 0:w]
    uu, vv = (xx + 0.5 - w / 2) * s, (yy + 0.5 - h / 2) * s
    bg = coef[0] + coef[1] * uu + coef[2] * vv + coef[3] * uu * uu + coef[4] * uu * vv + coef[5] * vv * vv
    bg = np.clip(np.rint(bg), 1, 255)
    return np.clip(np.rint(img * bg.mean() / bg), 0, 255).astype(np.uint8)


def markers(img, mask, count=3):
    h, w = img.shape
    t = (np.percentile(img, 0.05) + np.median(img)) // 2
    lab = label(img <= t, connectivity=2)
    rmin, rmax = 1.5, min(w, h) / 16
    cands = []
    for r in regionprops(lab, intensity_image=img):
        if not (np.pi * rmin ** 2 <= r.area <= np.pi * rmax ** 2):
            continue
        cy, cx = r.centroid
        far = np.sqrt(((r.coords - [cy, cx]) ** 2).sum(axis=1)).max() + 0.5
        rnd = r.area / (np.pi * far * far)
        if rnd >= 0.5:
            cands.append((rnd, r))
    cands.sort(key=lambda c: -c[0])
    for _, r in cands[:count + 1]:
        mask[lab == r.label] = False
    return [r.centroid for _, r in cands[:count + 1]]


def run(images):
    t = {k: 0.0 for k in ("background", "threshold", "smooth", "markers", "specks", "contours")}
    pixels = 0
    for img in images:
        s = time.perf_counter()
        flat = background(img)
        t["background"] += time.perf_counter() - s
        s = time.perf_counter()
        mask = flat <= threshold_otsu(flat)
        t["threshold"] += time.perf_counter() - s
        s = time.perf_counter()
        mask = ndimage.median_filter(mask.astype(np.uint8), size=3).astype(bool)
        t["smooth"] += time.perf_counter() - s
        s = time.perf_counter()
        markers(flat, mask)
        t["markers"] += time.perf_counter() - s
        s = time.perf_counter()
        mask = remove_small_objects(mask, 16, connectivity=2)
        mask = remove_small_holes(mask, 16)
        t["specks"] += time.perf_counter() - s
        s = time.perf_counter()
        find_contours(mask.astype(np.float32), 0.5)
        t["contours"] += time.perf_counter() - s
        pixels += int(mask.sum())
    return {k: v * 1e3 for k, v in t.items()}, pixels


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--bench", help="bench_recon's output (JSON lines)")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    files = glob.glob(os.path.join(args.dir, "s*.png"))
    files.sort(key=lambda p: int(re.findall(r"(\d+)\.png$", p)[0]))
    if not files:
        sys.exit("compare_recon_skimage.py: no s*.png in %s (bench_recon --save DIR)" % args.dir)
    images = [imread(p) for p in files]
    runs = [run(images) for _ in range(max(1, args.runs))]
    steps = {k: statistics.median(r[0][k] for r in runs) for k in runs[0][0]}
    out = {"peer": "skimage+scipy", "sections": len(images), "size": list(images[0].shape),
           "runs": len(runs)}
    out.update({k + "_ms": round(v, 2) for k, v in steps.items()})
    out["peer_ms"] = round(sum(steps.values()), 2)
    out["peer_object_pixels"] = runs[0][1]
    if args.bench:
        for o in json_lines(args.bench):
            if o.get("case") == "pipeline_1thread":
                out["bvox_ms"] = o["sections_ms"]
                out["speedup"] = round(out["peer_ms"] / o["sections_ms"], 1)
            if o.get("case") == "pipeline":
                out["bvox_object_pixels"] = o["object_pixels"]
                out["bvox_threads_ms"] = o["sections_ms"]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
