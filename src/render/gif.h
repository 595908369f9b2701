/*
 * gif.h — private animated-GIF writer of src/render/ (turntables), on
 * giflib, streaming each frame into the temp+rename sink of src/io so that a
 * failure leaves no partial file and nothing holds all the frames at once.
 */
#ifndef BVOX_RENDER_GIF_H
#define BVOX_RENDER_GIF_H

#include "render.h"

typedef struct bvox__gif bvox__gif;

/* Start a looping animation of width x height (1..65535) frames shown
 * delay_cs hundredths of a second each. */
bvox_status bvox__gif_open(const char *path, int32_t width, int32_t height, int delay_cs,
                           bvox__gif **out);
/* Add a frame: 8 bits, 1 channel (a gray palette) or 3 (a palette of 256
 * colours made for the frame by median cut), of the size given to open. */
bvox_status bvox__gif_add(bvox__gif *g, const bvox_image *frame);
/* Finish and rename into place (at least one frame needed). Releases g. */
bvox_status bvox__gif_commit(bvox__gif *g);
/* Drop everything, remove the temporary file. Releases g; accepts NULL. */
void bvox__gif_abort(bvox__gif *g);

#endif
