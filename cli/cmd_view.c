/*
 * cmd_view.c — `bvox view MODEL [--script FILE | --bench]`: the interactive
 * viewer (viewer/, SDL2). Parses the options, reads the model (or builds the
 * demo specimen) and hands it to vw_run. A build without the viewer (or
 * without SDL2) says so and exits 1.
 */
#include "args.h"
#include "cli.h"

#ifdef BVOX_HAVE_VIEWER
#include "view.h"
#endif

#include <stdlib.h>
#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox view MODEL [options]\n"
          "       bvox view --demo [options]\n"
          "\n"
          "Open a window showing the shaded object: turn it with the mouse (left drag),\n"
          "zoom (wheel), pan (right drag), move the light (arrows, shift+left drag:\n"
          "only the lookup table changes), switch shading, cut it with a plane, see\n"
          "the mosaic and three linked orthogonal slices, edit it (brush, box\n"
          "selection, primitives; undo/redo) and save it. Press h in the window for\n"
          "every key.\n"
          "\n"
          "Options:\n"
          "  --demo                view the built-in specimen instead of a file\n"
          "  --script FILE         replay FILE's events (key, drag, click, move, wheel,\n"
          "                        wait, screenshot PATH, save PATH, quit; see README)\n"
          "                        in the window, then exit\n"
          "  --offscreen           with --script: draw in memory, open no window\n"
          "  --bench               render a full turn off screen and print frames per\n"
          "                        second and the time of each phase\n"
          "  --frames N            frames of the --bench turn (default 120)\n"
          "  --size W,H            canvas size in pixels (default 800,800)\n"
          "  -o, --output OUT      where ctrl+s saves the model\n"
          "                        (default bvox-view-model.nii.gz)\n"
          "  --help                show this help\n",
          f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox view embryo.nii.gz\n"
          "  bvox view --demo --bench\n"
          "  xvfb-run -a bvox view model.nii --script rotate.txt\n",
          f);
}

int cmd_view(int argc, char **argv)
{
    const char *cmd = "view", *in = NULL, *v = NULL, *script = NULL, *output = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    int options_done = 0, r, demo = 0, bench = 0, offscreen = 0;
    int64_t frames = 0, width = 0, height = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--demo")) {
            demo = 1;
        } else if (!strcmp(arg, "--bench")) {
            bench = 1;
        } else if (!strcmp(arg, "--offscreen")) {
            offscreen = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--script", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            script = v;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--frames", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 1, 100000, &frames))
                return cli_usage_error(cmd, "--frames: '%s' is not a count in 1..100000", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--size", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            const char *comma = strchr(v, ',');
            char wbuf[32];
            if (!comma || (size_t)(comma - v) >= sizeof wbuf)
                return cli_usage_error(cmd, "--size: '%s' is not W,H", v);
            memcpy(wbuf, v, (size_t)(comma - v));
            wbuf[comma - v] = 0;
            if (cli_parse_int64(wbuf, 64, 8192, &width) || cli_parse_int64(comma + 1, 64, 8192, &height))
                return cli_usage_error(cmd, "--size: '%s' is not W,H with each in 64..8192", v);
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "-o", &v)) ||
                   (r = cli_match_value(cmd, argc, argv, &i, "--output", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            output = v;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in && !demo) return cli_usage_error(cmd, "needs MODEL (or --demo)");
    if (in && demo) return cli_usage_error(cmd, "give MODEL or --demo, not both");
    if (script && bench) return cli_usage_error(cmd, "--script and --bench exclude each other");
    if (offscreen && !script) return cli_usage_error(cmd, "--offscreen goes with --script");
#ifndef BVOX_HAVE_VIEWER
    (void)output, (void)frames, (void)width, (void)height;
    fprintf(stderr, "bvox: view: this bvox was built without the viewer "
                    "(configure with -DBVOX_BUILD_VIEWER=ON and libsdl2-dev installed)\n");
    return CLI_FAIL;
#else
    bvox_volume *vol = NULL;
    bvox_status st = demo ? bvox_demo_specimen(&vol) : cli_read_volume(in, &ra, &vol);
    if (st) return cli_fail();
    vw_run_opts o = {script, bench, (int)frames, (int)width, (int)height, output, offscreen};
    return vw_run(&o, vol) ? CLI_FAIL : CLI_OK;
#endif
}
