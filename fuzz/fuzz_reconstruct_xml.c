/*
 * fuzz_reconstruct_xml.c — libFuzzer target for the Reconstruct section
 * reader (bvox_stack_read_reconstruct_section_memory). The input is split at
 * the first NUL byte into two section files appended to one stack (the
 * second exercises appending, z chaining and the pixel scale of a stack that
 * already exists); a stack that reads is exercised (contour_fuzz_common.h).
 */
#include "bvox.h"
#include "contour_fuzz_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    const uint8_t *nul = memchr(data, 0, size);
    size_t first = nul ? (size_t)(nul - data) : size;
    bvox_contour_stack *s = NULL;
    bvox_status st = bvox_stack_read_reconstruct_section_memory((const char *)data, first,
                                                                "fuzz.1", &s);
    if (st != BVOX_OK && s != NULL) abort();
    if (st == BVOX_OK && nul) {
        int32_t before = s->nsections;
        st = bvox_stack_read_reconstruct_section_memory((const char *)nul + 1, size - first - 1,
                                                        "fuzz.2", &s);
        if (s == NULL || (st != BVOX_OK && s->nsections != before)) abort();
        st = BVOX_OK;
    }
    if (s) {
        exercise_stack(s);
        bvox_stack_destroy(s);
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
