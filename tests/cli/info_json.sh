#!/bin/sh
# info_json.sh — `bvox info` on small hand-made raw files whose count, bounding
# box and volume are known by construction: every binarisation mode, raw
# layout options (type, byte order, offset), the text and the --json output
# (checked key by key with python3), the same numbers after a convert to
# NIfTI, the empty volume, and JSON escaping of an awkward file name.
# Usage: sh info_json.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# 4 x 3 x 2 voxels of u8, x fastest, then y, then z. Non-zero samples:
#   (1,0,0) = 1     index 1
#   (2,1,1) = 200   index 12 + 4 + 2 = 18
#   (3,2,1) = 5     index 12 + 8 + 3 = 23
printf '\000\001\000\000\000\000\000\000\000\000\000\000' >"$tmp/a.raw"
printf '\000\000\000\000\000\000\310\000\000\000\000\005' >>"$tmp/a.raw"
[ "$(wc -c <"$tmp/a.raw")" -eq 24 ] || fail "test file has the wrong size"
RAW="--dims 4,3,2 --type u8 --voxel-size 0.5,0.5,2 --unit mm"

# check JSON KEY=VALUE...: compare keys of the one JSON object in file JSON
# with Python literals (floats compared to 1e-9 relative).
check() {
    python3 - "$@" <<'PY'
import json, math, sys
path, *pairs = sys.argv[1:]
text = open(path).read()
assert text.count("\n") == 1, "not exactly one line of JSON: %r" % text
obj = json.loads(text)
for key in ("dims", "voxel_size", "unit", "count", "volume", "bbox"):
    assert key in obj, "missing key " + key
def same(a, b):
    if isinstance(b, float) or isinstance(a, float):
        return a is not None and b is not None and math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    if isinstance(b, list):
        return isinstance(a, list) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(b, dict):
        return isinstance(a, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in b)
    return a == b and type(a) == type(b)
for pair in pairs:
    key, want = pair.split("=", 1)
    want = eval(want, {"null": None})
    if not same(obj.get(key), want):
        sys.exit("%s: %s is %r, expected %r" % (path, key, obj.get(key), want))
PY
}

# Default binarisation (non-zero): 3 voxels, bbox (1,0,0)..(3,2,1).
"$BVOX" info "$tmp/a.raw" $RAW --json >"$tmp/j1" || fail "info --json exited $?"
check "$tmp/j1" 'dims=[4,3,2]' 'voxel_size=[0.5,0.5,2.0]' 'unit="mm"' 'count=3' \
    'volume=1.5' 'bbox={"min":[1,0,0],"max":[3,2,1]}' 'format="raw"' \
    'origin=[0.0,0.0,0.0]' 'bbox_physical={"min":[0.25,-0.25,-1.0],"max":[1.75,1.25,3.0]}' \
    || fail "nonzero"
"$BVOX" info "$tmp/a.raw" $RAW --nonzero --json >"$tmp/j" && check "$tmp/j" 'count=3' || fail "--nonzero"
# --threshold T keeps value >= T: only the 200.
"$BVOX" info "$tmp/a.raw" $RAW --threshold 200 --json >"$tmp/j" &&
    check "$tmp/j" 'count=1' 'bbox={"min":[2,1,1],"max":[2,1,1]}' 'volume=0.5' || fail "--threshold"
"$BVOX" info "$tmp/a.raw" $RAW --threshold=201 --json >"$tmp/j" &&
    check "$tmp/j" 'count=0' 'bbox=null' 'volume=0.0' || fail "--threshold="
# --range LO:HI inclusive: 1 and 5.
"$BVOX" info "$tmp/a.raw" $RAW --range 1:5 --json >"$tmp/j" &&
    check "$tmp/j" 'count=2' 'bbox={"min":[1,0,0],"max":[3,2,1]}' || fail "--range"
"$BVOX" info "$tmp/a.raw" $RAW --range 2:5 --json >"$tmp/j" &&
    check "$tmp/j" 'count=1' 'bbox={"min":[3,2,1],"max":[3,2,1]}' || fail "--range 2:5"
# --label N: exactly N.
"$BVOX" info "$tmp/a.raw" $RAW --label 5 --json >"$tmp/j" &&
    check "$tmp/j" 'count=1' 'bbox={"min":[3,2,1],"max":[3,2,1]}' || fail "--label"
# --otsu on {0 x21, 1, 5, 200}: any sensible threshold separates 200 from the rest.
"$BVOX" info "$tmp/a.raw" $RAW --otsu --json >"$tmp/j" &&
    check "$tmp/j" 'count=1' 'bbox={"min":[2,1,1],"max":[2,1,1]}' || fail "--otsu"
