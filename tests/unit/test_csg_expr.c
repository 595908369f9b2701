/* test_csg_expr.c — CSG expressions: parsing (precedence, parentheses,
 * quoting, every error with its column: unbalanced parentheses, unknown
 * primitive, missing or unknown parameter, bad number, trailing garbage,
 * too deep nesting, too long, empty), evaluation against the byte-per-voxel
 * reference with files (served from memory by a loader callback) placed at
 * offsets that cross word boundaries, the set identities, primitives equal
 * to direct bvox_shape_draw / bvox_halfspace_draw calls, physical units
 * (a sphere of r = 10 mm on 0.5 mm voxels), grid rules and loader errors. */
#include "harness.h"
#include "internal.h"
#include "ref/voxref.h"

#include <stdlib.h>
#include <string.h>

/* ---- files from memory ---- */

#define NFILES 3
typedef struct files {
    const char *names[NFILES];
    voxref *ref[NFILES];
    bvox_geometry geom[NFILES];
    int loads[NFILES];
    int refuse; /* 1: every load fails (parse-only must not load) */
} files;

static bvox_status load(void *ctx, const char *name, bvox_volume **out)
{
    files *f = ctx;
    if (f->refuse) return BVOX_EIO;
    for (int i = 0; i < NFILES; i++)
        if (f->names[i] && !strcmp(f->names[i], name)) {
            f->loads[i]++;
            bvox_volume *v = voxref_to_volume(f->ref[i]);
            if (!v) return BVOX_ENOMEM;
            bvox_volume_set_geometry(v, &f->geom[i]);
            *out = v;
            return BVOX_OK;
        }
    return bvox__fail(BVOX_ENOTFOUND, "%s: no such test file", name);
}

static void files_init(files *f, const int dims[NFILES][3])
{
    memset(f, 0, sizeof *f);
    static const char *names[NFILES] = {"A", "b.nii", "my-file.nii.gz"};
    for (int i = 0; i < NFILES; i++) {
        f->names[i] = names[i];
        f->ref[i] = voxref_create(dims[i][0], dims[i][1], dims[i][2]);
        voxref_random(f->ref[i], 1, 2, harness_rand);
        f->geom[i] = bvox_geometry_default();
    }
}

static void files_free(files *f)
{
    for (int i = 0; i < NFILES; i++) voxref_destroy(f->ref[i]);
}

static bvox_status eval(files *f, const char *expr, bvox_volume **out)
{
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.load = load;
    o.load_ctx = f;
    return bvox_csg_eval(expr, &o, out);
}

static int64_t eval_count(files *f, const char *expr)
{
    bvox_volume *v = NULL;
    if (eval(f, expr, &v)) {
        fprintf(stderr, "%s: %s\n", expr, bvox_errmsg());
        return -1;
    }
    int64_t n = bvox_volume_check(v) ? -2 : bvox_volume_count(v);
    bvox_volume_destroy(v);
    return n;
}

static int same(files *f, const char *e1, const char *e2)
{
    bvox_volume *a = NULL, *b = NULL;
    bvox_status s1 = eval(f, e1, &a), s2 = eval(f, e2, &b);
    int ok = !s1 && !s2 && bvox_volume_equal(a, b);
    if (!ok) fprintf(stderr, "'%s' differs from '%s' (%s)\n", e1, e2, bvox_errmsg());
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return ok;
}

static const int dims_awkward[NFILES][3] = {{9, 7, 130}, {5, 11, 65}, {7, 3, 63}};

/* ---- parsing errors ---- */

static int error_is(const char *expr, const char *want)
{
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.parse_only = 1;
    bvox_volume *v = (bvox_volume *)&o; /* must become NULL */
    bvox_status st = bvox_csg_eval(expr, &o, &v);
    if (st != BVOX_EINVAL || v != NULL || !strstr(bvox_errmsg(), want)) {
        fprintf(stderr, "'%.80s': got %s '%s', wanted '%s'\n", expr, bvox_status_name(st),
                bvox_errmsg(), want);
        return 0;
    }
    return 1;
}

