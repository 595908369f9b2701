/*
 * cmd_voxelize.c — `bvox voxelize MESH -o OUT`: bvox_mesh_read, then
 * bvox_mesh_voxelize at a resolution (voxels along the longest side) or a
 * voxel size, solid or --shell, then bvox_write in the format OUT names. A
 * mesh that is not closed is reported on stderr (and voxelized by majority
 * vote of the parities along x, y and z).
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "manip.h"
#include "opts.h"

#include <string.h>

typedef struct voxelize_args {
    const char *in, *out, *fmt, *like;
    bvox_voxelize_opts vo;
    bvox_dims grid_dims; /* --dims (nx 0: not given) */
    cli_grid origin;     /* --origin */
    int json;
    bvox_write_opts wo;
} voxelize_args;

#define A(member) CLI_AT(voxelize_args, member)

static int take_unit(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    bvox_voxelize_opts *vo = target;
    if (strlen(v) >= sizeof vo->unit) {
        cli_usage_error(cmd, "--unit: at most %zu characters", sizeof vo->unit - 1);
        return CLI_OPT_FAILED;
    }
    snprintf(vo->unit, sizeof vo->unit, "%s", v);
    return CLI_OPT_OK;
}

/* S (cubic voxels) or SX,SY,SZ (anisotropic voxels). */
static int take_voxel_size(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    bvox_voxelize_opts *vo = target;
    if (strchr(v, ',')) {
        if (cli_parse_triple(v, vo->spacing) || !(vo->spacing[0] > 0) || !(vo->spacing[1] > 0) ||
            !(vo->spacing[2] > 0)) {
            cli_usage_error(cmd, "--voxel-size needs S or SX,SY,SZ > 0, not '%s'", v);
            return CLI_OPT_FAILED;
        }
    } else if (cli_parse_double(v, &vo->voxel_size) || !(vo->voxel_size > 0)) {
        cli_usage_error(cmd, "--voxel-size needs a positive number, not '%s'", v);
        return CLI_OPT_FAILED;
    }
    return CLI_OPT_OK;
}

static int take_dims(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    return cli_parse_dims(v, target) ? CLI_OPT_BAD : CLI_OPT_OK;
}

#define STR_(x) #x
#define STR(x) STR_(x)

static const cli_opt voxelize_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT", "the volume file (format by extension)", A(out)},
    {"--res", 0, CLI_INT, "N", "N voxels along the longest side of the bounding box", A(vo.res),
     .lo = 1, .hi = BVOX_MAX_DIM, .bad = "--res needs an integer 1.." STR(BVOX_MAX_DIM) ", not '%s'"},
    {"--voxel-size", 0, CLI_STR, "S",
     "or the voxel size in mesh units (cubic voxels), or SX,SY,SZ for anisotropic voxels",
     A(vo), .fn = take_voxel_size},
    {"--like", 0, CLI_PATH, "IMAGE",
     "or the grid of an existing image (its dimensions, voxel size, origin, axes and unit), to "
     "overlay the two",
     A(like)},
    {"--dims", 0, CLI_STR, "NX,NY,NZ",
     "with --origin and --voxel-size: a grid given in full (mesh parts outside are cut)",
     A(grid_dims), .fn = take_dims, .bad = "--dims needs NX,NY,NZ, not '%s'"},
    {"--origin", 0, CLI_TRIPLE, "X,Y,Z", "with --dims: the centre of voxel (0,0,0)", A(origin),
     .fn = cli_take_origin, .bad = "--origin needs X,Y,Z, not '%s'"},
    {"--shell", 0, CLI_FLAG, NULL, "only the voxels the surface passes through", A(vo.shell)},
    {"--unit", 0, CLI_STR, "NAME", "unit of the mesh coordinates, stored in OUT (e.g. mm)",
     A(vo), .fn = take_unit},
    {"--mesh-format", 0, CLI_STR, "NAME", "stl, obj, ply or off (default: by extension/content)",
     A(fmt), .choices = cli_mesh_formats},
    CLI_OPT_OUTPUT_FORMAT(voxelize_args, wo.format),
    CLI_OPT_FORCE(voxelize_args, wo.force),
    {"--json", 0, CLI_FLAG, NULL,
     "print one JSON object instead of the summary line: what 'bvox info --json' says of "
     "OUT, input, output, method, closed, open_edges",
     A(json)},
    {NULL},
};
static const cli_group voxelize_group = {"Options", voxelize_opts, NULL};
static const cli_pos voxelize_pos[] = {
    {"MESH", "the mesh file (STL, OBJ, PLY, OFF)", A(in)},
    {NULL},
};

