/*
 * cmd_image.c — `bvox image OP IN.png OUT.png [...]`: the 2D image
 * operations of the display pipeline on their own (zoom by replication, the
 * zoom x2 with pixel averaging of the paper's Figure 5, 3x3 filters and
 * kernels, pan, colour maps), each one library call on a PNG read and
 * written by the library.
 */
#include "args.h"
#include "cli.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox image OP IN.png OUT.png [options]\n"
          "\n"
          "Operations on 8-bit (zoom, average, pan: also 16-bit) gray or RGB PNG images:\n"
          "  zoom     enlarge by pixel replication (--factor 1, 2, 4 or 8; default 2)\n"
          "  average  zoom x2 with pixel averaging, the paper's Figure 5: each new pixel\n"
          "           is the average of its original neighbours, rounded half up, zeros\n"
          "           beyond the edge (13 5 / 0 8 -> 13 9 5 3 / 7 7 7 3 / 0 4 8 4 / 0 2 4 2)\n"
          "  filter   3x3 convolution: --filter highpass|smooth|laplace|sobel, or\n"
          "           --kernel K1,...,K9 (row by row) [--divisor D] [--bias B];\n"
          "           results saturate at 0 and 255, the edge pixels are repeated\n"
          "  pan      move by --offset DX,DY pixels (zeros where nothing lands)\n"
          "  colormap gray to RGB: --map gray|bone|hot|copper|cool\n"
          "\n"
          "Options:\n"
          "  --help   show this help\n",
          f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox image average pre.png big.png\n"
          "  bvox image filter big.png sharp.png --filter highpass\n"
          "  bvox image filter in.png edges.png --kernel -1,0,1,-2,0,2,-1,0,1 --bias 128\n",
          f);
}

/* "a,b,...": exactly n integers in lo..hi. */
static int parse_ints(const char *s, int n, int64_t lo, int64_t hi, int64_t *out)
{
    char buf[256];
    if (!s || strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    char *p = buf;
    for (int k = 0; k < n; k++) {
        char *comma = strchr(p, ',');
        if ((k < n - 1) != (comma != NULL)) return -1;
        if (comma) *comma = '\0';
        if (cli_parse_int64(p, lo, hi, &out[k])) return -1;
        p = comma ? comma + 1 : p;
    }
    return 0;
}

enum { OP_ZOOM, OP_AVERAGE, OP_FILTER, OP_PAN, OP_COLORMAP };
static const char *const ops[] = {"zoom", "average", "filter", "pan", "colormap"};

int cmd_image(int argc, char **argv)
{
    const char *cmd = "image", *pos[3] = {NULL, NULL, NULL}, *v = NULL;
    int npos = 0, options_done = 0, r, op = -1, filter = -1, map = -1, kernel_given = 0;
    int64_t factor = 2, kernel[9], divisor = 1, bias = 0, offset[2] = {0, 0};
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (options_done || !cli_is_option(arg)) {
            if (npos == 3) return cli_usage_error(cmd, "unexpected argument '%s'", arg);
            pos[npos++] = arg;
        } else if (!strcmp(arg, "--")) {
            options_done = 1;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            return CLI_OK;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--factor", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 1, 8, &factor) || (factor & (factor - 1)))
                return cli_usage_error(cmd, "--factor: '%s' is not 1, 2, 4 or 8", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--filter", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            filter = !strcmp(v, "laplace") ? BVOX_FILTER_LAPLACIAN : bvox_filter_parse(v);
            if (filter < 0)
                return cli_usage_error(cmd, "--filter: '%s' is not highpass, smooth, laplace or "
                                            "sobel", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--kernel", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (parse_ints(v, 9, -65536, 65536, kernel))
                return cli_usage_error(cmd, "--kernel: '%s' is not 9 integers K1,...,K9", v);
            kernel_given = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--divisor", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, -65536, 65536, &divisor) || !divisor)
                return cli_usage_error(cmd, "--divisor: '%s' is not a non-zero integer", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--bias", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, -65536, 65536, &bias))
                return cli_usage_error(cmd, "--bias: '%s' is not an integer", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--offset", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (parse_ints(v, 2, -BVOX_IMAGE_MAX_DIM, BVOX_IMAGE_MAX_DIM, offset))
                return cli_usage_error(cmd, "--offset: '%s' is not DX,DY", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--map", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if ((map = bvox_colormap_parse(v)) < 0)
                return cli_usage_error(cmd, "--map: unknown colour map '%s'", v);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, NULL) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (npos < 3) return cli_usage_error(cmd, "needs OP IN.png OUT.png");
    for (int k = 0; k < 5; k++)
        if (!strcmp(pos[0], ops[k])) op = k;
    if (op < 0)
        return cli_usage_error(cmd, "unknown operation '%s' (zoom, average, filter, pan, colormap)",
                               pos[0]);
    if (op == OP_FILTER && (filter >= 0) == kernel_given)
        return cli_usage_error(cmd, "filter needs one of --filter or --kernel");
    if (op == OP_COLORMAP && map < 0) return cli_usage_error(cmd, "colormap needs --map");

    bvox_image *in = NULL, *out = NULL;
    if (bvox_image_read_png(pos[1], &in)) return cli_fail();
    bvox_status st;
    switch (op) {
    case OP_ZOOM: st = bvox_image_zoom(in, (int)factor, &out); break;
    case OP_AVERAGE: st = bvox_image_zoom2_average(in, &out); break;
    case OP_PAN: st = bvox_image_pan(in, (int32_t)offset[0], (int32_t)offset[1], &out); break;
    case OP_COLORMAP: st = bvox_image_colormap(in, (bvox_colormap)map, &out); break;
    default:
        if (kernel_given) {
            int32_t k[9];
            for (int j = 0; j < 9; j++) k[j] = (int32_t)kernel[j];
            st = bvox_image_convolve(in, k, (int32_t)divisor, (int32_t)bias, &out);
        } else {
            st = bvox_image_filter(in, (bvox_filter)filter, &out);
        }
    }
    if (!st) st = bvox_image_write_png(out, pos[2]);
    bvox_image_destroy(in);
    bvox_image_destroy(out);
    return st ? cli_fail() : CLI_OK;
}
