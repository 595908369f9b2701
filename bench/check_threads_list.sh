#!/bin/sh
# check_threads_list.sh BENCH — the CTest smoke run of --threads-list: BENCH
# --quick --threads-list 1,3 must succeed and print lines for both counts
# (key "threads", with or without a space after the colon); a bad list must
# be refused with exit status 2.
set -u
exe=$1
out=$("$exe" --quick --threads-list 1,3 2>/dev/null) || { echo "FAIL: $exe exited $?"; exit 1; }
for t in 1 3; do
    printf '%s\n' "$out" | grep -Eq "\"threads\": ?$t[,}]" || { echo "FAIL: no line with threads $t"; exit 1; }
done
"$exe" --quick --threads-list 1,x >/dev/null 2>&1
rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL: a bad list gave exit status $rc, not 2"; exit 1; }
echo ok
