/*
 * bvox/recon.h — reconstruction from serial sections: the image half (gray
 * section -> background-corrected -> binary -> smoothed -> traced contours),
 * reference markers (detection, matching, least-squares similarity
 * transforms chained to a reference section) and bvox_reconstruct, which
 * runs it all and hands the aligned contour stack to bvox_stack_to_volume
 * (bvox/contours.h). Included by bvox.h; do not include it alone.
 *
 * Every step is a library call whose result is an image or a bitmap that
 * can be written out (bvox_image_write_png, bvox_bitmap_to_image) and looked
 * at. Coordinates are pixels of the section image, x to the right, y down,
 * pixel (i, j) covering [i, i+1) x [j, j+1) (its centre at (i+0.5, j+0.5)),
 * as in bvox/contours.h.
 */
#ifndef BVOX_RECON_H
#define BVOX_RECON_H

/* ------------------------------------------------------------ bitmaps */

/* A binary 2-D image, 64 pixels per word along a row: pixel (x, y) is bit
 * (x & 63) of words[y * words_per_row + (x >> 6)]. The bits of the last word
 * of a row beyond width are always zero. Made and released by the library. */
typedef struct bvox_bitmap {
    int32_t width, height;
    int32_t words_per_row; /* ceil(width / 64) */
    uint64_t *words;
} bvox_bitmap;

/* An all-zero bitmap; width, height in 1..BVOX_IMAGE_MAX_DIM. */
BVOX_API bvox_status bvox_bitmap_create(int32_t width, int32_t height, bvox_bitmap **out);
BVOX_API void bvox_bitmap_destroy(bvox_bitmap *bm);
BVOX_API bvox_status bvox_bitmap_copy(const bvox_bitmap *bm, bvox_bitmap **out);
/* 0 outside the bitmap. */
BVOX_API int bvox_bitmap_get(const bvox_bitmap *bm, int32_t x, int32_t y);
/* Ignored outside the bitmap. */
BVOX_API void bvox_bitmap_set(bvox_bitmap *bm, int32_t x, int32_t y, int value);
BVOX_API int64_t bvox_bitmap_count(const bvox_bitmap *bm);
/* 8-bit gray image, 255 where set, 0 elsewhere (to write as PNG). */
BVOX_API bvox_status bvox_bitmap_to_image(const bvox_bitmap *bm, bvox_image **out);

/* Square structuring element of (2 radius + 1)^2 pixels (radius >= 0), word
 * by word (shifts along rows, ORs/ANDs of whole rows). Outside the bitmap is
 * background for dilation, and does not erode (erosion treats it as object),
 * so an object touching the edge is not eaten from there. */
BVOX_API bvox_status bvox_bitmap_dilate(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out);
BVOX_API bvox_status bvox_bitmap_erode(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out);
BVOX_API bvox_status bvox_bitmap_open(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out);
BVOX_API bvox_status bvox_bitmap_close(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out);
/* Median (majority) filter over the (2 radius + 1)^2 square clipped to the
 * bitmap: a pixel is set when more than half of the window's pixels inside
 * the bitmap are set. radius 0 copies. Summed-area table: O(1) per pixel. */
BVOX_API bvox_status bvox_bitmap_median(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out);
/* Connected components of the set pixels (conn 4 or 8), labelled 1..count
 * in the order of their first pixel (row by row); 0 background. *labels
 * (width*height, row-major) is released with bvox_free. */
BVOX_API bvox_status bvox_bitmap_label(const bvox_bitmap *bm, int conn, int32_t **labels,
                                       int32_t *count);
/* In place: clear the 8-connected components of fewer than min_area pixels,
 * then, if fill_holes, set the 4-connected background components of fewer
 * than min_area pixels that do not touch the edge (small holes). */
BVOX_API bvox_status bvox_bitmap_remove_specks(bvox_bitmap *bm, int64_t min_area, int fill_holes);

/* ---------------------------------------------------- gray section steps */

/* A section image as 8- or 16-bit gray: PNG (gray, or RGB turned to
 * luminance 0.299 R + 0.587 G + 0.114 B) or, by the extension .tif/.tiff,
 * the first page of a TIFF (unsigned 8/16-bit gray or RGB as stored,
 * min-is-white inverted; other layouts libtiff decodes as 8-bit RGB). */
BVOX_API bvox_status bvox_section_read(const char *path, bvox_image **out);
/* Gray copy of img (RGB -> luminance as above; gray: a copy). */
BVOX_API bvox_status bvox_section_gray(const bvox_image *img, bvox_image **out);

