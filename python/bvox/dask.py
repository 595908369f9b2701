"""bvox.dask — bvox's operations on Dask arrays (e.g. dask.array.from_zarr),
run by whatever scheduler is active: a dask.distributed Client (a
LocalCluster or a cluster's scheduler, Client("tcp://host:8786")) or Dask's
default threads.

Arrays are indexed [x, y, z] like bvox.Volume.from_numpy; any dtype is
binarised as nonzero. Each chunk's work is one call into libbvox on that
chunk (with the halo the operation needs); what crosses chunk borders is
joined here:

- count: a sum of chunk counts;
- measure: each chunk, read once, gives the exact integer sums of what
  lies on its side of the border (bvox_measure_part: counts, moments, Euler
  number, the transitions behind the surface areas; what crosses its high
  sides is added by a small task from its last planes and its neighbours'
  first planes, see _chunk_scan) and its three labellings (object 26,
  background 6 and 26); the sums add up and bvox_measure_from_sums turns
  them into the dict of Volume.measure(). Components and cavities come from
  the global labellings below;
- components: chunk labels (each chunk labelled once per pass; only its
  faces leave the C labelling, and they stay on the workers), then per pair
  of neighbouring chunks a task that
  finds the label equivalences across their shared plane (the low face of
  the upper chunk widened by the rims of its in-plane neighbours: edges and
  corners), a tree reduction of union-find forests of those pairs, and one
  final task that ranks the components in the in-memory order (largest
  first, ties by the first voxel in column order) into a lookup of one
  entry per chunk label. Only n comes back to the client; the lookup stays
  on the cluster and the lazy labels relabel each chunk with it
  (map_blocks), so they equal Volume.components()'s;
- dilate, erode, dilate_ball, erode_ball: map_overlap with the reach of the
  structuring element (outside the array counts as 0, as in memory);
- csg: chunk by chunk;
- mesh: marching cubes per chunk with a one-voxel halo on each side, each
  cell kept by the one chunk whose core holds its upper corner plane, and
  vertices welded by position: the triangles of the in-memory mesh. With
  path=, written to a file one row of chunks along z at a time (welded
  against the previous row's top plane), never held whole.
"""
import math
import os

import numpy as np

import dask
import dask.array as da

from ._lib import check, cstr, ffi, lib
from ._volume import Volume, _conn

__all__ = ["count", "measure", "components", "dilate", "erode", "dilate_ball", "erode_ball",
           "csg", "mesh"]


def _vol(block, spacing=None):
    return Volume.from_numpy(np.asarray(block), spacing=spacing)


def _check3(arr):
    if not isinstance(arr, da.Array):
        arr = da.asarray(arr)
    if arr.ndim != 3:
        raise ValueError("bvox.dask: needs a 3-D array [x, y, z], got %d-D" % arr.ndim)
    if 0 in arr.shape:
        raise ValueError("bvox.dask: the array has a zero dimension %r" % (arr.shape,))
    return arr


def _starts(chunks):
    """Chunk start indices per axis (with the end appended)."""
    return [np.concatenate([[0], np.cumsum(c)]).astype(np.int64) for c in chunks]


def _grid(arr):
    return [len(c) for c in arr.chunks]


def _halo_block(arr, starts, idx, lo, hi):
    """A delayed ndarray of chunk idx widened by lo voxels below and hi
    above (clipped to the array), and where its voxel 0 lies."""
    sl, off = [], []
    for a in range(3):
        s0 = max(int(starts[a][idx[a]]) - lo, 0)
        s1 = min(int(starts[a][idx[a] + 1]) + hi, arr.shape[a])
        sl.append(slice(s0, s1))
        off.append(s0)
    return dask.delayed(np.asarray)(arr[tuple(sl)]), off


# ------------------------------------------------------------------ count

def _count_block(block):
    return np.full((1, 1, 1), _vol(block).count(), dtype=np.int64)


def count(arr):
    """Number of nonzero voxels (an int)."""
    arr = _check3(arr)
    per = arr.map_blocks(_count_block, chunks=tuple((1,) * len(c) for c in arr.chunks),
                         dtype=np.int64)
    return int(per.sum().compute())


# ------------------------------------------------------------ components

