#!/bin/sh
# bad_input.sh — bad files and impossible outputs through the real command:
# each must exit 1 with exactly one "bvox: <message>" line on stderr, print
# nothing on stdout, and leave no output file behind (no partial file, no
# temporary file). The cases here are the "Bad inputs" table of README.md;
# run this script by hand to see each message.
# Usage: sh bad_input.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
in=$tmp/in
out=$tmp/out
mkdir "$in" "$out"

# A valid 4 x 3 x 2 volume (3 voxels) as NIfTI and gzipped NIfTI.
printf '\000\001\000\000\000\000\000\000\000\000\000\000' >"$in/a.raw"
printf '\000\000\000\000\000\000\310\000\000\000\000\005' >>"$in/a.raw"
"$BVOX" convert "$in/a.raw" "$in/good.nii" --dims 4,3,2 --type u8 || fail "making good.nii"
"$BVOX" convert "$in/good.nii" "$in/good.nii.gz" || fail "making good.nii.gz"
size=$(wc -c <"$in/good.nii")
[ "$size" -gt 352 ] || fail "good.nii is only $size bytes"

# expect RC LABEL -- COMMAND...: runs COMMAND, checks the exit status, the one
# stderr line and that $out (and the target, for paths outside it) is as before.
expect() {
    want=$1 label=$2
    shift 3
    before=$(ls -A "$out")
    set +e
    "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    rc=$?
    set -e
    msg=$(cat "$tmp/stderr")
    [ "$rc" -eq "$want" ] || fail "$label: exit $rc, expected $want ($msg)"
    [ ! -s "$tmp/stdout" ] || fail "$label: wrote to stdout: $(cat "$tmp/stdout")"
    [ "$(wc -l <"$tmp/stderr")" -eq 1 ] || fail "$label: stderr is not one line: $msg"
    case $msg in "bvox: "?*) ;; *) fail "$label: stderr is not 'bvox: ...': $msg" ;; esac
    [ "$(ls -A "$out")" = "$before" ] || fail "$label: left files in the output folder: $(ls -A "$out")"
    printf '%-28s exit %s  %s\n' "$label" "$rc" "$msg"
}

# Missing input, for both commands that read.
expect 1 "missing file" -- "$BVOX" info "$in/nope.nii"
expect 1 "missing file (convert)" -- "$BVOX" convert "$in/nope.nii" "$out/x.nii"
# A folder where a file is expected (.nii named folder).
mkdir "$in/folder.nii"
expect 1 "folder named .nii" -- "$BVOX" convert "$in/folder.nii" "$out/x.nii"

# Truncated NIfTI: inside the 348-byte header, and inside the voxel data.
head -c 200 "$in/good.nii" >"$in/short-header.nii"
expect 1 "truncated header" -- "$BVOX" convert "$in/short-header.nii" "$out/x.tif"
head -c $((size - 5)) "$in/good.nii" >"$in/short-data.nii"
expect 1 "truncated voxel data" -- "$BVOX" convert "$in/short-data.nii" "$out/x.nii"
gzsize=$(wc -c <"$in/good.nii.gz")
head -c $((gzsize / 2)) "$in/good.nii.gz" >"$in/short.nii.gz"
expect 1 "truncated .nii.gz" -- "$BVOX" convert "$in/short.nii.gz" "$out/x.nii"
: >"$in/empty.nii"
expect 1 "empty file" -- "$BVOX" info "$in/empty.nii"

