"""Files: write/read round trips through every volume format, NIfTI geometry
checked with nibabel (an independent reader and writer), label volumes,
meshes and PNGs; clear errors for missing and corrupt files."""
import numpy as np
import pytest

import bvox
from conftest import random_mask

nib = pytest.importorskip("nibabel")


@pytest.mark.parametrize("name", ["v.nii", "v.nii.gz", "v.tif", "v.binvox"])
def test_write_read_round_trip(rng, tmp_path, name):
    a = random_mask(rng, (9, 8, 70))
    v = bvox.Volume.from_numpy(a, spacing=(0.5, 0.5, 2.0), unit="mm")
    v.write(tmp_path / name)
    back = bvox.read(tmp_path / name)
    assert back == v and np.array_equal(back.to_numpy(), a)
    if name != "v.binvox":  # binvox keeps one (cubic) scale
        assert back.spacing == pytest.approx((0.5, 0.5, 2.0))


def test_nifti_geometry_with_nibabel(rng, tmp_path):
    a = random_mask(rng, (7, 9, 66))
    v = bvox.Volume.from_numpy(a, spacing=(0.8, 0.9, 2.5), unit="mm", origin=(-10, 20, 5))
    v.write(tmp_path / "g.nii.gz")
    img = nib.load(str(tmp_path / "g.nii.gz"))
    assert img.shape == a.shape
    assert np.array_equal(np.asanyarray(img.dataobj) != 0, a)
    assert np.allclose(img.header.get_zooms()[:3], (0.8, 0.9, 2.5))
    assert np.allclose(img.affine, v.affine)
    assert img.header.get_xyzt_units()[0] == "mm"


def test_read_nibabel_file(rng, tmp_path):
    data = rng.integers(0, 5, size=(10, 6, 67)).astype(np.int16)
    aff = np.array([[2.0, 0, 0, -40], [0, 1.5, 0, 12], [0, 0, 3, 7], [0, 0, 0, 1]])
    img = nib.Nifti1Image(data, aff)
    img.header.set_xyzt_units("mm")
    nib.save(img, str(tmp_path / "n.nii.gz"))
    v = bvox.read(tmp_path / "n.nii.gz", label=3)
    assert np.array_equal(v.to_numpy(), data == 3)
    assert np.allclose(v.affine, aff) and v.unit == "mm"
    # nibabel hands arrays over in Fortran order: read in place, same answer
    arr = np.asanyarray(nib.load(str(tmp_path / "n.nii.gz")).dataobj)
    assert np.array_equal(bvox.Volume.from_numpy(arr, range=(2, 3)).to_numpy(),
                          (data >= 2) & (data <= 3))


def test_labels_file(rng, tmp_path):
    a = random_mask(rng, (8, 8, 65), 0.2)
    v = bvox.Volume.from_numpy(a, spacing=(1, 1, 2), unit="mm")
    labels, comps = v.components(conn=6)
    v.write_labels(tmp_path / "l.nii.gz", labels)
    img = nib.load(str(tmp_path / "l.nii.gz"))
    assert np.array_equal(np.asanyarray(img.dataobj), labels)
    assert bvox.read(tmp_path / "l.nii.gz", label=1).count() == comps[0]["voxels"]


def test_mesh_and_png_files(tmp_path):
    v = bvox.Volume((20, 20, 20))
    v.draw("sphere", radius=6)
    verts, faces = v.mesh()
    bvox.write_mesh(tmp_path / "s.stl", verts, faces)
    bvox.write_mesh(tmp_path / "s.ply", verts, faces)
    for f in ("s.stl", "s.ply"):
        v2, f2 = bvox.read_mesh(tmp_path / f)
        assert len(f2) == len(faces)
        assert bvox.mesh_info(v2, f2)["volume"] == pytest.approx(
            bvox.mesh_info(verts, faces)["volume"], rel=1e-6)
    img = v.render("+z", path=tmp_path / "r.png")
    from PIL import Image
    png = np.asarray(Image.open(tmp_path / "r.png"))
    assert np.array_equal(png if png.ndim == 2 else png[..., 0], img[..., 0])
    bvox.write_png(tmp_path / "w.png", img)
    assert np.array_equal(np.asarray(Image.open(tmp_path / "w.png")), img)
    with pytest.raises(TypeError):
        bvox.write_png(tmp_path / "x.png", img.astype(np.float32))


def test_file_errors(tmp_path):
    with pytest.raises(bvox.NotFound) as e:
        bvox.read(tmp_path / "missing.nii")
    assert "missing.nii" in str(e.value) and isinstance(e.value, FileNotFoundError)
    (tmp_path / "bad.nii").write_bytes(b"\x5c\x01\x00\x00" + b"\x00" * 100)
    with pytest.raises(bvox.FormatError):
        bvox.read(tmp_path / "bad.nii")
    with pytest.raises(bvox.Error) as e:
        bvox.Volume((2, 2, 2)).write(tmp_path / "no_dir" / "x.nii")
    assert e.value.status_name in ("BVOX_EIO", "BVOX_ENOTFOUND")
    assert not (tmp_path / "no_dir").exists()


def test_raw_with_numpy(rng, tmp_path):
    data = rng.integers(0, 300, size=(6, 5, 67)).astype(np.int16)
    # raw files are x fastest: Fortran order of the [x, y, z] array
    (tmp_path / "v.raw").write_bytes(b"HDR!" + data.tobytes(order="F"))
    for dtype in ("i16", np.int16, "int16"):
        v = bvox.read(tmp_path / "v.raw", dims=data.shape, dtype=dtype, offset=4,
                      threshold=150, spacing=(1, 2, 3), unit="um")
        assert np.array_equal(v.to_numpy(), data >= 150), dtype
        assert v.spacing == (1.0, 2.0, 3.0) and v.unit == "um"
    u8 = rng.integers(0, 2, size=(3, 4, 5)).astype(np.uint8)
    (tmp_path / "b.raw").write_bytes(u8.tobytes(order="F"))
    assert np.array_equal(bvox.read(tmp_path / "b.raw", dims=u8.shape, dtype="u8").to_numpy(),
                          u8 != 0)  # bvox's "u8" is uint8 (NumPy's would be uint64)
    with pytest.raises(TypeError):
        bvox.read(tmp_path / "b.raw", dims=u8.shape, dtype="complex64")
    with pytest.raises(bvox.Error):
        bvox.read(tmp_path / "b.raw", dims=(9, 9, 9), dtype="u8")  # file too short
