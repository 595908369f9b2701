#!/bin/sh
# reconstruct.sh — `bvox reconstruct` end to end on sections written here by
# the tests' own PNG coder (pngtool.py): an ellipsoid (semi-axes 14, 14, 9
# pixels) cut into 12 sections 2 pixels apart, dark on a bright field with 3
# dark round markers, each section shifted by a known offset (the middle one,
# the reference, not). Aligned, the model's bounding box is the ellipsoid's;
# with --no-align it is smeared by the shifts. The report (JSON) gives each
# section's markers and the shift found; --save-contours writes the aligned
# stack. Bad input: sections of different sizes, an empty folder, a section
# whose markers are gone (warning naming it, fallback in the report), TIFF
# sections, a --background blank, contour files with a self-crossing or a
# 2-point contour (exit 1 naming the section), bad command lines (exit 2).
# Usage: sh reconstruct.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# mksections DIR [nomarkers=K] [bigger=K] [noshift]: DIR/s1.png .. s12.png
mksections() {
    mkdir -p "$1"
    python3 - "$here" "$@" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from pngtool import write_png
out, opts = sys.argv[2], sys.argv[3:]
nomarkers = [int(o.split("=")[1]) for o in opts if o.startswith("nomarkers=")]
bigger = [int(o.split("=")[1]) for o in opts if o.startswith("bigger=")]
shifts = [(3, -2), (-4, 1), (2, 4), (-1, -3), (4, 2), (-3, -4), (0, 0),
          (1, 3), (-2, 2), (4, -1), (-4, -2), (2, -4)]
if "noshift" in opts:
    shifts = [(0, 0)] * 12
markers = [(8.5, 8.5), (71.5, 12.5), (10.5, 70.5)]
for k in range(12):
    w = h = 80 + (4 if k in bigger else 0)
    dx, dy = shifts[k]
    z = 2 * k - 11.0
    px = []
    for y in range(h):
        for x in range(w):
            cx, cy = x + 0.5 - dx, y + 0.5 - dy   # the block point seen at this pixel
            v = 200
            if ((cx - 40) / 14) ** 2 + ((cy - 40) / 14) ** 2 + (z / 9) ** 2 <= 1:
                v = 70
            if k not in nomarkers:
                for mx, my in markers:
                    if (cx - mx) ** 2 + (cy - my) ** 2 <= 9:
                        v = 10
            px.append(v)
    write_png("%s/s%d.png" % (out, k + 1), w, h, px)
PY
}

jcheck() {
    python3 - "$@" <<'PY' || return 1
import json, sys
path, expr = sys.argv[1:]
o = json.load(open(path))
if not eval(expr):
    sys.exit("%s: %s is false for %s" % (path, expr, json.dumps(o)[:1500]))
PY
}

# info JSON of a model into $tmp/info.json
info() { "$BVOX" info --json "$1" >"$tmp/info.json" || fail "info $1"; }

mksections "$tmp/sec"

# aligned: the ellipsoid's box (x, y 26..53 for semi-axis 14 about 40)
"$BVOX" reconstruct "$tmp/sec" --markers 3 --spacing 2 --unit um -o "$tmp/m.nii" \
    --report "$tmp/r.json" --save-contours "$tmp/c.json" 2>"$tmp/err" ||
    { cat "$tmp/err"; fail "reconstruct exited $?"; }
grep -q "reconstruct: sections 12/12" "$tmp/err" || fail "no progress on stderr"
info "$tmp/m.nii"
jcheck "$tmp/info.json" 'o["dims"] == [80, 80, 24] and o["voxel_size"] == [1, 1, 1] and o["unit"] == "um"' ||
    fail "model size"
jcheck "$tmp/info.json" 'o["bbox"]["min"][:2] == [26, 26] and o["bbox"]["max"][:2] == [53, 53]' ||
    fail "aligned bounding box"
# report: markers, the shifts found (onto the reference: minus the shift), timings
jcheck "$tmp/r.json" 'o["sections"] == 12 and o["aligned"] and o["reference"] == 7 and o["fallbacks"] == 0' ||
    fail "report header"
jcheck "$tmp/r.json" 'all(s["markers_found"] == 3 and s["matched"] >= 2 and not s["fallback"] for s in o["per_section"])' ||
    fail "report markers"
jcheck "$tmp/r.json" '[s["name"] for s in o["per_section"]] == ["s%d.png" % (k + 1) for k in range(12)]' ||
    fail "natural order"
