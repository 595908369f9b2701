#!/bin/sh
# run_fuzz.sh SECONDS — fuzz every reader with libFuzzer for SECONDS each.
# Configures a clang build with BVOX_FUZZ=ON and ASan+UBSan in build-fuzz/,
# runs each fuzz_<name>_libfuzzer on a scratch copy of fuzz/corpus/<name>/
# (the checked-in corpus is never modified), and fails if any target finds a
# crash, leak, timeout or out-of-memory input. Those inputs are saved to
# fuzz/crashes/<name>-crash-<hash> for inspection: reproduce one with
# build-fuzz/fuzz/fuzz_<name> FILE, fix the bug, then add the file to
# fuzz/corpus/<name>/ so CTest replays it forever.
set -eu

secs=${1:-20}
case $secs in
    '' | *[!0-9]*) echo "usage: $0 SECONDS" >&2; exit 2 ;;
esac
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BVOX_FUZZ_BUILD:-$root/build-fuzz}
crashes=$root/fuzz/crashes
jobs=$(nproc 2>/dev/null || echo 2)

command -v clang >/dev/null || { echo "run_fuzz.sh: clang is needed (scripts/install-deps.sh)" >&2; exit 1; }

CC=clang cmake -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DBVOX_FUZZ=ON -DBVOX_SANITIZE=ON -DBVOX_BUILD_BENCH=OFF >/dev/null

targets=""
for src in "$root"/fuzz/fuzz_*.c; do
    [ -e "$src" ] || continue
    name=$(basename "$src" .c)
    targets="$targets ${name#fuzz_}"
done
if [ -z "$targets" ]; then
    echo "run_fuzz.sh: no fuzz/fuzz_*.c targets" >&2
    exit 1
fi
set --
for t in $targets; do set -- "$@" --target "fuzz_${t}_libfuzzer"; done
cmake --build "$build" -j"$jobs" "$@"

work=$(mktemp -d "${TMPDIR:-/tmp}/bvox-fuzz.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM
mkdir -p "$crashes"

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
failed=""
for t in $targets; do
    exe=$build/fuzz/fuzz_${t}_libfuzzer
    corpus=$work/corpus-$t
    mkdir -p "$corpus"
    # A scratch copy: new inputs libFuzzer finds go there, not into git.
    if [ -d "$root/fuzz/corpus/$t" ]; then
        find "$root/fuzz/corpus/$t" -type f ! -name '.*' -exec cp {} "$corpus/" \;
    fi
    dict=""
    [ -f "$root/fuzz/$t.dict" ] && dict="-dict=$root/fuzz/$t.dict"
    echo "== fuzz $t for ${secs}s ($(ls "$corpus" | wc -l) seed inputs)"
    # -timeout: an input taking over 20 s is a hang; -rss_limit_mb: a reader
    # that ignores the memory budget is a bug.
    if ! "$exe" "$corpus" $dict -max_total_time="$secs" -rss_limit_mb=2048 -timeout=20 \
        -print_final_stats=1 -artifact_prefix="$crashes/$t-" \
        >"$work/$t.log" 2>&1; then
        failed="$failed $t"
        tail -n 60 "$work/$t.log" >&2
        echo "!! fuzz $t FAILED; inputs saved under $crashes/" >&2
    else
        grep -E "^(stat::number_of_executed_units|Done)" "$work/$t.log" || true
    fi
done
rmdir "$crashes" 2>/dev/null || true

if [ -n "$failed" ]; then
    echo "run_fuzz.sh: crashes found in:$failed" >&2
    exit 1
fi
echo "run_fuzz.sh: no crashes in:$targets"