def _labelling(vol, conn, off, shape, order):
    """One labelling of a chunk (a Volume): the count, each label's size and
    first voxel (global column-order key: (y nx + x) nz + z; only when order
    is asked: the ties of the final order) and the chunk's six faces of
    labels. Only the faces (and, for the keys, one plane of each label's
    box) are written out of the C labelling (bvox_components_labels_box):
    the whole label array of a 256^3 chunk, 64 MiB written with a plane
    stride, cost 3-10x the labelling itself."""
    out = ffi.new("bvox_components **")
    check(lib.bvox_components_find(vol._p, conn, out))
    comps = ffi.gc(out[0], lib.bvox_components_destroy)
    nx, ny, nz = vol.shape
    n = int(lib.bvox_components_count(comps))
    items = [lib.bvox_components_get(comps, i) for i in range(n)]
    sizes = np.array([c.voxels for c in items], dtype=np.int64)
    # the smallest unsigned type that holds the labels: faces wait on the
    # workers for their face-pair tasks
    dt = np.uint8 if n < 0xFF else np.uint16 if n < 0xFFFF else np.uint32

    def box(x0, y0, z0, x1, y1, z1):
        b = np.empty((z1 - z0, y1 - y0, x1 - x0), dtype=np.uint32)  # x fastest
        check(lib.bvox_components_labels_box(comps, (x0, y0, z0, x1, y1, z1),
                                             ffi.from_buffer("uint32_t[]", b)))
        return b.transpose(2, 1, 0)  # [x, y, z]

    keys = np.zeros(n, dtype=np.int64)
    if n and order:
        # the first voxel in column order (y slowest, then x, z fastest) lies
        # in the label's lowest y plane: search only that plane of its box
        for i, c in enumerate(items):
            b = c.bbox
            plane = box(b.x0, b.y0, b.z0, b.x1, b.y0 + 1, b.z1)[:, 0, :] == i + 1
            x, z = np.unravel_index(int(np.argmax(plane)), plane.shape)  # x-major, z fastest
            keys[i] = ((b.y0 + off[1]) * shape[0] + b.x0 + x + off[0]) * shape[2] + \
                b.z0 + z + off[2]
    faces = [(box(0, 0, 0, 1, ny, nz)[0], box(nx - 1, 0, 0, nx, ny, nz)[0]),
             (box(0, 0, 0, nx, 1, nz)[:, 0], box(0, ny - 1, 0, nx, ny, nz)[:, 0]),
             (box(0, 0, 0, nx, ny, 1)[:, :, 0], box(0, 0, nz - 1, nx, ny, nz)[:, :, 0])]
    faces = [tuple(np.ascontiguousarray(f, dtype=dt) for f in pair) for pair in faces]
    ffi.release(comps)
    return n, sizes, keys, faces


def _label_chunk(block, specs, off, shape, order, measure=False):
    """One task per chunk: the chunk read once, labelled once per (conn,
    background) of specs (background: of its 0 voxels), and with measure its
    part of the measure sums too (_chunk_scan). Returns (scan or None,
    [labelling per spec])."""
    b = np.asarray(block)
    v = _vol(b)
    scan = _chunk_scan(v, b, off) if measure else None
    bg = None
    out = []
    for conn, background in specs:
        if background and bg is None:
            bg = ~v
        out.append(_labelling(bg if background else v, conn, off, shape, order))
    return scan, out


def _shifts(conn):
    """In-plane offsets of the neighbours across a plane: (1, du, dv) is a
    conn-neighbour offset when |du| + |dv| <= 0 (6), 1 (18), 2 (26)."""
    reach = {6: 0, 18: 1, 26: 2}[conn]
    return [(du, dv) for du in (-1, 0, 1) for dv in (-1, 0, 1) if abs(du) + abs(dv) <= reach]


# A chunk label's key before the chunks' label counts are known: the chunk's
# flat index in the high 32 bits, the local label (uint32) in the low ones.
# The equivalences are found and reduced in these keys, so no task waits for
# a global count; only the final task turns them into global labels.
_KEYBITS = 32


def _keys_of(local, flat):
    return (np.int64(flat) << _KEYBITS) | local.astype(np.int64)


def _chunk_summary(res, flat, borders):
    """The small part of a chunk's task, for the final merge: per labelling
    the label count, sizes, first-voxel keys and (background labellings:
    cavities) the keys of the labels on the array's border (borders: per
    labelling, per axis, (low, high) flags)."""
    out = []
    for (n, sizes, keys, faces), border in zip(res[1], borders):
        on = []
        for a in range(3):
            for side in (0, 1):
                if border[a][side]:
                    f = faces[a][side]
                    on.append(np.unique(f[f > 0]))
        b = np.unique(np.concatenate(on)) if on else np.zeros(0, dtype=np.uint32)
        out.append((n, sizes, keys, _keys_of(b, flat)))
    return out


def _chunk_rims(res):
    """The four edges of each low face of each labelling (the rims a
    diagonal neighbour across the plane touches): per labelling, per axis,
    (first row, last row, first column, last column)."""
    return [[(f[0].copy(), f[-1].copy(), f[:, 0].copy(), f[:, -1].copy())
             for f in (faces[a][0] for a in range(3))]
            for _, _, _, faces in res[1]]


