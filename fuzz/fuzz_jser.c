/*
 * fuzz_jser.c — libFuzzer target for the PyReconstruct .jser reader
 * (bvox_stack_read_jser_memory), all objects and then object "d" only; a
 * stack that reads is exercised (see contour_fuzz_common.h). Nothing may
 * leak: bvox_memory_in_use() is 0 after.
 */
#include "bvox.h"
#include "contour_fuzz_common.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    static const char *const objects[2] = {NULL, "d"};
    for (int k = 0; k < 2; k++) {
        bvox_contour_stack *s = NULL;
        if (bvox_stack_read_jser_memory((const char *)data, size, "fuzz.jser", objects[k], &s) ==
            BVOX_OK) {
            exercise_stack(s);
            bvox_stack_destroy(s);
        } else if (s != NULL) {
            abort();
        }
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