TEST(parse_errors)
{
    CHECK(error_is("", "csg: empty expression"));
    CHECK(error_is("  \t ", "csg: empty expression"));
    CHECK(error_is("(a.nii + b.nii", "csg: expected ')' at column 15"));
    CHECK(error_is("((a) + (b)", "csg: expected ')' at column 11"));
    CHECK(error_is("a.nii + b.nii)", "csg: unmatched ')' at column 14"));
    CHECK(error_is("a.nii b.nii", "csg: expected an operator at column 7"));
    CHECK(error_is("a.nii +", "csg: expected an operand, found the end at column 8"));
    CHECK(error_is("a.nii + * b", "csg: expected an operand at column 9"));
    CHECK(error_is("- a.nii", "csg: expected an operand at column 1"));
    CHECK(error_is("()", "csg: expected an operand at column 2"));
    CHECK(error_is("a + sphre(r=2)", "csg: unknown primitive 'sphre'"));
    CHECK(error_is("a + sphre(r=2)", "sphre' at column 5 (known: sphere,"));
    CHECK(error_is("sphere(at=1,2,3)", "csg: sphere: missing parameter 'r' at column 1"));
    CHECK(error_is("x - cylinder(r=1)", "csg: cylinder: missing parameter 'h' at column 5"));
    CHECK(error_is("sphere(r=2, q=1)", "csg: sphere has no parameter 'q' at column 13"));
    CHECK(error_is("sphere(r=2, r=3)", "csg: sphere: parameter 'r' given twice at column 13"));
    CHECK(error_is("sphere(r=abc)", "csg: expected a number at column 10"));
    CHECK(error_is("sphere(r=1e999)", "csg: number out of range at column 10"));
    CHECK(error_is("sphere(r=inf)", "csg: expected a number at column 10"));
    CHECK(error_is("sphere(r=0x10)", "csg: expected ',' or ')' at column 11"));
    CHECK(error_is("sphere(r=2mm)", "csg: expected ',' or ')' at column 11"));
    CHECK(error_is("sphere(r=2, at=1,2)", "csg: sphere: 'at' needs 3 values at column 13"));
    CHECK(error_is("sphere(r=2, at=1,2,3,4)", "csg: sphere: too many values for 'at' at column 22"));
    CHECK(error_is("sphere(r 2)", "csg: expected '=' after 'r' at column 10"));
    CHECK(error_is("sphere(=2)", "csg: expected a parameter name at column 8"));
    CHECK(error_is("sphere(r=2", "csg: expected ',' or ')' at column 11"));
    CHECK(error_is("sphere(r=-2)", "csg: sphere at column 1: "));
    CHECK(error_is("sphere + a", "csg: sphere needs its parameters in parentheses at column 1"));
    CHECK(error_is("box(size=1,2,3, min=0,0,0, max=1,1,1)", "csg: box: give size="));
    CHECK(error_is("box(min=0,0,0)", "csg: box: give size="));
    CHECK(error_is("box(min=0,5,0, max=1,1,1)", "csg: box: max is below min at column 1"));
    CHECK(error_is("halfspace(n=0,0,0)", "csg: halfspace: the normal n is zero"));
    CHECK(error_is("ellipsoid(r=1,2, at=0,0,0)", "'r' needs 1 or 3 values"));
    CHECK(error_is("a.nii@1,2", "csg: expected ',' at column 10"));
    CHECK(error_is("a.nii@1.5,2,3", "voxel offset must be an integer at column 7"));
    CHECK(error_is("a.nii@(1,2,3", "csg: expected ')' at column 13"));
    CHECK(error_is("a.nii@1e12,0,0", "offset too large at column 7"));
    CHECK(error_is("'a.nii + b", "csg: unterminated quoted file name at column 1"));
    CHECK(error_is("a + ''", "csg: empty file name at column 5"));
    CHECK(error_is("a + ~", "csg: expected an operand, found the end at column 6"));
    CHECK(error_is("a ? b", "csg: expected an operator at column 3"));
    /* nesting: 256 levels are fine, 257 are refused, 30000 do not crash */
    size_t n = 30000;
    char *deep = malloc(2 * n + 4);
    CHECK(deep);
    for (int k = 0; k < 2; k++) {
        size_t levels = k ? n : 257;
        memset(deep, '(', levels);
        deep[levels] = 'a';
        memset(deep + levels + 1, ')', levels);
        deep[2 * levels + 1] = '\0';
        CHECK(error_is(deep, "nesting deeper than 256 at column 257"));
        memset(deep, '~', levels);
        deep[levels] = 'a';
        deep[levels + 1] = '\0';
        CHECK(error_is(deep, "nesting deeper than 256 at column 257"));
    }
    memset(deep, '(', 256);
    deep[256] = 'a';
    memset(deep + 257, ')', 256);
    deep[513] = '\0';
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.parse_only = 1;
    bvox_volume *v = NULL;
    CHECK_OK(bvox_csg_eval(deep, &o, &v));
    CHECK(v == NULL);
    free(deep);
    /* length */
    char *big = malloc(BVOX_CSG_MAX_LENGTH + 2);
    CHECK(big);
    memset(big, 'a', BVOX_CSG_MAX_LENGTH + 1);
    big[BVOX_CSG_MAX_LENGTH + 1] = '\0';
    CHECK(error_is(big, "longer than 65536"));
    big[BVOX_CSG_MAX_LENGTH] = '\0';
    CHECK_OK(bvox_csg_eval(big, &o, &v));
    free(big);
    CHECK_STATUS(bvox_csg_eval(NULL, &o, &v), BVOX_EINVAL);
    CHECK_STATUS(bvox_csg_eval("a", &o, NULL), BVOX_EINVAL);
    return 0;
}

