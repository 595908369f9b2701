/*
 * cmd_cut.c — `bvox cut IN --plane A,B,C,D [--keep above|below] -o OUT`:
 * reslice a volume by a plane in world coordinates (bvox_cut_plane: one z
 * threshold per column, whole-word masks), print the region that changed and
 * the count before and after, write OUT (temporary file, renamed on success).
 */
#include "cli.h"
#include "manip.h"
#include "opts.h"

#include <string.h>

typedef struct cut_args {
    const char *in, *out;
    cli_plane plane;
    int keep_below, json;
    bvox_write_opts wo;
    cli_read_args ra;
} cut_args;

#define A(member) CLI_AT(cut_args, member)

static const cli_opt cut_opts[] = {
    {"--plane", 0, CLI_STR, "A,B,C,D", "the plane (required; A,B,C not all zero)", A(plane),
     .fn = cli_take_plane},
    {"--keep", 0, CLI_CHOICE, NULL, "the side to keep", A(keep_below), .def = "above",
     .choices = cli_keep_choices},
    {"--output", 'o', CLI_PATH, "OUT", "the file to write (required)", A(out)},
    {"--json", 0, CLI_FLAG, NULL, "print the report as one JSON object", A(json)},
    CLI_OPT_OUTPUT_FORMAT(cut_args, wo.format),
    CLI_OPT_FORCE(cut_args, wo.force),
    {NULL},
};
static const cli_group cut_group = {"Options", cut_opts, NULL};
static const cli_pos cut_pos[] = {
    {"IN", "the volume to cut", A(in)},
    {NULL},
};

const cli_spec cli_spec_cut = {
    .name = "cut",
    .summary = "cut by a plane ax+by+cz+d=0 (world coordinates), keep one side",
    .usage = "IN --plane A,B,C,D [--keep above|below] -o OUT [options]",
    .about = "Cut a volume by the plane A*x + B*y + C*z + D = 0 and keep one side. x, y, z\n"
             "are world coordinates of voxel centres in the file's unit: origin +\n"
             "direction * (index * voxel size), as the file's geometry says (with the\n"
             "identity direction and zero origin: index * voxel size). 'above' is\n"
             "A*x + B*y + C*z + D >= 0 (a centre on the plane is above), 'below' < 0, so\n"
             "the two cuts split the object exactly. Prints the region that changed\n"
             "(inclusive voxel indices) and the count before and after.\n",
    .pos = cut_pos,
    .uses = {{&cut_group, 0}, CLI_USE_READ(cut_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox cut brain.nii.gz --plane 0,0,1,-40 -o top.nii.gz        (keep z >= 40 mm)\n"
                "  bvox cut embryo.tif --plane 1,1,0,-1.2 --keep below -o half.tif\n",
};

int cmd_cut(int argc, char **argv)
{
    const char *cmd = "cut";
    cut_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_cut, argc, argv, &a);
    const char *in = a.in, *out = a.out;
    int json = a.json, keep_above = !a.keep_below;
    const double *plane = a.plane.p;
    if (!in) return cli_usage_error(cmd, "missing the input file IN");
    if (!a.plane.given) return cli_usage_error(cmd, "missing --plane A,B,C,D");
    if (!out) return cli_usage_error(cmd, "missing -o OUT");
    if (cli_check_output(cmd, out, &a.wo) != CLI_OK) return CLI_USAGE;

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    int64_t before = bvox_volume_count(vol);
    bvox_box changed;
    bvox_status st = bvox_cut_plane(vol, plane[0], plane[1], plane[2], plane[3], keep_above,
                                    &changed);
    int64_t after = bvox_volume_count(vol);
    if (!st) st = bvox_write(out, vol, &a.wo);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    if (json) {
        cli_json j;
        cli_json_init(&j, stdout);
        cli_json_begin_object(&j);
        cli_json_key(&j, "file");
        cli_json_string(&j, out);
        cli_json_io(&j, in, out);
        cli_json_key(&j, "plane");
        cli_json_double_array(&j, plane, 4);
        cli_json_key(&j, "keep");
        cli_json_string(&j, keep_above ? "above" : "below");
        cli_json_key(&j, "changed");
        cli_json_box(&j, &changed);
        cli_json_key(&j, "count_before");
        cli_json_int(&j, before);
        cli_json_key(&j, "count_after");
        cli_json_int(&j, after);
        cli_json_end_object(&j);
        fputc('\n', stdout);
    } else {
        char f[200];
        cli_format_plane(f, sizeof f, plane);
        printf("%-14s%s = 0\n", "plane:", f);
        printf("%-14s%s (%s %s 0)\n", "kept:", keep_above ? "above" : "below", f,
               keep_above ? ">=" : "<");
        printf("%-14s", "changed:");
        cli_print_box(stdout, &changed);
        puts(changed.x0 < changed.x1 ? " (voxel indices, inclusive)" : "");
        printf("%-14s%lld -> %lld voxels\n", "count:", (long long)before, (long long)after);
    }
    return CLI_OK;
}
