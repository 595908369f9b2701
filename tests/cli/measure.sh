#!/bin/sh
# measure.sh — `bvox measure` through the real command on hand-made volumes
# with known answers: a box of anisotropic voxels (voxel-face area, centroid,
# principal axes and moments computed by hand), a set of four objects with a
# cavity and a tunnel (components, cavities, tunnels, Euler number; one CSV
# row per component, largest first), the JSON holding every key of
# `bvox info --json` with the same values and in the same order, the empty
# volume, and bad command lines (exit 2) and files (exit 1).
# Usage: sh measure.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# A box of 4 x 3 x 2 voxels (x 1..4, y 1..3, z 1..2) of 0.5 x 0.5 x 2 mm.
# Voxel faces: x 2*3*2 = 12 of 0.5*2 = 1 mm^2, y 2*4*2 = 16 of 1 mm^2,
# z 2*4*3 = 24 of 0.25 mm^2: 34 mm^2. Centroid: indices (2.5, 2, 1.5) times
# the voxel size. Variances: x var{1..4} * 0.25 = 0.3125, y var{1..3} * 0.25
# = 1/6, z var{1,2} * 4 = 1: the axes are z, x, y in that order.
mk box 6 5 4 '1 <= x <= 4 and 1 <= y <= 3 and 1 <= z <= 2' --voxel-size 0.5,0.5,2 --unit mm
"$BVOX" measure "$tmp/box.nii" --json >"$tmp/j" || fail "measure --json exited $?"
"$BVOX" info "$tmp/box.nii" --json >"$tmp/info" || fail "info --json exited $?"
python3 - "$tmp/j" "$tmp/info" <<'PY' || fail "measure does not start with info's keys"
import json, sys
m = json.loads(open(sys.argv[1]).read())
i = json.loads(open(sys.argv[2]).read())
assert list(m)[:len(i)] == list(i), (list(m), list(i))
for k in i:
    assert m[k] == i[k], (k, m[k], i[k])
for k in ("surface_area", "centroid", "principal_axes", "components"):
    assert k in m, "missing " + k
PY
jcheck "$tmp/j" 'o["count"] == 24 and o["volume"] == 12 and o["unit"] == "mm"' || fail "box count"
jcheck "$tmp/j" 'o["faces"] == [12, 16, 24] and near(o["surface_area_faces"], 34)' ||
    fail "box faces"
jcheck "$tmp/j" 'o["area_unit"] == "mm^2"' || fail "area unit"
# The smooth estimate lies below the staircase of voxel faces.
jcheck "$tmp/j" '0 < o["surface_area"] < o["surface_area_faces"]' || fail "box surface_area"
jcheck "$tmp/j" 'near(o["centroid"], [1.25, 1.0, 3.0])' || fail "box centroid"
jcheck "$tmp/j" 'near(o["principal_axes"], [[0, 0, 1], [1, 0, 0], [0, 1, 0]])' || fail "box axes"
jcheck "$tmp/j" 'near(o["principal_moments"], [1, 0.3125, 1 / 6])' || fail "box moments"
jcheck "$tmp/j" 'near(o["covariance"], [[0.3125, 0, 0], [0, 1 / 6, 0], [0, 0, 1]])' ||
    fail "box covariance"
jcheck "$tmp/j" '(o["components"], o["cavities"], o["tunnels"], o["euler"]) == (1, 0, 0, 1)' ||
    fail "box topology"
# Text: the info lines and the measures, aligned in one column.
"$BVOX" measure "$tmp/box.nii" >"$tmp/t" || fail "measure text exited $?"
grep -q '^count: *24 voxels' "$tmp/t" || fail "text count: $(cat "$tmp/t")"
grep -q '^centroid: *1.25, 1, 3 mm$' "$tmp/t" || fail "text centroid: $(cat "$tmp/t")"
grep -q '^surface area: .* mm^2 (area of the voxel faces: 34 mm^2)$' "$tmp/t" || fail "text area: $(cat "$tmp/t")"
grep -q '^axis 1: *(0.0000, 0.0000, 1.0000), sd 1 mm$' "$tmp/t" || fail "text axis 1"
grep -q '^components: *1 ' "$tmp/t" || fail "text components"
col=$(sed 's/^\([a-z. 0-9]*: *\).*/\1/' "$tmp/t" | awk '{ print length($0) }' | sort -u)
[ "$col" = 14 ] || fail "text values are not aligned in one column: $col"

