#!/bin/sh
# demo.sh — `bvox demo` builds the sample specimen and reports it; the files
# it writes with -o (NIfTI and TIFF) read back with the same dimensions and
# count, and the paper's four pictures are there; the count agrees with the
# specimen's exact volume, computed here in closed form from its shapes (see
# src/ops/demo.c), within the discretisation error of 10 x 10 x 25 um voxels.
# The reconstruction from the simulated sections: its Dice and volume error,
# printed and in --json, are recomputed here from the written model and
# specimen (raw bytes), and must be good (Dice >= 0.97, |error| < 5 %); the
# section images are gray, with three markers each; -o follows the folder
# rules (its own earlier output replaced, a foreign folder refused, --force).
# Usage: sh demo.sh BVOX DATADIR
set -eu
BVOX=$1
here=$(cd "$(dirname "$0")" && pwd)
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
grep -q '^reconstruction: 65 sections of 352 x 352 pixels (10 um, 40 um apart, 3 markers, 0 not aligned by them)$' \
    "$tmp/demo.txt" || fail "reconstruction line: $(cat "$tmp/demo.txt")"
dice=$(sed -n 's/^dice: \([0-9.]*\)$/\1/p' "$tmp/demo.txt")
verr=$(sed -n 's/^volume error: \([-+0-9.]*\) %.*/\1/p' "$tmp/demo.txt")
[ -n "$dice" ] && [ -n "$verr" ] || fail "no dice or volume error in: $(cat "$tmp/demo.txt")"
grep -q "^wrote into $tmp/out/sub: " "$tmp/demo.err" || fail "demo -o does not say where: $(cat "$tmp/demo.err")"

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
r = obj["reconstruction"]
assert r["sections"] == 65, r
assert r["dice"] >= 0.97 and abs(r["volume_error_percent"]) < 5, r
PY

# Exactly the two files, the four pictures, the two smooth-shaded ones
# (pictures 1 and 3) and the three by the paper's pre-image methods
# (picture 1 by the binary operator over the pre-image, 2 and 3 by the
# gradient over the enlarged pre-image), no temporary ones; each
# volume reads back the same.
sections=$(i=0; while [ $i -lt 65 ]; do printf 'section_%04d.png ' $i; i=$((i + 1)); done)
[ "$(LC_ALL=C ls -A "$tmp/out/sub" | tr '\n' ' ')" = \
  ".bvox-manifest model.nii.gz picture1.png picture1_preimage.png picture1_smooth.png picture2.png picture2_enlarged.png picture3.png picture3_enlarged.png picture3_smooth.png picture4.png ${sections}specimen.nii.gz specimen.tif turntable.gif " ] ||
    fail "demo -o wrote: $(ls -A "$tmp/out/sub")"
# The paper's pictures and the smooth ones: 512 x 512, gray but for
# picture 3 (its cut face tinted); their content is compared with golden copies by the unit test
# render_pictures.
python3 - "$tmp/out/sub" <<'PY' || fail "the pictures"
import struct, sys
for k, color in ((1, 0), (2, 0), (3, 2), (4, 0), ("1_smooth", 0), ("3_smooth", 2),
                 ("1_preimage", 0), ("2_enlarged", 0), ("3_enlarged", 2)):
    head = open("%s/picture%s.png" % (sys.argv[1], k), "rb").read(33)
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
# The model on the specimen's grid; Dice and volume error recomputed from
# the raw bytes of the two volumes (not from bvox's own counts).
"$BVOX" convert "$tmp/out/sub/model.nii.gz" "$tmp/model.raw" >/dev/null || fail "model to raw"
"$BVOX" convert "$tmp/out/sub/specimen.nii.gz" "$tmp/specimen.raw" >/dev/null || fail "specimen to raw"
python3 - "$tmp/model.raw" "$tmp/specimen.raw" "$dice" "$verr" "$tmp/demo.json" <<'PY' || fail "the reconstruction's numbers"
import json, sys
m, s = (open(p, "rb").read() for p in sys.argv[1:3])
assert len(m) == len(s) == 256 * 256 * 128, (len(m), len(s))
a = sum(1 for v in s if v)
b = sum(1 for v in m if v)
both = sum(1 for x, y in zip(m, s) if x and y)
dice = 2 * both / (a + b)
printed = float(sys.argv[3])
assert abs(dice - printed) < 6e-5, (dice, printed)
assert dice >= 0.97, dice
obj = json.loads(open(sys.argv[5]).read())
assert abs(obj["reconstruction"]["dice"] - dice) < 1e-9, (obj["reconstruction"], dice)
# the volume error counts the whole reconstruction; on the grid nothing is lost
err = 100.0 * (b - a) / a
assert abs(err - float(sys.argv[4])) < 0.006, (err, sys.argv[4])
assert abs(err) < 5, err
print("demo: dice %.4f, volume error %+.2f %%" % (dice, err))
PY

# Section images: gray, 352 x 352, three dark round markers, the object
# (read by the tests' own PNG reader); the turntable: a looping GIF of 36 frames.
python3 - "$tmp/out/sub" "$here" <<'PY' || fail "the section images or the turntable"
import sys
sys.path.insert(0, sys.argv[2])
import pngtool
for k in (1, 32, 64):
    img = pngtool.read_png("%s/section_%04d.png" % (sys.argv[1], k))
    assert (img["width"], img["height"], img["channels"], img["bits"]) == (352, 352, 1, 8), img["width"]
    rows = img["rows"]
    dark = [(x, y) for y in range(352) for x in range(352) if rows[y][x] < 50]
    # marker pixels only (radius 5: ~80 each), in three separate places
    cells = {(x // 40, y // 40) for x, y in dark}
    assert 3 <= len(cells) <= 6 and 150 < len(dark) < 400, (k, len(cells), len(dark))
    tissue = sum(1 for row in rows for v in row if 50 <= v < 110)
    assert tissue > (5 if k in (1, 64) else 5000), (k, tissue)
gif = pngtool.read_gif("%s/turntable.gif" % sys.argv[1])
assert gif["frames"] == 36 and (gif["width"], gif["height"]) == (256, 256), gif
PY

# -o again into its own output: replaced; into a folder with other files:
# refused (exit 1, nothing written), unless --force.
"$BVOX" demo -o "$tmp/out/sub" >/dev/null 2>&1 || fail "demo -o over its own output"
mkdir "$tmp/mine"
echo keep >"$tmp/mine/notes.txt"
set +e
"$BVOX" demo -o "$tmp/mine" >"$tmp/refused.out" 2>&1
rc=$?
set -e
[ $rc -eq 1 ] || fail "demo -o into a foreign folder must exit 1 (got $rc)"
[ "$(ls -A "$tmp/mine")" = "notes.txt" ] || fail "a refused demo wrote: $(ls -A "$tmp/mine")"
grep -q "^bvox: " "$tmp/refused.out" || fail "no clear refusal: $(cat "$tmp/refused.out")"
"$BVOX" demo -o "$tmp/mine" --force >/dev/null 2>&1 || fail "demo -o --force"
[ -f "$tmp/mine/model.nii.gz" ] && [ "$(cat "$tmp/mine/notes.txt")" = keep ] || fail "--force"
echo "ok"
