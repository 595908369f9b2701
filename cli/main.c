/*
 * main.c — the `bvox` command: a table of subcommands {name, run, summary}
 * from which dispatch, `bvox --help` and `bvox help CMD` are all derived, plus
 * --version. Each subcommand lives in its own cmd_<name>.c and is a thin
 * wrapper over one library call.
 */
#include "cli.h"

#include <string.h>

static const cli_command commands[] = {
    {"info", cmd_info, "print dimensions, voxel size, count, volume and bounding box"},
    {"convert", cmd_convert, "convert between formats (binarising gray/label images)"},
    {"demo", cmd_demo, "build the sample specimen, print its info, optionally write it"},
    {"morph", cmd_morph, "dilate, erode, open, close, fill cavities, hollow, remove islands"},
    {"components", cmd_components, "list connected components; keep the largest; label map"},
    {"measure", cmd_measure, "surface area, centroid, principal axes, topology, per component"},
    {"labels", cmd_labels, "label volume: per-label measures, names, neighbours (one pass)"},
    {"interpolate", cmd_interpolate, "fill unannotated slices of a mask (shape-based, per label)"},
    {"edit", cmd_edit, "set or clear voxels and boxes, keep a box or one side of a plane"},
    {"cut", cmd_cut, "cut by a plane ax+by+cz+d=0 (world coordinates), keep one side"},
    {"csg", cmd_csg, "set operations on files and shapes: \"a.nii - sphere(r=2)\""},
    {"shape", cmd_shape, "draw a sphere, ellipsoid, box, cylinder, cone, torus or half-space"},
    {"render", cmd_render, "shaded picture: axis/iso/any view, cut, stereo, sheet, turntable"},
    {"mosaic", cmd_mosaic, "the data set as the frame buffer held it: 8 slices per byte"},
    {"image", cmd_image, "2D image operations: zoom, average (Figure 5), filter, pan"},
    {"reconstruct", cmd_reconstruct, "serial section images or traced contours -> aligned model"},
    {"view", cmd_view, "interactive viewer: turn, light, cut, slices, mosaic, edit (SDL2)"},
    {"mesh", cmd_mesh, "surface mesh (marching cubes or voxel faces) as STL, PLY, OBJ, OFF"},
    {"voxelize", cmd_voxelize, "triangle mesh (STL, OBJ, PLY, OFF) -> volume, solid or shell"},
    {"meshinfo", cmd_meshinfo, "mesh counts, volume, area, bounding box, watertightness"},
    {"contours", cmd_contours, "model slices across x, y or z -> contour stack (JSON or SVG)"},
};
#define NCOMMANDS (sizeof commands / sizeof commands[0])

static const cli_command *find(const char *name)
{
    for (size_t i = 0; i < NCOMMANDS; i++)
        if (!strcmp(commands[i].name, name)) return &commands[i];
    return NULL;
}

static void help(FILE *f)
{
    fputs("Usage: bvox COMMAND [options]\n"
          "\n"
          "Binary voxel models: read, measure, convert.\n"
          "\n"
          "Commands:\n",
          f);
    for (size_t i = 0; i < NCOMMANDS; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n"
               "Global options:\n"
               "  --help, -h     show this help ('bvox COMMAND --help' for a command)\n"
               "  --version      show the version and the SIMD level in use\n"
               "  --quiet        no warnings on stderr (errors are still printed)\n"
               "\n"
               "Formats: %s\n"
               "Exit status: 0 success, 1 failure, 2 wrong command line.\n",
            bvox_format_list());
}

/* Library warnings: one line each on stderr, "bvox: warning: ...". */
static void print_warning(const char *message, void *user)
{
    (void)user;
    fprintf(stderr, "bvox: warning: %s\n", message);
}

/* --quiet is global: accepted anywhere on the line, removed before the
 * command sees its arguments. Returns the new argc. */
static int take_quiet(int argc, char **argv, int *quiet)
{
    int n = 0;
    for (int i = 0; i < argc; i++) {
        if (i > 0 && !strcmp(argv[i], "--")) { /* operands from here on */
            while (i < argc) argv[n++] = argv[i++];
            break;
        }
        if (i > 0 && !strcmp(argv[i], "--quiet")) {
            *quiet = 1;
            continue;
        }
        argv[n++] = argv[i];
    }
    argv[n] = NULL;
    return n;
}

int cli_quiet;

static void version(void)
{
    bvox_simd level = bvox_simd_active();
    printf("bvox %s (simd: %s, threads: %d)\n", bvox_version(), bvox_simd_name(level),
           bvox_threads());
}

int main(int argc, char **argv)
{
    argc = take_quiet(argc, argv, &cli_quiet);
    if (!cli_quiet) bvox_set_warning_handler(print_warning, NULL);
    if (argc < 2) {
        help(stderr);
        return CLI_USAGE;
    }
    const char *name = argv[1];
    if (!strcmp(name, "--help") || !strcmp(name, "-h")) {
        help(stdout);
        return CLI_OK;
    }
    if (!strcmp(name, "--version") || !strcmp(name, "-V")) {
        version();
        return CLI_OK;
    }
    if (!strcmp(name, "help")) {
        if (argc < 3) {
            help(stdout);
            return CLI_OK;
        }
        const cli_command *c = find(argv[2]);
        if (!c) return cli_usage_error(NULL, "unknown command '%s'", argv[2]);
        char *sub[] = {argv[2], "--help", NULL};
        return c->run(2, sub);
    }
    const cli_command *c = find(name);
    if (!c) {
        if (name[0] == '-') return cli_usage_error(NULL, "unknown option '%s'", name);
        return cli_usage_error(NULL, "unknown command '%s'", name);
    }
    int rc = c->run(argc - 1, argv + 1);
    /* A full disk or closed pipe on stdout is a failure too. */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        if (rc == CLI_OK) fprintf(stderr, "bvox: error writing the output\n");
        return rc == CLI_OK ? CLI_FAIL : rc;
    }
    return rc;
}
