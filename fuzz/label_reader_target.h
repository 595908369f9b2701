/*
 * label_reader_target.h — the body shared by the fuzz targets of readers
 * that give both binary and label volumes (NRRD, MetaImage): read the input
 * as format, once as a binary volume and once split into labels; every result
 * must pass the invariant checks and every byte of the budget come back.
 * A detached data file is looked up beside name, i.e. in the current folder,
 * and is normally missing.
 */
#ifndef BVOX_FUZZ_LABEL_READER_TARGET_H
#define BVOX_FUZZ_LABEL_READER_TARGET_H

#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>

static int fuzz_label_reader(const uint8_t *data, size_t size, const char *format,
                             const char *name)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_read_opts opts = BVOX_READ_OPTS_INIT;
    opts.format = format;
    bvox_volume *vol = NULL;
    if (bvox_read_memory(data, size, name, &opts, &vol) == BVOX_OK) {
        if (bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol != NULL) {
        abort();
    }
    bvox_labelset *set = NULL;
    if (bvox_labels_read_memory(data, size, name, &opts, 1000, &set) == BVOX_OK) {
        for (int64_t i = 0; i < set->n; i++)
            if (bvox_volume_check(set->objects[i].volume) != BVOX_OK) abort();
        bvox_labelset_destroy(set);
    } else if (set != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}

#endif
