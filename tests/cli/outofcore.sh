#!/bin/sh
# outofcore.sh — a .zarr larger than --max-memory is streamed in slabs by
# info, measure, components, morph, csg and mesh, with the same answers as in memory
# (the JSON outputs are identical; the morphology's .zarr holds the same
# voxels as the in-memory result), odd chunks (37 x 100 x 65) and objects
# crossing chunk borders and corners. What needs the whole volume (--csv,
# --labels, fill, a non-.zarr output) is refused with a one-line error.
# Usage: sh outofcore.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
D=81,101,1000
M=5M  # the volume's words (1 MiB) times the copies of the in-memory path exceed it

# a hollow ball (a cavity) around the chunk corner (37, 100, 65), a torus (a
# tunnel) across the z chunk border at 130, a thin bar along z through all
"$BVOX" shape sphere r=25 at=37,70,65 --dims $D -o "$tmp/s.nii" >/dev/null
"$BVOX" shape sphere r=12 at=37,70,65 --dims $D -o "$tmp/i.nii" >/dev/null
"$BVOX" shape torus R=20 r=6 at=40,40,130 axis=1,0,0 --dims $D -o "$tmp/t.nii" >/dev/null
"$BVOX" shape box min=70,5,3 max=72,7,996 --dims $D -o "$tmp/b.nii" >/dev/null
"$BVOX" csg "$tmp/s.nii - $tmp/i.nii + $tmp/t.nii + $tmp/b.nii" -o "$tmp/all.nii" >/dev/null
"$BVOX" convert "$tmp/all.nii" "$tmp/a.zarr" --chunks 37,100,65 --voxel-size 0.5,0.5,1.5 \
    --unit um

for args in "info --json" "measure --json" "components --json --conn 26" \
            "components --json --conn 6" "components --conn 18"; do
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" > "$tmp/mem.out" || fail "$args in memory"
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" --max-memory $M > "$tmp/ooc.out" || fail "$args by slabs"
    cmp -s "$tmp/mem.out" "$tmp/ooc.out" || { diff "$tmp/mem.out" "$tmp/ooc.out" | head; \
                                              fail "$args: slabs differ from memory"; }
done
"$BVOX" measure --json "$tmp/a.zarr" --max-memory $M | grep -Eq '"cavities": ?1[,}]' ||
    fail "the specimen has no cavity"

# the streamed path was taken: what needs the whole volume is refused
if "$BVOX" measure --csv "$tmp/a.zarr" --max-memory $M 2> "$tmp/err"; then
    fail "--csv over the budget was accepted"
fi
grep -q "needs the whole volume in memory" "$tmp/err" || fail "unclear --csv refusal: $(cat "$tmp/err")"
[ "$(wc -l < "$tmp/err")" -eq 1 ] || fail "more than one line of error"
if "$BVOX" components "$tmp/a.zarr" --labels "$tmp/l.nii" --max-memory $M 2>/dev/null; then
    fail "--labels over the budget was accepted"
fi
[ ! -e "$tmp/l.nii" ] || fail "--labels left a file"
if "$BVOX" morph "$tmp/a.zarr" fill -o "$tmp/f.zarr" --max-memory $M 2>/dev/null; then
    fail "fill over the budget was accepted"
fi
if "$BVOX" morph "$tmp/a.zarr" dilate -o "$tmp/d.nii" --max-memory $M 2> "$tmp/err"; then
    fail "a non-.zarr output of a streamed volume was accepted"
fi
grep -q "\.zarr" "$tmp/err" || fail "unclear output refusal: $(cat "$tmp/err")"
[ ! -e "$tmp/d.nii" ] && [ ! -e "$tmp/f.zarr" ] || fail "a refused command left output"

# morphology by slabs equals morphology in memory
for op in "dilate --conn 6" "erode --conn 26" "open --conn 18" "close --radius 2" \
          "dilate --radius 3.1"; do
    # shellcheck disable=SC2086
    "$BVOX" morph "$tmp/all.nii" $op --voxel-size 0.5,0.5,1.5 -o "$tmp/mem.nii"
    # shellcheck disable=SC2086
    "$BVOX" morph "$tmp/a.zarr" $op -o "$tmp/ooc.zarr" --max-memory $M
    "$BVOX" csg "$tmp/mem.nii ^ $tmp/ooc.zarr" -o "$tmp/x.nii" --json > "$tmp/x.json"
    grep -Eq '"count": ?0[,}]' "$tmp/x.json" || fail "morph $op: slabs differ from memory"
    "$BVOX" info "$tmp/mem.nii" --json | grep -Eq '"count": ?0[,}]' && fail "morph $op: empty result"
    rm -rf "$tmp/ooc.zarr"
