#!/bin/sh
# zarr_python.sh — OME-Zarr written by bvox is read by Debian's python3-zarr
# with the right shape (z, y, x), dtype, chunks, voxels and multiscales scale
# and unit; arrays written by python3-zarr (int16 with zlib, big-endian int16
# with gzip and a fill value for chunks never written, nested chunk keys) are
# read by bvox with a threshold, counts checked against numpy's; Blosc
# (bit-shuffle) both ways. The reference counts come from numpy.
# Usage: sh zarr_python.sh BVOX DATADIR
set -eu
BVOX=$1
PY=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
count() { "$BVOX" info "$@" --json | $PY -c 'import json,sys; print(json.load(sys.stdin)["count"])'; }

. "$(dirname "$0")/lib/common.sh"
need_python_zarr

# 1. bvox -> python: an off-centre sphere in an awkward grid, odd chunks.
"$BVOX" shape sphere r=20 at=30,25,40 --dims 61,53,100 -o "$tmp/s.nii" >/dev/null
"$BVOX" convert "$tmp/s.nii" "$tmp/s.zarr" --chunks 37,100,65 --voxel-size 0.5,0.25,2 --unit um
want=$(count "$tmp/s.nii")
$PY - "$tmp/s.zarr" "$want" <<'PY' || fail "python3-zarr disagrees with bvox's zarr"
import sys, zarr, numpy as np
path, want = sys.argv[1], int(sys.argv[2])
g = zarr.open_group(path, mode="r")
a = g["0"]
assert a.shape == (100, 53, 61), a.shape          # z, y, x
assert a.dtype == np.uint8, a.dtype
assert a.chunks == (65, 53, 37), a.chunks         # capped by the dims
v = a[:]
assert set(np.unique(v)) <= {0, 1}
assert int(v.sum()) == want, (int(v.sum()), want)
# the centre (x=30, y=25, z=40) is inside, a corner outside
assert v[40, 25, 30] == 1 and v[0, 0, 0] == 0
# the sphere spans z 20..60 (centre 40, r 20 voxels): not transposed
zs = np.nonzero(v.any(axis=(1, 2)))[0]
assert zs.min() >= 19 and zs.max() <= 61, (zs.min(), zs.max())
ms = g.attrs["multiscales"][0]
assert [ax["name"] for ax in ms["axes"]] == ["z", "y", "x"]
assert all(ax["type"] == "space" and ax["unit"] == "micrometer" for ax in ms["axes"])
ds = ms["datasets"][0]
assert ds["path"] == "0"
assert ds["coordinateTransformations"][0]["scale"] == [2, 0.25, 0.5], ds
PY

# 2. python -> bvox: int16 zlib, threshold.
$PY - "$tmp" >"$tmp/expect" <<'PY'
import sys, zarr, numcodecs, numpy as np
d = sys.argv[1]
x = np.random.RandomState(3).randint(-500, 1000, size=(70, 45, 33)).astype("<i2")
z = zarr.open(d + "/a.zarr", mode="w", shape=x.shape, chunks=(16, 20, 11), dtype="<i2",
              compressor=numcodecs.Zlib(level=3))
z[:] = x
print((x >= 300).sum())
# big-endian, gzip, only the first 20 slices written: the rest is fill 400
z = zarr.open(d + "/b.zarr", mode="w", shape=x.shape, chunks=(10, 45, 33), dtype=">i2",
              compressor=numcodecs.GZip(), fill_value=400)
z[:20] = x[:20]
y = np.full(x.shape, 400, "<i2"); y[:20] = x[:20]
print((y >= 300).sum())
# nested chunk keys ("0/0/0")
z = zarr.open(zarr.NestedDirectoryStore(d + "/c.zarr"), mode="w", shape=x.shape,
              chunks=(32, 32, 32), dtype="<u2", compressor=numcodecs.Zlib())
z[:] = np.abs(x).astype("<u2")
print((np.abs(x) >= 300).sum())
z = zarr.open(d + "/d.zarr", mode="w", shape=x.shape, chunks=(32, 32, 32), dtype="<i2",
              compressor=numcodecs.Blosc(cname="lz4", shuffle=numcodecs.Blosc.BITSHUFFLE))
z[:] = x
print((x >= 300).sum())
PY
[ "$(count "$tmp/a.zarr" --threshold 300)" = "$(sed -n 1p "$tmp/expect")" ] || fail "int16 zlib count"
[ "$(count "$tmp/b.zarr" --threshold 300)" = "$(sed -n 2p "$tmp/expect")" ] || fail "gzip fill count"
[ "$(count "$tmp/c.zarr" --threshold 300)" = "$(sed -n 3p "$tmp/expect")" ] || fail "nested count"
"$BVOX" info "$tmp/a.zarr" | grep -q "dimensions: *33 x 45 x 70 voxels" || fail "a.zarr dims"
[ "$(count "$tmp/d.zarr" --threshold 300)" = "$(sed -n 4p "$tmp/expect")" ] || fail "blosc count"
# bvox's Blosc output (bit-shuffled 0/1 bytes) read back by python3-zarr
"$BVOX" convert "$tmp/a.zarr" "$tmp/e.zarr" --threshold 300 --compressor blosc --chunks 33,45,32
$PY - "$tmp/e.zarr" "$(sed -n 1p "$tmp/expect")" <<'PY' || fail "python3-zarr on bvox's blosc"
import sys, zarr
a = zarr.open_group(sys.argv[1], mode="r")["0"]
assert a.compressor.codec_id == "blosc" and a.compressor.shuffle == 2, a.compressor
assert a.shape == (70, 45, 33) and int(a[:].sum()) == int(sys.argv[2])
PY

# 3. a chunk removed from bvox's output (fill 0 in the metadata) reads as 0s;
#    a corrupt chunk is an error naming it.
"$BVOX" convert "$tmp/a.zarr" "$tmp/r.zarr" --threshold 300 --chunks 11,20,16
cp "$tmp/r.zarr/0/0.0.0" "$tmp/saved"
printf 'junk' >"$tmp/r.zarr/0/0.0.0"
if "$BVOX" info "$tmp/r.zarr" 2>"$tmp/err"; then fail "corrupt chunk accepted"; fi
grep -q "chunk 0.0.0" "$tmp/err" || fail "corrupt chunk message: $(cat "$tmp/err")"
rm "$tmp/r.zarr/0/0.0.0"
full=$(count "$tmp/a.zarr" --threshold 300)
cp "$tmp/saved" "$tmp/r.zarr/0/0.0.0"
[ "$(count "$tmp/r.zarr")" = "$full" ] || fail "re-written chunks"
echo ok
