#!/bin/sh
# render.sh — `bvox render` through the real command, its PNG and GIF output
# read back by pngtool.py (an independent coder): the axis-view pixel
# conventions checked on a tiny volume through the 16-bit --depth map (one
# pixel per voxel column; +z: column x, row y, rays entering at z = 0; 0 for
# background, else depth + 1), image sizes of zoom, average, --size, stereo
# pairs, the sheet and turntables (GIF frame count and numbered PNGs), cut
# pictures in colour; bad command lines (exit 2) and failures (exit 1).
# Usage: sh render.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

# shape FILE W H CHANNELS BITS
shape() {
    png read "$1" >"$tmp/s.json" || fail "cannot read $1"
    python3 - "$tmp/s.json" "$2" "$3" "$4" "$5" <<'PY' || fail "$1 has the wrong shape"
import json, sys
g = json.load(open(sys.argv[1]))
want = tuple(int(a) for a in sys.argv[2:6])
got = (g["width"], g["height"], g["channels"], g["bits"])
assert got == want, (got, want)
PY
}
# rows FILE ROWS-AS-PYTHON-LIST (exact samples)
rows() {
    png read "$1" >"$tmp/r.json" || fail "cannot read $1"
    python3 - "$tmp/r.json" "$2" <<'PY' || fail "$1 is not as expected"
import json, sys
g = json.load(open(sys.argv[1]))
want = eval(sys.argv[2])
assert g["rows"] == want, "\n got %s\nwant %s" % (g["rows"], want)
PY
}

# 3 x 2 x 5 voxels: (0,0,0), (2,1,3), (2,1,4)
python3 - "$tmp/tiny.raw" <<'PY'
import sys
nx, ny, nz = 3, 2, 5
v = bytearray(nx * ny * nz)
for x, y, z in [(0, 0, 0), (2, 1, 3), (2, 1, 4)]:
    v[(z * ny + y) * nx + x] = 1
open(sys.argv[1], "wb").write(v)
PY
"$BVOX" convert "$tmp/tiny.raw" "$tmp/tiny.nii" --dims 3,2,5 --type u8 || fail "making tiny.nii"

view() { # VIEW ROWS: the depth map of an axis view
    "$BVOX" render "$tmp/tiny.nii" -o "$tmp/v.png" --view "$1" --depth "$tmp/d.png" ||
        fail "render --view $1 exited $?"
    rows "$tmp/d.png" "$2"
}
view +z '[[1,0,0],[0,0,4]]'      # column x, row y; z = 0 is depth 0
view -z '[[5,0,0],[0,0,1]]'      # rays enter at z = 4
view +x '[[1,0],[0,0],[0,0],[0,3],[0,3]]'  # column y, row z
view -x '[[3,0],[0,0],[0,0],[0,1],[0,1]]'
view +y '[[1,0,0],[0,0,0],[0,0,0],[0,0,2],[0,0,2]]'  # column x, row z
view -y '[[2,0,0],[0,0,0],[0,0,0],[0,0,1],[0,0,1]]'
shape "$tmp/d.png" 3 5 1 16
shape "$tmp/v.png" 3 5 1 8
# the default view is +z, and its picture is black exactly where nothing is hit
"$BVOX" render "$tmp/tiny.nii" -o "$tmp/v.png" --shade depth || fail "render default"
png read "$tmp/v.png" >"$tmp/v.json"
python3 - "$tmp/v.json" <<'PY' || fail "background pixels"
import json, sys
r = json.load(open(sys.argv[1]))["rows"]
assert r[0][0] > 0 and r[1][2] > 0 and r[0][1] == r[0][2] == r[1][0] == r[1][1] == 0, r
assert r[0][0] > r[1][2], r   # depth shading: nearer is brighter
PY

# sizes: zoom, average, --size, projections, stereo, sheet
"$BVOX" render "$tmp/tiny.nii" -o "$tmp/z.png" --zoom 4 --average --filter smooth || fail "zoom"
shape "$tmp/z.png" 24 16 1 8
"$BVOX" render "$tmp/tiny.nii" -o "$tmp/p.png" --view 30,20 --size 40,30 --shade gradient --light 90,30 ||
    fail "projection"
shape "$tmp/p.png" 40 30 1 8
"$BVOX" render "$tmp/tiny.nii" -o "$tmp/p.png" --view iso-x+y-z --depth "$tmp/pd.png" || fail "iso"
shape "$tmp/p.png" 512 512 1 8
shape "$tmp/pd.png" 512 512 1 16