TEST(parse_only_reads_nothing)
{
    files f;
    files_init(&f, dims_awkward);
    f.refuse = 1;
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.load = load;
    o.load_ctx = &f;
    o.parse_only = 1;
    bvox_volume *v = NULL;
    CHECK_OK(bvox_csg_eval("A - (b.nii@1,-2,70 * ~my-file.nii.gz@(0.5,1,2)) ^ "
                           "sphere(r=2, at=1,2,3) + box(min=0,0,0, max=1,2,3) + 'x y.nii'",
                           &o, &v));
    CHECK(v == NULL);
    for (int i = 0; i < NFILES; i++) CHECK_EQ(f.loads[i], 0);
    /* evaluated, a refused load is an error naming the column */
    o.parse_only = 0;
    CHECK_STATUS(bvox_csg_eval("sphere(r=1) + b.nii", &o, &v), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "csg: column 15"));
    CHECK(v == NULL);
    files_free(&f);
    return 0;
}

/* ---- evaluation against the reference ---- */

/* dst = OP-combination through the reference, for "A op name@off". */
static int check_binary(files *f, const char *op_txt, bvox_csg_op op, int file,
                        const int off[3])
{
    char expr[160];
    snprintf(expr, sizeof expr, "A %s %s@%d,%d,%d", op_txt, f->names[file], off[0], off[1],
             off[2]);
    voxref *want = voxref_copy(f->ref[0]);
    voxref_csg(want, op, f->ref[file], off);
    bvox_volume *v = NULL;
    CHECK_OK(eval(f, expr, &v));
    int ok = voxref_matches(want, v);
    if (!ok) fprintf(stderr, "%s\n", expr);
    bvox_volume_destroy(v);
    voxref_destroy(want);
    return ok ? 0 : 1;
}

