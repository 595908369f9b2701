/*
 * contour_internal.h — private helpers shared by the contour files of
 * src/recon/ (contour_*.c, stack_volume.c, model_contours.c): limits, the
 * scan converter, the signed distance transform, growable buffers.
 */
#ifndef BVOX_CONTOUR_INTERNAL_H
#define BVOX_CONTOUR_INTERNAL_H

#include "internal.h"
#include "common/json.h"
#include "common/strbuf.h"

/* Limits on what a file (or a caller) may put into a stack. */
#define BVOX__MAX_SECTIONS 65535
#define BVOX__MAX_CONTOURS (1 << 20)      /* per section */
#define BVOX__MAX_POINTS (1 << 24)        /* per contour */
#define BVOX__MAX_MARKERS 4096            /* per section */
#define BVOX__MAX_COORD 1e7               /* |x|, |y| in pixels */

/* The name of a section for messages: "'name' (z = Z)" or "#index (z = Z)". */
const char *bvox__section_label(const bvox_section *sec, int32_t index, char *buf, size_t size);

/* Free the last section of s and remove it (contour_stack.c): a reader
 * takes back the section it added when that section fails to read. */
void bvox__stack_drop_last(bvox_contour_stack *s);

/* Grow *ptr (elements of elem bytes, *cap of them) to hold at least need;
 * doubling. false on overflow / out of memory (message set). */
bool bvox__grow(void **ptr, size_t elem, size_t need, size_t *cap, const char *what);

/* ---- contour_scan.c ---- */
/* Even-odd fill of all contours of sec into a bitmap of ny rows of wpr words
 * (bit x & 63 of word x >> 6 of row y = pixel (x, y) of the window whose
 * first pixel is (x0, y0) of the section's pixel grid). The bitmap is
 * cleared first. */
void bvox__scan_section(const bvox_section *sec, int32_t x0, int32_t y0, int32_t nx, int32_t ny,
                        size_t wpr, uint64_t *bits);

/* ---- contour_edt.c ---- */
/* Signed Euclidean distance map of a bitmap (rows of wpr words, nx x ny
 * pixels): out[y * nx + x] = -(distance to the nearest 0 pixel) for a 1
 * pixel, +(distance to the nearest 1 pixel) for a 0 pixel, in pixels, capped
 * at +-cap (when there is no 0 or no 1 pixel at all). Exact (Felzenszwalb &
 * Huttenlocher's lower envelope of parabolas). tmp: 2 * nx * ny doubles of
 * scratch plus 3 * (max(nx, ny) + 1) doubles. Pure function of its inputs. */
size_t bvox__edt_scratch_doubles(int32_t nx, int32_t ny);
void bvox__signed_edt(const uint64_t *bits, size_t wpr, int32_t nx, int32_t ny, float cap,
                      double *tmp, float *out);

/* ---- contour_text.c: text helpers for the readers and writers ---- */
/* The largest text file a contour reader accepts. */
#define BVOX__MAX_TEXT_BYTES ((size_t)256 << 20)
/* Nesting depth limit of the JSON and XML readers. */
#define BVOX__MAX_DEPTH 64

/* Whether two of the n segments p[i]-q[i] cross, by a sweep line
 * (contour_sweep.c): test(ctx, i, j) is called on the pairs that become
 * neighbours in the sweep's order and returns 1 for a crossing (which
 * stops the sweep). Returns 1 (found), 0 (none), -1 (out of memory). */
int bvox__sweep_crossing(const bvox_point2 *p, const bvox_point2 *q, size_t n,
                         int (*test)(void *ctx, size_t i, size_t j), void *ctx);
/* Test hook: the segment pairs the last bvox_section_check_simple of this
 * thread tested (a work bound for the tests). */
uint64_t bvox__check_simple_tests(void);

/* Record bytes charged to the memory budget (bvox__budget_charge) for the
 * stack's contents; bvox_stack_destroy refunds them (contour_stack.c). */
void bvox__stack_charged(bvox_contour_stack *s, size_t bytes);

/* Text buffers: src/common/strbuf.h; JSON string literals:
 * src/common/json.h (bvox__sb_json_string). XML attribute text (escaped): */
void bvox__sb_xml_text(bvox__strbuf *b, const char *s);
/* Write the buffer to path atomically (bvox__sink). */
bvox_status bvox__sb_write_file(const bvox__strbuf *b, const char *path);

/* The checks every *_memory reader makes of its text: data NULL with a size
 * (EINVAL "FN: no data"), over BVOX__MAX_TEXT_BYTES (ETOOBIG); *name NULL
 * becomes "<memory>". */
