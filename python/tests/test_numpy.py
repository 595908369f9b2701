"""NumPy in and out: round trips in both memory orders, every dtype and read
mode against NumPy's own comparison, the zero-copy words view (bits checked
against np.packbits), geometry, and bad arrays / closed volumes."""
import numpy as np
import pytest

import bvox
from conftest import SIZES, random_mask


@pytest.mark.parametrize("shape", SIZES)
@pytest.mark.parametrize("order", ["C", "F"])
def test_round_trip(rng, shape, order):
    a = np.asarray(random_mask(rng, shape), order=order)
    v = bvox.Volume.from_numpy(a)
    v.check()
    assert v.shape == shape
    assert v.count() == int(a.sum())
    for out_order in ("C", "F"):
        b = v.to_numpy(out_order)
        assert b.dtype == np.bool_ and b.shape == shape
        assert np.array_equal(a, b)
    # voxel access agrees with the array's [x, y, z] indexing
    x, y, z = (int(rng.integers(0, n)) for n in shape)
    assert v[x, y, z] == bool(a[x, y, z])


def test_non_contiguous_is_copied(rng):
    big = random_mask(rng, (10, 12, 70))
    a = big[::2, 1::3, ::-1]
    assert not a.flags.c_contiguous and not a.flags.f_contiguous
    assert np.array_equal(bvox.Volume.from_numpy(a).to_numpy(), a)


@pytest.mark.parametrize("dtype", [np.uint8, np.int8, np.uint16, np.int16, np.uint32, np.int32,
                                   np.uint64, np.int64, np.float32, np.float64])
def test_dtypes_and_modes(rng, dtype):
    a = rng.integers(-3, 12, size=(6, 5, 67)).astype(dtype)
    cases = [({}, a != 0), ({"threshold": 5}, a >= 5), ({"range": (2, 7)}, (a >= 2) & (a <= 7)),
             ({"label": 4}, a == 4), ({"nonzero": True}, a != 0)]
    for kw, want in cases:
        for arr in (a, np.asfortranarray(a)):
            v = bvox.Volume.from_numpy(arr, **kw)
            assert np.array_equal(v.to_numpy(), want), kw


def test_big_endian_samples(rng):
    a = rng.integers(0, 1000, size=(4, 5, 66)).astype(">i2")
    assert np.array_equal(bvox.Volume.from_numpy(a, threshold=500).to_numpy(), a >= 500)


def test_otsu_splits_two_levels(rng):
    a = np.where(random_mask(rng, (8, 8, 40)), 200.0, 10.0) + rng.random((8, 8, 40))
    assert np.array_equal(bvox.Volume.from_numpy(a, otsu=True).to_numpy(), a > 100)


def test_geometry():
    v = bvox.Volume.from_numpy(np.ones((2, 3, 4), bool), spacing=(0.5, 0.25, 2), unit="mm",
                               origin=(1, -2, 3))
    assert v.spacing == (0.5, 0.25, 2.0) and v.unit == "mm" and v.origin == (1.0, -2.0, 3.0)
    assert np.allclose(v.affine, [[0.5, 0, 0, 1], [0, 0.25, 0, -2], [0, 0, 2, 3], [0, 0, 0, 1]])
    with pytest.raises(bvox.InvalidArgument, match="voxel size 0"):
        v.set_geometry(spacing=(1, 0, 1))


def _packed_words(a):
    """The words of an [x, y, z] mask, computed with NumPy: bit z % 64 of word
    z // 64 of each column, little-endian bit order."""
    nx, ny, nz = a.shape
    wpc = (nz + 63) // 64
    padded = np.zeros((nx, ny, wpc * 64), bool)
    padded[:, :, :nz] = a
    return np.packbits(padded, axis=2, bitorder="little").view("<u8").reshape(nx, ny, wpc)


