/*
 * cmd_contours.c — `bvox contours MODEL [--axis x|y|z] -o OUT.json|DIR`: the
 * outlines of the model's slices across an axis (bvox_volume_to_contours),
 * written as the JSON contour stack (OUT.json) or as one SVG per slice in a
 * folder (any other name). Both are written atomically.
 */
#include "args.h"
#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

static void help(FILE *f)
{
    fputs("Usage: bvox contours MODEL [--axis x|y|z] -o OUT.json|DIR\n"
          "\n"
          "Trace the outlines of the 1-voxels of every slice of MODEL across an axis\n"
          "(outer contours and holes, on pixel edges) and write them as a contour\n"
          "stack: a JSON file when OUT ends in .json, else a folder of SVG files\n"
          "(section_0001.svg, ...). Reading the stack back with `bvox reconstruct`\n"
          "gives the same voxels again. Slices across x are (y, z) images, across y\n"
          "(x, z), across z (x, y); their pixels must be square.\n"
          "\n"
          "Options:\n"
          "  --axis x|y|z          the axis the slices are across (default z)\n"
          "  -o, --output OUT      OUT.json, or a folder for SVG files\n"
          CLI_FORCE_HELP
          "  --help                show this help\n",
          f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox contours model.nii.gz -o model-contours.json\n"
          "  bvox contours model.nii.gz --axis x -o sagittal/\n",
          f);
}

static int ends_with_json(const char *s)
{
    size_t n = strlen(s);
    return n >= 5 && strcasecmp(s + n - 5, ".json") == 0;
}

int cmd_contours(int argc, char **argv)
{
    const char *cmd = "contours", *in = NULL, *out = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, axis = 2;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--axis", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (!strcmp(v, "x")) axis = 0;
            else if (!strcmp(v, "y")) axis = 1;
            else if (!strcmp(v, "z")) axis = 2;
            else return cli_usage_error(cmd, "--axis: '%s' is not x, y or z", v);
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "missing the input model MODEL");
    if (!out) return cli_usage_error(cmd, "missing -o OUT.json|DIR");
    if (wo.format) return cli_usage_error(cmd, "--output-format does not apply: OUT.json or a folder");

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_contour_stack *stack = NULL;
    int rc = CLI_OK;
    if (bvox_volume_to_contours(vol, axis, &stack)) {
        rc = cli_fail();
    } else {
        bvox_status st = ends_with_json(out) ? bvox_stack_write_json(out, stack)
                                             : bvox_stack_write_svg_dir_opts(out, stack, &wo);
        if (st) {
            rc = cli_fail();
        } else {
            int64_t nc = 0, np = 0;
            for (int32_t s = 0; s < stack->nsections; s++) {
                nc += stack->sections[s].ncontours;
                for (int32_t c = 0; c < stack->sections[s].ncontours; c++)
                    np += stack->sections[s].contours[c].npoints;
            }
            printf("contours: %d slices across %c, %lld contours, %lld points -> %s\n",
                   (int)stack->nsections, "xyz"[axis], (long long)nc, (long long)np, out);
        }
    }
    bvox_stack_destroy(stack);
    bvox_volume_destroy(vol);
    return rc;
}
