#!/bin/sh
# manip_csg.sh — `bvox csg` through the real command: files of different
# sizes placed at voxel offsets that cross word boundaries and at physical
# offsets, every operator and the precedence, compared voxel by voxel with
# Python; the set identities on counts; primitives in physical units (a
# sphere of r = 10 mm on 0.5 mm voxels); the output grid taken from the
# first file or from --dims; quoted names; --check; errors with their
# column (exit 1), bad command lines (exit 2), nothing written on failure.
# Usage: sh manip_csg.sh BVOX DATADIR
set -eu
BVOX=$1
case $BVOX in /*) ;; *) BVOX=$PWD/$BVOX ;; esac # commands run in $tmp
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# mk NAME NX NY NZ PYEXPR: NAME.nii (0.5 mm voxels) whose voxel is PYEXPR.
mk() {
    name=$1 nx=$2 ny=$3 nz=$4 expr=$5
    python3 - "$tmp/$name.raw" "$nx" "$ny" "$nz" "$expr" <<'PY'
import sys
out, nx, ny, nz, expr = sys.argv[1], *map(int, sys.argv[2:5]), sys.argv[5]
f = eval("lambda x, y, z: " + expr)
open(out, "wb").write(bytes(1 if f(x, y, z) else 0
                            for z in range(nz) for y in range(ny) for x in range(nx)))
PY
    "$BVOX" convert "$tmp/$name.raw" "$tmp/$name.nii" --dims "$nx,$ny,$nz" --type u8 \
        --voxel-size 0.5,0.5,0.5 --unit mm || fail "making $name.nii"
}
mk a 9 7 130 '(x * 3 + y * 5 + z) % 4 < 2'
mk b 5 11 65 '(x + y * 2 + z * 3) % 3 == 0'
mk c 7 3 63 '(x * y + z) % 2 == 0'
cp "$tmp/c.nii" "$tmp/my-file c.nii"

# check EXPR PYEXPR: `csg EXPR` (run in $tmp) equals PYEXPR over the arrays
# A, B, C with place(V, dx, dy, dz) on A's grid.
check() {
    (cd "$tmp" && "$BVOX" csg "$1" -o out.nii --json >out.json) || fail "csg '$1' exited $?"
    "$BVOX" convert "$tmp/out.nii" "$tmp/out.raw" || fail "convert out.nii"
    python3 - "$tmp" "$2" <<'PY' || fail "csg '$1' differs from $2"
import json, sys
d, expr = sys.argv[1:]
dims = {"a": (9, 7, 130), "b": (5, 11, 65), "c": (7, 3, 63)}
def load(name):
    nx, ny, nz = dims[name]
    raw = open("%s/%s.raw" % (d, name), "rb").read()
    return {(x, y, z): raw[(z * ny + y) * nx + x]
            for z in range(nz) for y in range(ny) for x in range(nx)}
G = dims["a"]
grid = [(x, y, z) for z in range(G[2]) for y in range(G[1]) for x in range(G[0])]
def place(v, dx=0, dy=0, dz=0):
    return {p: v.get((p[0] - dx, p[1] - dy, p[2] - dz), 0) for p in grid}
A, B, C = place(load("a")), load("b"), load("c")
U = lambda p, q: {k: p[k] | q[k] for k in grid}
I = lambda p, q: {k: p[k] & q[k] for k in grid}
D = lambda p, q: {k: p[k] & (1 - q[k]) for k in grid}
X = lambda p, q: {k: p[k] ^ q[k] for k in grid}
N = lambda p: {k: 1 - p[k] for k in grid}
want = eval(expr)
got = open(d + "/out.raw", "rb").read()
assert bytes(want[p] for p in grid) == got, "voxels differ"
o = json.loads(open(d + "/out.json").read())
assert o["count"] == sum(want.values()) and o["dims"] == list(G), o
assert o["voxel_size"] == [0.5, 0.5, 0.5] and o["unit"] == "mm", o
PY
}
check "a.nii + b.nii" "U(A, place(B))"
check "a.nii * b.nii@3,-2,70" "I(A, place(B, 3, -2, 70))"
check "a.nii - b.nii@-1,4,-63" "D(A, place(B, -1, 4, -63))"
check "a.nii ^ c.nii@2,2,64" "X(A, place(C, 2, 2, 64))"
check "~a.nii" "N(A)"
check "~(a.nii+b.nii@1,1,1)" "N(U(A, place(B, 1, 1, 1)))"
# precedence: * before + - ^, left to right
check "a.nii + b.nii * c.nii@0,0,60" "U(A, I(place(B), place(C, 0, 0, 60)))"
check "a.nii - b.nii + c.nii" "U(D(A, place(B)), place(C))"
check "a.nii - (b.nii + c.nii)" "D(A, U(place(B), place(C)))"
check "a.nii ^ b.nii - c.nii@1,0,1" "D(X(A, place(B)), place(C, 1, 0, 1))"
# physical offsets: (1, -0.5, 32) mm on 0.5 mm voxels = (2, -1, 64)
check "a.nii + b.nii@(1,-0.5,32)" "U(A, place(B, 2, -1, 64))"
# a name with a space (quoted) and one with a '-' (not an operator inside a name)
check "a.nii * 'my-file c.nii'@0,1,65" "I(A, place(C, 0, 1, 65))"
cp "$tmp/c.nii" "$tmp/my-c.nii"
check "a.nii - my-c.nii" "D(A, place(C))"

# Identities on counts: |A+B| = |A| + |B| - |A*B|, A-B = A*~B, xor.
n() { (cd "$tmp" && "$BVOX" csg "$1" -o n.nii --json) | python3 -c 'import json,sys; print(json.load(sys.stdin)["count"])'; }
u=$(n "a.nii + b.nii@2,3,65") i=$(n "a.nii * b.nii@2,3,65") na=$(n "a.nii")
nb=$(n "a.nii - a.nii + b.nii@2,3,65")
[ "$u" -eq $((na + nb - i)) ] || fail "|A+B| $u != $na + $nb - $i"
[ "$(n "a.nii - b.nii@2,3,65")" -eq "$(n "a.nii * ~b.nii@2,3,65")" ] || fail "A-B != A*~B"
[ "$(n "a.nii ^ b.nii@2,3,65")" -eq $((u - i)) ] || fail "xor"

# Primitives in physical units: r = 10 mm on 0.5 mm voxels ~ 4/3 pi 20^3.
"$BVOX" csg "sphere(r=10)" --dims 48,48,48 --voxel-size 0.5,0.5,0.5 --unit mm -o "$tmp/s.nii" \
    --json >"$tmp/s.json" || fail "sphere exited $?"
python3 - "$tmp/s.json" <<'PY' || fail "sphere: $(cat "$tmp/s.json")"
import json, math, sys
o = json.loads(open(sys.argv[1]).read())
want = 4 / 3 * math.pi * 20 ** 3
assert abs(o["count"] - want) < 0.01 * want, (o["count"], want)
assert abs(o["volume"] - 4 / 3 * math.pi * 1000) < 0.01 * 4188.8, o["volume"]
assert o["dims"] == [48, 48, 48] and o["unit"] == "mm", o
# centred: bbox symmetric about 23.5
assert o["bbox"]["min"][0] + o["bbox"]["max"][0] == 47, o["bbox"]
PY
# with --origin: 'at' is relative to the same frame as the origin
"$BVOX" csg "box(min=10,10,10, max=12,11,10.5)" --dims 8,8,8 --origin 9,9,9 -o "$tmp/o.nii" \
    --json >"$tmp/o.json" || fail "box with --origin"
python3 -c 'import json,sys; o=json.load(open(sys.argv[1])); assert o["count"]==3*2*1 and o["bbox"]=={"min":[1,1,1],"max":[3,2,1]}, o' \
    "$tmp/o.json" || fail "box with --origin: $(cat "$tmp/o.json")"
# a file and primitives: the sphere removed from a full block
mk full 20 20 20 'True'
(cd "$tmp" && "$BVOX" csg "full.nii - sphere(r=2, at=5,5,5) - halfspace(n=0,0,1, d=-8)" \
    -o h.nii --json >h.json) || fail "file minus shapes"
python3 - "$tmp/h.json" <<'PY' || fail "file minus shapes: $(cat "$tmp/h.json")"
import json, sys
o = json.loads(open(sys.argv[1]).read())
# halfspace z*0.5 - 8 >= 0 removes z >= 16 (4 layers); the ball of radius 4
# voxels around voxel (10,10,10): count its centres
ball = sum(1 for x in range(20) for y in range(20) for z in range(16)
           if (x - 10) ** 2 + (y - 10) ** 2 + (z - 10) ** 2 <= 16)
assert o["count"] == 20 * 20 * 16 - ball, (o["count"], 20 * 20 * 16 - ball)
PY
# Text output is the info report.
(cd "$tmp" && "$BVOX" csg "a.nii * b.nii" -o t.nii >t.txt) || fail "csg text"
grep -q '^dimensions: *9 x 7 x 130 voxels$' "$tmp/t.txt" || fail "text: $(cat "$tmp/t.txt")"
grep -q '^file: .*t.nii$' "$tmp/t.txt" || fail "text file line"

# --check reads nothing (the files need not exist).
"$BVOX" csg "(x.nii + y.nii@1,2,3) * ~sphere(r=1)" --check >"$tmp/k" || fail "--check exited $?"
[ "$(cat "$tmp/k")" = ok ] || fail "--check printed $(cat "$tmp/k")"

# Errors: exit 1 (bad expression, missing file) or 2 (command line), one
# "bvox: " line, nothing written.
expect() {
    want=$1 msg=$2
    shift 2
    set +e
    (cd "$tmp" && "$BVOX" csg "$@") >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "csg $*: exit $rc, expected $want ($(cat "$tmp/err"))"
    [ ! -s "$tmp/out" ] || fail "csg $*: wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "csg $*: stderr: $(cat "$tmp/err")"
    grep -q '^bvox: ' "$tmp/err" && grep -qF -- "$msg" "$tmp/err" ||
        fail "csg $*: stderr '$(cat "$tmp/err")' lacks '$msg'"
    [ ! -e "$tmp/bad.nii" ] || fail "csg $*: wrote an output"
}
expect 1 "csg: expected ')' at column 15" "(a.nii + b.nii" -o bad.nii
expect 1 "csg: unmatched ')' at column 14" "a.nii + b.nii)" -o bad.nii
expect 1 "csg: unknown primitive 'sphre' at column 9" "a.nii - sphre(r=2)" -o bad.nii
expect 1 "csg: sphere: missing parameter 'r' at column 9" "a.nii - sphere(at=1,2,3)" -o bad.nii
expect 1 "csg: expected a number at column 18" "a.nii - sphere(r=two)" -o bad.nii
expect 1 "csg: expected an operator at column 7" "a.nii b.nii" -o bad.nii
expect 1 "csg: empty expression" "" -o bad.nii
expect 1 "csg: column 9: " "a.nii + nope.nii" -o bad.nii
mk big 4 4 4 'True'
"$BVOX" convert "$tmp/big.nii" "$tmp/big1.nii" --voxel-size 1,1,1 || fail "big1"
expect 1 "has voxels of 1 x 1 x 1, the output grid 0.5 x 0.5 x 0.5" "a.nii + big1.nii" -o bad.nii
expect 2 "csg: EXPR has no file: give the grid with --dims" "sphere(r=1)" -o bad.nii
expect 2 "csg: missing -o OUT" "a.nii"
expect 2 "csg: missing the expression" -o bad.nii
expect 2 "csg: unexpected argument" a.nii b.nii -o bad.nii
expect 2 "csg: " "a.nii" -o bad.unknown
expect 2 "csg: --origin" "sphere(r=1)" --dims 4,4,4 --origin 1,2 -o bad.nii
deep=$(python3 -c 'print("(" * 300 + "a.nii" + ")" * 300)')
expect 1 "csg: nesting deeper than 256 at column 257" "$deep" -o bad.nii
echo "ok"