jcheck "$tmp/r.json" 'all(abs(s["transform"]["tx"] + d[0]) < 0.01 and abs(s["transform"]["ty"] + d[1]) < 0.01 and abs(s["transform"]["angle_deg"]) < 0.01 for s, d in zip(o["per_section"], [(3, -2), (-4, 1), (2, 4), (-1, -3), (4, 2), (-3, -4), (0, 0), (1, 3), (-2, 2), (4, -1), (-4, -2), (2, -4)]))' ||
    fail "shifts found"
jcheck "$tmp/r.json" 'sorted(o["timings_ms"]) == sorted(["read", "background", "threshold", "smooth", "markers", "specks", "contours", "align", "volume", "total"])' ||
    fail "timings"
jcheck "$tmp/r.json" 'o["model"]["dims"] == [80, 80, 24]' || fail "report model"
jcheck "$tmp/c.json" 'len(o["sections"]) == 12' || fail "saved contours"

# the saved (aligned) contours as input: the same model; its markers align
# it again (onto themselves: identity)
"$BVOX" reconstruct "$tmp/c.json" --quiet -o "$tmp/fromc.nii" --report "$tmp/rc.json" ||
    fail "reconstruct from contours"
info "$tmp/fromc.nii"
jcheck "$tmp/info.json" 'o["dims"] == [80, 80, 24] and o["bbox"]["min"][:2] == [26, 26] and o["bbox"]["max"][:2] == [53, 53] and o["unit"] == "um"' ||
    fail "model from contours"
jcheck "$tmp/rc.json" 'o["aligned"] and all(abs(s["transform"]["tx"]) < 1e-6 and s["threshold"] is None for s in o["per_section"])' ||
    fail "contours report"

if "$BVOX" reconstruct "$tmp/c.json" --markers-file "$tmp/c.json" -o "$tmp/x.nii" 2>"$tmp/err"; then
    fail "--markers-file with a contour file accepted"
fi
grep -q "carries its own markers" "$tmp/err" || fail "--markers-file message"

# not aligned: smeared by the shifts
"$BVOX" reconstruct "$tmp/sec" --markers 3 --spacing 2 --no-align --quiet -o "$tmp/n.nii" ||
    fail "reconstruct --no-align"
info "$tmp/n.nii"
jcheck "$tmp/info.json" 'o["bbox"]["max"][0] - o["bbox"]["min"][0] >= 31 and o["bbox"]["max"][1] - o["bbox"]["min"][1] >= 31' || fail "unaligned box (aligned: 27 wide)"

# a blank section image as the background, and a fixed threshold: the same box
python3 - "$here" "$tmp" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from pngtool import write_png
write_png(sys.argv[2] + "/blank.png", 80, 80, [200] * 6400)
write_png(sys.argv[2] + "/blank84.png", 84, 84, [200] * 84 * 84)
PY
"$BVOX" reconstruct "$tmp/sec" --background "$tmp/blank.png" --threshold 100 --markers 3 \
    --spacing 2 --quiet -o "$tmp/bg.nii" || fail "--background"
info "$tmp/bg.nii"
jcheck "$tmp/info.json" 'o["bbox"]["min"][:2] == [26, 26] and o["bbox"]["max"][:2] == [53, 53]' ||
    fail "box with --background --threshold"
if "$BVOX" reconstruct "$tmp/sec" --background "$tmp/blank84.png" --quiet -o "$tmp/bg2.nii" \
    2>"$tmp/err"; then fail "a background of another size accepted"; fi
grep -q "section 's1.png': the background is 84 x 84 pixels but the section 80 x 80" "$tmp/err" ||
    { cat "$tmp/err"; fail "background size message"; }
[ ! -e "$tmp/bg2.nii" ] || fail "output after a failure"

# the same files given one by one, in the order given
set --
for k in 1 2 3 4 5 6 7 8 9 10 11 12; do set -- "$@" "$tmp/sec/s$k.png"; done
"$BVOX" reconstruct "$@" --markers 3 --spacing 2 --quiet -o "$tmp/m2.nii" || fail "file list"
cp "$tmp/info.json" "$tmp/info_m.json"
info "$tmp/m.nii"
count=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["count"])' "$tmp/info.json")
info "$tmp/m2.nii"
jcheck "$tmp/info.json" "o['count'] == $count" || fail "the file list gives another model"

