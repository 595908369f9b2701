#!/bin/sh
# image_preimage.sh — `bvox image enlarge|shade` on a 16-bit depth map from
# `bvox render --depth`: the paper's Figure 5 numbers (13 5 / 0 8) enlarged
# exactly, the three gradient operators' picture sizes, and refusals (an
# 8-bit input: exit 1; a bad --shade: exit 2).
# Usage: sh image_preimage.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

# 2 x 2 columns whose first voxels along +z are at 13, 5 / 0, 8
python3 - "$tmp/f5.raw" <<'PY'
import sys
nx, ny, nz = 2, 2, 16
v = bytearray(nx * ny * nz)
for x, y, z in [(0, 0, 13), (1, 0, 5), (0, 1, 0), (1, 1, 8)]:
    v[(z * ny + y) * nx + x] = 1
open(sys.argv[1], "wb").write(v)
PY
"$BVOX" convert "$tmp/f5.raw" "$tmp/f5.nii" --dims 2,2,16 --type u8 >/dev/null || fail "f5.nii"
"$BVOX" render "$tmp/f5.nii" -o "$tmp/f5.png" --depth "$tmp/d.png" || fail "depth map"
"$BVOX" image enlarge "$tmp/d.png" "$tmp/d2.png" || fail "enlarge"
png read "$tmp/d2.png" >"$tmp/d2.json"
python3 - "$tmp/d2.json" <<'PY' || fail "Figure 5"
import json, sys
g = json.load(open(sys.argv[1]))
assert (g["width"], g["height"], g["bits"]) == (4, 4, 16), g
# depths + 1; the originals kept at even places, averages rounded half up,
# nothing beyond the edge averaged in
want = [[14, 10, 6, 6], [8, 8, 8, 8], [1, 5, 9, 9], [1, 5, 9, 9]]
assert g["rows"] == want, g["rows"]
PY

"$BVOX" demo -o "$tmp/demo" >/dev/null 2>&1 || fail "demo"
"$BVOX" render "$tmp/demo/specimen.nii.gz" -o "$tmp/s.png" --view iso --size 64,48 \
    --depth "$tmp/sd.png" || fail "specimen depth map"
for m in gradient binary-preimage enlarged-gradient; do
    "$BVOX" image shade "$tmp/sd.png" "$tmp/$m.png" --shade "$m" --light 120,30 || fail "shade $m"
    png read "$tmp/$m.png" >"$tmp/$m.json"
done
python3 - "$tmp/gradient.json" "$tmp/binary-preimage.json" "$tmp/enlarged-gradient.json" <<'PY' ||
import json, sys
g, b, e = (json.load(open(p)) for p in sys.argv[1:4])
assert (g["width"], g["height"], g["bits"]) == (64, 48, 8), g
assert (e["width"], e["height"]) == (128, 96), e
# the binary operator knows 9 normals: few gray levels; Sobel many
levels = lambda im: len({v for row in im["rows"] for v in row})
assert levels(b) <= 10 < levels(g), (levels(b), levels(g))
PY
    fail "shaded pictures"

set +e
"$BVOX" image shade "$tmp/s.png" "$tmp/x.png" 2>"$tmp/err"; rc=$?
set -e
[ $rc -eq 1 ] && grep -q '^bvox: depth map: needs a 16-bit' "$tmp/err" || fail "8-bit input: $rc $(cat "$tmp/err")"
set +e
"$BVOX" image shade "$tmp/sd.png" "$tmp/x.png" --shade phong 2>"$tmp/err"; rc=$?
set -e
[ $rc -eq 2 ] || fail "bad --shade exited $rc"
[ ! -e "$tmp/x.png" ] || fail "a refusal wrote output"
echo "ok"
