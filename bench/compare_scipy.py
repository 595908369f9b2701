#!/usr/bin/python3
"""compare_scipy.py — the same dilation and labelling as bench_manip.c, done
with SciPy, on the very volumes the bench wrote (bench_manip --save DIR
writes DIR/<pattern>_<n>.nii, uint8 0/1), so both tools see the same voxels.

    bench_manip --save DIR > DIR/bvox.jsonl
    /usr/bin/python3 bench/compare_scipy.py DIR [--bench DIR/bvox.jsonl] [--runs N]

Prints one JSON line per volume and operation:
  op "dilate26": scipy.ndimage.binary_dilation with a 3x3x3 structure;
  op "label26":  scipy.ndimage.label with a 3x3x3 structure (26-connected).
Each line has the median time of `runs` runs ("scipy_ms"), the result's
count of 1-voxels or of components, and, with --bench, bvox's median time
from the bench's line of the same op, n and pattern ("bvox_ms"), whether both
agree on the count, and "speedup" = scipy_ms / bvox_ms. SciPy runs on one
thread; the bench's "threads" is copied to the line. Needs numpy and scipy
(Debian: python3-numpy python3-scipy; use /usr/bin/python3 if another
python3 comes first in PATH). Reads .nii (not .nii.gz) with numpy alone.
"""
import argparse
import glob
import json
import os
import re
import sys

try:
    import numpy as np
    from scipy import ndimage
except ImportError as e:  # say what to install, not a traceback
    sys.exit("compare_scipy.py: %s (apt-get install python3-numpy python3-scipy, "
             "and run it with /usr/bin/python3)" % e)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # compare_common, from any cwd
from compare_common import bench_by_op, read_nifti_u8, timed  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", help="folder where bench_manip --save wrote its volumes")
    ap.add_argument("--bench", help="bench_manip's output (JSON lines) to compare with")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()

    bvox = bench_by_op(args.bench) if args.bench else {}

    paths = sorted(glob.glob(os.path.join(args.dir, "*_*.nii")))
    if not paths:
        sys.exit("compare_scipy.py: no <pattern>_<n>.nii in %s (run bench_manip --save %s)"
                 % (args.dir, args.dir))
    box = np.ones((3, 3, 3), dtype=bool)
    for path in paths:
        m = re.match(r"(.+)_(\d+)\.nii$", os.path.basename(path))
        if not m:
            continue
        pattern, n = m.group(1), int(m.group(2))
        a = read_nifti_u8(path) != 0
        cases = (
            ("dilate26", lambda: ndimage.binary_dilation(a, structure=box),
             lambda r: int(np.count_nonzero(r)), "count_out"),
            ("label26", lambda: ndimage.label(a, structure=box),
             lambda r: int(r[1]), "components"),
        )
        for op, fn, summary, key in cases:
            ms, out = timed(args.runs, fn)
            line = {"bench": "scipy", "op": op, "n": n, "pattern": pattern,
                    "threads": 1, "runs": args.runs, "scipy_ms": round(ms, 3),
                    key: summary(out)}
            b = bvox.get((op, n, pattern))
            if b:
                line["bvox_ms"] = b["ms"]
                line["bvox_threads"] = b["threads"]
                line["agree"] = b.get(key) == line[key]
                line["speedup"] = round(ms / b["ms"], 1)
            print(json.dumps(line), flush=True)
            del out


if __name__ == "__main__":
    main()
