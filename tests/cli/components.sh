#!/bin/sh
# components.sh — `bvox components` through the real command on a
# constructed set whose components differ by connectivity (a 2^3 cube, a bar
# of 3, two voxels sharing an edge, two sharing a corner: 6/5/4 components
# with --conn 6/18/26): the JSON's keys, order (largest first, ties by first
# voxel), voxels, volumes and inclusive boxes; the text table; --keep-largest
# with -o; --labels read back label by label with `bvox info --label K`
# (uint16, and uint32 past 65535 labels); bad command lines (exit 2) and bad
# files (exit 1), neither writing anything.
# Usage: sh components.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

count() {
    "$BVOX" info "$@" --json >"$tmp/ij" || fail "info $* exited $?"
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["count"])' "$tmp/ij"
}

# 8^3, voxels 0.5 x 0.5 x 2 mm (0.5 mm^3 each):
#   A  cube x,y,z in 0..1                       8 voxels
#   B  bar (5..7, 0, 0)                         3
#   C  (0,5,5) and (1,6,5): share an edge       2 with 18/26, else 1 + 1
#   D  (5,4,6) and (6,5,7): share a corner      2 with 26, else 1 + 1
# Ties (C, D with 26) go to the first voxel in column order (y, then x):
# D's (5,4) comes before C's (0,5).
SET='(x <= 1 and y <= 1 and z <= 1) or (y == 0 and z == 0 and x >= 5) or (x, y, z) in ((0, 5, 5), (1, 6, 5), (5, 4, 6), (6, 5, 7))'
mk set 8 8 8 "$SET" --voxel-size 0.5,0.5,2 --unit mm
[ "$(count "$tmp/set.nii")" = 15 ] || fail "test set"

"$BVOX" components "$tmp/set.nii" --json >"$tmp/j26" || fail "components --json exited $?"
jcheck "$tmp/j26" 'list(o) == ["count", "component_count", "input", "output", "components"] and o["input"] == sys.argv[1].replace("/j26", "/set.nii") and o["output"] is None and o["component_count"] == o["count"]' || fail "top-level keys"
jcheck "$tmp/j26" 'all(list(c) == ["voxels", "volume", "bbox"] for c in o["components"])' ||
    fail "component keys"
jcheck "$tmp/j26" 'o["count"] == 4 == len(o["components"])' || fail "26: count"
jcheck "$tmp/j26" '[c["voxels"] for c in o["components"]] == [8, 3, 2, 2]' || fail "26: sizes"
jcheck "$tmp/j26" '[c["volume"] for c in o["components"]] == [4, 1.5, 1, 1]' || fail "26: volumes"
jcheck "$tmp/j26" '[c["bbox"] for c in o["components"]] == [
    {"min": [0, 0, 0], "max": [1, 1, 1]}, {"min": [5, 0, 0], "max": [7, 0, 0]},
    {"min": [5, 4, 6], "max": [6, 5, 7]}, {"min": [0, 5, 5], "max": [1, 6, 5]}]' ||
    fail "26: boxes (inclusive, ties by first voxel)"
"$BVOX" components "$tmp/set.nii" --conn 26 --json >"$tmp/j" && cmp -s "$tmp/j" "$tmp/j26" ||
    fail "--conn 26 is not the default"
"$BVOX" components "$tmp/set.nii" --conn 18 --json >"$tmp/j18" || fail "--conn 18 exited $?"
jcheck "$tmp/j18" '[c["voxels"] for c in o["components"]] == [8, 3, 2, 1, 1]' || fail "18: sizes"
jcheck "$tmp/j18" 'o["components"][2]["bbox"] == {"min": [0, 5, 5], "max": [1, 6, 5]}' ||
    fail "18: the edge pair"
"$BVOX" components "$tmp/set.nii" --conn=6 --json >"$tmp/j6" || fail "--conn 6 exited $?"
jcheck "$tmp/j6" 'o["count"] == 6 and [c["voxels"] for c in o["components"]] == [8, 3, 1, 1, 1, 1]' ||
    fail "6: sizes"
jcheck "$tmp/j6" 'sum(c["voxels"] for c in o["components"]) == 15' || fail "6: total"

# Text: a summary line and one row per component.
"$BVOX" components "$tmp/set.nii" >"$tmp/t" || fail "components text exited $?"
grep -q '^components: *4 (26-connected)$' "$tmp/t" || fail "text summary: $(cat "$tmp/t")"
[ "$(grep -c '^ *[0-9]\+ \+[0-9]\+ ' "$tmp/t")" = 4 ] || fail "text rows: $(cat "$tmp/t")"
grep -q '^ *1 \+8 \+4 \+x 0\.\.1, y 0\.\.1, z 0\.\.1$' "$tmp/t" || fail "text first row: $(cat "$tmp/t")"

