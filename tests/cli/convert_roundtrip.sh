#!/bin/sh
# convert_roundtrip.sh — `bvox convert` between every pair of formats (NIfTI,
# gzipped NIfTI, binvox, TIFF stack, folder of PNG slices, raw) keeps the
# dimensions, the count and the bounding box of a volume with awkward sizes
# (odd nx and ny, nz = 70 crossing a 64-bit word); formats that store a voxel
# size keep it. The reference numbers come from the hand-written raw source,
# counted by python3, not by bvox.
# Usage: sh convert_roundtrip.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

NX=37 NY=23 NZ=70
# An off-centre ellipsoid plus a scatter of single voxels (fixed seed), as
# u8 samples x fastest; python prints count and inclusive bbox.
python3 - "$tmp/src.raw" $NX $NY $NZ >"$tmp/expect" <<'PY'
import random, sys
path, nx, ny, nz = sys.argv[1], *map(int, sys.argv[2:])
rnd = random.Random(7)
data = bytearray(nx * ny * nz)
for z in range(nz):
    for y in range(ny):
        for x in range(nx):
            e = ((x - 15) / 12) ** 2 + ((y - 11) / 8) ** 2 + ((z - 40) / 25) ** 2
            if e <= 1 or rnd.random() < 0.01:
                data[(z * ny + y) * nx + x] = rnd.randint(1, 255)
open(path, "wb").write(data)
pts = [(i % nx, i // nx % ny, i // (nx * ny)) for i, v in enumerate(data) if v]
lo = [min(p[a] for p in pts) for a in range(3)]
hi = [max(p[a] for p in pts) for a in range(3)]
print(len(pts), *lo, *hi)
PY
read -r count x0 y0 z0 x1 y1 z1 <"$tmp/expect"
[ "$count" -gt 1000 ] || fail "the source volume is too small: $count"

# File name, extra convert options and extra read options for each format.
out_name() {
    case $1 in
    nii) echo "$2.nii" ;; niigz) echo "$2.nii.gz" ;; binvox) echo "$2.binvox" ;;
    tif) echo "$2.tif" ;; png) echo "$2_png" ;; raw) echo "$2.raw" ;;
    esac
}
out_opts() { [ "$1" = png ] && echo "--output-format png" || true; }
in_opts() { [ "$1" = raw ] && echo "--dims $NX,$NY,$NZ --type u8" || true; }

# check FILE FORMAT: dims, count and bbox as expected.
check() {
    "$BVOX" info "$1" $(in_opts "$2") --json >"$tmp/j" || fail "info $1 exited $?"
    python3 - "$tmp/j" $NX $NY $NZ $count $x0 $y0 $z0 $x1 $y1 $z1 <<'PY' || fail "$1 differs"
import json, sys
obj = json.loads(open(sys.argv[1]).read())
v = list(map(int, sys.argv[2:]))
want = {"dims": v[0:3], "count": v[3], "bbox": {"min": v[4:7], "max": v[7:10]}}
for k, w in want.items():
    if obj[k] != w:
        sys.exit("%s is %r, expected %r" % (k, obj[k], w))
PY
}

# The source: raw -> NIfTI with a voxel size.
"$BVOX" convert "$tmp/src.raw" "$tmp/base.nii" --dims $NX,$NY,$NZ --type u8 \
    --voxel-size 0.2,0.3,1.5 --unit mm || fail "raw -> nii exited $?"
check "$tmp/base.nii" nii

formats="nii niigz binvox tif png raw"
for a in $formats; do
    src=$tmp/$(out_name $a from)
    "$BVOX" convert "$tmp/base.nii" "$src" $(out_opts $a) || fail "nii -> $a exited $?"
    check "$src" $a
    for b in $formats; do
        dst=$tmp/$(out_name $b "$a-to")
        "$BVOX" convert "$src" "$dst" $(in_opts $a) $(out_opts $b) ||
            fail "$a -> $b exited $?"
        check "$dst" $b
        rm -rf "$dst"
    done
done

# The voxel size and unit survive NIfTI -> NIfTI (gzipped or not) -> NIfTI.
"$BVOX" convert "$tmp/from.nii.gz" "$tmp/again.nii" || fail "nii.gz -> nii exited $?"
"$BVOX" info "$tmp/again.nii" --json >"$tmp/j"
python3 - "$tmp/j" <<'PY' || fail "NIfTI lost the voxel size"
import json, math, sys
obj = json.loads(open(sys.argv[1]).read())
assert all(math.isclose(a, b, rel_tol=1e-6) for a, b in zip(obj["voxel_size"], [0.2, 0.3, 1.5])), obj
assert obj["unit"] == "mm", obj
PY

# No temporary files left anywhere in the scratch folder (a PNG folder's
# manifest, .bvox-manifest, is part of the output).
leftover=$(find "$tmp" -name '.*' ! -name . ! -name .bvox-manifest | head -n 5)
[ -z "$leftover" ] || fail "temporary files left behind: $leftover"
echo "ok"
