#!/bin/sh
# check_alloc.sh ROOT — fails if a heap allocation in ROOT/src or ROOT/viewer
# bypasses the allocation seam (src/core/alloc.c). Every allocation must go
# through bvox__alloc or bvox__mem_*, so the fault-injection tests reach its
# error path. libc functions that allocate behind the caller's back (strdup,
# asprintf, getline, scandir, ...) count too; allocations made inside libpng,
# libtiff, zlib or giflib are out of reach and out of scope.
# With --self-test it plants a raw call in a copy and checks that it is found.
set -u
if [ "${1:-}" = "--self-test" ]; then
    root=$2
    tmp=$(mktemp -d) || exit 2
    trap 'rm -rf "$tmp"' EXIT
    mkdir -p "$tmp/src/core" "$tmp/viewer"
    cp "$root/src/core/alloc.c" "$tmp/src/core/alloc.c"
    printf 'int f(void) { return 0; }\n' > "$tmp/src/ok.c"
    sh "$0" "$tmp" >/dev/null || { echo "check_alloc: a clean tree was refused"; exit 1; }
    for call in 'p = malloc(4);' 'p = calloc(1, 4);' 'q = realloc(p, 8);' 's = strdup(t);' \
                'n = getline(&l, &c, f);' 'asprintf(&s, "%d", 1);' 'n = scandir(d, &l, 0, 0);'; do
        printf 'void g(void) { %s }\n' "$call" > "$tmp/viewer/bad.c"
        if sh "$0" "$tmp" >/dev/null; then
            echo "check_alloc: missed a planted '$call'"
            exit 1
        fi
    done
    echo "check_alloc: self-test ok"
    exit 0
fi
root=${1:-.}
raw='(^|[^A-Za-z0-9_])(malloc|calloc|realloc|reallocarray|aligned_alloc|posix_memalign|valloc|memalign|strdup|strndup|asprintf|vasprintf|getline|getdelim|scandir|open_memstream|realpath|tempnam|get_current_dir_name)[[:space:]]*\('
found=$(grep -rnE --include='*.c' --include='*.h' "$raw" "$root/src" "$root/viewer" |
        grep -v "^$root/src/core/alloc.c:")
if [ -n "$found" ]; then
    echo "$found"
    echo "check_alloc: raw allocation outside src/core/alloc.c; use bvox__alloc or bvox__mem_* (src/core/alloc.h)"
    exit 1
fi
echo "check_alloc: every allocation of src/ and viewer/ goes through src/core/alloc.c"