# Four objects in 16^3 unit voxels:
#   A  a 5^3 cube with a 3^3 cavity (98 voxels; 1 cavity)
#   B  a square ring of 8 in slice z = 1 (1 tunnel)
#   C  a bar of 3
#   D  one voxel
# components 4, cavities 1, tunnels 1, euler = 4 - 1 + 1 = 4.
SET='(1 <= min(x, y, z) and max(x, y, z) <= 5 and not (2 <= min(x, y, z) and max(x, y, z) <= 4))'
SET="$SET"' or (8 <= x <= 10 and 1 <= y <= 3 and z == 1 and (x, y) != (9, 2))'
SET="$SET"' or (1 <= x <= 3 and y == 10 and z == 10) or (x, y, z) == (12, 12, 12)'
mk set 16 16 16 "$SET"
"$BVOX" measure "$tmp/set.nii" --json >"$tmp/j" || fail "measure set exited $?"
jcheck "$tmp/j" 'o["count"] == 110' || fail "set count"
jcheck "$tmp/j" '(o["components"], o["cavities"], o["tunnels"], o["euler"]) == (4, 1, 1, 4)' ||
    fail "set topology"
jcheck "$tmp/j" 'o["area_unit"] == "voxel^2"' || fail "area unit without a unit"
jcheck "$tmp/j" 'o["cavities_6"] == 1 and o["cavities_26"] == 1' || fail "set cavities by connectivity"

# Two hollow voxels that touch only at a corner, inside a 7^3 block: two
# cavities for a 6-connected background, one for a 26-connected one. 341
# voxels: too few for a sphericity estimate (null); a ball of radius 10
# (4224 voxels, whose Crofton estimate reads 1.003) is reported as 1.
mk diag 9 9 9 '1 <= min(x, y, z) and max(x, y, z) <= 7 and (x, y, z) not in ((3, 3, 3), (4, 4, 4))'
"$BVOX" measure "$tmp/diag.nii" --json >"$tmp/j" || fail "measure diag exited $?"
jcheck "$tmp/j" '(o["cavities"], o["cavities_6"], o["cavities_26"]) == (2, 2, 1)' ||
    fail "diagonal cavities: $(cat "$tmp/j")"
jcheck "$tmp/j" 'o["sphericity"] is None' || fail "sphericity of 341 voxels is not null"
"$BVOX" measure "$tmp/diag.nii" >"$tmp/t" || fail "measure diag text"
grep -q '^cavities:     2 (6-connected background; 26-connected: 1)$' "$tmp/t" ||
    fail "cavities text: $(cat "$tmp/t")"
grep -q '^sphericity:   n/a' "$tmp/t" || fail "sphericity text: $(cat "$tmp/t")"
"$BVOX" shape sphere r=10 --dims 40,40,40 -o "$tmp/ball.nii" || fail "ball"
"$BVOX" measure "$tmp/ball.nii" --json >"$tmp/j" || fail "measure ball"
jcheck "$tmp/j" 'o["count"] == 4224 and o["sphericity"] == 1' || fail "ball sphericity: $(cat "$tmp/j")"
"$BVOX" measure "$tmp/set.nii" --csv >"$tmp/c" || fail "measure --csv exited $?"
python3 - "$tmp/c" <<'PY' || fail "set CSV: $(cat "$tmp/c")"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 4, len(rows)  # one per component, after the header
assert [int(r["voxels"]) for r in rows] == [98, 8, 3, 1], [r["voxels"] for r in rows]
assert [int(r["component"]) for r in rows] == [1, 2, 3, 4]
assert [int(r["cavities"]) for r in rows] == [1, 0, 0, 0]
assert [int(r["tunnels"]) for r in rows] == [0, 1, 0, 0]
assert [int(r["euler"]) for r in rows] == [2, 0, 1, 1]
a, b = rows[0], rows[1]
assert (float(a["centroid_x"]), float(a["centroid_y"]), float(a["centroid_z"])) == (3, 3, 3)
assert [int(a[k]) for k in ("bbox_min_x", "bbox_min_y", "bbox_min_z", "bbox_max_x",
                            "bbox_max_y", "bbox_max_z")] == [1, 1, 1, 5, 5, 5]
