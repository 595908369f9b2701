/*
 * bvox/contours.h — traced outlines of serial sections: the data model shared
 * by the reconstruction pipeline (images -> contours -> aligned stack ->
 * model), the contour file readers/writers (JSON, SVG, Reconstruct XML) and
 * model-to-contours. Included by bvox.h; do not include it alone.
 *
 * Coordinates: points and markers are in PIXELS of the section image (x to
 * the right, y down, the centre of pixel (i, j) at (i + 0.5, j + 0.5));
 * the physical position of a point is origin + pixel * coordinate (origin:
 * the stack's in-plane origin, default 0, 0). A section's z is in physical units
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
    int32_t z_from_index;    /* 1: the file gave no z; z = index * the stack's spacing, so
                                a spacing given later (--spacing) re-places the section */
} bvox_section;

typedef struct bvox_contour_stack {
    char unit[16];           /* "um", "mm", ... ("" unknown) */
    double pixel;            /* pixel size (x and y), in unit; > 0 */
    double spacing;          /* nominal distance between sections, in unit; > 0 */
    int32_t width, height;   /* image extent in pixels; 0: take the contours' bounds */
    bvox_section *sections;  /* in stack order (increasing z) */
    int32_t nsections;
    double origin[2];        /* physical x, y of pixel coordinate (0, 0), in unit; so
                                that model -> contours -> model keeps its position */
    uint32_t given;          /* BVOX_STACK_GIVEN_*: which of pixel, spacing, unit the
                                file stated (the others are defaults: reconstruct warns) */
} bvox_contour_stack;

enum {
    BVOX_STACK_GIVEN_PIXEL = 1,
    BVOX_STACK_GIVEN_SPACING = 2,
    BVOX_STACK_GIVEN_UNIT = 4,
};

/* An empty stack: unit "", pixel 1, spacing 1, width = height = 0. */
BVOX_API bvox_status bvox_stack_create(bvox_contour_stack **out);
BVOX_API void bvox_stack_destroy(bvox_contour_stack *stack);
/* Append a section at z (name copied, may be NULL); *out (may be NULL) points
 * into the stack and stays valid until the next append. */
BVOX_API bvox_status bvox_stack_add_section(bvox_contour_stack *stack, double z, const char *name,
                                            bvox_section **out);
/* Append a copy of the n points (n >= 3, finite) as a contour of sec; parent
 * is -1 or the index of an earlier contour. */
BVOX_API bvox_status bvox_section_add_contour(bvox_section *sec, const bvox_point2 *points,
                                              int32_t n,
                                              int hole, int32_t parent);
BVOX_API bvox_status bvox_section_add_marker(bvox_section *sec, bvox_point2 marker);

/* ------------------------------------------------ contour stack -> model */

typedef struct bvox_stack_volume_opts {
    double z_spacing;  /* output slice spacing in the stack's unit; 0: = stack->pixel (isotropic voxels) */
    int interpolate;   /* 1 (default): shape-based interpolation through signed distance maps between
                          neighbouring sections; 0: each output slice copies the nearest section */
    int32_t margin;    /* empty pixels added around the contours' bounds when stack->width/height are 0 */
} bvox_stack_volume_opts;

/* z_spacing 0, interpolate 1, margin 1. */
BVOX_API bvox_stack_volume_opts bvox_stack_volume_opts_default(void);