/* Estimate the background of a gray section from itself: a quadratic
 * surface a + bx + cy + dx^2 + exy + fy^2 fitted by least squares to a grid
 * of about 64 x 64 samples: first to those on the background side of Otsu's
 * threshold, then 4 more times to the samples within 3 robust sigmas
 * (median and MAD of the kept residuals) on the object's side (dark != 0:
 * the object is darker; bright objects the other way). Smooth illumination
 * gradients and vignetting are captured, objects of any size are not, as
 * long as the object's contrast exceeds the background's variation. *bg has
 * img's size and depth. */
BVOX_API bvox_status bvox_section_background_estimate(const bvox_image *img, int dark,
                                                      bvox_image **bg);
/* out = img - bg + mean(bg), clamped to the sample range: an even
 * background at the blank's mean level. bg: a blank (empty) section image
 * or an estimate; same size as img (BVOX_EINVAL naming both sizes if not). */
BVOX_API bvox_status bvox_section_subtract_background(const bvox_image *img, const bvox_image *bg,
                                                      bvox_image **out);
/* Flat-field correction for transmitted light (illumination multiplies):
 * out = img * mean(bg) / bg (bg 0 counts as 1), rounded and clamped; same
 * size rule. Absorbing markers and tissue keep their contrast across an
 * uneven field, which a subtraction would not give them. */
BVOX_API bvox_status bvox_section_divide_background(const bvox_image *img, const bvox_image *bg,
                                                    bvox_image **out);
/* Otsu's threshold of a gray image (one histogram bin per value): the
 * value t maximising the between-class variance of {v <= t} and {v > t}. */
BVOX_API bvox_status bvox_section_otsu(const bvox_image *img, double *threshold);
/* Object mask: dark != 0: value <= threshold; else value > threshold. */
BVOX_API bvox_status bvox_section_threshold(const bvox_image *img, double threshold, int dark,
                                            bvox_bitmap **out);

/* Closed contours of the set pixels, traced along pixel edges (crack
 * following): vertices at pixel corners (integer coordinates), one vertex per
 * change of direction, so that an even-odd fill sampling pixel centres gives
 * the bitmap back exactly. Objects are 8-connected (diagonal neighbours join:
 * such a contour passes twice through the shared corner), holes 4-connected.
 * Outer contours have positive bvox_polygon_signed_area, holes negative
 * (hole = 1); each contour's parent is the smallest contour enclosing it
 * (-1 for outermost):
 * a hole's parent is its object's outer contour, an island in a hole has the
 * hole as parent. *contours (malloc'd, points too) is released with
 * bvox_contours_free. */
BVOX_API bvox_status bvox_bitmap_trace(const bvox_bitmap *bm, bvox_contour **contours,
                                       int32_t *count);
BVOX_API void bvox_contours_free(bvox_contour *contours, int32_t count);

/* ----------------------------------------------------------- markers */

/* A similarity transform of the plane: p' = scale * R(angle) p + (tx, ty),
 * R = [cos -sin; sin cos] in pixel coordinates (x right, y down: a positive
 * angle turns clockwise on the screen). */
typedef struct bvox_sim2 {
    double angle; /* radians */
    double scale;
    double tx, ty;
} bvox_sim2;

BVOX_API bvox_sim2 bvox_sim2_identity(void);
BVOX_API bvox_point2 bvox_sim2_apply(const bvox_sim2 *t, bvox_point2 p);
/* a after b: p -> a(b(p)). */
BVOX_API bvox_sim2 bvox_sim2_compose(const bvox_sim2 *a, const bvox_sim2 *b);
BVOX_API bvox_sim2 bvox_sim2_inverse(const bvox_sim2 *t);

/* Least-squares transform taking src[i] onto dst[i] (n >= 2): rigid
 * (Kabsch / Umeyama in 2-D: centroids, then the angle atan2(sum a x b,
 * sum a . b)), with the uniform scale too when allow_scale. rms (may be
 * NULL): root mean square distance of the mapped src from dst. */
BVOX_API bvox_status bvox_sim2_fit(const bvox_point2 *src, const bvox_point2 *dst, int32_t n,
                                   int allow_scale, bvox_sim2 *t, double *rms);

