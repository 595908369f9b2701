/*
 * cmd_render.c — `bvox render IN -o OUT.png [...]`: parse the view, shading,
 * image operations, cut and depth-cue options into a bvox_render_opts and
 * make one library call (bvox_render, bvox_render_sheet or
 * bvox_render_turntable); --depth also writes the pre-image's depth map
 * (bvox_preimage_depth_map) as a 16-bit PNG.
 */
#include "args.h"
#include "cli.h"
#include "common/names.h"

#include <stdlib.h>
#include <string.h>

static void help(FILE *f)
{
    fputs(
        "Usage: bvox render IN -o OUT.png [options]\n"
        "\n"
        "Render a binary volume as the paper's display pipeline does: cast a\n"
        "pre-image (depth and normal code per pixel), shade it through a lookup\n"
        "table, then zoom and filter the image. Axes are the file's voxel index\n"
        "axes (x, y, z = i, j, k), never reoriented.\n"
        "\n"
        "Options:\n"
        "  -o, --output OUT.png  the picture (required)\n"
        "  --view V              +z -z +x -x +y -y: an axis view; +z looks along +z\n"
        "                        (rays enter at z = 0); one pixel per voxel column,\n"
        "                        for +-z column = x, row = y; for +-x column = y,\n"
        "                        row = z; for +-y column = x, row = z (default +z).\n"
        "                        AZ,EL: a parallel projection turned by azimuth and\n"
        "                        elevation in degrees (0,0 is +z). iso: isometric,\n"
        "                        looking from the corner (+1,+1,+1), z up; iso+x-y+z\n"
        "                        etc. pick any of the 8 corners\n"
        "  --shade S             depth, binary (binary gradient: the 26 voxel normals),\n"
        "                        gradient (from the depth map, Sobel) or binary+depth\n"
        "                        (default)\n"
        "  --light AZ,EL         light direction: azimuth in the image plane (0 from\n"
        "                        the right, 90 from the top), elevation towards the\n"
        "                        viewer (default 135,45)\n"
        "  --size W,H            image size: the view becomes a projection of W x H\n"
        "                        pixels that fits the object (default for AZ,EL and\n"
        "                        iso: 512,512)\n"
        "  --zoom N              enlarge by pixel replication, N = 1, 2, 4 or 8\n"
        "  --average             then zoom x2 with pixel averaging (the paper's Figure 5)\n"
        "  --filter F            then a 3x3 filter: highpass, smooth, laplace, sobel\n"
        "  --cut A,B,C,D         cut by the plane A*x + B*y + C*z + D = 0 in world\n"
        "                        coordinates (as 'bvox cut'); the cut face is drawn\n"
        "                        lit by the plane's normal and tinted (RGB output)\n"
        "  --keep above|below    the side of the cut to keep (default above: >= 0)\n"
        "  --stereo sbs|anaglyph a stereo pair, the view turned by -+3 degrees about\n"
        "                        the image's vertical: side by side (left eye's image\n"
        "                        on the left, for parallel viewing) or a red-cyan\n"
        "                        anaglyph (red = left eye)\n"
        "  --sheet               four views in a 2x2 grid: +z, +x / -y, iso (each\n"
        "                        --size, default 256,256)\n"
        "  --turntable N         N frames of the object spinning about the volume axis\n"
        "                        nearest the image's vertical: OUT ending in .gif is\n"
        "                        an animated GIF, else OUT_000.png, OUT_001.png ...\n"
        "  --depth OUT16.png     also write the depth map, 16 bits: 0 background,\n"
        "                        else depth + 1; depth in voxels from the entry face\n"
        "                        for an axis view, in pixel units from the front of\n"
        "                        the fitting sphere for a projection\n"
        "  --help                show this help\n",
        f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox render embryo.nii.gz -o top.png --view +z --shade depth\n"
          "  bvox render embryo.nii.gz -o iso.png --view iso --zoom 2 --average --filter highpass\n"
          "  bvox render embryo.nii.gz -o half.png --view 30,20 --cut 1,0,0,-1.2 --keep below\n"
          "  bvox render embryo.nii.gz -o spin.gif --view iso --turntable 36\n",
          f);
}

/* "a,b,...": exactly n finite numbers. */
static int parse_list(const char *s, int n, double *out)
{
    char buf[256];
    if (!s || strlen(s) >= sizeof buf) return -1;
    strcpy(buf, s);
    char *p = buf;
    for (int k = 0; k < n; k++) {
        char *comma = strchr(p, ',');
        if ((k < n - 1) != (comma != NULL)) return -1;
        if (comma) *comma = '\0';
        if (cli_parse_double(p, &out[k])) return -1;
        p = comma ? comma + 1 : p;
    }
    return 0;
}

/* The filter names of the CLI: the library's, and "laplace". */
static int parse_filter(const char *v)
{
    return !strcmp(v, "laplace") ? BVOX_FILTER_LAPLACIAN : bvox_filter_parse(v);
}

