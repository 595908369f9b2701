# common.sh — helpers shared by the CLI scripts; source it after setting BVOX,
# tmp (a scratch folder) and fail().

# mk NAME NX NY NZ PYEXPR [read options]: $tmp/NAME.nii whose voxel (x, y, z)
# is 1 where the Python expression PYEXPR holds, through raw u8 bytes and
# `bvox convert`.
mk() {
    name=$1 nx=$2 ny=$3 nz=$4 expr=$5
    shift 5
    python3 - "$tmp/$name.raw" "$nx" "$ny" "$nz" "$expr" <<'PY'
import sys
out, nx, ny, nz, expr = sys.argv[1], *map(int, sys.argv[2:5]), sys.argv[5]
f = eval("lambda x, y, z: " + expr)
open(out, "wb").write(bytes(1 if f(x, y, z) else 0
                            for z in range(nz) for y in range(ny) for x in range(nx)))
PY
    "$BVOX" convert "$tmp/$name.raw" "$tmp/$name.nii" --dims "$nx,$ny,$nz" --type u8 "$@" ||
        fail "making $name.nii"
}

# jcheck FILE PYEXPR: PYEXPR, about o (the one line of JSON in FILE), holds.
# near(a, b) compares numbers or nested lists (relative 1e-9, absolute
# 1e-12); near(a, b, tol) allows tol * max(1, |b|).
jcheck() {
    python3 - "$@" <<'PY' || return 1
import json, math, sys
path, expr = sys.argv[1:]
text = open(path).read()
assert text.count("\n") == 1, "not one line of JSON: %r" % text[:200]
o = json.loads(text)
def near(a, b, tol=None):
    if isinstance(b, list):
        return isinstance(a, list) and len(a) == len(b) and all(near(x, y, tol) for x, y in zip(a, b))
    if a is None:
        return False
    if tol is not None:
        return abs(a - b) <= tol * max(1.0, abs(b))
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
if not eval(expr):
    sys.exit("%s: %s is false for %s" % (path, expr, text.strip()[:600]))
PY
}

# need_python_zarr: Debian's python3-zarr (with numcodecs) is importable by
# /usr/bin/python3, or the script fails saying what to install.
need_python_zarr() {
    /usr/bin/python3 -c 'import zarr, numcodecs' 2>/dev/null && return 0
    echo "python3-zarr missing (scripts/install-deps.sh installs it)" >&2
    exit 1
}
