#!/bin/sh
# help.sh — the command's front door: --version names the version and the
# SIMD level, --help lists every command, every command's --help exits 0,
# and wrong command lines exit 2 with one "bvox: ..." line.
# Usage: sh help.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# --version: "bvox 0.1.0 (simd: LEVEL, ...)"; BVOX_SIMD=generic must show.
"$BVOX" --version >"$tmp/v" || fail "--version exited $?"
grep -Eq '^bvox 0\.1\.0 \(simd: (generic|avx2|avx512), threads: [0-9]+\)$' "$tmp/v" ||
    fail "--version printed: $(cat "$tmp/v")"
BVOX_SIMD=generic "$BVOX" --version | grep -q 'simd: generic' || fail "BVOX_SIMD=generic not shown"

# --help lists the commands (two-space indent under "Commands:").
"$BVOX" --help >"$tmp/help" || fail "--help exited $?"
cmds=$(sed -n '/^Commands:/,/^$/s/^  \([a-z][a-z-]*\) .*/\1/p' "$tmp/help")
for c in info convert demo; do
    echo "$cmds" | grep -qx "$c" || fail "--help does not list $c"
done
for c in $cmds; do
    "$BVOX" "$c" --help >"$tmp/h.$c" 2>"$tmp/e.$c" || fail "$c --help exited $?"
    grep -q "^Usage: bvox $c" "$tmp/h.$c" || fail "$c --help has no usage line"
    [ ! -s "$tmp/e.$c" ] || fail "$c --help wrote to stderr"
    "$BVOX" help "$c" | cmp -s - "$tmp/h.$c" || fail "'bvox help $c' differs from '$c --help'"
done

# Usage errors: exit 2, nothing on stdout, exactly one "bvox: " line.
usage_error() {
    set +e
    "$BVOX" "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    set -e
    [ "$rc" -eq 2 ] || fail "'$*' exited $rc, expected 2"
    [ ! -s "$tmp/out" ] || fail "'$*' wrote to stdout"
    [ "$(wc -l <"$tmp/err")" -eq 1 ] || fail "'$*' stderr is not one line: $(cat "$tmp/err")"
    grep -q '^bvox: ' "$tmp/err" || fail "'$*' stderr: $(cat "$tmp/err")"
}
set +e
"$BVOX" >/dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] || fail "no arguments exited $rc, expected 2"
usage_error frobnicate
usage_error --frobnicate
usage_error info
usage_error info a.nii b.nii
usage_error info a.nii --frobnicate
usage_error info a.nii --threshold
usage_error info a.nii --threshold abc
usage_error info a.nii --threshold inf
usage_error info a.nii --range 5
usage_error info a.nii --range 9:3
usage_error info a.nii --otsu --label 3
usage_error info a.raw --dims 0,4,4 --type u8
usage_error info a.raw --dims 4,4 --type u8
usage_error info a.raw --dims 4,4,70000 --type u8
usage_error info a.raw --dims 4,4,4 --type u7
usage_error info a.raw --dims 4,4,4 --endian middle
usage_error info a.raw --voxel-size 1,0,1
usage_error info a.nii --max-memory lots
usage_error info a.nii --threads 0
usage_error convert a.nii
usage_error convert a.nii b.nii c.nii
usage_error convert a.nii b.unknownext
usage_error demo extra
usage_error demo -o
usage_error help frobnicate
echo "ok"
