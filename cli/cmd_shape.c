/*
 * cmd_shape.c — `bvox shape KIND KEY=VALUE... --dims NX,NY,NZ -o OUT`: one
 * primitive in physical units on a new grid, written to OUT, its info
 * printed. The parameters are those of the csg primitives, so the command
 * builds "KIND(KEY=VALUE, ...)" and evaluates it with bvox_csg_eval: one
 * parser, one set of checks and messages for both commands.
 */
#include "cli.h"
#include "manip.h"
#include "opts.h"

#include <stdlib.h>
#include <string.h>

static const char *const kinds[] = {"sphere", "ellipsoid", "box",      "cylinder",
                                    "cone",   "torus",     "halfspace"};
#define NKINDS (sizeof kinds / sizeof kinds[0])

typedef struct shape_args {
    const char *kind, *out;
    cli_list params;
    int json;
    cli_grid grid;
    bvox_write_opts wo;
    cli_read_args ra; /* --dims, --voxel-size, --unit only */
} shape_args;

#define A(member) CLI_AT(shape_args, member)

static const cli_opt shape_opts[] = {
    {"--dims", 0, CLI_STR, "NX,NY,NZ", "the volume's size in voxels (required)", A(ra),
     .fn = cli_take_dims, .bad = CLI_BAD_DIMS},
    {"--voxel-size", 0, CLI_TRIPLE, "SX,SY,SZ", "voxel size (default 1,1,1)", A(ra),
     .fn = cli_take_voxel_size, .bad = CLI_BAD_VOXEL_SIZE},
    {"--unit", 0, CLI_STR, "U", "length unit, e.g. mm or um", A(ra), .fn = cli_take_unit,
     .bad = CLI_BAD_UNIT},
    {"--origin", 0, CLI_TRIPLE, "X,Y,Z", "position of voxel (0,0,0) (default 0,0,0)", A(grid),
     .fn = cli_take_origin, .bad = "--origin: '%s' is not X,Y,Z"},
    {"--output", 'o', CLI_PATH, "OUT", "the file to write (required)", A(out)},
    {"--json", 0, CLI_FLAG, NULL, "print the info as one JSON object", A(json)},
    CLI_OPT_OUTPUT_FORMAT(shape_args, wo.format),
    CLI_OPT_FORCE(shape_args, wo.force),
    {NULL},
};
static const cli_group shape_group = {"Options", shape_opts, NULL};
static const cli_pos shape_pos[] = {
    {"KIND", "sphere, ellipsoid, box, cylinder, cone, torus or halfspace", A(kind)},
    {"KEY=VALUE...", "the primitive's parameters", A(params), .many = 1},
    {NULL},
};
static const cli_section shape_sections[] = {
    {"Kinds and parameters (as in 'bvox csg')",
     "  sphere     r=R [at=X,Y,Z]\n"
     "  ellipsoid  r=RX,RY,RZ [at=X,Y,Z]\n"
     "  box        size=SX,SY,SZ [at=X,Y,Z]   or  min=X0,Y0,Z0 max=X1,Y1,Z1\n"
     "  cylinder   r=R h=H [at=X,Y,Z] [axis=AX,AY,AZ]   (at: centre, h: full height)\n"
     "  cone       r=R h=H [at=X,Y,Z] [axis=AX,AY,AZ]   (at: centre of the base)\n"
     "  torus      R=RING r=TUBE [at=X,Y,Z] [axis=AX,AY,AZ]\n"
     "  halfspace  n=A,B,C [d=D]                 A*x + B*y + C*z + D >= 0\n"},
    {NULL, NULL},
};

