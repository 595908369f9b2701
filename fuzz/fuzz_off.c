/*
 * fuzz_off.c — libFuzzer target for the OFF mesh reader: the input is the
 * file, read, checked, measured and voxelized by mesh_fuzz_one (see
 * mesh_fuzz_common.h).
 */
#include "mesh_fuzz_common.h"

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return mesh_fuzz_one(data, size, "fuzz.off", "off");
}
