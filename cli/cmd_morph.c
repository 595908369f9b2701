/*
 * cmd_morph.c — `bvox morph IN OPERATION -o OUT`: one morphological operation
 * of the library (src/morph.c, src/morph_derived.c) on a volume read with the
 * shared read options, written like convert writes (temporary file, renamed
 * on success).
 *
 * --radius is in the file's physical unit and selects the ball (an ellipsoid
 * in voxels when the voxels are not cubes); without it the 6-, 18- or
 * 26-neighbourhood of --conn is used. Options that an operation would ignore
 * are refused, so that a typo in a script does not go unnoticed.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "manip.h"
#include "opts.h"
#include "outofcore.h"

#include <string.h>

typedef enum op { DILATE, ERODE, OPEN, CLOSE, FILL, HOLLOW, ISLANDS, NOPS } op;
static const char *const op_names[NOPS] = {"dilate", "erode",  "open",   "close",
                                           "fill",   "hollow", "islands"};

typedef struct morph_args {
    const char *in, *opname, *out;
    double radius;
    int64_t conn, min_size;
    int json;
    bvox_write_opts wo;
    cli_read_args ra;
} morph_args;

#define A(member) CLI_AT(morph_args, member)

static const cli_opt morph_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT", "the file to write (required)", A(out)},
    {"--radius", 0, CLI_DOUBLE, "R",
     "dilate, erode, open, close: use a ball of radius R in the file's unit (voxel offsets "
     "(i,j,k) with (i*sx)^2 + (j*sy)^2 + (k*sz)^2 <= R^2); hollow: the shell's thickness",
     A(radius), .flags = CLI_MIN_OPEN, .min = 0, .bad = "--radius: '%s' is not a length > 0"},
    {"--conn", 0, CLI_INT, NULL,
     "neighbourhood when --radius is not given (default 26; hollow: 6); islands: the "
     "connectivity (default 26)",
     A(conn), .lo = 0, .hi = 26, .choices = cli_conn_choices,
     .bad = "--conn: '%s' is not 6, 18 or 26"},
    {"--min-size", 0, CLI_INT, "N", "islands: smallest component kept, in voxels (required)",
     A(min_size), .lo = 1, .hi = INT64_MAX, .bad = "--min-size: '%s' is not a voxel count >= 1"},
    CLI_OPT_OUTPUT_FORMAT(morph_args, wo.format),
    CLI_OPT_FORCE(morph_args, wo.force),
    {"--json", 0, CLI_FLAG, NULL,
     "print one JSON object: what 'bvox info --json' says of OUT, input, output, operation, "
     "conn, radius, min_size, count_before, count_after",
     A(json)},
    {NULL},
};
static const cli_group morph_group = {"Options", morph_opts, NULL};
static const cli_pos morph_pos[] = {
    {"IN", "the volume to read", A(in)},
    {"OPERATION", "dilate, erode, open, close, fill, hollow or islands", A(opname)},
    {NULL},
};
static const cli_section morph_sections[] = {
    {"Operations",
     "  dilate    add every voxel within reach of the object\n"
     "  erode     keep only voxels whose whole neighbourhood is object (the\n"
     "            outside of the volume counts as background)\n"
     "  open      erode, then dilate: removes specks and thin bridges\n"
     "  close     dilate, then erode: closes small gaps and dents (the border of\n"
     "            the volume does not eat into the object)\n"
     "  fill      fill the cavities (background not 6-connected to the border)\n"
     "  hollow    keep only the shell: object voxels within --radius of the\n"
     "            background (default: the voxels with a --conn neighbour outside\n"
     "            the object, --conn 6 by default: a one-voxel shell)\n"
     "  islands   remove the components (--conn connected) of fewer than\n"
     "            --min-size voxels\n"},
    {NULL, NULL},
};

const cli_spec cli_spec_morph = {
    .name = "morph",
    .summary = "dilate, erode, open, close, fill cavities, hollow, remove islands",
    .usage = "IN OPERATION -o OUT [options]",
    .about = "Apply one morphological operation to a volume and write the result.\n",
    .pos = morph_pos,
    .sections = morph_sections,
    .uses = {{&morph_group, 0}, CLI_USE_READ(morph_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox morph mask.nii.gz dilate --conn 6 -o grown.nii.gz\n"
                "  bvox morph embryo.tif close --radius 0.05 -o closed.tif\n"
                "  bvox morph mask.nii islands --min-size 100 -o clean.nii\n"
                "  bvox morph organ.nii hollow --radius 0.5 -o shell.nii\n",
};

static int parse_op(const char *s)
{
    for (int i = 0; i < NOPS; i++)
        if (!strcmp(s, op_names[i])) return i;
    return -1;
}

/* hollow without --radius: the object minus its erosion by the neighbourhood,
 * i.e. the voxels with a neighbour outside the object. */
static bvox_status hollow_conn(const bvox_volume *in, int conn, bvox_volume **out)
{
    *out = NULL;
    bvox_volume *inner = NULL;
    bvox_status st = bvox_morph_erode(in, conn, &inner);
    if (st) return st;
    st = bvox_volume_copy(in, out);
    if (!st) st = bvox_csg_apply(*out, BVOX_CSG_DIFFERENCE, inner, NULL);
    bvox_volume_destroy(inner);
    if (st) {
        bvox_volume_destroy(*out);
        *out = NULL;
    }
    return st;
}

