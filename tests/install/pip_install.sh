#!/bin/sh
# pip_install.sh PYTHON BUILD_DIR SOURCE_DIR — the README's Python install, on
# a fresh virtual environment that sees Debian's NumPy and cffi
# (--system-site-packages; no package index is reached: --no-index):
#   cmake --install BUILD --prefix VENV    (libbvox.so.0 into VENV/lib)
#   VENV/bin/pip install --no-build-isolation ./python
# then, from another folder and without BVOX_LIBRARY, `import bvox` must load
# the installed package and library and compute a known count.
set -eu
py=$1 build=$2 src=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "pip_install: $*" >&2; exit 1; }

"$py" -m venv --system-site-packages "$tmp/venv" || fail "python3 -m venv failed (python3-venv)"
cmake --install "$build" --prefix "$tmp/venv" >"$tmp/log" 2>&1 || { cat "$tmp/log"; fail "cmake --install"; }
# a copy of python/, so that the build leaves nothing in the source tree
cp -r "$src/python" "$tmp/python"
rm -rf "$tmp/python/build" "$tmp/python/"*.egg-info
(cd "$tmp" && "$tmp/venv/bin/pip" install -q --no-index --no-build-isolation ./python) \
    >"$tmp/log" 2>&1 || { cat "$tmp/log"; fail "pip install --no-build-isolation ./python failed"; }
rm -rf "$tmp/python"
cd "$tmp"
env -u BVOX_LIBRARY "$tmp/venv/bin/python" - "$tmp/venv" <<'PY' || fail "the installed package does not work"
import os, sys
import numpy as np
import bvox
venv = os.path.realpath(sys.argv[1])
assert os.path.realpath(bvox.__file__).startswith(venv), bvox.__file__
a = np.zeros((3, 4, 70), bool)
a[1, 2, 3:68] = True
v = bvox.Volume.from_numpy(a, spacing=(1, 1, 0.5), unit="mm")
assert v.count() == 65 and v.measure()["volume"] == 32.5
assert np.array_equal(v.dilate(conn=6).to_numpy().sum(), 65 * 5 + 2)
print("pip_install: ok, bvox", bvox.version(), "from", os.path.dirname(bvox.__file__))
PY
