/*
 * cmd_info.c — `bvox info FILE`: read a volume (bvox_read with the shared
 * read options) and print what bvox_info_compute says about it: dimensions,
 * voxel size, count of 1-voxels, physical volume and bounding box.
 */
#include "args.h"
#include "cli.h"
#include "opts.h"
#include "outofcore.h"

#include <string.h>

typedef struct info_args {
    const char *path;
    int json;
    cli_read_args ra;
} info_args;

#define A(member) CLI_AT(info_args, member)

static const cli_opt info_opts[] = {
    {"--json", 0, CLI_FLAG, NULL, "print one JSON object instead of text", A(json)},
    {NULL},
};
static const cli_group info_group = {"Options", info_opts, NULL};
static const cli_pos info_pos[] = {
    {"FILE", "a volume file or a folder of PNG slices", A(path)},
    {NULL},
};

const cli_spec cli_spec_info = {
    .name = "info",
    .summary = "print dimensions, voxel size, count, volume and bounding box",
    .usage = "FILE [options]",
    .about = "Print the dimensions, voxel size, count of 1-voxels, physical volume and\n"
             "bounding box of a volume file (or a folder of PNG slices).\n",
    .pos = info_pos,
    .uses = {{&info_group, 0}, CLI_USE_READ(info_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox info brain.nii.gz\n"
                "  bvox info atlas.nii.gz --label 17 --json\n"
                "  bvox info scan.raw --dims 256,256,64 --type u16 --threshold 1200 "
                "--voxel-size 0.1,0.1,0.5 --unit mm\n",
};

int cmd_info(int argc, char **argv)
{
    info_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_info, argc, argv, &a);
    if (!a.path) return cli_usage_error("info", "missing the FILE to read");

    bvox_info info;
    bvox_status st;
    bvox__slab_source src;
    if (cli_ooc_open(a.path, &a.ra, &src) == 1) { /* a .zarr over --max-memory: by slabs */
        st = bvox__stream_info(&src, &info);
        bvox__slab_source_close(&src);
    } else {
        bvox_volume *vol = NULL;
        if (cli_read_volume(a.path, &a.ra, &vol)) return cli_fail();
        st = bvox_info_compute(vol, &info);
        bvox_volume_destroy(vol);
    }
    if (st) return cli_fail();
    const char *format = cli_input_format(a.path, &a.ra);
    if (a.json) cli_print_info_json_io(stdout, &info, a.path, format, a.path, NULL);
    else cli_print_info_text(stdout, &info, a.path, format);
    return CLI_OK;
}
