#!/bin/sh
# manip_cut.sh — `bvox cut` through the real command: planes in physical
# units on anisotropic voxels, planes exactly through voxel centres (a centre
# on the plane is "above"), c = 0 planes, keep above and below splitting the
# object exactly, the output compared voxel by voxel with Python and the
# reported changed region equal to the box of the voxels that changed; text
# and JSON reports; bad command lines (exit 2) and failures (exit 1).
# Usage: sh manip_cut.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# 13 x 9 x 130 voxels of 0.5 x 0.25 x 2 mm, two thirds full.
python3 - "$tmp/a.raw" <<'PY'
import sys
nx, ny, nz = 13, 9, 130
open(sys.argv[1], "wb").write(bytes(1 if (x * 5 + y * 11 + z * 7) % 3 else 0
                                    for z in range(nz) for y in range(ny) for x in range(nx)))
PY
"$BVOX" convert "$tmp/a.raw" "$tmp/a.nii" --dims 13,9,130 --type u8 --voxel-size 0.5,0.25,2 \
    --unit mm || fail "making a.nii"

# cut PLANE KEEP: run with --json, compare with Python (exact arithmetic:
# binary fractions only), print the count kept.
cut() {
    "$BVOX" cut "$tmp/a.nii" --plane "$1" --keep "$2" -o "$tmp/c.nii" --json >"$tmp/c.json" ||
        fail "cut --plane $1 --keep $2 exited $?"
    "$BVOX" convert "$tmp/c.nii" "$tmp/c.raw" || fail "convert c.nii"
    python3 - "$tmp/a.raw" "$tmp/c.raw" "$tmp/c.json" "$1" "$2" <<'PY' || fail "cut --plane $1 --keep $2"
import json, sys
nx, ny, nz = 13, 9, 130
s = (0.5, 0.25, 2.0)
a = open(sys.argv[1], "rb").read()
got = open(sys.argv[2], "rb").read()
rep = json.loads(open(sys.argv[3]).read())
A, B, C, D = map(float, sys.argv[4].split(","))
above = sys.argv[5] == "above"
want = bytearray(len(a))
pts = []
for z in range(nz):
    for y in range(ny):
        for x in range(nx):
            i = (z * ny + y) * nx + x
            f = A * x * s[0] + B * y * s[1] + C * z * s[2] + D
            keep = (f >= 0) == above
            want[i] = a[i] if keep else 0
            if want[i] != a[i]:
                pts.append((x, y, z))
assert bytes(want) == got, "voxels differ"
box = None if not pts else {"min": [min(p[k] for p in pts) for k in range(3)],
                            "max": [max(p[k] for p in pts) for k in range(3)]}
assert rep["changed"] == box, (rep["changed"], box)
assert rep["count_before"] == sum(a) and rep["count_after"] == sum(want), rep
assert rep["keep"] == sys.argv[5] and rep["plane"] == [A, B, C, D], rep
print(sum(want))
PY
}
total=$(python3 -c 'import sys; print(sum(open(sys.argv[1],"rb").read()))' "$tmp/a.raw")
# z = 100 mm is slice 50 exactly: on the plane counts as above.
up=$(cut 0,0,1,-100 above) && down=$(cut 0,0,1,-100 below) || exit 1
[ $((up + down)) -eq "$total" ] || fail "above $up + below $down != $total"
# Oblique, through voxel centres (x=2 mm, y=1 mm, z=60 mm: voxel (4, 4, 30)).
up=$(cut 1,-2,0.25,-15 above) && down=$(cut 1,-2,0.25,-15 below) || exit 1
[ $((up + down)) -eq "$total" ] || fail "oblique: above $up + below $down != $total"
# c = 0: whole columns; a negative normal; a plane missing the volume.
cut 2,1,0,-3.5 above >/dev/null
cut -1,0,-0.5,40 above >/dev/null
[ "$(cut 0,0,1,100 above)" -eq "$total" ] || fail "plane below the volume removed voxels"
[ "$(cut 0,0,1,100 below)" -eq 0 ] || fail "keep below a plane under the volume kept voxels"
python3 -c 'import json,sys; o=json.load(open(sys.argv[1])); assert o["changed"]=={"min":[0,0,0],"max":[12,8,129]}, o' \
    "$tmp/c.json" || fail "whole volume changed box"
cut 0,0,1,100 above >/dev/null
python3 -c 'import json,sys; o=json.load(open(sys.argv[1])); assert o["changed"] is None, o' \
    "$tmp/c.json" || fail "no change must report null"

# Text report; --keep defaults to above.
"$BVOX" cut "$tmp/a.nii" --plane 0,0,1,-100 -o "$tmp/t.nii" >"$tmp/t.txt" || fail "cut (text)"
grep -q '^plane: *z - 100 = 0$' "$tmp/t.txt" || fail "plane line: $(cat "$tmp/t.txt")"
grep -q '^kept: *above (z - 100 >= 0)$' "$tmp/t.txt" || fail "kept line"
grep -q '^changed: *x 0\.\.12, y 0\.\.8, z 0\.\.49 (voxel indices, inclusive)$' "$tmp/t.txt" ||
    fail "changed line"
grep -Eq "^count: *$total -> [0-9]+ voxels$" "$tmp/t.txt" || fail "count line"
"$BVOX" info "$tmp/t.nii" --json >"$tmp/j"
python3 -c 'import json,sys; o=json.load(open(sys.argv[1])); assert o["bbox"]["min"][2]==50 and o["voxel_size"]==[0.5,0.25,2.0], o' \
    "$tmp/j" || fail "t.nii: $(cat "$tmp/j")"

# Bad command lines (exit 2) and failures (exit 1): nothing written.
expect() {
    want=$1
    shift
    set +e
    "$BVOX" cut "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "cut $*: exit $rc, expected $want ($(cat "$tmp/err"))"
    [ ! -s "$tmp/out" ] || fail "cut $*: wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q '^bvox: ' "$tmp/err" ||
        fail "cut $*: stderr: $(cat "$tmp/err")"
    [ ! -e "$tmp/bad.nii" ] || fail "cut $*: wrote an output"
}
expect 2 "$tmp/a.nii" -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1,1
expect 2 --plane 0,0,1,1 -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1 -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1,x -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1,inf -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,0,1 -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1,1 --keep left -o "$tmp/bad.nii"
expect 2 "$tmp/a.nii" --plane 0,0,1,1 -o "$tmp/bad.unknown"
expect 1 "$tmp/nope.nii" --plane 0,0,1,1 -o "$tmp/bad.nii"
expect 1 "$tmp/a.nii" --plane 0,0,1e300,1 --voxel-size 1e10,1e10,1e10 -o "$tmp/bad.nii"
grep -q 'too large' "$tmp/err" || fail "huge plane: $(cat "$tmp/err")"
echo "ok"
