/*
 * cmd_image.c — `bvox image OP IN.png OUT.png [...]`: the 2D image
 * operations of the display pipeline on their own (zoom by replication, the
 * zoom x2 with pixel averaging of the paper's Figure 5, 3x3 filters and
 * kernels, pan, colour maps), each one library call on a PNG read and
 * written by the library.
 */
#include "args.h"
#include "cli.h"
#include "opts.h"

#include <string.h>

typedef struct image_args {
    const char *op, *in, *out;
    int filter, map, kernel_given;
    int shade;        /* shade: a bvox_shade_mode */
    bvox_light light; /* shade */
    int64_t factor, kernel[9], divisor, bias, offset[2];
} image_args;

#define A(member) CLI_AT(image_args, member)

static int take_kernel(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_divisor(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_offset(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_map(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_shade(const char *cmd, const cli_opt *o, const char *v, void *target);

static const char *const factors[] = {"1", "2", "4", "8", NULL};
static const char *const maps[] = {"gray", "bone", "hot", "copper", "cool", NULL};
static const char *const image_shades[] = {"gradient", "binary-preimage", "enlarged-gradient", NULL};

static const cli_opt image_opts[] = {
    {"--factor", 0, CLI_INT, NULL, "zoom: the enlargement", A(factor), .def = "2", .lo = 1,
     .hi = 8, .choices = factors, .bad = "--factor: '%s' is not 1, 2, 4 or 8"},
    {"--filter", 0, CLI_CHOICE, "F", "filter: a named 3x3 filter", A(filter),
     .choices = cli_filter_choices, .fn = cli_take_filter, .bad = CLI_BAD_FILTER},
    {"--kernel", 0, CLI_STR, "K1,...,K9", "filter: a 3x3 kernel, row by row",
     .offset = 0, .size = sizeof(image_args),
     .fn = take_kernel, .bad = "--kernel: '%s' is not 9 integers K1,...,K9"},
    {"--divisor", 0, CLI_INT, "D", "filter: the kernel's sum is divided by D", A(divisor),
     .def = "1", .fn = take_divisor, .bad = "--divisor: '%s' is not a non-zero integer"},
    {"--bias", 0, CLI_INT, "B", "filter: added to the kernel's result", A(bias), .def = "0",
     .lo = -65536, .hi = 65536, .bad = "--bias: '%s' is not an integer"},
    {"--offset", 0, CLI_STR, "DX,DY", "pan: the move in pixels", A(offset), .fn = take_offset,
     .bad = "--offset: '%s' is not DX,DY"},
    {"--map", 0, CLI_CHOICE, NULL, "colormap: the colour map", A(map), .choices = maps,
     .fn = take_map, .bad = "--map: unknown colour map '%s'"},
    /* --- issue 18: the paper's pre-image operators on a depth map --- */
    {"--shade", 0, CLI_CHOICE, "S",
     "shade: the normals, gradient (Sobel over the depths, default), binary-preimage (the "
     "paper's binary gradient operator) or enlarged-gradient (the pre-image enlarged x2 with "
     "the Figure 5 averaging first)",
     A(shade), .choices = image_shades, .fn = take_shade,
     .bad = "--shade: '%s' is not gradient, binary-preimage or enlarged-gradient"},
    {"--light", 0, CLI_STR, "AZ,EL", "shade: the light, as in render (default 135,45)", A(light),
     .fn = cli_take_light, .bad = CLI_BAD_LIGHT},
    {NULL},
};
static const cli_group image_group = {"Options", image_opts, NULL};
static const cli_pos image_pos[] = {
    {"OP", "zoom, average, filter, pan, colormap, enlarge or shade", A(op)},
    {"IN.png", "the image to read", A(in)},
    {"OUT.png", "the image to write", A(out)},
    {NULL},
};

const cli_spec cli_spec_image = {
    .name = "image",
    .summary = "2D image operations: zoom, average (Figure 5), filter, pan",
    .usage = "OP IN.png OUT.png [options]",
    .about = "Operations on 8-bit (zoom, average, pan: also 16-bit) gray or RGB PNG images:\n"
             "  zoom     enlarge by pixel replication (--factor 1, 2, 4 or 8; default 2)\n"
             "  average  zoom x2 with pixel averaging, the paper's Figure 5: each new pixel\n"
             "           is the average of its original neighbours, rounded half up, zeros\n"
             "           beyond the edge (13 5 / 0 8 -> 13 9 5 3 / 7 7 7 3 / 0 4 8 4 / 0 2 4 2)\n"
             "  filter   3x3 convolution: --filter highpass|smooth|laplace|sobel, or\n"
             "           --kernel K1,...,K9 (row by row) [--divisor D] [--bias B];\n"
             "           results saturate at 0 and 255, the edge pixels are repeated\n"
             "  pan      move by --offset DX,DY pixels (zeros where nothing lands)\n"
             "  colormap gray to RGB: --map gray|bone|hot|copper|cool\n"
             "The paper's pre-image operators, on a 16-bit depth map (render --depth: 0\n"
             "background, else depth + 1; depth steps as long as pixels):\n"
             "  enlarge  the pre-image enlarged x2: zoom, then the Figure 5 averaging of\n"
             "           the depths (background neither averaged in nor grown); 16-bit out\n"
             "  shade    a gradient operator over the depths, lit (--light): --shade\n"
             "           gradient, binary-preimage or enlarged-gradient (Picture 2's order)\n",
    .pos = image_pos,
    .uses = {{&image_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox image average pre.png big.png\n"
                "  bvox image filter big.png sharp.png --filter highpass\n"
                "  bvox image filter in.png edges.png --kernel -1,0,1,-2,0,2,-1,0,1 --bias 128\n"
                "  bvox image shade depth16.png shaded.png --shade enlarged-gradient\n",
};

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

enum { OP_ZOOM, OP_AVERAGE, OP_FILTER, OP_PAN, OP_COLORMAP, OP_ENLARGE, OP_SHADE, NOPS };
static const char *const ops[] = {"zoom", "average", "filter", "pan", "colormap", "enlarge", "shade"};

static int take_kernel(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    image_args *a = target; /* the whole args: kernel and kernel_given */
    if (parse_ints(v, 9, -65536, 65536, a->kernel)) return CLI_OPT_BAD;
    a->kernel_given = 1;
    return CLI_OPT_OK;
}

static int take_divisor(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int64_t d;
    if (cli_parse_int64(v, -65536, 65536, &d) || !d) return CLI_OPT_BAD;
    *(int64_t *)target = d;
    return CLI_OPT_OK;
}

static int take_offset(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    return parse_ints(v, 2, -BVOX_IMAGE_MAX_DIM, BVOX_IMAGE_MAX_DIM, target) ? CLI_OPT_BAD
                                                                              : CLI_OPT_OK;
}

static int take_map(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int m = bvox_colormap_parse(v);
    if (m < 0) return CLI_OPT_BAD;
    *(int *)target = m;
    return CLI_OPT_OK;
}

static int take_shade(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int m = bvox_shade_mode_parse(v);
    if (m != BVOX_SHADE_GRADIENT && m != BVOX_SHADE_PREIMAGE_BINARY &&
        m != BVOX_SHADE_ENLARGED_GRADIENT)
        return CLI_OPT_BAD;
    *(int *)target = m;
    return CLI_OPT_OK;
}

/* enlarge, shade: the depth map as a pre-image, the operator, the result. */
static bvox_status depth_op(int op, const bvox_image *in, const image_args *a, bvox_image **out)
{
    bvox_preimage *pre = NULL, *big = NULL;
    bvox_status st = bvox_preimage_from_depth_map(in, &pre);
    if (!st && op == OP_ENLARGE) {
        st = bvox_preimage_enlarge(pre, &big);
        if (!st) st = bvox_preimage_depth_map(big, out);
    } else if (!st) {
        st = bvox_shade_preimage(NULL, pre, (bvox_shade_mode)a->shade, 0, &a->light, out);
    }
    bvox_preimage_destroy(big);
    bvox_preimage_destroy(pre);
    return st;
}

int cmd_image(int argc, char **argv)
{
    const char *cmd = "image";
    image_args a = {.filter = -1, .map = -1, .shade = BVOX_SHADE_GRADIENT,
                    .light = BVOX_LIGHT_INIT};
    CLI_PARSE_OR_RETURN(&cli_spec_image, argc, argv, &a);
    const char *pos[3] = {a.op, a.in, a.out};
    int npos = !!a.op + !!a.in + !!a.out, op = -1, filter = a.filter, map = a.map;
    int kernel_given = a.kernel_given;
    int64_t factor = a.factor, *kernel = a.kernel, divisor = a.divisor, bias = a.bias,
            *offset = a.offset;
    if (npos < 3) return cli_usage_error(cmd, "needs OP IN.png OUT.png");
    for (int k = 0; k < NOPS; k++)
        if (!strcmp(pos[0], ops[k])) op = k;
    if (op < 0)
        return cli_usage_error(cmd, "unknown operation '%s' (zoom, average, filter, pan, "
                                    "colormap, enlarge, shade)",
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
    case OP_ENLARGE:
    case OP_SHADE: st = depth_op(op, in, &a, &out); break;
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
