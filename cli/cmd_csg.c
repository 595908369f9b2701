/*
 * cmd_csg.c — `bvox csg EXPR -o OUT`: evaluate a set-operation expression
 * over files and primitives (bvox_csg_eval; the grammar is documented in
 * bvox.h and in the help below), write the result and print its info. Files
 * in the expression are read with the shared read options, through a loader
 * callback, so --threshold, --voxel-size etc. apply to every one of them.
 */
#include "cli.h"
#include "manip.h"
#include "opts.h"
#include "outofcore.h"

#include <string.h>

typedef struct csg_args {
    const char *expr, *out;
    int json, check;
    cli_grid grid;
    bvox_write_opts wo;
    cli_read_args ra;
} csg_args;

#define A(member) CLI_AT(csg_args, member)

static const cli_opt csg_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT", "the file to write (required unless --check)", A(out)},
    {"--check", 0, CLI_FLAG, NULL, "only check EXPR (syntax, parameters); read nothing", A(check)},
    {"--dims", 0, CLI_STR, "NX,NY,NZ", "grid dimensions when EXPR has no file", A(ra),
     .fn = cli_take_dims, .bad = CLI_BAD_DIMS},
    {"--voxel-size", 0, CLI_TRIPLE, "SX,SY,SZ", "grid voxel size (also overrides every file's)",
     A(ra), .fn = cli_take_voxel_size, .bad = CLI_BAD_VOXEL_SIZE},
    {"--unit", 0, CLI_STR, "U", "grid unit (also overrides every file's)", A(ra),
     .fn = cli_take_unit, .bad = CLI_BAD_UNIT},
    {"--origin", 0, CLI_TRIPLE, "X,Y,Z", "grid origin when EXPR has no file (default 0,0,0)",
     A(grid), .fn = cli_take_origin, .bad = "--origin: '%s' is not X,Y,Z"},
    {"--json", 0, CLI_FLAG, NULL, "print the info as one JSON object", A(json)},
    CLI_OPT_OUTPUT_FORMAT(csg_args, wo.format),
    CLI_OPT_FORCE(csg_args, wo.force),
    {NULL},
};
static const cli_group csg_group = {"Options", csg_opts, NULL};
static const cli_pos csg_pos[] = {
    {"EXPR", "the expression (quoted for the shell)", A(expr)},
    {NULL},
};
static const cli_section csg_sections[] = {
    {"Operators (quote EXPR for the shell)",
     "  A + B     union                A * B     intersection\n"
     "  A - B     difference           A ^ B     symmetric difference (xor)\n"
     "  ~A        complement (within the output grid)\n"
     "  ( ... )   grouping\n"
     "'*' binds tighter than '+', '-', '^', which group left to right:\n"
     "'a + b * c - d' is '(a + (b * c)) - d'; '~' binds tightest.\n"},
    {"Operands",
     "  FILE             a volume file; names may contain '-' (so put spaces\n"
     "                   around the '-' operator); quote other names: 'my file.nii'\n"
     "  FILE@I,J,K       the file moved by I,J,K voxels (integers, may be < 0)\n"
     "  FILE@(X,Y,Z)     moved by X,Y,Z in physical units, rounded to voxels\n"
     "  sphere(r=R, at=X,Y,Z)\n"
     "  ellipsoid(r=RX,RY,RZ, at=X,Y,Z)\n"
     "  box(size=SX,SY,SZ, at=X,Y,Z)    or  box(min=X0,Y0,Z0, max=X1,Y1,Z1)\n"
     "  cylinder(r=R, h=H, at=X,Y,Z, axis=AX,AY,AZ)   (at: centre; h: full height)\n"
     "  cone(r=R, h=H, at=X,Y,Z, axis=AX,AY,AZ)       (at: centre of the base)\n"
     "  torus(R=RING, r=TUBE, at=X,Y,Z, axis=AX,AY,AZ)\n"
     "  halfspace(n=A,B,C, d=D)          the voxels with A*x + B*y + C*z + D >= 0\n"
     "Primitive sizes and positions are physical (the grid's unit), positions\n"
     "relative to the grid's origin + index * voxel size (direction ignored);\n"
     "'at' defaults to the centre of the grid, 'axis' to 0,0,1, 'd' to 0. A voxel\n"
     "is inside when its centre is.\n"
     "\n"
     "The output grid (dimensions, voxel size, origin, unit) is the first file's;\n"
     "other files are placed index to index (plus their offset) and must have\n"
     "the same voxel size; outside a file's extent it counts as empty. Without\n"
     "a file, --dims gives the grid (with --voxel-size, --unit, --origin).\n"},
    {NULL, NULL},
};

