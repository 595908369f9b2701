#!/bin/sh
# interpolate.sh — `bvox interpolate` through the real command: a box
# annotated on its first and last slice is filled exactly (binary and as a
# label volume of two labels), and bad command lines exit 2.
# Usage: sh interpolate.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

mk full 10 8 20 '2 <= x <= 6 and 1 <= y <= 5 and 3 <= z <= 15'
mk ends 10 8 20 '2 <= x <= 6 and 1 <= y <= 5 and z in (3, 15)'
"$BVOX" interpolate "$tmp/ends.nii" --axis z -o "$tmp/filled.nii" >"$tmp/o" ||
    fail "interpolate exited $?"
grep -q "50 voxels annotated, 325 after filling" "$tmp/o" || fail "summary: $(cat "$tmp/o")"
"$BVOX" csg "$tmp/filled.nii ^ $tmp/full.nii" -o "$tmp/diff.nii" >/dev/null || fail "csg"
"$BVOX" info "$tmp/diff.nii" --json >"$tmp/j" || fail "info"
jcheck "$tmp/j" 'o["count"] == 0' || fail "not filled exactly"

# Two labels annotated on their end slices: each filled on its own.
python3 - "$tmp/lab.raw" <<'PY'
import struct, sys
nx, ny, nz = 12, 6, 12
v = [0] * (nx * ny * nz)
for z in (1, 10):
    for y in range(1, 5):
        for x in range(1, 5): v[(z * ny + y) * nx + x] = 3
        for x in range(6, 11): v[(z * ny + y) * nx + x] = 8
open(sys.argv[1], "wb").write(struct.pack("<%dH" % len(v), *v))
PY
"$BVOX" interpolate "$tmp/lab.raw" --dims 12,6,12 --type u16 --labels --axis z \
    -o "$tmp/lab.nii" >"$tmp/o" || fail "interpolate --labels exited $?"
"$BVOX" labels "$tmp/lab.nii" --json >"$tmp/j" || fail "labels"
jcheck "$tmp/j" '[(l["label"], l["count"]) for l in o["labels"]] == [(3, 160), (8, 200)]' ||
    fail "labels filled: $(cat "$tmp/j")"

for args in "" "$tmp/ends.nii --axis y" "$tmp/ends.nii --labels --label 3"; do
    set +e
    # shellcheck disable=SC2086
    "$BVOX" interpolate $args >/dev/null 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "interpolate $args exited $rc (want 2)"
done
echo "interpolate: ok"
