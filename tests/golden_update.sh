#!/bin/sh
# golden_update.sh — the update mode of the golden tests can never pass:
# with BVOX_UPDATE_GOLDEN=1 (goldens redirected to a scratch folder by
# BVOX_GOLDEN_DIR, so tests/data is not touched) the unit test of the
# paper's pictures and the viewer's end-to-end test must write their goldens
# and exit non-zero with a message saying so; run again without the variable,
# they pass against what they just wrote (and the viewer's rewritten goldens
# are byte for byte the committed ones: the screenshots are deterministic).
# Usage: sh golden_update.sh TEST_RENDER_PICTURES BVOX DATADIR
set -eu
PICTURES=$1
BVOX=$2
DATA=$3
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

# unit test: picture 1
mkdir -p "$tmp/g/golden"
set +e
BVOX_UPDATE_GOLDEN=1 BVOX_GOLDEN_DIR="$tmp/g" "$PICTURES" picture1_golden >"$tmp/u.out" 2>&1
rc=$?
set -e
[ $rc -ne 0 ] || fail "the picture test passed in update mode"
grep -q "golden $tmp/g/golden/picture1.png updated; inspect and commit" "$tmp/u.out" ||
    fail "no update message: $(cat "$tmp/u.out")"
[ -s "$tmp/g/golden/picture1.png" ] || fail "update mode wrote no golden"
BVOX_GOLDEN_DIR="$tmp/g" "$PICTURES" picture1_golden >"$tmp/c.out" 2>&1 ||
    fail "the picture test fails against the golden it wrote: $(cat "$tmp/c.out")"
# a wrong golden fails (the comparison is real): picture 2's golden as picture 1's
cp "$DATA/golden/picture2.png" "$tmp/g/golden/picture1.png"
if BVOX_GOLDEN_DIR="$tmp/g" "$PICTURES" picture1_golden >"$tmp/w.out" 2>&1; then
    fail "the picture test passed against a wrong golden"
fi
# BVOX_UPDATE_GOLDEN=0 is not the update mode
BVOX_UPDATE_GOLDEN=0 "$PICTURES" picture1_golden >"$tmp/z.out" 2>&1 ||
    fail "BVOX_UPDATE_GOLDEN=0 must compare: $(cat "$tmp/z.out")"
echo "unit goldens: update mode fails, compare mode compares"

# the viewer's screenshots (needs the viewer and xvfb-run, as view.sh)
[ "${BVOX_GOLDEN_NO_VIEW:-0}" = 1 ] && exit 0
if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "SKIP: xvfb-run is missing (the viewer part)"
    exit 77
fi
mkdir -p "$tmp/v/view"
set +e
BVOX_UPDATE_GOLDEN=1 BVOX_GOLDEN_DIR="$tmp/v" sh "$here/cli/view.sh" "$BVOX" "$DATA" >"$tmp/v.out" 2>&1
rc=$?
set -e
[ $rc -ne 0 ] || fail "view.sh passed in update mode"
grep -q "goldens updated (BVOX_UPDATE_GOLDEN): this run fails on purpose" "$tmp/v.out" ||
    fail "view.sh: no update message: $(tail -5 "$tmp/v.out")"
for k in s1 s2 s3 s5; do
    grep -q "golden $tmp/v/view/$k.png updated; inspect and commit" "$tmp/v.out" || fail "view.sh: $k not reported"
    cmp -s "$tmp/v/view/$k.png" "$DATA/view/$k.png" || fail "view.sh: the rewritten $k.png differs from the committed golden"
done
echo "view goldens: update mode fails, rewrites them identically"
