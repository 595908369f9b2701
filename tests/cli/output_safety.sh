#!/bin/sh
# output_safety.sh — what bvox will and will not overwrite (README, "Bad
# inputs and outputs"), through the real command in a scratch folder:
#  - a folder output never deletes a file bvox did not write: a user's folder
#    is refused (shape, convert into the input's own folder, contours,
#    reconstruct --save-contours, a viewer script's save), --force adds files
#    and removes nothing, bvox's own earlier output is replaced exactly; a
#    .zarr tree is replaced only with --force, a user's folder never;
#  - a FIFO as output is refused and stays a FIFO, a symlink is written
#    through (the link stays), a 0600 file stays 0600;
#  - a FIFO as input is refused at once instead of hanging;
#  - Ctrl-C / SIGTERM in the middle of a write leave no temporary file.
# Usage: sh output_safety.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$tmp"

# refused LABEL CMD...: exit 1 with one "bvox: " line
refused() {
    label=$1
    shift
    set +e
    "$@" >"$tmp/out.txt" 2>"$tmp/err.txt"
    rc=$?
    set -e
    [ "$rc" -eq 1 ] || fail "$label: exit $rc, expected 1 ($(cat "$tmp/err.txt"))"
    [ "$(wc -l <"$tmp/err.txt")" -eq 1 ] && grep -q "^bvox: " "$tmp/err.txt" || fail "$label: stderr: $(cat "$tmp/err.txt")"
    printf '%-34s %s\n' "$label" "$(cat "$tmp/err.txt")"
}
# user_data DIR: a folder of the user's (the issue's reproducer)
user_data() {
    mkdir -p "$1/sub"
    echo x >"$1/thesis.txt"
    echo y >"$1/sub/notes.txt"
}
intact() {
    [ "$(cat "$1/thesis.txt")" = x ] && [ "$(cat "$1/sub/notes.txt")" = y ] ||
        fail "$2: the user's files were touched: $(ls -A "$1")"
}
no_temps() {
    left=$(ls -A "$1" | grep '^\.' | grep -v '^\.bvox-manifest$' || true)
    [ -z "$left" ] || fail "$2: temporary files left in $1: $left"
}

# ---- 1. folder outputs
user_data p
refused "shape -o user folder/" "$BVOX" shape sphere r=3 --dims 8,8,8 -o p/
intact p "shape"
[ "$(ls -A p | tr '\n' ' ')" = "sub thesis.txt " ] || fail "shape wrote into p: $(ls -A p)"
"$BVOX" shape sphere r=3 --dims 8,8,8 -o p/ --force >/dev/null || fail "--force"
intact p "--force"
[ -f p/slice_0007.png ] || fail "--force wrote no slices"
no_temps . "--force"

# convert into the folder that holds the input: the input is never an output
mkdir scan
"$BVOX" shape sphere r=3 --dims 8,8,8 -o scan/scan.nii >/dev/null
cp scan/scan.nii scan.copy
(cd scan && refused "convert scan.nii \$PWD/" "$BVOX" convert scan.nii "$PWD/" --output-format png)
cmp -s scan/scan.nii scan.copy || fail "convert into its own folder changed the input"
[ "$(ls -A scan)" = scan.nii ] || fail "convert wrote beside the input: $(ls -A scan)"

# bvox's own earlier output: replaced exactly (fewer slices: the rest go)
"$BVOX" shape sphere r=3 --dims 8,8,8 -o own/ >/dev/null
[ "$(ls own | wc -l)" -eq 9 ] && [ -f own/.bvox-manifest ] && [ -f own/voxel_size.txt ] ||
    fail "own/: $(ls -A own)"
chmod 0750 own
"$BVOX" shape sphere r=2 --dims 6,6,4 -o own/ >/dev/null || fail "replacing own output"
[ "$(ls own | tr '\n' ' ')" = "slice_0000.png slice_0001.png slice_0002.png slice_0003.png voxel_size.txt " ] ||
    fail "own/ after replace: $(ls -A own)"
[ "$(stat -c %a own)" = 750 ] || fail "the folder was not kept: mode $(stat -c %a own)"
"$BVOX" info own/ | grep -q "6 x 6 x 4" || fail "own/ reads back wrong"
# a user's file added to it: refused; with --force it stays
echo mine >own/mine.txt
refused "shape -o own/ + user file" "$BVOX" shape sphere r=2 --dims 6,6,4 -o own/
"$BVOX" shape sphere r=2 --dims 6,6,2 -o own/ --force >/dev/null
[ "$(cat own/mine.txt)" = mine ] && [ ! -e own/slice_0002.png ] || fail "--force over own: $(ls -A own)"
no_temps . "own"

# a .zarr tree: new or empty folder written; bvox's own replaced only with
# --force (whole: the old levels go); a user's folder refused even forced
"$BVOX" shape sphere r=3 --dims 9,8,70 -o z.nii >/dev/null
"$BVOX" convert z.nii z.zarr --chunks 4,4,16 >/dev/null || fail "zarr"
[ -d z.zarr/2 ] && [ -f z.zarr/.bvox-manifest ] || fail "z.zarr: $(ls -A z.zarr)"
refused "convert -o own .zarr" "$BVOX" convert z.nii z.zarr
"$BVOX" convert z.nii z.zarr --levels 1 --force >/dev/null || fail "zarr --force"
[ "$(ls -A z.zarr | tr '\n' ' ')" = ".bvox-manifest .zattrs .zgroup 0 " ] ||
    fail "z.zarr after --force: $(ls -A z.zarr)"
