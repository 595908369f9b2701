#!/bin/sh
# Installs the Debian 12 packages bvox needs to build, test and benchmark.
# Run as root (or with sudo). Idempotent.
set -eu
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# build: compiler, cmake, codecs (libpng, libtiff, zlib)
# tests: mricron-data (real MRI atlas), clang + compiler-rt for the fuzz targets
$SUDO apt-get install -y -qq --no-install-recommends \
    build-essential cmake pkg-config \
    zlib1g-dev libpng-dev libtiff-dev libgif-dev \
    clang libclang-rt-14-dev \
    mricron-data python3 >/dev/null
# benchmarks only (bench/compare_scipy.py; no test needs them): SciPy and
# numpy for the comparison. A failure here does not stop the rest.
$SUDO apt-get install -y -qq --no-install-recommends python3-numpy python3-scipy >/dev/null ||
    echo "install-deps: python3-numpy/python3-scipy not installed (only the SciPy comparison needs them)" >&2
