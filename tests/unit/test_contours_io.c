/* test_contours_io.c — the contour stack files: JSON (contour_json.c), SVG
 * (contour_svg.c), Reconstruct series (contour_reconstruct.c) and the
 * dispatcher bvox_stack_read (contour_read.c): write -> read round trips,
 * hand-written inputs with known outlines (path commands, transforms,
 * markers, Bezier areas), malformed inputs with clear messages
 * (file:line:column, the section), deep nesting, and folders. */
#include "harness.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 1;
    fputs(text, f);
    return fclose(f) != 0;
}

static bvox_contour_stack *sample_stack(void)
{
    bvox_contour_stack *s = NULL;
    if (bvox_stack_create(&s)) return NULL;
    strcpy(s->unit, "um");
    s->pixel = 0.37;
    s->spacing = 1.5;
    s->width = 90;
    s->height = 70;
    for (int i = 0; i < 4; i++) {
        bvox_section *sec;
        char name[32];
        snprintf(name, sizeof name, "sec \"%d\".png", i);
        if (bvox_stack_add_section(s, 1.5 * i + 0.1, i == 2 ? NULL : name, &sec)) return NULL;
        for (int c = 0; c < i; c++) {
            bvox_point2 p[50];
            int n = 12 + (int)(harness_rand() % 30);
            for (int k = 0; k < n; k++) {
                double a = 2 * M_PI * k / n * (c == 1 ? -1 : 1), r = c == 1 ? 5 : 20 + c;
                p[k] = (bvox_point2){40 + r * cos(a) + 1e-7 * (double)(harness_rand() % 1000),
                                     30 + r * sin(a) / 3};
            }
            if (bvox_section_add_contour(sec, p, n, 0, -1)) return NULL;
        }
        for (int m = 0; m < i % 3; m++)
            if (bvox_section_add_marker(sec, (bvox_point2){5.25 + m, 60.125})) return NULL;
    }
    return s;
}

static int same_stack(const bvox_contour_stack *a, const bvox_contour_stack *b, int names)
{
    CHECK(strcmp(a->unit, b->unit) == 0);
    CHECK(a->pixel == b->pixel && a->spacing == b->spacing);
    CHECK_EQ(a->width, b->width);
    CHECK_EQ(a->height, b->height);
    CHECK_EQ(a->nsections, b->nsections);
    for (int32_t i = 0; i < a->nsections; i++) {
        const bvox_section *x = &a->sections[i], *y = &b->sections[i];
        CHECK(x->z == y->z);
        if (names) CHECK((x->name == NULL && y->name == NULL) || (x->name && y->name && !strcmp(x->name, y->name)));
        CHECK_EQ(x->ncontours, y->ncontours);
        CHECK_EQ(x->nmarkers, y->nmarkers);
        for (int32_t c = 0; c < x->ncontours; c++) {
            CHECK_EQ(x->contours[c].npoints, y->contours[c].npoints);
            for (int32_t k = 0; k < x->contours[c].npoints; k++)
                CHECK(x->contours[c].points[k].x == y->contours[c].points[k].x &&
                      x->contours[c].points[k].y == y->contours[c].points[k].y);
        }
        for (int32_t m = 0; m < x->nmarkers; m++)
            CHECK(x->markers[m].x == y->markers[m].x && x->markers[m].y == y->markers[m].y);
    }
    return 0;
}

TEST(json_round_trip)
{
    bvox_contour_stack *s = sample_stack(), *r = NULL;
    CHECK(s != NULL);
    const char *path = harness_path("stack.json");
    CHECK_OK(bvox_stack_write_json(path, s));
    CHECK_OK(bvox_stack_read(path, &r));
    CHECK(same_stack(s, r, 1) == 0);
    CHECK(r->origin[0] == 0 && r->origin[1] == 0);
    bvox_stack_destroy(r);
    /* the in-plane origin, when set, is written and read back */
    s->origin[0] = -12.5;
    s->origin[1] = 0.375;
    CHECK_OK(bvox_stack_write_json(path, s));
    CHECK_OK(bvox_stack_read(path, &r));
    CHECK(r->origin[0] == -12.5 && r->origin[1] == 0.375);
    /* nesting found on reading: in section 3, contour 3 (r = 22) holds
     * contour 1 (r = 20, a hole) which holds contour 2 (r = 5, an island) */
    const bvox_contour *c3 = r->sections[3].contours;
    CHECK(c3[0].hole == 1 && c3[0].parent == 2);
    CHECK(c3[1].hole == 0 && c3[1].parent == 0);
    CHECK(c3[2].hole == 0 && c3[2].parent == -1);
    bvox_stack_destroy(r);
    bvox_stack_destroy(s);
    return 0;
}

