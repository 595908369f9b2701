/*
 * cmd_convert.c — `bvox convert IN OUT`: bvox_read with the shared read
 * options (so a gray or label image is binarised on the way), then bvox_write,
 * which writes to a temporary file and renames it only on success.
 */
#include "args.h"
#include "cli.h"
#include "manip.h"
#include "opts.h"

#include <string.h>

typedef struct convert_args {
    const char *in, *out;
    int json;
    bvox_write_opts wo;
    int wo_codec; /* index into zarr_codecs */
    cli_read_args ra;
} convert_args;

#define A(member) CLI_AT(convert_args, member)

static const char *const zarr_codecs[] = {"zlib", "blosc", NULL};

/* --chunks X,Y,Z: the Zarr writer's chunk shape (each in 1..65535). */
static int take_chunks(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    (void)cmd, (void)o;
    bvox_dims d;
    if (cli_parse_dims(v, &d)) return CLI_OPT_BAD;
    int32_t *c = ((bvox_write_opts *)t)->chunks;
    c[0] = d.nx, c[1] = d.ny, c[2] = d.nz;
    return CLI_OPT_OK;
}

static const cli_opt convert_opts[] = {
    {"--output-format", 0, CLI_STR, "NAME",
     "force the output format ({formats}); needed for a folder of PNG slices", A(wo.format)},
    {"--force", 0, CLI_FLAG, NULL, CLI_FORCE_HELP, A(wo.force)},
    {"--chunks", 0, CLI_STR, "X,Y,Z", "chunk shape of a .zarr output (default: up to 64 per axis)",
     A(wo), .fn = take_chunks, .bad = "--chunks needs X,Y,Z (each 1..65535), not '%s'"},
    {"--compressor", 0, CLI_CHOICE, NULL, "chunk codec of a .zarr output (blosc: bit-shuffled lz4)",
     A(wo_codec), .def = "zlib", .choices = zarr_codecs},
    {"--levels", 0, CLI_INT, "N", "resolution levels of a .zarr output (0: halve until a side "
     "is under one chunk; 1: no pyramid)", A(wo.zarr_levels), .lo = 0, .hi = 16,
     .bad = "--levels: '%s' is not a count 0..16"},
    {"--json", 0, CLI_FLAG, NULL,
     "print one JSON object: what 'bvox info --json' says of OUT, and input, output",
     A(json)},
    {NULL},
};
static const cli_group convert_group = {"Options", convert_opts, NULL};
static const cli_pos convert_pos[] = {
    {"IN", "the volume to read", A(in)},
    {"OUT", "the file to write (format by extension)", A(out)},
    {NULL},
};

const cli_spec cli_spec_convert = {
    .name = "convert",
    .summary = "convert between formats (binarising gray/label images)",
    .usage = "IN OUT [options]",
    .about = "Read IN (binarising gray or label images with the read options) and write\n"
             "the binary volume to OUT, in the format its extension names. A failure\n"
             "leaves no partial OUT behind and an existing OUT unchanged.\n",
    .pos = convert_pos,
    .uses = {{&convert_group, 0}, CLI_USE_READ(convert_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox convert mask.nii.gz mask.tif\n"
                "  bvox convert atlas.nii.gz hippocampus.binvox --label 37\n"
                "  bvox convert stack.tif slices --output-format png\n"
                "  bvox convert mask.nii.gz mask.zarr --chunks 128,128,64\n"
                "  bvox convert scan.raw scan.nii.gz --dims 512,512,200 --type i16 --threshold 300 "
                "--voxel-size 0.4,0.4,1 --unit mm\n",
};

int cmd_convert(int argc, char **argv)
{
    const char *cmd = "convert";
    convert_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_convert, argc, argv, &a);
    const char *in = a.in, *out = a.out;
    if (!in || !out) return cli_usage_error(cmd, "needs IN and OUT");
    a.wo.compressor = zarr_codecs[a.wo_codec];
    /* Refuse before reading a possibly large input. */
    if (cli_check_output(cmd, out, &a.wo) != CLI_OK) return CLI_USAGE;

    /* ... and when the header alone shows that the output cannot hold it */
    bvox_dims dims;
    if (bvox_read_dims(in, &a.ra.opts, &dims) == BVOX_OK && bvox_write_check(out, dims, &a.wo))
        return cli_fail();
    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    bvox_status st = bvox_write(out, vol, &a.wo);
    if (!st && a.json) st = cli_print_volume_json(vol, in, out, a.wo.format, NULL, NULL);
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