const cli_spec cli_spec_voxelize = {
    .name = "voxelize",
    .summary = "triangle mesh (STL, OBJ, PLY, OFF) -> volume, solid or shell",
    .usage = "MESH -o OUT (--res N | --voxel-size S | --like IMAGE) [--shell] [options]",
    .about = "Turn a triangle mesh (STL, OBJ, PLY, OFF) into a binary volume: a voxel is set\n"
             "when its centre is inside the mesh (exact, robust to vertices and edges on\n"
             "the sampling lines), or with --shell when the surface passes through it. The\n"
             "grid covers the mesh's bounding box; voxel centres are at origin + i * S, so\n"
             "meshing the volume back ('bvox mesh') lands on the original coordinates.\n"
             "A mesh that is not closed is reported (open edges) and voxelized by the\n"
             "majority vote of inside tests along x, y and z.\n",
    .pos = voxelize_pos,
    .uses = {{&voxelize_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox voxelize bunny.off -o bunny.nii.gz --res 256\n"
                "  bvox voxelize part.stl -o part.binvox --voxel-size 0.1 --unit mm\n"
                "  bvox voxelize part.stl -o shell.tif --res 128 --shell\n",
};

static void voxelize_json(cli_json *j, const bvox_volume *vol, void *ctx)
{
    const bvox_voxelize_report *rep = ctx;
    cli_json_key(j, "method");
    cli_json_string(j, rep->method);
    cli_json_key(j, "closed");
    cli_json_bool(j, rep->closed);
    cli_json_key(j, "open_edges");
    cli_json_int(j, rep->open_edges);
}

int cmd_voxelize(int argc, char **argv)
{
    const char *cmd = "voxelize";
    voxelize_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    CLI_PARSE_OR_RETURN(&cli_spec_voxelize, argc, argv, &a);
    const char *in = a.in, *out = a.out, *fmt = a.fmt, *like = a.like;
    bvox_voxelize_opts vo = a.vo;
    int have_dims = a.grid_dims.nx > 0, have_origin = a.origin.origin_given;
    bvox_dims grid_dims = a.grid_dims;
    const double *origin = a.origin.origin;
    bvox_geometry grid = bvox_geometry_default();
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
    if (!a.wo.format && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; use "
                               "--output-format (one of %s)",
                               out, bvox_format_list());
    bvox_mesh *m = NULL;
    if (bvox_mesh_read(in, fmt, &m)) return cli_fail();
    bvox_volume *vol = NULL;
    bvox_voxelize_report rep;
    /* an output that cannot take the result is refused before the work */
    bvox_dims dims;
    bvox_status st = bvox_mesh_voxelize_dims(m, &vo, &dims);
    if (!st) st = bvox_write_check(out, dims, &a.wo);
    if (!st) st = bvox_mesh_voxelize(m, &vo, &vol, &rep);
    bvox_mesh_destroy(m);
    if (st) return cli_fail();
    if (!rep.closed)
        fprintf(stderr,
                "bvox: warning: %s is not closed (%lld open edges)%s\n", in,
                (long long)rep.open_edges,
                vo.shell ? "" : ": voxels by majority vote of the inside tests along x, y, z");
    st = bvox_write(out, vol, &a.wo);
    if (!st && a.json) {
        st = cli_print_volume_json(vol, in, out, a.wo.format, voxelize_json, &rep);
    } else if (!st) {
        bvox_dims d = bvox_volume_dims(vol);
        const bvox_geometry *g = bvox_volume_geometry(vol);
        printf("%s: %d x %d x %d voxels of %.9g%s%s, %lld set (%s)\n", out, d.nx, d.ny, d.nz,
               g->spacing[0], g->unit[0] ? " " : "", g->unit, (long long)bvox_volume_count(vol),
               rep.method);
    }
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
