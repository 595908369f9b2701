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
# OME-TIFF: written with OME-XML physical sizes (tifffile, an independent
# reader, sees an OME series of the right shape and sizes); an OME-TIFF made
# by tifffile in nanometres reads back in nm.
"$BVOX" convert "$tmp/box.nii" "$tmp/box.ome.tif" || fail "convert to .ome.tif"
/usr/bin/python3 - "$tmp/box.ome.tif" <<'PY' || fail "tifffile reads no OME sizes from bvox's .ome.tif"
import sys, tifffile, xml.etree.ElementTree as ET
t = tifffile.TiffFile(sys.argv[1])
assert t.is_ome and t.series[0].shape == (8, 8, 8), (t.is_ome, t.series[0].shape)
px = ET.fromstring(t.ome_metadata).find(".//{*}Pixels").attrib
assert (float(px["PhysicalSizeX"]), float(px["PhysicalSizeZ"])) == (1.0, 2.0), px
assert px["PhysicalSizeXUnit"] == "mm", px
assert int((t.series[0].asarray() > 0).sum()) == 64, "voxels"
PY
"$BVOX" info "$tmp/box.ome.tif" --json >"$tmp/i.json"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [1, 1, 2]) and o["unit"] == "mm" and o["count"] == 64' ||
    fail ".ome.tif round trip: $(cat "$tmp/i.json")"
/usr/bin/python3 - "$tmp/nm.ome.tif" <<'PY' || fail "tifffile could not write the nm OME-TIFF"
import sys, numpy as np, tifffile
a = np.zeros((5, 6, 7), np.uint8)
a[1:4, 2:5, 3:6] = 1
tifffile.imwrite(sys.argv[1], a, metadata={"axes": "ZYX", "PhysicalSizeX": 20, "PhysicalSizeXUnit": "nm",
                 "PhysicalSizeY": 20, "PhysicalSizeYUnit": "nm", "PhysicalSizeZ": 0.05, "PhysicalSizeZUnit": "\u00b5m"})
PY
"$BVOX" info "$tmp/nm.ome.tif" --json >"$tmp/i.json"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [20, 20, 50]) and o["unit"] == "nm" and o["count"] == 27' ||
    fail "OME-TIFF in nm: $(cat "$tmp/i.json")"
# STL cannot keep two vertices at one place: a cuberille mesh of two voxels
# touching along an edge is written with a warning (STL) or silently (PLY);
# marching cubes (no shared positions) never warns.
mk edge 4 4 4 '(x, y, z) in ((1, 1, 1), (2, 2, 1))'
"$BVOX" mesh "$tmp/edge.nii" -o "$tmp/e.stl" --method cuberille 2>"$tmp/err" || fail "cuberille to STL"
grep -q '^bvox: warning: .*e.stl: [0-9]* vertices share their position .* write .ply, .obj or .off' "$tmp/err" ||
    fail "cuberille STL not warned: $(cat "$tmp/err")"
"$BVOX" mesh "$tmp/edge.nii" -o "$tmp/e.ply" --method cuberille 2>"$tmp/err" || fail "cuberille to PLY"
grep -q warning "$tmp/err" && fail "PLY warned: $(cat "$tmp/err")"
"$BVOX" mesh "$tmp/edge.nii" -o "$tmp/m.stl" 2>"$tmp/err" || fail "mc to STL"
grep -q warning "$tmp/err" && fail "marching cubes STL warned: $(cat "$tmp/err")"
# PNG slices have no z: a round trip keeps it through voxel_size.txt; a
# folder without one says what it assumed, unless --voxel-size tells it
"$BVOX" convert "$tmp/box.nii" "$tmp/png/" 2>"$tmp/err" || fail "convert to PNG slices"
"$BVOX" info "$tmp/png/" --json >"$tmp/i.json" 2>"$tmp/err"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [1, 1, 2]) and o["unit"] == "mm"' ||
    fail "PNG round trip lost the z spacing: $(cat "$tmp/i.json")"
[ ! -s "$tmp/err" ] || fail "a bvox-written folder warned: $(cat "$tmp/err")"
rm "$tmp/png/voxel_size.txt"
"$BVOX" info "$tmp/png/" --json >"$tmp/i.json" 2>"$tmp/err"
grep -q '^bvox: warning: .*PNG slices hold no z spacing: 1 mm .*assumed' "$tmp/err" ||
    fail "assumed z not warned: $(cat "$tmp/err")"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [1, 1, 1])' || fail "pHYs x/y: $(cat "$tmp/i.json")"
"$BVOX" info "$tmp/png/" --voxel-size 1,1,2 --json >"$tmp/i.json" 2>"$tmp/err"
[ ! -s "$tmp/err" ] || fail "--voxel-size still warned: $(cat "$tmp/err")"
jcheck "$tmp/i.json" 'near(o["voxel_size"], [1, 1, 2])' || fail "--voxel-size: $(cat "$tmp/i.json")"
echo "geometry_kept: ok"
