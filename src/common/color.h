/*
 * color.h — colours named in options (color.c): CSS-style names (red,
 * green, ...) and #rrggbb / #rgb, for `render --color/--background` and
 * whatever else takes a colour.
 */
#ifndef BVOX_COMMON_COLOR_H
#define BVOX_COMMON_COLOR_H

#include <stdint.h>

/* Parse one colour; 0 on success, -1 if text is no colour. Case-insensitive. */
int bvox__color_parse(const char *text, uint8_t rgb[3]);
/* The names known, ", "-separated, for help and error messages. */
const char *bvox__color_names(void);
/* The colour of a label a table does not colour (render, .seg.nrrd): a
 * distinct hue per label, neighbouring labels far apart on the wheel. */
void bvox__label_color(int64_t label, uint8_t rgb[3]);

#endif
