#!/bin/sh
# mosaic.sh — `bvox mosaic` (Picture 4, the data set as the frame buffer held
# it) on raw volumes made here, its PNG read back by pngtool.py: the exact
# bytes of a hand-made volume (8 slices per byte, sections in a grid), plane
# masks and displays, the 16-section 4 x 4 layout checked voxel by voxel in
# Python; bad command lines (exit 2) and failures (exit 1).
# Usage: sh mosaic.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

expect() {
    png read "$1" >"$tmp/got.json" || fail "cannot read $1"
    python3 - "$tmp/got.json" "$2" <<'PY' || fail "$1 is not as expected"
import json, sys
got = json.load(open(sys.argv[1]))
want = eval(sys.argv[2])
assert got["channels"] == 1 and got["bits"] == 8, got
assert got["rows"] == want, "\n got %s\nwant %s" % (got["rows"], want)
PY
}

# 3 x 2 x 20 voxels, x fastest: 3 sections (slices 0-7, 8-15, 16-19) in a
# 2 x 2 grid of 3 x 2 pixels.
python3 - "$tmp/hand.raw" <<'PY'
import sys
nx, ny, nz = 3, 2, 20
v = bytearray(nx * ny * nz)
for x, y, z in [(0, 0, 0), (1, 0, 3), (1, 0, 5), (2, 1, 9), (0, 1, 16), (0, 1, 19)]:
    v[(z * ny + y) * nx + x] = 1
open(sys.argv[1], "wb").write(v)
PY
raw="--dims 3,2,20 --type u8"
# shellcheck disable=SC2086
"$BVOX" mosaic "$tmp/hand.raw" $raw -o "$tmp/bytes.png" --display bytes || fail "mosaic exited $?"
expect "$tmp/bytes.png" '[[1,40,0,0,0,0],[0,0,0,0,0,2],[0,0,0,0,0,0],[9,0,0,0,0,0]]'
# shellcheck disable=SC2086
"$BVOX" mosaic "$tmp/hand.raw" $raw -o "$tmp/any.png" --planes 0x08 --display any || fail "any"
expect "$tmp/any.png" '[[0,255,0,0,0,0],[0]*6,[0]*6,[255,0,0,0,0,0]]'
# shellcheck disable=SC2086
"$BVOX" mosaic "$tmp/hand.raw" $raw -o "$tmp/count.png" --planes 0b101001 || fail "count"
expect "$tmp/count.png" '[[85,170,0,0,0,0],[0]*6,[0]*6,[170,0,0,0,0,0]]'
# shellcheck disable=SC2086
"$BVOX" mosaic "$tmp/hand.raw" $raw -o "$tmp/col.png" --planes 41 --display bytes --columns 1 ||
    fail "columns"
expect "$tmp/col.png" '[[1,40,0],[0,0,0],[0,0,0],[0,0,0],[0,0,0],[9,0,0]]'

# 16 x 12 x 128: 16 sections in 4 x 4, checked voxel by voxel
python3 - "$tmp/big.raw" <<'PY'
import sys
nx, ny, nz = 16, 12, 128
open(sys.argv[1], "wb").write(bytes(1 if (x * 7 + y * 3 + z * 5) % 4 == 0 or z == x + y else 0
                                    for z in range(nz) for y in range(ny) for x in range(nx)))
PY
"$BVOX" mosaic "$tmp/big.raw" --dims 16,12,128 --type u8 -o "$tmp/big.png" --display bytes ||
    fail "mosaic big"
png read "$tmp/big.png" >"$tmp/big.json"
python3 - "$tmp/big.raw" "$tmp/big.json" <<'PY' || fail "the 4 x 4 layout"
import json, sys
nx, ny, nz = 16, 12, 128
v = open(sys.argv[1], "rb").read()
got = json.load(open(sys.argv[2]))
assert (got["width"], got["height"]) == (64, 48), (got["width"], got["height"])
for s in range(16):
    for y in range(ny):
        for x in range(nx):
            want = sum(v[((8 * s + b) * ny + y) * nx + x] << b for b in range(8))
            g = got["rows"][(s // 4) * ny + y][(s % 4) * nx + x]
            assert g == want, (s, x, y, g, want)
PY

# bad command lines: exit 2
usage() {
    set +e
    "$BVOX" mosaic "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "mosaic $* exited $rc, wanted 2"
    grep -q '^bvox: mosaic: ' "$tmp/err" || fail "mosaic $*: message: $(cat "$tmp/err")"
}
usage
usage "$tmp/hand.raw" --dims 3,2,20 --type u8
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --planes 256
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --planes 0x1g
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --planes ''
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --display all
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --columns 0
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.tif"
usage "$tmp/hand.raw" --dims 3,2,20 --type u8 -o "$tmp/x.png" --bogus
[ ! -e "$tmp/x.png" ] || fail "a usage error wrote output"

# failures: exit 1, no output
set +e
"$BVOX" mosaic "$tmp/missing.nii" -o "$tmp/x.png" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 1 ] || fail "missing input exited $rc"
grep -q '^bvox: ' "$tmp/err" || fail "missing input message"
[ ! -e "$tmp/x.png" ] || fail "a failure wrote output"

"$BVOX" mosaic --help | grep -q 'bit planes' || fail "mosaic --help"
echo "ok"
