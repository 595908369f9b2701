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
    zlib1g-dev libpng-dev libtiff-dev \
    clang libclang-rt-14-dev \
    mricron-data python3 >/dev/null