#define BVOX_MARKERS_AUTO (-1) /* bvox_recon_opts.markers.count: find the count */
typedef struct bvox_marker_opts {
    int32_t count;      /* expected markers per section (N >= 1); in bvox_recon_opts also
                           BVOX_MARKERS_AUTO: the median count found in up to 9 sections
                           spread over the stack (a warning says it) */
    double min_radius;  /* pixels; 0: 1.5 */
    double max_radius;  /* pixels; 0: min(width, height) / 16 */
    double threshold;   /* gray level at or below which a pixel is marker-dark;
                           < 0: automatic, halfway between the image's median
                           and its 0.05 % darkest level */
    /* matching */
    double tolerance;   /* pixels: a marker pair matches within this (0: 4) */
    double max_angle;   /* radians: largest plausible turn between neighbours (0: 30 deg) */
    int allow_scale;    /* fit a uniform scale (shrinkage) too */
    double max_scale_change; /* |scale - 1| at most this (0: 0.2) */
} bvox_marker_opts;
BVOX_API bvox_marker_opts bvox_marker_opts_default(void); /* count 3, the rest automatic */

/* Find up to opts->count markers: 8-connected components of marker-dark
 * pixels whose area is between pi min_radius^2 and pi max_radius^2 and
 * which are round (area / (pi r_max^2) >= 0.5, r_max the farthest pixel
 * centre from the centroid plus half a pixel) and about as dark as the
 * darkest such blob (mean level within a quarter of the way from it to the
 * image's median: a dark object's small round tip is not a marker when the
 * markers are darker than the object); the opts->count roundest are
 * kept, scored by roundness minus the relative difference of the area from
 * the candidates' median area; up to opts->count + 1 are kept, so that one
 * spurious blob cannot push a true marker out (matching drops it). Centres
 * are the components' centroids (pixel centres). markers holds
 * opts->count + 1 points;
 * *found receives how many were written (0 is not an error). erase (may be
 * NULL): the pixels of the kept markers, dilated by 2, are cleared from it
 * (the object mask, when markers are as dark as the object). */
BVOX_API bvox_status bvox_section_find_markers(const bvox_image *img, const bvox_marker_opts *opts,
                                               bvox_point2 *markers, int32_t *found,
                                               bvox_bitmap *erase);

/* Match the markers src[0..ns) of one section with dst[0..nd) of its
 * neighbour: every pair of src markers against every pair of dst markers
 * with the same distance (within tolerance and the scale limit) gives a
 * transform; the one under which most src markers land within tolerance of
 * a distinct dst marker wins (ties: smallest residual), then it is refitted
 * by least squares on those pairs. Implausible transforms (angle or scale
 * over the limits) are rejected. So one missing or spurious marker on either
 * side is survived when at least 2 true markers are shared. match (ns
 * entries, may be NULL): the dst index of each src marker or -1.
 * BVOX_ENOTFOUND when fewer than 2 markers match. */
BVOX_API bvox_status bvox_markers_match(const bvox_point2 *src, int32_t ns, const bvox_point2 *dst,
                                        int32_t nd, const bvox_marker_opts *opts, bvox_sim2 *t,
                                        int32_t *match, int32_t *nmatched, double *rms);

/* One section's alignment. */
typedef struct bvox_align_result {
    bvox_sim2 transform; /* section pixels -> reference section pixels */
    bvox_sim2 step;      /* section pixels -> neighbour's pixels */
    int32_t neighbour;   /* section it was matched with; -1: the reference itself */
    int32_t matched;     /* markers matched with the neighbour */
    double residual;     /* RMS distance (pixels) of the matched markers after the step */
    int fallback;        /* 1: no usable match: step = identity (the neighbour's transform) */
    int by_contours;     /* 1: the markers were unusable and bvox_reconstruct aligned the
                            section by its traced contours onto its neighbour's instead
                            (step and residual are that registration's; fallback stays 1) */
} bvox_align_result;

/* Align n sections by their markers, chained to the reference section
 * (reference < 0: the middle one, n / 2): going outwards from it, each
 * section is matched with its nearest section towards the reference that
 * has markers and was itself aligned without a fallback, and its transform
 * is the neighbour's composed with the step. A section whose markers do
 * not match (fewer than 2 found, or no consistent pair) keeps its
 * neighbour's transform and is flagged (fallback); the caller reports it.
 * result holds n entries. */
BVOX_API bvox_status bvox_markers_align(const bvox_point2 *const *markers, const int32_t *counts,
                                        int32_t n, int32_t reference, const bvox_marker_opts *opts,
                                        bvox_align_result *result);

/* ------------------------------------------------------- the pipeline */

