"""progress=callable(fraction, stage) on long calls: fractions never
decrease and end at 1; an exception raised in the callback cancels the call
(nothing returned, no file written, the library's memory back to base) and
comes out of the call."""
import gc
import os

import numpy as np
import pytest

import bvox
from bvox._lib import lib


def ball(n=96):
    x, y, z = np.ogrid[:n, :n * 3, :n]
    return (x - n / 2) ** 2 + (y - 1.5 * n) ** 2 / 4 + (z - n / 2) ** 2 < (n / 2.5) ** 2


class Stop(Exception):
    pass


def recorder(stop_at=None):
    seen = []

    def cb(fraction, stage):
        seen.append((fraction, stage))
        if stop_at is not None and len(seen) >= stop_at:
            raise Stop(stage)
    return seen, cb


CALLS = {
    "dilate": lambda v, p: v.dilate(26, progress=p),
    "erode_ball": lambda v, p: v.erode_ball(2.5, progress=p),
    "closing": lambda v, p: v.closing(6, progress=p),
    "components": lambda v, p: v.components(progress=p),
    "measure": lambda v, p: v.measure(progress=p),
    "mesh": lambda v, p: v.mesh("mc", smooth=2, progress=p),
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_fractions_and_cancel(name):
    lib.bvox_set_progress_interval(0)  # every check calls back: counts are exact
    try:
        v = bvox.Volume.from_numpy(ball())
        seen, cb = recorder()
        want = CALLS[name](v, None)
        got = CALLS[name](v, cb)
        fr = [f for f, _ in seen]
        assert len(fr) >= 2 and fr == sorted(fr) and fr[-1] == 1 and fr.count(1) == 1
        assert all(0 <= f <= 1 for f in fr) and all(s for _, s in seen)
        if isinstance(want, bvox.Volume):
            assert got == want
        del got, want
        gc.collect()
        base = lib.bvox_memory_in_use()
        for k in range(1, len(fr)):
            seen, cb = recorder(stop_at=k)
            with pytest.raises(Stop):
                CALLS[name](v, cb)
            assert len(seen) == k
            gc.collect()
            assert lib.bvox_memory_in_use() == base
    finally:
        lib.bvox_set_progress_interval(0.005)


def test_read_write_cancel(tmp_path):
    lib.bvox_set_progress_interval(0)
    try:
        v = bvox.Volume.from_numpy(ball())
        path = str(tmp_path / "b.nii.gz")
        seen, cb = recorder()
        v.write(path, progress=cb)
        assert seen[-1][0] == 1 and seen[0][1] == "write"
        os.unlink(path)
        seen, cb = recorder(stop_at=1)
        with pytest.raises(Stop):
            v.write(path, progress=cb)
        assert not os.path.exists(path) and os.listdir(tmp_path) == []
        v.write(path)
        seen, cb = recorder()
        assert bvox.read(path, progress=cb) == v
        assert [s for _, s in seen] == ["read"] * len(seen) and seen[-1][0] == 1
        seen, cb = recorder(stop_at=1)
        with pytest.raises(Stop):
            bvox.read(path, progress=cb)
    finally:
        lib.bvox_set_progress_interval(0.005)


def test_callback_is_checked():
    v = bvox.Volume.from_numpy(ball(8))
    with pytest.raises(TypeError):
        v.dilate(progress=3)
    assert bvox.Canceled.__mro__[1] is bvox.Error
