/*
 * cmd_contours.c — `bvox contours MODEL [--axis x|y|z] -o OUT.json|DIR`: the
 * outlines of the model's slices across an axis (bvox_volume_to_contours),
 * written as the JSON contour stack (OUT.json) or as one SVG per slice in a
 * folder (any other name). Both are written atomically.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"
#include "common/names.h"

#include <stdio.h>
#include <string.h>

typedef struct contours_args {
    const char *in, *out, *output_format;
    int axis, force, json;
    cli_read_args ra;
} contours_args;

#define A(member) CLI_AT(contours_args, member)

static const char *const axes[] = {"x", "y", "z", NULL};

static const cli_opt contours_opts[] = {
    {"--axis", 0, CLI_CHOICE, NULL, "the axis the slices are across", A(axis), .def = "z",
     .choices = axes},
    {"--output", 'o', CLI_PATH, "OUT", "OUT.json, or a folder for SVG files", A(out)},
    /* refused below: kept so that the message says why */
    {"--output-format", 0, CLI_STR, "NAME", "not used: OUT.json or a folder says the format",
     A(output_format)},
    {"--force", 0, CLI_FLAG, NULL, CLI_FORCE_HELP, A(force)},
    {"--json", 0, CLI_FLAG, NULL,
     "print one JSON object instead of the summary line: file, format, input, output, axis, "
     "slices, contours, points",
     A(json)},
    {NULL},
};
static const cli_group contours_group = {"Options", contours_opts, NULL};
static const cli_pos contours_pos[] = {
    {"MODEL", "the volume to trace", A(in)},
    {NULL},
};

const cli_spec cli_spec_contours = {
    .name = "contours",
    .summary = "model slices across x, y or z -> contour stack (JSON or SVG)",
    .usage = "MODEL [--axis x|y|z] -o OUT.json|DIR",
    .about = "Trace the outlines of the 1-voxels of every slice of MODEL across an axis\n"
             "(outer contours and holes, on pixel edges) and write them as a contour\n"
             "stack: a JSON file when OUT ends in .json, else a folder of SVG files\n"
             "(section_0001.svg, ...). Reading the stack back with `bvox reconstruct`\n"
             "gives the same voxels again. Slices across x are (y, z) images, across y\n"
             "(x, z), across z (x, y); their pixels must be square.\n",
    .pos = contours_pos,
    .uses = {{&contours_group, 0}, CLI_USE_READ(contours_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox contours model.nii.gz -o model-contours.json\n"
                "  bvox contours model.nii.gz --axis x -o sagittal/\n",
};

int cmd_contours(int argc, char **argv)
{
    const char *cmd = "contours";
    contours_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_contours, argc, argv, &a);
    const char *in = a.in, *out = a.out;
    int axis = a.axis;
    if (!in) return cli_usage_error(cmd, "missing the input model MODEL");
    if (!out) return cli_usage_error(cmd, "missing -o OUT.json|DIR");
    if (a.output_format) return cli_usage_error(cmd, "--output-format does not apply: OUT.json or a folder");

    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.force = a.force;
    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    bvox_contour_stack *stack = NULL;
    int rc = CLI_OK;
    if (bvox_volume_to_contours(vol, axis, &stack)) {
        rc = cli_fail();
    } else {
        bvox_status st = bvox__ends_with_ci(out, ".json") ? bvox_stack_write_json(out, stack)
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
            if (a.json) {
                cli_json j;
                cli_json_init(&j, stdout);
                cli_json_begin_object(&j);
                cli_json_key(&j, "file");
                cli_json_string(&j, out);
                cli_json_key(&j, "format");
                cli_json_string(&j, bvox__ends_with_ci(out, ".json") ? "json" : "svg");
                cli_json_io(&j, in, out);
                cli_json_key(&j, "axis");
                cli_json_string(&j, (const char[]){"xyz"[axis], 0});
                cli_json_key(&j, "slices");
                cli_json_int(&j, stack->nsections);
                cli_json_key(&j, "contours");
                cli_json_int(&j, nc);
                cli_json_key(&j, "points");
                cli_json_int(&j, np);
                cli_json_end_object(&j);
                fputc('\n', stdout);
            } else {
                printf("contours: %d slices across %c, %lld contours, %lld points -> %s\n",
                       (int)stack->nsections, "xyz"[axis], (long long)nc, (long long)np, out);
            }
        }
    }
    bvox_stack_destroy(stack);
    bvox_volume_destroy(vol);
    return rc;
}
