/*
 * fuzz_nrrd.c — libFuzzer target for the NRRD reader (attached data; a
 * detached "data file" is looked up beside "fuzz.nrrd", i.e. in the current
 * folder, and normally missing), as a binary volume and as a label volume.
 */
#include "label_reader_target.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_label_reader(data, size, "nrrd", "fuzz.nrrd");
}
