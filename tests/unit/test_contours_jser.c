/* test_contours_jser.c — PyReconstruct .jser series (contour_jser.c): both
 * layouts, written here by hand, give the volume of PyReconstruct's own rule
 * (sum over sections of closed-trace area x section thickness, negative
 * traces subtracted) computed by hand; the current alignment is the one
 * applied; z from the thicknesses; --object selection and its error; open
 * traces warned about once; bad input refused with a message. */
#include "harness.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Object "d" on sections 0..2 (thickness 0.05 um each), "other" on section 3.
 * Alignment "main" is current; "default" would scale everything by 3.
 *   s0: rect [0,5.12]x[0,2.56] (13.1072) minus negative [1,2]x[1,2] (1), identity
 *   s1: rect [0,2.56]x[0,2.56] under x' = 2x: [0,5.12]x[0,2.56] (13.1072)
 *   s2: rect [0,1.28]^2 (1.6384) moved by (0.64, 0.32), plus an open trace
 * Extent 5.12 um -> pixel 0.01 um, every edge on a pixel edge: exact.
 * Volume = (12.1072 + 13.1072 + 1.6384) x 0.05 = 1.34264 um^3. */
#define VOLUME 1.34264
#define RECT(x0, y0, x1, y1, neg)                                                             \
    "[[" #x0 "," #x1 "," #x1 "," #x0 "],[" #y0 "," #y0 "," #y1 "," #y1                     \
    "],[255,0,0],true," neg ",false,[\"none\",\"none\"],[]]"
static const char CURRENT[] =
    "{\"sections\": [\n"
    " {\"thickness\": 0.05, \"mag\": 0.002,\n"
    "  \"tforms\": {\"default\": [3,0,0,0,3,0], \"main\": [1,0,0,0,1,0]},\n"
    "  \"contours\": {\"d\": [" RECT(0, 0, 5.12, 2.56, "false") "," RECT(1, 1, 2, 2, "true") "]}},\n"
    " {\"thickness\": 0.05, \"tforms\": {\"default\": [3,0,0,0,3,0], \"main\": [2,0,0,0,1,0]},\n"
    "  \"contours\": {\"d\": [" RECT(0, 0, 2.56, 2.56, "false") "]}},\n"
    " null,\n"
    " {\"thickness\": 0.05, \"tforms\": {\"default\": [3,0,0,0,3,0], \"main\": [1,0,0.64,0,1,0.32]},\n"
    "  \"contours\": {\"d\": [" RECT(0, 0, 1.28, 1.28, "false") ",\n"
    "     [[0,1,2],[0,1,0],[0,0,0],false,false,false,[\"none\",\"none\"],[]]]}},\n"
    " {\"thickness\": 0.05, \"tforms\": {\"main\": [1,0,0,0,1,0]},\n"
    "  \"contours\": {\"other\": [" RECT(0, 0, 90, 90, "false") "]}}\n"
    "], \"series\": {\"alignment\": \"main\", \"current_section\": 0}, \"log\": \"\"}\n";

/* The same series in the older layout: one key per section file, trace
 * fields as objects holding strings, the series under "s.ser". */
#define ORECT(x0, y0, x1, y1, neg)                                                            \
    "{\"x\": \"" #x0 ", " #x1 ", " #x1 ", " #x0 "\", \"y\": \"" #y0 ", " #y0 ", " #y1 ", " #y1 \
    "\", \"closed\": \"True\", \"negative\": \"" neg "\", \"hidden\": \"False\"}"
