#!/bin/sh
# check_threads.sh — issue 17's rule "no operation gets slower with more
# threads": runs every benchmark at two thread counts (--threads-list A,B, by
# default 2,16) and prints, per case and per timed key, the time at each
# count and the ratio B/A; a ratio above 1 + TOL (default 0.10) is marked
# SLOWER, and the exit status is 1 if any case is.
#
#   bench/check_threads.sh [BUILD_DIR]            (default: build)
#   ROUNDS=3 COUNTS=2,16 TOL=0.10 ARGS=--quick BENCHES="ops manip" bench/check_threads.sh
#
# ARGS (default --quick) go to every benchmark, ARGS_<bench> (e.g.
# ARGS_ops="--sizes 512 --no-ref") to that one instead. Each round runs the counts in
# alternating order (A,B then B,A) so that a load that drifts during a run
# does not favour one count; a case's ratio is the median over ROUNDS rounds
# (default 3) of the ratio within one run. Lines are matched by their
# non-timing keys (strings, booleans, integers other than "threads" and the
# reference's, which only the first count's lines carry); the
# timed keys are "ms", "median_ms" and every "*_ms" except the reference's
# (ref_*, ms_1thread, memcpy_ms: measured once or a baseline). Times below
# FLOOR ms (default 0.05) at both counts are listed but not judged: a few
# microseconds of timer and scheduler noise move them by more than 10 %.
set -u
build=${1:-build}
counts=${COUNTS:-2,16}
rounds=${ROUNDS:-3}
args=${ARGS:---quick}
benches=${BENCHES:-"ops manip render mesh io arrays binarize contours labels recon"}
a=${counts%,*}
b=${counts#*,}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/bvox_threads.XXXXXX") || exit 2
trap 'rm -rf "$tmp"' EXIT INT TERM
for bench in $benches; do
    exe=$build/bench/bench_$bench
    [ -x "$exe" ] || { echo "check_threads: $exe is missing (build first)" >&2; exit 2; }
    eval "bargs=\${ARGS_$bench:-\$args}"
    r=1
    while [ "$r" -le "$rounds" ]; do
        if [ $((r % 2)) -eq 1 ]; then list=$a,$b; else list=$b,$a; fi
        # shellcheck disable=SC2086 # ARGS is a list of words
        if ! "$exe" $bargs --threads-list "$list" >"$tmp/$bench.$r" 2>"$tmp/$bench.$r.err"; then
            echo "check_threads: $exe $bargs --threads-list $list failed:" >&2
            tail -3 "$tmp/$bench.$r.err" >&2
            exit 2
        fi
        r=$((r + 1))
    done
done
python3 - "$tmp" "$a" "$b" "${TOL:-0.10}" "${FLOOR:-0.05}" $benches <<'EOF'
import json, os, statistics, sys

tmp, ta, tb, tol, floor = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
benches = sys.argv[6:]
skip = {"ref_ms", "ms_1thread", "memcpy_ms"}

def timed(k):
    return (k == "ms" or k.endswith("_ms")) and k not in skip and not k.startswith("ref_")

volatile = ("ref", "agree", "speedup", "ratio", "mismatch")

def ident(d):
    return tuple(sorted((k, v) for k, v in d.items()
                        if k != "threads" and not timed(k) and not k.startswith(volatile)
                        and isinstance(v, (str, int, bool))
                        and not isinstance(v, float)))

slower = judged = 0
print(f"{'bench':8} {'case':58} {'key':14} {ta:>3} thr ms {tb:>3} thr ms  ratio")
for bench in benches:
    # ratios[(ident, key)] = [per-round ratio], times for display from round 1
    ratios, shown = {}, {}
    r = 1
    while os.path.exists(f"{tmp}/{bench}.{r}"):
        lines = {}
        for line in open(f"{tmp}/{bench}.{r}"):
            line = line.strip()
            if not line.startswith("{"):
                continue
            d = json.loads(line)
            t = d.get("threads")
            if t not in (ta, tb):
                continue
            lines.setdefault(ident(d), {})[t] = d
        for idt, by in lines.items():
            if ta not in by or tb not in by:
                continue
            for k, v in by[ta].items():
                w = by[tb].get(k)
                if not timed(k) or not isinstance(v, (int, float)) or not isinstance(w, (int, float)) or v <= 0:
                    continue
                ratios.setdefault((idt, k), []).append(w / v)
                shown.setdefault((idt, k), []).append((v, w))
        r += 1
    for (idt, k), rs in ratios.items():
        d = dict(idt)
        name = ",".join(f"{x}={y}" for x, y in idt if x not in ("bench", "runs"))[:58]
        va = statistics.median(p[0] for p in shown[(idt, k)])
        vb = statistics.median(p[1] for p in shown[(idt, k)])
        ratio = statistics.median(rs)
        mark = ""
        if va < floor and vb < floor:
            mark = "(below floor)"
        else:
            judged += 1
            if ratio > 1 + tol:
                slower += 1
                mark = "SLOWER"
        print(f"{bench:8} {name:58} {k:14} {va:10.3f} {vb:10.3f}  {ratio:5.2f} {mark}")
print(f"\n{judged} cases judged, {slower} more than {tol:.0%} slower at {tb} threads than at {ta}")
sys.exit(1 if slower else 0)
EOF
