#!/bin/sh
# limits.sh — resource limits through the real command: a volume is read
# back under a --max-memory close to its bits (readers stream slices); heavy
# operations are refused before they start; sizes and numbers in messages
# are readable.
# Usage: sh limits.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# A 256^3 sphere: 2 MiB of bits, 16 MiB as u8 samples. Each format is read
# under a budget of 5 MiB (the old readers held every sample at once, and
# for .nii.gz the compressed file too).
"$BVOX" shape sphere r=97 --dims 256,256,256 -o "$tmp/s.nii" >/dev/null || fail "shape"
"$BVOX" info "$tmp/s.nii" --json >"$tmp/ref.json" || fail "info"
want=$(sed 's/.*"count": *\([0-9]*\).*/\1/' "$tmp/ref.json")
[ "$want" -gt 3000000 ] || fail "sphere count $want"
"$BVOX" convert "$tmp/s.nii" "$tmp/s.nii.gz" >/dev/null || fail "convert to .nii.gz"
"$BVOX" convert "$tmp/s.nii" "$tmp/s.tif" >/dev/null || fail "convert to .tif"
"$BVOX" convert "$tmp/s.nii" "$tmp/png" --output-format png >/dev/null || fail "convert to PNG"
for f in s.nii s.nii.gz s.tif png; do
    "$BVOX" info "$tmp/$f" --max-memory 5M --json >"$tmp/i.json" 2>"$tmp/err" ||
        fail "info $f under 5 MiB: $(cat "$tmp/err")"
    got=$(sed 's/.*"count": *\([0-9]*\).*/\1/' "$tmp/i.json")
    [ "$got" = "$want" ] || fail "$f: count $got, want $want"
done
echo ok