TEST(files_at_offsets)
{
    files f;
    files_init(&f, dims_awkward);
    static const int zoffs[] = {-70, -64, -63, -1, 0, 1, 37, 63, 64, 65, 129};
    static const char *ops[] = {"+", "*", "-", "^"};
    static const bvox_csg_op opv[] = {BVOX_CSG_UNION, BVOX_CSG_INTERSECTION,
                                      BVOX_CSG_DIFFERENCE, BVOX_CSG_XOR};
    for (int file = 1; file < NFILES; file++)
        for (int k = 0; k < 4; k++)
            for (size_t z = 0; z < sizeof zoffs / sizeof zoffs[0]; z++) {
                int off[3] = {(int)(harness_rand() % 12) - 5, (int)(harness_rand() % 12) - 5,
                              zoffs[z]};
                CHECK(!check_binary(&f, ops[k], opv[k], file, off));
            }
    /* each distinct file loaded once per evaluation */
    memset(f.loads, 0, sizeof f.loads);
    CHECK(eval_count(&f, "A + A * b.nii - (b.nii@1,1,1 ^ A)") >= 0);
    CHECK_EQ(f.loads[0], 1);
    CHECK_EQ(f.loads[1], 1);
    CHECK_EQ(f.loads[2], 0);
    /* the grid is the first file's, whatever the other sizes */
    bvox_volume *v = NULL;
    CHECK_OK(eval(&f, "b.nii + A", &v));
    bvox_dims d = bvox_volume_dims(v);
    CHECK(d.nx == 5 && d.ny == 11 && d.nz == 65);
    bvox_volume_destroy(v);
    files_free(&f);
    return 0;
}

TEST(identities)
{
    files f;
    files_init(&f, dims_awkward);
    const char *B[] = {"b.nii@3,-2,70", "b.nii@-1,4,-63", "my-file.nii.gz@2,2,64",
                       "'my-file.nii.gz' @ 0 , 0 , 1"};
    for (size_t i = 0; i < sizeof B / sizeof B[0]; i++) {
        char e1[200], e2[200], e3[200];
        snprintf(e1, sizeof e1, "A + %s", B[i]);
        snprintf(e2, sizeof e2, "A * %s", B[i]);
        /* "A - A + B": B alone on A's grid (B first would be B's own grid) */
        snprintf(e3, sizeof e3, "A - A + %s", B[i]);
        int64_t u = eval_count(&f, e1), in = eval_count(&f, e2), a = eval_count(&f, "A"),
                b = eval_count(&f, e3);
        if (!(u >= 0 && in > 0 && a > 0 && b > 0))
            fprintf(stderr, "%s: %lld %lld %lld %lld\n", B[i], (long long)u, (long long)in,
                    (long long)a, (long long)b);
        CHECK(u >= 0 && in > 0 && a > 0 && b > 0);
        CHECK_EQ(u, a + b - in);
        snprintf(e1, sizeof e1, "A - %s", B[i]);
        snprintf(e2, sizeof e2, "A * ~%s", B[i]);
        CHECK(same(&f, e1, e2));
        snprintf(e1, sizeof e1, "A ^ %s", B[i]);
        snprintf(e2, sizeof e2, "(A - %s) + (%s - A)", B[i], B[i]);
        CHECK(same(&f, e1, e2));
        snprintf(e1, sizeof e1, "A - A + ~~%s", B[i]);
        CHECK(same(&f, e1, e3));
        /* De Morgan */
        snprintf(e1, sizeof e1, "~(A + %s)", B[i]);
        snprintf(e2, sizeof e2, "~A * ~%s", B[i]);
        CHECK(same(&f, e1, e2));
    }
    CHECK(same(&f, "~~A", "A"));
    CHECK(same(&f, "A ^ A", "A - A"));
    CHECK_EQ(eval_count(&f, "A - A"), 0);
    CHECK_EQ(eval_count(&f, "A + ~A"), 9 * 7 * 130);
    files_free(&f);
    return 0;
}

