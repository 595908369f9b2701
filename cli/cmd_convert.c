/*
 * cmd_convert.c — `bvox convert IN OUT`: bvox_read with the shared read
 * options (so a gray or label image is binarised on the way), then bvox_write,
 * which writes to a temporary file and renames it only on success.
 */
#include "args.h"
#include "cli.h"

#include <string.h>
#include <sys/stat.h>

static void help(FILE *f)
{
    fputs("Usage: bvox convert IN OUT [options]\n"
          "\n"
          "Read IN (binarising gray or label images with the read options) and write\n"
          "the binary volume to OUT, in the format its extension names. A failure\n"
          "leaves no partial OUT behind and an existing OUT unchanged.\n"
          "\n"
          "Options:\n",
          f);
    fprintf(f, "  --output-format NAME  force the output format (%s);\n"
               "                        needed for a folder of PNG slices\n",
            bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox convert mask.nii.gz mask.tif\n"
          "  bvox convert atlas.nii.gz hippocampus.binvox --label 37\n"
          "  bvox convert stack.tif slices --output-format png\n"
          "  bvox convert scan.raw scan.nii.gz --dims 512,512,200 --type i16 --threshold 300 "
          "--voxel-size 0.4,0.4,1 --unit mm\n",
          f);
}

int cmd_convert(int argc, char **argv)
{
    const char *cmd = "convert", *in = NULL, *out = NULL, *value = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (options_done || !cli_is_option(arg)) {
            if (!in) in = arg;
            else if (!out) out = arg;
            else return cli_usage_error(cmd, "unexpected argument '%s'", arg);
        } else if (!strcmp(arg, "--")) {
            options_done = 1;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            return CLI_OK;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--output-format", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            wo.format = value;
        } else if (!strcmp(arg, "--force")) {
            wo.force = 1;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in || !out) return cli_usage_error(cmd, "needs IN and OUT");
    /* Refuse before reading a possibly large input. (A folder, existing or
     * named with a trailing '/', is a PNG stack for bvox_write.) */
    struct stat sb;
    size_t len = strlen(out);
    int folder = (len && out[len - 1] == '/') || (stat(out, &sb) == 0 && S_ISDIR(sb.st_mode));
    if (!wo.format && !folder && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; "
                               "use --output-format (one of %s)",
                               out, bvox_format_list());

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_status st = bvox_write(out, vol, &wo);
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
