#!/bin/sh
# mesh.sh — `bvox mesh`, `bvox meshinfo` and `bvox voxelize` through the real
# command: a box of anisotropic voxels with a known origin meshed by both
# methods into every format (cuberille volume = voxel volume, bounding box
# on the voxel faces, watertight), meshinfo's JSON keys and values, the
# mesh voxelized back to the same voxel count at the same voxel size, the
# shell, an open mesh reported (warning) and still filled, a smoothed
# sphere; bad command lines (exit 2) and bad meshes (exit 1, the file named,
# nothing written).
# Usage: sh mesh.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# A 6 x 4 x 3 box of voxels (x 2..7, y 1..4, z 1..3) in a 10 x 6 x 5 volume,
# voxels 0.5 x 1 x 2 mm, origin (10, 20, 30).
mk box 10 6 5 '2 <= x <= 7 and 1 <= y <= 4 and 1 <= z <= 3' --voxel-size 0.5,1,2 --unit mm
"$BVOX" convert "$tmp/box.nii" "$tmp/box.nii" --voxel-size 0.5,1,2 --unit mm >/dev/null
python3 - "$tmp/box.nii" <<'PY'
import struct, sys
p = sys.argv[1]
b = bytearray(open(p, "rb").read())
struct.pack_into("<h", b, 254, 1)             # sform_code: scanner
struct.pack_into("<4f", b, 280, 0.5, 0, 0, 10)  # srow_x
struct.pack_into("<4f", b, 296, 0, 1, 0, 20)    # srow_y
struct.pack_into("<4f", b, 312, 0, 0, 2, 30)    # srow_z
open(p, "wb").write(b)
PY
"$BVOX" info "$tmp/box.nii" --json > "$tmp/info.json"
jcheck "$tmp/info.json" 'o["count"] == 72 and near(o["origin"][0], 10) if "origin" in o else o["count"] == 72' ||
    fail "box.nii: $(cat "$tmp/info.json")"

# cuberille: exact volume 72 * 0.5 * 1 * 2 = 72, faces on the voxel faces
for f in stl ply obj off; do
    "$BVOX" mesh "$tmp/box.nii" -o "$tmp/c.$f" --method cuberille >"$tmp/out" || fail "mesh cuberille $f"
    grep -q "triangles (cuberille)" "$tmp/out" || fail "mesh summary: $(cat "$tmp/out")"
    "$BVOX" meshinfo "$tmp/c.$f" --json > "$tmp/mi.json" || fail "meshinfo c.$f"
    jcheck "$tmp/mi.json" 'o["watertight"] is True and near(o["volume"], 72, 1e-6) and o["triangles"] == 2 * 2 * (6*4 + 4*3 + 6*3) and near(o["area"], 2 * (3*4 + 4*6 + 3*6), 1e-6)' ||
        fail "cuberille $f: $(cat "$tmp/mi.json")"
done
# the keys the issue names, and the bounding box in world coordinates
jcheck "$tmp/mi.json" 'all(k in o for k in ("vertices", "triangles", "volume", "area", "bbox", "watertight"))' ||
    fail "meshinfo keys: $(cat "$tmp/mi.json")"
python3 - "$tmp/mi.json" <<'PY' || fail "cuberille bbox: $(cat "$tmp/mi.json")"
import json, sys
o = json.load(open(sys.argv[1]))
lo, hi = o["bbox"]["min"], o["bbox"]["max"]
want_lo = [10 + 0.5 * 1.5, 20 + 1 * 0.5, 30 + 2 * 0.5]
want_hi = [10 + 0.5 * 7.5, 20 + 1 * 4.5, 30 + 2 * 3.5]
assert all(abs(a - b) < 1e-5 for a, b in zip(lo + hi, want_lo + want_hi)), (lo, hi)
PY

# marching cubes, ASCII STL and PLY: closed, smaller than the voxels
for f in stl ply; do
    "$BVOX" mesh "$tmp/box.nii" -o "$tmp/m.$f" --ascii >/dev/null || fail "mesh mc $f"
    head -c 5 "$tmp/m.$f" | grep -q -e solid -e ply || fail "m.$f is not ASCII"
    "$BVOX" meshinfo "$tmp/m.$f" --json > "$tmp/mi.json" || fail "meshinfo m.$f"
    jcheck "$tmp/mi.json" 'o["watertight"] and 50 < o["volume"] < 72' || fail "mc $f: $(cat "$tmp/mi.json")"
done
"$BVOX" meshinfo "$tmp/m.stl" > "$tmp/mi.txt" || fail "meshinfo text"
grep -q '^watertight: *yes' "$tmp/mi.txt" || fail "meshinfo text: $(cat "$tmp/mi.txt")"

