/*
 * fuzz_contour_json.c — libFuzzer target for the JSON contour stack reader
 * (bvox_stack_read_json_memory); a stack that reads is exercised (see
 * contour_fuzz_common.h). Nothing may leak: bvox_memory_in_use() is 0 after.
 */
#include "bvox.h"
#include "contour_fuzz_common.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_contour_stack *s = NULL;
    if (bvox_stack_read_json_memory((const char *)data, size, "fuzz.json", &s) == BVOX_OK) {
        exercise_stack(s);
        bvox_stack_destroy(s);
    } else if (s != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
