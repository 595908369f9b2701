/*
 * mosaic.c — Picture 4 of the paper: the binary data set as the frame buffer
 * held it. The paper stored a 128^3 volume in one 512 x 512 8-bit frame
 * buffer, 8 consecutive slices per byte, as 4 x 4 sections of 128 x 128, and
 * chose the slices on screen through the output lookup table.
 *
 * The volume already packs the slices along z, 64 to a word: byte k of word
 * w of column (x, y) holds slices 64 w + 8 k .. + 7, which is exactly pixel
 * (x, y) of section s = 8 w + k. So each column's words are read once, whole,
 * and their 8 bytes go through the display table straight to the 8 sections
 * they belong to; zero words (most of them, outside the object) are skipped.
 */
#include "render.h"

#include <string.h>

static const char *const display_names[] = {"count", "any", "bytes"};
#define NDISPLAYS (int)(sizeof display_names / sizeof display_names[0])

const char *bvox_mosaic_display_name(bvox_mosaic_display display)
{
    return (unsigned)display < (unsigned)NDISPLAYS ? display_names[display] : "unknown";
}

int bvox_mosaic_display_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < NDISPLAYS; i++)
        if (!strcmp(name, display_names[i])) return i;
    return -1;
}

bvox_status bvox_mosaic_lut(uint8_t planes, bvox_mosaic_display display, bvox_lut *lut)
{
    if (!lut) return bvox__fail(BVOX_EINVAL, "mosaic: no table");
    if ((unsigned)display >= (unsigned)NDISPLAYS)
        return bvox__fail(BVOX_EINVAL, "mosaic: unknown display %d", (int)display);
    const unsigned selected = bvox__popcount64(planes);
    for (unsigned b = 0; b < 256; b++) {
        unsigned m = b & planes;
        uint8_t v;
        if (display == BVOX_MOSAIC_BYTES) v = (uint8_t)m;
        else if (display == BVOX_MOSAIC_ANY) v = m ? 255 : 0;
        else v = selected ? (uint8_t)((255 * bvox__popcount64(m) + selected / 2) / selected) : 0;
        lut->value[b] = v;
    }
    return BVOX_OK;
}

typedef struct mosaic_ctx {
    const bvox_volume *v;
    const uint8_t *lut;
    int64_t sections, columns;
    size_t width; /* of the image */
    uint8_t *pixels;
} mosaic_ctx;

static void mosaic_rows(void *arg, int64_t y0, int64_t y1)
{
    const mosaic_ctx *m = arg;
    const bvox_volume *v = m->v;
    for (int32_t y = (int32_t)y0; y < (int32_t)y1; y++)
        for (int32_t x = 0; x < v->nx; x++) {
            const uint64_t *col = bvox__column_c(v, x, y);
            for (size_t w = 0; w < v->wpc; w++) {
                uint64_t word = col[w];
                if (!word) continue; /* every table maps byte 0 to 0 */
                for (int64_t k = 0, s = (int64_t)w * 8; k < 8 && s < m->sections; k++, s++) {
                    size_t row = (size_t)(s / m->columns) * (size_t)v->ny + (size_t)y;
                    size_t at = row * m->width + (size_t)(s % m->columns) * (size_t)v->nx +
                                (size_t)x;
                    m->pixels[at] = m->lut[(word >> (8 * k)) & 0xff];
                }
            }
        }
}

bvox_status bvox_mosaic(const bvox_volume *vol, const bvox_mosaic_opts *opts, bvox_image **out)
{
    BVOX_CHECK_VOLUME(vol);
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "mosaic: no volume");
    const bvox_mosaic_opts def = BVOX_MOSAIC_OPTS_INIT;
    if (!opts) opts = &def;
    bvox_lut lut;
    bvox_status st = bvox_mosaic_lut(opts->planes, opts->display, &lut);
    if (st) return st;
    if (opts->columns < 0)
        return bvox__fail(BVOX_EINVAL, "mosaic: columns must be >= 0 (0: a square grid)");
    bvox__clear_error();
    const int64_t sections = ((int64_t)vol->nz + 7) / 8;
    int64_t columns = opts->columns;
    if (!columns)
        while (columns * columns < sections) columns++;
    const int64_t rows = (sections + columns - 1) / columns;
    const int64_t width = columns * vol->nx, height = rows * vol->ny;
    if (width > BVOX_IMAGE_MAX_DIM || height > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL,
                          "mosaic: %lld x %lld sections of %d x %d pixels exceed the image "
                          "limit of %d pixels a side",
                          (long long)columns, (long long)rows, (int)vol->nx, (int)vol->ny,
                          BVOX_IMAGE_MAX_DIM);
    st = bvox_image_create((int32_t)width, (int32_t)height, 1, 8, out);
    if (st) return st;
    mosaic_ctx m = {vol, lut.value, sections, columns, (size_t)width, (*out)->pixels};
    bvox__parallel_for(vol->ny, 16, mosaic_rows, &m);
    BVOX_CHECK_IMAGE(*out);
    return BVOX_OK;
}
