#!/usr/bin/python3
"""bench_dask.py — bvox.dask on a LocalCluster of worker processes: an N^3
specimen (a lattice of balls, a quarter of them hollow, joined along x by bars
that cross the chunk borders) generated chunk by chunk and written as a Zarr
array with zarr-python, then read with dask.array.from_zarr and run through
count, measure, 26-connected components (the count n, and the labels computed
and reduced on the workers), dilate, a CSG difference and the mesh. One JSON
line per step: seconds, voxels per second, voxels per second per worker.

    BVOX_LIBRARY=build/libbvox.so.0 PYTHONPATH=python \\
        /usr/bin/python3 bench/bench_dask.py --size 512 --chunks 128 --workers 2
    ... --quick        # 96^3, and every answer checked against the in-memory one
    ... --no-mesh      # skip the mesh step
    ... --zarr DIR.zarr --chunks 256 --steps count,components,measure
                       # an existing OME-Zarr (bench_scale --keep writes one;
                       # level 0 is read), its storage chunks grouped into
                       # dask chunks of 256^3; only the steps named. Each
                       # line then also gives the peak resident memory of
                       # every process (client, workers), and a first step
                       # "read" times reading and decompressing every chunk
                       # with no compute (the other steps include it).
"""
import argparse
import json
import os
import resource
import shutil
import sys
import tempfile
import time

import numpy as np


