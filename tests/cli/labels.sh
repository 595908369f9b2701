#!/bin/sh
# labels.sh — `bvox labels` through the real command: on a hand-made label
# volume (three labels, one with a cavity filled by another, anisotropic
# voxels) every number of every row equals what `bvox measure FILE --label N
# --json` says for that label; neighbours and contact areas computed by
# hand; CSV rows; a lookup table with a duplicate and a missing label warns
# and still names the rest; --max-labels, float labels, binary formats and
# bad command lines are refused with a clear message (exit 1 / 2).
# Usage: sh labels.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# 12 x 10 x 9 voxels of 0.5 x 1 x 2 mm, u16:
#   label 4:  a 5x5x5 cube at x 1..5, y 1..5, z 1..5 whose centre voxel is label 9
#   label 9:  that one voxel (6 faces with 4)
#   label 300: a 3x2x2 box at x 6..8, y 1..2, z 1..2 touching 4 across x:
#              2*2 = 4 faces of 1*2 = 2 mm^2 -> 8 mm^2
python3 - "$tmp/lab.raw" <<'PY'
import struct, sys
nx, ny, nz = 12, 10, 9
v = [0] * (nx * ny * nz)
def put(x, y, z, l): v[(z * ny + y) * nx + x] = l
for z in range(1, 6):
    for y in range(1, 6):
        for x in range(1, 6):
            put(x, y, z, 4)
put(3, 3, 3, 9)
for z in range(1, 3):
    for y in range(1, 3):
        for x in range(6, 9):
            put(x, y, z, 300)
open(sys.argv[1], "wb").write(struct.pack("<%dH" % len(v), *v))
PY
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --voxel-size 0.5,1,2 --unit mm \
    --json >"$tmp/j" 2>"$tmp/err" || fail "labels --json on raw exited $?: $(cat "$tmp/err")"
"$BVOX" convert "$tmp/lab.raw" "$tmp/all.nii" --dims 12,10,9 --type u16 --voxel-size 0.5,1,2 \
    --unit mm --range 1:1000 || fail "convert"
jcheck "$tmp/j" '[l["label"] for l in o["labels"]] == [4, 9, 300]' || fail "labels listed"
jcheck "$tmp/j" 'o["background"] == 12 * 10 * 9 - 125 - 12' || fail "background count"
jcheck "$tmp/j" '[l["count"] for l in o["labels"]] == [124, 1, 12]' || fail "counts"
jcheck "$tmp/j" 'o["labels"][0]["cavities"] == 1 and o["labels"][1]["cavities"] == 0' ||
    fail "the cavity of label 4"
# neighbours: 4 touches 9 (6 faces: 2 of 1*2, 2 of 0.5*2, 2 of 0.5*1 = 4+2+1 = 7 mm^2)
# and 300 (4 faces across x, 1*2 each = 8 mm^2)
jcheck "$tmp/j" '[(n["label"], n["faces"]) for n in o["labels"][0]["neighbours"]] == [(9, [2, 2, 2]), (300, [4, 0, 0])]' ||
    fail "neighbours of 4"
jcheck "$tmp/j" 'near(o["labels"][0]["neighbours"][0]["contact_area"], 7) and near(o["labels"][0]["neighbours"][1]["contact_area"], 8)' ||
    fail "contact areas"
jcheck "$tmp/j" '[n["label"] for n in o["labels"][2]["neighbours"]] == [4]' || fail "neighbours of 300"

# Every number equals `bvox measure --label N` on the same file.
for l in 4 9 300; do
    "$BVOX" measure "$tmp/lab.raw" --dims 12,10,9 --type u16 --voxel-size 0.5,1,2 --unit mm \
        --label $l --json >"$tmp/m$l" || fail "measure --label $l exited $?"
    python3 - "$tmp/j" "$tmp/m$l" "$l" <<'PY' || fail "labels and measure --label $l differ"
import json, math, sys
o = json.load(open(sys.argv[1]))
m = json.load(open(sys.argv[2]))
row = [r for r in o["labels"] if r["label"] == int(sys.argv[3])][0]
def near(a, b):
    if isinstance(b, list):
        return len(a) == len(b) and all(near(x, y) for x, y in zip(a, b))
    if b is None or a is None:
        return a is b
    if isinstance(b, dict):
        return a.keys() == b.keys() and all(near(a[k], b[k]) for k in b)
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
keys = ["count", "volume", "surface_area", "surface_area_faces", "faces", "centroid", "bbox",
        "principal_moments", "equivalent_diameter", "sphericity", "components", "cavities",
        "cavities_26", "tunnels", "euler"]
for k in keys:
    assert near(row[k], m[k]), (k, row[k], m[k])
PY
done

# CSV: a header and one row per label; neighbours as label:area pairs.
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --voxel-size 0.5,1,2 --unit mm --csv \
    >"$tmp/c" || fail "labels --csv exited $?"
