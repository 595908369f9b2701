"""Progress callbacks for long calls: progress(fraction, stage) is called
during the work (fraction 0..1 never decreasing, 1 once at the end; stage
"read", "dilate", "mesh", ...). An exception raised in it cancels the call
(the library stops at its next check, frees what it holds and writes
nothing) and is raised again from the call. With tqdm:

    bar = tqdm(total=1.0)
    vol.dilate(progress=lambda f, stage: bar.update(f - bar.n))
"""
from ._lib import check, ffi, lib


def call(progress, fn, *args):
    """check(fn(*args)) with progress as the thread's callback meanwhile."""
    if progress is None:
        return check(fn(*args))
    if not callable(progress):
        raise TypeError("bvox: progress must be a callable progress(fraction, stage)")
    caught = []

    @ffi.callback("int(double, const char *, void *)")
    def cb(fraction, stage, user):
        if caught:
            return 1
        try:
            progress(fraction, ffi.string(stage).decode())
        except BaseException as e:  # never across C: raised after the call
            caught.append(e)
            return 1
        return 0

    lib.bvox_set_progress(cb, ffi.NULL)
    try:
        status = fn(*args)
    finally:
        lib.bvox_set_progress(ffi.NULL, ffi.NULL)
    if caught and status:
        raise caught[0]
    return check(status)
