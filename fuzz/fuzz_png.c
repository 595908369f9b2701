/*
 * fuzz_png.c — libFuzzer target for the PNG slice reader: the input is one PNG
 * file (one slice). Before reading, the target rewrites every chunk's CRC in
 * a copy of the input: otherwise nearly every mutation dies at libpng's CRC
 * check and the fuzzer never reaches the header, transform and size handling
 * that is ours. The memory budget is small so that a header claiming a huge
 * image is refused quickly; a successful read must pass the invariant
 * checker, a failed one must leave *out NULL, and every budgeted byte must be
 * released afterwards.
 */
#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static void fix_crcs(uint8_t *d, size_t size)
{
    size_t pos = 8; /* after the signature */
    while (size >= 12 && pos <= size - 12) {
        uint32_t len = be32(d + pos);
        if (len > size - pos - 12) break;
        uint32_t crc = (uint32_t)crc32(0, d + pos + 4, 4 + len);
        uint8_t *c = d + pos + 8 + len;
        c[0] = (uint8_t)(crc >> 24);
        c[1] = (uint8_t)(crc >> 16);
        c[2] = (uint8_t)(crc >> 8);
        c[3] = (uint8_t)crc;
        pos += 12 + (size_t)len;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy) return 0;
    if (size) memcpy(copy, data, size);
    fix_crcs(copy, size);
    bvox_read_opts opts = BVOX_READ_OPTS_INIT;
    opts.format = "png";
    bvox_volume *vol = NULL;
    if (bvox_read_memory(copy, size, "fuzz.png", &opts, &vol) == BVOX_OK) {
        if (bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol != NULL) {
        abort();
    }
    free(copy);
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