[ "$(wc -l <"$tmp/c")" -eq 4 ] || fail "csv rows: $(cat "$tmp/c")"
head -1 "$tmp/c" | grep -q '^label,name,voxels,volume,surface_area,' || fail "csv header"
grep -q '^4,,124,124,.*,9:7;300:8,1$' "$tmp/c" || fail "csv row of 4: $(cat "$tmp/c")"

# A table with a duplicate (4), a name with a comma, and label 300 missing:
# warnings on stderr, names for the rest, exit 0.
printf '# test table\n4 Cortex 255 0 0 0\n4 Again 0 0 255 0\n9 "Core, inner" 0 255 0 0\n' \
    >"$tmp/lut.txt"
printf '    9   0 255 0   1  1  1  "Core, inner"\n    4 255 0 0   1  1  1  "Cortex"\n    4 0 0 255  1 1 1 "Again"\n' \
    >"$tmp/itk.txt"
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --lut "$tmp/itk.txt" --csv \
    >"$tmp/c2" 2>"$tmp/err" || fail "labels --lut exited $?: $(cat "$tmp/err")"
grep -q "^bvox: warning: .*itk.txt:3: label 4 is listed again" "$tmp/err" ||
    fail "no duplicate warning: $(cat "$tmp/err")"
grep -q "^bvox: warning: label 300 is not in .*itk.txt" "$tmp/err" ||
    fail "no missing-label warning: $(cat "$tmp/err")"
grep -q '^4,Cortex,124,' "$tmp/c2" || fail "name of 4: $(cat "$tmp/c2")"
grep -q '^9,"Core, inner",1,' "$tmp/c2" || fail "quoted name of 9: $(cat "$tmp/c2")"
grep -q '^300,,12,' "$tmp/c2" || fail "unnamed 300: $(cat "$tmp/c2")"
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --lut "$tmp/itk.txt" --json \
    >"$tmp/j2" 2>/dev/null || fail "labels --lut --json"
jcheck "$tmp/j2" 'o["labels"][0]["color"] == [255, 0, 0, 255] and o["labels"][2]["color"] is None' ||
    fail "colours"
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --lut "$tmp/itk.txt" >"$tmp/t" 2>/dev/null ||
    fail "labels text"
grep -q '^ *4  Cortex  *124 ' "$tmp/t" || fail "text row: $(cat "$tmp/t")"

# --voxel-size overrides the file's, as for every command that reads.
"$BVOX" labels "$tmp/all.nii" --voxel-size 2,2,2 --unit um --json >"$tmp/j3" ||
    fail "labels --voxel-size exited $?"
jcheck "$tmp/j3" 'o["unit"] == "um" and o["labels"][0]["count"] == 137 and near(o["labels"][0]["volume"], 137 * 8)' ||
    fail "voxel size override"
jcheck "$tmp/j3" 'near(o["labels"][0]["centroid"][0], 2 * o["labels"][0]["centroid"][0] / 2) and o["labels"][0]["bbox"]["min"] == [1, 1, 1]' ||
    fail "override bbox"

# Per-label meshes: one file per label in a new folder, named after the
# label and its table name; a list picks labels; mc and smoothing refused.
"$BVOX" mesh "$tmp/lab.raw" --dims 12,10,9 --type u16 --labels all --lut "$tmp/itk.txt" \
    -o "$tmp/meshes" >"$tmp/o" 2>/dev/null || fail "mesh --labels all exited $?"
[ "$(ls "$tmp/meshes" | tr '\n' ' ')" = "300.ply 4_Cortex.ply 9_Core_inner.ply " ] ||
    fail "mesh files: $(ls "$tmp/meshes")"
grep -q "3 meshes" "$tmp/o" || fail "mesh summary: $(cat "$tmp/o")"
"$BVOX" meshinfo "$tmp/meshes/9_Core_inner.ply" --json >"$tmp/mi" || fail "meshinfo"
jcheck "$tmp/mi" 'o["triangles"] == 12 and near(o["volume"], 1)' || fail "mesh of 9: $(cat "$tmp/mi")"
"$BVOX" mesh "$tmp/all.nii" --labels 1 --mesh-format obj -o "$tmp/m2/" >/dev/null ||
    fail "mesh --labels 1"
[ -f "$tmp/m2/1.obj" ] || fail "mesh --labels 1: $(ls "$tmp/m2")"
for args in "--labels 1 --method mc -o $tmp/m3" "--labels 1 --smooth 3 -o $tmp/m3" \
    "--labels 1" "--lut $tmp/itk.txt -o $tmp/m3" "--labels 1,x -o $tmp/m3"; do
    set +e
    # shellcheck disable=SC2086
    "$BVOX" mesh "$tmp/all.nii" $args >/dev/null 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "mesh $args exited $rc (want 2): $(cat "$tmp/err")"
