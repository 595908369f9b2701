/*
 * fuzz_zarr.c — libFuzzer target for the Zarr metadata parsers: the input is
 * parsed as a .zarray (bvox__zarr_meta_parse) and as a group's .zattrs
 * (bvox__zarr_attrs_parse, at level 0 and 1), through the bounded JSON tree of zarr_json.c.
 * An accepted .zarray must describe a valid 3-D array (shape and chunks in
 * 1..65535, a known dtype, '.' or '/' separator).
 */
#include "io/zarr.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox__zarr_meta m;
    if (bvox__zarr_meta_parse((const char *)data, size, "fuzz/.zarray", &m) == BVOX_OK) {
        for (int a = 0; a < 3; a++)
            if (m.shape[a] < 1 || m.shape[a] > BVOX_MAX_DIM || m.chunks[a] < 1 ||
                m.chunks[a] > BVOX_MAX_DIM)
                abort();
        if (bvox_dtype_size(m.dtype) == 0 || (m.sep != '.' && m.sep != '/')) abort();
    }
    bvox__zarr_attrs at;
    if (bvox__zarr_attrs_parse((const char *)data, size, "fuzz/.zattrs", &at) == BVOX_OK) {
        for (int a = 0; a < 3; a++)
            if (!(at.spacing[a] > 0)) abort();
        if (at.unit[sizeof at.unit - 1] != '\0' || at.path[sizeof at.path - 1] != '\0') abort();
    }
    /* a coarser level: its own dataset's path and scale */
    if (bvox__zarr_attrs_parse_level((const char *)data, size, "fuzz/.zattrs", 1, &at) == BVOX_OK) {
        for (int a = 0; a < 3; a++)
            if (!(at.spacing[a] > 0)) abort();
        if (at.nlevels < 2 || at.path[sizeof at.path - 1] != '\0') abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
