/*
 * section_internal.h — what the files of src/recon/ share: runs of set
 * pixels along bitmap rows joined into components by a union-find (the 2-D
 * cousin of components.c), and small helpers.
 */
#ifndef BVOX_SECTION_INTERNAL_H
#define BVOX_SECTION_INTERNAL_H

#include "internal.h"

/* A run of set pixels x0 <= x < x1 on row y, in component comp (0-based). */
typedef struct bvox__run {
    int32_t y, x0, x1, comp;
} bvox__run;

typedef struct bvox__runs {
    bvox__run *runs;   /* row by row, left to right (malloc) */
    int64_t nruns;
    int32_t ncomp;     /* components, numbered in the order of their first run */
    int64_t *area;     /* pixels per component (malloc, ncomp entries) */
    uint8_t *edge;     /* 1 if the component touches the bitmap's edge (malloc) */
} bvox__runs;

/* Runs of the set pixels (invert: of the clear pixels) and their components
 * (conn 4 or 8). */
bvox_status bvox__runs_label(const bvox_bitmap *bm, int conn, int invert, bvox__runs *out);
void bvox__runs_free(bvox__runs *r);

/* The bitmap's row y. */
static inline uint64_t *bvox__bm_row(bvox_bitmap *bm, int32_t y)
{
    return bm->words + (size_t)y * (size_t)bm->words_per_row;
}
static inline const uint64_t *bvox__bm_row_c(const bvox_bitmap *bm, int32_t y)
{
    return bm->words + (size_t)y * (size_t)bm->words_per_row;
}
/* Mask of the valid bits of a row's last word. */
static inline uint64_t bvox__bm_tail(const bvox_bitmap *bm)
{
    unsigned r = (unsigned)(bm->width & 63);
    return r ? (1ull << r) - 1 : ~0ull;
}
/* Set bits x0 <= x < x1 of a row. */
void bvox__bm_fill_run(uint64_t *row, int32_t x0, int32_t x1, int value);

/* Gray sample (8 or 16 bit, channel 0) at pixel index i. */
static inline int bvox__gray_at(const bvox_image *img, size_t i)
{
    return img->bits == 8 ? img->pixels[i] : img->pixels16[i];
}

/* section_tiff.c: a TIFF's first page as 8/16-bit gray (name: for messages);
 * the _read variant reads the file whole through the budget first. */
bvox_status bvox__section_tiff_decode(const uint8_t *data, size_t size, const char *name,
                                      bvox_image **out);
bvox_status bvox__section_tiff_read(const char *path, bvox_image **out);

/* align_contours.c: the rigid step taking src's outline onto dst's (ICP on
 * half-pixel samples of the edges); rms: RMS distance of the kept pairs.
 * BVOX_ENOTFOUND when an outline is too small to align by. */
bvox_status bvox__contours_register(const bvox_contour *src, int32_t ns, const bvox_contour *dst,
                                    int32_t nd, bvox_sim2 *step, double *rms);

#endif
