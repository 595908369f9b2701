/*
 * cmd_voxelize.c — `bvox voxelize MESH -o OUT`: bvox_mesh_read, then
 * bvox_mesh_voxelize at a resolution (voxels along the longest side) or a
 * voxel size, solid or --shell, then bvox_write in the format OUT names. A
 * mesh that is not closed is reported on stderr (and voxelized by majority
 * vote of the parities along x, y and z).
 */
#include "args.h"
#include "cli.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox voxelize MESH -o OUT (--res N | --voxel-size S | --like IMAGE) [--shell]\n"
          "                     [options]\n"
          "\n"
          "Turn a triangle mesh (STL, OBJ, PLY, OFF) into a binary volume: a voxel is set\n"
          "when its centre is inside the mesh (exact, robust to vertices and edges on\n"
          "the sampling lines), or with --shell when the surface passes through it. The\n"
          "grid covers the mesh's bounding box; voxel centres are at origin + i * S, so\n"
          "meshing the volume back ('bvox mesh') lands on the original coordinates.\n"
          "A mesh that is not closed is reported (open edges) and voxelized by the\n"
          "majority vote of inside tests along x, y and z.\n"
          "\n"
          "Options:\n"
          "  -o, --output OUT      the volume file (format by extension)\n"
          "  --res N               N voxels along the longest side of the bounding box\n"
          "  --voxel-size S        or the voxel size in mesh units (cubic voxels), or\n"
          "                        SX,SY,SZ for anisotropic voxels\n"
          "  --like IMAGE          or the grid of an existing image (its dimensions, voxel\n"
          "                        size, origin, axes and unit), to overlay the two\n"
          "  --dims NX,NY,NZ --origin X,Y,Z  with --voxel-size: a grid given in full, voxel\n"
          "                        (0,0,0)'s centre at the origin (mesh parts outside are cut)\n"
          "  --shell               only the voxels the surface passes through\n"
          "  --unit NAME           unit of the mesh coordinates, stored in OUT (e.g. mm)\n"
          "  --mesh-format NAME    stl, obj, ply or off (default: by extension/content)\n"
          "  --output-format NAME  force the output format\n"
          "  --help                show this help\n",
          f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox voxelize bunny.off -o bunny.nii.gz --res 256\n"
          "  bvox voxelize part.stl -o part.binvox --voxel-size 0.1 --unit mm\n"
          "  bvox voxelize part.stl -o shell.tif --res 128 --shell\n",
          f);
}

int cmd_voxelize(int argc, char **argv)
{
    const char *cmd = "voxelize", *in = NULL, *out = NULL, *value = NULL, *fmt = NULL;
    bvox_voxelize_opts vo;
    memset(&vo, 0, sizeof vo);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, have_dims = 0, have_origin = 0;
    const char *like = NULL;
    bvox_dims grid_dims = {0, 0, 0};
    double origin[3] = {0, 0, 0};
    bvox_geometry grid = bvox_geometry_default();
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--shell")) {
            vo.shell = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--res", &value))) {
            int64_t n;
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(value, 1, BVOX_MAX_DIM, &n))
                return cli_usage_error(cmd, "--res needs an integer 1..%d, not '%s'",
                                       BVOX_MAX_DIM, value);
            vo.res = (int32_t)n;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--voxel-size", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (strchr(value, ',')) { /* SX,SY,SZ: anisotropic voxels */
                if (cli_parse_triple(value, vo.spacing) || !(vo.spacing[0] > 0) ||
                    !(vo.spacing[1] > 0) || !(vo.spacing[2] > 0))
                    return cli_usage_error(cmd, "--voxel-size needs S or SX,SY,SZ > 0, not '%s'",
                                           value);
            } else if (cli_parse_double(value, &vo.voxel_size) || !(vo.voxel_size > 0)) {
                return cli_usage_error(cmd, "--voxel-size needs a positive number, not '%s'",
                                       value);
            }
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--like", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            like = value;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--dims", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_dims(value, &grid_dims))
                return cli_usage_error(cmd, "--dims needs NX,NY,NZ, not '%s'", value);
            have_dims = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--origin", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_triple(value, origin))
                return cli_usage_error(cmd, "--origin needs X,Y,Z, not '%s'", value);
            have_origin = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--unit", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (strlen(value) >= sizeof vo.unit)
                return cli_usage_error(cmd, "--unit: at most %zu characters",
                                       sizeof vo.unit - 1);
            snprintf(vo.unit, sizeof vo.unit, "%s", value);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--mesh-format", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            fmt = value;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, NULL) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "needs MESH");
    if (!out) return cli_usage_error(cmd, "needs -o OUT");
    if (like && (vo.res > 0 || vo.voxel_size > 0 || vo.spacing[0] > 0 || have_dims || have_origin))
        return cli_usage_error(cmd, "--like takes the whole grid from IMAGE: no --res, "
                                    "--voxel-size, --dims or --origin with it");
    if ((have_dims || have_origin) && !(have_dims && have_origin && (vo.voxel_size > 0 ||
                                                                   vo.spacing[0] > 0)))
        return cli_usage_error(cmd, "a grid needs all of --dims, --origin and --voxel-size");
    if (!like && (vo.res > 0) + (vo.voxel_size > 0) + (vo.spacing[0] > 0) != 1)
        return cli_usage_error(cmd, "give one of --res N, --voxel-size S or --like IMAGE");
    if (like) {
        bvox_volume *ref = NULL;
        if (bvox_read(like, NULL, &ref)) return cli_fail();
        grid = *bvox_volume_geometry(ref);
        grid_dims = bvox_volume_dims(ref);
        bvox_volume_destroy(ref);
        vo.grid = &grid;
        vo.grid_dims = grid_dims;
    } else if (have_dims) { /* the grid given in full: voxel (0,0,0)'s centre at --origin */
        for (int k = 0; k < 3; k++) {
            grid.spacing[k] = vo.voxel_size > 0 ? vo.voxel_size : vo.spacing[k];
            grid.origin[k] = origin[k];
        }
        vo.voxel_size = 0;
        memset(vo.spacing, 0, sizeof vo.spacing);
        vo.grid = &grid;
        vo.grid_dims = grid_dims;
    }
    if (!wo.format && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; use "
                               "--output-format (one of %s)",
                               out, bvox_format_list());
    bvox_mesh *m = NULL;
    if (bvox_mesh_read(in, fmt, &m)) return cli_fail();
    bvox_volume *vol = NULL;
    bvox_voxelize_report rep;
    bvox_status st = bvox_mesh_voxelize(m, &vo, &vol, &rep);
    bvox_mesh_destroy(m);
    if (st) return cli_fail();
    if (!rep.closed)
        fprintf(stderr,
                "bvox: warning: %s is not closed (%lld open edges)%s\n", in,
                (long long)rep.open_edges,
                vo.shell ? "" : ": voxels by majority vote of the inside tests along x, y, z");
    st = bvox_write(out, vol, &wo);
    if (!st) {
        bvox_dims d = bvox_volume_dims(vol);
        const bvox_geometry *g = bvox_volume_geometry(vol);
        printf("%s: %d x %d x %d voxels of %.9g%s%s, %lld set (%s)\n", out, d.nx, d.ny, d.nz,
               g->spacing[0], g->unit[0] ? " " : "", g->unit, (long long)bvox_volume_count(vol),
               rep.method);
    }
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