# NIfTI headers with impossible dimensions, written field by field.
# hdr FILE NDIM NX NY NZ DATATYPE BITPIX
hdr() {
    python3 - "$@" <<'PY'
import struct, sys
path, ndim, nx, ny, nz, dtype, bitpix = sys.argv[1], *map(int, sys.argv[2:])
h = bytearray(348)
struct.pack_into("<i", h, 0, 348)
struct.pack_into("<8h", h, 40, ndim, nx, ny, nz, 1, 1, 1, 1)
struct.pack_into("<hh", h, 70, dtype, bitpix)
struct.pack_into("<8f", h, 76, 1, 1, 1, 1, 1, 1, 1, 1)
struct.pack_into("<f", h, 108, 352.0)
h[344:348] = b"n+1\0"
open(path, "wb").write(bytes(h) + b"\0" * 4 + b"\1" * 64)
PY
}
hdr "$in/huge.nii" 3 32767 32767 32767 2 8
expect 1 "huge dims (32767^3)" -- "$BVOX" convert "$in/huge.nii" "$out/x.nii"
hdr "$in/huge16.nii" 3 30000 30000 1000 512 16
expect 1 "huge dims, u16" -- "$BVOX" info "$in/huge16.nii"
hdr "$in/negative.nii" 3 -4 3 2 2 8
expect 1 "negative dimension" -- "$BVOX" info "$in/negative.nii"
hdr "$in/zero.nii" 3 0 3 2 2 8
expect 1 "zero dimension" -- "$BVOX" info "$in/zero.nii"
hdr "$in/badtype.nii" 3 4 3 2 12345 8
expect 1 "unknown datatype" -- "$BVOX" info "$in/badtype.nii"
hdr "$in/ndim9.nii" 9 4 3 2 2 8
expect 1 "dim[0] out of range" -- "$BVOX" info "$in/ndim9.nii"
# A valid file (2.5 MiB of raw samples) over the memory budget given on the
# command line.
head -c 2560000 /dev/zero >"$in/big.raw"
expect 1 "over --max-memory" -- "$BVOX" convert "$in/big.raw" "$out/x.nii" --dims 200,200,64 \
    --type u8 --max-memory 1M

# Not a volume at all, under a known and an unknown extension.
printf 'hello, world\n' >"$in/text.nii"
expect 1 "text named .nii" -- "$BVOX" info "$in/text.nii"
printf 'hello, world\n' >"$in/text.xyz"
expect 1 "unknown input extension" -- "$BVOX" info "$in/text.xyz"
# Raw data shorter than --dims says.
expect 1 "raw shorter than --dims" -- "$BVOX" info "$in/a.raw" --dims 4,3,3 --type u8
expect 1 "raw --offset past the end" -- "$BVOX" info "$in/a.raw" --dims 4,3,2 --type u8 --offset 100
# An unknown --format name.
expect 1 "unknown --format" -- "$BVOX" info "$in/good.nii" --format jpeg2000

# Outputs that cannot be written: nothing may appear anywhere.
expect 1 "output folder missing" -- "$BVOX" convert "$in/good.nii" "$out/no/such/dir/x.nii"
[ ! -e "$out/no" ] || fail "a folder was created for a failed output"
expect 1 "output under /proc" -- "$BVOX" convert "$in/good.nii" /proc/bvox-test.nii
[ ! -e /proc/bvox-test.nii ] || fail "/proc/bvox-test.nii exists"
expect 1 "output is a folder" -- "$BVOX" convert "$in/good.nii" "$in/folder.nii"
# A FIFO as input (it used to hang in open), a FIFO as output (it used to be
# replaced by a regular file), a folder output into a folder of the user's
# (it used to be deleted with everything in it).
mkfifo "$in/fifo.nii"
expect 1 "a FIFO as input" -- timeout 20 "$BVOX" info "$in/fifo.nii"
expect 1 "output is a FIFO" -- timeout 20 "$BVOX" convert "$in/good.nii" "$in/fifo.nii"
[ -p "$in/fifo.nii" ] || fail "the FIFO was replaced"
mkdir "$in/p"
echo x >"$in/p/thesis.txt"
expect 1 "folder output, user's folder" -- "$BVOX" convert "$in/good.nii" "$in/p/" --output-format png
[ "$(ls -A "$in/p")" = thesis.txt ] || fail "the user's folder was changed: $(ls -A "$in/p")"
expect 1 "demo -o under /proc" -- "$BVOX" demo -o /proc/bvox-test-dir
hidden=$(find "$in" -name '.*' ! -name .)
[ -z "$hidden" ] || fail "temporary files left in the input folder: $hidden"