/* Scan-convert every section (even-odd fill of all its contours, holes kept:
 * pixel (i, j) is inside when its centre (i + 0.5, j + 0.5) is; exactly on
 * an edge, the half-open rule of a ray cast towards -x decides: an edge
 * counts for the rows with min y <= cy < max y, where it crosses strictly
 * left of the centre; so a centre on a vertical edge belongs to the region
 * on the edge's left, one on a horizontal edge to the region below it, and
 * two polygons sharing an edge never both own a centre on it) and
 * build a model of slices z_spacing apart.
 *
 * Extent: nx = width, ny = height when both are > 0 (points are pixels of that
 * image; parts outside are clipped); otherwise the contours' bounding box
 * (integer pixel bounds) plus `margin` pixels on each side. Along z the model
 * covers [z_first - spacing/2, z_last + spacing/2] (each end section extends
 * half the stack's nominal spacing): nz = max(1, round(length / z_spacing))
 * slices centred on that range, so with z_spacing = spacing and equally spaced
 * sections slice k lies exactly on section k.
 *
 * Interpolation (Raya & Udupa 1990; Herman, Zheng & Bucholtz 1992): each
 * section gets an exact signed Euclidean distance map in pixels (negative
 * inside: minus the distance to the nearest outside pixel centre; positive
 * outside: the distance to the nearest inside pixel centre); a slice at z
 * between sections a and b (z_a < z < z_b, t = (z - z_a)/(z_b - z_a)) is
 * inside where (1 - t) d_a + t d_b <= 0. A slice at a section's z copies
 * it (to 1e-9 of the gap); slices beyond the first/last section copy that
 * section. An empty section acts as "far outside" (its distance is capped at
 * the width + height of the box of all sections' pixels), so the object ends
 * close to its neighbour. Memory: a bitmap per section and a float map per
 * interpolated section (70 sections of 512 x 512: about 75 MB), within the
 * memory budget. Threads: sections and slices are split over them.
 *
 * Geometry: spacing (pixel, pixel, z_spacing), unit from the stack, origin
 * the centre of voxel (0, 0, 0): (stack origin[0] + (x0 + 0.5) pixel,
 * origin[1] + (y0 + 0.5) pixel, z of slice 0), x0/y0 the extent's first
 * pixel (0 with width/height).
 * Sections must have distinct z (any order: they are sorted). Errors:
 * BVOX_EINVAL (no sections, bad options, equal z, no extent), BVOX_ETOOBIG.
 * *out is owned by the caller. */
BVOX_API bvox_status bvox_stack_to_volume(const bvox_contour_stack *stack,
                                          const bvox_stack_volume_opts *opts,
                                          bvox_volume **out);

/* ---------------------------------------------------- contour geometry */

/* Shoelace area of a closed polygon, in pixels^2. Positive when the points
 * turn from +x towards +y (counter-clockwise in a y-up frame, which is
 * clockwise on screen where y points down); outer contours written by bvox
 * are positive, holes negative. */
BVOX_API double bvox_polygon_signed_area(const bvox_point2 *points, int32_t n);
/* 1 if p is inside the polygon (even-odd; a point on an edge follows the
 * same half-open rule as the scan conversion). */
BVOX_API int bvox_polygon_contains(const bvox_point2 *points, int32_t n, bvox_point2 p);
/* 1 if p is inside the section (even-odd over all its contours). */
BVOX_API int bvox_section_contains(const bvox_section *sec, bvox_point2 p);

/* Drop consecutive duplicate points (the last equal to the first included).
 * BVOX_EFORMAT if fewer than 3 distinct points remain (the contour is left
 * as it was). */
BVOX_API bvox_status bvox_contour_close(bvox_contour *c);
/* Moving average over 2 * radius + 1 neighbours (closed), `iterations` times,
 * then scaled about the centroid so that the area is what it was (a smoothed
 * outline does not shrink). radius >= 1, iterations >= 1. */
BVOX_API bvox_status bvox_contour_smooth(bvox_contour *c, int32_t radius, int32_t iterations);
/* Douglas-Peucker on the closed polygon (split at point 0 and the point
 * farthest from it): every dropped point is within tolerance (pixels) of the
 * simplified outline; at least 3 points stay. Iterative (no recursion). */
BVOX_API bvox_status bvox_contour_simplify(bvox_contour *c, double tolerance);
/* Whether edges of the contours of sec cross each other (a contour crossing
 * itself, or two contours crossing). BVOX_OK when none do; BVOX_EFORMAT with
 * a message naming the section (name or index, z), the contours, edges and
 * the crossing point otherwise. Reported: proper crossings of two edges and
 * collinear overlaps of positive length. Not reported: touching at a point
 * (traced outlines touch at pixel corners), and so neither a crossing that
 * passes exactly through a vertex. Sweep over edges sorted by x.
 * section_index only names the section. */
