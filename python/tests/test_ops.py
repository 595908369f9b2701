"""Operations against independent oracles on random volumes: set algebra
(with offsets) against NumPy logic, morphology against scipy.ndimage
(binary_dilation / binary_erosion with the 6/18/26 structures, outside = 0),
components against scipy.ndimage.label, measures against NumPy counts and
hand-computed boxes, shapes against their analytic inside test, meshes
(closed, cuberille volume = voxel volume), voxelize and render."""
import numpy as np
import pytest
from scipy import ndimage

import bvox
from conftest import SIZES, random_mask

STRUCT = {6: ndimage.generate_binary_structure(3, 1), 18: ndimage.generate_binary_structure(3, 2),
          26: ndimage.generate_binary_structure(3, 3)}


@pytest.mark.parametrize("shape", SIZES)
def test_set_operators(rng, shape):
    a, b = random_mask(rng, shape), random_mask(rng, shape)
    va, vb = bvox.Volume.from_numpy(a), bvox.Volume.from_numpy(b)
    for got, want in [(va | vb, a | b), (va & vb, a & b), (va - vb, a & ~b), (va ^ vb, a ^ b),
                      (~va, ~a)]:
        got.check()
        assert np.array_equal(got.to_numpy(), want)
    assert np.array_equal(va.to_numpy(), a)  # operands unchanged
    vc = va.copy()
    vc ^= vb
    assert np.array_equal(vc.to_numpy(), a ^ b)


def _placed(b, shape, off):
    """b placed at offset off in a grid of shape (outside: 0)."""
    out = np.zeros(shape, bool)
    src = [slice(max(0, -o), min(n, s - o)) for o, n, s in zip(off, b.shape, shape)]
    dst = [slice(max(0, o), max(0, o) + (sl.stop - sl.start)) for o, sl in zip(off, src)]
    if all(sl.stop > sl.start for sl in src):
        out[tuple(dst)] = b[tuple(src)]
    return out


@pytest.mark.parametrize("off", [(1, 0, 0), (0, -2, 3), (-1, 2, -70), (2, 1, 65)])
def test_offsets(rng, off):
    a, b = random_mask(rng, (6, 7, 131)), random_mask(rng, (4, 5, 80))
    va, vb = bvox.Volume.from_numpy(a), bvox.Volume.from_numpy(b)
    p = _placed(b, a.shape, off)
    assert np.array_equal(va.union(vb, offset=off).to_numpy(), a | p)
    assert np.array_equal(va.intersection(vb, offset=off).to_numpy(), a & p)
    assert np.array_equal(va.difference(vb, offset=off).to_numpy(), a & ~p)
    assert np.array_equal(va.xor(vb, offset=off).to_numpy(), a ^ p)


@pytest.mark.parametrize("conn", [6, 18, 26])
@pytest.mark.parametrize("shape", SIZES + [(12, 11, 70)])
def test_morphology_matches_scipy(rng, conn, shape):
    a = random_mask(rng, shape, 0.3)
    v = bvox.Volume.from_numpy(a)
    d = v.dilate(conn=conn)
    d.check()
    assert np.array_equal(d.to_numpy(), ndimage.binary_dilation(a, STRUCT[conn]))
    assert np.array_equal(v.erode(conn=conn).to_numpy(),
                          ndimage.binary_erosion(a, STRUCT[conn], border_value=0))


def test_ball_and_derived(rng):
    a = random_mask(rng, (20, 18, 70), 0.05)
    v = bvox.Volume.from_numpy(a, spacing=(1, 1, 2))
    # a ball of radius 2 with 1 x 1 x 2 voxels: offsets with i^2 + j^2 + (2k)^2 <= 4
    i, j, k = np.mgrid[-2:3, -2:3, -1:2]
    ball = i ** 2 + j ** 2 + (2 * k) ** 2 <= 4
    assert np.array_equal(v.dilate_ball(2).to_numpy(), ndimage.binary_dilation(a, ball))
    s = STRUCT[6]
    assert np.array_equal(v.opening(conn=6).to_numpy(),
                          ndimage.binary_dilation(ndimage.binary_erosion(a, s, border_value=0),
                                                  s))
    # closing works on a padded copy: scipy's closing of the padded array, cut back
    p = np.pad(a, 1)
    closed = ndimage.binary_erosion(ndimage.binary_dilation(p, s), s, border_value=0)
    assert np.array_equal(v.closing(conn=6).to_numpy(), closed[1:-1, 1:-1, 1:-1])
    assert np.array_equal(v.fill_holes().to_numpy(), ndimage.binary_fill_holes(a))