# voxelize the cuberille mesh back (box x 10.75..13.75, y 20.5..24.5, z 31..37)
# at 0.5: 6 x 8 x 12 voxels, centres a half voxel inside the faces
"$BVOX" voxelize "$tmp/c.stl" -o "$tmp/back.nii" --voxel-size 0.5 >"$tmp/out" || fail "voxelize"
grep -q "parity-z" "$tmp/out" || fail "voxelize summary: $(cat "$tmp/out")"
"$BVOX" info "$tmp/back.nii" --json > "$tmp/info.json"
jcheck "$tmp/info.json" 'o["count"] == 6 * 8 * 12 and o["dims"] == [6, 8, 12] and o["origin"] == [11, 20.75, 31.25]' ||
    fail "voxelized back: $(cat "$tmp/info.json")"
"$BVOX" voxelize "$tmp/c.obj" -o "$tmp/back.nii" --res 6 >/dev/null || fail "voxelize --res"
"$BVOX" info "$tmp/back.nii" --json > "$tmp/info.json"
jcheck "$tmp/info.json" 'o["count"] == 3 * 4 * 6 and o["dims"] == [3, 4, 6]' || fail "--res 6: $(cat "$tmp/info.json")"
"$BVOX" voxelize "$tmp/c.ply" -o "$tmp/shell.nii" --res 6 --shell >/dev/null || fail "voxelize --shell"
"$BVOX" info "$tmp/shell.nii" --json > "$tmp/info.json"
jcheck "$tmp/info.json" 'o["count"] == 3 * 4 * 6 - 1 * 2 * 4' || fail "shell: $(cat "$tmp/info.json")"

# an open mesh: a box without its top (OBJ by hand): warned, still filled
cat > "$tmp/open.obj" <<'OBJ'
v 0 0 0
v 4 0 0
v 4 4 0
v 0 4 0
v 0 0 4
v 4 0 4
v 4 4 4
v 0 4 4
f 1 4 3 2
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
OBJ
"$BVOX" meshinfo "$tmp/open.obj" --json > "$tmp/mi.json" || fail "meshinfo open"
jcheck "$tmp/mi.json" 'o["watertight"] is False and o["open_edges"] == 4' || fail "open: $(cat "$tmp/mi.json")"
"$BVOX" voxelize "$tmp/open.obj" -o "$tmp/open.nii" --voxel-size 1 >/dev/null 2>"$tmp/err" || fail "voxelize open"
grep -q "not closed (4 open edges)" "$tmp/err" || fail "open warning: $(cat "$tmp/err")"
"$BVOX" info "$tmp/open.nii" --json > "$tmp/info.json"
jcheck "$tmp/info.json" 'o["count"] == 64' || fail "open filled: $(cat "$tmp/info.json")"

# a sphere, smoothed: the volume stays within 2 % of the voxel volume
"$BVOX" shape sphere r=12 --dims 32,32,32 -o "$tmp/s.nii" >/dev/null || fail "shape"
"$BVOX" info "$tmp/s.nii" --json > "$tmp/info.json"
n=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["count"])' "$tmp/info.json")
"$BVOX" mesh "$tmp/s.nii" -o "$tmp/s.ply" --smooth 10 >/dev/null || fail "mesh --smooth"
"$BVOX" meshinfo "$tmp/s.ply" --json > "$tmp/mi.json"
jcheck "$tmp/mi.json" "o['watertight'] and near(o['volume'], $n, 0.02)" || fail "smooth: $(cat "$tmp/mi.json")"

# help and bad command lines: exit 2, nothing written
for c in mesh voxelize meshinfo; do
    "$BVOX" $c --help | grep -q "^Usage: bvox $c" || fail "$c --help"
done
expect2() { set +e; "$BVOX" "$@" >/dev/null 2>&1; rc=$?; set -e; [ $rc -eq 2 ] || fail "$* exited $rc, wanted 2"; }
expect2 mesh "$tmp/box.nii"
expect2 mesh "$tmp/box.nii" -o "$tmp/x.vtk"
expect2 mesh "$tmp/box.nii" -o "$tmp/x.stl" --method dual
expect2 mesh "$tmp/box.nii" -o "$tmp/x.stl" --smooth -1
expect2 voxelize "$tmp/c.stl" -o "$tmp/x.nii"
expect2 voxelize "$tmp/c.stl" -o "$tmp/x.nii" --res 10 --voxel-size 1
expect2 voxelize "$tmp/c.stl" -o "$tmp/x.nii" --res 0
expect2 meshinfo
[ ! -e "$tmp/x.stl" ] && [ ! -e "$tmp/x.nii" ] || fail "a refused command wrote a file"

# bad meshes: exit 1 with the file named
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' > "$tmp/bad.obj"
printf 'OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n' > "$tmp/nan.off"
head -c 120 "$tmp/c.stl" > "$tmp/cut.stl"
for b in bad.obj nan.off cut.stl; do
    set +e
    "$BVOX" voxelize "$tmp/$b" -o "$tmp/x.nii" --res 8 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 1 ] || fail "voxelize $b exited $rc"
    grep -q "^bvox: .*$b" "$tmp/err" || fail "$b: message does not name the file: $(cat "$tmp/err")"
    [ ! -e "$tmp/x.nii" ] || fail "$b: wrote a file"
done
echo "mesh: ok"
