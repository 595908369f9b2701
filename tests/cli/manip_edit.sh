#!/bin/sh
# manip_edit.sh — `bvox edit` through the real command: a sequence of
# actions (set, clear, fill-box, clear-box, keep-box with inclusive and open
# intervals, keep-above/below a plane in physical units) applied in order,
# the output compared voxel by voxel with the same edits done in Python, the
# changed region of every action (JSON) equal to the box of the voxels that
# really changed, the text report; bad command lines (exit 2) and failures
# (exit 1) writing nothing.
# Usage: sh manip_edit.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"


# 11 x 7 x 70 voxels of 0.5 x 1 x 2 mm, a pattern crossing the word boundary.
mk a 11 7 70 '(x * 7 + y * 13 + z * 3) % 5 < 2' --voxel-size 0.5,1,2 --unit mm

"$BVOX" edit "$tmp/a.nii" -o "$tmp/e.nii" --json \
    --set 1,2,3 --clear 0,0,0 --set 10,6,69 --fill-box 2:4,1:5,60:66 --clear-box 5:,:,:9 \
    --keep-box :9,1:,2: --set 1,2,3 --keep-above 1,0,0.5,-20 --keep-below 0,1,0,-5 \
    >"$tmp/e.json" || fail "edit exited $?"
"$BVOX" convert "$tmp/e.nii" "$tmp/e.raw" || fail "convert e.nii to raw"
python3 - "$tmp/a.raw" "$tmp/e.raw" "$tmp/e.json" <<'PY' || fail "edit differs from the Python edits"
import json, sys
nx, ny, nz = 11, 7, 70
sx, sy, sz = 0.5, 1.0, 2.0
a = bytearray(open(sys.argv[1], "rb").read())
got = open(sys.argv[2], "rb").read()
rep = json.loads(open(sys.argv[3]).read())
idx = lambda x, y, z: (z * ny + y) * nx + x
def box_of(before, after):
    pts = [(x, y, z) for z in range(nz) for y in range(ny) for x in range(nx)
           if before[idx(x, y, z)] != after[idx(x, y, z)]]
    if not pts:
        return None
    return {"min": [min(p[k] for p in pts) for k in range(3)],
            "max": [max(p[k] for p in pts) for k in range(3)]}
def inbox(x, y, z, b):
    return all(lo <= v <= hi for v, (lo, hi) in zip((x, y, z), b))
N = 10**9
steps = [
    ("set", lambda x, y, z, v: 1 if (x, y, z) == (1, 2, 3) else v),
    ("clear", lambda x, y, z, v: 0 if (x, y, z) == (0, 0, 0) else v),
    ("set", lambda x, y, z, v: 1 if (x, y, z) == (10, 6, 69) else v),
    ("fill-box", lambda x, y, z, v: 1 if inbox(x, y, z, [(2, 4), (1, 5), (60, 66)]) else v),
    ("clear-box", lambda x, y, z, v: 0 if inbox(x, y, z, [(5, N), (-N, N), (-N, 9)]) else v),
    ("keep-box", lambda x, y, z, v: v if inbox(x, y, z, [(-N, 9), (1, N), (2, N)]) else 0),
    ("set", lambda x, y, z, v: 1 if (x, y, z) == (1, 2, 3) else v),
    # x, y, z in mm: identity direction, zero origin (exact binary fractions)
    ("keep-above", lambda x, y, z, v: v if x * sx + 0.5 * z * sz - 20 >= 0 else 0),
    ("keep-below", lambda x, y, z, v: v if y * sy - 5 < 0 else 0),
]
assert len(rep["actions"]) == len(steps), rep["actions"]
count_before = sum(a)
for (name, f), act in zip(steps, rep["actions"]):
    b = bytearray(f(x, y, z, a[idx(x, y, z)]) for z in range(nz) for y in range(ny)
                  for x in range(nx))
    assert act["action"] == name, (act, name)
    want = box_of(a, b)
    assert act["changed"] == want, (name, act["changed"], want)
    a = b
assert rep["count_before"] == count_before, (rep["count_before"], count_before)
assert rep["count_after"] == sum(a), (rep["count_after"], sum(a))
assert bytes(a) == got, "voxels differ"
assert rep["changed"] is not None and rep["file"].endswith("e.nii")
print("edit: %d -> %d voxels, %d actions checked" % (count_before, sum(a), len(steps)))
PY
# The geometry survives.
"$BVOX" info "$tmp/e.nii" --json >"$tmp/j" || fail "info e.nii"
python3 -c 'import json,sys; o=json.load(open(sys.argv[1])); assert o["voxel_size"]==[0.5,1.0,2.0] and o["unit"]=="mm", o' "$tmp/j" ||
    fail "geometry lost"

