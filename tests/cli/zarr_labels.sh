#!/bin/sh
# zarr_labels.sh — integer Zarr arrays written by Debian's python3-zarr read
# as label volumes: `bvox labels x.zarr` gives each label's voxel count,
# bounding box and centroid as numpy computes them (uint16 with Blosc and
# chunks that cut every label; big-endian int32 with zlib, a chunk never
# written filled with its fill value, itself a label), `bvox mesh x.zarr
# --labels` one closed mesh per label (its volume the label's voxels), an
# NGFF group's coarse level (--level 1) with its translation kept as the
# origin, and a float array of non-integers refused with the voxel named.
# Usage: sh zarr_labels.sh BVOX DATADIR
set -eu
BVOX=$1
PY=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

. "$(dirname "$0")/lib/common.sh"
need_python_zarr

# The arrays, and numpy's answers per label: count, bbox (voxels) and
# centroid (physical: origin + spacing * index) in bvox's x, y, z order (the
# arrays are z, y, x).
$PY - "$tmp" <<'PY'
import json, sys
import numpy as np
import zarr
from numcodecs import Zlib

tmp = sys.argv[1]
rng = np.random.default_rng(16)

def answers(a, name, sp=(1, 1, 1), org=(0, 0, 0)):
    out = {}
    for k in np.unique(a):
        if k == 0:
            continue
        z, y, x = np.nonzero(a == k)
        out[str(int(k))] = {"count": int(len(x)),
                            "min": [int(x.min()), int(y.min()), int(z.min())],
                            "max": [int(x.max()), int(y.max()), int(z.max())],
                            "centroid": [org[i] + sp[i] * float(c.mean())
                                         for i, c in enumerate((x, y, z))]}
    json.dump(out, open("%s/%s.json" % (tmp, name), "w"))

# uint16, Blosc (zarr's default), odd chunks: boxes, a ball and random specks
a = np.zeros((40, 33, 29), dtype=np.uint16)
a[2:12, 3:20, 4:9] = 7
zz, yy, xx = np.ogrid[:40, :33, :29]
a[(zz - 25) ** 2 + (yy - 16) ** 2 + (xx - 14) ** 2 <= 64] = 300
a[rng.random(a.shape) < 0.01] = 65535
z = zarr.open(tmp + "/u16.zarr", mode="w", shape=a.shape, chunks=(7, 9, 11), dtype="<u2")
z[:] = a
answers(a, "u16")

# big-endian int32, zlib, fill value 5: the chunks never written are label 5
b = np.full((12, 10, 8), 5, dtype=np.int32)
b[0:6, :, :] = 0
b[1:4, 2:5, 1:7] = -2
b[3:6, 6:10, 0:3] = 123456
z = zarr.open(tmp + "/i32.zarr", mode="w", shape=b.shape, chunks=(6, 10, 8), dtype=">i4",
              compressor=Zlib(level=3), fill_value=5)
z[0:6] = b[0:6]  # z 6..11: one chunk left unwritten
answers(b, "i32")

# an NGFF group of two levels; level 1 translated
g = zarr.open_group(tmp + "/ngff.zarr", mode="w")
g.create_dataset("0", data=a, chunks=(16, 16, 16))
g.create_dataset("1", data=a[::2, ::2, ::2], chunks=(16, 16, 16))
g.attrs["multiscales"] = [{"version": "0.4", "axes": [
    {"name": "z", "type": "space", "unit": "micrometer"},
    {"name": "y", "type": "space", "unit": "micrometer"},
    {"name": "x", "type": "space", "unit": "micrometer"}], "datasets": [
    {"path": "0", "coordinateTransformations": [{"type": "scale", "scale": [2.0, 1.0, 0.5]},
                                                 {"type": "translation",
                                                  "translation": [10.0, 20.0, 30.0]}]},
    {"path": "1", "coordinateTransformations": [{"type": "scale", "scale": [4.0, 2.0, 1.0]},
                                                 {"type": "translation",
                                                  "translation": [11.0, 20.5, 30.25]}]}]}]
answers(a[::2, ::2, ::2], "ngff1", (1.0, 2.0, 4.0), (30.25, 20.5, 11.0))

# float labels that are not integers
f = np.zeros((4, 4, 4), dtype=np.float32)
f[1, 2, 3] = 1.5
zarr.open(tmp + "/f.zarr", mode="w", shape=f.shape, chunks=(4, 4, 4), dtype="<f4")[:] = f
PY

check() { # ZARR ANSWERS [read options]
    zarr=$1 want=$2
    shift 2
    "$BVOX" labels "$zarr" --json "$@" >"$tmp/got.json" || fail "bvox labels $zarr"
    $PY - "$tmp/got.json" "$want" <<'PY' || fail "bvox labels $1 disagrees with numpy"
import json, sys
got = {str(l["label"]): l for l in json.load(open(sys.argv[1]))["labels"]}
want = json.load(open(sys.argv[2]))
assert sorted(got) == sorted(want), (sorted(got), sorted(want))
for k, w in want.items():
    g = got[k]
    assert g["count"] == w["count"], (k, g["count"], w["count"])
    assert g["bbox"]["min"] == w["min"] and g["bbox"]["max"] == w["max"], (k, g["bbox"], w)
    assert all(abs(a - b) < 1e-9 for a, b in zip(g["centroid"], w["centroid"])), (k, g, w)
PY
}

# 1. uint16 + Blosc, big-endian int32 + zlib with a fill-value chunk
check "$tmp/u16.zarr" "$tmp/u16.json"
check "$tmp/i32.zarr" "$tmp/i32.json"

# 2. one mesh per label: closed, its volume the label's voxel count
"$BVOX" mesh "$tmp/i32.zarr" --labels all -o "$tmp/meshes/" >/dev/null || fail "mesh --labels"
for l in -2 5 123456; do
    [ -f "$tmp/meshes/$l.ply" ] || fail "no mesh for label $l: $(ls "$tmp/meshes")"
    "$BVOX" meshinfo "$tmp/meshes/$l.ply" --json >"$tmp/mi.json" || fail "meshinfo $l"
    $PY - "$tmp/mi.json" "$tmp/i32.json" "$l" <<'PY' || fail "mesh of label $l"
import json, sys
m = json.load(open(sys.argv[1]))
want = json.load(open(sys.argv[2]))[sys.argv[3]]["count"]
assert abs(m["volume"] - want) < 1e-6, (m["volume"], want)
assert m["boundary_edges"] == 0, m
PY
done

# 3. an NGFF group's level 1: its labels, and its translation as the origin
check "$tmp/ngff.zarr" "$tmp/ngff1.json" --level 1
"$BVOX" info "$tmp/ngff.zarr" --level 1 --json | $PY -c '
import json, sys
d = json.load(sys.stdin)
assert d["origin"] == [30.25, 20.5, 11.0], d["origin"]
assert d["spacing"] == [1.0, 2.0, 4.0], d["spacing"]
' || fail "level 1 origin or spacing"
"$BVOX" info "$tmp/ngff.zarr" --json | $PY -c '
import json, sys
assert json.load(sys.stdin)["origin"] == [30.0, 20.0, 10.0]
' || fail "level 0 origin"

# 4. a float array of non-integers is not a label volume
if "$BVOX" labels "$tmp/f.zarr" 2>"$tmp/err"; then fail "1.5 read as a label"; fi
grep -q "voxel (3, 2, 1)" "$tmp/err" || fail "no voxel named: $(cat "$tmp/err")"
[ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "error not one line: $(cat "$tmp/err")"
echo ok