TEST(svg_round_trip)
{
    bvox_contour_stack *s = sample_stack(), *r = NULL;
    CHECK(s != NULL);
    const char *dir = harness_path("svgs");
    CHECK_OK(bvox_stack_write_svg_dir(dir, s));
    CHECK_OK(bvox_stack_read(dir, &r));
    CHECK(same_stack(s, r, 0) == 0);
    CHECK(strcmp(r->sections[0].name, "sec \"0\".png") == 0);
    CHECK(r->sections[2].name && strcmp(r->sections[2].name, "section_0003.svg") == 0);
    /* writing again replaces the folder atomically */
    CHECK_OK(bvox_stack_write_svg_dir(dir, s));
    bvox_stack_destroy(r);
    bvox_stack_destroy(s);
    return 0;
}

TEST(json_hand_written)
{
    const char *text =
        "\xEF\xBB\xBF{\"unit\": \"mm\", \"pixel\": 0.5, \"comment\": {\"a\": [1, 2.5e3, true, null, \"x\\u00e9\"]},\n"
        " \"sections\": [\n"
        "  {\"contours\": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]], \"markers\": [[1, 2]]},\n"
        "  {\"z\": 7, \"name\": \"two\\n\", \"contours\": [], \"extra\": [[[]]]},\n"
        "  {}\n"
        " ], \"spacing\": 3}\n";
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read_json_memory(text, strlen(text), "a.json", &s));
    CHECK(strcmp(s->unit, "mm") == 0 && s->pixel == 0.5 && s->spacing == 3);
    CHECK_EQ(s->nsections, 3);
    CHECK(s->sections[0].z == 0 && s->sections[1].z == 7 && s->sections[2].z == 6); /* index * spacing */
    CHECK_EQ(s->sections[0].contours[0].npoints, 4); /* the repeated first point dropped */
    CHECK(s->sections[0].markers[0].x == 1 && s->sections[0].markers[0].y == 2);
    CHECK(strcmp(s->sections[1].name, "two\n") == 0);
    bvox_stack_destroy(s);
    return 0;
}

/* Every malformed input: BVOX_EFORMAT, the name, a line:column, and the
 * given words in the message; nothing leaks (ASan). */
static int expect_json_error(const char *text, const char *words)
{
    bvox_contour_stack *s = (bvox_contour_stack *)&words;
    bvox_status st = bvox_stack_read_json_memory(text, strlen(text), "bad.json", &s);
    if (st != BVOX_EFORMAT || s != NULL || !strstr(bvox_errmsg(), "bad.json:") ||
        !strstr(bvox_errmsg(), words)) {
        fprintf(stderr, "input %s: %s: %s\n", text, bvox_status_name(st), bvox_errmsg());
        return 1;
    }
    return 0;
}

TEST(json_errors)
{
    CHECK(expect_json_error("", "end of the file") == 0);
    CHECK(expect_json_error("[]", "JSON object") == 0);
    CHECK(expect_json_error("{}", "no \"sections\"") == 0);
    CHECK(expect_json_error("{\"sections\": [], }", "") == 0);
    CHECK(expect_json_error("{\"sections\": [{\"contours\": [[[0, 0], [1, 1]]]}]}",
                            "section 1 (z = 0): contour 1 has 2 distinct points") == 0);
    CHECK(expect_json_error("{\"sections\": [{\"name\": \"s5.png\", \"contours\": [[[0,0],[1,0],[1,0],[0,0]]]}]}",
                            "section 's5.png'") == 0);
    CHECK(expect_json_error("{\"sections\": [{\"contours\": [[[0, 0, 1]]]}]}", "more than 2") == 0);
    CHECK(expect_json_error("{\"pixel\": -1, \"sections\": []}", "pixel must be > 0") == 0);
    CHECK(expect_json_error("{\"pixel\": 1e999, \"sections\": []}", "out of range") == 0);
    CHECK(expect_json_error("{\"sections\": []} x", "after the end") == 0);
    CHECK(expect_json_error("{\"sections\": [], \"sections\": []}", "twice") == 0);
    CHECK(expect_json_error("{\"unit\": \"abcdefghijklmnopq\", \"sections\": []}", "longer") == 0);
    CHECK(expect_json_error("{\"sections\": [{\"z\": NaN}]}", "number") == 0);
    CHECK(expect_json_error("{\"width\": 2.5, \"sections\": []}", "integer") == 0);
    CHECK(expect_json_error("{\"a\": \"\\q\", \"sections\": []}", "escape") == 0);
    CHECK(expect_json_error("{\"sections\": [\n\n   {\"z\": }]}", "bad.json:3:10:") == 0);
    /* deep nesting in a skipped value: refused, no crash */
    size_t n = 100000;
    char *deep = malloc(2 * n + 64);
    strcpy(deep, "{\"x\": ");
    size_t len = strlen(deep);
    for (size_t i = 0; i < n; i++) deep[len++] = '[';
    for (size_t i = 0; i < n; i++) deep[len++] = ']';
    strcpy(deep + len, ", \"sections\": []}");
    CHECK(expect_json_error(deep, "nesting deeper") == 0);
    free(deep);
    return 0;
}