bvox_status bvox__text_input_check(const char *fn, const char *data, size_t size,
                                   const char **name);
/* 1-based line and column of byte pos of text. */
void bvox__line_col(const char *text, size_t pos, int64_t *line, int64_t *col);
/* Append code point c (at most 0x10FFFF) as UTF-8, 1 to 4 bytes, at
 * out + *n (the JSON and XML readers' escapes). */
void bvox__put_utf8(char *out, size_t *n, uint32_t c);
/* Read a text file whole (at most BVOX__MAX_TEXT_BYTES, NUL added):
 * *data from malloc. */
bvox_status bvox__read_text(const char *path, char **data, size_t *size);

/* ---- contour nesting (contour_geom.c) ---- */
/* Set hole and parent of every contour of sec from containment: a contour
 * inside an odd number of others is a hole, its parent the smallest contour
 * that holds it. Sections with more than 4096 contours are left as they are
 * (hole 0, parent -1: filling is even-odd anyway). */
void bvox__section_nest(bvox_section *sec);

/* ---- contour_xml.c: a small pull tokenizer for XML (SVG, Reconstruct) ----
 * Yields start tags (with raw attributes), end tags and the end of the
 * document; skips text, comments, CDATA, processing instructions and the
 * DOCTYPE. Checks that end tags match (local names), limits nesting to
 * BVOX__MAX_DEPTH and attributes to BVOX__XML_MAX_ATTRS per tag. No DTD
 * entities (only the five predefined ones and character references). */
#define BVOX__XML_MAX_ATTRS 64
typedef enum bvox__xml_kind { BVOX__XML_START, BVOX__XML_END, BVOX__XML_EOF } bvox__xml_kind;
typedef struct bvox__xml_attr {
    const char *name, *value; /* value raw: entities not decoded */
    size_t nlen, vlen;
} bvox__xml_attr;
typedef struct bvox__xml {
    const char *start, *p, *end, *name;
    bvox__xml_kind kind;
    const char *tag;      /* local name (after any prefix:) */
    size_t taglen;
    const char *at;       /* where the token starts (messages) */
    bool empty;           /* <tag/>: an END follows at once */
    bool pending_end;
    bvox__xml_attr attrs[BVOX__XML_MAX_ATTRS];
    int nattrs;
    int depth;
    const char *stack[BVOX__MAX_DEPTH];
    size_t stacklen[BVOX__MAX_DEPTH];
} bvox__xml;
void bvox__xml_init(bvox__xml *x, const char *data, size_t size, const char *name);
bvox_status bvox__xml_next(bvox__xml *x);
/* BVOX_EFORMAT "NAME:LINE:COL: msg" at `at` (NULL: the current token). */
bvox_status bvox__xml_fail(const bvox__xml *x, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
bool bvox__xml_is(const bvox__xml *x, const char *tag); /* current tag's local name */
const bvox__xml_attr *bvox__xml_attr_get(const bvox__xml *x, const char *name);
/* The decoded value (entities replaced), malloc'd; NULL on a bad entity
 * (*st = BVOX_EFORMAT) or out of memory (*st = BVOX_ENOMEM), message set. */
char *bvox__xml_attr_dup(const bvox__xml *x, const bvox__xml_attr *a, bvox_status *st);

/* ---- contour_svg.c ---- */
/* bvox_stack_read_svg_memory / _files with an --svg-select list (NULL: all). */
bvox_status bvox__svg_read(const char *data, size_t size, const char *name, double z,
                           const char *select, bvox_contour_stack **stack);
bvox_status bvox__svg_read_files(const char *const *paths, int32_t n, const char *select,
                                 bvox_contour_stack **out);

/* ---- contour_repair.c ---- */
/* Crossing contours of every section: a contour crossing itself is warned
 * about and kept (even-odd fill) unless strict; contours crossing each
 * other are refused. Messages start with path. */
bvox_status bvox__stack_check_crossings(const char *path, const bvox_contour_stack *s, int strict);

/* ---- svg_filter.c: which SVG elements are outlines ---- */
/* The element hides itself and its children (display/visibility). */
int bvox__svg_hides(const bvox__xml *x);
/* The element matches the --svg-select list ("id:a,class:b,layer:c,name"). */
int bvox__svg_selected(const bvox__xml *x, const char *select);
/* The transformed rectangle covers the canvas {x, y, w, h} (a background). */
int bvox__svg_covers_canvas(const bvox_point2 corner[4], const double canvas[4]);

/* ---- contour_reconstruct.c ---- */
/* A Reconstruct series from its .ser file and the NAME.<n> files beside it. */
bvox_status bvox__stack_read_reconstruct_series(const char *ser_path, bvox_contour_stack **out);

#endif