# --keep-largest N -o OUT: the N largest as a volume, geometry kept.
"$BVOX" components "$tmp/set.nii" --keep-largest 2 -o "$tmp/k2.nii" --json >"$tmp/j" ||
    fail "--keep-largest exited $?"
jcheck "$tmp/j" 'o["count"] == 4' || fail "--keep-largest still reports every component"
[ "$(count "$tmp/k2.nii")" = 11 ] || fail "--keep-largest 2"
jcheck "$tmp/ij" 'o["bbox"] == {"min": [0, 0, 0], "max": [7, 1, 1]} and o["voxel_size"] == [0.5, 0.5, 2]' ||
    fail "--keep-largest 2 box or geometry"
"$BVOX" components "$tmp/set.nii" --keep-largest 1 --output "$tmp/k1.tif" --conn 6 >/dev/null ||
    fail "--keep-largest 1 to tif"
[ "$(count "$tmp/k1.tif")" = 8 ] || fail "--keep-largest 1"
"$BVOX" components "$tmp/set.nii" --keep-largest 99 -o "$tmp/k99.nii" >/dev/null || fail "keep 99"
[ "$(count "$tmp/k99.nii")" = 15 ] || fail "--keep-largest more than there are"

# --labels: label K read back is exactly component K's voxels; 0 beyond.
for conn in 6 26; do
    "$BVOX" components "$tmp/set.nii" --conn $conn --labels "$tmp/l$conn.nii" --json \
        >"$tmp/j" || fail "--labels exited $?"
    n=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["count"])' "$tmp/j")
    k=1
    while [ $k -le "$n" ]; do
        want=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["components"][int(sys.argv[2]) - 1]["voxels"])' "$tmp/j" $k)
        got=$(count "$tmp/l$conn.nii" --label $k)
        [ "$got" = "$want" ] || fail "--conn $conn label $k has $got voxels, component has $want"
        jcheck "$tmp/ij" 'o["voxel_size"] == [0.5, 0.5, 2] and o["unit"] == "mm"' ||
            fail "labels geometry"
        k=$((k + 1))
    done
    [ "$(count "$tmp/l$conn.nii" --label $((n + 1)))" = 0 ] || fail "label past the count"
    [ "$(count "$tmp/l$conn.nii")" = 15 ] || fail "labels: non-zero voxels"
done
# The box of label 3 (26) is that of the third component (the corner pair).
"$BVOX" info "$tmp/l26.nii" --label 3 --json >"$tmp/j" &&
    jcheck "$tmp/j" 'o["bbox"] == {"min": [5, 4, 6], "max": [6, 5, 7]}' || fail "label 3 box"
# Sample type: NIfTI datatype 512 (uint16), intent 1002 (labels).
python3 - "$tmp/l26.nii" <<'PY' || fail "labels header"
import struct, sys
h = open(sys.argv[1], "rb").read(348)
intent, dtype, bitpix = struct.unpack_from("<hhh", h, 68)
assert (intent, dtype, bitpix) == (1002, 512, 16), (intent, dtype, bitpix)
PY
# .nii.gz too, with -o and --labels together.
"$BVOX" components "$tmp/set.nii" --labels "$tmp/l.nii.gz" --keep-largest 1 -o "$tmp/k.nii" \
    >/dev/null || fail "--labels .nii.gz"
[ "$(count "$tmp/l.nii.gz" --label 2)" = 3 ] || fail ".nii.gz label 2"
# labelio: --labels as NRRD and MetaImage hold the same labels as the NIfTI.
for f in l.nrrd l.mha l.seg.nrrd; do
    "$BVOX" components "$tmp/set.nii" --conn 26 --labels "$tmp/$f" >/dev/null || fail "--labels $f"
    "$BVOX" labels "$tmp/$f" --csv | cut -d, -f1,3 >"$tmp/got.csv" || fail "labels $f"
    "$BVOX" labels "$tmp/l26.nii" --csv | cut -d, -f1,3 | cmp -s - "$tmp/got.csv" ||
        fail "--labels $f differs from the NIfTI"
done

