#!/bin/sh
# install.sh BUILD_DIR SOURCE_DIR — installs the build into a temporary
# prefix and checks what a user of the library gets: the files, only bvox_
# symbols exported (every BVOX_API declaration among them), the installed
# command running without LD_LIBRARY_PATH, and examples/c/measure_box.c
# built once with pkg-config and once with CMake's find_package(bvox),
# printing the box's known numbers (120 voxels of 0.5 mm: 15 mm^3, faces
# 2 (4*5 + 4*6 + 5*6) / 4 = 37 mm^2).
set -eu
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$tmp/p" >"$tmp/install.log" 2>&1 ||
    { cat "$tmp/install.log"; fail "cmake --install failed"; }
lib=$(dirname "$(find "$tmp/p" -name bvox.pc)")/..
[ -f "$lib/pkgconfig/bvox.pc" ] || fail "no bvox.pc"
for f in include/bvox.h include/bvox/version.h include/bvox/mesh.h bin/bvox; do
    [ -f "$tmp/p/$f" ] || fail "missing $f"
done
[ -f "$lib/cmake/bvox/bvoxConfig.cmake" ] || fail "no CMake package"
shared=0
if [ -e "$lib/libbvox.so.0" ]; then
    shared=1
    [ -L "$lib/libbvox.so" ] || fail "no libbvox.so development link"
    soname=$(readelf -d "$lib/libbvox.so.0" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
    [ "$soname" = libbvox.so.0 ] || fail "soname is '$soname'"
    # exported: exactly the bvox_ functions the headers declare with BVOX_API
    nm -D --defined-only "$lib/libbvox.so.0" | awk '$2 ~ /^[TtDdBbRrVWi]$/ {print $3}' |
        sort >"$tmp/exported"
    if grep -v '^bvox_' "$tmp/exported" | grep -v '^_' >"$tmp/bad"; then
        fail "exports non-bvox symbols: $(head -5 "$tmp/bad" | tr '\n' ' ')"
    fi
    grep -q '^bvox__' "$tmp/exported" && fail "exports internal bvox__ symbols"
    cat "$tmp/p/include/bvox.h" "$tmp/p/include/bvox/"*.h |
        sed -n 's/^BVOX_API[^(]*[ *]\(bvox_[a-z0-9_]*\)(.*/\1/p' | sort -u >"$tmp/declared"
    comm -23 "$tmp/declared" "$tmp/exported" >"$tmp/missing"
    [ -s "$tmp/missing" ] && fail "declared but not exported: $(head -5 "$tmp/missing" | tr '\n' ' ')"
    comm -13 "$tmp/declared" "$tmp/exported" >"$tmp/extra"
    [ -s "$tmp/extra" ] && fail "exported without a BVOX_API declaration: $(head -5 "$tmp/extra" | tr '\n' ' ')"
    # every public function in the headers carries BVOX_API
    if cat "$tmp/p/include/bvox.h" "$tmp/p/include/bvox/"*.h |
        grep -E '^[a-z][a-z0-9_ ]*[ *]bvox_[a-z0-9_]+\(' | grep -v '^typedef' >"$tmp/unmarked"; then
        fail "declarations without BVOX_API: $(head -3 "$tmp/unmarked")"
    fi
    echo "install: $(wc -l <"$tmp/exported") symbols exported, all bvox_"
fi
"$tmp/p/bin/bvox" --version | grep -q "^bvox " || fail "installed bvox does not run"
# manual pages and completion: generated when the command can print them
# (`bvox help --man`, from the table-driven CLI), and then installed
if "$tmp/p/bin/bvox" help --man >/dev/null 2>&1; then
    for f in share/man/man1/bvox.1 share/man/man1/bvox-info.1 share/man/man1/bvox-measure.1 \
             share/bash-completion/completions/bvox; do
        [ -s "$tmp/p/$f" ] || fail "missing $f"
    done
    echo "install: $(ls "$tmp/p/share/man/man1" | wc -l) manual pages, bash completion"
else
    echo "install: bvox has no 'help --man' yet: no manual pages (cmake/gen_docs.cmake hook)"
fi

expect() {
    grep -qx "count 120" "$1" && grep -qx "volume 15 mm^3" "$1" &&
        grep -qx "area_faces 37 mm^2" "$1" && grep -qx "components 1" "$1" ||
        { cat "$1"; fail "$2: wrong output"; }
}

# 1. pkg-config
export PKG_CONFIG_PATH="$lib/pkgconfig"
flags=$(pkg-config --cflags --libs bvox) || fail "pkg-config bvox failed"
[ "$(pkg-config --modversion bvox)" = "$("$tmp/p/bin/bvox" --version | sed 's/^bvox \([^ ]*\).*/\1/')" ] ||
    fail "bvox.pc version differs from the command's"
if [ $shared = 1 ]; then
    # shellcheck disable=SC2086
    cc -std=c11 -Wall -Werror "$src/examples/c/measure_box.c" $flags -o "$tmp/ex_pc" ||
        fail "build with pkg-config failed"
else
    # shellcheck disable=SC2086
    cc -std=c11 -Wall -Werror "$src/examples/c/measure_box.c" $(pkg-config --cflags --libs --static bvox) \
        -o "$tmp/ex_pc" || fail "static build with pkg-config failed"
fi
LD_LIBRARY_PATH="$lib" "$tmp/ex_pc" >"$tmp/out_pc" || fail "pkg-config build does not run"
expect "$tmp/out_pc" pkg-config

# 2. CMake package
cmake -S "$src/examples/c" -B "$tmp/b" -DCMAKE_PREFIX_PATH="$tmp/p" >"$tmp/cmake.log" 2>&1 &&
    cmake --build "$tmp/b" >>"$tmp/cmake.log" 2>&1 || { cat "$tmp/cmake.log"; fail "CMake build failed"; }
"$tmp/b/measure_box" >"$tmp/out_cmake" || fail "CMake build does not run"
expect "$tmp/out_cmake" cmake
echo "install: ok (pkg-config and find_package(bvox) builds ran)"
