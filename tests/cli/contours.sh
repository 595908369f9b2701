#!/bin/sh
# contours.sh — `bvox contours` through the real command: a constructed model
# (a ring with a hole plus a bar, 0.5 mm voxels) traced across z, y and x;
# the JSON stack's keys and values (unit, pixel, spacing, width/height, one
# section per slice at its physical z) and the sum of the contours' signed
# areas (outer positive, holes negative) equal to the voxel count; an SVG
# folder with one file per slice; non-square slice pixels scaled; bad command
# lines (exit 2) and bad inputs/outputs (exit 1), neither leaving output.
# Usage: sh contours.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# 20 x 16 x 6: a ring 3 <= r <= 6 around (10, 8) on z = 1..4, and a bar
# x = 15..18, y = 2, z = 0..5
mk m 20 16 6 '(1 <= z <= 4 and 9 <= (x-10)**2 + (y-8)**2 <= 36) or (15 <= x <= 18 and y == 2)' --voxel-size 0.5,0.5,0.5 --unit mm
count=$("$BVOX" info "$tmp/m.nii" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["count"])')
[ "$count" -gt 50 ] || fail "the model has $count voxels"

# jstack FILE NSECTIONS WIDTH HEIGHT PIXEL SPACING WANT_AREA
jstack() {
    python3 - "$@" <<'PY' || fail "JSON stack check: $*"
import json, sys
path, ns, w, h, px, sp, area = sys.argv[1], *map(int, sys.argv[2:5]), *map(float, sys.argv[5:8])
o = json.load(open(path))
assert o["unit"] == "mm", o["unit"]
assert o["pixel"] == px and o["spacing"] == sp, (o["pixel"], o["spacing"])
assert o["width"] == w and o["height"] == h, (o["width"], o["height"])
secs = o["sections"]
assert len(secs) == ns, len(secs)
total = 0.0
for k, s in enumerate(secs):
    assert abs(s["z"] - k * sp) < 1e-9, (k, s["z"])
    for c in s["contours"]:
        assert len(c) >= 3 and all(len(p) == 2 for p in c)
        total += 0.5 * sum(c[i][0] * c[(i + 1) % len(c)][1] - c[(i + 1) % len(c)][0] * c[i][1]
                           for i in range(len(c)))
assert abs(total - area) < 1e-6, (total, area)
PY
}

"$BVOX" contours "$tmp/m.nii" -o "$tmp/z.json" >"$tmp/out" || fail "contours across z"
grep -q "6 slices across z" "$tmp/out" || fail "summary: $(cat "$tmp/out")"
jstack "$tmp/z.json" 6 20 16 0.5 0.5 "$count"
# the ring's hole is a negative contour in slice 2
python3 - "$tmp/z.json" <<'PY' || fail "ring hole"
import json, sys
s = json.load(open(sys.argv[1]))["sections"][2]["contours"]
areas = sorted(0.5 * sum(c[i][0] * c[(i + 1) % len(c)][1] - c[(i + 1) % len(c)][0] * c[i][1]
                         for i in range(len(c))) for c in s)
assert len(areas) == 3 and areas[0] < 0 and areas[1] == 4 and areas[2] > 0, areas
PY
"$BVOX" contours "$tmp/m.nii" --axis y -o "$tmp/y.json" >/dev/null || fail "contours across y"
jstack "$tmp/y.json" 16 20 6 0.5 0.5 "$count"
"$BVOX" contours "$tmp/m.nii" --axis=x -o "$tmp/x.json" >/dev/null || fail "contours across x"
jstack "$tmp/x.json" 20 16 6 0.5 0.5 "$count"

# SVG folder: one file per slice, even-odd paths
"$BVOX" contours "$tmp/m.nii" -o "$tmp/svg" >/dev/null || fail "contours to SVG"
[ "$(ls "$tmp/svg" | wc -l)" -eq 6 ] || fail "SVG files: $(ls "$tmp/svg")"
grep -q 'fill-rule="evenodd"' "$tmp/svg/section_0003.svg" || fail "no even-odd path"
grep -q 'data-z="1"' "$tmp/svg/section_0003.svg" || fail "no data-z"
# written again over itself (atomic replace)
"$BVOX" contours "$tmp/m.nii" -o "$tmp/svg" >/dev/null || fail "SVG over an existing folder"

# non-square slice pixels: across x the pixels are 0.5 x 2 (z spacing 2):
# v scaled by 4, so the areas in pixels of 0.5 are 4 per voxel
"$BVOX" convert "$tmp/m.nii" "$tmp/a.nii" --voxel-size 0.5,0.5,2 >/dev/null || fail "anisotropic copy"
"$BVOX" contours "$tmp/a.nii" --axis x -o "$tmp/ax.json" >/dev/null || fail "anisotropic contours"
python3 - "$tmp/ax.json" "$count" <<'PY' || fail "anisotropic areas"
import json, sys
o = json.load(open(sys.argv[1]))
assert o["height"] == 24 and o["pixel"] == 0.5, (o["height"], o["pixel"])
t = sum(0.5 * sum(c[i][0] * c[(i + 1) % len(c)][1] - c[(i + 1) % len(c)][0] * c[i][1]
                  for i in range(len(c))) for s in o["sections"] for c in s["contours"])
assert abs(t - 4 * int(sys.argv[2])) < 1e-6, t
PY

# bad command lines: exit 2, nothing written
st=0; "$BVOX" contours "$tmp/m.nii" --axis w -o "$tmp/bad.json" 2>"$tmp/err" || st=$?
[ $st -eq 2 ] || fail "--axis w exited $st"
grep -q "axis" "$tmp/err" || fail "message: $(cat "$tmp/err")"
st=0; "$BVOX" contours "$tmp/m.nii" 2>"$tmp/err" || st=$?
[ $st -eq 2 ] || fail "missing -o exited $st"
st=0; "$BVOX" contours -o "$tmp/bad.json" 2>"$tmp/err" || st=$?
[ $st -eq 2 ] || fail "missing input exited $st"
# bad files: exit 1 with a message, nothing written
st=0; "$BVOX" contours "$tmp/missing.nii" -o "$tmp/bad.json" 2>"$tmp/err" || st=$?
[ $st -eq 1 ] || fail "missing input file exited $st"
grep -q "^bvox: " "$tmp/err" || fail "message: $(cat "$tmp/err")"
st=0; "$BVOX" contours "$tmp/m.nii" -o "$tmp/no/such/dir/x.json" 2>"$tmp/err" || st=$?
[ $st -eq 1 ] || fail "unwritable output exited $st"
[ ! -e "$tmp/bad.json" ] || fail "a failed run left bad.json"
[ -z "$(ls -A "$tmp" | grep '^\.')" ] || fail "temporary files left: $(ls -A "$tmp")"
"$BVOX" contours --help | grep -q "Usage: bvox contours MODEL" || fail "--help"
echo "contours.sh: ok"
