#!/bin/sh
# render_shading.sh — the shading modes of issue 18 through the real command:
# smooth normals on a voxelized sphere lit from the viewer (the centre row
# brightens towards the middle through many gray levels, where the paper's
# binary normals jump between a few), the paper's binary operator
# over the pre-image and its enlarged pre-image (twice the size), --ao,
# --shadows and --supersample (sizes), with turntables and stereo, and bad
# values (exit 2).
# Usage: sh render_shading.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

# shape FILE W H CHANNELS
shape() {
    png read "$1" >"$tmp/s.json" || fail "cannot read $1"
    python3 - "$tmp/s.json" "$2" "$3" "$4" <<'PY' || fail "$1 has the wrong shape"
import json, sys
g = json.load(open(sys.argv[1]))
want = tuple(int(a) for a in sys.argv[2:5])
got = (g["width"], g["height"], g["channels"])
assert got == want, (got, want)
PY
}

"$BVOX" shape sphere r=20 --dims 48,48,48 -o "$tmp/ball.nii" >/dev/null || fail "sphere"
b="$tmp/ball.nii"
for m in smooth binary; do
    "$BVOX" render "$b" -o "$tmp/$m.png" --shade "$m" --light 0,90 || fail "render $m"
    shape "$tmp/$m.png" 48 48 1
    png read "$tmp/$m.png" >"$tmp/$m.json"
done
python3 - "$tmp/smooth.json" "$tmp/binary.json" <<'PY' || fail "smooth sphere"
import json, sys
s = json.load(open(sys.argv[1]))["rows"][24]
b = json.load(open(sys.argv[2]))["rows"][24]
lit = [i for i, v in enumerate(s) if v > 0]
half, bhalf = s[lit[0]:24], b[lit[0]:24]
drop = lambda h: max(h[i] - h[i + 1] for i in range(len(h) - 1))
# from the rim to the middle the smooth shade rises through many levels and
# never falls far (the voxel terraces near the pole); the binary normals
# jump between a few levels
assert drop(half) < 30 and drop(bhalf) > 60, (half, bhalf)
assert len(set(half)) >= 12 and len(set(bhalf)) <= 4, (half, bhalf)
assert s == s[::-1], s                      # the sphere is symmetric
PY

# the paper's second normal method, and its Picture 2 order (x2)
"$BVOX" render "$b" -o "$tmp/bp.png" --shade binary-preimage || fail "binary-preimage"
shape "$tmp/bp.png" 48 48 1
"$BVOX" render "$b" -o "$tmp/eg.png" --shade enlarged-gradient || fail "enlarged-gradient"
shape "$tmp/eg.png" 96 96 1
"$BVOX" render "$b" -o "$tmp/eg2.png" --shade enlarged-gradient --view iso --size 40,30 --cut 1,0,0,-24 ||
    fail "enlarged-gradient, cut"
shape "$tmp/eg2.png" 80 60 3

# depth cues and antialiasing
"$BVOX" render "$b" -o "$tmp/cues.png" --shade smooth --ao --shadows --smooth-radius 3 || fail "cues"
shape "$tmp/cues.png" 48 48 1
"$BVOX" render "$b" -o "$tmp/ss.png" --shade smooth --supersample 3 --size 40,30 || fail "supersample"
shape "$tmp/ss.png" 40 30 1
png read "$tmp/ss.png" >"$tmp/ss.json"
python3 - "$tmp/ss.json" <<'PY' || fail "antialiased edge"
import json, sys
r = json.load(open(sys.argv[1]))["rows"]
# the rim mixes object and background: gray levels between the dark
# surround and the lit sphere appear along the middle row's edge
row = r[15]
first = next(i for i, v in enumerate(row) if v > 0)
assert 0 < row[first] < max(row), row
PY
"$BVOX" render "$b" -o "$tmp/st.png" --shade smooth --stereo sbs --size 32,32 --ao || fail "stereo"
shape "$tmp/st.png" 64 32 1
"$BVOX" render "$b" -o "$tmp/spin.gif" --shade smooth --shadows --size 32,32 --turntable 3 || fail "turntable"

usage() {
    set +e
    "$BVOX" render "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "render $* exited $rc, wanted 2"
    grep -q '^bvox: render: ' "$tmp/err" || fail "render $*: message: $(cat "$tmp/err")"
}
usage "$b" -o "$tmp/x.png" --shade smoothest
usage "$b" -o "$tmp/x.png" --supersample 5
usage "$b" -o "$tmp/x.png" --supersample 0
usage "$b" -o "$tmp/x.png" --smooth-radius 4
usage "$b" -o "$tmp/x.png" --ao yes
[ ! -e "$tmp/x.png" ] || fail "a usage error wrote output"
"$BVOX" render --help | grep -q -- '--supersample N' || fail "render --help"
echo "ok"
