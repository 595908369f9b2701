/*
 * fuzz_tiff.c — libFuzzer target for the TIFF stack reader (libtiff on a
 * memory buffer): the input is the file.
 * The memory budget is small so that a header claiming a huge volume is
 * refused quickly instead of making the fuzzer allocate gigabytes; a
 * successful read must pass the invariant checker, a failed one must leave
 * *out NULL, and every budgeted byte must be released afterwards.
 */
#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_read_opts opts = BVOX_READ_OPTS_INIT;
    opts.format = "tiff";
    bvox_volume *vol = NULL;
    if (bvox_read_memory(data, size, "fuzz.tif", &opts, &vol) == BVOX_OK) {
        if (bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
