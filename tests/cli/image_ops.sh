#!/bin/sh
# image_ops.sh — `bvox image` on PNGs written and read back here by an
# independent PNG coder (pngtool.py: zlib + struct): the paper's Figure 5
# exactly through `bvox image average` (13 5 / 0 8 -> 13 9 5 3 / 7 7 7 3 /
# 0 4 8 4 / 0 2 4 2), zoom by replication, filters (presets and a kernel,
# with saturation), pan, colour map; bad command lines (exit 2) and failures
# (exit 1, no output file).
# Usage: sh image_ops.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(dirname "$0")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
png() { python3 "$here/pngtool.py" "$@"; }

# expect FILE W H CHANNELS ROWS-AS-PYTHON-LIST
expect() {
    png read "$1" >"$tmp/got.json" || fail "cannot read $1"
    python3 - "$tmp/got.json" "$2" "$3" "$4" "$5" <<'PY' || fail "$1 is not as expected"
import json, sys
got = json.load(open(sys.argv[1]))
w, h, ch = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
want = eval(sys.argv[5])
assert (got["width"], got["height"], got["channels"], got["bits"]) == (w, h, ch, 8), got
assert got["rows"] == want, "\n got %s\nwant %s" % (got["rows"], want)
PY
}

# Figure 5
png write "$tmp/fig5.png" 2 2 13,5,0,8
"$BVOX" image average "$tmp/fig5.png" "$tmp/avg.png" || fail "image average exited $?"
expect "$tmp/avg.png" 4 4 1 '[[13,9,5,3],[7,7,7,3],[0,4,8,4],[0,2,4,2]]'

# replication
"$BVOX" image zoom "$tmp/fig5.png" "$tmp/z2.png" || fail "image zoom exited $?"
expect "$tmp/z2.png" 4 4 1 '[[13,13,5,5],[13,13,5,5],[0,0,8,8],[0,0,8,8]]'
"$BVOX" image zoom "$tmp/fig5.png" "$tmp/z4.png" --factor 4 || fail "zoom --factor 4"
expect "$tmp/z4.png" 8 8 1 '[[13]*4+[5]*4]*4+[[0]*4+[8]*4]*4'

# 3x3 filters on a 3x3 image, the edge pixels repeated beyond the border:
# the Laplacian of a single bright centre, high pass saturating at 255
png write "$tmp/dot.png" 3 3 0,0,0,0,50,0,0,0,0
"$BVOX" image filter "$tmp/dot.png" "$tmp/lap.png" --filter laplace || fail "filter laplace"
expect "$tmp/lap.png" 3 3 1 '[[0,0,0],[0,200,0],[0,0,0]]'
"$BVOX" image filter "$tmp/dot.png" "$tmp/hp.png" --filter highpass || fail "filter highpass"
expect "$tmp/hp.png" 3 3 1 '[[0,0,0],[0,255,0],[0,0,0]]'
# a kernel: shift right by one (out(x) = in(x - 1)), with bias and divisor
"$BVOX" image filter "$tmp/dot.png" "$tmp/k.png" --kernel 0,0,0,2,0,0,0,0,0 --divisor 4 --bias 3 ||
    fail "filter --kernel"
expect "$tmp/k.png" 3 3 1 '[[3,3,3],[3,3,28],[3,3,3]]'

# pan
"$BVOX" image pan "$tmp/fig5.png" "$tmp/pan.png" --offset 1,-1 || fail "image pan"
expect "$tmp/pan.png" 2 2 1 '[[0,0],[0,0]]'
"$BVOX" image pan "$tmp/fig5.png" "$tmp/pan.png" --offset 0,1 || fail "image pan"
expect "$tmp/pan.png" 2 2 1 '[[0,0],[13,5]]'

# colour map: gray stays gray, as RGB
"$BVOX" image colormap "$tmp/fig5.png" "$tmp/gray.png" --map gray || fail "colormap"
expect "$tmp/gray.png" 2 2 3 '[[13,13,13,5,5,5],[0,0,0,8,8,8]]'

# bad command lines: exit 2
usage() {
    set +e
    "$BVOX" image "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 2 ] || fail "image $* exited $rc, wanted 2"
    grep -q '^bvox: image: ' "$tmp/err" || fail "image $*: message: $(cat "$tmp/err")"
}
usage
usage average "$tmp/fig5.png"
usage blur "$tmp/fig5.png" "$tmp/x.png"
usage zoom "$tmp/fig5.png" "$tmp/x.png" --factor 3
usage filter "$tmp/fig5.png" "$tmp/x.png"
usage filter "$tmp/fig5.png" "$tmp/x.png" --filter blur
usage filter "$tmp/fig5.png" "$tmp/x.png" --filter smooth --kernel 1,1,1,1,1,1,1,1,1
usage filter "$tmp/fig5.png" "$tmp/x.png" --kernel 1,2,3
usage filter "$tmp/fig5.png" "$tmp/x.png" --kernel 1,1,1,1,1,1,1,1,1 --divisor 0
usage pan "$tmp/fig5.png" "$tmp/x.png" --offset 1
usage colormap "$tmp/fig5.png" "$tmp/x.png"
usage average "$tmp/fig5.png" "$tmp/x.png" --bogus
usage average "$tmp/fig5.png" "$tmp/x.png" extra
[ ! -e "$tmp/x.png" ] || fail "a usage error wrote output"

# failures: exit 1 with the library's message, no output
failure() {
    set +e
    "$BVOX" image "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ $rc -eq 1 ] || fail "image $* exited $rc, wanted 1"
    grep -q '^bvox: ' "$tmp/err" || fail "image $*: message: $(cat "$tmp/err")"
}
failure average "$tmp/missing.png" "$tmp/x.png"
printf 'not a png at all' >"$tmp/bad.png"
failure average "$tmp/bad.png" "$tmp/x.png"
head -c 40 "$tmp/fig5.png" >"$tmp/trunc.png"
failure zoom "$tmp/trunc.png" "$tmp/x.png"
failure average "$tmp/fig5.png" "$tmp/no/such/dir/x.png"
[ ! -e "$tmp/x.png" ] || fail "a failure wrote output"

"$BVOX" image --help | grep -q 'Figure 5' || fail "image --help"
echo "ok"