assert [int(b[k]) for k in ("bbox_min_x", "bbox_min_y", "bbox_min_z", "bbox_max_x",
                            "bbox_max_y", "bbox_max_z")] == [8, 1, 1, 10, 3, 1]
assert float(rows[2]["volume"]) == 3 and float(rows[3]["surface_area_faces"]) == 6
# the bar lies along x
assert (float(rows[2]["axis1_x"]), float(rows[2]["axis1_y"]), float(rows[2]["axis1_z"])) == (1, 0, 0)
PY
# Row count = component count on a real-looking object too.
"$BVOX" demo -o "$tmp/demo" >/dev/null 2>&1 || fail "demo -o"
"$BVOX" measure "$tmp/demo/specimen.nii.gz" --json >"$tmp/j" || fail "measure demo exited $?"
"$BVOX" measure "$tmp/demo/specimen.nii.gz" --csv >"$tmp/c" || fail "measure demo --csv exited $?"
n=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["components"])' "$tmp/j")
[ "$(($(wc -l <"$tmp/c") - 1))" = "$n" ] || fail "demo: CSV rows != $n components"

# An empty volume: zeros, and null where there is no value.
mk empty 3 3 3 'False'
"$BVOX" measure "$tmp/empty.nii" --json >"$tmp/j" || fail "measure empty exited $?"
jcheck "$tmp/j" 'o["count"] == 0 and o["surface_area"] == 0 and o["components"] == 0' ||
    fail "empty"
jcheck "$tmp/j" 'o["centroid"] is None and o["principal_axes"] is None and o["bbox"] is None' ||
    fail "empty nulls"
"$BVOX" measure "$tmp/empty.nii" --csv >"$tmp/c" || fail "empty --csv"
[ "$(wc -l <"$tmp/c")" = 1 ] || fail "empty CSV has rows"
"$BVOX" measure "$tmp/empty.nii" >/dev/null || fail "empty text"

# Read options apply: the raw file, read with --dims and --type.
"$BVOX" measure "$tmp/set.raw" --dims 16,16,16 --type u8 --json >"$tmp/j" &&
    jcheck "$tmp/j" 'o["count"] == 110 and o["format"] == "raw"' || fail "measure raw"

"$BVOX" measure --help >"$tmp/help" || fail "--help exited $?"
for word in --json --csv surface; do
    grep -q -- "$word" "$tmp/help" || fail "--help does not mention $word"
done

# Bad command lines: exit 2; bad files: exit 1; one "bvox: " line, no stdout.
expect() {
    want=$1
    shift
    set +e
    "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "$*: exit $rc, expected $want ($(cat "$tmp/stderr"))"
    [ ! -s "$tmp/stdout" ] || fail "$*: wrote to stdout"
    [ "$(wc -l <"$tmp/stderr")" -eq 1 ] || fail "$*: stderr is not one line: $(cat "$tmp/stderr")"
    grep -q '^bvox: ' "$tmp/stderr" || fail "$*: stderr is not 'bvox: ...'"
}
expect 2 "$BVOX" measure
expect 2 "$BVOX" measure "$tmp/box.nii" --json --csv
expect 2 "$BVOX" measure "$tmp/box.nii" "$tmp/set.nii"
expect 2 "$BVOX" measure "$tmp/box.nii" --xml
expect 2 "$BVOX" measure "$tmp/box.nii" --threshold
expect 1 "$BVOX" measure "$tmp/nope.nii" --json
head -c 360 "$tmp/box.nii" >"$tmp/short.nii"
expect 1 "$BVOX" measure "$tmp/short.nii" --csv
printf 'not a volume\n' >"$tmp/text.nii"
expect 1 "$BVOX" measure "$tmp/text.nii"
echo "ok"