# the same sections as TIFF files (uncompressed 8-bit gray, written here)
mkdir "$tmp/tif"
python3 - "$here" "$tmp" <<'PY'
import struct, sys
sys.path.insert(0, sys.argv[1])
from pngtool import read_png
for k in range(1, 13):
    img = read_png("%s/sec/s%d.png" % (sys.argv[2], k))
    w, h = img["width"], img["height"]
    pix = b"".join(bytes(r) for r in img["rows"])
    tags = [(256, 3, w), (257, 3, h), (258, 3, 8), (259, 3, 1), (262, 3, 1),
            (273, 4, 8), (277, 3, 1), (278, 3, h), (279, 4, len(pix))]
    ifd_off = 8 + len(pix)
    ifd = struct.pack("<H", len(tags)) + b"".join(
        struct.pack("<HHI", t, ty, 1) + (struct.pack("<HH", v, 0) if ty == 3 else struct.pack("<I", v))
        for t, ty, v in tags) + struct.pack("<I", 0)
    open("%s/tif/t%d.tif" % (sys.argv[2], k), "wb").write(
        b"II*\0" + struct.pack("<I", ifd_off) + pix + ifd)
PY
"$BVOX" reconstruct "$tmp/tif" --markers 3 --spacing 2 --quiet -o "$tmp/t.nii" || fail "TIFF sections"
info "$tmp/t.nii"
jcheck "$tmp/info.json" "o['count'] == $count" || fail "TIFF sections give another model"

# the steps as pictures: 4 per section, the final mask without markers
mkdir "$tmp/steps"
"$BVOX" reconstruct "$tmp/sec" --markers 3 --quiet --save-steps "$tmp/steps" -o "$tmp/s.nii" ||
    fail "--save-steps"
[ "$(ls "$tmp/steps" | wc -l)" = 48 ] || fail "48 step pictures"
python3 - "$here" "$tmp/steps" <<'PY' || fail "step pictures"
import sys
sys.path.insert(0, sys.argv[1])
from pngtool import read_png
d = sys.argv[2]
thr = read_png(d + "/s7.2_threshold.png")["rows"]
fin = read_png(d + "/s7.4_final.png")["rows"]
assert thr[8][8] == 255 and fin[8][8] == 0, "the marker at (8, 8) is erased"
assert thr[40][40] == 255 and fin[40][40] == 255, "the object stays"
assert read_png(d + "/s7.1_flat.png")["bits"] == 8
PY

# SVG folder of the aligned contours
"$BVOX" reconstruct "$tmp/sec" --markers 3 --spacing 2 --quiet --save-contours "$tmp/svg" ||
    fail "--save-contours DIR"
[ "$(ls "$tmp/svg" | grep -c '\.svg$')" = 12 ] || fail "12 SVG files"

# a section without markers: warning naming it, fallback, exit 0
mksections "$tmp/nom" nomarkers=4
"$BVOX" reconstruct "$tmp/nom" --markers 3 --spacing 2 -o "$tmp/f.nii" --report "$tmp/f.json" \
    2>"$tmp/err" || fail "fallback exit $?"
grep -q "warning: section 's5.png': 0 markers found (3 expected)" "$tmp/err" ||
    { cat "$tmp/err"; fail "fallback warning"; }
jcheck "$tmp/f.json" 'o["fallbacks"] == 1 and o["per_section"][4]["fallback"] and "s5.png" in o["per_section"][4]["message"]' ||
    fail "fallback in the report"

# sections of different sizes: exit 1 naming the section, no output
mksections "$tmp/big" bigger=8
if "$BVOX" reconstruct "$tmp/big" --quiet -o "$tmp/b.nii" 2>"$tmp/err"; then fail "sizes accepted"; fi
grep -q "s9.png' is 84 x 84" "$tmp/err" || { cat "$tmp/err"; fail "size message"; }
[ ! -e "$tmp/b.nii" ] || fail "output after a failure"

# an empty folder
mkdir "$tmp/empty"
if "$BVOX" reconstruct "$tmp/empty" -o "$tmp/e.nii" 2>"$tmp/err"; then fail "empty folder accepted"; fi
grep -q "holds no section images" "$tmp/err" || { cat "$tmp/err"; fail "empty folder message"; }

