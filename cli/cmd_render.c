/*
 * cmd_render.c — `bvox render IN -o OUT.png [...]`: parse the view, shading,
 * image operations, cut and depth-cue options into a bvox_render_opts and
 * make one library call (bvox_render, bvox_render_sheet or
 * bvox_render_turntable); --depth also writes the pre-image's depth map
 * (bvox_preimage_depth_map) as a 16-bit PNG. Several inputs (one grid) or
 * --labels go to bvox_render_objects / bvox_render_labels, each object in
 * its --color (issue 18 item 2, issue 19 item 4).
 */
#include "args.h"
#include "cli.h"
#include "manip.h"
#include "opts.h"
#include "common/color.h"
#include "common/names.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_COLORS 256

typedef struct render_args {
    cli_list ins;
    const char *out, *depth;
    /* --- issue 18 item 2: colours and annotations --- */
    uint8_t colors[MAX_COLORS][3];
    int ncolors, labels;
    const char *background, *lut;
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
static int take_colors(const char *cmd, const cli_opt *o, const char *v, void *target);

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
    /* --- issue 18 item 2, issue 19 item 4: colours and annotations --- */
    {"--color", 0, CLI_STR, "C[,C...]",
     "the object's colour (a name: red, green, blue, orange, ... or #rrggbb), the shading "
     "modulating it and the cut face in a lighter tone of it; with several IN, one colour per "
     "volume in order",
     .offset = 0, .size = sizeof(render_args), .fn = take_colors}, /* target: the args */
    {"--background", 0, CLI_STR, "C", "the background: a colour, or transparent (an RGBA PNG)",
     A(background)},
    {"--scale-bar", 0, CLI_FLAG, NULL,
     "a scale bar, lower left: a round length (1, 2 or 5 x 10^k of the volume's unit) near a "
     "fifth of the width, labelled",
     A(o.scale_bar)},
    {"--axes", 0, CLI_FLAG, NULL,
     "an x/y/z triad, lower right, turned as the view (x red, y green, z blue); the "
     "annotations go on every --turntable frame and --sheet cell",
     A(o.axes)},
    {"--title", 0, CLI_STR, "TEXT", "a line of text at the top (ASCII)", A(o.title)},
    {"--labels", 0, CLI_FLAG, NULL,
     "IN is a label volume: every label in its colour (from --lut, else a palette of distinct "
     "hues)",
     A(labels)},
    {"--lut", 0, CLI_PATH, "FILE",
     "with --labels: the label table giving the colours (FreeSurfer LUT, ITK-SNAP, Slicer, "
     "AAL)",
     A(lut)},
    {NULL},
};
static const cli_group render_group = {"Options", render_opts, NULL};
static const cli_pos render_pos[] = {
    {"IN...", "the volume to render; several (one grid) for one picture of them all",
     A(ins), .many = 1},
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
                "--supersample 2\n"
                "  bvox render a.nii b.nii --color red,#00ff88 --view iso --scale-bar --axes "
                "-o both.png\n"
                "  bvox render atlas.nii --labels --lut atlas.txt --view iso --background white "
                "-o atlas.png\n",
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

/* "red,#00ff88,...": up to MAX_COLORS colours into the args' list. The
 * option has no target field (offset 0 is the list): target is the args. */
static int take_colors(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    (void)o;
    render_args *a = target;
    a->ncolors = 0;
    const char *p = v;
    for (;;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        char one[32];
        if (len == 0 || len >= sizeof one || a->ncolors == MAX_COLORS) {
            cli_usage_error(cmd, "--color: '%s' is not a list of colours (names: %s; or #rrggbb)",
                            v, bvox__color_names());
            return CLI_OPT_FAILED;
        }
        memcpy(one, p, len);
        one[len] = '\0';
        if (bvox__color_parse(one, a->colors[a->ncolors])) {
            cli_usage_error(cmd, "--color: '%s' is not a colour (names: %s; or #rrggbb)", one,
                            bvox__color_names());
            return CLI_OPT_FAILED;
        }
        a->ncolors++;
        if (!comma) return CLI_OPT_OK;
        p = comma + 1;
    }
}

static int write_depth(const bvox_preimage *pre, const char *path)
{
    bvox_image *d = NULL;
    bvox_status st = bvox_preimage_depth_map(pre, &d);
    if (!st) st = bvox_image_write_png(d, path);
    bvox_image_destroy(d);
    return st ? cli_fail() : CLI_OK;
}

/* Several inputs, or a label volume: one picture of all their objects. */
static bvox_status render_many(render_args *a, const bvox_render_opts *o, bvox_image **img)
{
    const int n = a->ins.n;
    bvox_status st = BVOX_OK;
    if (a->labels) {
        bvox_labelset *set = NULL;
        bvox_label_table *table = NULL;
        if (cli_labels_load(a->ins.items[0], &a->ra, a->lut, 0, &set, &table)) return BVOX_EINVAL;
        st = bvox_render_labels(set, table, o, img);
        bvox_labelset_destroy(set);
        bvox_label_table_destroy(table);
        return st;
    }
    bvox_volume **vols = calloc((size_t)n, sizeof *vols);
    uint8_t(*colors)[3] = calloc((size_t)n, sizeof *colors);
    if (!vols || !colors) {
        free(vols);
        free(colors);
        return BVOX_ENOMEM;
    }
    /* no --color: a palette that tells the objects apart on black or white */
    static const uint8_t fallback[6][3] = {{230, 60, 60},  {60, 200, 110}, {70, 130, 240},
                                          {240, 180, 40}, {200, 90, 220}, {40, 200, 210}};
    for (int k = 0; k < n; k++)
        memcpy(colors[k], a->ncolors ? a->colors[k] : fallback[k % 6], 3);
    for (int k = 0; k < n && !st; k++)
        if (cli_read_volume(a->ins.items[k], &a->ra, &vols[k])) st = BVOX_EINVAL;
    if (!st) st = bvox_render_objects((const bvox_volume *const *)vols, (const uint8_t(*)[3])colors,
                                      n, o, img);
    for (int k = 0; k < n; k++) bvox_volume_destroy(vols[k]);
    free(vols);
    free(colors);
    return st;
}

static int render_main(render_args *a)
{
    const char *cmd = "render";
    const char *in = a->ins.n ? a->ins.items[0] : NULL, *out = a->out, *depth = a->depth;
    bvox_render_opts o = a->o;
    int keep_given = a->keep >= 0, sheet = a->sheet;
    int64_t turntable = a->turntable;
    const int many = a->ins.n > 1 || a->labels;
    if (a->cut.given) {
        memcpy(o.plane, a->cut.p, sizeof o.plane);
        o.cut = 1;
    }
    if (keep_given) o.keep_above = a->keep == 0;
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
    /* --- issue 18 item 2: colours and annotations --- */
    if (a->labels && a->ins.n > 1) return cli_usage_error(cmd, "--labels takes one IN");
    /* a stray word after IN (a flag's value given to a flag) stays a usage
     * error, as it was when render took one IN */
    for (int k = 1; k < a->ins.n; k++) {
        struct stat sb;
        if (stat(a->ins.items[k], &sb))
            return cli_usage_error(cmd, "'%s' is not an option or a file to render",
                                   a->ins.items[k]);
    }
    if (a->lut && !a->labels) return cli_usage_error(cmd, "--lut needs --labels");
    if (a->labels && a->ncolors) return cli_usage_error(cmd, "--labels takes its colours from --lut, not --color");
    if (a->ncolors > 1 && a->ncolors != a->ins.n)
        return cli_usage_error(cmd, "--color: %d colours for %d volumes", a->ncolors, a->ins.n);
    if (a->ncolors == 1 && !many) {
        o.color_set = 1;
        memcpy(o.color, a->colors[0], 3);
    }
    if (a->background) {
        if (!strcmp(a->background, "transparent")) o.transparent = 1;
        else if (bvox__color_parse(a->background, o.background))
            return cli_usage_error(cmd, "--background: '%s' is not a colour or transparent "
                                        "(names: %s; or #rrggbb)",
                                   a->background, bvox__color_names());
    }
    if (o.title)
        for (const unsigned char *t = (const unsigned char *)o.title; *t; t++)
            if (*t < 32 || *t > 126)
                return cli_usage_error(cmd, "--title: only printable ASCII can be drawn");
    if (o.title && strlen(o.title) > 200)
        return cli_usage_error(cmd, "--title: at most 200 characters");
    if (o.transparent && turntable)
        return cli_usage_error(cmd, "--background transparent: a turntable has no alpha");
    if (o.transparent && o.stereo == BVOX_STEREO_ANAGLYPH)
        return cli_usage_error(cmd, "--background transparent: an anaglyph has no alpha");
    if (many && (turntable || sheet || depth))
        return cli_usage_error(cmd, "several volumes or --labels make a single picture (no "
                                    "--turntable, --sheet, --depth)");

    bvox_status st;
    int rc = CLI_OK;
    if (many) {
        bvox_image *img = NULL;
        st = render_many(a, &o, &img);
        if (!st) st = bvox_image_write_png(img, out);
        bvox_image_destroy(img);
        return st ? cli_fail() : CLI_OK;
    }
    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a->ra, &vol)) return cli_fail();
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

int cmd_render(int argc, char **argv)
{
    render_args a = {.o = bvox_render_opts_default(), .keep = -1};
    cli_read_args_init(&a.ra);
    a.ins.items = calloc((size_t)argc + 1, sizeof *a.ins.items);
    if (!a.ins.items) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    int r = cli_parse(&cli_spec_render, argc, argv, &a);
    if (r != CLI_PARSED) {
        free(a.ins.items);
        return r == CLI_PARSE_HELP ? CLI_OK : CLI_USAGE;
    }
    r = render_main(&a);
    free(a.ins.items);
    return r;
}
