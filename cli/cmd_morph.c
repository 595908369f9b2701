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

#include <string.h>
#include <sys/stat.h>

typedef enum op { DILATE, ERODE, OPEN, CLOSE, FILL, HOLLOW, ISLANDS, NOPS } op;
static const char *const op_names[NOPS] = {"dilate", "erode",  "open",   "close",
                                           "fill",   "hollow", "islands"};

static void help(FILE *f)
{
    fputs("Usage: bvox morph IN OPERATION -o OUT [options]\n"
          "\n"
          "Apply one morphological operation to a volume and write the result.\n"
          "\n"
          "Operations:\n"
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
          "            --min-size voxels\n"
          "\n"
          "Options:\n"
          "  -o, --output OUT      the file to write (required)\n"
          "  --radius R            dilate, erode, open, close: use a ball of radius R in\n"
          "                        the file's unit (voxel offsets (i,j,k) with\n"
          "                        (i*sx)^2 + (j*sy)^2 + (k*sz)^2 <= R^2);\n"
          "                        hollow: the shell's thickness\n"
          "  --conn 6|18|26        neighbourhood when --radius is not given (default 26;\n"
          "                        hollow: 6); islands: the connectivity (default 26)\n"
          "  --min-size N          islands: smallest component kept, in voxels (required)\n",
          f);
    fprintf(f, "  --output-format NAME  force the output format (%s)\n", bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox morph mask.nii.gz dilate --conn 6 -o grown.nii.gz\n"
          "  bvox morph embryo.tif close --radius 0.05 -o closed.tif\n"
          "  bvox morph mask.nii islands --min-size 100 -o clean.nii\n"
          "  bvox morph organ.nii hollow --radius 0.5 -o shell.nii\n",
          f);
}

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

int cmd_morph(int argc, char **argv)
{
    const char *cmd = "morph", *in = NULL, *opname = NULL, *out = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, conn = 0;
    double radius = 0;
    int64_t min_size = -1, n;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (options_done || !cli_is_option(arg)) {
            if (!in) in = arg;
            else if (!opname) opname = arg;
            else return cli_usage_error(cmd, "unexpected argument '%s'", arg);
        } else if (!strcmp(arg, "--")) {
            options_done = 1;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            return CLI_OK;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--radius", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_double(v, &radius) || !(radius > 0))
                return cli_usage_error(cmd, "--radius: '%s' is not a length > 0", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--conn", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 0, 26, &n) || (n != 6 && n != 18 && n != 26))
                return cli_usage_error(cmd, "--conn: '%s' is not 6, 18 or 26", v);
            conn = (int)n;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--min-size", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 1, INT64_MAX, &min_size))
                return cli_usage_error(cmd, "--min-size: '%s' is not a voxel count >= 1", v);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
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
    struct stat sb;
    size_t len = strlen(out);
    int folder = (len && out[len - 1] == '/') || (stat(out, &sb) == 0 && S_ISDIR(sb.st_mode));
    if (!wo.format && !folder && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; "
                               "use --output-format (one of %s)",
                               out, bvox_format_list());

    bvox_volume *vol = NULL, *res = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_status st = run((op)o, vol, conn, radius, min_size, &res);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    st = bvox_write(out, res, &wo);
    bvox_volume_destroy(res);
    return st ? cli_fail() : CLI_OK;
}