TEST(svg_paths_and_shapes)
{
    const char *svg =
        "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [ <!ENTITY x \"y\"> ]>\n"
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"100px\">\n"
        " <!-- a comment with <tags> -->\n"
        " <defs><path d=\"M0 0 L5 0 L5 5 Z\"/></defs>\n"
        " <path d=\"M10,10 h20 v10 H10 z m30 0 l10 0 l0 10 l-10 0 Z\"/>\n"
        " <g transform=\"translate(100 0) scale(2)\"><polygon points=\"0,0 5,0 5,5 0,5\"/>\n"
        "   <circle class=\"big marker\" cx=\"1\" cy=\"2\" r=\"1\"/></g>\n"
        " <polyline points=\"0 50 10 50 10 60\" transform=\"matrix(1 0 0 1 0 1)\"/>\n"
        " <path d=\"M150,50 C150,77.6 172.4,100 200,100 L200 50 Z\"/>\n"
        " <path d=\"M0 80 Q10 70 20 80 T40 80 Z\"/>\n"
        " <rect x=\"60\" y=\"60\" width=\"4\" height=\"3\"/>\n"
        " <circle id=\"marker2\" cx=\"7\" cy=\"8\" r=\"2\"/>\n"
        " <ellipse cx=\"80\" cy=\"80\" rx=\"10\" ry=\"5\"/>\n"
        " <text>ignored &amp; <tspan>this</tspan></text>\n"
        "</svg>\n";
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read_svg_memory(svg, strlen(svg), "dir/s1.svg", 4, &s));
    CHECK_EQ(s->width, 200);
    CHECK_EQ(s->height, 100);
    CHECK_EQ(s->nsections, 1);
    const bvox_section *sec = &s->sections[0];
    CHECK(sec->z == 4 && strcmp(sec->name, "s1.svg") == 0);
    CHECK_EQ(sec->ncontours, 8);
    double want[8] = {200, 100, 100, 50, 0, 0, 12, M_PI * 50};
    /* path 1: two rectangles; polygon scaled 2x: 100; polyline triangle 50;
     * cubic quarter-circle-ish region: area of the quarter disc r=50 bounded
     * by the chord... checked separately below */
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[0].points, sec->contours[0].npoints)), want[0], 1e-9);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[1].points, sec->contours[1].npoints)), want[1], 1e-9);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[2].points, sec->contours[2].npoints)), want[2], 1e-9);
    CHECK(sec->contours[2].points[1].x == 110 && sec->contours[2].points[2].y == 10);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[3].points, sec->contours[3].npoints)), want[3], 1e-9);
    CHECK(sec->contours[3].points[0].y == 51);
    /* the cubic is the usual Bezier quarter circle of radius 50 centred at
     * (200, 50): the region is the quarter disc, to the Bezier's 0.03% radial
     * error and the chords' loss (at most 0.1 pixel over a length of 79) */
    double cub = fabs(bvox_polygon_signed_area(sec->contours[4].points, sec->contours[4].npoints));
    CHECK_NEAR(cub, M_PI * 2500 / 4, 8);
    CHECK(sec->contours[4].npoints > 10);
    /* quadratic then its smooth continuation: an arch up to y = 75 and, with
     * the control point reflected, one down to y = 85 (a figure eight whose
     * signed areas cancel) */
    const bvox_contour *qc = &sec->contours[5];
    CHECK_NEAR(bvox_polygon_signed_area(qc->points, qc->npoints), 0, 1e-6);
    double ymin = HUGE_VAL, ymax = -HUGE_VAL;
    for (int k = 0; k < qc->npoints; k++) {
        ymin = fmin(ymin, qc->points[k].y);
        ymax = fmax(ymax, qc->points[k].y);
    }
    CHECK_NEAR(ymin, 75, 0.1);
    CHECK_NEAR(ymax, 85, 0.1);
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[6].points, sec->contours[6].npoints)), want[6], 1e-9);
    /* chords at most 0.1 pixel inside: the area loss is under 2/3 * 0.1 * the perimeter (48) */
    CHECK_NEAR(fabs(bvox_polygon_signed_area(sec->contours[7].points, sec->contours[7].npoints)), want[7], 3.3);
    CHECK_EQ(sec->nmarkers, 2);
    CHECK(sec->markers[0].x == 102 && sec->markers[0].y == 4);
    CHECK(sec->markers[1].x == 7 && sec->markers[1].y == 8);
    bvox_stack_destroy(s);
    return 0;
}