static const char OLDER[] =
    "{\"s.ser\": {\"alignment\": \"main\"},\n"
    " \"s.4\": {\"thickness\": \"0.05\", \"tforms\": {\"main\": \"[1, 0, 0, 0, 1, 0]\"},\n"
    "  \"contours\": {\"other\": [" ORECT(0, 0, 90, 90, "False") "]}},\n"
    " \"s.0\": {\"thickness\": \"0.05\",\n"
    "  \"tforms\": {\"default\": \"[3, 0, 0, 0, 3, 0]\", \"main\": \"[1, 0, 0, 0, 1, 0]\"},\n"
    "  \"contours\": {\"d\": [" ORECT(0, 0, 5.12, 2.56, "False") "," ORECT(1, 1, 2, 2, "True") "]}},\n"
    " \"s.1\": {\"thickness\": \"0.05\", \"tforms\": {\"main\": [\"2\", 0, 0, 0, 1, 0]},\n"
    "  \"contours\": {\"d\": [" ORECT(0, 0, 2.56, 2.56, "False") "]}},\n"
    " \"s.3\": {\"thickness\": 0.05, \"tforms\": {\"main\": [1, 0, 0.64, 0, 1, 0.32]},\n"
    "  \"contours\": {\"d\": [" ORECT(0, 0, 1.28, 1.28, "False") ",\n"
    "     {\"x\": \"0, 1, 2\", \"y\": \"0, 1, 0\", \"closed\": \"False\", \"negative\": \"False\"}]}}}\n";

static char warned[512];
static int nwarned;
static void on_warning(const char *msg, void *user)
{
    (void)user;
    nwarned++;
    snprintf(warned, sizeof warned, "%s", msg);
}

/* Stack object d of text without interpolation, z slices 0.01 um: volume. */
static double object_volume(const char *text, bvox_contour_stack **keep)
{
    bvox_contour_stack *s = NULL;
    nwarned = 0;
    warned[0] = '\0';
    bvox_set_warning_handler(on_warning, NULL);
    bvox_status st = bvox_stack_read_jser_memory(text, strlen(text), "t.jser", "d", &s);
    bvox_set_warning_handler(NULL, NULL);
    if (st) {
        fprintf(stderr, "read: %s\n", bvox_errmsg());
        return -1;
    }
    bvox_stack_volume_opts o = bvox_stack_volume_opts_default();
    o.z_spacing = 0.01;
    o.interpolate = 0;
    bvox_volume *v = NULL;
    st = bvox_stack_to_volume(s, &o, &v);
    double vol = -1;
    if (!st) {
        const double *sp = bvox_volume_geometry(v)->spacing;
        vol = (double)bvox_volume_count(v) * sp[0] * sp[1] * sp[2];
        bvox_volume_destroy(v);
    } else {
        fprintf(stderr, "volume: %s\n", bvox_errmsg());
    }
    if (keep) *keep = s;
    else bvox_stack_destroy(s);
    return vol;
}

