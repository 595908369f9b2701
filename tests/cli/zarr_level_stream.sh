#!/bin/sh
# zarr_level_stream.sh — `--level K` holds when a .zarr over --max-memory is
# streamed in slabs: info, measure and components of level 1 by slabs equal
# those of level 1 read whole (its dims, voxels, origin), not level 0's.
# Usage: sh zarr_level_stream.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
D=162,202,2000   # level 1: 81 x 101 x 1000, 1 MiB of words
M=5M             # over level 1's in-memory path, under level 0's words (8 MiB)

"$BVOX" shape sphere r=60 at=80,100,400 --dims $D -o "$tmp/s.nii" >/dev/null
"$BVOX" shape torus R=40 r=12 at=80,100,1500 axis=1,0,0 --dims $D -o "$tmp/t.nii" >/dev/null
"$BVOX" csg "$tmp/s.nii + $tmp/t.nii" -o "$tmp/all.nii" >/dev/null
"$BVOX" convert "$tmp/all.nii" "$tmp/a.zarr" --chunks 37,100,65 >/dev/null

for args in "info --json" "measure --json" "components --json --conn 26"; do
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" --level 1 > "$tmp/mem.out" || fail "$args in memory"
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" --level 1 --max-memory $M > "$tmp/ooc.out" ||
        fail "$args by slabs"
    cmp -s "$tmp/mem.out" "$tmp/ooc.out" || { diff "$tmp/mem.out" "$tmp/ooc.out" | head; \
                                              fail "$args: slabs differ from memory"; }
done
grep -q '"dims": *\[81, *101, *1000\]' "$tmp/mem.out" ||
    "$BVOX" info "$tmp/a.zarr" --level 1 --json | grep -q '"dims":\[81,101,1000\]' ||
    fail "level 1 is not 81 x 101 x 1000"
# the streamed path was taken: what needs the whole volume is refused
if "$BVOX" measure --csv "$tmp/a.zarr" --level 1 --max-memory $M 2> "$tmp/err"; then
    fail "--csv over the budget was accepted"
fi
grep -q "needs the whole volume in memory" "$tmp/err" || fail "unclear refusal: $(cat "$tmp/err")"
echo ok
