#!/bin/sh
# mesh_stream.sh — `bvox mesh` of a .zarr over --max-memory writes the mesh
# slab by slab as it is made: for every format (binary and ASCII STL and PLY,
# OBJ, OFF) the file holds the same triangles (up to order) and as many
# vertices as the in-memory mesh's, the summary line and --json agree, and a
# mesh larger than the budget (which the in-memory path refuses) is written.
# Odd chunks (37 x 100 x 65), objects crossing chunk and slab borders.
# Usage: sh mesh_stream.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
PY=/usr/bin/python3
M=5M

# canon FILE: the triangles as sorted rows of positions (each rotated to
# start at its smallest corner) and the number of vertices (STL: distinct
# positions), whatever the format
canon() { $PY - "$1" <<'PY'
import struct, sys
import numpy as np
path = sys.argv[1]
data = open(path, "rb").read()
ext = path.rsplit(".", 1)[1]
def text():
    return data.decode().split("\n")
if ext == "stl" and not data.startswith(b"solid"):
    n = struct.unpack("<I", data[80:84])[0]
    assert len(data) == 84 + 50 * n, "binary STL size"
    rec = np.frombuffer(data[84:], dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    tri = rec["v"].astype(np.float64)
    nv = len(np.unique(tri.reshape(-1, 3), axis=0))
elif ext == "stl":
    v = [tuple(map(float, l.split()[1:])) for l in text() if l.strip().startswith("vertex")]
    tri = np.array(v).reshape(-1, 3, 3)
    assert text()[-2].strip() == "endsolid bvox"
    nv = len(np.unique(tri.reshape(-1, 3), axis=0))
elif ext == "ply":
    end = data.index(b"end_header\n") + len(b"end_header\n")
    head = data[:end].decode().split("\n")
    nv = int([l for l in head if l.startswith("element vertex")][0].split()[2])
    nf = int([l for l in head if l.startswith("element face")][0].split()[2])
    if "format ascii 1.0" in head:
        rows = data[end:].decode().split("\n")
        verts = np.array([list(map(float, r.split())) for r in rows[:nv]]).reshape(-1, 3)
        faces = np.array([list(map(int, r.split()))[1:] for r in rows[nv:nv + nf]]).reshape(-1, 3)
        assert not "".join(rows[nv + nf:]).strip()
    else:
        verts = np.frombuffer(data, "<f8", 3 * nv, end).reshape(-1, 3)
        f = np.frombuffer(data, [("n", "u1"), ("i", "<i4", 3)], nf, end + 24 * nv)
        assert (f["n"] == 3).all() and len(data) == end + 24 * nv + 13 * nf
        faces = f["i"]
    tri = verts[faces]
elif ext == "obj":
    rows = text()
    verts = np.array([list(map(float, r.split()[1:])) for r in rows if r.startswith("v ")])
    faces = np.array([list(map(int, r.split()[1:])) for r in rows if r.startswith("f ")]) - 1
    nv = len(verts)
    tri = verts[faces]
else:
    rows = [r for r in text() if r.strip()]
    nv, nf, _ = map(int, rows[1].split())
    verts = np.array([list(map(float, r.split())) for r in rows[2:2 + nv]])
    faces = np.array([list(map(int, r.split()))[1:] for r in rows[2 + nv:2 + nv + nf]])
    tri = verts[faces]
out = []
for t in tri.tolist():
    k = t.index(min(t))
    out.append(tuple(map(tuple, t[k:] + t[:k])))
out.sort()
print(nv, len(out))
for t in out:
    print(t)
PY
}

# a hollow ball around the chunk corner (37, 100, 65), a torus across the z
# chunk border at 130, a bar along z through all chunks
D=81,101,1000
"$BVOX" shape sphere r=25 at=37,70,65 --dims $D -o "$tmp/s.nii" >/dev/null
"$BVOX" shape sphere r=12 at=37,70,65 --dims $D -o "$tmp/i.nii" >/dev/null
"$BVOX" shape torus R=20 r=6 at=40,40,130 axis=1,0,0 --dims $D -o "$tmp/t.nii" >/dev/null
"$BVOX" shape box min=70,5,3 max=72,7,996 --dims $D -o "$tmp/b.nii" >/dev/null
"$BVOX" csg "$tmp/s.nii - $tmp/i.nii + $tmp/t.nii + $tmp/b.nii" -o "$tmp/all.nii" >/dev/null
"$BVOX" convert "$tmp/all.nii" "$tmp/a.zarr" --chunks 37,100,65 --voxel-size 0.5,0.5,1.5 \
    --unit um
# the words (1 MiB) times the in-memory copies exceed 5M: streamed
for f in "stl" "stl --ascii" "ply" "ply --ascii" "obj" "off"; do
    ext=${f%% *} flags=${f#"$ext"}
    # shellcheck disable=SC2086
    "$BVOX" mesh "$tmp/all.nii" --voxel-size 0.5,0.5,1.5 -o "$tmp/mem.$ext" $flags --json \
        > "$tmp/mem.json" || fail "mesh $f in memory"
    # shellcheck disable=SC2086
    "$BVOX" mesh "$tmp/a.zarr" -o "$tmp/ooc.$ext" $flags --json --max-memory $M \
        > "$tmp/ooc.json" || fail "mesh $f by slabs"
    canon "$tmp/mem.$ext" > "$tmp/mc" || fail "reading mem.$ext"
    canon "$tmp/ooc.$ext" > "$tmp/oc" || fail "reading ooc.$ext"
    cmp -s "$tmp/mc" "$tmp/oc" || fail "mesh $f: the streamed file holds other triangles"
    [ "$(wc -l < "$tmp/mc")" -gt 1000 ] || fail "mesh $f: too few triangles"
    # --json: the same keys and answers (the volume summed in another order)
    $PY - "$tmp/mem.json" "$tmp/ooc.json" <<'PY' || fail "mesh $f: --json differs"
import json, math, sys
m, o = (json.load(open(p)) for p in sys.argv[1:])
assert set(m) == set(o), (sorted(m), sorted(o))
for k in m:
    if k in ("file", "input", "output"):
        continue
    if isinstance(m[k], float):
        assert math.isclose(m[k], o[k], rel_tol=1e-9), (k, m[k], o[k])
    else:
        assert m[k] == o[k], (k, m[k], o[k])
assert o["watertight"] is True
PY
    ls -a "$tmp" | grep -q '^\.ooc' && fail "mesh $f: a temporary file was left"
    rm -f "$tmp/mem.$ext" "$tmp/ooc.$ext"
done
# the summary line
"$BVOX" mesh "$tmp/all.nii" --voxel-size 0.5,0.5,1.5 -o "$tmp/m.ply" | sed 's/m\.ply/X/' > "$tmp/m1"
"$BVOX" mesh "$tmp/a.zarr" -o "$tmp/o.ply" --max-memory $M | sed 's/o\.ply/X/' > "$tmp/o1"
cmp -s "$tmp/m1" "$tmp/o1" || fail "summary lines differ: $(cat "$tmp/m1") / $(cat "$tmp/o1")"

# a mesh larger than the budget: scattered voxels (about 8 triangles
# each) in 128 x 128 x 512; in memory the mesh is refused, by slabs it is written
$PY - "$tmp/n.raw" <<'PY'
import sys
import numpy as np
rng = np.random.default_rng(7)
v = (rng.random((512, 128, 128)) < 1 / 150).astype(np.uint8)  # z, y, x
v[100:300, 20:60, 30:90] = 1  # a box across slabs and chunks
v.tofile(sys.argv[1])
PY
"$BVOX" convert "$tmp/n.raw" "$tmp/n.nii" --dims 128,128,512 --type u8
"$BVOX" convert "$tmp/n.nii" "$tmp/n.zarr" --chunks 64,64,29
if "$BVOX" mesh "$tmp/n.nii" -o "$tmp/refused.ply" --max-memory $M 2> "$tmp/err"; then
    fail "the whole mesh fits the budget: the test shows nothing"
fi
grep -q "memory budget" "$tmp/err" || fail "unclear refusal: $(cat "$tmp/err")"
"$BVOX" mesh "$tmp/n.zarr" -o "$tmp/big.ply" --max-memory $M > "$tmp/big.txt" ||
    fail "the streamed mesh over the budget failed"
"$BVOX" mesh "$tmp/n.nii" -o "$tmp/want.ply" > /dev/null
canon "$tmp/want.ply" > "$tmp/wc"; canon "$tmp/big.ply" > "$tmp/bc"
cmp -s "$tmp/wc" "$tmp/bc" || fail "the mesh over the budget differs from the in-memory one"
[ ! -e "$tmp/refused.ply" ] || fail "the refused mesh left a file"

# what cannot stream is refused, and leaves nothing
if "$BVOX" mesh "$tmp/a.zarr" --method cuberille -o "$tmp/c.ply" --max-memory $M 2> "$tmp/err"; then
    fail "cuberille over the budget was accepted"
fi
grep -q "needs the whole volume in memory" "$tmp/err" || fail "unclear refusal: $(cat "$tmp/err")"
[ ! -e "$tmp/c.ply" ] || fail "a refused mesh left output"
echo ok