static int check_layout(const char *text)
{
    bvox_contour_stack *s = NULL;
    double v = object_volume(text, &s);
    CHECK(s != NULL);
    CHECK_NEAR(v, VOLUME, 1e-9);
    /* sections 0, 1 and 3 (2 is missing); "other"'s section 4 is not kept */
    CHECK_EQ(s->nsections, 3);
    CHECK_NEAR(s->sections[0].z, 0.0, 1e-12);
    CHECK_NEAR(s->sections[1].z, 0.05, 1e-12);
    CHECK_NEAR(s->sections[2].z, 0.10, 1e-12);
    CHECK(!strcmp(s->sections[2].name, "3"));
    CHECK_NEAR(s->pixel, 0.01, 1e-15);
    CHECK_NEAR(s->spacing, 0.05, 1e-15);
    CHECK(!strcmp(s->unit, "um"));
    CHECK_EQ(s->sections[0].ncontours, 2);
    CHECK_EQ(s->sections[0].contours[1].hole, 1);
    /* the third section: 1.28 um square moved by (0.64, 0.32), y flipped:
     * pixels x 64..192, y -160..-32 */
    const bvox_contour *c = &s->sections[2].contours[0];
    CHECK_EQ(s->sections[2].ncontours, 1);
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (int32_t i = 0; i < c->npoints; i++) {
        x0 = fmin(x0, c->points[i].x), x1 = fmax(x1, c->points[i].x);
        y0 = fmin(y0, c->points[i].y), y1 = fmax(y1, c->points[i].y);
    }
    CHECK_NEAR(x0, 64, 1e-9);
    CHECK_NEAR(x1, 192, 1e-9);
    CHECK_NEAR(y0, -160, 1e-9);
    CHECK_NEAR(y1, -32, 1e-9);
    CHECK_EQ(nwarned, 1);
    CHECK(strstr(warned, "1 open trace skipped") != NULL);
    bvox_stack_destroy(s);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(jser_current_layout_volume) { return check_layout(CURRENT); }

TEST(jser_older_layout_volume) { return check_layout(OLDER); }

/* The rule with a rotation: the area is kept, edges no longer on pixel
 * edges: within the rasterisation error (perimeter x pixel x thickness). */
TEST(jser_rotated_alignment_volume)
{
    static const char text[] =
        "{\"sections\": [{\"thickness\": 0.05, \"tforms\": {\"default\": [0.6,-0.8,3,0.8,0.6,1]},"
        " \"contours\": {\"d\": [" RECT(0, 0, 4, 3, "false") "]}},"
        " {\"thickness\": 0.05, \"tforms\": {\"default\": [0.6,-0.8,3,0.8,0.6,1]},"
        " \"contours\": {\"d\": [" RECT(0, 0, 4, 3, "false") "]}}],"
        " \"series\": {\"alignment\": \"default\"}}";
    double v = object_volume(text, NULL);
    double pixel = 5.0 / 512; /* the rotated 4 x 3 rect spans 5 um in y */
    CHECK(v > 0);
    CHECK(fabs(v - 2 * 12 * 0.05) <= 2 * 14 * pixel * 0.05);
    CHECK(fabs(v - 2 * 12 * 0.05) > 0); /* not on the grid: some error */
    return 0;
}

/* z of each section = the sum of the thicknesses before it. */
TEST(jser_z_from_thicknesses)
{
    static const char text[] =
        "{\"sections\": [{\"thickness\": 0.05, \"contours\": {\"d\": [" RECT(0, 0, 1, 1, "false")
        "]}}, {\"thickness\": 0.07, \"contours\": {\"d\": [" RECT(0, 0, 1, 1, "false") "]}},"
        " {\"thickness\": 0.03, \"contours\": {\"d\": [" RECT(0, 0, 1, 1, "false") "]}}],"
        " \"series\": {\"alignment\": \"no-alignment\"}}";
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read_jser_memory(text, strlen(text), "z.jser", NULL, &s));
    CHECK_EQ(s->nsections, 3);
    CHECK_NEAR(s->sections[1].z, 0.05, 1e-12);
    CHECK_NEAR(s->sections[2].z, 0.12, 1e-12);
    bvox_stack_destroy(s);
    return 0;
}