def _plane_pairs(p, q, rims, a, flat_lo, flat_hi, flats, conn):
    """The equivalences (pairs of label keys, unique) between p, the high
    face along axis a of chunk flat_lo, and the plane of low faces across
    it: q, the low face of chunk flat_hi, and where conn reaches diagonally
    the rims of its in-plane neighbours (rims[(du, dv)], their flat indices
    flats[(du, dv)])."""
    nu, nv = p.shape
    # the plane across, widened by one voxel on each side, in keys
    qk = np.zeros((nu + 2, nv + 2), dtype=np.int64)
    qk[1:-1, 1:-1] = np.where(q > 0, _keys_of(q, flat_hi), 0)
    for (du, dv), r in rims.items():
        row0, row1, col0, col1 = r[a]
        if du and dv:
            e = np.array([(row1 if du < 0 else row0)[-1 if dv < 0 else 0]])
        elif du:
            e = row1 if du < 0 else row0
        else:
            e = col1 if dv < 0 else col0
        ek = np.where(e > 0, _keys_of(e, flats[(du, dv)]), 0)
        u = slice(0, 1) if du < 0 else slice(nu + 1, nu + 2) if du > 0 else slice(1, nu + 1)
        v = slice(0, 1) if dv < 0 else slice(nv + 1, nv + 2) if dv > 0 else slice(1, nv + 1)
        qk[u, v] = ek.reshape(qk[u, v].shape)
    # the keys across as small indices, so that a pair is one integer: the
    # pairs are deduplicated by a table (or a 1-D sort) instead of a sort
    # of rows (np.unique(axis=0) was most of a 256^3 chunk's merge time)
    uq, qi = np.unique(qk, return_inverse=True)
    qi = qi.reshape(qk.shape)
    m_uq = len(uq)
    pi = p.astype(np.int64)
    center = qi[1:-1, 1:-1]
    codes = []
    for du, dv in _shifts(conn):
        b = qi[1 + du:1 + du + nu, 1 + dv:1 + dv + nv]
        m = (pi > 0) & (qk[1 + du:1 + du + nu, 1 + dv:1 + dv + nv] != 0)
        if du or dv:  # the same pair as the centre's is already there
            m &= b != center
        if m.any():
            codes.append(pi[m] * m_uq + b[m])
    if not codes:
        return np.zeros((0, 2), dtype=np.int64)
    c = np.concatenate(codes)
    top = (int(p.max()) + 1) * m_uq
    if top <= 1 << 22:
        seen = np.zeros(top, dtype=bool)
        seen[c] = True
        c = np.flatnonzero(seen)
    else:
        c = np.unique(c)
    return np.stack([_keys_of(c // m_uq, flat_lo), uq[c % m_uq]], axis=1)


def _face_pairs(lo, hi, a, rims, flat_lo, flat_hi, flats, conns):
    """The equivalences across the plane between chunk tasks lo and hi
    (along axis a), one array of key pairs per labelling (conns: each
    labelling's connectivity; rims[(du, dv)]: per labelling)."""
    out = []
    for i, conn in enumerate(conns):
        nb = {s: r[i] for s, r in rims.items() if s in _shifts(conn)}
        out.append(_plane_pairs(lo[1][i][3][a][1], hi[1][i][3][a][0], nb, a, flat_lo,
                                flat_hi, flats, conn))
    return out


def _forest(*parts):
    """Union-find of equivalence pairs (or of forests: (key, root) pairs):
    the forest of every key met, each with the smallest key of its set as
    root. A tree reduction of these keeps only the keys on chunk faces."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e = np.concatenate(parts) if parts else np.zeros((0, 2), dtype=np.int64)
    if not len(e):
        return np.zeros((0, 2), dtype=np.int64)
    ids, inv = np.unique(e, return_inverse=True)
    inv = inv.reshape(-1, 2)
    g = coo_matrix((np.ones(len(inv), dtype=np.int8), (inv[:, 0], inv[:, 1])),
                   shape=(len(ids), len(ids)))
    _, comp = connected_components(g, directed=False)
    root = np.full(comp.max() + 1, np.iinfo(np.int64).max, dtype=np.int64)
    np.minimum.at(root, comp, ids)  # ids ascend: the first of each set
    return np.stack([ids, root[comp]], axis=1)


def _forests(*parts):
    """_forest per labelling of lists of pair arrays (one per labelling)."""
    return [_forest(*[p[i] for p in parts]) for i in range(len(parts[0]))]


def _tree(tasks, fanin=8, fn=_forest):
    """Tree reduction of forests by delayed fn, fanin at a time."""
    level = list(tasks)
    if not level:
        return dask.delayed(fn)()
    while len(level) > 1:
        level = [dask.delayed(fn, pure=True)(*level[i:i + fanin])
                 for i in range(0, len(level), fanin)]
    return dask.delayed(fn, pure=True)(level[0]) if len(tasks) == 1 else level[0]


def _finish(summaries, forest, exclude_border):
    """The final merge of one labelling (label-sized inputs only): global
    labels (chunk base + local label, chunks in flat order) joined by the
    forest, ranked in the in-memory order: a _Merged."""
    counts = np.array([s[0] for s in summaries], dtype=np.int64)
    bases = np.concatenate([[0], np.cumsum(counts)])
    total = int(bases[-1])
    sizes = np.zeros(total + 1, dtype=np.int64)
    keys = np.full(total + 1, np.iinfo(np.int64).max, dtype=np.int64)
    for s, b in zip(summaries, bases):
        sizes[b + 1:b + s[0] + 1] = s[1]
        keys[b + 1:b + s[0] + 1] = s[2]

    def glob(k):
        return bases[k >> _KEYBITS] + (k & ((1 << _KEYBITS) - 1))

    root = np.arange(total + 1, dtype=np.int64)
    if len(forest):
        root[glob(forest[:, 0])] = glob(forest[:, 1])
    ncomp = total + 1  # components indexed by their root label
    csize = np.bincount(root[1:], weights=sizes[1:], minlength=ncomp).astype(np.int64)
    ckey = np.full(ncomp, np.iinfo(np.int64).max, dtype=np.int64)
    np.minimum.at(ckey, root[1:], keys[1:])
    keep = np.zeros(ncomp, dtype=bool)
    keep[root[1:]] = True
    if exclude_border:
        b = np.concatenate([s[3] for s in summaries])
        keep[root[glob(b)]] = False
    keep[0] = False
    kept = np.flatnonzero(keep)
    rank = kept[np.lexsort((ckey[kept], -csize[kept]))]
    final = np.zeros(ncomp, dtype=np.uint32)
    final[rank] = np.arange(1, len(rank) + 1, dtype=np.uint32)
    lut = final[root]
    lut[0] = 0
    return _Merged(lut, bases, len(rank), csize[rank])


def _finish_all(summaries, forests, backgrounds, sums):
    """The final task of a graph: the chunks' measure sums added up (None
    when there are none) and a _Merged per labelling."""
    total = _add_sums(sums) if sums else None
    return total, [_finish([s[i] for s in summaries], forests[i], bg)
                   for i, bg in enumerate(backgrounds)]


def _merge_graph(arr, specs, order=True, measure=False):
    """The delayed global labellings of arr, one per (conn, background) of
    specs, in one graph: one task per chunk (read once; with measure its
    part of the measure sums too, and a small task per chunk that adds what
    crosses its high sides), its faces kept on the workers; per pair of
    neighbouring chunks a task of label equivalences of every labelling; a
    tree reduction of union-find forests and one final task: a delayed
    (sums or None, [_Merged])."""
    starts, grid = _starts(arr.chunks), _grid(arr)
    blocks = arr.to_delayed()
    flat = {idx: i for i, idx in enumerate(np.ndindex(*grid))}
    conns = [c for c, _ in specs]
    reach = max(conns, key=lambda c: len(_shifts(c)))
    chunk, summ, rims = {}, [], {}
    for idx in np.ndindex(*grid):
        off = [int(starts[a][idx[a]]) for a in range(3)]
        chunk[idx] = dask.delayed(_label_chunk, pure=True)(blocks[idx], specs, off,
                                                           arr.shape, order, measure)
        borders = [[(bg and idx[a] == 0, bg and idx[a] == grid[a] - 1) for a in range(3)]
                   for _, bg in specs]
        summ.append(dask.delayed(_chunk_summary, pure=True)(chunk[idx], flat[idx], borders))
        rims[idx] = dask.delayed(_chunk_rims, pure=True)(chunk[idx])
    sums = []
    for idx in np.ndindex(*grid) if measure else ():
        nbrs = {}
        for e in np.ndindex(2, 2, 2):
            j = tuple(idx[a] + e[a] for a in range(3))
            if any(e) and all(j[a] < grid[a] for a in range(3)):
                nbrs[e] = chunk[j]
        core = [int(arr.chunks[a][idx[a]]) for a in range(3)]
        off = [int(starts[a][idx[a]]) for a in range(3)]
        sums.append(dask.delayed(_halo_sums, pure=True)(chunk[idx], nbrs, core, off))
    pairs = []
    for idx in np.ndindex(*grid):
        for a in range(3):
            if idx[a] + 1 >= grid[a]:
                continue
            hi = list(idx)
            hi[a] += 1
            o = [i for i in range(3) if i != a]
            nb, nf = {}, {}
            for du, dv in _shifts(reach):
                if not du and not dv:
                    continue
                j = list(hi)
                j[o[0]] += du
                j[o[1]] += dv
                if 0 <= j[o[0]] < grid[o[0]] and 0 <= j[o[1]] < grid[o[1]]:
                    nb[(du, dv)], nf[(du, dv)] = rims[tuple(j)], flat[tuple(j)]
            pairs.append(dask.delayed(_face_pairs, pure=True)(
                chunk[idx], chunk[tuple(hi)], a, nb, flat[idx], flat[tuple(hi)], nf, conns))
    forests = _tree(pairs, fn=_forests) if pairs else [np.zeros((0, 2), dtype=np.int64)] * \
        len(specs)
    return dask.delayed(_finish_all, pure=True)(summ, forests, [bg for _, bg in specs], sums)


class _Merged:
    """The final merge's result, kept on the cluster (persisted) and
    broadcast to the relabel tasks: lut maps global labels (chunk base +
    local label) to final ones; bases per chunk in flat order; n
    components with their sizes."""

    def __init__(self, lut, bases, n, sizes):
        self.lut, self.bases, self.n, self.sizes = lut, bases, n, sizes


def _relabel_block(block, merged, conn, background, block_info=None):
    b = np.asarray(block)
    if background:
        b = b == 0
    labels, comps = _vol(b).components(conn)
    info = block_info[0]
    f = int(np.ravel_multi_index(info["chunk-location"], info["num-chunks"]))
    b0 = int(merged.bases[f])
    part = merged.lut[b0:b0 + len(comps) + 1].copy()
    part[0] = 0
    return part[labels]


def _first_merged(res):
    return res[1][0]


def components(arr, conn=26):
    """(labels, n): labels a lazy uint32 Dask array with the chunks of arr
    (0 background, i + 1 for component i, largest first, ties by the first
    voxel in column order: exactly Volume.components()'s labels) and n the
    number of conn-components. The merge runs on the workers: only n comes
    back here; the label lookup stays on the cluster (persisted, one array
    of one entry per chunk label) for the lazy labels. Computing the labels
    labels each chunk again: keeping the first labelling would hold 4 bytes
    per voxel in the workers' memory."""
    arr = _check3(arr)
    conn = _conn(conn)
    merged = dask.delayed(_first_merged, pure=True)(_merge_graph(arr, [(conn, False)]))
    merged, = dask.persist(merged)
    n = int(dask.compute(dask.delayed(getattr)(merged, "n"))[0])
    labels = arr.map_blocks(_relabel_block, merged, conn, False, dtype=np.uint32)
    return labels, n


# ------------------------------------------------------------------ measure

def _i128(v):
    return (v.hi << 64) + v.lo  # lo unsigned, hi signed


def _set_i128(dst, v):
    dst.hi = v >> 64
    dst.lo = v & 0xFFFFFFFFFFFFFFFF


def _measure_sums(vol, core, off):
    s = ffi.new("bvox_measure_sums *")
    check(lib.bvox_measure_part(vol._p, core, off, s))
    return (int(s.count), [_i128(s.s[a]) for a in range(3)], [_i128(s.ss[k]) for k in range(6)],
            list(s.bbox), int(s.euler), list(s.trans))


def _add_sums(parts):
    total = [0, [0] * 3, [0] * 6, None, 0, [0] * 7]
    for c, s, ss, bb, eu, tr in parts:
        total[0] += c
        total[1] = [x + y for x, y in zip(total[1], s)]
        total[2] = [x + y for x, y in zip(total[2], ss)]
        total[4] += eu
        total[5] = [x + y for x, y in zip(total[5], tr)]
        if c:
            total[3] = bb if total[3] is None else (
                [min(x, y) for x, y in zip(total[3][:3], bb[:3])]
                + [max(x, y) for x, y in zip(total[3][3:], bb[3:])])
    return total


def _sub_sums(a, b):
    return (a[0] - b[0], [x - y for x, y in zip(a[1], b[1])],
            [x - y for x, y in zip(a[2], b[2])], a[3], a[4] - b[4],
            [x - y for x, y in zip(a[5], b[5])])


# Why a chunk needs no halo read: bvox_measure_part of the chunk P with its
# one-voxel overlap on the high sides is linear in scans of boxes (see
# measure_part.c), and every box but the first (all of P) lies in the shell
# of P: its overlap planes and the chunk's own last planes. Splitting that
# first scan along x, y, z (scan(A u B) = scan(A) + scan(B) - scan(A n B)
# for boxes sharing a plane) leaves scan(core) plus boxes in the shell. So
# with P~ = P with the core's inside (all but its last planes) cleared,
# part(P) = part(P~) + scan(core) - scan(core~): the chunk task gives the
# difference and its six boundary planes, and a small task per chunk builds
# P~ from its own last planes and the neighbours' first planes. The chunks'
# voxels are released when their task ends; only planes wait for the
# neighbours (a halo read held each whole chunk until its neighbours on the
# high sides were read, at 2048^3 a plane of chunks per worker).

def _chunk_scan(v, b, off):
    """A chunk's part of the measure sums apart from its halo: (scan(core)
    - scan(core with its inside cleared), with core's bbox; its first and
    last planes along x, y, z)."""
    core = list(v.shape)
    sc = _measure_sums(v, core, off)
    d = (0, [0] * 3, [0] * 6, sc[3] if sc[0] else None, 0, [0] * 7)
    if all(c > 1 for c in core):
        t = v.copy()
        t.fill_box((0, 0, 0), [c - 2 for c in core], False)
        d = _sub_sums(sc, _measure_sums(t, core, off))
        d = d[:3] + (sc[3] if sc[0] else None,) + d[4:]
    firsts = (b[0] != 0, b[:, 0] != 0, b[:, :, 0] != 0)
    lasts = (b[-1] != 0, b[:, -1] != 0, b[:, :, -1] != 0)
    return d, firsts, lasts


def _halo_sums(own, nbrs, core, off):
    """A chunk's measure sums: P~ (its last planes, and the first planes of
    its neighbours on the high sides: nbrs[(ex, ey, ez)] their chunk tasks)
    through bvox_measure_part, plus the chunk's own difference."""
    d, _, lasts = own[0]
    over = [any(e[a] for e in nbrs) for a in range(3)]
    p = np.zeros([core[a] + over[a] for a in range(3)], dtype=bool)
    c0, c1, c2 = core
    p[c0 - 1, :c1, :c2] = lasts[0]
    p[:c0, c1 - 1, :c2] = lasts[1]
    p[:c0, :c1, c2 - 1] = lasts[2]
    for e, r in nbrs.items():
        a0 = e.index(1)  # the neighbour's first plane across axis a0
        plane = r[0][1][a0]
        sub = tuple(0 if e[x] else slice(0, core[x]) for x in range(3) if x != a0)
        p[tuple(core[x] if e[x] else slice(0, core[x]) for x in range(3))] = plane[sub]
    h = _measure_sums(_vol(p), core, off)
    return (h[0] + d[0], [x + y for x, y in zip(h[1], d[1])],
            [x + y for x, y in zip(h[2], d[2])], d[3] or [0] * 6, h[4] + d[4],
            [x + y for x, y in zip(h[5], d[5])])


def _topology(res):
    """What measure needs of the final task: the sums and three counts."""
    return res[0], [m.n for m in res[1]]


def _geometry(spacing, unit, origin):
    g = ffi.new("bvox_geometry *", lib.bvox_geometry_default())
    if spacing is not None:
        sp = [float(v) for v in spacing]
        if len(sp) != 3 or not all(v > 0 and math.isfinite(v) for v in sp):
            raise ValueError("bvox.dask: spacing must be three positive numbers, got %r"
                             % (spacing,))
        g.spacing = sp
    if origin is not None:
        g.origin = [float(v) for v in origin]
    if unit:
        u = unit.encode()
        if len(u) >= len(g.unit):
            raise ValueError("bvox.dask: unit %r too long" % unit)
        g.unit = u
    return g


# measure's topology, as bvox_measure's: 26-components, 6-connected cavities
# (background components off the border) and 26-connected ones
_MEASURE_SPECS = [(26, False), (6, True), (26, True)]


def measure(arr, spacing=None, unit=None, origin=None):
    """The dict of Volume.measure() (keys of `bvox measure --json`) of the
    whole array with that geometry. One graph: each chunk read once (with a
    one-voxel overlap on its high sides) gives the exact integer sums of
    what lies on its side of the border and its three labellings (object
    26, background 6 and 26); the merges need only counts, no first voxels."""
    from ._measure import measures_dict
    arr = _check3(arr)
    geom = _geometry(spacing, unit, origin)
    total, ns = dask.compute(dask.delayed(_topology, pure=True)(
        _merge_graph(arr, _MEASURE_SPECS, order=False, measure=True)))[0]
    sums = ffi.new("bvox_measure_sums *")
    sums.count = total[0]
    for a in range(3):
        _set_i128(sums.s[a], total[1][a])
    for k in range(6):
        _set_i128(sums.ss[k], total[2][k])
    sums.bbox = total[3] or [0] * 6
    sums.euler = total[4]
    sums.trans = total[5]
    m = ffi.new("bvox_measures *")
    check(lib.bvox_measure_from_sums(sums, geom, m))
    if m.count:
        # cavities_26 only when there are 6-connected ones (as in memory)
        m.components, m.cavities = ns[0], ns[1]
        m.cavities_26 = ns[2] if ns[1] > 0 else 0
    m.tunnels = m.components + m.cavities - m.euler
    return measures_dict(arr.shape, geom[0], m)


# --------------------------------------------------------------- morphology

def _morph_block(block, op, arg, spacing):
    v = _vol(block, spacing)
    return getattr(v, op)(arg).to_numpy()


def _morph(arr, op, arg, depth, spacing=None):
    arr = _check3(arr)
    return arr.map_overlap(_morph_block, depth=depth, boundary=0, dtype=bool,
                           op=op, arg=arg, spacing=spacing)


def dilate(arr, conn=26):
    """Lazy dilation by the 6-, 18- or 26-neighbourhood (a bool Dask array)."""
    return _morph(arr, "dilate", _conn(conn), 1)


def erode(arr, conn=26):
    """Lazy erosion by the 6-, 18- or 26-neighbourhood; outside counts as 0
    (the border erodes), as Volume.erode."""
    return _morph(arr, "erode", _conn(conn), 1)


def _ball_depth(radius, spacing):
    sp = (1.0, 1.0, 1.0) if spacing is None else tuple(float(v) for v in spacing)
    return {a: int(math.floor(float(radius) / sp[a])) + 1 for a in range(3)}, sp


def dilate_ball(arr, radius, spacing=None):
    """Lazy dilation by a ball of that physical radius (voxel size spacing,
    default 1, 1, 1)."""
    depth, sp = _ball_depth(radius, spacing)
    return _morph(arr, "dilate_ball", float(radius), depth, sp)


def erode_ball(arr, radius, spacing=None):
    depth, sp = _ball_depth(radius, spacing)
    return _morph(arr, "erode_ball", float(radius), depth, sp)


# ---------------------------------------------------------------------- csg

_OPS = {"union": "union", "|": "union", "intersection": "intersection", "&": "intersection",
        "difference": "difference", "-": "difference", "xor": "xor", "^": "xor"}


def _csg_block(a, b, op):
    va = _vol(a)
    va._apply(op, _vol(b), None)  # in place: one bvox_csg_apply
    return va.to_numpy()


def csg(a, b, op):
    """Lazy a op b, chunk by chunk (op: union |, intersection &,
    difference -, xor ^); b is rechunked to a's chunks."""
    a, b = _check3(a), _check3(b)
    if op not in _OPS:
        raise ValueError("bvox.dask: csg op is one of %s, not %r" % (", ".join(_OPS), op))
    if a.shape != b.shape:
        raise ValueError("bvox.dask: csg shapes differ: %r and %r" % (a.shape, b.shape))
    b = b.rechunk(a.chunks)
    return da.map_blocks(_csg_block, a, b, op=_OPS[op], dtype=bool)


# --------------------------------------------------------------------- mesh

def _vkey(g, shape):
    """One int64 per vertex from its doubled index coordinates (-1 .. 2n - 1)."""
    my, mz = 2 * shape[1] + 4, 2 * shape[2] + 4
    return ((g[:, 0] + 2) * my + g[:, 1] + 2) * mz + g[:, 2] + 2


def _mesh_block(block, off, core0, core1, last, shape):
    """Marching cubes of one chunk with its halo, in the whole array's voxel
    indices; only the triangles of the cells this chunk owns (per axis: the
    cell's upper corner plane in [core0, core1), the last chunk also the
    plane past the end; a triangle flat in a plane P belongs to P). Returns
    the used vertices as keys (_vkey) and the triangles as indices into them."""
    v, f = _vol(block).mesh("mc")
    if not len(f):
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3), dtype=np.int32)
    # vertices at edge midpoints or cell centres: 2 v is an integer
    g = np.rint(2 * v).astype(np.int64) + 2 * np.asarray(off, dtype=np.int64)
    t = g[f]  # (m, 3 vertices, 3 axes), doubled coordinates
    lo = t.min(axis=1)
    flat = (t.max(axis=1) == lo) & (lo % 2 == 0)
    owner = np.where(flat, lo // 2, lo // 2 + 1)
    keep = np.ones(len(f), dtype=bool)
    for a in range(3):
        hi_ok = owner[:, a] <= core1[a] if last[a] else owner[:, a] < core1[a]
        keep &= (owner[:, a] >= core0[a]) & hi_ok
    used, inv = np.unique(f[keep], return_inverse=True)
    return _vkey(g[used], shape), inv.reshape(-1, 3).astype(np.int32)


def _mesh_tasks(arr, starts, grid, idxs):
    tasks = []
    for idx in idxs:
        blk, off = _halo_block(arr, starts, idx, 1, 1)
        core0 = [int(starts[a][idx[a]]) for a in range(3)]
        core1 = [int(starts[a][idx[a] + 1]) for a in range(3)]
        last = [idx[a] == grid[a] - 1 for a in range(3)]
        tasks.append(dask.delayed(_mesh_block, pure=True)(blk, off, core0, core1, last,
                                                          arr.shape))
    return tasks


def _weld(parts, shape, spacing, origin):
    """The chunks' parts welded by key: sorted unique keys, their positions,
    and the faces as indices into them."""
    keys = np.concatenate([p[0] for p in parts])
    base = np.concatenate([[0], np.cumsum([len(p[0]) for p in parts])])
    faces = np.concatenate([p[1].astype(np.int64) + b for p, b in zip(parts, base)])
    uniq, inv = np.unique(keys, return_inverse=True)
    my, mz = 2 * shape[1] + 4, 2 * shape[2] + 4
    g2 = np.stack([uniq // (my * mz) - 2, uniq // mz % my - 2, uniq % mz - 2], axis=1)
    g = _geometry(spacing, None, origin)[0]
    verts = g2.astype(np.float64) / 2.0 * np.array(list(g.spacing)) + np.array(list(g.origin))
    return uniq, g2, verts, inv.reshape(-1)[faces].astype(np.int32)


def mesh(arr, spacing=None, origin=None, path=None, format=None, ascii=False):
    """(vertices, faces) of the marching-cubes surface of the whole array,
    meshed chunk by chunk and welded: the same triangles (up to order) as
    Volume.mesh("mc") of a volume with that spacing and origin, and a closed
    surface across chunk borders. The weld (one sort of the chunks' vertex
    keys) and the mesh are on the client.

    With path, the mesh goes to that file instead (STL, PLY, OBJ or OFF by
    the extension unless format; ascii for STL and PLY) and is never held
    whole: the rows of chunks along z are computed one after the other,
    each row welded within itself and against the vertices the row before
    left in their shared plane, written, and forgotten. The client holds one
    row's meshes. The file appears complete or not at all. Returns
    (number of vertices, number of triangles)."""
    arr = _check3(arr)
    starts, grid = _starts(arr.chunks), _grid(arr)
    if path is None:
        parts = dask.compute(*_mesh_tasks(arr, starts, grid, np.ndindex(*grid)))
        _, _, verts, faces = _weld(parts, arr.shape, spacing, origin)
        return verts, faces
    out = ffi.new("bvox_mesh_writer **")
    check(lib.bvox_mesh_writer_open(os.fsencode(path), cstr(format) if format else ffi.NULL,
                                    1 if ascii else 0, out))
    w, commit = out[0], 0
    try:
        seam_keys, seam_g = np.zeros(0, np.int64), np.zeros(0, np.int64)
        nv = 0
        for kz in range(grid[2]):
            idxs = [(i, j, kz) for i in range(grid[0]) for j in range(grid[1])]
            parts = dask.compute(*_mesh_tasks(arr, starts, grid, idxs))
            uniq, g2, verts, faces = _weld(parts, arr.shape, spacing, origin)
            del parts
            z0, z1 = int(starts[2][kz]), int(starts[2][kz + 1])
            # the row's vertices in the plane z0 - 1 were written by the row below
            glob = np.full(len(uniq), -1, dtype=np.int64)
            low = np.nonzero(g2[:, 2] == 2 * (z0 - 1))[0]
            if len(low) and len(seam_keys):
                pos = np.minimum(np.searchsorted(seam_keys, uniq[low]), len(seam_keys) - 1)
                hit = seam_keys[pos] == uniq[low]
                glob[low[hit]] = seam_g[pos[hit]]
            new = glob < 0
            given = glob.copy()  # the file's index of every row vertex
            given[new] = nv + np.arange(int(new.sum()), dtype=np.int64)
            check(lib.bvox_mesh_writer_add(
                w, ffi.from_buffer("double[]", np.ascontiguousarray(verts)), len(verts),
                ffi.from_buffer("int64_t[]", glob), ffi.from_buffer("int32_t[]", faces),
                len(faces)))
            nv += int(new.sum())
            top = g2[:, 2] == 2 * (z1 - 1)  # shared with the next row
            seam_keys, seam_g = uniq[top], given[top]
        counts = ffi.new("int64_t[2]")
        lib.bvox_mesh_writer_counts(w, counts, counts + 1)
        result = (int(counts[0]), int(counts[1]))
        commit = 1
    finally:
        st = lib.bvox_mesh_writer_close(w, commit)
    check(st)
    return result
