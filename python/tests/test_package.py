"""The package itself: the cffi declarations match the headers (regenerated
and compared), the version agrees with the library and the command."""
import os
import subprocess
import sys

import bvox

HERE = os.path.dirname(os.path.abspath(__file__))


def test_cdef_matches_headers():
    gen = os.path.join(HERE, "..", "gen_cdef.py")
    r = subprocess.run([sys.executable, gen, "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_version():
    assert bvox.version() == bvox.__version__
    assert bvox.version().count(".") == 2
    exe = os.environ.get("BVOX_CLI")
    if exe:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
        assert out.startswith("bvox %s " % bvox.version())


def test_error_classes():
    assert issubclass(bvox.InvalidArgument, ValueError)
    assert issubclass(bvox.NotFound, FileNotFoundError)
    assert issubclass(bvox.TooBig, MemoryError)
    for cls in (bvox.InvalidArgument, bvox.OutOfMemory, bvox.IOFailure, bvox.FormatError,
                bvox.TooBig, bvox.NotFound, bvox.Unsupported):
        assert issubclass(cls, bvox.Error)
