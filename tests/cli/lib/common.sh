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