BVOX_API bvox_status bvox_section_check_simple(const bvox_section *sec, int32_t section_index);

/* A 2-D affine map x' = a x + b y + tx, y' = c x + d y + ty (pixels). */
typedef struct bvox_xform2 {
    double a, b, c, d, tx, ty;
} bvox_xform2;
/* Rotation by angle (radians, from +x towards +y) and uniform scale about
 * the origin, then the translation. */
BVOX_API bvox_xform2 bvox_xform2_similarity(double angle, double scale, double tx, double ty);
/* first then second: (second o first)(p). */
BVOX_API bvox_xform2 bvox_xform2_compose(const bvox_xform2 *first, const bvox_xform2 *second);
/* BVOX_EINVAL if singular. */
BVOX_API bvox_status bvox_xform2_invert(const bvox_xform2 *t, bvox_xform2 *out);
BVOX_API bvox_point2 bvox_xform2_apply(const bvox_xform2 *t, bvox_point2 p);
/* Map every contour point and marker of sec (a reflection reverses the
 * point order so that orientations are kept). */
BVOX_API void bvox_section_transform(bvox_section *sec, const bvox_xform2 *t);

/* ------------------------------------------------------ files */

/* Read a contour stack: a .json file, a folder of .svg files (one per section,
 * natural sort order), a .svg file (one section), or a Reconstruct series
 * (the .ser file; its sections NAME.1, NAME.2, ... beside it), or a
 * PyReconstruct series (NAME.jser, all objects). Format by
 * extension, else by content. BVOX_EFORMAT with file and line:column on
 * malformed input. *out is owned by the caller. */
BVOX_API bvox_status bvox_stack_read(const char *path, bvox_contour_stack **out);
/* A list of .svg files, one section each, in the given order. */
BVOX_API bvox_status bvox_stack_read_svg_files(const char *const *paths, int32_t n,
                                               bvox_contour_stack **out);
/* Memory entry points (name is for messages). */
BVOX_API bvox_status bvox_stack_read_json_memory(const char *data, size_t size, const char *name,
                                                 bvox_contour_stack **out);
/* Options of bvox_stack_read_with. */
typedef struct bvox_stack_read_opts {
    /* SVG only: read only the elements that are, or lie inside, one named here:
     * a comma-separated list of id:NAME, class:NAME, layer:NAME (Inkscape's
     * layer label or a <g id>) or a bare NAME matching any of these. NULL:
     * every visible outline. Either way hidden elements (display:none,
     * visibility:hidden) and a full-canvas background <rect> are skipped, with
     * one warning per file (bvox_set_warning_handler) counting what was. A
     * selection that names nothing in any section: BVOX_EINVAL. */
    const char *svg_select;
    /* PyReconstruct .jser series only: read only the traces of this object
     * (trace name). NULL: every object. An object with no closed trace in any
     * section: BVOX_EINVAL naming some objects that are there. Given for any
     * other input: BVOX_EINVAL. */
    const char *object;
} bvox_stack_read_opts;

/* bvox_stack_read with options (opts NULL: the defaults). */
BVOX_API bvox_status bvox_stack_read_with(const char *path, const bvox_stack_read_opts *opts,
                                          bvox_contour_stack **out);

/* One SVG document as one section at z (pixel 1, spacing 1); appended to
 * *stack when *stack is not NULL, else a new stack is made. */
BVOX_API bvox_status bvox_stack_read_svg_memory(const char *data, size_t size, const char *name,
                                                double z,
                                                bvox_contour_stack **stack);
/* A Reconstruct section file's text appended as a section; the first call
 * (with *stack NULL) creates the stack. thickness <= 0: take the section's
 * thickness attribute. */
BVOX_API bvox_status bvox_stack_read_reconstruct_section_memory(const char *data, size_t size,
                                                                const char *name,
                                                                bvox_contour_stack **stack);
