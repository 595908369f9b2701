#!/bin/sh
# Fixture for the mesh tests that need a real mesh: extract CGAL's Stanford
# bunny (data/meshes/bunny00.off, 37706 vertices, closed) from Debian's
# libcgal-demo into the build tree, installing the package when it is missing
# (and we may), or fail with a clear message.
#   setup_meshdata.sh DEST_DIR   -> DEST_DIR/meshes/bunny00.off
dest=${1:?usage: setup_meshdata.sh DEST_DIR}
out="$dest/meshes/bunny00.off"
[ -s "$out" ] && exit 0
tarball=/usr/share/doc/libcgal-demo/data.tar.gz
if [ ! -f "$tarball" ] && [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libcgal-demo >/dev/null 2>&1 ||
        { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libcgal-demo >/dev/null; }
fi
[ -f "$tarball" ] || { echo "missing $tarball: install Debian's libcgal-demo (scripts/install-deps.sh)" >&2; exit 1; }
mkdir -p "$dest/meshes" || exit 1
tmp="$out.tmp.$$"
tar -xzOf "$tarball" data/meshes/bunny00.off > "$tmp" && [ -s "$tmp" ] && mv "$tmp" "$out" || {
    rm -f "$tmp"
    echo "cannot extract data/meshes/bunny00.off from $tarball" >&2
    exit 1
}