TEST(precedence)
{
    files f;
    files_init(&f, dims_awkward);
    /* '*' binds tighter; + - ^ group left to right */
    CHECK(same(&f, "A + b.nii * my-file.nii.gz", "A + (b.nii * my-file.nii.gz)"));
    CHECK(same(&f, "A * b.nii + my-file.nii.gz", "(A * b.nii) + my-file.nii.gz"));
    CHECK(same(&f, "A - b.nii - my-file.nii.gz", "(A - b.nii) - my-file.nii.gz"));
    CHECK(same(&f, "A - b.nii + my-file.nii.gz", "(A - b.nii) + my-file.nii.gz"));
    CHECK(same(&f, "A ^ b.nii - my-file.nii.gz", "(A ^ b.nii) - my-file.nii.gz"));
    CHECK(same(&f, "~A * b.nii", "(~A) * b.nii"));
    CHECK(same(&f, "A+b.nii*my-file.nii.gz", "A + (b.nii * my-file.nii.gz)"));
    /* and they differ from the other grouping (so the test can fail) */
    bvox_volume *x = NULL, *y = NULL;
    CHECK_OK(eval(&f, "A - b.nii + my-file.nii.gz", &x));
    CHECK_OK(eval(&f, "A - (b.nii + my-file.nii.gz)", &y));
    CHECK(!bvox_volume_equal(x, y));
    bvox_volume_destroy(x);
    bvox_volume_destroy(y);
    /* a long flat chain evaluates iteratively */
    size_t terms = 5000;
    char *chain = malloc(terms * 4 + 1);
    CHECK(chain);
    char *p = chain;
    for (size_t i = 0; i < terms; i++) p += sprintf(p, i ? " ^ A" : "A");
    CHECK_EQ(eval_count(&f, chain), 0); /* even number of A's */
    free(chain);
    files_free(&f);
    return 0;
}

/* ---- primitives ---- */

static int same_as_shape(const char *expr, const bvox_shape *s, const bvox_geometry *g,
                         bvox_dims d)
{
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = d;
    o.geometry = *g;
    bvox_volume *a = NULL, *b = NULL;
    CHECK_OK(bvox_csg_eval(expr, &o, &a));
    CHECK_OK(bvox_volume_create(d, &b));
    CHECK_OK(bvox_volume_set_geometry(b, g));
    CHECK_OK(bvox_shape_draw(b, s, BVOX_CSG_UNION));
    int ok = bvox_volume_equal(a, b) && bvox_volume_count(a) > 0;
    if (!ok) fprintf(stderr, "%s: %lld vs %lld voxels\n", expr, (long long)bvox_volume_count(a),
                     (long long)bvox_volume_count(b));
    const bvox_geometry *ga = bvox_volume_geometry(a);
    ok = ok && ga->spacing[2] == g->spacing[2] && !strcmp(ga->unit, g->unit);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return ok ? 0 : 1;
}

