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

# refuse EXPECTED-TEXT COMMAND...: exit 1, one "bvox: " line holding the text,
# and no output file (the outputs here are all $tmp/x.*)
refuse() {
    want=$1
    shift
    set +e
    "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 1 ] || fail "$*: exit $rc ($(cat "$tmp/err"))"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "$*: stderr is not one line: $(cat "$tmp/err")"
    grep -q -- "$want" "$tmp/err" || fail "$*: expected '$want' in: $(cat "$tmp/err")"
    ! ls "$tmp"/x.* >/dev/null 2>&1 || fail "$*: left $(ls "$tmp"/x.*)"
}

# Refused before the work. A 40000 x 2000 PNG (78 KB, 76 MiB of pixels) to
# NIfTI: the writer's 32767 limit is known from the PNG header, so the
# refusal is NIfTI's even under a budget that decoding would exceed.
python3 - "$tmp/wide.png" <<'PY'
import struct, sys, zlib
w, h = 40000, 2000
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d))
raw = zlib.compress(b''.join(b'\0' * (w + 1) for _ in range(h)), 9)
open(sys.argv[1], 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0))
                              + chunk(b'IDAT', raw) + chunk(b'IEND', b''))
PY
refuse "NIfTI-1 dimensions are at most 32767 per axis (volume is 40000 x 2000 x 1)" \
    "$BVOX" convert "$tmp/wide.png" "$tmp/x.nii" --max-memory 1M
# voxelize --res 65535 into NIfTI: refused from the bounding box alone
printf 'v 0 0 0\nv 1 0 0\nv 0 0.001 0\nv 0 0 0.001\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n' >"$tmp/flat.obj"
refuse "NIfTI-1 dimensions are at most 32767 per axis (volume is 65535 x 66 x 66)" \
    "$BVOX" voxelize "$tmp/flat.obj" -o "$tmp/x.nii" --res 65535 --max-memory 16M
# an open mesh needs four volumes (x, y, z votes and the result): 4 x 2 MiB
# at 256^3 is over 5 MiB, said at once (not after voxelizing along x and y)
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n' >"$tmp/open.obj"
refuse "needs 8.0 MiB (4 volumes" \
    "$BVOX" voxelize "$tmp/open.obj" -o "$tmp/x.nii" --res 256 --max-memory 5M
# contours follows --max-memory: a 128^3 random volume has ~150000 outlines
# per axis (~25 MiB of points, ~20 MiB of JSON); under 8 MiB it stops
python3 -c "import os, sys; sys.stdout.buffer.write(os.urandom(128 ** 3))" >"$tmp/noise.raw"
"$BVOX" convert "$tmp/noise.raw" "$tmp/noise.nii" --dims 128,128,128 --type u8 --threshold 128 ||
    fail "making noise.nii"
refuse "memory budget of 8.0 MiB" "$BVOX" contours "$tmp/noise.nii" -o "$tmp/x.json" --max-memory 8M
refuse "memory budget of 8.0 MiB" "$BVOX" contours "$tmp/noise.nii" -o "$tmp/x.svg" --max-memory 8M
"$BVOX" contours "$tmp/noise.nii" -o "$tmp/n.json" --max-memory 200M >/dev/null || fail "contours 200M"
# a failed demo -o leaves no folder behind (it created dd/ee: both go)
refuse "memory budget of 2.0 MiB" "$BVOX" demo -o "$tmp/dd/ee" --max-memory 2M
[ ! -e "$tmp/dd" ] || fail "demo left $(find "$tmp/dd")"
# a contour file's pixel size of 1e300: the limit is named, not just "> 0"
printf '{"pixel": 1e300, "sections": []}' >"$tmp/c.json"
refuse "pixel must be > 0 and at most 1e12 (it is 1e+300)" "$BVOX" reconstruct "$tmp/c.json" -o "$tmp/x.nii"
echo ok
