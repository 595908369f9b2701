/*
 * fuzz_svg.c — libFuzzer target for the SVG section reader
 * (bvox_stack_read_svg_memory, with the XML tokenizer under it); a stack
 * that reads is exercised (see contour_fuzz_common.h).
 */
#include "bvox.h"
#include "contour_fuzz_common.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_contour_stack *s = NULL;
    if (bvox_stack_read_svg_memory((const char *)data, size, "fuzz.svg", 0, &s) == BVOX_OK) {
        if (s == NULL || s->nsections != 1) abort();
        exercise_stack(s);
        bvox_stack_destroy(s);
    } else if (s != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
