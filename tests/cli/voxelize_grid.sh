#!/bin/sh
# voxelize_grid.sh — `bvox voxelize --like IMAGE` and a grid given in full
# (--dims/--origin/--voxel-size SX,SY,SZ) put the mesh on exactly that grid:
# the voxels equal an independent parity test (the generalised winding
# number of each voxel centre, in Python) on the same grid, here a rotated
# NIfTI grid of 0.7 x 0.9 x 1.3 mm voxels made with nibabel, and an
# axis-aligned anisotropic one.
# Usage: sh voxelize_grid.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

/usr/bin/python3 - "$tmp" <<'PY' || fail "making the mesh and the reference grid"
import sys, numpy as np, nibabel as nib
d = sys.argv[1]
# an irregular octahedron (closed, outward faces), no vertex on a voxel centre
v = np.array([[0.31, 0.17, 9.1], [0.23, -0.11, -8.3], [7.7, 0.41, 0.13], [-6.9, 0.27, -0.21],
              [0.19, 8.2, 0.37], [-0.33, -7.4, 0.29]]) + [1.13, -0.47, 0.71]
f = [(0, 2, 4), (0, 4, 3), (0, 3, 5), (0, 5, 2), (1, 4, 2), (1, 3, 4), (1, 5, 3), (1, 2, 5)]
with open(d + "/oct.obj", "w") as o:
    for p in v: o.write("v %.17g %.17g %.17g\n" % tuple(p))
    for t in f: o.write("f %d %d %d\n" % tuple(i + 1 for i in t))
a, b = np.radians(23), np.radians(-11)
rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
aff = np.eye(4)
aff[:3, :3] = rz @ rx @ np.diag([0.7, 0.9, 1.3])
aff[:3, 3] = [-12.3, -11.1, -9.7]
img = nib.Nifti1Image(np.zeros((33, 31, 17), np.uint8), aff)
img.header.set_xyzt_units("mm")
nib.save(img, d + "/ref.nii")
np.save(d + "/v.npy", v); np.save(d + "/f.npy", np.array(f))
PY
"$BVOX" voxelize "$tmp/oct.obj" --like "$tmp/ref.nii" -o "$tmp/like.nii" >/dev/null ||
    fail "voxelize --like"
"$BVOX" voxelize "$tmp/oct.obj" --dims 25,23,27 --origin -11.5,-8.25,-9.75 --voxel-size 0.9,0.75,0.8 \
    -o "$tmp/grid.nii" >/dev/null || fail "voxelize --dims --origin --voxel-size"
/usr/bin/python3 - "$tmp" <<'PY' || fail "voxels differ from the winding-number reference"
import sys, numpy as np, nibabel as nib
d = sys.argv[1]
v, f = np.load(d + "/v.npy"), np.load(d + "/f.npy")
def inside(p):  # generalised winding number (van Oosterom-Strackee solid angles)
    w = np.zeros(len(p))
    for t in f:
        a, b, c = (v[t[i]] - p for i in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        num = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la \
            + np.einsum("ij,ij->i", c, a) * lb
        w += 2 * np.arctan2(num, den)
    return w / (4 * np.pi) > 0.5
for name, ref in (("like", "ref"), ("grid", None)):
    img = nib.load(d + "/%s.nii" % name)
    if ref:
        r = nib.load(d + "/ref.nii")
        assert img.shape == r.shape, (img.shape, r.shape)
        assert np.allclose(img.affine, r.affine, atol=1e-5), (img.affine, r.affine)
        assert img.header["sform_code"] > 0
    else:
        assert img.shape == (25, 23, 27), img.shape
        assert np.allclose(img.affine[:3, :3], np.diag([0.9, 0.75, 0.8]), atol=1e-6)
        assert np.allclose(img.affine[:3, 3], [-11.5, -8.25, -9.75], atol=1e-6)
    got = np.asarray(img.dataobj) > 0
    ijk = np.indices(got.shape).reshape(3, -1).T
    world = ijk @ img.affine[:3, :3].T + img.affine[:3, 3]
    want = inside(world).reshape(got.shape)
    assert want.sum() > 500, want.sum()
    diff = int((got != want).sum())
    assert diff == 0, "%s: %d voxels differ (%d set, %d expected)" % (name, diff, got.sum(), want.sum())
PY
"$BVOX" voxelize "$tmp/oct.obj" --like "$tmp/ref.nii" --res 10 -o "$tmp/x.nii" 2>/dev/null &&
    fail "--like with --res accepted"
"$BVOX" voxelize "$tmp/oct.obj" --dims 5,5,5 --voxel-size 1 -o "$tmp/x.nii" 2>/dev/null &&
    fail "--dims without --origin accepted"
echo "voxelize_grid: ok"
