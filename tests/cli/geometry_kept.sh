#!/bin/sh
# geometry_kept.sh — convert keeps what the output format can express and
# says what it cannot (issue 14): a NIfTI's space code (an MNI atlas stays
# MNI: sform/qform code 4 survives), binvox's single voxel size and missing
# unit are warned about.
# Usage: sh geometry_kept.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$here/lib/common.sh"

mk box 8 8 8 '2 <= min(x, y, z) and max(x, y, z) <= 5' --voxel-size 1,1,2 --unit mm
# codes: qform_code at byte 252, sform_code at 254 (int16, little-endian)
codes() { python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(); print(*struct.unpack('<hh', d[252:256]))" "$1"; }
setcodes() {
    python3 -c "
import struct, sys
p = sys.argv[1]
d = bytearray(open(p, 'rb').read())
d[252:256] = struct.pack('<hh', int(sys.argv[2]), int(sys.argv[3]))
open(p, 'wb').write(d)" "$1" "$2" "$3"
}
[ "$(codes "$tmp/box.nii")" = "1 1" ] || fail "a new volume is not in scanner space: $(codes "$tmp/box.nii")"
setcodes "$tmp/box.nii" 0 4 # MNI in the sform only, as the AAL atlas has it
"$BVOX" convert "$tmp/box.nii" "$tmp/out.nii" || fail "convert"
[ "$(codes "$tmp/out.nii")" = "4 4" ] || fail "MNI space lost: $(codes "$tmp/out.nii")"
setcodes "$tmp/box.nii" 3 0 # Talairach in the qform only
"$BVOX" convert "$tmp/box.nii" "$tmp/out.nii" || fail "convert"
[ "$(codes "$tmp/out.nii")" = "3 3" ] || fail "Talairach space lost: $(codes "$tmp/out.nii")"

# binvox: one voxel size, no unit: both said, translate and scale kept
"$BVOX" convert "$tmp/box.nii" "$tmp/box.binvox" 2>"$tmp/err" || fail "convert to binvox"
grep -q '^bvox: warning: .*binvox has one voxel size: 1 x 1 x 2 mm' "$tmp/err" ||
    fail "anisotropy not warned: $(cat "$tmp/err")"
grep -q '^bvox: warning: .*binvox stores no unit' "$tmp/err" || fail "unit not warned: $(cat "$tmp/err")"
"$BVOX" convert "$tmp/box.nii" "$tmp/q.binvox" --quiet 2>"$tmp/err" || fail "convert --quiet"
[ ! -s "$tmp/err" ] || fail "--quiet printed: $(cat "$tmp/err")"
mk cube 8 8 8 'x < 4' --voxel-size 0.5,0.5,0.5
"$BVOX" convert "$tmp/cube.nii" "$tmp/c.binvox" 2>"$tmp/err" || fail "convert isotropic"
[ ! -s "$tmp/err" ] || fail "isotropic unitless volume warned: $(cat "$tmp/err")"
"$BVOX" info "$tmp/c.binvox" --json >"$tmp/i.json"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [0.5, 0.5, 0.5])' || fail "binvox scale not kept"
echo "geometry_kept: ok"