@pytest.mark.parametrize("conn", [6, 18, 26])
def test_components_match_scipy(rng, conn):
    a = random_mask(rng, (15, 13, 70), 0.25)
    labels, comps = bvox.Volume.from_numpy(a, spacing=(1, 1, 0.5)).components(conn=conn)
    ref, n = ndimage.label(a, STRUCT[conn])
    assert labels.shape == a.shape and labels.dtype == np.uint32
    assert len(comps) == n
    assert np.array_equal(labels > 0, a)
    # the same partition: each bvox label is exactly one scipy label
    pairs = np.unique(np.stack([labels[a], ref[a]]), axis=1)
    assert pairs.shape[1] == n
    assert len(np.unique(pairs[0])) == n and len(np.unique(pairs[1])) == n
    sizes = np.bincount(labels.ravel())[1:]
    assert [c["voxels"] for c in comps] == list(sizes)
    assert sizes.tolist() == sorted(sizes.tolist(), reverse=True)  # largest first
    for i, c in enumerate(comps[:5]):
        xs, ys, zs = np.nonzero(labels == i + 1)
        assert c["bbox"] == {"min": [xs.min(), ys.min(), zs.min()],
                             "max": [xs.max(), ys.max(), zs.max()]}
        assert c["volume"] == pytest.approx(c["voxels"] * 0.5)
    assert set(comps[0]) == {"voxels", "volume", "bbox"}  # the CLI's JSON keys


def test_measure_box():
    # a 4 x 5 x 6 box of 0.5 mm voxels: everything hand-computed
    v = bvox.Volume((20, 20, 20), spacing=0.5, unit="mm")
    v.fill_box((2, 3, 4), (5, 7, 9))
    m = v.measure()
    assert m["count"] == 120 and m["volume"] == pytest.approx(15.0)
    assert m["volume_unit"] == "mm^3" and m["volume_mm3"] == pytest.approx(15.0)
    assert m["bbox"] == {"min": [2, 3, 4], "max": [5, 7, 9]}
    assert m["bbox_physical"]["min"] == pytest.approx([0.75, 1.25, 1.75])
    assert m["faces"] == [2 * 30, 2 * 24, 2 * 20]
    assert m["surface_area_faces"] == pytest.approx(37.0)
    assert m["centroid"] == pytest.approx([1.75, 2.5, 3.25])
    assert (m["components"], m["cavities"], m["tunnels"], m["euler"]) == (1, 0, 0, 1)


def test_measure_keys_match_cli(tmp_path):
    import json
    import os
    import subprocess
    exe = os.environ.get("BVOX_CLI")
    if not exe:
        pytest.skip("BVOX_CLI not set")
    v = bvox.demo()
    v.write(tmp_path / "d.nii.gz")
    out = subprocess.run([exe, "measure", str(tmp_path / "d.nii.gz"), "--json"], check=True,
                         capture_output=True, text=True).stdout
    cli = json.loads(out)
    m = v.measure()
    assert set(cli) - {"file", "format", "input", "output"} == set(m)
    for k in ("count", "faces", "components", "cavities", "tunnels", "euler", "bbox", "dims",
              "unit", "volume_unit", "area_unit"):
        assert m[k] == cli[k], k
    for k in ("volume", "surface_area", "surface_area_faces", "equivalent_diameter"):
        assert m[k] == pytest.approx(cli[k], rel=1e-5), k


