"""compare_common.py — what the bench/compare_*.py peer scripts share:
reading the uint8 NIfTI-1 volumes the benchmarks write with --save, timing a
call as the benchmarks time theirs (median of the runs after one untimed
warm-up), and reading a benchmark's JSON lines. Not a script: the
compare_*.py scripts import it from their own folder, whatever the cwd.
numpy is imported where it is needed, so that a script can still say which
package is missing.
"""
import json
import statistics
import struct
import time


def read_nifti_u8(path):
    """A NIfTI-1 .nii of uint8 samples as a uint8 array indexed [z, y, x]."""
    import numpy as np

    with open(path, "rb") as f:
        hdr = f.read(348)
        if struct.unpack_from("<i", hdr, 0)[0] != 348:
            raise ValueError("%s: not a little-endian NIfTI-1 file" % path)
        dim = struct.unpack_from("<8h", hdr, 40)
        dtype, bitpix = struct.unpack_from("<hh", hdr, 70)
        vox_offset = int(struct.unpack_from("<f", hdr, 108)[0])
        if (dtype, bitpix) != (2, 8):
            raise ValueError("%s: datatype %d, expected uint8" % (path, dtype))
        nx, ny, nz = dim[1], dim[2], dim[3]
        f.seek(vox_offset)
        data = np.frombuffer(f.read(nx * ny * nz), dtype=np.uint8)
    return data.reshape(nz, ny, nx)


def timed(runs, fn):
    """(median ms of `runs` calls of fn after one untimed warm-up call, the
    last call's result)."""
    fn()  # warm-up, as the benchmarks do
    times = []
    out = None
    for _ in range(runs):
        t = time.perf_counter()
        out = fn()
        times.append((time.perf_counter() - t) * 1e3)
    return statistics.median(times), out


def json_lines(path):
    """The JSON objects of a benchmark's output, one a line (other lines
    are passed over)."""
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line.startswith("{"):
                yield json.loads(line)


def bench_by_op(path):
    """A benchmark's lines that time an operation ("op" and "ms"), keyed
    by (op, n, pattern)."""
    return {(o["op"], o["n"], o["pattern"]): o for o in json_lines(path)
            if "op" in o and "ms" in o}