static int expect_svg_error(const char *text, const char *words)
{
    bvox_contour_stack *s = NULL;
    bvox_status st = bvox_stack_read_svg_memory(text, strlen(text), "bad.svg", 0, &s);
    if (st != BVOX_EFORMAT || s != NULL || !strstr(bvox_errmsg(), "bad.svg:") ||
        !strstr(bvox_errmsg(), words)) {
        fprintf(stderr, "input %s: %s: %s\n", text, bvox_status_name(st), bvox_errmsg());
        return 1;
    }
    return 0;
}

TEST(svg_errors)
{
    CHECK(expect_svg_error("", "no <svg>") == 0);
    CHECK(expect_svg_error("<html/>", "not <svg>") == 0);
    CHECK(expect_svg_error("<svg><path d=\"M0 0 L1 1\"/></svg>", "section 'bad.svg' (z = 0): <path>: an outline with 2") == 0);
    CHECK(expect_svg_error("<svg><path d=\"M0 0 A1 1 0 0 1 5 5 Z\"/></svg>", "arcs") == 0);
    CHECK(expect_svg_error("<svg><path d=\"M0 0 L1\"/></svg>", "needs 2 numbers") == 0);
    CHECK(expect_svg_error("<svg><polygon points=\"0 0 1\"/></svg>", "odd count") == 0);
    CHECK(expect_svg_error("<svg><g transform=\"spin(3)\"><path d=\"M0 0 L1 0 L1 1Z\"/></g></svg>", "unsupported transform") == 0);
    CHECK(expect_svg_error("<svg><g></svg>", "</svg> closes <g>") == 0);
    CHECK(expect_svg_error("<svg>", "ends inside <svg>") == 0);
    CHECK(expect_svg_error("<svg></svg><svg></svg>", "second root") == 0);
    CHECK(expect_svg_error("<svg a=b></svg>", "quoted value") == 0);
    CHECK(expect_svg_error("<svg><rect width=\"&bogus;\"/></svg>", "entity") == 0);
    CHECK(expect_svg_error("<svg>\n\n  <circle cx=\"x\"/></svg>", "bad.svg:3:3:") == 0);
    /* deep nesting */
    size_t n = 5000;
    char *deep = malloc(n * 7 + 64);
    strcpy(deep, "<svg>");
    for (size_t i = 0; i < n; i++) strcat(deep + strlen(deep) - 0, "<g>");
    CHECK(expect_svg_error(deep, "nested deeper") == 0);
    free(deep);
    return 0;
}

