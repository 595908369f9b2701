/*
 * cmd_render.c — `bvox render IN -o OUT.png [...]`: parse the view, shading,
 * image operations, cut and depth-cue options into a bvox_render_opts and
 * make one library call (bvox_render, bvox_render_sheet or
 * bvox_render_turntable); --depth also writes the pre-image's depth map
 * (bvox_preimage_depth_map) as a 16-bit PNG.
 */
#include "args.h"
#include "cli.h"
#include "manip.h"
#include "opts.h"
#include "common/names.h"

#include <stdlib.h>
#include <string.h>

typedef struct render_args {
    const char *in, *out, *depth;
    bvox_render_opts o;
    cli_plane cut;
    int keep, sheet; /* keep: -1 not given, 0 above, 1 below */
    int64_t turntable;
    cli_read_args ra;
} render_args;

#define A(member) CLI_AT(render_args, member)

static int take_view(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_shade(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_size(const char *cmd, const cli_opt *o, const char *v, void *target);
static int take_stereo(const char *cmd, const cli_opt *o, const char *v, void *target);

static const char *const shades[] = {"depth", "binary", "gradient", "binary+depth", "smooth",
                                     "binary-preimage", "enlarged-gradient", NULL};
static const char *const zooms[] = {"1", "2", "4", "8", NULL};
static const char *const stereos[] = {"sbs", "anaglyph", NULL};

static const cli_opt render_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT.png", "the picture (required)", A(out)},
    {"--view", 0, CLI_STR, "V",
     "+z -z +x -x +y -y: an axis view; +z looks along +z (rays enter at z = 0); one pixel per "
     "voxel column, for +-z column = x, row = y; for +-x column = y, row = z; for +-y column = "
     "x, row = z (default +z). AZ,EL: a parallel projection turned by azimuth and elevation in "
     "degrees (0,0 is +z). iso: isometric, looking from the corner (+1,+1,+1), z up; iso+x-y+z "
     "etc. pick any of the 8 corners",
     A(o), .fn = take_view},
    {"--shade", 0, CLI_CHOICE, "S",
     "depth, binary (binary gradient: the 26 voxel normals), gradient (from the depth map, "
     "Sobel), binary+depth (default), smooth (normals from the occupancy around the hit "
     "voxel: the gray-level gradient over a ball, see --smooth-radius), binary-preimage (the "
     "paper's binary gradient operator run over the pre-image) or enlarged-gradient (the "
     "paper's Picture 2 order: the depth pre-image enlarged x2 with the Figure 5 averaging, "
     "then the gradient operator over it; twice the size)",
     A(o.shade), .choices = shades, .fn = take_shade,
     .bad = "--shade: '%s' is not depth, binary, gradient, binary+depth, smooth, "
            "binary-preimage or enlarged-gradient"},
    /* --- issue 18: publishable shading --- */
    {"--smooth-radius", 0, CLI_INT, "R",
     "smooth normals (and --ao, --shadows) from the ball of radius R: 1 (3x3x3), 2 (5x5x5, "
     "default) or 3 (7x7x7)",
     A(o.smooth_radius), .lo = 1, .hi = 3,
     .bad = "--smooth-radius: '%s' is not 1, 2 or 3"},
    {"--ao", 0, CLI_FLAG, NULL,
     "ambient occlusion: darken the surface by how much of the space in front of it the "
     "object fills (at 2, 4 and 8 voxels)",
     A(o.ao)},
    {"--shadows", 0, CLI_FLAG, NULL,
     "cast shadows: a surface the object hides from the light keeps only its ambient light",
     A(o.shadows)},
    {"--supersample", 0, CLI_INT, "N",
     "antialiased edges: N x N rays a pixel, averaged (2..4; an axis view becomes a "
     "projection, as with --size)",
     A(o.supersample), .lo = 1, .hi = 4, .bad = "--supersample: '%s' is not 1, 2, 3 or 4"},
    {"--light", 0, CLI_STR, "AZ,EL",
     "light direction: azimuth in the image plane (0 from the right, 90 from the top), "
     "elevation towards the viewer (default 135,45)",
     A(o.light), .fn = cli_take_light, .bad = CLI_BAD_LIGHT},
    {"--size", 0, CLI_STR, "W,H",
     "image size: the view becomes a projection of W x H pixels that fits the object (default "
     "for AZ,EL and iso: 512,512)",
     A(o.proj), .fn = take_size, .bad = "--size: '%s' is not W,H (whole pixels, 1..16384)"},
    {"--zoom", 0, CLI_INT, NULL, "enlarge by pixel replication", A(o.zoom), .lo = 1, .hi = 8,
     .choices = zooms, .bad = "--zoom: '%s' is not 1, 2, 4 or 8"},
    {"--average", 0, CLI_FLAG, NULL, "then zoom x2 with pixel averaging (the paper's Figure 5)",
     A(o.average)},
    {"--filter", 0, CLI_CHOICE, "F", "then a 3x3 filter: highpass, smooth, laplace, sobel",
     A(o.filter), .choices = cli_filter_choices, .fn = cli_take_filter, .bad = CLI_BAD_FILTER},
    {"--cut", 0, CLI_STR, "A,B,C,D",
     "cut by the plane A*x + B*y + C*z + D = 0 in world coordinates (as 'bvox cut'); the cut "
     "face is drawn lit by the plane's normal and tinted (RGB output)",
     A(cut), .fn = cli_take_plane},
    {"--keep", 0, CLI_CHOICE, NULL, "the side of the cut to keep (default above: >= 0)", A(keep),
     .choices = cli_keep_choices},
    {"--stereo", 0, CLI_CHOICE, NULL,
     "a stereo pair, the view turned by -+3 degrees about the image's vertical: side by side "
     "(left eye's image on the left, for parallel viewing) or a red-cyan anaglyph (red = left "
     "eye)",
     A(o.stereo), .choices = stereos, .fn = take_stereo},
    {"--sheet", 0, CLI_FLAG, NULL,
     "four views in a 2x2 grid: +z, +x / -y, iso (each --size, default 256,256)", A(sheet)},
    {"--turntable", 0, CLI_INT, "N",
     "N frames of the object spinning about the volume axis nearest the image's vertical: OUT "
     "ending in .gif is an animated GIF, else OUT_000.png, OUT_001.png ...",
     A(turntable), .lo = 1, .hi = 3600, .bad = "--turntable: '%s' is not a frame count in 1..3600"},
    {"--depth", 0, CLI_PATH, "OUT16.png",
     "also write the depth map, 16 bits: 0 background, else depth + 1; depth in voxels from "
     "the entry face for an axis view, in pixel units from the front of the fitting sphere for "
     "a projection",
     A(depth)},
    {NULL},
};
static const cli_group render_group = {"Options", render_opts, NULL};
static const cli_pos render_pos[] = {
    {"IN", "the volume to render", A(in)},
    {NULL},
};

const cli_spec cli_spec_render = {
    .name = "render",
    .summary = "shaded picture: axis/iso/any view, cut, stereo, sheet, turntable",
    .usage = "IN -o OUT.png [options]",
    .about = "Render a binary volume as the paper's display pipeline does: cast a\n"
             "pre-image (depth and normal code per pixel), shade it through a lookup\n"
             "table, then zoom and filter the image. Axes are the file's voxel index\n"
             "axes (x, y, z = i, j, k), never reoriented.\n",
    .pos = render_pos,
    .uses = {{&render_group, 0}, CLI_USE_READ(render_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox render embryo.nii.gz -o top.png --view +z --shade depth\n"
                "  bvox render embryo.nii.gz -o iso.png --view iso --zoom 2 --average --filter highpass\n"
                "  bvox render embryo.nii.gz -o half.png --view 30,20 --cut 1,0,0,-1.2 --keep below\n"
                "  bvox render embryo.nii.gz -o spin.gif --view iso --turntable 36\n"
                "  bvox render embryo.nii.gz -o pub.png --view iso --shade smooth --ao --shadows "
                "--supersample 2\n",
};

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

static int take_view(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    if (!bvox_render_parse_view(v, target)) return CLI_OPT_OK;
    cli_usage_error(cmd, "--view: %s", bvox_errmsg());
    return CLI_OPT_FAILED;
}

static int take_shade(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int m = bvox_shade_mode_parse(v);
    if (m < 0) return CLI_OPT_BAD;
    *(bvox_shade_mode *)target = (bvox_shade_mode)m;
    return CLI_OPT_OK;
}

static int take_size(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    double x[2];
    if (parse_list(v, 2, x) || x[0] != (int32_t)x[0] || x[1] != (int32_t)x[1] || x[0] < 1 ||
        x[1] < 1 || x[0] > 16384 || x[1] > 16384)
        return CLI_OPT_BAD;
    bvox_projection *proj = target;
    proj->width = (int32_t)x[0], proj->height = (int32_t)x[1];
    return CLI_OPT_OK;
}

static int take_stereo(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    if (!strcmp(v, "sbs")) *(bvox_stereo *)target = BVOX_STEREO_SBS;
    else if (!strcmp(v, "anaglyph")) *(bvox_stereo *)target = BVOX_STEREO_ANAGLYPH;
    else return CLI_OPT_BAD;
    return CLI_OPT_OK;
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
    const char *cmd = "render";
    render_args a = {.o = bvox_render_opts_default(), .keep = -1};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_render, argc, argv, &a);
    const char *in = a.in, *out = a.out, *depth = a.depth;
    bvox_render_opts o = a.o;
    int keep_given = a.keep >= 0, sheet = a.sheet;
    int64_t turntable = a.turntable;
    if (a.cut.given) {
        memcpy(o.plane, a.cut.p, sizeof o.plane);
        o.cut = 1;
    }
    if (keep_given) o.keep_above = a.keep == 0;
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
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
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
