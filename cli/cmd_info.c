/*
 * cmd_info.c — `bvox info FILE`: read a volume (bvox_read with the shared
 * read options) and print what bvox_info_compute says about it: dimensions,
 * voxel size, count of 1-voxels, physical volume and bounding box.
 */
#include "args.h"
#include "cli.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox info FILE [options]\n"
          "\n"
          "Print the dimensions, voxel size, count of 1-voxels, physical volume and\n"
          "bounding box of a volume file (or a folder of PNG slices).\n"
          "\n"
          "Options:\n"
          "  --json                print one JSON object instead of text\n"
          "  --help                show this help\n",
          f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox info brain.nii.gz\n"
          "  bvox info atlas.nii.gz --label 17 --json\n"
          "  bvox info scan.raw --dims 256,256,64 --type u16 --threshold 1200 "
          "--voxel-size 0.1,0.1,0.5 --unit mm\n",
          f);
}

int cmd_info(int argc, char **argv)
{
    const char *cmd = "info", *path = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    int json = 0, options_done = 0, r;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &path, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!path) return cli_usage_error(cmd, "missing the FILE to read");

    bvox_volume *vol = NULL;
    if (cli_read_volume(path, &ra, &vol)) return cli_fail();
    bvox_info info;
    bvox_status st = bvox_info_compute(vol, &info);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    if (json) cli_print_info_json(stdout, &info, path, cli_input_format(path, &ra));
    else cli_print_info_text(stdout, &info, path, cli_input_format(path, &ra));
    return CLI_OK;
}
