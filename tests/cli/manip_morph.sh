#!/bin/sh
# manip_morph.sh — `bvox morph` through the real command on small hand-made
# volumes with known answers: one voxel dilated by the 6/18/26
# neighbourhoods (7/19/27 voxels) and by balls of physical radius (isotropic
# and anisotropic voxels), erosion undoing it, opening removing a speck,
# closing bridging a gap, filling a cavity, hollowing a cube, removing
# islands by size and connectivity; the geometry kept; bad command lines
# (exit 2) and bad files (exit 1), neither writing anything.
# Usage: sh manip_morph.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
. "$(dirname "$0")/lib/common.sh"

# info FILE [read options] -> $tmp/j ; count FILE -> the count
info() { "$BVOX" info "$@" --json >"$tmp/j" || fail "info $1 exited $?"; }
count() {
    info "$@"
    python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["count"])' "$tmp/j"
}

# morph IN OP OUT [options]: run and expect success.
morph() {
    in=$1 op=$2 out=$3
    shift 3
    "$BVOX" morph "$tmp/$in.nii" "$op" -o "$tmp/$out.nii" "$@" || fail "morph $in $op $* exited $?"
}

# One voxel in the middle of 7^3.
mk one 7 7 7 '(x, y, z) == (3, 3, 3)'
morph one dilate d6 --conn 6
morph one dilate d18 --conn 18
morph one dilate d26 --conn 26
morph one dilate ddef
[ "$(count "$tmp/d6.nii")" = 7 ] || fail "dilate --conn 6: $(cat "$tmp/j")"
[ "$(count "$tmp/d18.nii")" = 19 ] || fail "dilate --conn 18"
[ "$(count "$tmp/d26.nii")" = 27 ] || fail "dilate --conn 26"
jcheck "$tmp/j" 'o["bbox"] == {"min": [2, 2, 2], "max": [4, 4, 4]}' || fail "dilate 26 bbox"
[ "$(count "$tmp/ddef.nii")" = 27 ] || fail "dilate default is not 26"
# --conn=N form, and the voxel at a corner: the outside is clipped (2^3).
mk corner 5 5 5 '(x, y, z) == (0, 0, 0)'
morph corner dilate dc --conn=26
[ "$(count "$tmp/dc.nii")" = 8 ] || fail "dilate at the corner"
# Erosion undoes the dilation of one voxel: the 3^3 cube erodes to its
# centre with 26 and with 6; the 6-cross vanishes with 26, keeps its centre
# with 6.
morph d26 erode e26
[ "$(count "$tmp/e26.nii")" = 1 ] || fail "erode 26 of a 3^3 cube"
jcheck "$tmp/j" 'o["bbox"] == {"min": [3, 3, 3], "max": [3, 3, 3]}' || fail "erode bbox"
morph d26 erode e6 --conn 6
[ "$(count "$tmp/e6.nii")" = 1 ] || fail "erode 6 of a 3^3 cube"
morph d6 erode e6b --conn 26
[ "$(count "$tmp/e6b.nii")" = 0 ] || fail "erode 26 of a 6-cross"
morph d6 erode e6c --conn 6
[ "$(count "$tmp/e6c.nii")" = 1 ] || fail "erode 6 of a 6-cross"

