/*
 * cmd_mosaic.c — `bvox mosaic IN -o OUT.png [--planes MASK]`: the data set as
 * the paper's frame buffer held it (Picture 4), through bvox_mosaic.
 */
#include "args.h"
#include "cli.h"
#include "common/names.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox mosaic IN -o OUT.png [options]\n"
          "\n"
          "Show the volume as the paper's frame buffer stored it: 8 consecutive z\n"
          "slices packed in the 8 bit planes of one byte per pixel (slice 8s+b in bit b\n"
          "of section s), the sections laid out row by row in a grid. A 128^3 volume\n"
          "gives 512 x 512 pixels: 4 x 4 sections of 128 x 128.\n"
          "\n"
          "Options:\n"
          "  -o, --output OUT.png  the picture (required)\n"
          "  --planes MASK         the bit planes shown, 0..255 (decimal, 0x.. or 0b..):\n"
          "                        bit b shows slice 8s+b of every section (default 0xff)\n"
          "  --display D           count: gray = how many selected planes are set\n"
          "                        (default); any: white where any is set; bytes: the\n"
          "                        stored byte (masked) itself\n"
          "  --columns N           sections per row (default: a square grid)\n"
          "  --help                show this help\n",
          f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox mosaic embryo.nii.gz -o stored.png\n"
          "  bvox mosaic embryo.nii.gz -o first-slices.png --planes 0x01\n",
          f);
}

/* 0..255 as decimal, 0x hex or 0b binary; -1 if not. */
static int parse_mask(const char *s)
{
    int base = 10;
    if (s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) base = 16, s += 2;
    else if (s[0] == '0' && (s[1] == 'b' || s[1] == 'B')) base = 2, s += 2;
    if (!*s) return -1;
    int v = 0;
    for (; *s; s++) {
        int d = *s >= '0' && *s <= '9' ? *s - '0'
              : *s >= 'a' && *s <= 'f' ? *s - 'a' + 10
              : *s >= 'A' && *s <= 'F' ? *s - 'A' + 10 : 99;
        if (d >= base) return -1;
        v = v * base + d;
        if (v > 255) return -1;
    }
    return v;
}

int cmd_mosaic(int argc, char **argv)
{
    const char *cmd = "mosaic", *in = NULL, *out = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_mosaic_opts mo = BVOX_MOSAIC_OPTS_INIT;
    int options_done = 0, r;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "-o", &v)) ||
                   (r = cli_match_value(cmd, argc, argv, &i, "--output", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            out = v;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--planes", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            int m = parse_mask(v);
            if (m < 0) return cli_usage_error(cmd, "--planes: '%s' is not a mask 0..255", v);
            mo.planes = (uint8_t)m;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--display", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            int d = bvox_mosaic_display_parse(v);
            if (d < 0) return cli_usage_error(cmd, "--display: '%s' is not count, any or bytes", v);
            mo.display = (bvox_mosaic_display)d;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--columns", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            int64_t c;
            if (cli_parse_int64(v, 1, 8192, &c))
                return cli_usage_error(cmd, "--columns: '%s' is not a count in 1..8192", v);
            mo.columns = (int32_t)c;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "needs IN");
    if (!out || !*out) return cli_usage_error(cmd, "needs -o OUT.png");
    if (!bvox__ends_with_ci(out, ".png"))
        return cli_usage_error(cmd, "%s: the output must end in .png", out);

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_image *img = NULL;
    bvox_status st = bvox_mosaic(vol, &mo, &img);
    if (!st) st = bvox_image_write_png(img, out);
    bvox_image_destroy(img);
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