static int write_depth(const bvox_preimage *pre, const char *path)
{
    bvox_image *d = NULL;
    bvox_status st = bvox_preimage_depth_map(pre, &d);
    if (!st) st = bvox_image_write_png(d, path);
    bvox_image_destroy(d);
    return st ? cli_fail() : CLI_OK;
}

int cmd_render(int argc, char **argv)
{
    const char *cmd = "render", *in = NULL, *out = NULL, *depth = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_render_opts o = bvox_render_opts_default();
    int options_done = 0, r, keep_given = 0, sheet = 0;
    int64_t turntable = 0;
    double x[4];
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--average")) {
            o.average = 1;
        } else if (!strcmp(arg, "--sheet")) {
            sheet = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "-o", &v)) ||
                   (r = cli_match_value(cmd, argc, argv, &i, "--output", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            out = v;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--view", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (bvox_render_parse_view(v, &o)) return cli_usage_error(cmd, "--view: %s", bvox_errmsg());
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--shade", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            int s = bvox_shade_mode_parse(v);
            if (s < 0)
                return cli_usage_error(cmd, "--shade: '%s' is not depth, binary, gradient or "
                                            "binary+depth", v);
            o.shade = (bvox_shade_mode)s;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--light", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (parse_list(v, 2, x)) return cli_usage_error(cmd, "--light: '%s' is not AZ,EL", v);
            o.light.azimuth = x[0], o.light.elevation = x[1];
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--size", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (parse_list(v, 2, x) || x[0] != (int32_t)x[0] || x[1] != (int32_t)x[1] || x[0] < 1 ||
                x[1] < 1 || x[0] > 16384 || x[1] > 16384)
                return cli_usage_error(cmd, "--size: '%s' is not W,H (whole pixels, 1..16384)", v);
            o.proj.width = (int32_t)x[0], o.proj.height = (int32_t)x[1];
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--zoom", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            int64_t z;
            if (cli_parse_int64(v, 1, 8, &z) || (z != 1 && z != 2 && z != 4 && z != 8))
                return cli_usage_error(cmd, "--zoom: '%s' is not 1, 2, 4 or 8", v);
            o.zoom = (int)z;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--filter", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if ((o.filter = parse_filter(v)) < 0)
                return cli_usage_error(cmd, "--filter: '%s' is not highpass, smooth, laplace or "
                                            "sobel", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--cut", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (parse_list(v, 4, o.plane))
                return cli_usage_error(cmd, "--cut: '%s' is not A,B,C,D", v);
            if (!o.plane[0] && !o.plane[1] && !o.plane[2])
                return cli_usage_error(cmd, "--cut: the normal A,B,C is zero");
            o.cut = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--keep", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (!strcmp(v, "above")) o.keep_above = 1;
            else if (!strcmp(v, "below")) o.keep_above = 0;
            else return cli_usage_error(cmd, "--keep: '%s' is not above or below", v);
            keep_given = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--stereo", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (!strcmp(v, "sbs")) o.stereo = BVOX_STEREO_SBS;
            else if (!strcmp(v, "anaglyph")) o.stereo = BVOX_STEREO_ANAGLYPH;
            else return cli_usage_error(cmd, "--stereo: '%s' is not sbs or anaglyph", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--turntable", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 1, 3600, &turntable))
                return cli_usage_error(cmd, "--turntable: '%s' is not a frame count in 1..3600", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--depth", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            depth = v;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "needs IN");
    if (!out || !*out) return cli_usage_error(cmd, "needs -o OUT.png");
    if (keep_given && !o.cut) return cli_usage_error(cmd, "--keep needs --cut");
    if (turntable && sheet) return cli_usage_error(cmd, "--turntable and --sheet do not mix");
    if (sheet && o.stereo) return cli_usage_error(cmd, "--sheet and --stereo do not mix");
    if (depth && (turntable || sheet || o.stereo))
        return cli_usage_error(cmd, "--depth needs a single view (no --turntable, --sheet, "
                                    "--stereo)");
    if (depth && !bvox__ends_with_ci(depth, ".png"))
        return cli_usage_error(cmd, "--depth: '%s' must end in .png", depth);
    if (!bvox__ends_with_ci(out, ".png") && !(turntable && bvox__ends_with_ci(out, ".gif")))
        return cli_usage_error(cmd, "%s: the output must end in .png%s", out,
                               turntable ? " or .gif" : "");

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_status st;
    int rc = CLI_OK;
    if (turntable) {
        st = bvox_render_turntable(vol, &o, (int)turntable, out);
    } else if (sheet) {
        bvox_image *img = NULL;
        st = bvox_render_sheet(vol, &o, &img);
        if (!st) st = bvox_image_write_png(img, out);
        bvox_image_destroy(img);
    } else {
        bvox_image *img = NULL;
        bvox_preimage *pre = NULL;
        st = bvox_render(vol, &o, &img, depth ? &pre : NULL);
        if (!st) st = bvox_image_write_png(img, out);
        if (!st && depth) rc = write_depth(pre, depth);
        bvox_image_destroy(img);
        bvox_preimage_destroy(pre);
    }
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    return rc;
}
