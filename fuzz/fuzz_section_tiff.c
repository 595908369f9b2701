/*
 * fuzz_section_tiff.c — libFuzzer target for the TIFF section image reader
 * of the reconstruction (src/recon/section_tiff.c: libtiff on a memory
 * buffer, first page to 8/16-bit gray): the input is the file. A small
 * memory budget refuses huge claimed sizes quickly; a successful read must
 * give a gray image of a valid size, a failed one must leave *out NULL, and
 * every budgeted byte must be released afterwards.
 */
#include "recon/section_internal.h"

#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_image *img = NULL;
    if (bvox__section_tiff_decode(data, size, "fuzz.tif", &img) == BVOX_OK) {
        if (!img || img->channels != 1 || (img->bits != 8 && img->bits != 16) || img->width < 1 ||
            img->height < 1)
            abort();
        bvox_image_destroy(img);
    } else if (img != NULL) {
        abort();
    }
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
