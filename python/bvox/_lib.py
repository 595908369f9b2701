"""_lib.py — loads libbvox through cffi in ABI mode (no compiler needed at
import) and turns the library's status codes into exceptions.

Which library: $BVOX_LIBRARY if set (a path, e.g. build/libbvox.so.0 for the
tests), else libbvox.so.0 beside this package, under sys.prefix/lib, or
wherever the dynamic loader finds it (an installed bvox).

cffi releases the GIL for every call into the library, so long operations
(reading, morphology, measuring, rendering) let other Python threads run.
The library's error message is thread-local: it is read right after the
failing call, in the same thread.
"""
import os
import sys

from cffi import FFI

ffi = FFI()
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "_cdef.h")) as _f:
    ffi.cdef(_f.read())


def _candidates():
    env = os.environ.get("BVOX_LIBRARY")
    if env:
        return [env]
    here = os.path.dirname(os.path.abspath(__file__))
    names = [os.path.join(here, "libbvox.so.0")]
    for prefix in (sys.prefix, sys.base_prefix, "/usr/local"):
        names.append(os.path.join(prefix, "lib", "libbvox.so.0"))
    names.append("libbvox.so.0")  # the dynamic loader's search path
    return names


def _load():
    tried = []
    for name in _candidates():
        if os.sep in name and not os.path.exists(name):
            tried.append(name + " (missing)")
            continue
        try:
            return ffi.dlopen(name)
        except OSError as e:
            tried.append("%s (%s)" % (name, e))
    raise ImportError("bvox: cannot load libbvox.so.0; set BVOX_LIBRARY to its path. Tried: "
                      + "; ".join(tried))


lib = _load()


class Error(Exception):
    """A failed library call: str(e) is the library's message; e.status the
    numeric bvox_status, e.status_name its token ("BVOX_EFORMAT", ...)."""

    def __init__(self, message, status):
        super().__init__(message)
        self.status = status
        self.status_name = ffi.string(lib.bvox_status_name(status)).decode()


class InvalidArgument(Error, ValueError):
    """BVOX_EINVAL: a bad argument or an out-of-range value."""


class OutOfMemory(Error, MemoryError):
    """BVOX_ENOMEM: an allocation failed."""


class IOFailure(Error, OSError):
    """BVOX_EIO: the operating system refused a read or a write."""


class FormatError(Error, ValueError):
    """BVOX_EFORMAT: corrupt, truncated or unsupported input."""


class TooBig(Error, MemoryError):
    """BVOX_ETOOBIG: dimensions over the limits or the memory budget."""


class NotFound(Error, FileNotFoundError):
    """BVOX_ENOTFOUND: a named file does not exist."""


class Unsupported(Error, NotImplementedError):
    """BVOX_EUNSUPPORTED: a feature this build or format does not have."""


class Canceled(Error):
    """BVOX_ECANCELED: the progress callback asked to stop."""


_ERRORS = {1: InvalidArgument, 2: OutOfMemory, 3: IOFailure, 4: FormatError, 5: TooBig,
           6: NotFound, 7: Unsupported, 8: Canceled}


def errmsg():
    return ffi.string(lib.bvox_errmsg()).decode("utf-8", "replace")


def check(status):
    """Raise the Error subclass of a non-zero status, with the library's message."""
    if status:
        raise _ERRORS.get(status, Error)(errmsg(), status)


def cstr(text):
    """A char[] for a str argument (kept alive by the caller's reference)."""
    return ffi.new("char[]", os.fsencode(text) if isinstance(text, (str, os.PathLike))
                   else bytes(text))
