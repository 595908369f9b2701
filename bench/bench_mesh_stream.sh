#!/bin/sh
# bench_mesh_stream.sh — `bvox mesh` of a .zarr in memory against by slabs
# (written as it is made, docs/SCALE.md): an N^3 specimen (scattered voxels,
# one in 400, and a ball of radius 0.39 N holding the same noise as holes; 64^3
# chunks), meshed whole and under --max-memory budgets. One JSON line per run:
# seconds, peak resident memory (GNU time's %M), vertices and triangles.
# Usage: sh bench/bench_mesh_stream.sh BVOX [N] [DIR]   (N 512, DIR /tmp)
set -eu
BVOX=$1 N=${2:-512} DIR=${3:-/tmp}
tmp=$(mktemp -d "$DIR/bvox-mesh-stream.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
/usr/bin/python3 - "$tmp/n.raw" "$N" <<'PY'
import sys
import numpy as np
path, n = sys.argv[1], int(sys.argv[2])
rng = np.random.default_rng(3)
with open(path, "wb") as f:
    for z in range(n):  # slice by slice: z, y, x
        s = (rng.random((n, n), dtype=np.float32) < 1 / 400).astype(np.uint8)
        y, x = np.ogrid[:n, :n]
        r = 0.39 * n
        s[(x - n / 2) ** 2 + (y - n / 2) ** 2 + (z - n / 2) ** 2 < r * r] ^= 1
        s.tofile(f)
PY
"$BVOX" convert "$tmp/n.raw" "$tmp/n.zarr" --dims "$N,$N,$N" --type u8 --chunks 64,64,64
rm "$tmp/n.raw"
run() { # NAME ARGS...
    name=$1
    shift
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$BVOX" mesh "$tmp/n.zarr" -o "$tmp/out.ply" "$@" \
        > "$tmp/out.txt"
    read -r s kb < "$tmp/time"
    nv=$(sed -E 's/.*: ([0-9]+) vertices.*/\1/' "$tmp/out.txt")
    nt=$(sed -E 's/.* ([0-9]+) triangles.*/\1/' "$tmp/out.txt")
    echo "{\"bench\": \"mesh_stream\", \"n\": $N, \"run\": \"$name\", \"seconds\": $s, \"peak_rss_mib\": $((kb / 1024)), \"vertices\": $nv, \"triangles\": $nt, \"bytes\": $(wc -c < "$tmp/out.ply")}"
    rm -f "$tmp/out.ply"
}
run "in memory"
# budgets: just under the in-memory path's (the volume's words times 6),
# then down to 1.5 rows of chunks' samples (the reader's own floor: one row)
words=$((N * N * ((N + 63) / 64) * 8)) row=$((N * N * 64 / 1048576))
for m in $((words * 6 / 1048576 - 1))M $((row * 4))M $((row * 2))M $((row * 3 / 2))M; do
    run "by slabs, --max-memory $m" --max-memory "$m"
done
