#!/bin/sh
# manip_shape.sh — `bvox shape` through the real command: every kind with
# counts known exactly (boxes, half-spaces, counted voxel centres) or close
# to the analytic volume (sphere, cylinder along x with anisotropic voxels,
# cone, torus, ellipsoid), the geometry (--voxel-size, --unit, --origin)
# written into the file, the default centre, text and JSON reports; bad
# command lines (exit 2) and bad parameters (exit 1), nothing written.
# Usage: sh manip_shape.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# shape OUT PYCHECK ARGS...: run with --json, then PYCHECK (about o, the JSON
# object, and its re-read with `bvox info`) must hold.
shape() {
    out=$1 expr=$2
    shift 2
    "$BVOX" shape "$@" -o "$tmp/$out" --json >"$tmp/s.json" || fail "shape $* exited $?"
    "$BVOX" info "$tmp/$out" --json >"$tmp/i.json" || fail "info $out"
    python3 - "$tmp/s.json" "$tmp/i.json" "$expr" <<'PY' || fail "shape $*: $(cat "$tmp/s.json")"
import json, math, sys
o = json.loads(open(sys.argv[1]).read())
i = json.loads(open(sys.argv[2]).read())
for k in ("dims", "unit", "count", "bbox"):
    assert o[k] == i[k], (k, o[k], i[k])
# NIfTI keeps the voxel size as float32
assert all(math.isclose(a, b, rel_tol=1e-6) for a, b in zip(o["voxel_size"], i["voxel_size"]))
pi = math.pi
near = lambda got, want, rel: abs(got - want) <= rel * want
assert eval(sys.argv[3]), sys.argv[3]
PY
}

# The example of the issue: r = 20 voxels, ~ 4/3 pi 8000.
shape s.nii 'near(o["count"], 4 / 3 * pi * 8000, 0.01) and o["bbox"] == {"min": [12, 12, 12], "max": [52, 52, 52]}' \
    sphere r=20 at=32,32,32 --dims 64,64,64
# Default centre: (63/2, 63/2, 63/2) on 64^3, symmetric bbox.
shape c.nii 'o["bbox"]["min"][0] + o["bbox"]["max"][0] == 63' sphere r=10 --dims 64,64,64
# Physical units: 0.5 mm voxels, r = 5 mm = 10 voxels; volume in mm^3.
shape p.nii 'near(o["volume"], 4 / 3 * pi * 125, 0.015) and o["unit"] == "mm" and o["voxel_size"] == [0.5, 0.5, 0.5]' \
    sphere r=5 --dims 32,32,32 --voxel-size 0.5,0.5,0.5 --unit mm
# Boxes: exact counts of voxel centres in the closed box.
shape b1.nii 'o["count"] == 9 * 7 * 17 and o["bbox"] == {"min": [2, 3, 4], "max": [10, 9, 20]}' \
    box min=2,3,4 max=10,9,20 --dims 16,16,32
shape b2.nii 'o["count"] == 5 * 5 * 5' box size=4 at=8,8,8 --dims 16,16,16
shape b3.nii 'o["count"] == 3 * 5 * 1' box size=2,2,1 at=1,1,2 --dims 16,16,16 --voxel-size 1,0.5,2
# --origin moves the frame: voxel (i,j,k) is at origin + (i,j,k) * size.
shape o.nii 'o["count"] == 2 and o["bbox"] == {"min": [1, 2, 3], "max": [2, 2, 3]} and i["origin"] == [-1.0, -2.0, -3.0]' \
    box min=0,0,0 max=1,0,0 --dims 4,4,4 --origin -1,-2,-3