done
# marching cubes by slabs: the same triangles as in memory (sorted ASCII PLY
# faces, vertices by position), and the refusals of what needs the volume
"$BVOX" mesh "$tmp/all.nii" --voxel-size 0.5,0.5,1.5 -o "$tmp/mem.ply" --ascii > "$tmp/mem.txt"
"$BVOX" mesh "$tmp/a.zarr" -o "$tmp/ooc.ply" --ascii --max-memory $M > "$tmp/ooc.txt"
sed 's/mem\.ply/X/' "$tmp/mem.txt" > "$tmp/m3"; sed 's/ooc\.ply/X/' "$tmp/ooc.txt" > "$tmp/o3"
cmp -s "$tmp/m3" "$tmp/o3" || fail "mesh: counts differ: $(cat "$tmp/mem.txt") / $(cat "$tmp/ooc.txt")"
faces() { $PY - "$1" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
nv = int([l for l in lines if l.startswith("element vertex")][0].split()[2])
start = lines.index("end_header") + 1
verts = [tuple(l.split()) for l in lines[start:start + nv]]
out = []
for l in lines[start + nv:]:
    if not l.strip():
        continue
    idx = [int(x) for x in l.split()[1:]]
    tri = [verts[i] for i in idx]
    k = tri.index(min(tri))
    out.append(tri[k:] + tri[:k])
for t in sorted(out):
    print(t)
PY
}
PY=/usr/bin/python3
faces "$tmp/mem.ply" > "$tmp/mf"; faces "$tmp/ooc.ply" > "$tmp/of"
cmp -s "$tmp/mf" "$tmp/of" || fail "mesh: slabs give other triangles than memory"
if "$BVOX" mesh "$tmp/a.zarr" --smooth 5 -o "$tmp/s.ply" --max-memory $M 2>/dev/null; then
    fail "--smooth over the budget was accepted"
fi
[ ! -e "$tmp/s.ply" ] || fail "a refused mesh left output"

# CSG by slabs: a .zarr grid, a second .zarr with other chunks, a NIfTI read
# whole, a primitive and a complement, equal to the same expression in memory
"$BVOX" convert "$tmp/t.nii" "$tmp/b.zarr" --chunks 64,64,29
E="$tmp/a.zarr - sphere(r=9, at=20,30,100) + ~$tmp/b.zarr * $tmp/s.nii ^ box(min=5,5,5, max=30,60,700)"
"$BVOX" csg "$E" --voxel-size 0.5,0.5,1.5 -o "$tmp/mem.nii" --json > "$tmp/mem.json"
"$BVOX" csg "$E" --voxel-size 0.5,0.5,1.5 -o "$tmp/ooc.zarr" --json --max-memory $M > "$tmp/ooc.json"
"$BVOX" csg "$tmp/mem.nii ^ $tmp/ooc.zarr" -o "$tmp/x.nii" --json > "$tmp/x.json"
grep -Eq '"count": ?0[,}]' "$tmp/x.json" || fail "csg: slabs differ from memory"
# the printed info agrees but for the file names
sed -E 's/mem\.nii/OUT/g; s/"format": ?"[a-z]*"//' "$tmp/mem.json" > "$tmp/m2"
sed -E 's/ooc\.zarr/OUT/g; s/"format": ?"[a-z]*"//' "$tmp/ooc.json" > "$tmp/o2"
cmp -s "$tmp/m2" "$tmp/o2" || { diff "$tmp/m2" "$tmp/o2"; fail "csg: the info differs"; }
if "$BVOX" csg "$tmp/a.zarr + $tmp/b.zarr@0,0,3" -o "$tmp/y.zarr" --max-memory $M 2> "$tmp/err"; then
    fail "an offset in a streamed expression was accepted"
fi
grep -q "placement offset" "$tmp/err" || fail "unclear offset refusal: $(cat "$tmp/err")"
[ ! -e "$tmp/y.zarr" ] || fail "a refused csg left output"

# a .zarr judged small enough to read whole (its words times the copies fit
# 8M) whose uint8 samples alone (7.8 MiB) do not: read a row of chunks at a
# time, it fits, and answers as with no budget
for args in "measure --json" "components --json --conn 26"; do
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" > "$tmp/mem.out" || fail "$args in memory"
    # shellcheck disable=SC2086
    "$BVOX" $args "$tmp/a.zarr" --max-memory 8M > "$tmp/whole.out" 2> "$tmp/err" ||
        fail "$args read whole under 8M: $(cat "$tmp/err")"
    cmp -s "$tmp/mem.out" "$tmp/whole.out" || fail "$args under 8M differs from memory"
done
"$BVOX" mesh "$tmp/a.zarr" -o "$tmp/w.stl" --max-memory 8M > /dev/null 2> "$tmp/err" ||
    fail "mesh read whole under 8M: $(cat "$tmp/err")"
echo ok
