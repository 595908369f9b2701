/*
 * fuzz_metaimage.c — libFuzzer target for the MetaImage reader (LOCAL data; a
 * detached ElementDataFile is looked up beside "fuzz.mha", i.e. in the current
 * folder, and normally missing), as a binary volume and as a label volume.
 */
#include "label_reader_target.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_label_reader(data, size, "metaimage", "fuzz.mha");
}