static bvox_status run(op o, const bvox_volume *in, int conn, double radius, int64_t min_size,
                       bvox_volume **out)
{
    int ball = radius > 0;
    switch (o) {
    case DILATE:
        return ball ? bvox_morph_dilate_ball(in, radius, out) : bvox_morph_dilate(in, conn, out);
    case ERODE:
        return ball ? bvox_morph_erode_ball(in, radius, out) : bvox_morph_erode(in, conn, out);
    case OPEN: return bvox_morph_open(in, conn, radius, out);
    case CLOSE: return bvox_morph_close(in, conn, radius, out);
    case FILL: return bvox_morph_fill_holes(in, out);
    case HOLLOW: return ball ? bvox_morph_hollow(in, radius, out) : hollow_conn(in, conn, out);
    case ISLANDS: return bvox_morph_remove_islands(in, conn, min_size, out);
    default: return BVOX_EINVAL;
    }
}

typedef struct morph_report {
    const char *op;
    int conn; /* 0 with --radius */
    double radius;
    int64_t min_size, before;
} morph_report;

static void morph_json(cli_json *j, const bvox_volume *res, void *ctx)
{
    const morph_report *r = ctx;
    cli_json_key(j, "operation");
    cli_json_string(j, r->op);
    cli_json_key(j, "conn");
    if (r->conn) cli_json_int(j, r->conn);
    else cli_json_null(j);
    cli_json_key(j, "radius");
    if (r->radius > 0) cli_json_double(j, r->radius);
    else cli_json_null(j);
    cli_json_key(j, "min_size");
    if (r->min_size >= 0) cli_json_int(j, r->min_size);
    else cli_json_null(j);
    cli_json_key(j, "count_before");
    cli_json_int(j, r->before);
    cli_json_key(j, "count_after");
    cli_json_int(j, bvox_volume_count(res));
}

int cmd_morph(int argc, char **argv)
{
    const char *cmd = "morph";
    morph_args a = {.min_size = -1, .wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_morph, argc, argv, &a);
    const char *in = a.in, *opname = a.opname, *out = a.out;
    int conn = (int)a.conn;
    double radius = a.radius;
    int64_t min_size = a.min_size;
    if (!in) return cli_usage_error(cmd, "missing the input file IN");
    if (!opname)
        return cli_usage_error(cmd, "missing the OPERATION (dilate, erode, open, close, fill, "
                                    "hollow or islands)");
    int o = parse_op(opname);
    if (o < 0)
        return cli_usage_error(cmd,
                               "unknown operation '%s' (dilate, erode, open, close, fill, "
                               "hollow or islands)",
                               opname);
    if (!out) return cli_usage_error(cmd, "missing -o OUT");
    if (radius > 0 && conn && o != ISLANDS)
        return cli_usage_error(cmd, "give --radius or --conn, not both");
    if (o == FILL && (radius > 0 || conn))
        return cli_usage_error(cmd, "fill takes no --radius or --conn (cavities are the "
                                    "background not 6-connected to the border)");
    if (o == ISLANDS && radius > 0) return cli_usage_error(cmd, "islands takes no --radius");
    if (o == ISLANDS && min_size < 0) return cli_usage_error(cmd, "islands needs --min-size N");
    if (o != ISLANDS && min_size >= 0)
        return cli_usage_error(cmd, "--min-size applies to islands only");
    if (!conn) conn = o == HOLLOW ? 6 : 26;
    /* Refuse an output name of unknown format before reading a large input. */
    if (cli_check_output(cmd, out, &a.wo) != CLI_OK) return CLI_USAGE;

    bvox__slab_source src;
    if (cli_ooc_open(in, &a.ra, &src) == 1) { /* a .zarr over --max-memory: by slabs */
        bvox__slab_sink sink;
        int ok = o <= CLOSE && cli_ooc_sink(cmd, out, &src, &a.wo, &sink);
        if (o > CLOSE) cli_ooc_refuse(cmd, in, op_names[o]);
        bvox_status st = BVOX_EINVAL;
        if (ok) {
            st = bvox__stream_morph(&src, (bvox__stream_morph_op)o, conn, radius, &sink);
            sink.close(&sink, true, &st);
            if (st) cli_fail();
        }
        bvox__slab_source_close(&src);
        return ok && !st ? CLI_OK : CLI_FAIL;
    }
    bvox_volume *vol = NULL, *res = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    bvox_status st = run((op)o, vol, conn, radius, min_size, &res);
    int64_t before = bvox_volume_count(vol);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    st = bvox_write(out, res, &a.wo);
    if (!st && a.json) {
        morph_report r = {op_names[o], radius > 0 ? 0 : conn, radius, o == ISLANDS ? min_size : -1,
                          before};
        st = cli_print_volume_json(res, in, out, a.wo.format, morph_json, &r);
    }
    bvox_volume_destroy(res);
    return st ? cli_fail() : CLI_OK;
}