TEST(reconstruct_series)
{
    /* NAME.ser + sections 1, 2, 10 (numeric order, not text order); section
     * 1 has a domain image with its boundary contour and an open trace,
     * section 2 a translation (dim 1) and a marker trace, section 10 scales
     * (dim 2: y scale in b1, as RECONSTRUCT reads it) */
    const char *dir = harness_tmpdir();
    char p[512];
    snprintf(p, sizeof p, "%s/rec.ser", dir);
    CHECK(write_text(p, "<?xml version=\"1.0\"?>\n<!DOCTYPE Series SYSTEM \"series.dtd\">\n"
                        "<Series index=\"1\" viewport=\"0 0 0.00254\"/>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.1", dir);
    CHECK(write_text(p, "<?xml version=\"1.0\"?>\n<Section index=\"1\" thickness=\"0.05\">\n"
                        "<Transform dim=\"0\" xcoef=\" 0 1 0 0 0 0\" ycoef=\" 0 0 1 0 0 0\">\n"
                        "<Image mag=\"0.01\" src=\"a.tif\"/>\n"
                        "<Contour name=\"domain1\" closed=\"true\" points=\"0 0, 5 0, 5 5, 0 5,\"/>\n"
                        "</Transform>\n"
                        "<Transform dim=\"0\" xcoef=\" 0 1 0 0 0 0\" ycoef=\" 0 0 1 0 0 0\">\n"
                        "<Contour name=\"d001\" hidden=\"false\" closed=\"true\" points=\"1 1,\n\t2 1,\n\t2 2,\n\t1 2,\n\t\"/>\n"
                        "<Contour name=\"line\" closed=\"false\" points=\"0 0, 3 3\"/>\n"
                        "</Transform>\n</Section>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.2", dir);
    CHECK(write_text(p, "<Section index=\"2\" thickness=\"0.07\">\n"
                        "<Transform dim=\"1\" xcoef=\" 0.5 1 0 0 0 0\" ycoef=\" 0.25 0 1 0 0 0\">\n"
                        "<Contour name=\"d001\" points=\"1.5 1.25, 2.5 1.25, 2.5 2.25, 1.5 2.25\"/>\n"
                        "<Contour name=\"marker1\" points=\"3.5 3.25, 3.7 3.25, 3.6 3.45\"/>\n"
                        "</Transform></Section>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.10", dir);
    CHECK(write_text(p, "<Section index=\"10\" thickness=\"0.05\">\n"
                        "<Transform dim=\"2\" xcoef=\" 0 2 0 0 0 0\" ycoef=\" 0 2 0 0 0 0\">\n"
                        "<Contour name=\"d001\" points=\"2 2, 4 2, 4 4, 2 4\"/>\n"
                        "</Transform></Section>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.1.bak", dir); /* not a section file */
    CHECK(write_text(p, "garbage") == 0);
    snprintf(p, sizeof p, "%s/rec.ser", dir);
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read(p, &s));
    CHECK(strcmp(s->unit, "um") == 0);
    CHECK_NEAR(s->pixel, 0.01, 0);
    CHECK_NEAR(s->spacing, 0.05, 0);
    CHECK_EQ(s->nsections, 3);
    CHECK(strcmp(s->sections[2].name, "rec.10") == 0);
    CHECK_NEAR(s->sections[0].z, 0, 1e-12);
    CHECK_NEAR(s->sections[1].z, 0.07, 1e-12);
    CHECK_NEAR(s->sections[2].z, 0.12, 1e-12);
    for (int i = 0; i < 3; i++) {
        CHECK_EQ(s->sections[i].ncontours, 1);
        const bvox_contour *c = &s->sections[i].contours[0];
        CHECK_EQ(c->npoints, 4);
        /* every section's square is [1, 2] x [1, 2] um: 100 x 100 pixels, y flipped */
        double x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL, y1 = -HUGE_VAL;
        for (int k = 0; k < 4; k++) {
            x0 = fmin(x0, c->points[k].x), x1 = fmax(x1, c->points[k].x);
            y0 = fmin(y0, c->points[k].y), y1 = fmax(y1, c->points[k].y);
        }
        CHECK_NEAR(x0, 100, 1e-9);
        CHECK_NEAR(x1, 200, 1e-9);
        CHECK_NEAR(y0, -200, 1e-9);
        CHECK_NEAR(y1, -100, 1e-9);
    }
    CHECK_EQ(s->sections[1].nmarkers, 1);
    CHECK_NEAR(s->sections[1].markers[0].x, 310, 1e-9);
    CHECK_NEAR(s->sections[1].markers[0].y, -(3.25 + 0.2 / 3 - 0.25) * 100, 1e-9);
    bvox_stack_destroy(s);
    /* a folder holding only the series reads the same */
    CHECK_OK(bvox_stack_read(dir, &s));
    CHECK_EQ(s->nsections, 3);
    bvox_stack_destroy(s);
    /* a polynomial transform (x' = x + 0.1 x y): inverted point by point */
    snprintf(p, sizeof p, "%s/rec.2", dir);
    CHECK(write_text(p, "<Section index=\"2\" thickness=\"0.07\">\n"
                        "<Transform dim=\"6\" xcoef=\" 0 1 0 0.1 0 0\" ycoef=\" 0 0 1 0 0 0\">\n"
                        "<Contour name=\"d001\" points=\"1.1 1, 2.2 1, 2.4 2, 1.2 2\"/>\n"
                        "</Transform></Section>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.ser", dir);
    CHECK_OK(bvox_stack_read(p, &s));
    const bvox_contour *pc = &s->sections[1].contours[0];
    const double wx[4] = {100, 200, 200, 100}, wy[4] = {-100, -100, -200, -200};
    for (int k = 0; k < 4; k++) {
        CHECK_NEAR(pc->points[k].x, wx[k], 1e-6);
        CHECK_NEAR(pc->points[k].y, wy[k], 1e-6);
    }
    bvox_stack_destroy(s);
    /* a bad transform is refused, naming the section file and line */
    snprintf(p, sizeof p, "%s/rec.2", dir);
    CHECK(write_text(p, "<Section index=\"2\" thickness=\"0.07\">\n"
                        "<Transform dim=\"9\" xcoef=\" 0 1 0 0 0 0\" ycoef=\" 0 0 1 0 0 0\">\n"
                        "</Transform></Section>\n") == 0);
    snprintf(p, sizeof p, "%s/rec.ser", dir);
    CHECK_STATUS(bvox_stack_read(p, &s), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "rec.2:2:1: section 'rec.2'") && strstr(bvox_errmsg(), "dim must be"));
    CHECK(s == NULL);
    return 0;
}

TEST(read_dispatch_and_folders)
{
    const char *dir = harness_path("svgfolder");
    CHECK(mkdir(dir, 0755) == 0);
    char p[512];
    const char *names[3] = {"s10.svg", "s2.svg", "s1.svg"};
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        char svg[300];
        snprintf(svg, sizeof svg, "<svg><polygon points=\"0 0 %d 0 %d 5 0 5\"/></svg>", i + 2, i + 2);
        CHECK(write_text(p, svg) == 0);
    }
    snprintf(p, sizeof p, "%s/notes.txt", dir);
    CHECK(write_text(p, "ignored") == 0);
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read(dir, &s));
    CHECK_EQ(s->nsections, 3);
    CHECK(strcmp(s->sections[0].name, "s1.svg") == 0 && strcmp(s->sections[2].name, "s10.svg") == 0);
    CHECK(s->sections[0].z == 0 && s->sections[1].z == 1 && s->sections[2].z == 2);
    CHECK_NEAR(bvox_polygon_signed_area(s->sections[2].contours[0].points, 4), 10, 0); /* s10: i = 0 */
    bvox_stack_destroy(s);
    /* content sniffing without an extension */
    const char *f = harness_path("stack_noext");
    CHECK(write_text(f, "  {\"sections\": [{\"contours\": [[[0,0],[1,0],[1,1]]]}]}") == 0);
    CHECK_OK(bvox_stack_read(f, &s));
    CHECK_EQ(s->sections[0].ncontours, 1);
    bvox_stack_destroy(s);
    CHECK(write_text(f, "hello") == 0);
    CHECK_STATUS(bvox_stack_read(f, &s), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "not a contour stack") != NULL);
    const char *empty = harness_path("empty");
    CHECK(mkdir(empty, 0755) == 0);
    CHECK_STATUS(bvox_stack_read(empty, &s), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "no .svg files") != NULL);
    CHECK_STATUS(bvox_stack_read(harness_path("missing.json"), &s), BVOX_ENOTFOUND);
    CHECK(s == NULL);
    /* a write into a missing folder fails cleanly */
    bvox_contour_stack *t = NULL;
    CHECK_OK(bvox_stack_create(&t));
    CHECK(bvox_stack_write_json(harness_path("no/such/dir/x.json"), t) != BVOX_OK);
    bvox_stack_destroy(t);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Reconstruct's <Series units=...> sets the stack's unit (microns the
 * default); a unit bvox cannot name is refused, never taken as microns (an
 * EM series in nanometers read as um is 10^9 off in volume). */