# a real object: the specimen, written by bvox demo
"$BVOX" demo -o "$tmp/demo" >/dev/null 2>&1 || fail "demo"
spec="$tmp/demo/specimen.nii.gz"
"$BVOX" render "$spec" -o "$tmp/sbs.png" --view iso --size 64,48 --stereo sbs || fail "sbs"
shape "$tmp/sbs.png" 128 48 1 8
"$BVOX" render "$spec" -o "$tmp/ana.png" --view iso --size 64,48 --stereo anaglyph || fail "anaglyph"
shape "$tmp/ana.png" 64 48 3 8
png read "$tmp/ana.png" >"$tmp/ana.json"
python3 - "$tmp/ana.json" <<'PY' || fail "anaglyph channels"
import json, sys
r = json.load(open(sys.argv[1]))["rows"]
px = [(row[i], row[i + 1], row[i + 2]) for row in r for i in range(0, len(row), 3)]
assert all(g == b for _, g, b in px), "green and blue are the right eye"
assert sum(1 for rr, g, _ in px if rr != g) > 20, "the eyes differ"
PY
"$BVOX" render "$spec" -o "$tmp/sheet.png" --sheet --size 40,40 || fail "sheet"
shape "$tmp/sheet.png" 80 80 1 8
"$BVOX" render "$spec" -o "$tmp/cut.png" --view +z --cut 0,0,1,-1500 --keep above || fail "cut"
shape "$tmp/cut.png" 256 256 3 8
png read "$tmp/cut.png" >"$tmp/cut.json"
python3 - "$tmp/cut.json" <<'PY' || fail "cut face"
import json, sys
r = json.load(open(sys.argv[1]))["rows"]
# seen along +z, the part above z = 1500 um (slice 60) shows its cut face:
# the tinted pixels (red above blue) fill the body's section at the centre
tinted = sum(1 for row in r for i in range(0, len(row), 3) if row[i] > row[i + 2] + 20)
assert tinted > 10000, tinted
c = r[128][3 * 60:3 * 60 + 3]
assert c[0] > c[2] + 20, c
PY

# turntables: a looping GIF of N frames, or N numbered PNGs
"$BVOX" render "$spec" -o "$tmp/spin.gif" --view iso --size 48,48 --turntable 5 || fail "gif"
png gif "$tmp/spin.gif" >"$tmp/g.json"
python3 - "$tmp/g.json" <<'PY' || fail "the GIF"
import json, sys
g = json.load(open(sys.argv[1]))
assert g == {"version": "GIF89a", "width": 48, "height": 48, "frames": 5, "loops": True}, g
PY
mkdir "$tmp/frames"
"$BVOX" render "$spec" -o "$tmp/frames/turn.png" --size 32,32 --turntable 3 --cut 1,0,0,-1275 ||
    fail "png frames"
[ "$(ls "$tmp/frames" | tr '\n' ' ')" = "turn_000.png turn_001.png turn_002.png " ] ||
    fail "frames: $(ls "$tmp/frames")"
shape "$tmp/frames/turn_002.png" 32 32 3 8

# bad command lines: exit 2, nothing written
usage() {
    set +e
    "$BVOX" render "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "render $* exited $rc, wanted 2"
    grep -q '^bvox: render: ' "$tmp/err" || fail "render $*: message: $(cat "$tmp/err")"
}
t="$tmp/tiny.nii"
usage
usage "$t"
usage "$t" -o "$tmp/x.tif"
usage "$t" -o "$tmp/x.gif"
usage "$t" -o "$tmp/x.png" --view +w
usage "$t" -o "$tmp/x.png" --view iso+x
usage "$t" -o "$tmp/x.png" --view 1,2,3
usage "$t" -o "$tmp/x.png" --shade phong
usage "$t" -o "$tmp/x.png" --light 45
usage "$t" -o "$tmp/x.png" --size 0,10
usage "$t" -o "$tmp/x.png" --size 10
usage "$t" -o "$tmp/x.png" --zoom 3
usage "$t" -o "$tmp/x.png" --filter blur
usage "$t" -o "$tmp/x.png" --cut 1,2,3
usage "$t" -o "$tmp/x.png" --cut 0,0,0,1
usage "$t" -o "$tmp/x.png" --keep below
usage "$t" -o "$tmp/x.png" --cut 1,0,0,-1 --keep sideways
usage "$t" -o "$tmp/x.png" --stereo cross
usage "$t" -o "$tmp/x.png" --turntable 0
usage "$t" -o "$tmp/x.png" --turntable many
usage "$t" -o "$tmp/x.png" --stereo sbs --depth "$tmp/d2.png"
usage "$t" -o "$tmp/x.png" --turntable 3 --depth "$tmp/d2.png"
usage "$t" -o "$tmp/x.png" --depth "$tmp/d2.tif"
usage "$t" -o "$tmp/x.png" --sheet --stereo anaglyph
usage "$t" -o "$tmp/x.png" --sheet --turntable 2
usage "$t" -o "$tmp/x.png" --bogus
usage "$t" stray -o "$tmp/x.png" # a word that is no file (several IN: render_annotate.sh)
[ ! -e "$tmp/x.png" ] && [ ! -e "$tmp/d2.png" ] || fail "a usage error wrote output"

# failures: exit 1, no output
failure() {
    set +e
    "$BVOX" render "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 1 ] || fail "render $* exited $rc, wanted 1"
    grep -q '^bvox: ' "$tmp/err" || fail "render $*: message: $(cat "$tmp/err")"
}
failure "$tmp/missing.nii" -o "$tmp/x.png"
failure "$t" -o "$tmp/no/such/x.png"
failure "$t" -o "$tmp/x.png" --depth "$tmp/no/such/d.png"
rm -f "$tmp/x.png"
failure "$t" -o "$tmp/no/such/spin.gif" --turntable 2
[ ! -e "$tmp/x.png" ] || fail "a failure wrote output"
[ -z "$(ls -A "$tmp" | grep '^\.')" ] || fail "temporary files left: $(ls -A "$tmp")"

"$BVOX" render --help | grep -q -- '--turntable N' || fail "render --help"
echo "ok"
