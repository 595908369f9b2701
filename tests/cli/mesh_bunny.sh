#!/bin/sh
# mesh_bunny.sh — the real mesh (CGAL's bunny00.off, extracted into the build
# tree by the setup.meshdata fixture): meshinfo says closed with its counts;
# voxelized at 256 and meshed back (marching cubes and cuberille) the volume
# stays within 2 %.
# Usage: sh mesh_bunny.sh BVOX DATADIR
set -eu
BVOX=$1
bunny="$(dirname "$BVOX")/tests/data/meshes/bunny00.off"
[ -f "$bunny" ] || { echo "FAIL: $bunny missing (run the setup.meshdata test)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

"$BVOX" meshinfo "$bunny" --json > "$tmp/orig.json" || fail "meshinfo"
"$BVOX" voxelize "$bunny" -o "$tmp/b.nii" --res 256 >/dev/null || fail "voxelize"
for m in mc cuberille; do
    "$BVOX" mesh "$tmp/b.nii" -o "$tmp/b_$m.stl" --method $m >/dev/null || fail "mesh $m"
    "$BVOX" meshinfo "$tmp/b_$m.stl" --json > "$tmp/$m.json" || fail "meshinfo $m"
    python3 - "$tmp/orig.json" "$tmp/$m.json" <<'PY' || fail "bunny $m: $(cat "$tmp/$m.json")"
import json, sys
o, b = (json.load(open(p)) for p in sys.argv[1:])
assert o["watertight"] and o["vertices"] == 37706 and o["triangles"] == 75408, o
assert b["watertight"], b
assert abs(b["volume"] / o["volume"] - 1) < 0.02, (b["volume"], o["volume"])
PY
done
echo "mesh_bunny: ok"