user_data u.zarr
refused "convert -o user .zarr --force" "$BVOX" convert z.nii u.zarr --force
intact u.zarr "zarr"
mkdir e.zarr
"$BVOX" convert z.nii e.zarr >/dev/null || fail "zarr into an empty folder"
"$BVOX" info e.zarr | grep -q "9 x 8 x 70" || fail "e.zarr reads back wrong"
no_temps . "zarr"

# contour folders: contours -o DIR, reconstruct --save-contours DIR
user_data c
refused "contours -o user folder" "$BVOX" contours scan/scan.nii -o c
intact c "contours"
"$BVOX" contours scan/scan.nii -o svg >/dev/null || fail "contours -o svg"
"$BVOX" contours scan/scan.nii -o svg >/dev/null || fail "contours -o svg again"
refused "contours -o png folder" "$BVOX" contours scan/scan.nii -o own
"$BVOX" reconstruct svg -o model.nii --quiet >/dev/null || fail "reconstruct from svg"
refused "reconstruct --save-contours" "$BVOX" reconstruct svg --save-contours c --quiet
intact c "reconstruct --save-contours"
no_temps . "contours"

# a viewer script someone sent: save DIR/ must not wipe it
if "$BVOX" view --help 2>/dev/null | grep -q offscreen; then
    user_data v
    printf 'save %s/v/\n' "$tmp" >wipe.txt
    set +e
    "$BVOX" view scan/scan.nii --script wipe.txt --offscreen >/dev/null 2>err.txt
    rc=$?
    set -e
    [ "$rc" -ne 0 ] || fail "viewer script save into a user folder succeeded"
    intact v "viewer save"
    printf 'viewer script save DIR/           exit %s\n' "$rc"
fi

# ---- 2, 3. special files, symlinks, modes
mkfifo fifo.nii
refused "shape -o FIFO" timeout 20 "$BVOX" shape sphere r=3 --dims 8,8,8 -o fifo.nii
[ -p fifo.nii ] || fail "the FIFO was replaced"
grep -q "FIFO" err.txt || fail "the message does not say FIFO"
mkdir real
"$BVOX" shape sphere r=3 --dims 8,8,8 -o real/m.nii >/dev/null
ln -s real/m.nii link.nii
"$BVOX" shape sphere r=2 --dims 8,8,8 -o link.nii >/dev/null || fail "writing through a symlink"
[ -L link.nii ] || fail "the symlink was replaced by a file"
"$BVOX" info real/m.nii | grep -q "count:        32 voxels" || fail "the link's target was not written"
[ "$(ls -A real)" = m.nii ] || fail "temporary left beside the target: $(ls -A real)"
chmod 0600 real/m.nii
"$BVOX" shape sphere r=3 --dims 8,8,8 -o real/m.nii >/dev/null
[ "$(stat -c %a real/m.nii)" = 600 ] || fail "a 0600 file became $(stat -c %a real/m.nii)"
(umask 077 && "$BVOX" shape sphere r=3 --dims 8,8,8 -o new.nii >/dev/null)
[ "$(stat -c %a new.nii)" = 600 ] || fail "a new file under umask 077 is $(stat -c %a new.nii)"

# ---- 10. a FIFO as input: refused at once (it used to hang forever)
mkfifo in.nii
refused "info FIFO" timeout 20 "$BVOX" info in.nii
grep -q "FIFO" err.txt || fail "the message does not say FIFO"

# ---- 5. killed in the middle of a write: no temporary file left. The
# model is large enough that the write takes a while; the signal is sent
# once the temporary file exists. At least one kill must land mid-write.
# (Not SIGINT: a shell starts background jobs with SIGINT ignored, and bvox
# leaves an ignored signal alone; the unit tests of temp_files cover it.)
landed=0
for sig in TERM HUP; do
    mkdir "k$sig"
    "$BVOX" shape sphere r=250 --dims 600,600,600 -o "k$sig/big.nii.gz" >/dev/null 2>&1 &
    pid=$!
    n=0
    while [ -z "$(ls -A "k$sig")" ] && [ $n -lt 600 ]; do sleep 0.05; n=$((n + 1)); done
    kill -s "$sig" "$pid" 2>/dev/null || true
    set +e
    wait "$pid"
    rc=$?
    set -e
    # never a temporary; the output either absent (killed mid-write) or
    # complete (the signal came after the rename)
    left=$(ls -A "k$sig")
    case $left in '' | big.nii.gz) ;; *) fail "SIG$sig left: $left" ;; esac
    [ -z "$left" ] || "$BVOX" info "k$sig/big.nii.gz" >/dev/null || fail "SIG$sig: a partial output"
    [ "$rc" -gt 128 ] && [ -z "$left" ] && landed=$((landed + 1))
    printf 'SIG%-4s mid-write                  exit %s, left: %s\n' "$sig" "$rc" "$(ls -A "k$sig" | tr '\n' ' ')"
done
[ "$landed" -gt 0 ] || fail "no signal landed in the middle of a write"
echo "output_safety: all passed"
