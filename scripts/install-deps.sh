#!/bin/sh
# Installs the Debian 12 packages bvox needs to build, test and benchmark.
# Run as root (or with sudo). Idempotent.
set -eu
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# build: compiler, cmake, codecs (libpng, libtiff, zlib, blosc for OME-Zarr chunks)
# tests: mricron-data (real MRI atlas), clang + compiler-rt for the fuzz targets
$SUDO apt-get install -y -qq --no-install-recommends \
    build-essential cmake pkg-config \
    zlib1g-dev libpng-dev libtiff-dev libgif-dev libblosc-dev \
    clang libclang-rt-14-dev \
    mricron-data python3 python3-numpy python3-tifffile python3-zarr python3-numcodecs >/dev/null
# tests: libcgal-demo for CGAL's data sets (data.tar.gz: the bunny mesh the
# mesh tests voxelize, extracted by tests/setup_meshdata.sh)
$SUDO apt-get install -y -qq --no-install-recommends libcgal-demo >/dev/null
# the viewer (bvox view): SDL2 for its window; xvfb + xauth so that the tests
# (tests/cli/view.sh, through xvfb-run) open the real window without a display
$SUDO apt-get install -y -qq --no-install-recommends libsdl2-dev xvfb xauth >/dev/null
# the Python package (python/) and its tests: cffi loads libbvox, NumPy arrays
# in and out; pytest, SciPy (the oracle for morphology and labelling),
# nibabel (NIfTI geometry), PIL (reading PNGs back); venv, pip and setuptools
# for `pip install --no-build-isolation ./python` (the python.pip_install test)
$SUDO apt-get install -y -qq --no-install-recommends \
    python3-cffi python3-numpy python3-scipy python3-pytest python3-nibabel python3-pil \
    python3-venv python3-pip python3-setuptools >/dev/null
# benchmarks only (bench/compare_scipy.py; no test needs them): SciPy and
# numpy for the comparison. A failure here does not stop the rest.
$SUDO apt-get install -y -qq --no-install-recommends python3-numpy python3-scipy >/dev/null ||
    echo "install-deps: python3-numpy/python3-scipy not installed (only the SciPy comparison needs them)" >&2
# benchmarks only (bench/compare_vtk.py): VTK's flying edges and voxelizer,
# scikit-image's marching cubes, the peers of bench_mesh.
$SUDO apt-get install -y -qq --no-install-recommends python3-vtk9 python3-skimage >/dev/null ||
    echo "install-deps: python3-vtk9/python3-skimage not installed (only bench/compare_vtk.py needs them)" >&2
