/*
 * cmd_view.c — `bvox view MODEL [--script FILE | --bench]`: the interactive
 * viewer (viewer/, SDL2). Parses the options, reads the model (or builds the
 * demo specimen) and hands it to vw_run. A build without the viewer (or
 * without SDL2) says so and exits 1.
 */
#include "args.h"
#include "cli.h"
#include "opts.h"

#ifdef BVOX_HAVE_VIEWER
#include "view.h"
#endif

#include <stdlib.h>
#include <string.h>

typedef struct view_args {
    const char *in, *script, *output, *lut;
    int demo, bench, offscreen, labels;
    int64_t frames, size[2];
    cli_read_args ra;
} view_args;

#define A(member) CLI_AT(view_args, member)

static int take_size(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int64_t *wh = target;
    const char *comma = strchr(v, ',');
    char wbuf[32];
    if (!comma || (size_t)(comma - v) >= sizeof wbuf) {
        cli_usage_error(cmd, "--size: '%s' is not W,H", v);
        return CLI_OPT_FAILED;
    }
    memcpy(wbuf, v, (size_t)(comma - v));
    wbuf[comma - v] = 0;
    if (cli_parse_int64(wbuf, 64, 8192, &wh[0]) || cli_parse_int64(comma + 1, 64, 8192, &wh[1]))
        return CLI_OPT_BAD;
    return CLI_OPT_OK;
}

static const cli_opt view_opts[] = {
    {"--demo", 0, CLI_FLAG, NULL, "view the built-in specimen instead of a file", A(demo)},
    {"--script", 0, CLI_PATH, "FILE",
     "replay FILE's events (key, drag, click, move, wheel, wait, screenshot PATH, save PATH, "
     "quit; see README) in the window, then exit",
     A(script)},
    {"--offscreen", 0, CLI_FLAG, NULL, "with --script: draw in memory, open no window",
     A(offscreen)},
    {"--bench", 0, CLI_FLAG, NULL,
     "render a full turn off screen and print frames per second and the time of each phase",
     A(bench)},
    {"--frames", 0, CLI_INT, "N", "frames of the --bench turn (default 120)", A(frames), .lo = 1,
     .hi = 100000, .bad = "--frames: '%s' is not a count in 1..100000"},
    {"--size", 0, CLI_STR, "W,H", "canvas size in pixels (default 800,800)", A(size),
     .fn = take_size, .bad = "--size: '%s' is not W,H with each in 64..8192"},
    {"--output", 'o', CLI_PATH, "OUT",
     "where ctrl+s saves the model (default bvox-view-model.nii.gz)", A(output)},
    {"--labels", 0, CLI_FLAG, NULL,
     "MODEL is a label volume (an atlas, a segmentation): show every label, each in its "
     "colour (--lut, else a palette); a click names the label",
     A(labels)},
    {"--lut", 0, CLI_PATH, "TABLE",
     "with --labels: the label names and colours (FreeSurfer, Slicer, ITK-SNAP or AAL table)",
     A(lut)},
    {NULL},
};
static const cli_group view_group = {"Options", view_opts, NULL};
static const cli_pos view_pos[] = {
    {"MODEL", "the volume to view", A(in)},
    {NULL},
};

const cli_spec cli_spec_view = {
    .name = "view",
    .summary = "interactive viewer: turn, light, cut, slices, mosaic, edit (SDL2)",
    .usage = "MODEL [options]\n--demo [options]",
    .about = "Open a window showing the shaded object: turn it with the mouse (left drag),\n"
             "zoom (wheel), pan (right drag), move the light (arrows, shift+left drag:\n"
             "only the lookup table changes), switch shading, cut it with a plane, see\n"
             "the mosaic and three linked orthogonal slices, edit it (brush, box\n"
             "selection, primitives; undo/redo) and save it. Press h in the window for\n"
             "every key.\n",
    .pos = view_pos,
    .uses = {{&view_group, 0}, CLI_USE_READ(view_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox view embryo.nii.gz\n"
                "  bvox view --demo --bench\n"
                "  xvfb-run -a bvox view model.nii --script rotate.txt\n",
};

int cmd_view(int argc, char **argv)
{
    const char *cmd = "view";
    view_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_view, argc, argv, &a);
    const char *in = a.in, *script = a.script, *output = a.output;
    int demo = a.demo, bench = a.bench, offscreen = a.offscreen;
    int64_t frames = a.frames, width = a.size[0], height = a.size[1];
    if (!in && !demo) return cli_usage_error(cmd, "needs MODEL (or --demo)");
    if (in && demo) return cli_usage_error(cmd, "give MODEL or --demo, not both");
    if (script && bench) return cli_usage_error(cmd, "--script and --bench exclude each other");
    if (offscreen && !script) return cli_usage_error(cmd, "--offscreen goes with --script");
    if (a.lut && !a.labels) return cli_usage_error(cmd, "--lut goes with --labels");
    if (a.labels && demo) return cli_usage_error(cmd, "--labels needs a label volume, not --demo");
#ifndef BVOX_HAVE_VIEWER
    (void)output, (void)frames, (void)width, (void)height;
    fprintf(stderr, "bvox: view: this bvox was built without the viewer "
                    "(configure with -DBVOX_BUILD_VIEWER=ON and libsdl2-dev installed)\n");
    return CLI_FAIL;
#else
    bvox_volume *vol = NULL;
    bvox_labelset *set = NULL;
    bvox_label_table *table = NULL;
    bvox_status st;
    if (a.labels) {
        if (cli_labels_load(in, &a.ra, a.lut, BVOX_LABELS_MAX_DEFAULT, &set, &table)) return cli_fail();
        st = vw_labels_model(set, &vol);
    } else {
        st = demo ? bvox_demo_specimen(&vol) : cli_read_volume(in, &a.ra, &vol);
    }
    if (st) {
        bvox_labelset_destroy(set);
        bvox_label_table_destroy(table);
        return cli_fail();
    }
    vw_run_opts o = {script, bench, (int)frames, (int)width, (int)height, output, offscreen, set, table};
    int rc = vw_run(&o, vol);
    bvox_labelset_destroy(set);
    bvox_label_table_destroy(table);
    return rc ? CLI_FAIL : CLI_OK;
#endif
}