# Text report: one line per action, then the union and the counts.
"$BVOX" edit "$tmp/a.nii" -o "$tmp/t.nii" --clear-box 0:10,0:6,0:69 --set 3,3,3 --set 3,3,3 \
    >"$tmp/t.txt" || fail "edit (text) exited $?"
grep -q '^--clear-box 0:10,0:6,0:69 -> changed x 0\.\.10, y 0\.\.6, z 0\.\.69$' "$tmp/t.txt" ||
    fail "clear-box line: $(cat "$tmp/t.txt")"
grep -q '^--set 3,3,3 -> changed x 3\.\.3, y 3\.\.3, z 3\.\.3$' "$tmp/t.txt" || fail "set line"
grep -q '^--set 3,3,3 -> no change$' "$tmp/t.txt" || fail "second set is not 'no change'"
grep -q '^changed: *x 0\.\.10, y 0\.\.6, z 0\.\.69 (voxel indices, inclusive)$' "$tmp/t.txt" ||
    fail "changed line"
grep -Eq '^count: *[0-9]+ -> 1 voxels$' "$tmp/t.txt" || fail "count line"
[ "$("$BVOX" info "$tmp/t.nii" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["count"])')" = 1 ] ||
    fail "t.nii does not hold one voxel"
# A box wholly outside changes nothing (and says so).
"$BVOX" edit "$tmp/a.nii" -o "$tmp/n.nii" --fill-box 20:30,:,: >"$tmp/n.txt" || fail "outside box"
grep -q '^--fill-box 20:30,:,: -> no change$' "$tmp/n.txt" || fail "outside box: $(cat "$tmp/n.txt")"
grep -q '^changed: *none$' "$tmp/n.txt" || fail "outside box: changed"

# Bad command lines: exit 2, one "bvox: " line, nothing written.
usage() {
    set +e
    "$BVOX" edit "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq 2 ] || fail "edit $*: exit $rc, expected 2 ($(cat "$tmp/err"))"
    [ ! -s "$tmp/out" ] || fail "edit $*: wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q '^bvox: edit: ' "$tmp/err" ||
        fail "edit $*: stderr: $(cat "$tmp/err")"
    [ ! -e "$tmp/bad.nii" ] || fail "edit $*: wrote an output"
}
usage "$tmp/a.nii" -o "$tmp/bad.nii"
usage "$tmp/a.nii" --set 1,2,3
usage -o "$tmp/bad.nii" --set 1,2,3
usage "$tmp/a.nii" -o "$tmp/bad.nii" --set 1,2
usage "$tmp/a.nii" -o "$tmp/bad.nii" --set 1,2,3.5
usage "$tmp/a.nii" -o "$tmp/bad.nii" --fill-box 1:2,3:4
usage "$tmp/a.nii" -o "$tmp/bad.nii" --fill-box 5:2,:,:
usage "$tmp/a.nii" -o "$tmp/bad.nii" --clear-box a:b,:,:
usage "$tmp/a.nii" -o "$tmp/bad.nii" --keep-above 0,0,0,1
usage "$tmp/a.nii" -o "$tmp/bad.nii" --keep-below 1,2,3
usage "$tmp/a.nii" -o "$tmp/bad.nii" --set
usage "$tmp/a.nii" -o "$tmp/bad.xyz" --set 1,1,1
usage "$tmp/a.nii" "$tmp/b.nii" -o "$tmp/bad.nii" --set 1,1,1
usage "$tmp/a.nii" -o "$tmp/bad.nii" --frobnicate
# Failures: exit 1, nothing written.
failure() {
    set +e
    "$BVOX" edit "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq 1 ] || fail "edit $*: exit $rc, expected 1"
    [ ! -s "$tmp/out" ] || fail "edit $*: wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q '^bvox: ' "$tmp/err" ||
        fail "edit $*: stderr: $(cat "$tmp/err")"
    [ ! -e "$tmp/bad.nii" ] || fail "edit $*: wrote an output"
}
failure "$tmp/a.nii" -o "$tmp/bad.nii" --set 11,0,0
grep -q 'outside the 11x7x70 volume' "$tmp/err" || fail "message: $(cat "$tmp/err")"
failure "$tmp/a.nii" -o "$tmp/bad.nii" --fill-box 1:2,:,: --clear -1,0,0
failure "$tmp/nope.nii" -o "$tmp/bad.nii" --set 1,1,1
echo "ok"