const cli_spec cli_spec_shape = {
    .name = "shape",
    .summary = "draw a sphere, ellipsoid, box, cylinder, cone, torus or half-space",
    .usage = "KIND KEY=VALUE... --dims NX,NY,NZ -o OUT [options]",
    .about = "Draw one primitive shape into a new volume of the given size and write it;\n"
             "prints the result's info. Sizes and positions are physical (--unit; the\n"
             "centre of voxel (i,j,k) is at origin + (i,j,k) * voxel size); a voxel is\n"
             "inside when its centre is. 'at' defaults to the centre of the volume.\n",
    .pos = shape_pos,
    .sections = shape_sections,
    .uses = {{&shape_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox shape sphere r=20 at=32,32,32 --dims 64,64,64 -o s.nii\n"
                "  bvox shape torus R=3 r=1 axis=1,0,0 --dims 100,100,100 --voxel-size 0.1,0.1,0.1 "
                "--unit mm -o ring.nii.gz\n",
};

/* KEY=VALUE with only the characters a parameter can hold, so that nothing
 * but one primitive can come out of the text built from them. */
static int param_ok(const char *s)
{
    const char *eq = strchr(s, '=');
    if (!eq || eq == s || !eq[1]) return 0;
    for (const char *p = s; *p; p++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_=.,+-", *p))
            return 0;
    return 1;
}

/* The library's message without "csg: " and " at column N" (the columns are
 * those of the text built here, not of anything the user typed). */
static int shape_fail(void)
{
    char msg[1100];
    const char *m = bvox_errmsg();
    if (!strncmp(m, "csg: ", 5)) m += 5;
    snprintf(msg, sizeof msg, "%s", m);
    char *col = strstr(msg, " at column ");
    if (col) {
        char *end = col + 11;
        while (*end >= '0' && *end <= '9') end++;
        memmove(col, end, strlen(end) + 1);
    }
    fprintf(stderr, "bvox: shape: %s\n", msg);
    return CLI_FAIL;
}

static bvox_status no_files(void *ctx, const char *name, bvox_volume **out)
{
    return BVOX_EINVAL; /* unreachable: param_ok admits no file operand */
}

int cmd_shape(int argc, char **argv)
{
    const char *cmd = "shape";
    shape_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    a.params.items = calloc((size_t)argc, sizeof *a.params.items);
    if (!a.params.items) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    const char **params = a.params.items, *kind, *out;
    int json, nparams, rc = cli_parse(&cli_spec_shape, argc, argv, &a);
    if (rc != CLI_PARSED) {
        rc = rc == CLI_PARSE_HELP ? CLI_OK : CLI_USAGE;
        goto done;
    }
    rc = CLI_USAGE;
    kind = a.kind, out = a.out, json = a.json, nparams = a.params.n;
    size_t len = 0;
    for (int i = 0; i < nparams; i++) {
        if (!param_ok(params[i])) {
            cli_usage_error(cmd, "'%s' is not a parameter KEY=VALUE", params[i]);
            goto done;
        }
        len += strlen(params[i]) + 2;
    }
    size_t k = 0;
    while (kind && k < NKINDS && strcmp(kind, kinds[k])) k++;
    if (!kind) {
        cli_usage_error(cmd, "missing the KIND (sphere, ellipsoid, box, cylinder, cone, torus, "
                             "halfspace)");
        goto done;
    }
    if (k == NKINDS) {
        cli_usage_error(cmd, "unknown KIND '%s' (sphere, ellipsoid, box, cylinder, cone, torus, "
                             "halfspace)", kind);
        goto done;
    }
    if (!a.ra.opts.raw_dims.nx) {
        cli_usage_error(cmd, "missing --dims NX,NY,NZ");
        goto done;
    }
    if (!out) {
        cli_usage_error(cmd, "missing -o OUT");
        goto done;
    }
    if (cli_check_output(cmd, out, &a.wo) != CLI_OK) goto done;

    rc = CLI_FAIL;
    char *expr = malloc(strlen(kind) + len + 3);
    if (!expr) {
        fprintf(stderr, "bvox: out of memory\n");
        goto done;
    }
    char *p = expr + sprintf(expr, "%s(", kind);
    for (int i = 0; i < nparams; i++) p += sprintf(p, "%s%s", i ? ", " : "", params[i]);
    strcpy(p, ")");
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    cli_grid_to_opts(&a.ra, &a.grid, &o);
    o.load = no_files;
    bvox_volume *vol = NULL;
    bvox_status st = bvox_csg_eval(expr, &o, &vol);
    free(expr);
    if (st) {
        shape_fail();
        goto done;
    }
    bvox_info info;
    st = bvox_info_compute(vol, &info);
    if (!st) st = bvox_write(out, vol, &a.wo);
    bvox_volume_destroy(vol);
    if (st) {
        cli_fail();
        goto done;
    }
    const char *format = a.wo.format ? a.wo.format : bvox_format_for_path(out);
    if (json) cli_print_info_json_io(stdout, &info, out, format, NULL, out);
    else cli_print_info_text(stdout, &info, out, format);
    rc = CLI_OK;
done:
    free(params);
    return rc;
}
