/*
 * cmd_shape.c — `bvox shape KIND KEY=VALUE... --dims NX,NY,NZ -o OUT`: one
 * primitive in physical units on a new grid, written to OUT, its info
 * printed. The parameters are those of the csg primitives, so the command
 * builds "KIND(KEY=VALUE, ...)" and evaluates it with bvox_csg_eval: one
 * parser, one set of checks and messages for both commands.
 */
#include "cli.h"
#include "manip.h"

#include <stdlib.h>
#include <string.h>

static const char *const kinds[] = {"sphere", "ellipsoid", "box",      "cylinder",
                                    "cone",   "torus",     "halfspace"};
#define NKINDS (sizeof kinds / sizeof kinds[0])

static void help(FILE *f)
{
    fputs("Usage: bvox shape KIND KEY=VALUE... --dims NX,NY,NZ -o OUT [options]\n"
          "\n"
          "Draw one primitive shape into a new volume of the given size and write it;\n"
          "prints the result's info. Sizes and positions are physical (--unit; the\n"
          "centre of voxel (i,j,k) is at origin + (i,j,k) * voxel size); a voxel is\n"
          "inside when its centre is. 'at' defaults to the centre of the volume.\n"
          "\n"
          "Kinds and parameters (as in 'bvox csg'):\n"
          "  sphere     r=R [at=X,Y,Z]\n"
          "  ellipsoid  r=RX,RY,RZ [at=X,Y,Z]\n"
          "  box        size=SX,SY,SZ [at=X,Y,Z]   or  min=X0,Y0,Z0 max=X1,Y1,Z1\n"
          "  cylinder   r=R h=H [at=X,Y,Z] [axis=AX,AY,AZ]   (at: centre, h: full height)\n"
          "  cone       r=R h=H [at=X,Y,Z] [axis=AX,AY,AZ]   (at: centre of the base)\n"
          "  torus      R=RING r=TUBE [at=X,Y,Z] [axis=AX,AY,AZ]\n"
          "  halfspace  n=A,B,C [d=D]                 A*x + B*y + C*z + D >= 0\n"
          "\n"
          "Options:\n"
          "  --dims NX,NY,NZ       the volume's size in voxels (required)\n"
          "  --voxel-size SX,SY,SZ voxel size (default 1,1,1)\n"
          "  --unit U              length unit, e.g. mm or um\n"
          "  --origin X,Y,Z        position of voxel (0,0,0) (default 0,0,0)\n"
          "  -o, --output OUT      the file to write (required)\n"
          "  --json                print the info as one JSON object\n",
          f);
    fprintf(f, "  --output-format NAME  force the output format (%s)\n", bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox shape sphere r=20 at=32,32,32 --dims 64,64,64 -o s.nii\n"
          "  bvox shape torus R=3 r=1 axis=1,0,0 --dims 100,100,100 --voxel-size 0.1,0.1,0.1 "
          "--unit mm -o ring.nii.gz\n",
          f);
}

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
    const char *cmd = "shape", *kind = NULL, *out = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    cli_grid grid = {0, {0, 0, 0}};
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, json = 0, nparams = 0;
    size_t len = 0;
    const char **params = calloc((size_t)argc, sizeof *params);
    if (!params) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    int rc = CLI_USAGE;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (options_done || !cli_is_option(arg)) {
            if (!kind) {
                kind = arg;
            } else if (!param_ok(arg)) {
                cli_usage_error(cmd, "'%s' is not a parameter KEY=VALUE", arg);
                goto done;
            } else {
                params[nparams++] = arg;
                len += strlen(arg) + 2;
            }
        } else if (!strcmp(arg, "--")) {
            options_done = 1;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            rc = CLI_OK;
            goto done;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) goto done;
        } else if ((r = cli_parse_grid_option(cmd, argc, argv, &i, &grid))) {
            if (r == CLI_ARG_BAD) goto done;
        } else if ((!strncmp(arg, "--dims", 6) || !strncmp(arg, "--voxel-size", 12) ||
                    !strncmp(arg, "--unit", 6)) &&
                   (r = cli_parse_read_option(cmd, argc, argv, &i, &ra)) != CLI_ARG_NOT_MINE) {
            if (r == CLI_ARG_BAD) goto done;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, NULL) == CLI_ARG_BAD) {
            goto done;
        }
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
    if (!ra.opts.raw_dims.nx) {
        cli_usage_error(cmd, "missing --dims NX,NY,NZ");
        goto done;
    }
    if (!out) {
        cli_usage_error(cmd, "missing -o OUT");
        goto done;
    }
    if (cli_check_output(cmd, out, &wo) != CLI_OK) goto done;

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
    cli_grid_to_opts(&ra, &grid, &o);
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
    if (!st) st = bvox_write(out, vol, &wo);
    bvox_volume_destroy(vol);
    if (st) {
        cli_fail();
        goto done;
    }
    const char *format = wo.format ? wo.format : bvox_format_for_path(out);
    if (json) cli_print_info_json(stdout, &info, out, format);
    else cli_print_info_text(stdout, &info, out, format);
    rc = CLI_OK;
done:
    free(params);
    return rc;
}
