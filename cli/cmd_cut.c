/*
 * cmd_cut.c — `bvox cut IN --plane A,B,C,D [--keep above|below] -o OUT`:
 * reslice a volume by a plane in world coordinates (bvox_cut_plane: one z
 * threshold per column, whole-word masks), print the region that changed and
 * the count before and after, write OUT (temporary file, renamed on success).
 */
#include "cli.h"
#include "manip.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox cut IN --plane A,B,C,D [--keep above|below] -o OUT [options]\n"
          "\n"
          "Cut a volume by the plane A*x + B*y + C*z + D = 0 and keep one side. x, y, z\n"
          "are world coordinates of voxel centres in the file's unit: origin +\n"
          "direction * (index * voxel size), as the file's geometry says (with the\n"
          "identity direction and zero origin: index * voxel size). 'above' is\n"
          "A*x + B*y + C*z + D >= 0 (a centre on the plane is above), 'below' < 0, so\n"
          "the two cuts split the object exactly. Prints the region that changed\n"
          "(inclusive voxel indices) and the count before and after.\n"
          "\n"
          "Options:\n"
          "  --plane A,B,C,D       the plane (required; A,B,C not all zero)\n"
          "  --keep above|below    the side to keep (default above)\n"
          "  -o, --output OUT      the file to write (required)\n"
          "  --json                print the report as one JSON object\n",
          f);
    fprintf(f, "  --output-format NAME  force the output format (%s)\n", bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox cut brain.nii.gz --plane 0,0,1,-40 -o top.nii.gz        (keep z >= 40 mm)\n"
          "  bvox cut embryo.tif --plane 1,1,0,-1.2 --keep below -o half.tif\n",
          f);
}

int cmd_cut(int argc, char **argv)
{
    const char *cmd = "cut", *in = NULL, *out = NULL, *v = NULL, *plane_txt = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, json = 0, keep_above = 1;
    double plane[4];
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--plane", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_plane(v, plane))
                return cli_usage_error(cmd, "--plane: '%s' is not A,B,C,D", v);
            if (!plane[0] && !plane[1] && !plane[2])
                return cli_usage_error(cmd, "--plane: the normal A,B,C is zero");
            plane_txt = v;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--keep", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (!strcmp(v, "above")) keep_above = 1;
            else if (!strcmp(v, "below")) keep_above = 0;
            else return cli_usage_error(cmd, "--keep: '%s' is not above or below", v);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "missing the input file IN");
    if (!plane_txt) return cli_usage_error(cmd, "missing --plane A,B,C,D");
    if (!out) return cli_usage_error(cmd, "missing -o OUT");
    if (cli_check_output(cmd, out, &wo) != CLI_OK) return CLI_USAGE;

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    int64_t before = bvox_volume_count(vol);
    bvox_box changed;
    bvox_status st = bvox_cut_plane(vol, plane[0], plane[1], plane[2], plane[3], keep_above,
                                    &changed);
    int64_t after = bvox_volume_count(vol);
    if (!st) st = bvox_write(out, vol, &wo);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    if (json) {
        cli_json j;
        cli_json_init(&j, stdout);
        cli_json_begin_object(&j);
        cli_json_key(&j, "file");
        cli_json_string(&j, out);
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