TEST(primitives_match_shapes)
{
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 0.5;
    g.spacing[1] = 0.75;
    g.spacing[2] = 1.25;
    g.origin[0] = -3;
    snprintf(g.unit, sizeof g.unit, "mm");
    bvox_dims d = {31, 27, 70};
    bvox_shape s = {BVOX_SHAPE_SPHERE, {4, 9, 40}, {0}, {0, 0, 1}, 6, 0, 0};
    CHECK(!same_as_shape("sphere(r=6, at=4,9,40)", &s, &g, d));
    s = (bvox_shape){BVOX_SHAPE_ELLIPSOID, {4, 9, 40}, {5, 3, 20}, {0, 0, 1}, 0, 0, 0};
    CHECK(!same_as_shape("ellipsoid(r=5,3,20, at=4,9,40)", &s, &g, d));
    s = (bvox_shape){BVOX_SHAPE_BOX, {4, 9, 40}, {2.5, 3, 10}, {0, 0, 1}, 0, 0, 0};
    CHECK(!same_as_shape("box(size=5,6,20, at=4,9,40)", &s, &g, d));
    CHECK(!same_as_shape("box(min=1.5,6,30, max=6.5,12,50)", &s, &g, d));
    s = (bvox_shape){BVOX_SHAPE_CYLINDER, {4, 9, 40}, {0}, {1, 1, 2}, 3, 0, 30};
    CHECK(!same_as_shape("cylinder(r=3, h=30, at=4,9,40, axis=1,1,2)", &s, &g, d));
    s = (bvox_shape){BVOX_SHAPE_CONE, {4, 9, 20}, {0}, {0, 0.2, 1}, 5, 0, 40};
    CHECK(!same_as_shape("cone(r=5, h=40, at=4,9,20, axis=0,0.2,1)", &s, &g, d));
    s = (bvox_shape){BVOX_SHAPE_TORUS, {4, 9, 40}, {0}, {1, 0, 0}, 6, 2, 0};
    CHECK(!same_as_shape("torus(R=6, r=2, at=4,9,40, axis=1,0,0)", &s, &g, d));
    /* default centre: the middle of the grid, origin + (n-1)/2 * spacing */
    s = (bvox_shape){BVOX_SHAPE_SPHERE, {-3 + 15 * 0.5, 13 * 0.75, 34.5 * 1.25}, {0},
                     {0, 0, 1}, 6, 0, 0};
    CHECK(!same_as_shape("sphere(r=6)", &s, &g, d));
    /* halfspace against bvox_halfspace_draw */
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = d;
    o.geometry = g;
    bvox_volume *a = NULL, *b = NULL;
    CHECK_OK(bvox_csg_eval("halfspace(n=1,-2,0.5, d=3) * sphere(r=8)", &o, &a));
    CHECK_OK(bvox_volume_create(d, &b));
    CHECK_OK(bvox_volume_set_geometry(b, &g));
    s = (bvox_shape){BVOX_SHAPE_SPHERE, {-3 + 15 * 0.5, 13 * 0.75, 34.5 * 1.25}, {0},
                     {0, 0, 1}, 8, 0, 0};
    CHECK_OK(bvox_shape_draw(b, &s, BVOX_CSG_UNION));
    int64_t ball = bvox_volume_count(b);
    CHECK_OK(bvox_halfspace_draw(b, 1, -2, 0.5, 3, BVOX_CSG_INTERSECTION, NULL));
    CHECK(bvox_volume_equal(a, b));
    CHECK(bvox_volume_count(a) > 0 && bvox_volume_count(a) < ball);
    bvox_volume_destroy(a);
    CHECK_OK(bvox_csg_eval("halfspace(n=0,0,1)", &o, &a)); /* d defaults to 0 */
    CHECK_EQ(bvox_volume_count(a), (int64_t)31 * 27 * 70);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return 0;
}

TEST(physical_units)
{
    /* a sphere of r = 10 mm on 0.5 mm voxels has ~ 4/3 pi 20^3 voxels */
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = (bvox_dims){48, 48, 48};
    o.geometry.spacing[0] = o.geometry.spacing[1] = o.geometry.spacing[2] = 0.5;
    snprintf(o.geometry.unit, sizeof o.geometry.unit, "mm");
    bvox_volume *v = NULL;
    CHECK_OK(bvox_csg_eval("sphere(r=10)", &o, &v));
    double want = 4.0 / 3.0 * M_PI * 20 * 20 * 20;
    CHECK_NEAR((double)bvox_volume_count(v), want, 0.01 * want);
    bvox_volume_destroy(v);
    /* and 1 mm voxels: 8 times fewer */
    o.geometry.spacing[0] = o.geometry.spacing[1] = o.geometry.spacing[2] = 1;
    CHECK_OK(bvox_csg_eval("sphere(r=10)", &o, &v));
    CHECK_NEAR((double)bvox_volume_count(v), want / 8, 0.02 * want / 8);
    bvox_volume_destroy(v);
    /* physical placement rounds to the grid: (1, 0.75, 32) mm on 0.5 mm
     * voxels is (2, 2, 64) voxels (0.75 / 0.5 = 1.5 rounds away from 0) */
    files f;
    files_init(&f, dims_awkward);
    for (int i = 0; i < NFILES; i++)
        for (int k = 0; k < 3; k++) f.geom[i].spacing[k] = 0.5;
    CHECK(same(&f, "A + b.nii@(1,0.75,32)", "A + b.nii@2,2,64"));
    CHECK(same(&f, "A - b.nii@(-1.2,0,-31.9)", "A - b.nii@-2,0,-64"));
    /* a file with other voxels is refused, naming both sizes */
    f.geom[2].spacing[2] = 1;
    bvox_volume *w = NULL;
    CHECK_STATUS(eval(&f, "A + my-file.nii.gz", &w), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "column 5: my-file.nii.gz has voxels of 0.5 x 0.5 x 1"));
    CHECK(w == NULL);
    /* but it may define the grid itself */
    CHECK_OK(eval(&f, "my-file.nii.gz + sphere(r=1)", &w));
    CHECK_EQ(bvox_volume_geometry(w)->spacing[2], 1);
    bvox_volume_destroy(w);
    files_free(&f);
    return 0;
}