/* A PyReconstruct .jser series (both layouts: {"sections": [...], "series":
 * {...}} and the older one key per section file): closed traces of object
 * (NULL: all objects) as contours, the series' current alignment applied,
 * z from the section thicknesses, unit "um". Open traces are skipped with a
 * warning. */
BVOX_API bvox_status bvox_stack_read_jser_memory(const char *data, size_t size, const char *name,
                                                 const char *object, bvox_contour_stack **out);
/* Write atomically. JSON: {"unit", "pixel", "spacing", "width", "height",
 * "sections": [{"z", "name", "contours": [[[x, y], ...], ...], "markers"}]}.
 * SVG folder: one file per section, section_0001.svg ... (markers as
 * <circle class="marker">). */
BVOX_API bvox_status bvox_stack_write_json(const char *path, const bvox_contour_stack *stack);
BVOX_API bvox_status bvox_stack_write_svg_dir(const char *dir, const bvox_contour_stack *stack);
/* The same with write options: only opts->force is used (NULL: not forced);
 * see bvox_write for what a folder output may overwrite (here the files are
 * section_NNNN.svg). */
BVOX_API bvox_status bvox_stack_write_svg_dir_opts(const char *dir, const bvox_contour_stack *stack,
                                                   const bvox_write_opts *opts);

/* ------------------------------------------------- model -> contours */

/* The boundaries of the 1-voxels of every slice across `axis` (0: x, 1: y,
 * 2: z) as a stack: outer contours positive (bvox_polygon_signed_area > 0),
 * holes negative with parent set, points on pixel corners (integers) of the
 * slice's pixel grid, 8-connected pixels touching only at a corner are kept
 * apart (each pixel's square is a closed region; a corner shared by two
 * diagonal pixels becomes two separate vertices). Slice plane (u, v): axis z
 * -> (x, y), axis y -> (x, z), axis x -> (y, z). pixel = the spacing of u; if
 * the spacing of v differs, v coordinates are scaled by sv/su (points in
 * pixels of u, outlines in their true shape, height = ceil(h sv/su)), and
 * only then is the round trip not voxel for voxel. z = the
 * slice's physical position along the axis (origin + index * spacing),
 * spacing = the axis's spacing, width/height = the slice size, unit copied,
 * origin = the outer corner of the slice's first pixel (the volume's origin
 * minus half a voxel along u and v), so the stack maps back onto the same
 * world positions.
 * *out is owned by the caller. */
BVOX_API bvox_status bvox_volume_to_contours(const bvox_volume *vol, int axis,
                                             bvox_contour_stack **out);

/* Fill the z slices of a mask that were not annotated by shape-based
 * interpolation between the annotated slices around them (signed distance
 * maps blended linearly, as bvox_stack_to_volume does between sections).
 * annotated: nz flags (NULL: a slice is annotated when it holds a 1-voxel).
 * Annotated slices are kept; slices outside the first..last annotated one
 * are kept as they are. *out has in's size and geometry. */
BVOX_API bvox_status bvox_interpolate_slices(const bvox_volume *in, const uint8_t *annotated,
                                    bvox_volume **out);

/* Fill the z slices of a label volume that were not annotated, all labels
 * at once, in place: labels holds dims.nx*ny*nz values (x fastest, then y,
 * then z; 0 the background, each below 2^24). Between annotated slices each
 * label's signed distance maps (the background's too) are blended along z
 * and a voxel takes the label that is deepest inside (lowest blended
 * distance), so regions stay tiled: no gaps, no overlaps. annotated: nz
 * flags (NULL: a slice is annotated when it holds a non-zero label).
 * Annotated slices and those outside the first..last annotated one are kept
 * as they are. BVOX_EINVAL, BVOX_EUNSUPPORTED (a label of 2^24 or more),
 * BVOX_ENOMEM (then some unannotated slices may already be filled). */
BVOX_API bvox_status bvox_interpolate_labels(bvox_dims dims, uint32_t *labels,
                                             const uint8_t *annotated);

#endif /* BVOX_CONTOURS_H */
