#!/bin/sh
# render_annotate.sh — `bvox render`'s colours, background and annotations
# and several volumes in one picture (issue 18 item 2, issue 19 item 4),
# through the real command, the PNGs read back by pngtool.py: --color
# multiplies the gray picture sample by sample, a transparent background is
# an RGBA PNG with alpha 0 exactly on the background, two volumes on one grid
# take their colours (the nearer in front), --labels with --lut, annotations
# on every turntable frame and every sheet cell; bad colours,
# sizes and mixes exit 2 with one line, a grid mismatch exits 1, nothing
# written. Usage: sh render_annotate.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

# a 3 x 2 x 5 volume: column (x, y) filled from z = x + y on (tiny.nii of
# render.sh), and B: only column (2, 1) at z = 0 (nearer along +z)
python3 - "$tmp" <<'PY'
import sys
t = sys.argv[1]
a = bytearray(3 * 2 * 5)
b = bytearray(3 * 2 * 5)
for z in range(5):
    for y in range(2):
        for x in range(3):
            a[(z * 2 + y) * 3 + x] = 1 if z >= x + y else 0
b[(0 * 2 + 1) * 3 + 2] = 1
open(t + "/a.raw", "wb").write(a)
open(t + "/b.raw", "wb").write(b)
lab = bytearray(a)
for i in range(len(lab)):
    lab[i] = (3 if i % 3 < 2 else 7) if a[i] else 0
open(t + "/lab.raw", "wb").write(lab)
open(t + "/lab.txt", "w").write("3 Left 255 0 0 0\n7 Right 0 0 255 0\n")
PY
for v in a b; do
    "$BVOX" convert "$tmp/$v.raw" "$tmp/$v.nii" --dims 3,2,5 --type u8 >/dev/null || fail "making $v.nii"
done
"$BVOX" convert "$tmp/a.raw" "$tmp/c.nii" --dims 3,5,2 --type u8 >/dev/null || fail "making c.nii"

