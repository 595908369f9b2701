/*
 * font5x7.h — the built-in 5x7 bitmap font (font5x7.c): text drawn into an
 * 8-bit image of 1, 3 or 4 channels at an integer scale, clipped to it.
 */
#ifndef BVOX_COMMON_FONT5X7_H
#define BVOX_COMMON_FONT5X7_H

#include "bvox.h"

/* Cell height at scale 1 (7 rows of glyph, 2 of spacing). */
#define BVOX_FONT_CELL_H 9

/* The 5 column bytes of c's glyph (bit 0 the top row); '?' for a
 * character outside printable ASCII. The viewer's overlay draws these too. */
const uint8_t *bvox__font_glyph(unsigned char c);
/* Width in pixels of text drawn at scale (no trailing spacing). */
int32_t bvox__text_width(const char *text, int scale);
/* Draw text (ASCII; others show as '?') with its top left at (x, y), in rgb
 * (gray images: its luma; RGBA: opaque). */
void bvox__text_draw(bvox_image *img, int32_t x, int32_t y, int scale, const char *text,
                     const uint8_t rgb[3]);

#endif