def specimen_block(block_info=None):
    """The specimen's voxels in one chunk, from its global position."""
    info = block_info[None]
    (x0, x1), (y0, y1), (z0, z1) = info["array-location"]
    n = info["shape"][0]
    x, y, z = np.ogrid[x0:x1, y0:y1, z0:z1]
    step = n / 8.0
    r = n / 20.0
    out = np.zeros((x1 - x0, y1 - y0, z1 - z0), dtype=np.uint8)
    # nearest lattice centre per axis
    cx = (np.floor(x / step) + 0.5) * step
    cy = (np.floor(y / step) + 0.5) * step
    cz = (np.floor(z / step) + 0.5) * step
    d2 = (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2
    ball = d2 <= r * r
    hollow = ((np.floor(x / step) + np.floor(y / step) + np.floor(z / step)) % 4 == 0)
    ball &= ~(hollow & (d2 <= (r - 3) ** 2))
    bar = ((y - cy) ** 2 + (z - cz) ** 2 <= (r / 4) ** 2) & (np.floor(y / step) % 2 == 0)
    out[ball | bar] = 1
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--chunks", type=int, default=128)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--dir", default=tempfile.gettempdir())
    ap.add_argument("--scheduler", help="a running scheduler's address (tcp://host:8786) "
                    "instead of a LocalCluster")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-mesh", action="store_true", help="skip the mesh (its weld runs on "
                    "the client and holds every triangle)")
    ap.add_argument("--zarr", help="an existing OME-Zarr group or array to read instead of "
                    "writing the specimen")
    ap.add_argument("--steps", default="count,measure,components,dilate,csg,mesh",
                    help="comma-separated steps to run (with --zarr: read is added first)")
    args = ap.parse_args()
    if args.quick:
        args.size, args.chunks = 96, 37

    import dask.array as da
    import distributed
    import zarr

    import bvox
    import bvox.dask as bd

    here = os.path.dirname(os.path.abspath(__file__))
    os.environ["PYTHONPATH"] = os.path.join(here, "..", "python") + os.pathsep + \
        os.environ.get("PYTHONPATH", "")
    if args.scheduler:
        client = distributed.Client(args.scheduler)
        cluster = None
        workers = len(client.scheduler_info()["workers"])
    else:
        cluster = distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                           processes=True, dashboard_address=None,
                                           host="127.0.0.1")
        client = distributed.Client(cluster)
        workers = args.workers
    n, c = args.size, args.chunks
    steps = set(args.steps.split(","))
    work = tempfile.mkdtemp(prefix="bench_dask.", dir=args.dir)
    path = os.path.join(work, "specimen.zarr")
    if args.zarr:  # an existing group: its level 0, or an array
        path = args.zarr
        if os.path.exists(os.path.join(path, "0", ".zarray")):
            path = os.path.join(path, "0")
        n = zarr.open(path, mode="r").shape[0]
    vox = n ** 3

    def peaks():
        """Peak resident memory (MiB) of the client and of each worker."""
        def mib():
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        w = client.run(mib)
        return {"peak_rss_mib_client": round(mib(), 1),
                "peak_rss_mib_workers": [round(v, 1) for v in w.values()]}

    def line(step, seconds, **extra):
        d = {"bench": "dask", "step": step, "size": n, "chunks": c, "workers": workers,
             "seconds": round(seconds, 3), "voxels_per_s": vox / seconds,
             "voxels_per_s_per_worker": vox / seconds / workers}
        d.update(extra)
        if args.zarr:
            d.update(peaks())
        print(json.dumps(d), flush=True)

    def read_only(block):
        return np.full((1, 1, 1), block.dtype.itemsize, dtype=np.int64)

    try:
        if args.zarr:
            a = da.from_zarr(path, chunks=(c, c, c))
            t = time.perf_counter()
            per = a.map_blocks(read_only, chunks=tuple((1,) * len(k) for k in a.chunks),
                               dtype=np.int64)
            per.sum().compute()
            line("read (chunk files + decompress, no compute)", time.perf_counter() - t)
        else:
            t = time.perf_counter()
            spec = da.map_blocks(specimen_block,
                                 chunks=((c,) * (n // c) + ((n % c,) if n % c else ()),) * 3,
                                 dtype=np.uint8)
            z = zarr.open(path, mode="w", shape=(n, n, n), chunks=(c, c, c), dtype="u1")
            da.store(spec, z, lock=False)
            line("write (generate + zarr)", time.perf_counter() - t)
            a = da.from_zarr(path)

        if "count" in steps:
            t = time.perf_counter()
            count = bd.count(a)
            line("count", time.perf_counter() - t, count=count)
        if "components" in steps:
            t = time.perf_counter()
            labels, ncomp = bd.components(a, conn=26)
            t1 = time.perf_counter()
            line("components (26): n", t1 - t, n=ncomp)
            largest = int((labels == 1).sum().compute())
            line("components (26): labels", time.perf_counter() - t1, largest=largest)
            del labels
        if "measure" in steps:
            t = time.perf_counter()
            m = bd.measure(a)
            line("measure", time.perf_counter() - t, count=m["count"], euler=m["euler"],
                 components=m["components"], cavities=m["cavities"],
                 cavities_26=m["cavities_26"], tunnels=m["tunnels"])
        if "dilate" in steps:
            t = time.perf_counter()
            dil = int(bd.dilate(a, 26).sum().compute())
            line("dilate (26)", time.perf_counter() - t, count=dil)
        if "csg" in steps:
            t = time.perf_counter()
            diff = int(bd.csg(a, bd.erode(a, 6), "-").sum().compute())
            line("csg a - erode(a)", time.perf_counter() - t, count=diff)
        if not args.no_mesh and "mesh" in steps:
            t = time.perf_counter()
            v, f = bd.mesh(a)
            line("mesh", time.perf_counter() - t, vertices=len(v), triangles=len(f))

        if args.quick:  # the answers against the in-memory ones
            vol = bvox.Volume.from_numpy(np.asarray(z[:]))
            assert count == vol.count()
            want = vol.measure()
            assert (m["count"], m["euler"], m["components"], m["cavities"], m["cavities_26"]) == \
                (want["count"], want["euler"], want["components"], want["cavities"],
                 want["cavities_26"])
            wl, wc = vol.components(26)
            assert ncomp == len(wc) and largest == int((wl == 1).sum())
            assert dil == vol.dilate(26).count()
            assert diff == (vol - vol.erode(6)).count()
            v0, f0 = vol.mesh("mc")
            assert len(v) == len(v0) and len(f) == len(f0)
            print(json.dumps({"bench": "dask", "check": "in-memory answers equal"}))
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
