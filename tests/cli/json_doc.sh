#!/bin/sh
# json_doc.sh — docs/JSON.md documents every key the commands print: runs
# each command that has --json (and reconstruct's --report) on small inputs,
# collects every object key of the output, nested ones too, and fails naming
# any key docs/JSON.md does not mention in a code span (`key`, `{"key", ...}`).
# Usage: sh json_doc.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
doc=$(dirname "$0")/../../docs/JSON.md
[ -f "$doc" ] || fail "no docs/JSON.md"

"$BVOX" demo --json >"$tmp/demo.json" || fail "demo"
"$BVOX" shape sphere r=5 --dims 16,16,16 -o "$tmp/s.nii" --json >"$tmp/shape.json" || fail "shape"
"$BVOX" info "$tmp/s.nii" --json >"$tmp/info.json" || fail "info"
"$BVOX" measure "$tmp/s.nii" --json >"$tmp/measure.json" || fail "measure"
"$BVOX" components "$tmp/s.nii" --json >"$tmp/components.json" || fail "components"
"$BVOX" csg "$tmp/s.nii - sphere(r=2)" -o "$tmp/c.nii" --json >"$tmp/csg.json" || fail "csg"
"$BVOX" cut "$tmp/s.nii" -o "$tmp/cut.nii" --plane 0,0,1,-8 --json >"$tmp/cut.json" || fail "cut"
"$BVOX" edit "$tmp/s.nii" -o "$tmp/e.nii" --set 0,0,0 --json >"$tmp/edit.json" || fail "edit"
"$BVOX" mesh "$tmp/s.nii" -o "$tmp/s.stl" >/dev/null || fail "mesh"
"$BVOX" meshinfo "$tmp/s.stl" --json >"$tmp/meshinfo.json" || fail "meshinfo"
"$BVOX" contours "$tmp/s.nii" -o "$tmp/k.json" >/dev/null || fail "contours"
"$BVOX" reconstruct "$tmp/k.json" -o "$tmp/r.nii" --report "$tmp/report.json" \
    >/dev/null 2>&1 || fail "reconstruct"
# the --json of the commands that write (issue 15)
"$BVOX" convert "$tmp/s.nii" "$tmp/s.tif" --json >"$tmp/convert.json" || fail "convert"
"$BVOX" morph "$tmp/s.nii" dilate -o "$tmp/d.nii" --json >"$tmp/morph.json" || fail "morph"
"$BVOX" mesh "$tmp/s.nii" -o "$tmp/m.ply" --json >"$tmp/mesh.json" || fail "mesh --json"
"$BVOX" voxelize "$tmp/m.ply" -o "$tmp/v.nii" --res 12 --json >"$tmp/voxelize.json" ||
    fail "voxelize"
"$BVOX" contours "$tmp/s.nii" -o "$tmp/ksvg" --json >"$tmp/contours.json" || fail "contours --json"

python3 - "$doc" "$tmp"/*.json <<'PY'
import json, re, sys
doc = open(sys.argv[1]).read()
documented = {w for span in re.findall(r"`([^`]*)`", doc) for w in re.findall(r"[a-z_0-9]+", span)}
missing = {}
def walk(o, where):
    if isinstance(o, dict):
        for k, v in o.items():
            if k not in documented and k not in STEPS:
                missing.setdefault(k, where)
            walk(v, where)
    elif isinstance(o, list):
        for v in o:
            walk(v, where)
STEPS = set()
for path in sys.argv[2:]:
    if path.endswith("/k.json"):
        continue  # the contour stack file itself, a file format, not command output
    o = json.loads(open(path).read())
    if "timings_ms" in o:
        STEPS = set(o["timings_ms"])  # step names, listed in the doc's prose
    walk(o, path.rsplit("/", 1)[1])
if missing:
    sys.exit("docs/JSON.md lacks: " + ", ".join("%s (%s)" % kv for kv in sorted(missing.items())))
print("json_doc: %d documented keys cover every command's output" % len(documented))
PY
