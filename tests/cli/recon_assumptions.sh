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
echo "recon_assumptions: ok"