const cli_spec cli_spec_csg = {
    .name = "csg",
    .summary = "set operations on files and shapes: \"a.nii - sphere(r=2)\"",
    .usage = "EXPR -o OUT [options]",
    .about = "Combine volume files and primitive shapes with set operations and write\n"
             "the result; prints the result's info (as 'bvox info' does).\n",
    .pos = csg_pos,
    .sections = csg_sections,
    .uses = {{&csg_group, 0}, CLI_USE_READ(csg_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox csg \"heart.nii - sphere(r=2, at=10,12,8)\" -o out.nii\n"
                "  bvox csg \"a.nii + b.nii@0,0,64\" -o stacked.nii\n"
                "  bvox csg \"scan.nii * ~(halfspace(n=0,0,1, d=-40) + box(min=0,0,0, max=20,20,80))\" -o c.nii\n"
                "  bvox csg \"sphere(r=10) - cylinder(r=3, h=30, axis=1,0,0)\" --dims 64,64,64 "
                "--voxel-size 0.5,0.5,0.5 --unit mm -o bead.nii\n",
    .too_many = "unexpected argument '%s' (quote EXPR)",
};

static bvox_status load(void *ctx, const char *name, bvox_volume **out)
{
    return cli_read_volume(name, ctx, out);
}

int cmd_csg(int argc, char **argv)
{
    const char *cmd = "csg";
    csg_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_csg, argc, argv, &a);
    const char *expr = a.expr, *out = a.out;
    int json = a.json, check = a.check;
    if (!expr) return cli_usage_error(cmd, "missing the expression EXPR");
    if (!out && !check) return cli_usage_error(cmd, "missing -o OUT");
    if (out && cli_check_output(cmd, out, &a.wo) != CLI_OK) return CLI_USAGE;

    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    cli_grid_to_opts(&a.ra, &a.grid, &o);
    o.load = load;
    o.load_ctx = &a.ra;
    o.parse_only = check;
    bvox_info info;
    if (!check) { /* a .zarr grid over --max-memory: by slabs */
        int r = cli_ooc_csg(cmd, expr, &o, &a.ra, out, &a.wo, &info);
        if (r < 0) return CLI_FAIL;
        if (r > 0) {
            const char *format = a.wo.format ? a.wo.format : bvox_format_for_path(out);
            if (json) cli_print_info_json_io(stdout, &info, out, format, NULL, out);
            else cli_print_info_text(stdout, &info, out, format);
            return CLI_OK;
        }
    }
    bvox_volume *vol = NULL;
    if (bvox_csg_eval(expr, &o, &vol)) {
        if (strstr(bvox_errmsg(), "no output grid dimensions")) /* name the option */
            return cli_usage_error(cmd, "EXPR has no file: give the grid with --dims NX,NY,NZ");
        return cli_fail();
    }
    if (check) {
        puts("ok");
        return CLI_OK;
    }
    bvox_status st = bvox_info_compute(vol, &info);
    if (!st) st = bvox_write(out, vol, &a.wo);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    const char *format = a.wo.format ? a.wo.format : bvox_format_for_path(out);
    if (json) cli_print_info_json_io(stdout, &info, out, format, NULL, out);
    else cli_print_info_text(stdout, &info, out, format);
    return CLI_OK;
}