# Half-space: z >= 10 on 8 x 8 x 32 (a centre on the plane is inside).
shape h.nii 'o["count"] == 8 * 8 * 22 and o["bbox"]["min"] == [0, 0, 10]' halfspace n=0,0,1 d=-10 --dims 8,8,32
shape h2.nii 'o["count"] == 8 * 8 * 11' halfspace n=0,0,-2 d=20 --dims 8,8,32
# Cylinder along x, anisotropic voxels: pi r^2 h within 3 %.
shape y.nii 'near(o["volume"], pi * 3 * 3 * 20, 0.03)' cylinder r=3 h=20 axis=1,0,0 \
    --dims 60,40,30 --voxel-size 0.5,0.25,0.4 --unit mm
# (the base between two slices of centres: no half layer on it)
shape k.nii 'near(o["count"], pi * 12 * 12 * 30 / 3, 0.03)' cone r=12 h=30 at=20,20,1.5 --dims 40,40,40
shape t.nii 'near(o["count"], 2 * pi * pi * 12 * 4 * 4, 0.03)' torus R=12 r=4 axis=0,1,1 --dims 40,40,40
shape e.nii 'near(o["count"], 4 / 3 * pi * 15 * 8 * 5, 0.03)' ellipsoid r=15,8,5 --dims 40,40,40
# Text output: the info report.
"$BVOX" shape sphere r=3 --dims 10,10,10 --unit um -o "$tmp/txt.nii" >"$tmp/t.txt" || fail "text"
grep -q '^dimensions: *10 x 10 x 10 voxels$' "$tmp/t.txt" || fail "text: $(cat "$tmp/t.txt")"
grep -q '^voxel size: *1 x 1 x 1 um$' "$tmp/t.txt" || fail "text voxel size"

# Errors: exit 2 (command line) or 1 (bad value), one "bvox: shape: " line,
# nothing written.
expect() {
    want=$1 msg=$2
    shift 2
    set +e
    "$BVOX" shape "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "shape $*: exit $rc, expected $want ($(cat "$tmp/err"))"
    [ ! -s "$tmp/out" ] || fail "shape $*: wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q '^bvox: shape: ' "$tmp/err" &&
        grep -qF -- "$msg" "$tmp/err" || fail "shape $*: stderr '$(cat "$tmp/err")' lacks '$msg'"
    [ ! -e "$tmp/bad.nii" ] || fail "shape $*: wrote an output"
}
B=$tmp/bad.nii
expect 2 "missing the KIND" --dims 4,4,4 -o "$B"
expect 2 "unknown KIND 'blob'" blob r=1 --dims 4,4,4 -o "$B"
expect 2 "missing --dims" sphere r=1 -o "$B"
expect 2 "missing -o OUT" sphere r=1 --dims 4,4,4
expect 2 "'r1' is not a parameter" sphere r1 --dims 4,4,4 -o "$B"
expect 2 "is not a parameter" sphere 'r=1)+(x.nii' --dims 4,4,4 -o "$B"
expect 2 "--dims" sphere r=1 --dims 4,4 -o "$B"
expect 2 "--voxel-size" sphere r=1 --dims 4,4,4 --voxel-size 1,0,1 -o "$B"
expect 2 "unknown option '--threshold'" sphere r=1 --dims 4,4,4 --threshold 3 -o "$B"
expect 1 "sphere: missing parameter 'r'" sphere at=1,1,1 --dims 4,4,4 -o "$B"
expect 1 "sphere has no parameter 'h'" sphere r=1 h=2 --dims 4,4,4 -o "$B"
expect 1 "shape radius -1" sphere r=-1 --dims 4,4,4 -o "$B"
expect 1 "expected a number" sphere r=x --dims 4,4,4 -o "$B"
expect 1 "'at' needs 3 values" sphere r=1 at=1,2 --dims 4,4,4 -o "$B"
expect 1 "halfspace: the normal n is zero" halfspace n=0,0,0 --dims 4,4,4 -o "$B"
expect 1 "box: give size=" box size=1 min=0,0,0 max=1,1,1 --dims 4,4,4 -o "$B"
if grep -q 'column' "$tmp/err"; then fail "shape messages must not name columns"; fi
echo "ok"