typedef enum bvox_recon_step {
    BVOX_RECON_READ = 0,
    BVOX_RECON_BACKGROUND,
    BVOX_RECON_THRESHOLD,
    BVOX_RECON_SMOOTH,
    BVOX_RECON_MARKERS,
    BVOX_RECON_SPECKS,
    BVOX_RECON_CONTOURS,
    BVOX_RECON_ALIGN,
    BVOX_RECON_VOLUME,
    BVOX_RECON_TOTAL,
    BVOX_RECON_NSTEPS
} bvox_recon_step;
/* "read", "background", "threshold", "smooth", "markers", "specks",
 * "contours", "align", "volume", "total". */
BVOX_API const char *bvox_recon_step_name(bvox_recon_step step);

/* Progress: step is running, done of total items (sections) finished.
 * Called from the calling thread only. */
typedef void (*bvox_recon_progress)(void *ctx, bvox_recon_step step, int32_t done,
                                    int32_t total);

typedef struct bvox_recon_opts {
    /* images */
    const char *background;       /* a blank section image (bvox_reconstruct), or NULL */
    const bvox_image *background_image; /* the same, given as an image (takes precedence) */
    int estimate_background;      /* 1 (default): without a blank, estimate per section */
    double threshold;             /* < 0 (default): Otsu per section */
    int dark;                     /* 1 (default): object darker than the background */
    int32_t smooth;               /* median filter radius in pixels (default 1; 0: none) */
    int64_t min_area;             /* specks and holes below this many pixels go (default 16) */
    double simplify;              /* Douglas-Peucker tolerance for the traced contours,
                                     pixels (bvox_contour_simplify; 0, the default: exact
                                     pixel-edge contours) */
    int32_t contour_smooth;       /* moving-average radius for the traced contours
                                     (bvox_contour_smooth, area kept; 0, the default: none) */
    /* markers and alignment */
    bvox_marker_opts markers;     /* markers.count 0: no detection (default) */
    const char *markers_file;     /* a contour stack file (bvox_stack_read) whose section i
                                     holds the markers of section i; NULL */
    const char *marker_coords;    /* a contour stack file whose first section's markers are
                                     where the reference section's markers belong (pixels of
                                     the section images, in a frame of the user's: an atlas,
                                     a block face): the aligned stack is moved into that
                                     frame (markers matched as between sections, any turn);
                                     NULL: the reference section's own frame */
    int align;                    /* 1 (default): align by markers when there are any */
    int32_t reference;            /* reference section; -1 (default): the middle one */
    /* geometry */
    double pixel;                 /* pixel size; 0 (default): 1, or a contour file's own */
    double spacing;               /* distance between sections; 0 (default): 1, or the file's */
    char unit[16];                /* "" (default): none, or the file's */
    double z_spacing;             /* output slice spacing; 0 (default): pixel (isotropic) */
    int interpolate;              /* 1 (default): shape-based interpolation */
    /* contour inputs */
    const char *svg_select;       /* SVG sections: which elements are outlines
                                     (bvox_stack_read_opts.svg_select); NULL: all visible */
    const char *object;           /* a .jser series: only this object's traces
                                     (bvox_stack_read_opts.object); NULL: all objects */
    int strict;                   /* 1: refuse a contour crossing itself; 0 (default): fill it
                                     even-odd and warn (contours crossing each other are
                                     always refused) */
    /* looking at the steps */
    const char *save_steps;       /* an existing folder, or NULL (default): each image
                                     section's steps as PNG files NAME.1_flat.png (after the
                                     background), NAME.2_threshold.png, NAME.3_smooth.png
                                     and NAME.4_final.png (markers and specks removed: what
                                     is traced), NAME the section's name without ".png" */
    /* progress */
    bvox_recon_progress progress;
    void *progress_ctx;
} bvox_recon_opts;
BVOX_API bvox_recon_opts bvox_recon_opts_default(void);

typedef struct bvox_recon_section_report {
    char *name;                   /* file name or "section N" */
    double threshold;             /* the threshold used (NaN for a contour input) */
    int64_t area;                 /* object pixels after smoothing, markers, specks */
    int32_t ncontours;
    int32_t nmarkers;             /* markers found (or given) */
    bvox_point2 *markers;
    bvox_align_result align;      /* identity, no fallback, when not aligned */
    char message[200];            /* why a fallback happened, "" if none */
} bvox_recon_section_report;

