/*
 * cmd_mesh.c — `bvox mesh IN -o OUT`: bvox_read with the shared read
 * options, bvox_mesh_from_volume (marching cubes or cuberille, optional
 * Taubin smoothing), bvox_mesh_write in the format OUT's extension names
 * (STL, PLY, OBJ, OFF; binary unless --ascii). Prints one summary line.
 * With --labels, a label volume becomes one mesh per label in a folder
 * (cli/mesh_labels.c).
 */
#include "args.h"
#include "cli.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox mesh IN -o OUT.stl|ply|obj|off [--method mc|cuberille] [--smooth N]\n"
          "                 [--ascii] [options]\n"
          "\n"
          "The surface of the 1-voxels of IN as a closed, manifold triangle mesh, in the\n"
          "world coordinates of IN's voxel size and origin, triangles facing outward,\n"
          "vertices shared. Marching cubes puts vertices at the midpoints of the voxel\n"
          "edges that cross the surface; cuberille gives the voxel faces themselves\n"
          "(its volume is the voxel volume exactly). Where voxels touch only along an\n"
          "edge or at a corner, the 1-voxels are taken as 6-connected (separate sheets).\n"
          "\n"
          "Options:\n"
          "  -o, --output OUT      the mesh file: .stl (binary), .ply (binary), .obj, .off\n"
          "  --method mc|cuberille marching cubes (default) or voxel faces\n"
          "  --smooth N            N iterations of Taubin lambda/mu smoothing (keeps the\n"
          "                        volume; default 0)\n"
          "  --lambda L, --mu M    Taubin's factors (default 0.5 and -0.53)\n"
          "  --ascii               ASCII STL or PLY instead of binary\n"
          "  --mesh-format NAME    stl, ply, obj or off, whatever OUT's extension\n"
          "  --labels all|L,L,...  IN is a label volume: one cuberille mesh per label in\n"
          "                        the folder OUT, named LABEL_NAME.EXT (--mesh-format,\n"
          "                        default ply); touching labels share their boundary\n"
          "  --lut TABLE           label names for the file names (see 'bvox labels')\n"
          "  --max-labels N        refuse label volumes with more labels (default 65535)\n"
          "  --help                show this help\n",
          f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox mesh embryo.nii.gz -o embryo.stl\n"
          "  bvox mesh atlas.nii.gz --label 37 -o hippocampus.ply --smooth 10\n"
          "  bvox mesh cells.tif -o cells.obj --method cuberille\n"
          "  bvox mesh aal.nii.gz --labels all --lut aal.nii.txt -o aal_meshes/\n",
          f);
}

int cmd_mesh(int argc, char **argv)
{
    const char *cmd = "mesh", *in = NULL, *out = NULL, *value = NULL, *fmt = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_mesh_opts mo = BVOX_MESH_OPTS_INIT;
    int ascii = 0, options_done = 0, r, method_given = 0;
    const char *labels = NULL, *lut = NULL, *max_labels = NULL;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--ascii")) {
            ascii = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "-o", &value)) ||
                   (r = cli_match_value(cmd, argc, argv, &i, "--output", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            out = value;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--labels", &labels))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--lut", &lut))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--max-labels", &max_labels))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--mesh-format", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            fmt = value;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--method", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            method_given = 1;
            if (!strcmp(value, "mc")) mo.method = BVOX_MESH_MC;
            else if (!strcmp(value, "cuberille")) mo.method = BVOX_MESH_CUBERILLE;
            else return cli_usage_error(cmd, "--method must be mc or cuberille, not '%s'", value);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--smooth", &value))) {
            int64_t n;
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(value, 0, 100000, &n))
                return cli_usage_error(cmd, "--smooth needs an integer 0..100000, not '%s'",
                                       value);
            mo.smooth = (int)n;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--lambda", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_double(value, &mo.lambda) || mo.lambda <= 0 || mo.lambda >= 1)
                return cli_usage_error(cmd, "--lambda needs a number in (0, 1), not '%s'", value);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--mu", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_double(value, &mo.mu) || mo.mu >= 0 || mo.mu <= -1)
                return cli_usage_error(cmd, "--mu needs a number in (-1, 0), not '%s'", value);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "needs IN");
    if (labels || lut || max_labels) {
        if (!labels) return cli_usage_error(cmd, "--lut and --max-labels go with --labels");
        if (!out) return cli_usage_error(cmd, "needs -o FOLDER for the per-label meshes");
        if (method_given && mo.method != BVOX_MESH_CUBERILLE)
            return cli_usage_error(cmd, "per-label meshes are cuberille (shared boundaries); "
                                        "--method mc does not apply");
        if (mo.smooth > 0)
            return cli_usage_error(cmd, "per-label meshes are not smoothed (shared "
                                        "boundaries would part)");
        return cli_mesh_labels(in, &ra, labels, lut, max_labels, out, fmt ? fmt : "ply", ascii);
    }
    if (!out) return cli_usage_error(cmd, "needs -o OUT (.stl, .ply, .obj or .off)");
    if (!fmt && !bvox_mesh_format_for_path(out))
        return cli_usage_error(cmd, "%s: the extension must be .stl, .ply, .obj or .off", out);
    if (fmt && strcmp(fmt, "stl") && strcmp(fmt, "ply") && strcmp(fmt, "obj") &&
        strcmp(fmt, "off"))
        return cli_usage_error(cmd, "--mesh-format must be stl, ply, obj or off");
    if (mo.lambda > -mo.mu - 1e-12 && mo.smooth > 0)
        return cli_usage_error(cmd, "Taubin smoothing needs mu < -lambda");

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_mesh *m = NULL;
    bvox_status st = bvox_mesh_from_volume(vol, &mo, &m);
    bvox_volume_destroy(vol);
    if (!st) st = bvox_mesh_write(out, m, fmt, ascii);
    if (!st)
        printf("%s: %lld vertices, %lld triangles (%s%s)\n", out, (long long)m->nvertices,
               (long long)m->ntriangles, mo.method == BVOX_MESH_MC ? "marching cubes" : "cuberille",
               mo.smooth ? ", smoothed" : "");
    bvox_mesh_destroy(m);
    return st ? cli_fail() : CLI_OK;
}
