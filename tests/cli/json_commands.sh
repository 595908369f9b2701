#!/bin/sh
# json_commands.sh — --json of mesh, morph, convert, voxelize and contours,
# and the input/output keys every command shares, on objects whose answers
# are known by hand: a 4 x 4 x 4 box of voxels 2..5 (64 voxels; its voxel-face
# mesh has 5^3 - 3^3 = 98 vertices, 96 faces = 192 triangles, volume 64,
# area 96) and a single voxel (dilated by the 6-neighbourhood: 7 voxels, by
# the 26-neighbourhood: 27; its faces: 8 vertices, 12 triangles, area 6).
# Each output is one line of JSON, parsed with python3 and checked key by key.
# Usage: sh json_commands.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$tmp"

# check FILE KEY=PYTHON-LITERAL...: FILE is one line holding one JSON object
# with those values (floats to 1e-9)
check() {
    python3 - "$@" <<'PY' || fail "$*"
import ast, json, math, sys
path, *pairs = sys.argv[1:]
text = open(path).read()
assert text.count("\n") == 1 and text.endswith("\n"), "not one line: %r" % text
obj = json.loads(text)
def same(a, b):
    if isinstance(b, bool) or b is None:
        return a is b
    if isinstance(b, float):
        return isinstance(a, (int, float)) and math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    if isinstance(b, list):
        return isinstance(a, list) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(b, dict):
        return isinstance(a, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in b)
    return type(a) is type(b) and a == b
for pair in pairs:
    key, want = pair.split("=", 1)
    want = ast.literal_eval(want)
    assert key in obj, "missing key %s in %s" % (key, text)
    assert same(obj[key], want), "%s: %r, wanted %r" % (key, obj[key], want)
PY
}

"$BVOX" shape box min=2,2,2 max=5,5,5 --dims 10,10,10 -o box.nii --json >shape.json
check shape.json file="'box.nii'" input=None output="'box.nii'" count=64 voxels=64
"$BVOX" shape box min=5,5,5 max=5,5,5 --dims 10,10,10 -o one.nii >/dev/null

# convert: the output's info, input and output
"$BVOX" convert box.nii box.tif --json >convert.json
check convert.json file="'box.tif'" format="'tiff'" input="'box.nii'" output="'box.tif'" \
    dims=[10,10,10] spacing=[1.0,1.0,1.0] count=64 voxels=64 \
    'bbox={"min":[2,2,2],"max":[5,5,5]}'
[ -s box.tif ] || fail "convert --json wrote no file"
"$BVOX" convert box.nii box2.nii --json --output-format nifti >convert2.json
check convert2.json format="'nifti'" count=64

# morph: the operation, its element and the counts before and after
"$BVOX" morph one.nii dilate --conn 6 -o d6.nii --json >m6.json
check m6.json operation="'dilate'" conn=6 radius=None min_size=None count_before=1 \
    count_after=7 count=7 input="'one.nii'" output="'d6.nii'" file="'d6.nii'" \
    'bbox={"min":[4,4,4],"max":[6,6,6]}'
"$BVOX" morph one.nii dilate -o d26.nii --json >m26.json
check m26.json conn=26 count_after=27
"$BVOX" morph box.nii erode --radius 1 -o e.nii --json >mr.json
check mr.json operation="'erode'" conn=None radius=1.0 count_before=64 count_after=8
"$BVOX" morph box.nii islands --min-size 65 -o i.nii --json >mi.json
check mi.json operation="'islands'" min_size=65 count_before=64 count_after=0 bbox=None
[ "$("$BVOX" info d6.nii --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["count"])')" = 7 ] ||
    fail "morph --json's file differs from its report"

# mesh: meshinfo's keys
"$BVOX" mesh one.nii -o one.off --method cuberille --json >mesh1.json
check mesh1.json file="'one.off'" format="'off'" input="'one.nii'" output="'one.off'" \
    method="'cuberille'" smooth=0 vertices=8 triangles=12 volume=1.0 surface_area=6.0 \
    watertight=True
"$BVOX" mesh box.nii -o box.ply --method cuberille --json >mesh2.json
check mesh2.json format="'ply'" vertices=98 triangles=192 volume=64.0 surface_area=96.0
"$BVOX" mesh box.nii -o mc.stl --json >mesh3.json
check mesh3.json method="'mc'" format="'stl'" watertight=True
"$BVOX" meshinfo box.ply --json >meshinfo.json
check meshinfo.json file="'box.ply'" input="'box.ply'" output=None vertices=98 triangles=192
"$BVOX" mesh box.nii -o box.stl --json --labels all 2>/dev/null && fail "--json with --labels"

# voxelize: the box's faces back to its 64 voxels
"$BVOX" voxelize box.ply -o vox.nii --voxel-size 1 --json >vox.json
check vox.json file="'vox.nii'" format="'nifti'" input="'box.ply'" output="'vox.nii'" \
    count=64 dims=[4,4,4] origin=[2.0,2.0,2.0] closed=True open_edges=0 \
    'bbox_physical={"min":[1.5,1.5,1.5],"max":[5.5,5.5,5.5]}'

# contours: 4 of the 10 slices hold the box, one square of 4 corners each
"$BVOX" contours box.nii -o c.json --json >cont.json
check cont.json file="'c.json'" format="'json'" input="'box.nii'" output="'c.json'" \
    axis="'z'" slices=10 contours=4 points=16
"$BVOX" contours box.nii --axis x -o svgs --json >cont2.json
check cont2.json format="'svg'" axis="'x'" slices=10 contours=4

# input and output beside file in the older commands
"$BVOX" info box.nii --json >info.json
check info.json file="'box.nii'" input="'box.nii'" output=None
"$BVOX" measure box.nii --json >measure.json
check measure.json input="'box.nii'" output=None surface_area_faces=96.0
"$BVOX" components box.nii --json >comp.json
check comp.json input="'box.nii'" output=None count=1
"$BVOX" cut box.nii --plane 0,0,1,-3 -o cut.nii --json >cut.json
check cut.json file="'cut.nii'" input="'box.nii'" output="'cut.nii'"
"$BVOX" edit box.nii --set 0,0,0 -o ed.nii --json >edit.json
check edit.json file="'ed.nii'" input="'box.nii'" output="'ed.nii'" count_after=65
exit 0
