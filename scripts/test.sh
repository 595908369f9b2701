#!/bin/sh
# test.sh — the whole test suite, as the README's second command runs it:
#  1. release build in build/ and every CTest test there;
#  2. ASan + UBSan build in build-asan/ (-DBVOX_SANITIZE=ON), every test again;
#  3. ThreadSanitizer build in build-tsan/ (-DBVOX_TSAN=ON) of the library and
#     only the tests that run threads or processes at once: the thread stress
#     test (tests/unit/test_threads.c), the concurrent folder writers
#     (test_dir_sink.c) and the signal clean-up (test_temp_files.c);
#  4. fuzz/run_fuzz.sh: each libFuzzer target for BVOX_FUZZ_SECONDS (default
#     20) seconds on a clang ASan+UBSan build in build-fuzz/.
# Stops at the first failing step and exits non-zero.
# Environment: BVOX_JOBS (parallel jobs, default: CPU count),
# BVOX_FUZZ_SECONDS (0 skips the fuzzing step), BVOX_BUILD_DIR,
# BVOX_ASAN_DIR, BVOX_TSAN_DIR and BVOX_FUZZ_BUILD (other build folders than
# the defaults).
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
jobs=${BVOX_JOBS:-$(nproc 2>/dev/null || echo 2)}
fuzz_secs=${BVOX_FUZZ_SECONDS:-20}
build=${BVOX_BUILD_DIR:-build}
asan=${BVOX_ASAN_DIR:-build-asan}
tsan=${BVOX_TSAN_DIR:-build-tsan}
case $fuzz_secs in '' | *[!0-9]*) echo "BVOX_FUZZ_SECONDS must be a number" >&2; exit 2 ;; esac

step() { printf '\n==== %s\n' "$*"; }

# The options are given explicitly so that a folder configured otherwise
# before (say with BVOX_FUZZ=ON) still gets the build this step means.
step "release build ($build/)"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DBVOX_SANITIZE=OFF -DBVOX_FUZZ=OFF
cmake --build "$build" -j"$jobs"
step "release tests"
ctest --test-dir "$build" -j"$jobs" --output-on-failure

step "ASan + UBSan build ($asan/)"
cmake -S . -B "$asan" -DCMAKE_BUILD_TYPE=Debug -DBVOX_SANITIZE=ON -DBVOX_FUZZ=OFF
cmake --build "$asan" -j"$jobs"
step "ASan + UBSan tests"
ctest --test-dir "$asan" -j"$jobs" --output-on-failure

# Only what the stress test needs: a whole TSan build would double the time.
step "ThreadSanitizer build of the thread stress test ($tsan/)"
cmake -S . -B "$tsan" -DCMAKE_BUILD_TYPE=Debug -DBVOX_TSAN=ON -DBVOX_SANITIZE=OFF -DBVOX_FUZZ=OFF \
    -DBVOX_BUILD_BENCH=OFF -DBVOX_BUILD_VIEWER=OFF
cmake --build "$tsan" -j"$jobs" --target test_threads test_dir_sink test_temp_files
step "ThreadSanitizer: thread stress test, concurrent writers, signals"
ctest --test-dir "$tsan" -R '^(threads|dir_sink|temp_files)\.' --output-on-failure

if [ "$fuzz_secs" -gt 0 ]; then
    step "fuzzing, ${fuzz_secs}s per target (${BVOX_FUZZ_BUILD:-build-fuzz}/)"
    ./fuzz/run_fuzz.sh "$fuzz_secs"
fi

step "all tests passed"
