#!/bin/sh
# demo.sh — `bvox demo` builds the sample specimen and reports it; the files
# it writes with -o (NIfTI and TIFF) read back with the same dimensions and
# count, and the paper's four pictures are there; the count agrees with the
# specimen's exact volume, computed here in closed form from its shapes (see
# src/demo.c), within the discretisation error of 10 x 10 x 25 um voxels.
# Usage: sh demo.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

"$BVOX" demo >"$tmp/plain.txt" || fail "demo exited $?"
"$BVOX" demo -o "$tmp/out/sub" >"$tmp/demo.txt" 2>"$tmp/demo.err" || fail "demo -o exited $?"
cmp -s "$tmp/plain.txt" "$tmp/demo.txt" || fail "demo -o printed other info than demo"
grep -q '^dimensions: *256 x 256 x 128 voxels$' "$tmp/demo.txt" || fail "dimensions: $(cat "$tmp/demo.txt")"
grep -q '^voxel size: *10 x 10 x 25 um$' "$tmp/demo.txt" || fail "voxel size"
count=$(sed -n 's/^count: *\([0-9][0-9]*\) voxels.*/\1/p' "$tmp/demo.txt")
[ -n "$count" ] || fail "no count in: $(cat "$tmp/demo.txt")"
grep -q '^volume: .* um^3 (.* mm^3)$' "$tmp/demo.txt" || fail "volume line"

# The count against the closed form (spheroid with a bored hole + torus +
# cone, all disjoint): relative error under 1.5 %.
python3 - "$count" <<'PY' || fail "count $count is not the specimen's volume"
import math, sys
count = int(sys.argv[1])
R, c, r = 800.0, 1100.0, 200.0                   # spheroid and hole, um
body = 4 / 3 * math.pi * (R * R - r * r) ** 1.5 * c / R
ring = 2 * math.pi ** 2 * 1050.0 * 120.0 ** 2    # torus
cap = math.pi * 300.0 ** 2 * 350.0 / 3           # cone
exact = body + ring + cap
got = count * 10.0 * 10.0 * 25.0
err = abs(got - exact) / exact
print("demo: count %d, %.6g um^3 vs exact %.6g um^3 (%.3f %%)" % (count, got, exact, 100 * err))
assert err < 0.015, err
PY

# --json says the same.
"$BVOX" demo --json >"$tmp/demo.json" || fail "demo --json exited $?"
python3 - "$tmp/demo.json" "$count" <<'PY' || fail "demo --json"
import json, math, sys
obj = json.loads(open(sys.argv[1]).read())
count = int(sys.argv[2])
assert obj["dims"] == [256, 256, 128], obj["dims"]
assert obj["voxel_size"] == [10, 10, 25] and obj["unit"] == "um", obj
assert obj["count"] == count, (obj["count"], count)
assert math.isclose(obj["volume"], count * 2500.0), obj["volume"]
assert math.isclose(obj["volume_mm3"], count * 2500.0 * 1e-9), obj["volume_mm3"]
b = obj["bbox"]
# Symmetric in x and y about the centre (voxel 127.5): the torus is widest.
assert b["min"][0] + b["max"][0] == 255 and b["min"][1] + b["max"][1] == 255, b
PY

# Exactly the two files and the four pictures, no temporary ones; each
# volume reads back the same.
[ "$(ls -A "$tmp/out/sub" | tr '\n' ' ')" = \
  "picture1.png picture2.png picture3.png picture4.png specimen.nii.gz specimen.tif " ] ||
    fail "demo -o wrote: $(ls -A "$tmp/out/sub")"
# The paper's pictures: 512 x 512, gray but for picture 3 (its cut face
# tinted); their content is compared with golden copies by the unit test
# render_pictures.
python3 - "$tmp/out/sub" <<'PY' || fail "the pictures"
import struct, sys
for k, color in ((1, 0), (2, 0), (3, 2), (4, 0)):
    head = open("%s/picture%d.png" % (sys.argv[1], k), "rb").read(33)
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR", k
    w, h, depth, ctype = struct.unpack(">IIBB", head[16:26])
    assert (w, h, depth, ctype) == (512, 512, 8, color), (k, w, h, depth, ctype)
PY
for f in specimen.nii.gz specimen.tif; do
    "$BVOX" info "$tmp/out/sub/$f" --json >"$tmp/$f.json" || fail "info $f exited $?"
    python3 - "$tmp/$f.json" "$count" "$f" <<'PY' || fail "$f does not read back"
import json, math, sys
obj = json.loads(open(sys.argv[1]).read())
count, name = int(sys.argv[2]), sys.argv[3]
assert obj["dims"] == [256, 256, 128], obj["dims"]
assert obj["count"] == count, (obj["count"], count)
assert all(math.isclose(a, b, rel_tol=1e-5) for a, b in zip(obj["voxel_size"], [10, 10, 25])), obj
PY
done
echo "ok"
