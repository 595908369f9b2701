#!/bin/sh
# recon_assumptions.sh — reconstruct never silently assumes what a file does
# not say (issue 14): sections without z follow --spacing; a stack that gives
# no pixel size, spacing or unit is reconstructed with one "bvox: warning:"
# line naming what was assumed; --quiet (global) and -q silence it; keys
# another tool wrote into a contour JSON are named in a warning.
# Usage: sh recon_assumptions.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# three SVG sections, a 10 x 10 pixel square each, no data-z
mkdir "$tmp/svg"
for i in 1 2 3; do
    printf '<svg xmlns="http://www.w3.org/2000/svg" width="20" height="20"><polygon points="5,5 15,5 15,15 5,15"/></svg>' \
        >"$tmp/svg/s$i.svg"
done

# 1. --spacing 5 places them 5 apart: 3 sections x 5 = 15 slices of 100 voxels
"$BVOX" reconstruct "$tmp/svg" --spacing 5 --pixel 1 --unit um -o "$tmp/m.nii" --quiet 2>"$tmp/err" ||
    fail "reconstruct of the SVG folder"
[ ! -s "$tmp/err" ] || fail "--quiet still printed: $(cat "$tmp/err")"
"$BVOX" info "$tmp/m.nii" --json >"$tmp/i.json"
python3 - "$tmp/i.json" <<'PY' || fail "--spacing 5 not honoured"
import json, sys
o = json.load(open(sys.argv[1]))
assert o["dims"][2] == 15, o["dims"]
assert o["count"] == 1500, o["count"]
assert abs(o["volume"] - 1500) < 1e-9, o["volume"]
PY

# the same JSON stack without z: same model
printf '{"sections":[{"contours":[[[5,5],[15,5],[15,15],[5,15]]]},{"contours":[[[5,5],[15,5],[15,15],[5,15]]]},{"contours":[[[5,5],[15,5],[15,15],[5,15]]]}]}' >"$tmp/c.json"
"$BVOX" reconstruct "$tmp/c.json" --spacing 5 --pixel 1 --unit um -o "$tmp/j.nii" --quiet ||
    fail "reconstruct of the JSON stack"
"$BVOX" info "$tmp/j.nii" --json >"$tmp/j.json"
python3 -c "import json,sys; o=json.load(open(sys.argv[1])); assert o['count']==1500 and o['dims'][2]==15, o" \
    "$tmp/j.json" || fail "JSON without z ignores --spacing"

# 5. nothing given: one warning naming each assumption, and still exit 0
"$BVOX" reconstruct "$tmp/svg" -o "$tmp/d.nii" 2>"$tmp/err" || fail "reconstruct with defaults"
n=$(grep -c '^bvox: warning: ' "$tmp/err" || true)
[ "$n" -eq 1 ] || fail "expected one warning, got $n: $(cat "$tmp/err")"
for what in "pixel size 1" "section spacing 1" "no unit"; do
    grep -q "$what" "$tmp/err" || fail "warning does not name '$what': $(cat "$tmp/err")"
done
# -q and the global --quiet (even before the command) silence warnings
"$BVOX" reconstruct "$tmp/svg" -o "$tmp/d.nii" -q 2>"$tmp/err" || fail "-q"
[ ! -s "$tmp/err" ] || fail "-q printed: $(cat "$tmp/err")"
"$BVOX" --quiet reconstruct "$tmp/svg" -o "$tmp/d.nii" 2>"$tmp/err" || fail "global --quiet"
[ ! -s "$tmp/err" ] || fail "global --quiet printed: $(cat "$tmp/err")"

# 12. unknown keys: named, once each
printf '{"unit":"um","pixel":1,"spacing":2,"canvasWidth":640,"sections":[{"z":0,"layer":"a","contours":[[[5,5],[15,5],[15,15],[5,15]]]},{"z":2,"layer":"b","contours":[[[5,5],[15,5],[15,15],[5,15]]]}]}' >"$tmp/k.json"
"$BVOX" reconstruct "$tmp/k.json" -o "$tmp/k.nii" 2>"$tmp/err" || fail "reconstruct k.json"
grep -q 'warning: .*unknown key "canvasWidth"' "$tmp/err" || fail "no warning for canvasWidth: $(cat "$tmp/err")"
[ "$(grep -c 'unknown key "layer"' "$tmp/err")" -eq 1 ] || fail "layer not warned exactly once: $(cat "$tmp/err")"
grep -q 'assumed' "$tmp/err" && fail "a stack that states pixel, spacing and unit warned: $(cat "$tmp/err")"
# 3. an editor's drawing: a full-canvas background rect (a page of 210 x 297
# mm with a viewBox), a hidden layer, and two layers of tracings. Only the
# visible outlines are read (a 10 x 10 square: 100 voxels per section), the
# skipped elements are counted in one warning per file; --svg-select reads
# one layer; a selection naming nothing is refused.
mkdir "$tmp/ink"
for i in 1 2; do
    cat >"$tmp/ink/s$i.svg" <<SVG
<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="210mm" height="297mm" viewBox="0 0 210 297">
  <rect x="0" y="0" width="210" height="297" style="fill:#ffffff"/>
  <g inkscape:groupmode="layer" inkscape:label="cells" id="layer1">
    <polygon points="5,5 15,5 15,15 5,15"/>
  </g>
  <g inkscape:groupmode="layer" inkscape:label="nucleus" id="layer2">
    <circle cx="50" cy="50" r="4" class="nuc"/>
  </g>
  <g inkscape:label="sketch" style="display:none">
    <rect x="100" y="100" width="50" height="50"/>
    <path d="M 100 100 L 150 100 L 150 150 Z"/>
  </g>