typedef struct bvox_recon_report {
    int32_t nsections;
    int32_t width, height;        /* section image size (pixels) */
    int32_t reference;            /* -1 when not aligned */
    int aligned;                  /* 1 when marker alignment ran */
    int32_t fallbacks;            /* sections aligned by fallback */
    double ms[BVOX_RECON_NSTEPS]; /* wall-clock milliseconds per step; the per-section
                                     steps run on all threads together, so their
                                     times are their share of that phase */
    bvox_recon_section_report *sections;
} bvox_recon_report;
BVOX_API void bvox_recon_report_destroy(bvox_recon_report *report);

/* Images -> model. images: n gray or RGB sections in stack order (same size,
 * BVOX_EINVAL naming the first that differs); names (may be NULL) label them
 * in messages and the report. Per section (in parallel over the worker
 * threads): gray, background (opts->background_image, else an estimate when
 * estimate_background), threshold (fixed or Otsu) with the polarity, median
 * smoothing, markers (found and erased from the mask), specks, contours.
 * The background correction is a division (flat field, transmitted light)
 * for dark objects and a subtraction for bright ones (fluorescence, dark
 * field). Then alignment (when align and markers.count > 0 or a markers_file),
 * the contours moved onto the reference section, the stack (section i at
 * z = i * spacing, width and height the images') and
 * bvox_stack_to_volume. Any of volume, stack, report may be NULL (not
 * wanted); at least one must be given. */
BVOX_API bvox_status bvox_reconstruct_images(const bvox_image *const *images,
                                             const char *const *names,
                                             int32_t n, const bvox_recon_opts *opts,
                                             bvox_volume **volume,
                                             bvox_contour_stack **stack,
                                             bvox_recon_report **report);

/* Paths -> model. inputs: image files (PNG, TIFF), or one folder of them
 * (read in natural order: s2 before s10), or one contour stack file (JSON,
 * SVG folder, Reconstruct: bvox_stack_read; its markers align it when
 * present and opts->align). An empty folder is BVOX_ENOTFOUND. */
BVOX_API bvox_status bvox_reconstruct(const char *const *inputs, int32_t n,
                                      const bvox_recon_opts *opts,
                                      bvox_volume **volume, bvox_contour_stack **stack,
                                      bvox_recon_report **report);

/* Align a contour stack in place by its sections' markers (chained to the
 * reference as bvox_markers_align), moving contours and markers; report
 * (may be NULL) receives the per-section results. */
BVOX_API bvox_status bvox_stack_align(bvox_contour_stack *stack, const bvox_recon_opts *opts,
                                      bvox_recon_report **report);

/* ------------------------------------------------------ the demo's story */

/* `bvox demo`: the paper's system end to end on the built-in specimen
 * (bvox_demo_specimen). The specimen is cut into 70 serial sections 40 um
 * apart, each imaged as a microscope would (uneven light, noise, texture,
 * three embedding markers, a random rigid shift and turn), the model is
 * reconstructed from the images (bvox_reconstruct_images: markers aligned,
 * shape-based interpolation to the specimen's 25 um slices) and compared
 * with the specimen on its grid. */
typedef struct bvox_demo_opts {
    const char *dir;   /* NULL (default): write nothing; else the folder (made if
                          missing, its parent must exist) gets specimen.nii.gz,
                          specimen.tif, section_0000.png .., model.nii.gz (the
                          reconstruction on the specimen's grid), picture1.png ..
                          picture4.png (bvox_demo_picture of the model) and
                          turntable.gif, through the folder-safety rules of folder
                          outputs (a folder holding other files is refused) */
    int force;         /* with dir: add to a folder holding other files */
} bvox_demo_opts;
BVOX_API bvox_demo_opts bvox_demo_opts_default(void);

typedef struct bvox_demo_report {
    int32_t sections;               /* section images */
    int32_t width, height;          /* their size, pixels */
    double pixel, section_spacing;  /* um */
    int32_t markers;                /* markers per section */
    int32_t fallbacks;              /* sections not aligned by their markers */
    int64_t specimen_voxels, model_voxels;
    double dice;                    /* 2 |A and B| / (|A| + |B|), model vs specimen */
    double volume_error_percent;    /* 100 (model volume - specimen volume) / specimen volume */
    double ms_sections, ms_reconstruct, ms_compare, ms_write; /* wall clock */
} bvox_demo_report;
BVOX_API bvox_status bvox_demo_run(const bvox_demo_opts *opts, bvox_demo_report *report);

#endif /* BVOX_RECON_H */