def test_measure_counts_random(rng):
    a = random_mask(rng, (9, 10, 77))
    m = bvox.Volume.from_numpy(a, spacing=(1, 2, 3)).measure()
    xs, ys, zs = np.nonzero(a)
    assert m["count"] == a.sum() and m["volume"] == pytest.approx(6 * a.sum())
    assert m["centroid"] == pytest.approx([xs.mean(), 2 * ys.mean(), 3 * zs.mean()])
    # faces between a 1-voxel and a 0-voxel (or the outside), per axis
    p = np.pad(a, 1)
    faces = [int(np.count_nonzero(np.diff(p.astype(np.int8), axis=ax))) for ax in range(3)]
    assert m["faces"] == faces
    _, n26 = ndimage.label(a, STRUCT[26])
    assert m["components"] == n26


def test_shapes_and_csg():
    v = bvox.Volume((21, 21, 21))
    v.draw("sphere", radius=6)
    i, j, k = np.mgrid[0:21, 0:21, 0:21]
    ball = (i - 10) ** 2 + (j - 10) ** 2 + (k - 10) ** 2 <= 36
    assert np.array_equal(v.to_numpy(), ball)
    e = bvox.csg("sphere(r=6) - box(min=0,0,0, max=20,20,10)", shape=(21, 21, 21))
    assert np.array_equal(e.to_numpy(), ball & (k > 10))
    f = bvox.csg("s * ~t@0,0,1", s=v, t=v)
    shifted = np.zeros_like(ball)
    shifted[:, :, 1:] = ball[:, :, :-1]
    assert np.array_equal(f.to_numpy(), ball & ~shifted)
    with pytest.raises(bvox.InvalidArgument, match="column"):
        bvox.csg("sphere(r=", shape=(4, 4, 4))
    with pytest.raises(bvox.NotFound):
        bvox.csg("no_such_file.nii + s", s=v)


def test_edit_and_cut():
    v = bvox.Volume((10, 10, 70))
    assert v.fill_box((1, 2, 3), (4, 5, 66)) == ((1, 2, 3), (4, 5, 66))
    assert v.fill_box((1, 2, 3), (4, 5, 66)) is None  # nothing changed
    a = v.to_numpy()
    v.cut((0, 0, 1, -10))  # keep z >= 10
    k = np.arange(70)[None, None, :]
    assert np.array_equal(v.to_numpy(), a & (k >= 10))
    v.keep_box((0, 0, 0), (2, 9, 69))
    assert v.count() == 2 * 4 * 57
    v[0, 0, 0] = True
    assert v[0, 0, 0] and v.count() == 2 * 4 * 57 + 1
    with pytest.raises(bvox.InvalidArgument):
        v[10, 0, 0] = True


def test_mesh_closed_and_volume(rng):
    a = ndimage.binary_dilation(random_mask(rng, (12, 10, 9), 0.05), STRUCT[6])
    v = bvox.Volume.from_numpy(a, spacing=(1, 1, 2))
    for method in ("mc", "cuberille"):
        verts, faces = v.mesh(method=method)
        assert verts.shape[1] == 3 and faces.shape[1] == 3 and faces.dtype == np.int32
        assert faces.min() >= 0 and faces.max() < len(verts)
        info = bvox.mesh_info(verts, faces)
        assert info["watertight"] and info["nonmanifold_edges"] == 0
    verts, faces = v.mesh(method="cuberille")
    assert bvox.mesh_info(verts, faces)["volume"] == pytest.approx(2 * a.sum())


