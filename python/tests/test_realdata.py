"""Real data (Debian's mricron-data): the AAL atlas read with a label, against
nibabel's reading of the same file; one region measured, meshed, rendered."""
import os

import numpy as np
import pytest

import bvox

nib = pytest.importorskip("nibabel")
AAL = "/usr/share/mricron/templates/aal.nii.gz"
pytestmark = pytest.mark.skipif(not os.path.exists(AAL), reason="mricron-data not installed")


def test_aal_region_against_nibabel():
    img = nib.load(AAL)
    data = np.asanyarray(img.dataobj)
    v = bvox.read(AAL, label=37)
    assert v.shape == data.shape
    assert np.array_equal(v.to_numpy(), data == 37)
    assert np.allclose(v.affine, img.affine, atol=1e-4)
    assert v.spacing == pytest.approx(img.header.get_zooms()[:3])
    # the same through NumPy: nibabel's array handed over in place
    w = bvox.Volume.from_numpy(data, label=37)
    assert w == v


def test_aal_region_measure_mesh_render():
    v = bvox.read(AAL, label=37)
    m = v.measure()
    n = int((np.asanyarray(nib.load(AAL).dataobj) == 37).sum())
    assert m["count"] == n and m["volume"] == pytest.approx(n * np.prod(v.spacing))
    verts, faces = v.mesh()
    info = bvox.mesh_info(verts, faces)
    assert info["watertight"]
    assert info["volume"] == pytest.approx(m["volume"], rel=0.1)
    img = v.render("iso", width=128, height=128)
    assert img.shape == (128, 128, 3) and img.max() > 0
    labels, comps = v.components()
    assert sum(c["voxels"] for c in comps) == n