# contour files: a self-crossing contour, a contour of 2 points: exit 1 naming the section
cat >"$tmp/bow.json" <<'JSON'
{"unit": "um", "pixel": 1, "spacing": 2, "sections": [{"z": 0, "contours": [[[0,0],[10,10],[10,0],[0,10]]]}, {"z": 2, "contours": [[[0,0],[10,0],[10,10],[0,10]]]}]}
JSON
# (a contour crossing itself is filled even-odd with a warning by default,
# issue 14; --strict refuses it as before)
if "$BVOX" reconstruct "$tmp/bow.json" -o "$tmp/bow.nii" --strict 2>"$tmp/err"; then fail "a crossing contour accepted with --strict"; fi
grep -q "section 1 (z = 0): contour 1 crosses itself" "$tmp/err" || { cat "$tmp/err"; fail "crossing message"; }
[ ! -e "$tmp/bow.nii" ] || fail "output after a failure"
"$BVOX" reconstruct "$tmp/bow.json" -o "$tmp/bow.nii" 2>"$tmp/err" || fail "a crossing contour refused without --strict"
grep -q "^bvox: warning: .*section 1 (z = 0): contour 1 crosses itself" "$tmp/err" || { cat "$tmp/err"; fail "crossing warning"; }
cat >"$tmp/two.json" <<'JSON'
{"unit": "um", "pixel": 1, "spacing": 2, "sections": [{"z": 0, "contours": [[[0,0],[10,10]]]}]}
JSON
if "$BVOX" reconstruct "$tmp/two.json" -o "$tmp/two.nii" 2>"$tmp/err"; then fail "a 2-point contour accepted"; fi
grep -q "section 1 (z = 0): contour 1 has 2 distinct points" "$tmp/err" || { cat "$tmp/err"; fail "2-point message"; }

# command lines
"$BVOX" reconstruct --help | grep -q -- "--markers-file" || fail "--help"
for bad in "--threshold 80 --otsu" "--dark --bright" "--markers 1" "--smooth x" "--markers 3 --markers-file f.json" "--background b.png --no-background" "--pixel 0" "--unknown"; do
    # shellcheck disable=SC2086
    set +e
    "$BVOX" reconstruct "$tmp/sec" $bad -o "$tmp/x.nii" 2>/dev/null
    rc=$?
    set -e
    [ "$rc" = 2 ] || fail "'$bad' exited $rc, wanted 2"
done
set +e
"$BVOX" reconstruct -o "$tmp/x.nii" 2>/dev/null
rc=$?
set -e
[ "$rc" = 2 ] || fail "no sections exited $rc"
# --markers auto counts the 3 markers itself (said in a warning) and gives
# the same alignment and model as --markers 3
"$BVOX" reconstruct "$tmp/sec" --markers auto --spacing 2 --unit um -o "$tmp/auto.nii" \
    --report "$tmp/ra.json" 2>"$tmp/err" || { cat "$tmp/err"; fail "--markers auto exited $?"; }
grep -q '^bvox: warning: --markers auto: 3 markers per section' "$tmp/err" || { cat "$tmp/err"; fail "auto count not said"; }
jcheck "$tmp/ra.json" 'o["fallbacks"] == 0 and all(s["markers_found"] == 3 for s in o["per_section"])' ||
    fail "--markers auto report"
cmp "$tmp/auto.nii" "$tmp/m.nii" || fail "--markers auto gives another model than --markers 3"
# --marker-coords: the reference section's markers (8.5,8.5), (71.5,12.5),
# (10.5,70.5) belong at those points turned by 90 degrees and moved by
# (100, 10), listed in another order: the reference's transform is exactly
# that, and every other section is carried along
printf '{"sections":[{"markers":[[87.5,81.5],[91.5,18.5],[29.5,20.5]]}]}' >"$tmp/frame.json"
"$BVOX" reconstruct "$tmp/sec" --markers 3 --marker-coords "$tmp/frame.json" --spacing 2 --quiet \
    -o "$tmp/fr.nii" --report "$tmp/rf.json" || fail "--marker-coords exited $?"
jcheck "$tmp/rf.json" 'all(abs(o["per_section"][6]["transform"][k] - v) < 1e-3 for k, v in (("angle_deg", 90), ("tx", 100), ("ty", 10)))' ||
    fail "reference section not put into the given frame"
jcheck "$tmp/rf.json" 'all(abs(s["transform"]["angle_deg"] - 90) < 10 for s in o["per_section"])' ||
    fail "other sections not carried into the frame"
printf '{"sections":[{"markers":[[1,1]]}]}' >"$tmp/one.json"
"$BVOX" reconstruct "$tmp/sec" --markers 3 --marker-coords "$tmp/one.json" -o "$tmp/x.nii" 2>"$tmp/err" &&
    fail "marker coords without markers accepted"
grep -q "needs at least 2 marker positions" "$tmp/err" || { cat "$tmp/err"; fail "marker coords message"; }
exit 0