TEST(grid_and_loader_errors)
{
    /* only primitives and no grid */
    bvox_volume *v = NULL;
    CHECK_STATUS(bvox_csg_eval("sphere(r=1)", NULL, &v), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "no file operand"));
    /* a bad grid geometry */
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = (bvox_dims){4, 4, 4};
    o.geometry.spacing[1] = 0;
    CHECK(bvox_csg_eval("sphere(r=1)", &o, &v) != BVOX_OK);
    CHECK(v == NULL);
    /* a missing file through the default loader (bvox_read) */
    CHECK_STATUS(bvox_csg_eval("sphere(r=1) + /nonexistent/x.nii", NULL, &v), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "csg: column 15: "));
    CHECK(strstr(bvox_errmsg(), "/nonexistent/x.nii"));
    /* an unknown name from the loader */
    files f;
    files_init(&f, dims_awkward);
    CHECK_STATUS(eval(&f, "A + nope", &v), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "csg: column 5"));
    /* over the memory budget: a clean status, nothing leaked */
    bvox_set_memory_budget(1 << 20);
    o = bvox_csg_eval_opts_default();
    o.dims = (bvox_dims){1000, 1000, 64};
    CHECK_STATUS(bvox_csg_eval("sphere(r=1)", &o, &v), BVOX_ETOOBIG);
    bvox_set_memory_budget(0);
    CHECK(v == NULL);
    CHECK_EQ(bvox_memory_in_use(), 0);
    files_free(&f);
    return 0;
}

TEST(real_file_round_trip)
{
    /* through bvox_read: a file written here, then an expression on it */
    bvox_volume *a = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){20, 20, 70}, &a));
    CHECK_OK(bvox_volume_set_spacing(a, 0.5, 0.5, 0.5, "mm"));
    bvox_volume_fill_box(a, (bvox_box){2, 2, 2, 18, 18, 68}, 1);
    const char *path = harness_path("a.nii");
    CHECK_OK(bvox_write(path, a, NULL));
    char expr[1200];
    snprintf(expr, sizeof expr, "'%s' - sphere(r=2, at=4.5,4.5,10)", path);
    bvox_volume *v = NULL;
    CHECK_OK(bvox_csg_eval(expr, NULL, &v));
    bvox_volume *want = NULL;
    CHECK_OK(bvox_volume_copy(a, &want));
    bvox_shape s = {BVOX_SHAPE_SPHERE, {4.5, 4.5, 10}, {0}, {0, 0, 1}, 2, 0, 0};
    CHECK_OK(bvox_shape_draw(want, &s, BVOX_CSG_DIFFERENCE));
    CHECK(bvox_volume_equal(v, want));
    CHECK(bvox_volume_count(v) < bvox_volume_count(a));
    CHECK_EQ(bvox_volume_geometry(v)->spacing[0], 0.5);
    bvox_volume_destroy(a);
    bvox_volume_destroy(v);
    bvox_volume_destroy(want);
    return 0;
}