# Balls of physical radius, unit voxels: r 1 -> 7, 1.5 -> 19, 1.8 -> 27,
# 2 -> 33 (the six at distance 2 join).
for pair in 1:7 1.5:19 1.8:27 2:33; do
    r=${pair%%:*} want=${pair#*:}
    morph one dilate "b$r" --radius "$r"
    [ "$(count "$tmp/b$r.nii")" = "$want" ] || fail "dilate --radius $r: want $want"
done
# Anisotropic voxels 1 x 1 x 2 mm: radius 1 mm reaches x and y only (5);
# 2 mm reaches one slice up and down, and 13 voxels in the slice (15).
mk aniso 7 7 7 '(x, y, z) == (3, 3, 3)' --voxel-size 1,1,2 --unit mm
morph aniso dilate a1 --radius 1
[ "$(count "$tmp/a1.nii")" = 5 ] || fail "anisotropic radius 1"
morph aniso dilate a2 --radius 2
[ "$(count "$tmp/a2.nii")" = 15 ] || fail "anisotropic radius 2"
# The geometry is kept.
jcheck "$tmp/j" 'o["voxel_size"] == [1, 1, 2] and o["unit"] == "mm"' || fail "geometry lost"
# The voxel size given on the command line counts for the radius.
morph one dilate a3 --radius 1 --voxel-size 1,1,2
[ "$(count "$tmp/a3.nii")" = 5 ] || fail "--voxel-size override with --radius"
# Erosion by a ball: the 3^3 cube loses all but its centre at radius 1.
morph d26 erode eb --radius 1
[ "$(count "$tmp/eb.nii")" = 1 ] || fail "erode --radius 1"

# Opening (26) keeps a 3^3 cube and drops a lone speck.
mk speck 9 9 9 '(1 <= x <= 3 and 1 <= y <= 3 and 1 <= z <= 3) or (x, y, z) == (7, 7, 7)'
morph speck open op
[ "$(count "$tmp/op.nii")" = 27 ] || fail "open"
jcheck "$tmp/j" 'o["bbox"] == {"min": [1, 1, 1], "max": [3, 3, 3]}' || fail "open bbox"
# Closing (26) bridges a one-voxel gap between two voxels: a row of three.
mk gap 7 7 7 '(x, y, z) in ((2, 3, 3), (4, 3, 3))'
morph gap close cl
[ "$(count "$tmp/cl.nii")" = 3 ] || fail "close"
jcheck "$tmp/j" 'o["bbox"] == {"min": [2, 3, 3], "max": [4, 3, 3]}' || fail "close bbox"
# Closing at the border of the volume does not eat into the object.
mk full 4 4 4 'True'
morph full close clf
[ "$(count "$tmp/clf.nii")" = 64 ] || fail "close of a full volume"

# A 5^3 cube with a 3^3 cavity: fill gives 125; an open box (cavity reaching
# the border) stays as it is.
mk shell 7 7 7 '1 <= min(x, y, z) and max(x, y, z) <= 5 and not (2 <= min(x, y, z) and max(x, y, z) <= 4)'
[ "$(count "$tmp/shell.nii")" = 98 ] || fail "test shell"
morph shell fill fi
[ "$(count "$tmp/fi.nii")" = 125 ] || fail "fill"
mk cup 7 7 7 '1 <= min(x, y) and max(x, y) <= 5 and z <= 5 and not (2 <= min(x, y) and max(x, y) <= 4 and z >= 2)'
morph cup fill fc
[ "$(count "$tmp/fc.nii")" = "$(count "$tmp/cup.nii")" ] || fail "fill of an open cup"

# Hollowing a solid 5^3 cube: a one-voxel shell of 98 (default, --radius 1
# with unit voxels, --conn 26), 124 with radius 2 (only the centre is further).
mk cube 7 7 7 '1 <= min(x, y, z) and max(x, y, z) <= 5'
morph cube hollow h
[ "$(count "$tmp/h.nii")" = 98 ] || fail "hollow default"
morph cube hollow h1 --radius 1
[ "$(count "$tmp/h1.nii")" = 98 ] || fail "hollow --radius 1"
morph cube hollow h2 --radius 2
[ "$(count "$tmp/h2.nii")" = 124 ] || fail "hollow --radius 2"
# The default shell is the voxels with a face neighbour outside: on a
# 6-cross, every voxel but the centre (whose 6 neighbours are all set).
morph d6 hollow hx
[ "$(count "$tmp/hx.nii")" = 6 ] || fail "hollow of a 6-cross"

# Islands: a 3^3 cube, a bar of 2, a single voxel, and two voxels touching
# only at a corner (one 26-component of 2, two 6-components of 1).
mk isl 12 12 12 '(x <= 2 and y <= 2 and z <= 2) or (x, y, z) in ((8, 0, 0), (9, 0, 0), (0, 8, 8), (6, 6, 6), (7, 7, 7))'
[ "$(count "$tmp/isl.nii")" = 32 ] || fail "test islands"
morph isl islands i3 --min-size 3
[ "$(count "$tmp/i3.nii")" = 27 ] || fail "islands --min-size 3"
morph isl islands i2 --min-size 2
[ "$(count "$tmp/i2.nii")" = 31 ] || fail "islands --min-size 2 (26)"
morph isl islands i2b --min-size 2 --conn 6
[ "$(count "$tmp/i2b.nii")" = 29 ] || fail "islands --min-size 2 --conn 6"
morph isl islands i1 --min-size 1
[ "$(count "$tmp/i1.nii")" = 32 ] || fail "islands --min-size 1"

# Other output formats by extension.
"$BVOX" morph "$tmp/one.nii" dilate -o "$tmp/d.tif" --conn 6 || fail "morph to .tif"
[ "$(count "$tmp/d.tif")" = 7 ] || fail "morph to .tif"
"$BVOX" morph "$tmp/one.raw" dilate --output "$tmp/d.binvox" --dims 7,7,7 --type u8 ||
    fail "morph from raw to binvox"
[ "$(count "$tmp/d.binvox")" = 27 ] || fail "morph from raw"

# --help
"$BVOX" morph --help >"$tmp/help" || fail "morph --help exited $?"
for word in dilate erode open close fill hollow islands --radius --conn --min-size; do
    grep -q -- "$word" "$tmp/help" || fail "morph --help does not mention $word"
done

# Bad command lines: exit 2, one "bvox: morph: ..." line, nothing written.
out=$tmp/out
mkdir "$out"
expect() {
    want=$1
    shift
    set +e
    "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "$*: exit $rc, expected $want ($(cat "$tmp/stderr"))"
    [ ! -s "$tmp/stdout" ] || fail "$*: wrote to stdout"
    [ "$(wc -l <"$tmp/stderr")" -eq 1 ] || fail "$*: stderr is not one line: $(cat "$tmp/stderr")"
    grep -q '^bvox: ' "$tmp/stderr" || fail "$*: stderr is not 'bvox: ...'"
    [ -z "$(ls -A "$out")" ] || fail "$*: wrote $(ls -A "$out")"
}
IN=$tmp/one.nii
expect 2 "$BVOX" morph "$IN" dilate
expect 2 "$BVOX" morph "$IN" -o "$out/x.nii"
expect 2 "$BVOX" morph -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" grow -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate extra -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --conn 7 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --conn six -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --radius 0 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --radius -1 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --radius abc -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --radius 1 --conn 6 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --min-size 3 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" fill --radius 1 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" fill --conn 6 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" islands -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" islands --min-size 0 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" islands --min-size 3 --radius 1 -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate --frobnicate -o "$out/x.nii"
expect 2 "$BVOX" morph "$IN" dilate -o "$out/x.unknown"
expect 2 "$BVOX" morph "$IN" dilate -o
# Bad files: exit 1, nothing written.
expect 1 "$BVOX" morph "$tmp/nope.nii" dilate -o "$out/x.nii"
head -c 200 "$IN" >"$tmp/short.nii"
expect 1 "$BVOX" morph "$tmp/short.nii" dilate -o "$out/x.nii"
head -c 400 "$IN" >"$tmp/short2.nii"
expect 1 "$BVOX" morph "$tmp/short2.nii" erode -o "$out/x.nii"
expect 1 "$BVOX" morph "$IN" dilate -o "$out/no/such/dir/x.nii"
# A ball far too large for the volume's voxels is refused by the library.
expect 1 "$BVOX" morph "$IN" dilate --radius 1000 -o "$out/x.nii"
echo "ok"
