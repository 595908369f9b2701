"""bvox.dask on a LocalCluster of 2 worker processes against the in-memory
answers of bvox.Volume, on random and structured volumes with odd chunk
shapes and objects that cross chunk faces, edges and corners; arrays from
dask.array.from_array and from dask.array.from_zarr."""
import os

import numpy as np
import pytest

dask = pytest.importorskip("dask")
da = pytest.importorskip("dask.array")
distributed = pytest.importorskip("distributed")

import bvox  # noqa: E402
import bvox.dask as bd  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.fixture(scope="module")
def client():
    # the workers are spawned processes: they find the package (and, through
    # BVOX_LIBRARY, the library) by the environment
    pkg = os.path.abspath(os.path.join(HERE, ".."))
    old = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = pkg + (os.pathsep + old if old else "")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None, host="127.0.0.1")
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()
    if old is None:
        del os.environ["PYTHONPATH"]
    else:
        os.environ["PYTHONPATH"] = old


def structured(shape=(90, 120, 140)):
    """Balls (some hollow: cavities), bars and a torus (a tunnel) placed
    across the chunk faces, edges and corners of CHUNKS, plus specks that
    touch only diagonally across a corner."""
    x, y, z = np.ogrid[:shape[0], :shape[1], :shape[2]]
    m = np.zeros(shape, dtype=bool)
    for c, r, hollow in [((37, 100, 65), 9, True), ((36, 20, 64), 7, False),
                         ((74, 99, 130), 8, True), ((10, 60, 20), 5, False)]:
        d2 = (x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2
        m |= d2 <= r * r
        if hollow:
            m &= ~(d2 <= (r - 3) ** 2)
    m[5:85, 98:102, 60:70] = True          # a bar along x across two chunk faces
    m[20:24, 10:115, 63:67] = True         # along y across a face and an edge
    # a torus around the corner (37, 100, 65)... shifted to stay clear
    rho = np.sqrt((x - 55.0) ** 2 + (y - 40.0) ** 2)
    m |= (rho - 12) ** 2 + (z - 65.0) ** 2 <= 9
    # single voxels meeting only at a chunk corner (26-connected, not 18/6)
    m[36, 99, 129] = m[37, 100, 130] = True
    m[73, 40, 20] = m[74, 41, 20] = True   # an edge contact (18 and 26)
    return m


CHUNKS = (37, 100, 65)


def random_vol(seed, shape=(50, 45, 70), p=0.35):
    return np.random.default_rng(seed).random(shape) < p


def same_measure(got, want):
    assert got.keys() == want.keys()
    for k, w in want.items():
        g = got[k]
        if isinstance(w, float):
            assert g == pytest.approx(w, rel=1e-12, abs=1e-9), k
        elif isinstance(w, list) and w and isinstance(w[0], (list, float)):
            np.testing.assert_allclose(np.array(g, dtype=float), np.array(w, dtype=float),
                                       rtol=1e-12, atol=1e-9, err_msg=k)
        else:
            assert g == w, k


def test_count(client):
    m = random_vol(1)
    assert bd.count(da.from_array(m, chunks=(17, 20, 33))) == int(m.sum())
    s = structured()
    assert bd.count(da.from_array(s.astype(np.uint8), chunks=CHUNKS)) == int(s.sum())


@pytest.mark.parametrize("which", ["random", "structured"])
def test_measure(client, which):
    m = random_vol(2) if which == "random" else structured()
    chunks = (17, 20, 33) if which == "random" else CHUNKS
    spacing = (0.5, 0.7, 1.3)
    want = bvox.Volume.from_numpy(m, spacing=spacing).measure()
    got = bd.measure(da.from_array(m, chunks=chunks), spacing=spacing)
    same_measure(got, want)
    if which == "structured":  # the structure shows in the topology
        assert want["cavities"] >= 2 and want["tunnels"] >= 1 and want["components"] >= 5


def test_measure_empty_and_one_chunk(client):
    z = np.zeros((20, 21, 22), dtype=bool)
    same_measure(bd.measure(da.from_array(z, chunks=7)), bvox.Volume.from_numpy(z).measure())
    m = random_vol(3, (20, 21, 22))
    same_measure(bd.measure(da.from_array(m, chunks=m.shape)),
                 bvox.Volume.from_numpy(m).measure())


@pytest.mark.parametrize("conn", [6, 18, 26])
def test_components_random(client, conn):
    m = random_vol(4, p=0.3)
    want, comps = bvox.Volume.from_numpy(m).components(conn)
    labels, n = bd.components(da.from_array(m, chunks=(17, 20, 33)), conn=conn)
    assert isinstance(labels, da.Array) and labels.chunks == ((17, 17, 16), (20, 20, 5),
                                                              (33, 33, 4))
    assert n == len(comps)
    np.testing.assert_array_equal(labels.compute(), want)


@pytest.mark.parametrize("conn", [6, 18, 26])
def test_components_structured(client, conn):
    s = structured()
    want, comps = bvox.Volume.from_numpy(s).components(conn)
    labels, n = bd.components(da.from_array(s, chunks=CHUNKS), conn=conn)
    assert n == len(comps)
    np.testing.assert_array_equal(labels.compute(), want)
    # the corner specks join at 26 only; the edge pair at 18 and 26
    assert (want[36, 99, 129] == want[37, 100, 130]) == (conn == 26)
    assert (want[73, 40, 20] == want[74, 41, 20]) == (conn >= 18)


def test_morphology(client):
    m = random_vol(5, p=0.2)
    v = bvox.Volume.from_numpy(m)
    a = da.from_array(m, chunks=(17, 20, 33))
    s = structured()[20:60, 80:120, 50:90]  # hollow ball, bars, the chunk corner
    vs = bvox.Volume.from_numpy(s, spacing=(1.0, 1.0, 1.5))
    b = da.from_array(s, chunks=(17, 20, 21))
    cases = [(bd.dilate(a, c), v.dilate(c)) for c in (6, 18, 26)]
    cases += [(bd.erode(a, c), v.erode(c)) for c in (6, 18, 26)]
    cases += [(bd.dilate_ball(b, 3.0, spacing=(1.0, 1.0, 1.5)), vs.dilate_ball(3.0)),
              (bd.erode_ball(b, 2.0, spacing=(1.0, 1.0, 1.5)), vs.erode_ball(2.0))]
    got = dask.compute(*[c[0] for c in cases])  # one round trip to the cluster
    for g, (_, want) in zip(got, cases):
        np.testing.assert_array_equal(g, want.to_numpy())


def test_csg(client):
    p, q = random_vol(6), random_vol(7)
    vp, vq = bvox.Volume.from_numpy(p), bvox.Volume.from_numpy(q)
    a = da.from_array(p, chunks=(17, 20, 33))
    b = da.from_array(q, chunks=(25, 9, 40))  # other chunks: rechunked to a's
    for op, want in [("union", vp | vq), ("&", vp & vq), ("-", vp - vq), ("xor", vp ^ vq)]:
        np.testing.assert_array_equal(bd.csg(a, b, op).compute(), want.to_numpy())
    with pytest.raises(ValueError):
        bd.csg(a, b, "nand")
    with pytest.raises(ValueError):
        bd.csg(a, b[:10], "union")


def _triangle_set(v, f):
    """Triangles as sorted rows of rotated vertex coordinates (orientation
    kept: each triangle rotated to start at its smallest vertex)."""
    t = np.round(v[f] * 1e6).astype(np.int64)  # (m, 3, 3)
    out = []
    for tri in t:
        rows = [tuple(r) for r in tri]
        i = rows.index(min(rows))
        out.append(tuple(rows[i:] + rows[:i]))
    return sorted(out)


def test_mesh(client):
    s = structured()[10:80, 60:120, 40:140]  # balls and specks across the chunk corners
    spacing = (0.5, 1.0, 2.0)
    v0, f0 = bvox.Volume.from_numpy(s, spacing=spacing).mesh("mc")
    v, f = bd.mesh(da.from_array(s, chunks=(27, 40, 25)), spacing=spacing)
    assert len(v) == len(v0) and len(f) == len(f0)
    assert _triangle_set(v, f) == _triangle_set(v0, f0)
    info = bvox.mesh_info(v, f) if hasattr(bvox, "mesh_info") else None
    if info is not None:
        assert info["boundary_edges"] == 0


@pytest.mark.parametrize("ext,ascii", [("ply", False), ("ply", True), ("stl", False),
                                       ("obj", False), ("off", False)])
def test_mesh_to_file(client, tmp_path, ext, ascii):
    """path=: written row of chunks by row, the same file content (up to
    order) as the in-memory mesh written whole; z chunks of 25 and 13 so
    that rows meet inside objects and at odd planes."""
    s = structured()[10:80, 60:120, 40:140]
    spacing, origin = (0.5, 1.0, 2.0), (3.0, -1.0, 0.5)
    v0, f0 = bvox.Volume.from_numpy(s, spacing=spacing, origin=origin).mesh("mc")
    want = str(tmp_path / ("want." + ext))
    bvox.write_mesh(want, v0, f0, ascii=ascii)
    wv, wf = bvox.read_mesh(want)
    for chunks in ((27, 40, 25), (70, 60, 13)):
        got = str(tmp_path / ("got." + ext))
        n = bd.mesh(da.from_array(s, chunks=chunks), spacing=spacing, origin=origin, path=got,
                    ascii=ascii)
        assert n == (len(v0), len(f0))
        gv, gf = bvox.read_mesh(got)
        assert len(gv) == len(wv) and len(gf) == len(wf)
        assert _triangle_set(gv, gf) == _triangle_set(wv, wf)
        info = bvox.mesh_info(gv, gf)
        assert info["watertight"] and info["inconsistent_edges"] == 0
    # only the two files: the faces' temporary file is gone
    assert sorted(os.listdir(tmp_path)) == sorted(["want." + ext, "got." + ext])


def test_mesh_to_file_failure_leaves_nothing(client, tmp_path):
    s = structured()[10:40, 60:90, 40:80]
    with pytest.raises(ValueError):
        bd.mesh(da.from_array(s, chunks=(15, 15, 20)), path=str(tmp_path / "x.vtk"))
    with pytest.raises(bvox.Error):
        bd.mesh(da.from_array(s, chunks=(15, 15, 20)), path=str(tmp_path / "no" / "x.ply"))
    assert os.listdir(tmp_path) == []


def test_from_zarr(client, tmp_path):
    zarr = pytest.importorskip("zarr")
    s = structured()
    path = str(tmp_path / "s.zarr")
    z = zarr.open(path, mode="w", shape=s.shape, chunks=CHUNKS, dtype="u1")
    z[:] = s.astype(np.uint8)
    a = da.from_zarr(path)
    assert a.chunks[0] == (37, 37, 16)
    assert bd.count(a) == int(s.sum())
    same_measure(bd.measure(a), bvox.Volume.from_numpy(s).measure())
    want, comps = bvox.Volume.from_numpy(s).components(26)
    labels, n = bd.components(a)
    assert n == len(comps)
    np.testing.assert_array_equal(labels.compute(), want)


def test_bad_input():
    with pytest.raises(ValueError):
        bd.count(da.zeros((4, 4), chunks=2))
    with pytest.raises(ValueError):
        bd.measure(da.zeros((4, 4, 4), chunks=2), spacing=(1, -1, 1))


def test_components_many_small_chunks(client):
    # chunks of 6..8 voxels: most components cross several chunk faces,
    # edges and corners, so the merge's rims and tree reduction all matter
    m = random_vol(8, shape=(24, 20, 22), p=0.3)
    want, comps = bvox.Volume.from_numpy(m).components(26)
    labels, n = bd.components(da.from_array(m, chunks=(7, 6, 8)), conn=26)
    assert n == len(comps) and n > 1
    np.testing.assert_array_equal(labels.compute(), want)


def test_components_without_cluster():
    # Dask's default threads (no Client): the persisted merge is a value
    m = random_vol(10, shape=(30, 25, 28), p=0.35)
    want, comps = bvox.Volume.from_numpy(m).components(18)
    with dask.config.set(scheduler="threads"):
        labels, n = bd.components(da.from_array(m, chunks=(11, 9, 10)), conn=18)
        assert n == len(comps)
        np.testing.assert_array_equal(labels.compute(), want)


def test_forest_tree_reduction():
    # the tree of union-find forests joins the same sets as one union-find
    # over every pair (scipy's connected components as the reference)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    rng = np.random.default_rng(9)
    ids = rng.choice(10 ** 12, size=300, replace=False).astype(np.int64)
    parts = [ids[rng.integers(0, 300, size=(rng.integers(0, 12), 2))] for _ in range(40)]
    forest = bd._tree([dask.delayed(p) for p in parts], fanin=3).compute(scheduler="sync")
    every = np.concatenate(parts)
    u, inv = np.unique(every, return_inverse=True)
    inv = inv.reshape(-1, 2)
    _, comp = connected_components(coo_matrix((np.ones(len(inv)), (inv[:, 0], inv[:, 1])),
                                              shape=(len(u), len(u))), directed=False)
    assert np.array_equal(forest[:, 0], u)  # every key met, once, ascending
    for c in np.unique(comp):
        members = u[comp == c]
        assert set(forest[comp == c, 1]) == {members.min()}  # one root: the smallest key


def cavities_case():
    """Cavities that the chunked merge must get right, with chunks of 10:
    a hollow cube whose cavity spans the chunk corner (10, 10, 10); two
    hollow boxes with walls one voxel thick whose inside meets the outside
    only diagonally, across the chunk corner (30, 30, 30) (a removed corner
    voxel: a 6-cavity, no 26-cavity) and across the chunk edge x = y = 30
    (a removed edge voxel: likewise); and two pockets open only at the
    array's border, at x = 0 and at the last z, each reaching into the
    next chunk (not cavities: the chunk touching the border must tell the
    other)."""
    m = np.zeros((40, 45, 47), dtype=bool)
    m[4:16, 4:16, 4:16] = True
    m[6:14, 6:14, 6:14] = False                     # A: cavity across a chunk corner
    m[22:31, 22:31, 22:31] = True
    m[23:30, 23:30, 23:30] = False
    m[30, 30, 30] = False                           # B: corner contact to the outside
    m[22:31, 22:31, 2:11] = True
    m[23:30, 23:30, 3:10] = False
    m[30, 30, 6] = False                            # C: edge contact to the outside
    m[0:14, 32:40, 32:40] = True
    m[0:12, 34:38, 34:38] = False                   # D: open at x = 0, into chunk x 10..
    m[32:40, 2:10, 33:47] = True
    m[34:38, 4:8, 35:47] = False                    # E: open at z = 46, into chunk z 30..
    return m


@pytest.mark.parametrize("chunks", [(10, 10, 10), (7, 9, 11), (40, 45, 47)])
def test_measure_cavities_across_chunks(client, chunks):
    m = cavities_case()
    want = bvox.Volume.from_numpy(m).measure()
    # the case is what it claims: A, B and C are 6-cavities, only A a 26-one
    assert (want["cavities"], want["cavities_26"], want["components"]) == (3, 1, 5)
    same_measure(bd.measure(da.from_array(m, chunks=chunks)), want)
    # the complement: the pockets become objects, the border background one
    same_measure(bd.measure(da.from_array(~m, chunks=chunks)),
                 bvox.Volume.from_numpy(~m).measure())


def test_measure_thin_chunks(client):
    # chunks one and two voxels thick: a chunk's own last planes are then
    # all of it (no inside to clear), and the planes of the neighbours across
    # its faces, edges and corner make its whole overlap
    m = random_vol(11, shape=(20, 21, 22), p=0.5)
    want = bvox.Volume.from_numpy(m).measure()
    for chunks in [((1, 2, 17), (10, 1, 10), (2, 1, 19)), ((1,) * 20, (21,), (2,) * 11)]:
        same_measure(bd.measure(da.from_array(m, chunks=chunks)), want)