# 65536 components (a 32 x 64 x 64 checkerboard, 6-connected): uint32 labels.
python3 - "$tmp/cb.raw" <<'PY'
import sys
row0 = bytes((x % 2) for x in range(32))
row1 = bytes(((x + 1) % 2) for x in range(32))
plane0 = (row0 + row1) * 32
plane1 = (row1 + row0) * 32
open(sys.argv[1], "wb").write((plane0 + plane1) * 32)
PY
"$BVOX" components "$tmp/cb.raw" --dims 32,64,64 --type u8 --conn 6 --labels "$tmp/cb.nii" \
    --json >"$tmp/j" || fail "checkerboard exited $?"
jcheck "$tmp/j" 'o["count"] == 65536 and o["components"][-1]["voxels"] == 1' || fail "checkerboard count"
python3 - "$tmp/cb.nii" <<'PY' || fail "checkerboard labels are not uint32"
import struct, sys
h = open(sys.argv[1], "rb").read(348)
assert struct.unpack_from("<hh", h, 70) == (768, 32), struct.unpack_from("<hh", h, 70)
PY
[ "$(count "$tmp/cb.nii" --label 65536)" = 1 ] || fail "label 65536"
[ "$(count "$tmp/cb.nii" --label 65535)" = 1 ] || fail "label 65535"
[ "$(count "$tmp/cb.nii")" = 65536 ] || fail "checkerboard labels"
# The same with 26-connectivity is one component.
"$BVOX" components "$tmp/cb.raw" --dims 32,64,64 --type u8 --json >"$tmp/j" &&
    jcheck "$tmp/j" 'o["count"] == 1 and o["components"][0]["voxels"] == 65536' ||
    fail "checkerboard with 26"

# An empty volume: no components.
mk empty 3 3 3 'False'
"$BVOX" components "$tmp/empty.nii" --json >"$tmp/j" &&
    jcheck "$tmp/j" '{k: v for k, v in o.items() if k not in ("input", "output")} == {"count": 0, "component_count": 0, "components": []} and o["output"] is None' || fail "empty"
"$BVOX" components "$tmp/empty.nii" | grep -q '^components: *0 ' || fail "empty text"

"$BVOX" components --help >"$tmp/help" || fail "--help exited $?"
for word in --conn --keep-largest --labels --json -o; do
    grep -q -- "$word" "$tmp/help" || fail "--help does not mention $word"
done

# Bad command lines: exit 2; bad files: exit 1; one "bvox: " line, nothing written.
out=$tmp/out
mkdir "$out"
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
    [ -z "$(ls -A "$out")" ] || fail "$*: wrote $(ls -A "$out")"
}
IN=$tmp/set.nii
expect 2 "$BVOX" components
expect 2 "$BVOX" components "$IN" "$IN"
expect 2 "$BVOX" components "$IN" --conn 5
expect 2 "$BVOX" components "$IN" --conn
expect 2 "$BVOX" components "$IN" --keep-largest 0 -o "$out/x.nii"
expect 2 "$BVOX" components "$IN" --keep-largest two -o "$out/x.nii"
expect 2 "$BVOX" components "$IN" --keep-largest 2
expect 2 "$BVOX" components "$IN" -o "$out/x.nii"
expect 2 "$BVOX" components "$IN" --keep-largest 1 -o "$out/x.unknown"
expect 2 "$BVOX" components "$IN" --labels "$out/x.tif"
expect 2 "$BVOX" components "$IN" --labels "$out/x"
expect 2 "$BVOX" components "$IN" --bogus
expect 1 "$BVOX" components "$tmp/nope.nii" --labels "$out/x.nii"
head -c 300 "$IN" >"$tmp/short.nii"
expect 1 "$BVOX" components "$tmp/short.nii" --keep-largest 1 -o "$out/x.nii" --labels "$out/l.nii"
expect 1 "$BVOX" components "$IN" --labels "$out/no/such/dir/l.nii"
expect 1 "$BVOX" components "$IN" --keep-largest 1 -o "$out/no/such/dir/x.nii"
# The label volume (4 bytes a voxel) over --max-memory is refused up front.
python3 -c 'import sys; open(sys.argv[1], "wb").write(bytes(200 * 200 * 64))' "$tmp/big.raw"
expect 1 "$BVOX" components "$tmp/big.raw" --dims 200,200,64 --type u8 --max-memory 3M \
    --labels "$out/l.nii"
# ... before -o is written: no output at all.
expect 1 "$BVOX" components "$tmp/big.raw" --dims 200,200,64 --type u8 --max-memory 3M \
    --labels "$out/l.nii" --keep-largest 1 -o "$out/x.nii"
echo "ok"
