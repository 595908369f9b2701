#!/bin/sh
# zarr_python_exact.sh — voxel-exact agreement with Debian's python3-zarr:
# arrays written by zarr-python (uint8, uint16, float32; zlib and Blosc;
# chunks 37 x 100 x 65, which divide no side) are read by bvox and written
# back as raw bytes, compared voxel by voxel with numpy's (a != 0) and
# (a >= T); bvox's pyramid is read by zarr-python: every level's shape,
# dtype, chunks and scale, and each level equal to numpy's OR over 2x2x2
# blocks of the level below; a level is read back by bvox with --level.
# Usage: sh zarr_python_exact.sh BVOX DATADIR
set -eu
BVOX=$1
PY=/usr/bin/python3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

. "$(dirname "$0")/lib/common.sh"
need_python_zarr

# 1. python -> bvox, exactly. Shape (z, y, x) = (131, 203, 80); chunks
#    (z, y, x) = (65, 100, 37), so x 37, y 100, z 65 in bvox's order.
$PY - "$tmp" <<'PY'
import sys, zarr, numcodecs, numpy as np
d = sys.argv[1]
rs = np.random.RandomState(7)
shape = (131, 203, 80)
codecs = {"zlib": numcodecs.Zlib(level=4),
          "blosc": numcodecs.Blosc(cname="lz4", shuffle=numcodecs.Blosc.BITSHUFFLE)}
for dt in ("u1", "<u2", "<f4"):
    if dt == "<f4":
        a = rs.standard_normal(shape).astype(dt)
        a[rs.random_sample(shape) < 0.3] = 0
    else:
        a = (rs.randint(0, 4, shape) * rs.randint(0, 3, shape)).astype(dt)
    for name, codec in codecs.items():
        z = zarr.open(f"{d}/{dt[-2:]}_{name}.zarr", mode="w", shape=shape, chunks=(65, 100, 37),
                      dtype=dt, compressor=codec, fill_value=0)
        z[:] = a
    np.save(f"{d}/{dt[-2:]}.npy", a)
PY
for dt in u1 u2 f4; do
    for codec in zlib blosc; do
        "$BVOX" convert "$tmp/${dt}_$codec.zarr" "$tmp/${dt}_$codec.raw" \
            || fail "bvox cannot read zarr-python's $dt $codec array"
    done
    # and a threshold (a float one for f4)
    "$BVOX" convert "$tmp/${dt}_zlib.zarr" "$tmp/${dt}_t.raw" --threshold 0.5
done
$PY - "$tmp" <<'PY' || fail "bvox's voxels differ from zarr-python's"
import sys, numpy as np
d = sys.argv[1]
for dt in ("u1", "u2", "f4"):
    a = np.load(f"{d}/{dt}.npy")
    for codec in ("zlib", "blosc"):
        got = np.fromfile(f"{d}/{dt}_{codec}.raw", np.uint8).reshape(a.shape)  # x fastest
        assert np.array_equal(got, (a != 0).astype(np.uint8)), (dt, codec)
    got = np.fromfile(f"{d}/{dt}_t.raw", np.uint8).reshape(a.shape)
    assert np.array_equal(got, (a >= 0.5).astype(np.uint8)), (dt, "threshold")
PY

# 2. bvox's pyramid read by zarr-python.
"$BVOX" shape sphere r=40 at=50,45,60 --dims 101,93,130 -o "$tmp/s.nii" >/dev/null
"$BVOX" convert "$tmp/s.nii" "$tmp/p.zarr" --chunks 37,40,65 --voxel-size 0.5,0.25,2 --unit mm \
    --compressor blosc
$PY - "$tmp/p.zarr" "$tmp/level1.raw" <<'PY' || fail "python3-zarr disagrees with bvox's pyramid"
import sys, zarr, numpy as np
g = zarr.open_group(sys.argv[1], mode="r")
ms = g.attrs["multiscales"][0]
ds = ms["datasets"]
# (x, y, z) 101x93x130 -> 51x47x65 -> 26x24x33 (26 under 37: the last)
assert [d["path"] for d in ds] == ["0", "1", "2"], ds
assert all(ax["unit"] == "millimeter" for ax in ms["axes"])
prev = None
for l, d in enumerate(ds):
    a = g[d["path"]]
    f = 2 ** l
    scale = d["coordinateTransformations"][0]
    assert scale["type"] == "scale" and scale["scale"] == [2 * f, 0.25 * f, 0.5 * f], scale
    if l:
        tr = d["coordinateTransformations"][1]
        assert tr["type"] == "translation"
        assert tr["translation"] == [2 * (f - 1) / 2, 0.25 * (f - 1) / 2, 0.5 * (f - 1) / 2], tr
    assert a.dtype == np.uint8
    v = a[:]
    if prev is None:
        assert a.shape == (130, 93, 101) and a.chunks == (65, 40, 37), (a.shape, a.chunks)
    else:
        want_shape = tuple((s + 1) // 2 for s in prev.shape)
        assert a.shape == want_shape, (a.shape, want_shape)
        p = np.zeros(tuple(2 * s for s in want_shape), np.uint8)
        p[: prev.shape[0], : prev.shape[1], : prev.shape[2]] = prev
        want = p.reshape(want_shape[0], 2, want_shape[1], 2, want_shape[2], 2).max(axis=(1, 3, 5))
        assert np.array_equal(v, want), l
        assert v.sum() > 0
        if l == 1:
            v.tofile(sys.argv[2])
    prev = v
PY
"$BVOX" convert "$tmp/p.zarr" "$tmp/l1.raw" --level 1
cmp -s "$tmp/l1.raw" "$tmp/level1.raw" || fail "bvox's --level 1 differs from zarr-python's"
"$BVOX" info "$tmp/p.zarr" --level 1 | grep -q "voxel size: *1 x 0.5 x 4 mm" \
    || fail "level 1 voxel size: $("$BVOX" info "$tmp/p.zarr" --level 1)"
if "$BVOX" info "$tmp/p.zarr" --level 3 2>"$tmp/err"; then fail "level 3 accepted"; fi
grep -q "no resolution level 3" "$tmp/err" || fail "level 3 message: $(cat "$tmp/err")"
echo ok