done
set +e
"$BVOX" mesh "$tmp/all.nii" --labels 5 -o "$tmp/m3" >/dev/null 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 1 ] && grep -q "no voxel has label 5" "$tmp/err" || fail "mesh --labels 5: $rc $(cat "$tmp/err")"
[ ! -e "$tmp/m3" ] || fail "a folder was left behind"

# One file, one coloured object per label: PLY (ascii) with the table's
# colours on vertices and faces and a label per face; OBJ + MTL. Each object
# is the label's closed surface (shared faces in both), so the file's volume
# is the sum of the labels' voxel volumes: 124 + 1 + 12.
"$BVOX" --quiet mesh "$tmp/lab.raw" --dims 12,10,9 --type u16 --labels all --lut "$tmp/itk.txt" \
    --ascii -o "$tmp/all.ply" >"$tmp/o" || fail "mesh --labels all -o all.ply exited $?"
grep -q "3 labels in one file" "$tmp/o" || fail "one-file summary: $(cat "$tmp/o")"
python3 - "$tmp/all.ply" <<'PY' || fail "all.ply content"
import sys
lines = open(sys.argv[1]).read().split("\n")
end = lines.index("end_header")
head = lines[:end]
assert "comment object 4_Cortex: " in "\n".join(head)
nv = int([l for l in head if l.startswith("element vertex")][0].split()[2])
body = lines[end + 1:]
faces = [l.split() for l in body[nv:] if l]
by_label = {}
for f in faces:
    by_label.setdefault(int(f[7]), set()).add(tuple(f[4:7]))
# one colour per label: the table's for 4 and 9, bvox's palette for 300
assert by_label[4] == {("255", "0", "0")}, by_label[4]
assert by_label[9] == {("0", "255", "0")}, by_label[9]
assert len(by_label[300]) == 1 and sorted(by_label) == [4, 9, 300]
# label 9 (one voxel) is 12 triangles, and label 4 holds the same 12 faces
# (its cavity) besides its outside
assert sum(1 for f in faces if f[7] == "9") == 12
PY
"$BVOX" meshinfo "$tmp/all.ply" --json >"$tmp/mi" || fail "meshinfo all.ply"
jcheck "$tmp/mi" 'near(o["volume"], 137)' || fail "volume of all.ply: $(cat "$tmp/mi")"
"$BVOX" --quiet mesh "$tmp/lab.raw" --dims 12,10,9 --type u16 --labels 4,300 -o "$tmp/two.obj" \
    >/dev/null || fail "-o two.obj"
[ "$(grep -c '^o ' "$tmp/two.obj")" = 2 ] && grep -q '^mtllib two.mtl$' "$tmp/two.obj" &&
    [ "$(grep -c '^Kd ' "$tmp/two.mtl")" = 2 ] || fail "two.obj/two.mtl"

# Bad input: too many labels, float labels that are not integers, binary
# formats, a missing table, bad command lines.
set +e
"$BVOX" labels "$tmp/lab.raw" --dims 12,10,9 --type u16 --max-labels 2 >"$tmp/o" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 1 ] || fail "--max-labels 2 exited $rc"
grep -q '^bvox: .*lab.raw: more than 2 distinct labels' "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -s "$tmp/o" ] || fail "output despite the refusal"
python3 -c "
import struct; open('$tmp/f.raw','wb').write(struct.pack('<8f', 0, 1, 2, 2.5, 0, 0, 0, 1))"
set +e
"$BVOX" labels "$tmp/f.raw" --dims 2,2,2 --type f32 >/dev/null 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 1 ] || fail "float labels exited $rc"
grep -q '^bvox: .*f.raw: voxel (1, 1, 0) is not an integer label' "$tmp/err" ||
    fail "float message: $(cat "$tmp/err")"
"$BVOX" convert "$tmp/all.nii" "$tmp/all.binvox" || fail "convert binvox"
for args in "$tmp/all.binvox" "$tmp/lab.raw --dims 12,10,9 --type u16 --lut $tmp/none.txt"; do
    set +e
    # shellcheck disable=SC2086
    "$BVOX" labels $args >/dev/null 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 1 ] || fail "labels $args exited $rc"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q '^bvox: ' "$tmp/err" || fail "message: $(cat "$tmp/err")"
done
for args in "" "$tmp/all.nii --json --csv" "$tmp/all.nii --label 4" "$tmp/all.nii --max-labels 0" \
    "$tmp/all.nii --lut"; do
    set +e
    # shellcheck disable=SC2086
    "$BVOX" labels $args >/dev/null 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "labels $args exited $rc (want 2)"
done
"$BVOX" labels --help | grep -q -- '--max-labels' || fail "help"
echo "labels: ok"