# No unit and no voxel size: unit cubes, volume == count.
"$BVOX" info "$tmp/a.raw" --dims 4,3,2 --type u8 --json >"$tmp/j" &&
    check "$tmp/j" 'voxel_size=[1.0,1.0,1.0]' 'unit=""' 'count=3' 'volume=3.0' \
        'volume_unit="voxel^3"' || fail "no unit"

# Raw layout: a 4-byte header, then u16 big-endian samples 2 x 1 x 1.
# Big-endian 0x0100 = 256 and 0x0001 = 1; read little-endian they would be
# 1 and 256, so the threshold tells the byte order apart.
printf 'HDR!\001\000\000\001' >"$tmp/b.raw"
"$BVOX" info "$tmp/b.raw" --dims 2,1,1 --type u16 --endian big --offset 4 --threshold 100 \
    --json >"$tmp/j" && check "$tmp/j" 'count=1' 'bbox={"min":[0,0,0],"max":[0,0,0]}' ||
    fail "u16 big endian"
"$BVOX" info "$tmp/b.raw" --dims 2,1,1 --type uint16 --endian little --offset=4 \
    --threshold 100 --json >"$tmp/j" && check "$tmp/j" 'count=1' \
    'bbox={"min":[1,0,0],"max":[1,0,0]}' || fail "u16 little endian"

# Text output: aligned "key: value" lines with the same numbers.
"$BVOX" info "$tmp/a.raw" $RAW >"$tmp/t" || fail "info text exited $?"
grep -q '^dimensions: *4 x 3 x 2 voxels$' "$tmp/t" || fail "text dimensions: $(cat "$tmp/t")"
grep -q '^voxel size: *0.5 x 0.5 x 2 mm$' "$tmp/t" || fail "text voxel size"
grep -q '^count: *3 voxels' "$tmp/t" || fail "text count"
grep -q '^volume: *1.5 mm^3$' "$tmp/t" || fail "text volume"
grep -q '^bounding box: *x 1..3, y 0..2, z 0..1 ' "$tmp/t" || fail "text bbox"
col=$(sed 's/^\([a-z ]*: *\).*/\1/' "$tmp/t" | awk '{ print length($0) }' | sort -u)
[ "$col" = 14 ] || fail "text values are not aligned in one column: $col"

# Through NIfTI: the voxel size, unit and voxels survive convert.
"$BVOX" convert "$tmp/a.raw" "$tmp/a.nii" $RAW || fail "convert to nii exited $?"
"$BVOX" info "$tmp/a.nii" --json >"$tmp/j" &&
    check "$tmp/j" 'dims=[4,3,2]' 'voxel_size=[0.5,0.5,2.0]' 'unit="mm"' 'count=3' \
        'volume=1.5' 'bbox={"min":[1,0,0],"max":[3,2,1]}' 'format="nifti"' || fail "via nii"
# A gray threshold applied while converting: the file holds only the result.
"$BVOX" convert "$tmp/a.raw" "$tmp/t200.nii.gz" $RAW --threshold 200 || fail "convert --threshold"
"$BVOX" info "$tmp/t200.nii.gz" --json >"$tmp/j" && check "$tmp/j" 'count=1' || fail "t200"

# An all-zero volume: count 0, bbox null (text: none).
printf '\000\000\000\000\000\000\000\000' >"$tmp/z.raw"
"$BVOX" info "$tmp/z.raw" --dims 2,2,2 --type u8 --json >"$tmp/j" &&
    check "$tmp/j" 'count=0' 'bbox=null' 'bbox_physical=null' 'volume=0.0' || fail "empty"
"$BVOX" info "$tmp/z.raw" --dims 2,2,2 --type u8 | grep -q '^bounding box: *none' ||
    fail "empty text"

# JSON escaping: a file name with a quote, a backslash and a tab.
name=$(printf 'q"b\\s\tt.nii')
cp "$tmp/a.nii" "$tmp/$name"
"$BVOX" info "$tmp/$name" --json >"$tmp/j" || fail "info on an awkward name exited $?"
python3 - "$tmp/j" "$tmp/$name" <<'PY' || fail "file name not escaped"
import json, sys
obj = json.loads(open(sys.argv[1]).read())
assert obj["file"] == sys.argv[2], (obj["file"], sys.argv[2])
assert obj["count"] == 3
PY
echo "ok"