@pytest.mark.parametrize("shape", SIZES)
def test_words_view(rng, shape):
    a = random_mask(rng, shape)
    v = bvox.Volume.from_numpy(a)
    w = v.words
    assert w.dtype == np.uint64 and w.shape == (shape[0], shape[1], (shape[2] + 63) // 64)
    assert not w.flags.writeable
    assert np.array_equal(w, _packed_words(a))
    # zero copy: the same memory each time, and it sees in-place edits
    assert np.shares_memory(w, v.words)
    x, y, z = shape[0] - 1, shape[1] - 1, shape[2] - 1
    v[x, y, z] = not a[x, y, z]
    assert bool((int(w[x, y, z // 64]) >> (z % 64)) & 1) == (not a[x, y, z])
    v |= bvox.Volume(shape).fill()
    assert np.array_equal(w, _packed_words(np.ones(shape, bool)))


def test_words_view_keeps_volume_alive(rng):
    a = random_mask(rng, (4, 4, 70))
    w = bvox.Volume.from_numpy(a).words  # the volume itself is not referenced any more
    import gc
    gc.collect()
    assert np.array_equal(w, _packed_words(a))


def test_close():
    v = bvox.Volume((2, 2, 2))
    w = v.words
    with pytest.raises(BufferError):
        v.close()
    del w
    import gc
    gc.collect()
    v.close()
    v.close()  # twice is harmless
    assert v.closed
    for use in (lambda: v.count(), lambda: v.to_numpy(), lambda: v.dilate(),
                lambda: v | bvox.Volume((2, 2, 2)), lambda: v.words):
        with pytest.raises(ValueError, match="closed"):
            use()
    with bvox.Volume((3, 3, 3)) as u:
        u.fill()
    assert u.closed


@pytest.mark.parametrize("bad, exc, msg", [
    (np.zeros((3, 4), bool), ValueError, "3-D"),
    (np.zeros((2, 3, 4, 1), bool), ValueError, "3-D"),
    (np.zeros((3, 0, 4), bool), ValueError, "zero dimension"),
    (np.zeros((2, 2, 2), np.complex64), TypeError, "dtype"),
    (np.zeros((2, 2, 2), np.float16), TypeError, "dtype"),
    (np.zeros((2, 2, 2), object), TypeError, "dtype"),
    (np.zeros((2, 2, 2), "U3"), TypeError, "dtype"),
])
def test_bad_arrays(bad, exc, msg):
    with pytest.raises(exc, match=msg):
        bvox.Volume.from_numpy(bad)


def test_bad_options():
    a = np.zeros((2, 2, 2), np.uint8)
    with pytest.raises(ValueError, match="at most one"):
        bvox.Volume.from_numpy(a, threshold=1, label=2)
    with pytest.raises(bvox.InvalidArgument, match="NaN") as e:
        bvox.Volume.from_numpy(a, threshold=float("nan"))
    assert e.value.status_name == "BVOX_EINVAL" and e.value.status == 1
    with pytest.raises(bvox.InvalidArgument, match="outside 1..65535"):
        bvox.Volume((65536, 1, 1))
    budget = bvox.memory_budget()
    bvox.set_memory_budget(bvox.memory_in_use() + 4096)
    try:
        with pytest.raises(bvox.TooBig):
            bvox.Volume((1000, 1000, 64))
    finally:
        bvox.set_memory_budget(budget)
    with pytest.raises(ValueError, match="conn"):
        bvox.Volume((2, 2, 2)).dilate(conn=8)


def test_from_words_and_pickle(rng):
    import pickle
    a = random_mask(rng, (5, 6, 70))
    v = bvox.Volume.from_numpy(a, spacing=(0.5, 1, 2), unit="mm", origin=(1, 2, 3))
    w = bvox.Volume.from_words(v.words, 70)
    assert w == v and np.array_equal(w.to_numpy(), a)
    p = pickle.loads(pickle.dumps(v))
    assert p == v and p.spacing == v.spacing and p.unit == "mm" and p.origin == v.origin
    bad = np.array(v.words)
    bad[1, 2, 1] |= np.uint64(1 << 20)  # z = 84 > nz
    with pytest.raises(bvox.InvalidArgument, match="beyond"):
        bvox.Volume.from_words(bad, 70)
    with pytest.raises(bvox.InvalidArgument, match="words"):
        bvox.Volume.from_words(v.words, 200)
    with pytest.raises(TypeError):
        bvox.Volume.from_words(v.words.astype(np.int64), 70)
