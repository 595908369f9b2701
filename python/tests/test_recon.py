"""Contours and reconstruction: model -> contours -> model round trip (voxel
for voxel), hand-made contour stacks scan-converted, a JSON stack file, and
serial-section images given as NumPy arrays reconstructed into exactly their
masks (fixed threshold, no smoothing), with the progress callback."""
import numpy as np
import pytest

import bvox
from conftest import random_mask


def test_contours_round_trip(rng):
    a = random_mask(rng, (17, 13, 6), 0.5)
    v = bvox.Volume.from_numpy(a, spacing=(0.5, 0.5, 0.5), unit="mm", origin=(3, 4, 5))
    c = v.contours(axis=2)
    assert len(c) == 6 and c.unit == "mm" and c.pixel == 0.5
    for s in c:
        for k in s["contours"]:
            assert k["points"].shape[1] == 2 and len(k["points"]) >= 4
    w = c.to_volume(z_spacing=0.5, interpolate=False)
    assert w.shape == v.shape and np.array_equal(w.to_numpy(), a)
    assert w.origin == pytest.approx(v.origin)


def test_square_stack_and_file(tmp_path):
    sq = np.array([[2, 2], [8, 2], [8, 6], [2, 6]], float)  # 6 x 4 pixels
    hole = np.array([[4, 3], [6, 3], [6, 5], [4, 5]], float)  # 2 x 2 pixels
    c = bvox.Contours([{"z": 0.0, "contours": [{"points": sq}]},
                       {"z": 1.0, "contours": [{"points": sq}, {"points": hole, "hole": True,
                                                                "parent": 0}]}],
                      pixel=1, spacing=1, unit="um", width=10, height=8)
    v = c.to_volume(z_spacing=1, interpolate=False)
    assert v.shape == (10, 8, 2)
    a = v.to_numpy()
    assert a[:, :, 0].sum() == 24 and a[:, :, 1].sum() == 20
    assert a[2:8, 2:6, 0].all() and not a[4:6, 3:5, 1].any()
    c.write(tmp_path / "s.json")
    back = bvox.read_contours(tmp_path / "s.json")
    assert len(back) == 2 and back.unit == "um"
    assert np.array_equal(back.to_volume(z_spacing=1, interpolate=False).to_numpy(), a)
    with pytest.raises(bvox.InvalidArgument):
        bvox.Contours([]).to_volume()


def test_reconstruct_numpy_sections():
    h, w, n = 40, 50, 5
    yy, xx = np.mgrid[0:h, 0:w]
    masks, images = [], []
    for k in range(n):
        m = (xx - 25) ** 2 + (yy - 20) ** 2 <= (6 + 2 * k) ** 2
        masks.append(m)
        images.append(np.where(m, 40, 220).astype(np.uint8))  # a dark object
    seen = []
    v, c = bvox.reconstruct(images, threshold=128, smooth=0, min_area=0,
                            estimate_background=False, pixel=2, spacing=2, unit="um",
                            progress=lambda step, done, total: seen.append(step),
                            contours=True)
    assert v.shape == (w, h, n) and v.unit == "um" and v.spacing == pytest.approx((2, 2, 2))
    a = v.to_numpy()
    for k in range(n):
        assert np.array_equal(a[:, :, k], masks[k].T)
    assert len(c) == n
    assert "volume" in seen and "contours" in seen
    with pytest.raises(TypeError):
        bvox.reconstruct([im.astype(np.float32) for im in images])


def test_reconstruct_progress_exception_propagates():
    img = np.full((10, 10), 200, np.uint8)
    img[3:7, 3:7] = 10

    def boom(step, done, total):
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        bvox.reconstruct([img, img], threshold=100, smooth=0, min_area=0,
                         estimate_background=False, progress=boom)
