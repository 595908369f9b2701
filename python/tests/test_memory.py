"""Memory and threads: a 1024^3 volume (512^3 when the machine has less
than 6 GiB available) goes from NumPy to bvox and back without a
byte-per-voxel copy on the bvox side: the library's memory budget is set to
the volume's words plus 1 MiB, so any such buffer would fail with TooBig, and
tracemalloc (which sees NumPy's allocations) shows no copy on the Python
side either. Long calls release the GIL; volumes work from several threads."""
import threading
import time
import tracemalloc

import numpy as np
import pytest

import bvox


def _proc_kib(path, key):
    """The value of a "Key:   N kB" line of a /proc file, in bytes (0 if none)."""
    with open(path) as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


def _available_bytes():
    return _proc_kib("/proc/meminfo", "MemAvailable")


def test_large_round_trip_without_copy():
    n = 1024 if _available_bytes() > 6 << 30 else 512
    a = np.zeros((n, n, n), dtype=bool)
    a[:, ::3, 100:n - 50:7] = True
    a[n // 2, :, :] = True
    want = int(np.count_nonzero(a))
    words_bytes = n * n * ((n + 63) // 64) * 8

    budget = bvox.memory_budget()
    before = bvox.memory_in_use()
    bvox.set_memory_budget(before + words_bytes + (1 << 20))
    try:
        tracemalloc.start()
        v = bvox.Volume.from_numpy(a)
        _, peak_in = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert peak_in < 1 << 20  # no copy of the array on the Python side
        used = bvox.memory_in_use() - before
        assert words_bytes <= used < words_bytes + (1 << 20)  # one bit per voxel
        assert v.count() == want

        tracemalloc.start()
        b = v.to_numpy()
        _, peak_out = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert peak_out < a.nbytes + (1 << 20)  # the result array, nothing more
        assert bvox.memory_in_use() - before == used
    finally:
        bvox.set_memory_budget(budget)
    assert np.array_equal(a, b)
    v.close()
    assert bvox.memory_in_use() == before


def test_gil_released_during_long_calls():
    v = bvox.demo()
    done = threading.Event()

    start = time.perf_counter()

    def work():
        # long enough to tell on any machine: repeat until 0.3 s have passed
        while time.perf_counter() - start < 0.3:
            v.dilate_ball(40.0).close()
        done.set()

    t = threading.Thread(target=work)
    t.start()
    spins = 0
    while not done.is_set():
        spins += 1  # runs only while the worker is inside the library without the GIL
    t.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.05, "the work was too short to tell"
    assert spins > 1000


def test_threads_on_distinct_volumes(rng):
    from scipy import ndimage
    masks = [rng.random((40, 30, 70)) < 0.3 for _ in range(4)]
    results = [None] * 4

    def work(i):
        results[i] = bvox.Volume.from_numpy(masks[i]).dilate(conn=6).to_numpy()

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    s = ndimage.generate_binary_structure(3, 1)
    for m, r in zip(masks, results):
        assert np.array_equal(r, ndimage.binary_dilation(m, s))


def _rss_bytes():
    return _proc_kib("/proc/self/status", "VmRSS")


def test_memory_trim_returns_cached_buffers():
    # a freed volume's 64 MiB of words stay mapped for the next volume to
    # reuse (not counted in memory_in_use); memory_trim unmaps them
    bvox.memory_trim()
    before = bvox.memory_in_use()
    v = bvox.Volume((512, 1024, 1024))
    v.complement()  # writes every word: the pages are resident
    words = 1024 * 1024 * (512 // 64) * 8
    assert bvox.memory_in_use() - before == words
    v.close()
    assert bvox.memory_in_use() == before
    held = _rss_bytes()
    bvox.memory_trim()
    assert held - _rss_bytes() >= words // 2
    # and the cache gives a buffer back that reads as zeros
    w = bvox.Volume((512, 1024, 1024))
    assert w.count() == 0
    w.close()