TEST(jser_object_not_found_lists_names)
{
    bvox_contour_stack *s = NULL;
    CHECK_STATUS(bvox_stack_read_jser_memory(CURRENT, strlen(CURRENT), "t.jser", "axon", &s),
                 BVOX_EINVAL);
    CHECK(s == NULL);
    CHECK(strstr(bvox_errmsg(), "'axon'") != NULL);
    CHECK(strstr(bvox_errmsg(), "objects: d, other") != NULL);
    /* all objects: sections 0..4 with traces (5 of them, "other" included) */
    CHECK_OK(bvox_stack_read_jser_memory(CURRENT, strlen(CURRENT), "t.jser", NULL, &s));
    CHECK_EQ(s->nsections, 4);
    bvox_stack_destroy(s);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

static int refused(const char *text, const char *want)
{
    bvox_contour_stack *s = NULL;
    bvox_status st = bvox_stack_read_jser_memory(text, strlen(text), "bad.jser", NULL, &s);
    if (st == BVOX_OK || s != NULL || !strstr(bvox_errmsg(), want)) {
        fprintf(stderr, "expected an error with '%s', got %d: %s\n", want, (int)st, bvox_errmsg());
        bvox_stack_destroy(s);
        return 1;
    }
    return bvox_memory_in_use() != 0;
}

TEST(jser_bad_input_refused)
{
    CHECK(!refused("{\"sections\": [{\"contours\": {\"d\": [[[0,NaN,1],[0,0,1],[0],true,false]]}}],"
                   " \"series\": {}}", "NaN"));
    CHECK(!refused("{\"sections\": [{\"contours\": {\"d\": [[[0,1e308,1],[0,0,1],[0],true,false]]}}],"
                   " \"series\": {}}", "beyond"));
    CHECK(!refused("{\"sections\": [{\"contours\": {\"d\": [[[0,1e999,1],[0,0,1],[0],true,false]]}}],"
                   " \"series\": {}}", "out of range"));
    CHECK(!refused("{\"sections\": [{\"contours\": {\"d\": [[[0,1,1],[0,0],[0],true,false]]}}],"
                   " \"series\": {}}", "3 x and 2 y"));
    CHECK(!refused("{\"sections\": [{\"thickness\": -1, \"contours\": {}}], \"series\": {}}",
                   "thickness"));
    CHECK(!refused("{\"sections\": [{\"tforms\": {\"default\": [1,0,0]}, \"contours\": {\"d\": "
                   "[[[0,1,1],[0,0,1],[0],true,false]]}}], \"series\": {}}", "3 numbers, not 6"));
    CHECK(!refused("{\"sections\": [], \"series\": {}}", "no closed trace"));
    CHECK(!refused("[1, 2]", "JSON object"));
    CHECK(!refused("{\"sections\": [{}], \"series\": {}} x", "after the end"));
    char deep[300];
    memset(deep, '[', 200);
    deep[200] = '\0';
    CHECK(!refused(deep, "nesting deeper"));
    return 0;
}

/* An object's own alignment (obj_attrs), where the section has it, wins over
 * the series' one; in the older layout a "log" string beside "s.ser" is not
 * taken for the series. 2 sections x unit square x 0.05: 0.1 um^3, x2 under
 * "alt" on the first section only. */
TEST(jser_object_alignment)
{
    static const char text[] =
        "{\"s.ser\": {\"alignment\": \"main\", \"obj_attrs\": {\"d\": {\"alignment\": \"alt\"}}},"
        " \"s.0\": {\"thickness\": 0.05, \"tforms\": {\"main\": [1,0,0,0,1,0], \"alt\": [2,0,0,0,1,0]},"
        "  \"contours\": {\"d\": [" RECT(0, 0, 2.56, 5.12, "false") "],"
        "                 \"e\": [" RECT(0, 0, 1, 1, "false") "]}},"
        " \"s.1\": {\"thickness\": 0.05, \"tforms\": {\"main\": [1,0,0,0,1,0]},"
        "  \"contours\": {\"d\": [" RECT(0, 0, 2.56, 5.12, "false") "]}},"
        " \"log\": {\"alignment\": \"no-alignment\"}}";
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read_jser_memory(text, strlen(text), "o.jser", NULL, &s));
    CHECK_EQ(s->nsections, 2);
    /* areas in um^2 (pixel^2 x pixel size^2) */
    double px2 = s->pixel * s->pixel;
    CHECK_NEAR(fabs(bvox_polygon_signed_area(s->sections[0].contours[0].points,
                                 s->sections[0].contours[0].npoints)) * px2, 2 * 2.56 * 5.12, 1e-9);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(s->sections[0].contours[1].points,
                                 s->sections[0].contours[1].npoints)) * px2, 1.0, 1e-9);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(s->sections[1].contours[0].points,
                                 s->sections[1].contours[0].npoints)) * px2, 2.56 * 5.12, 1e-9);
    bvox_stack_destroy(s);
    return 0;
}