def test_voxelize_cube():
    # the closed cube [0, 10]^3: 8 vertices, 12 outward triangles
    verts = np.array([[x, y, z] for z in (0, 10) for y in (0, 10) for x in (0, 10)], float)
    faces = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                      [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    info = bvox.mesh_info(verts, faces)
    assert info["watertight"] and info["volume"] == pytest.approx(1000)
    v, rep = bvox.voxelize(verts, faces, voxel_size=1.0, unit="mm")
    assert rep["closed"] and v.unit == "mm"
    assert v.count() == 1000
    with pytest.raises(ValueError, match="exactly one"):
        bvox.voxelize(verts, faces)
    with pytest.raises(ValueError, match="does not exist"):
        bvox.voxelize(verts, faces + 8, res=10)


def test_render():
    v = bvox.Volume((32, 32, 32))
    v.draw("sphere", radius=10)
    img = v.render("+z")
    assert img.shape == (32, 32, 3) and img.dtype == np.uint8
    # background outside the sphere's disc, lit inside it
    assert img[0, 0].max() == 0 and img[16, 16].min() > 0
    assert np.array_equal(img[..., 0], img[..., 2])  # gray replicated
    iso = v.render("iso", width=100, height=80)
    assert iso.shape == (80, 100, 3)
    cut = v.render("iso", width=64, height=64, cut=(0, 0, 1, -16))
    assert not np.array_equal(cut[..., 0], cut[..., 2])  # the tinted cut face
    with pytest.raises(bvox.InvalidArgument):
        v.render("sideways")


def test_render_smooth_shading():
    v = bvox.Volume((40, 40, 40))
    v.draw("sphere", radius=15)
    # lit from the viewer, smooth normals brighten steadily towards the middle
    img = v.render("+z", shade="smooth", light=(0, 90))[20, :, 0].astype(int)
    lit = np.nonzero(img)[0]
    half = img[lit[0]:20]
    assert len(set(half.tolist())) >= 8 and np.all(np.diff(half) > -30)
    pub = v.render("iso", width=48, height=40, shade="smooth", ao=True, shadows=True,
                   supersample=2)
    assert pub.shape == (40, 48, 3) and pub.max() > 0
    assert v.render("+z", shade="enlarged-gradient").shape == (80, 80, 3)
    with pytest.raises(bvox.InvalidArgument):
        v.render("iso", shade="smooth", supersample=9)


def test_render_colours_background_and_objects():
    v = bvox.Volume((32, 32, 32))
    v.draw("sphere", radius=10)
    gray = v.render("+z")[..., 0].astype(int)
    red = v.render("+z", color="#ff0000")
    # shading times the colour: red carries the gray, green and blue are 0
    assert np.abs(red[..., 0].astype(int) - gray).max() <= 1
    assert red[..., 1].max() == 0 and red[..., 2].max() == 0
    clear = v.render("+z", background="transparent")
    assert clear.shape == (32, 32, 4)
    assert clear[0, 0, 3] == 0 and clear[16, 16, 3] == 255
    white = v.render("+z", background=(255, 255, 255))
    assert tuple(white[0, 0]) == (255, 255, 255)
    # two objects of one grid: each pixel in the colour of the nearer one
    ma, mb = np.zeros((32, 32, 32), bool), np.zeros((32, 32, 32), bool)
    ma[2:14, 2:30, 2:30] = True  # [x, y, z]
    mb[18:30, 2:30, 2:30] = True
    a, b = bvox.Volume.from_numpy(ma), bvox.Volume.from_numpy(mb)
    both = bvox.render_objects([a, b], ["#00ff00", (0, 0, 255)], "+z")
    assert both[16, 8, 1] > 0 and both[16, 8, 2] == 0  # a: green (row y, column x)
    assert both[16, 24, 2] > 0 and both[16, 24, 1] == 0  # b: blue
    titled = v.render("iso", width=96, height=96, title="bvox", scale_bar=True, axes=True)
    assert titled.shape == (96, 96, 3)
    assert not np.array_equal(titled, v.render("iso", width=96, height=96))
    with pytest.raises(ValueError, match="colour"):
        v.render("+z", color="reddish")
    with pytest.raises(ValueError, match="one colour per volume"):
        bvox.render_objects([a, b], ["#fff"])


def test_measure_components_match_each_alone(rng):
    a = random_mask(rng, (14, 12, 66), 0.2)
    v = bvox.Volume.from_numpy(a, spacing=(1, 1, 2), unit="um")
    labels, comps = v.components(conn=6)
    per = v.measure_components(conn=6)
    assert len(per) == len(comps)
    for i in (0, 1, len(per) - 1):
        alone = bvox.Volume.from_numpy(labels == i + 1, spacing=(1, 1, 2), unit="um").measure()
        assert per[i]["count"] == comps[i]["voxels"] == alone["count"]
        assert per[i]["bbox"] == comps[i]["bbox"] == alone["bbox"]
        for k in ("volume", "surface_area", "surface_area_faces", "euler", "cavities"):
            assert per[i][k] == pytest.approx(alone[k]), k
    assert bvox.Volume((3, 3, 3)).measure_components() == []