</svg>
SVG
done
"$BVOX" reconstruct "$tmp/ink" --pixel 1 --spacing 1 --unit um --svg-select layer:cells \
    -o "$tmp/cells.nii" 2>"$tmp/err" || fail "reconstruct --svg-select layer:cells: $(cat "$tmp/err")"
"$BVOX" info "$tmp/cells.nii" --json >"$tmp/c.json"
python3 -c "import json,sys; o=json.load(open(sys.argv[1])); assert o['count']==200, o" "$tmp/c.json" ||
    fail "the selected layer is not exactly the traced squares: $(cat "$tmp/c.json")"
[ "$(grep -c '^bvox: warning: .*s[12].svg: skipped 1 full-canvas background <rect> (line 3), 2 hidden elements, 1 element not named by --svg-select' "$tmp/err")" -eq 2 ] ||
    fail "skipped elements not listed per file: $(cat "$tmp/err")"
"$BVOX" reconstruct "$tmp/ink" --pixel 1 --spacing 1 --unit um -o "$tmp/all.nii" 2>"$tmp/err" ||
    fail "reconstruct of the drawing"
"$BVOX" info "$tmp/all.nii" --json >"$tmp/a.json"
python3 -c "import json,sys; o=json.load(open(sys.argv[1])); assert 200 < o['count'] < 400, o" "$tmp/a.json" ||
    fail "background or hidden layer read as an outline: $(cat "$tmp/a.json")"
"$BVOX" reconstruct "$tmp/ink" --svg-select class:nuc --quiet -o "$tmp/n.nii" || fail "--svg-select class:"
"$BVOX" reconstruct "$tmp/ink" --svg-select id:nothing -o "$tmp/x.nii" 2>"$tmp/err" &&
    fail "a selection naming nothing was accepted"
grep -q "names no outline" "$tmp/err" || fail "no message for an empty selection: $(cat "$tmp/err")"

# 4. tablet jitter: the outline overshoots its start by 0.3 pixel and so
# crosses itself: kept (the square's 100 voxels), one warning naming the
# section, the contour and the place; --strict refuses it
printf '{"unit":"um","pixel":1,"spacing":1,"sections":[{"z":0,"contours":[[[5,5],[15,5],[15,15],[5,15],[5,4.7],[5.3,5.2]]]}]}' >"$tmp/jit.json"
"$BVOX" reconstruct "$tmp/jit.json" -o "$tmp/jit.nii" 2>"$tmp/err" || fail "jitter refused: $(cat "$tmp/err")"
grep -q '^bvox: warning: .*jit.json: section 1.*contour 1 crosses itself (edges .* near ' "$tmp/err" ||
    fail "jitter not warned: $(cat "$tmp/err")"
"$BVOX" info "$tmp/jit.nii" --json >"$tmp/j.json"
python3 -c "import json,sys; o=json.load(open(sys.argv[1])); assert o['count']==100, o" "$tmp/j.json" ||
    fail "jittered square is not 100 voxels: $(cat "$tmp/j.json")"
"$BVOX" reconstruct "$tmp/jit.json" --strict -o "$tmp/jit2.nii" 2>"$tmp/err" && fail "--strict accepted it"
grep -q 'crosses itself' "$tmp/err" || fail "--strict message: $(cat "$tmp/err")"
# 5. a folder of section images that also holds the blank: given as
# --background it is not a section too; not given, it is named in a warning;
# the scale not given is said once
mkdir "$tmp/img"
python3 - "$(dirname "$0")" "$tmp/img" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from pngtool import write_png
d = sys.argv[2]
w = h = 32
write_png(d + "/blank.png", w, h, [200] * (w * h))
for k in range(3):
    write_png(d + "/s%d.png" % (k + 1), w, h,
              [60 if 8 <= x < 24 and 8 <= y < 24 else 200 for y in range(h) for x in range(w)])
PY
"$BVOX" reconstruct "$tmp/img" --background "$tmp/img/blank.png" --pixel 1 --spacing 1 --unit um \
    --report "$tmp/rep.json" -o "$tmp/img.nii" 2>"$tmp/err" || fail "reconstruct with the blank in the folder: $(cat "$tmp/err")"
jcheck "$tmp/rep.json" 'o["sections"] == 3' || fail "the blank was also used as a section: $(cat "$tmp/rep.json")"
grep -q warning "$tmp/err" && fail "warned with everything given: $(cat "$tmp/err")"
"$BVOX" reconstruct "$tmp/img" --report "$tmp/rep.json" -o "$tmp/img.nii" 2>"$tmp/err" ||
    fail "reconstruct without --background"
jcheck "$tmp/rep.json" 'o["sections"] == 4' || fail "sections without --background"
grep -q '^bvox: warning: .*blank.png: named like a blank' "$tmp/err" || fail "blank not named: $(cat "$tmp/err")"
grep -q '^bvox: warning: section images: not given, assumed: pixel size 1 (--pixel), section spacing 1 (--spacing), no unit (--unit)$' "$tmp/err" ||
    fail "assumed scale not said: $(cat "$tmp/err")"
echo "recon_assumptions: ok"