# Meshes: truncated, NaN coordinates, an index out of range, an absurd count.
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n' >"$in/trunc.stl"
expect 1 "truncated ASCII STL" -- "$BVOX" meshinfo "$in/trunc.stl"
printf 'OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n' >"$in/nan.off"
expect 1 "NaN coordinate (OFF)" -- "$BVOX" voxelize "$in/nan.off" -o "$out/x.nii" --res 16
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$in/idx.obj"
expect 1 "face index out of range" -- "$BVOX" voxelize "$in/idx.obj" -o "$out/x.nii" --res 16
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n' \
    >"$in/huge.ply"
expect 1 "absurd PLY vertex count" -- "$BVOX" meshinfo "$in/huge.ply"

# Sections and contours: an empty folder, sections of different sizes, a
# contour of 2 points, a self-crossing contour, deep nesting, an SVG arc.
mkdir "$in/nosections"
expect 1 "empty section folder" -- "$BVOX" reconstruct "$in/nosections" -o "$out/m.nii" --quiet
python3 - "$in" <<'PY'
import struct, sys, zlib
def png(path, w, h):
    raw = b"".join(b"\0" + bytes([200] * w) for _ in range(h))
    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                           + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
png(sys.argv[1] + "/s1.png", 32, 32)
png(sys.argv[1] + "/s2.png", 24, 32)
PY
expect 1 "sections of different sizes" -- "$BVOX" reconstruct "$in/s1.png" "$in/s2.png" \
    -o "$out/m.nii" --quiet
printf '{"sections":[{"z":0,"contours":[[[0,0],[5,0]]]}]}' >"$in/two.json"
expect 1 "contour of 2 points" -- "$BVOX" reconstruct "$in/two.json" -o "$out/m.nii" --quiet
printf '{"sections":[{"z":0,"contours":[[[0,0],[10,10],[10,0],[0,10]]]}]}' >"$in/cross.json"
expect 1 "self-crossing contour with --strict" -- "$BVOX" reconstruct "$in/cross.json" -o "$out/m.nii" --quiet --strict
printf '{"sections":[{"z":0,"contours":[[[0,0],[10,0],[10,10],[0,10]],[[5,5],[15,5],[15,15],[5,15]]]}]}' >"$in/cross2.json"
expect 1 "two contours crossing each other" -- "$BVOX" reconstruct "$in/cross2.json" -o "$out/m.nii" --quiet
python3 -c 'print("{\"extra\":" + "[" * 100000)' >"$in/deep.json"
expect 1 "JSON nested 100000 deep" -- "$BVOX" reconstruct "$in/deep.json" -o "$out/m.nii" --quiet
printf '<svg><path d="M 0 0 A 5 5 0 0 1 10 10 Z"/></svg>' >"$in/arc.svg"
expect 1 "SVG elliptical arc" -- "$BVOX" reconstruct "$in/arc.svg" -o "$out/m.nii" --quiet
printf 'key 5\nfrobnicate 3\n' >"$in/bad-script.txt"
expect 1 "bad viewer script" -- "$BVOX" view --demo --script "$in/bad-script.txt"

# MetaImage: data cut short, a missing .zraw, several channels; a .mhd that
# cannot be written leaves neither the header nor its data file.
"$BVOX" convert "$in/good.nii" "$in/good.mha" || fail "making good.mha"
printf 'NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n0123' \
    >"$in/short.mha"
expect 1 "MetaImage data cut short" -- "$BVOX" convert "$in/short.mha" "$out/x.nii"
printf 'NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\nCompressedData = True\nElementDataFile = gone.zraw\n' \
    >"$in/gone.mhd"
expect 1 "MetaImage data file missing" -- "$BVOX" info "$in/gone.mhd"
printf 'NDims = 3\nDimSize = 4 3 2\nElementNumberOfChannels = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n' \
    >"$in/rgb.mha"
expect 1 "MetaImage with 3 channels" -- "$BVOX" info "$in/rgb.mha"
expect 1 ".mhd into a missing folder" -- "$BVOX" convert "$in/good.mha" "$out/nowhere/x.mhd"

# A failed conversion leaves an existing output unchanged.
printf 'keep me' >"$out/keep.nii"
expect 1 "bad input, existing output" -- "$BVOX" convert "$in/short-data.nii" "$out/keep.nii"
[ "$(cat "$out/keep.nii")" = "keep me" ] || fail "an existing output was changed"
echo "ok"
