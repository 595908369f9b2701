/*
 * cmd_mosaic.c — `bvox mosaic IN -o OUT.png [--planes MASK]`: the data set as
 * the paper's frame buffer held it (Picture 4), through bvox_mosaic.
 */
#include "args.h"
#include "cli.h"
#include "opts.h"
#include "common/names.h"

#include <string.h>

typedef struct mosaic_args {
    const char *in, *out;
    bvox_mosaic_opts mo;
    cli_read_args ra;
} mosaic_args;

#define A(member) CLI_AT(mosaic_args, member)

static int take_planes(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_display(const char *cmd, const cli_opt *o, const char *v, void *target);
static const char *const displays[] = {"count", "any", "bytes", NULL};

static const cli_opt mosaic_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT.png", "the picture (required)", A(out)},
    {"--planes", 0, CLI_STR, "MASK",
     "the bit planes shown, 0..255 (decimal, 0x.. or 0b..): bit b shows slice 8s+b of every "
     "section (default 0xff)",
     A(mo.planes), .fn = take_planes, .bad = "--planes: '%s' is not a mask 0..255"},
    {"--display", 0, CLI_CHOICE, "D",
     "count: gray = how many selected planes are set (default); any: white where any is set; "
     "bytes: the stored byte (masked) itself",
     A(mo.display), .choices = displays, .fn = take_display},
    {"--columns", 0, CLI_INT, "N", "sections per row (default: a square grid)", A(mo.columns),
     .lo = 1, .hi = 8192, .bad = "--columns: '%s' is not a count in 1..8192"},
    {NULL},
};
static const cli_group mosaic_group = {"Options", mosaic_opts, NULL};
static const cli_pos mosaic_pos[] = {
    {"IN", "the volume to show", A(in)},
    {NULL},
};

const cli_spec cli_spec_mosaic = {
    .name = "mosaic",
    .summary = "the data set as the frame buffer held it: 8 slices per byte",
    .usage = "IN -o OUT.png [options]",
    .about = "Show the volume as the paper's frame buffer stored it: 8 consecutive z\n"
             "slices packed in the 8 bit planes of one byte per pixel (slice 8s+b in bit b\n"
             "of section s), the sections laid out row by row in a grid. A 128^3 volume\n"
             "gives 512 x 512 pixels: 4 x 4 sections of 128 x 128.\n",
    .pos = mosaic_pos,
    .uses = {{&mosaic_group, 0}, CLI_USE_READ(mosaic_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox mosaic embryo.nii.gz -o stored.png\n"
                "  bvox mosaic embryo.nii.gz -o first-slices.png --planes 0x01\n",
};

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

static int take_planes(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int m = parse_mask(v);
    if (m < 0) return CLI_OPT_BAD;
    *(uint8_t *)target = (uint8_t)m;
    return CLI_OPT_OK;
}

static int take_display(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int d = bvox_mosaic_display_parse(v);
    if (d < 0) return CLI_OPT_BAD;
    *(bvox_mosaic_display *)target = (bvox_mosaic_display)d;
    return CLI_OPT_OK;
}

int cmd_mosaic(int argc, char **argv)
{
    const char *cmd = "mosaic";
    mosaic_args a = {.mo = BVOX_MOSAIC_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_mosaic, argc, argv, &a);
    const char *in = a.in, *out = a.out;
    if (!in) return cli_usage_error(cmd, "needs IN");
    if (!out || !*out) return cli_usage_error(cmd, "needs -o OUT.png");
    if (!bvox__ends_with_ci(out, ".png"))
        return cli_usage_error(cmd, "%s: the output must end in .png", out);

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    bvox_image *img = NULL;
    bvox_status st = bvox_mosaic(vol, &a.mo, &img);
    if (!st) st = bvox_image_write_png(img, out);
    bvox_image_destroy(img);
    bvox_volume_destroy(vol);
    return st ? cli_fail() : CLI_OK;
}
