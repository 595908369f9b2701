/*
 * bvox/contours.h — traced outlines of serial sections: the data model shared
 * by the reconstruction pipeline (images -> contours -> aligned stack ->
 * model), the contour file readers/writers (JSON, SVG, Reconstruct XML) and
 * model-to-contours. Included by bvox.h; do not include it alone.
 *
 * Coordinates: points and markers are in PIXELS of the section image (x to
 * the right, y down, the centre of pixel (i, j) at (i + 0.5, j + 0.5));
 * physical size is pixel * coordinate. A section's z is in physical units
 * (its distance along the stack from the first section's plane is what
 * matters; sections need not be equally spaced).
 *
 * Ownership: the stack owns everything reachable from it (allocated with
 * malloc by the functions below); bvox_stack_destroy frees it all.
 */
#ifndef BVOX_CONTOURS_H
#define BVOX_CONTOURS_H

typedef struct bvox_point2 {
    double x, y;
} bvox_point2;

/* A closed polygon: the last point connects to the first (not repeated). */
typedef struct bvox_contour {
    bvox_point2 *points;
    int32_t npoints;
    int32_t hole;   /* 1: a hole (inner) contour; filling is even-odd anyway */
    int32_t parent; /* index in the section of the enclosing contour, -1 none */
} bvox_contour;

typedef struct bvox_section {
    double z;                /* position along the stack, physical units */
    char *name;              /* where it came from (file name), or NULL */
    bvox_contour *contours;
    int32_t ncontours;
    bvox_point2 *markers;    /* reference marker centres (pixels), may be 0 */
    int32_t nmarkers;
} bvox_section;

typedef struct bvox_contour_stack {
    char unit[16];           /* "um", "mm", ... ("" unknown) */
    double pixel;            /* pixel size (x and y), in unit; > 0 */
    double spacing;          /* nominal distance between sections, in unit; > 0 */
    int32_t width, height;   /* image extent in pixels; 0: take the contours' bounds */
    bvox_section *sections;  /* in stack order (increasing z) */
    int32_t nsections;
} bvox_contour_stack;

/* An empty stack: unit "", pixel 1, spacing 1, width = height = 0. */
bvox_status bvox_stack_create(bvox_contour_stack **out);
void bvox_stack_destroy(bvox_contour_stack *stack);
/* Append a section at z (name copied, may be NULL); *out (may be NULL) points
 * into the stack and stays valid until the next append. */
bvox_status bvox_stack_add_section(bvox_contour_stack *stack, double z, const char *name,
                                   bvox_section **out);
/* Append a copy of the n points (n >= 3, finite) as a contour of sec. */
bvox_status bvox_section_add_contour(bvox_section *sec, const bvox_point2 *points, int32_t n,
                                     int hole, int32_t parent);
bvox_status bvox_section_add_marker(bvox_section *sec, bvox_point2 marker);

#endif /* BVOX_CONTOURS_H */