# --color: every sample is gray * colour / 255, rounded
"$BVOX" render "$tmp/a.nii" -o "$tmp/g.png" --shade binary || fail "gray"
"$BVOX" render "$tmp/a.nii" -o "$tmp/c.png" --shade binary --color '#ff8000' || fail "colour"
png read "$tmp/g.png" >"$tmp/g.json"
png read "$tmp/c.png" >"$tmp/c.json"
python3 - "$tmp/g.json" "$tmp/c.json" <<'PY' || fail "--color is not gray x colour"
import json, sys
g = json.load(open(sys.argv[1])); c = json.load(open(sys.argv[2]))
assert (c["channels"], g["channels"]) == (3, 1)
col = (255, 128, 0)
for gr, cr in zip(g["rows"], c["rows"]):
    for x, v in enumerate(gr):
        assert cr[3 * x:3 * x + 3] == [(v * k + 127) // 255 for k in col], (gr, cr)
PY

# transparent: RGBA, alpha 0 exactly where the gray picture is background
# (column (0, 0) is full from z = 0; all columns hit: use B, one column)
"$BVOX" render "$tmp/b.nii" -o "$tmp/t.png" --background transparent || fail "transparent"
png read "$tmp/t.png" >"$tmp/t.json"
python3 - "$tmp/t.json" <<'PY' || fail "transparent alpha"
import json, sys
t = json.load(open(sys.argv[1]))
assert t["channels"] == 4, t["channels"]
alpha = [[r[4 * x + 3] for x in range(t["width"])] for r in t["rows"]]
assert alpha == [[0, 0, 0], [0, 0, 255]], alpha
PY
"$BVOX" render "$tmp/b.nii" -o "$tmp/w.png" --background white || fail "white"
png read "$tmp/w.png" >"$tmp/w.json"
python3 - "$tmp/w.json" <<'PY' || fail "white background"
import json, sys
w = json.load(open(sys.argv[1]))
assert w["rows"][0][:3] == [255, 255, 255], w["rows"][0]
PY

# two volumes, one grid: along +z B (blue) is in front at column (2, 1)
# (z = 0, where A starts at z = 3), A (red) elsewhere
"$BVOX" render "$tmp/a.nii" "$tmp/b.nii" --color red,blue -o "$tmp/two.png" --shade binary ||
    fail "two volumes"
png read "$tmp/two.png" >"$tmp/two.json"
python3 - "$tmp/two.json" <<'PY' || fail "two volumes' colours"
import json, sys
t = json.load(open(sys.argv[1]))
px = lambda x, y: t["rows"][y][3 * x:3 * x + 3]
r, g, b = px(2, 1)
assert r == 0 and g == 0 and b > 0, px(2, 1)
r, g, b = px(0, 0)
assert r > 0 and g == 0 and b == 0, px(0, 0)
PY
# a label volume in its table's colours: x 0, 1 label 3 (red), x 2 label 7 (blue)
"$BVOX" render "$tmp/lab.raw" --dims 3,2,5 --type u8 --labels --lut "$tmp/lab.txt" \
    -o "$tmp/lab.png" --shade binary || fail "labels"
png read "$tmp/lab.png" >"$tmp/lab.json"
python3 - "$tmp/lab.json" <<'PY' || fail "label colours"
import json, sys
t = json.load(open(sys.argv[1]))
px = lambda x, y: t["rows"][y][3 * x:3 * x + 3]
assert px(0, 0)[0] > 0 and px(0, 0)[1:] == [0, 0], px(0, 0)
assert px(2, 0)[2] > 0 and px(2, 0)[:2] == [0, 0], px(2, 0)
PY
# annotations on a picture large enough for them
"$BVOX" render "$tmp/a.nii" -o "$tmp/n.png" --view iso --size 120,90 --scale-bar --axes \
    --title "tiny" || fail "annotations"
png read "$tmp/n.png" >"$tmp/n.json"
python3 - "$tmp/n.json" <<'PY' || fail "annotation shape"
import json, sys
t = json.load(open(sys.argv[1]))
assert (t["width"], t["height"], t["channels"]) == (120, 90, 3)
PY

# annotations on the turntable's frames and on the sheet (issue 18): the
# annotated picture is the plain one (gray v = RGB v,v,v) except near the
# axes triad (lower right of each frame / each sheet cell, turned with the
# view) and the title (top rows of the frame / of the sheet), and every
# frame and cell has its triad
a="$tmp/a.nii"
"$BVOX" render "$a" -o "$tmp/tp.png" --view iso --turntable 3 --size 160,160 ||
    fail "plain turntable"
"$BVOX" render "$a" -o "$tmp/ta.png" --view iso --turntable 3 --size 160,160 --axes --title T ||
    fail "annotated turntable"
"$BVOX" render "$a" -o "$tmp/ta.gif" --view iso --turntable 3 --size 160,160 --axes --scale-bar \
    --title T || fail "annotated turntable GIF"
"$BVOX" render "$a" -o "$tmp/sp.png" --sheet --size 160,160 || fail "plain sheet"
"$BVOX" render "$a" -o "$tmp/sa.png" --sheet --size 160,160 --axes --title T || fail "annotated sheet"
for f in tp_000 tp_001 tp_002 ta_000 ta_001 ta_002 sp sa; do png read "$tmp/$f.png" >"$tmp/$f.json"; done
python3 - "$tmp" "$here" <<'PY' || fail "annotations of turntable frames and sheet cells"
import json, sys
t = sys.argv[1]
sys.path.insert(0, sys.argv[2])
import pngtool
assert pngtool.read_gif(t + "/ta.gif")["frames"] == 3
def load(n):
    return json.load(open("%s/%s.json" % (t, n)))
def diff(plain, ann):
    assert plain["channels"] == 1 and ann["channels"] == 3, (plain["channels"], ann["channels"])
    assert (plain["width"], plain["height"]) == (ann["width"], ann["height"])
    out = set()
    for y, (pr, ar) in enumerate(zip(plain["rows"], ann["rows"])):
        for x, v in enumerate(pr):
            if ar[3 * x:3 * x + 3] != [v, v, v]:
                out.add((x, y))
    return out
def near_axes(x, y, x1, y1):  # the triad: centre 32 pixels in from the corner, reach ~30
    return x1 - 64 <= x < x1 and y1 - 64 <= y < y1
for i in range(3):
    d = diff(load("tp_%03d" % i), load("ta_%03d" % i))
    triad = {p for p in d if near_axes(p[0], p[1], 160, 160)}
    title = {p for p in d if p[1] < 16}
    assert triad and title and d == triad | title, (i, sorted(d - triad - title)[:5])
d = diff(load("sp"), load("sa"))
title = {p for p in d if p[1] < 16}
assert title, "no title on the sheet"
for cx in (0, 160):
    for cy in (0, 160):
        assert any(near_axes(x, y, cx + 160, cy + 160) for x, y in d), ("no triad in cell", cx, cy)
rest = [p for p in d if p not in title and
        not any(near_axes(p[0], p[1], cx + 160, cy + 160) for cx in (0, 160) for cy in (0, 160))]
assert not rest, rest[:5]
PY

# bad command lines: exit 2, one line, nothing written
usage() {
    set +e
    "$BVOX" render "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "render $* exited $rc, wanted 2"
    grep -q '^bvox: render: ' "$tmp/err" || fail "render $*: message: $(cat "$tmp/err")"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "render $*: more than one line: $(cat "$tmp/err")"
}
a="$tmp/a.nii"
usage "$a" -o "$tmp/x.png" --color chartreuse
usage "$a" -o "$tmp/x.png" --color '#12345'
usage "$a" -o "$tmp/x.png" --color '#gg0000'
usage "$a" -o "$tmp/x.png" --color red,
usage "$a" -o "$tmp/x.png" --color ''
usage "$a" "$tmp/b.nii" -o "$tmp/x.png" --color red,green,blue
usage "$a" -o "$tmp/x.png" --background nothing
usage "$a" -o "$tmp/x.png" --size 0,10 --scale-bar
usage "$a" -o "$tmp/x.png" --size 10,-1
usage "$a" -o "$tmp/x.png" --size 20000,10
usage "$a" -o "$tmp/x.png" --title "$(printf 'tab\there')"
usage "$a" -o "$tmp/x.png" --lut "$tmp/lab.txt"
usage "$a" "$tmp/b.nii" -o "$tmp/x.png" --labels
usage "$a" -o "$tmp/x.gif" --turntable 2 --background transparent
usage "$a" -o "$tmp/x.png" --stereo anaglyph --background transparent
usage "$a" "$tmp/b.nii" -o "$tmp/x.png" --sheet
[ ! -e "$tmp/x.png" ] && [ ! -e "$tmp/x.gif" ] || fail "a usage error wrote output"

# two grids: a failure (exit 1) naming the mismatch, nothing written
set +e
"$BVOX" render "$a" "$tmp/c.nii" -o "$tmp/x.png" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 1 ] || fail "grid mismatch exited $rc"
grep -q "share one grid" "$tmp/err" || fail "grid mismatch message: $(cat "$tmp/err")"
[ ! -e "$tmp/x.png" ] || fail "a failure wrote output"
echo "render_annotate: ok"
