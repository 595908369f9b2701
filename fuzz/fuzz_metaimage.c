/*
 * fuzz_metaimage.c — libFuzzer target for the MetaImage reader (LOCAL data; a
 * detached ElementDataFile is looked up beside "fuzz.mha", i.e. in the current
 * folder, and normally missing), as a binary volume and as a label volume.
 */
#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_read_opts opts = BVOX_READ_OPTS_INIT;
    opts.format = "metaimage";
    bvox_volume *vol = NULL;
    if (bvox_read_memory(data, size, "fuzz.mha", &opts, &vol) == BVOX_OK) {
        if (bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol != NULL) {
        abort();
    }
    bvox_labelset *set = NULL;
    if (bvox_labels_read_memory(data, size, "fuzz.mha", &opts, 1000, &set) == BVOX_OK) {
        for (int64_t i = 0; i < set->n; i++)
            if (bvox_volume_check(set->objects[i].volume) != BVOX_OK) abort();
        bvox_labelset_destroy(set);
    } else if (set != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
