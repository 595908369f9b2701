/*
 * fuzz_raw.c — libFuzzer target for the raw reader. A raw file says nothing
 * about itself, so the first 9 bytes of the input play the read options and
 * the rest is the file:
 *   bytes 0-5  nx, ny, nz (uint16 little-endian each; 0 tests "missing dims")
 *   byte  6    element type (mod 12: two values are invalid on purpose)
 *   byte  7    bit 0 big-endian, bits 1-3 binarisation mode (mod 5)
 *   byte  8    offset into the file
 */
#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 9) return 0;
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_read_opts opts = BVOX_READ_OPTS_INIT;
    opts.format = "raw";
    opts.raw_dims.nx = data[0] | data[1] << 8;
    opts.raw_dims.ny = data[2] | data[3] << 8;
    opts.raw_dims.nz = data[4] | data[5] << 8;
    opts.raw_dtype = (bvox_dtype)(data[6] % 12);
    opts.raw_big_endian = data[7] & 1;
    opts.binarize.mode = (bvox_binarize_mode)((data[7] >> 1) % 5);
    opts.binarize.threshold = 1.0;
    opts.binarize.lo = 1.0;
    opts.binarize.hi = 100.0;
    opts.binarize.label = 1.0;
    opts.raw_offset = data[8];
    bvox_volume *vol = NULL;
    if (bvox_read_memory(data + 9, size - 9, "fuzz.raw", &opts, &vol) == BVOX_OK) {
        if (bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