static int series_with_units(const char *units, bvox_contour_stack **out)
{
    const char *dir = harness_tmpdir();
    char p[512], ser[600];
    snprintf(p, sizeof p, "%s/u.ser", dir);
    snprintf(ser, sizeof ser, "<?xml version=\"1.0\"?>\n<Series index=\"1\"%s%s%s/>\n",
             units ? " units=\"" : "", units ? units : "", units ? "\"" : "");
    if (write_text(p, ser)) return -1;
    char sec[512];
    snprintf(sec, sizeof sec, "%s/u.1", dir);
    if (write_text(sec, "<Section index=\"1\" thickness=\"0.05\"><Transform dim=\"0\" "
                        "xcoef=\" 0 1 0 0 0 0\" ycoef=\" 0 0 1 0 0 0\"><Contour name=\"a\" "
                        "points=\"1 1, 2 1, 2 2, 1 2\"/></Transform></Section>\n"))
        return -1;
    return (int)bvox_stack_read(p, out);
}

TEST(reconstruct_series_units)
{
    static const char *const given[] = {NULL, "microns", "nanometers", "millimeters", "Meters"};
    static const char *const want[] = {"um", "um", "nm", "mm", "m"};
    for (int i = 0; i < 5; i++) {
        bvox_contour_stack *s = NULL;
        CHECK_EQ(series_with_units(given[i], &s), BVOX_OK);
        CHECK(strcmp(s->unit, want[i]) == 0);
        CHECK(s->given & BVOX_STACK_GIVEN_UNIT);
        CHECK(s->given & BVOX_STACK_GIVEN_SPACING);
        CHECK_NEAR(s->spacing, 0.05, 0);
        bvox_stack_destroy(s);
    }
    bvox_contour_stack *s = NULL;
    CHECK_EQ(series_with_units("furlongs", &s), BVOX_EFORMAT);
    CHECK(s == NULL);
    CHECK(strstr(bvox_errmsg(), "furlongs") != NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

typedef struct warnings {
    int n;
    char last[512];
} warnings;

static void collect(const char *msg, void *user)
{
    warnings *w = user;
    w->n++;
    snprintf(w->last, sizeof w->last, "%s", msg);
}

/* Keys another tool wrote are ignored, but said: one warning per top-level
 * key, one per section key (not one per section). Known keys never warn. */
TEST(json_unknown_keys_warn)
{
    warnings w = {0, ""};
    bvox_set_warning_handler(collect, &w);
    const char *known = "{\"unit\":\"um\",\"pixel\":2,\"spacing\":3,\"width\":9,\"height\":9,"
                        "\"origin\":[0,0],\"sections\":[{\"z\":0,\"name\":\"a\",\"markers\":[],"
                        "\"contours\":[[[1,1],[4,1],[4,4]]]}]}";
    bvox_contour_stack *s = NULL;
    CHECK_OK(bvox_stack_read_json_memory(known, strlen(known), "k.json", &s));
    CHECK_EQ(w.n, 0);
    CHECK_EQ(s->given, BVOX_STACK_GIVEN_PIXEL | BVOX_STACK_GIVEN_SPACING | BVOX_STACK_GIVEN_UNIT);
    CHECK_EQ(s->sections[0].z_from_index, 0);
    bvox_stack_destroy(s);
    const char *other = "{\"canvas\":[640,480],\"sections\":[{\"layer\":1,\"contours\":[]},"
                        "{\"layer\":2},{\"layer\":3}]}";
    uint64_t before = bvox_warning_count();
    CHECK_OK(bvox_stack_read_json_memory(other, strlen(other), "o.json", &s));
    CHECK_EQ(w.n, 2);
    CHECK_EQ(bvox_warning_count() - before, 2);
    CHECK(strstr(w.last, "\"layer\"") && strstr(w.last, "section 1 and others"));
    CHECK_EQ(s->given, 0);
    CHECK_EQ(s->sections[2].z_from_index, 1);
    CHECK_NEAR(s->sections[2].z, 2, 0);
    bvox_stack_destroy(s);
    bvox_set_warning_handler(NULL, NULL);
    CHECK_OK(bvox_stack_read_json_memory(other, strlen(other), "o.json", &s));
    CHECK_EQ(w.n, 2); /* no handler: dropped, but still counted */
    bvox_stack_destroy(s);
    return 0;
}
