/*
 * cmd_reconstruct.c — `bvox reconstruct SECTIONS... -o MODEL`: serial
 * section images (or one contour stack file) to an aligned binary model,
 * one call of bvox_reconstruct. Progress and fallback warnings on stderr;
 * --save-contours writes the aligned stack (JSON file or SVG folder),
 * --report the per-section markers, transforms, residuals, fallbacks and
 * the time of each step as JSON (temporary file renamed on success).
 */
#include "args.h"
#include "cli.h"
#include "common/names.h"
#include "json.h"
#include "opts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct recon_args {
    cli_list inputs;
    const char *out, *save, *report_path;
    int quiet, thr_given, otsu_given, pol_given, markers_given, bg_given;
    bvox_recon_opts o;
    bvox_write_opts wo;
} recon_args;

#define A(member) CLI_AT(recon_args, member)
#define WHOLE .offset = 0, .size = sizeof(recon_args)

/* The takers that count what was given, for the exclusions checked after
 * parsing, or that check more than a bound. */
static int take_background(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    recon_args *a = target;
    if (v) a->o.background = v;
    else a->o.estimate_background = 0; /* --no-background */
    a->bg_given++;
    return CLI_OPT_OK;
}

static int take_threshold(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    recon_args *a = target;
    double d;
    if (cli_parse_double(v, &d) || d < 0) return CLI_OPT_BAD;
    a->o.threshold = d;
    a->thr_given = 1;
    return CLI_OPT_OK;
}

static int take_polarity(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    recon_args *a = target;
    int dark = !strcmp(o->name, "--dark");
    if (a->pol_given && a->o.dark != dark) {
        cli_usage_error(cmd, "--dark and --bright exclude each other");
        return CLI_OPT_FAILED;
    }
    a->o.dark = dark;
    a->pol_given = 1;
    return CLI_OPT_OK;
}

static int take_markers(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    recon_args *a = target;
    int64_t k;
    if (!strcmp(o->name, "--markers-file")) {
        a->o.markers_file = v;
    } else {
        if (!strcmp(v, "auto")) k = BVOX_MARKERS_AUTO;
        else if (cli_parse_int64(v, 2, 16, &k)) return CLI_OPT_BAD;
        a->o.markers.count = (int32_t)k;
    }
    a->markers_given++;
    return CLI_OPT_OK;
}

static int take_marker_radius(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    bvox_marker_opts *m = target;
    char buf[64], *comma;
    double lo, hi;
    if (strlen(v) >= sizeof buf || !strchr(v, ',')) {
        cli_usage_error(cmd, "--marker-radius: '%s' is not MIN,MAX", v);
        return CLI_OPT_FAILED;
    }
    strcpy(buf, v);
    comma = strchr(buf, ',');
    *comma = '\0';
    if (cli_parse_double(buf, &lo) || cli_parse_double(comma + 1, &hi) || lo <= 0 || hi < lo)
        return CLI_OPT_BAD;
    m->min_radius = lo;
    m->max_radius = hi;
    return CLI_OPT_OK;
}

static int take_reference(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int64_t k;
    if (cli_parse_int64(v, 1, INT32_MAX, &k)) return CLI_OPT_BAD;
    *(int32_t *)target = (int32_t)(k - 1); /* 1-based on the command line */
    return CLI_OPT_OK;
}

static int take_unit(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    char *unit = target;
    if (strlen(v) >= sizeof ((bvox_recon_opts *)0)->unit) return CLI_OPT_BAD;
    strcpy(unit, v);
    return CLI_OPT_OK;
}

static int take_quiet(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    *(int *)target = 1;
    bvox_set_warning_handler(NULL, NULL);
    return CLI_OPT_OK;
}

static const cli_opt recon_opts[] = {
    {"--output", 'o', CLI_PATH, "MODEL",
     "the model (format by extension: .nii, .nii.gz, .tif, ...)", A(out)},
    {"--background", 0, CLI_PATH, "BG.png",
     "a blank section image subtracted from every section (default: a smooth background "
     "estimated per section)",
     WHOLE, .fn = take_background},
    {"--no-background", 0, CLI_FLAG, NULL, "neither", WHOLE, .fn = take_background},
    {"--threshold", 0, CLI_DOUBLE, "T", "fixed gray threshold (default: --otsu, per section)",
     WHOLE, .fn = take_threshold, .bad = "--threshold: '%s' is not a gray level >= 0"},
    {"--otsu", 0, CLI_FLAG, NULL, "Otsu's threshold per section", A(otsu_given)},
    {"--dark", 0, CLI_FLAG, NULL, "the object is darker than the background (default)", WHOLE,
     .fn = take_polarity},
    {"--bright", 0, CLI_FLAG, NULL, "the object is brighter than the background", WHOLE,
     .fn = take_polarity},
    {"--smooth", 0, CLI_INT, "R", "median filter radius in pixels (default 1; 0: none)",
     A(o.smooth), .lo = 0, .hi = 1000, .bad = "--smooth: '%s' is not a radius 0..1000"},
    {"--min-area", 0, CLI_INT, "A", "remove specks and fill holes below A pixels (default 16)",
     A(o.min_area), .lo = 0, .hi = INT64_MAX / 2, .bad = "--min-area: '%s' is not a pixel count"},
    {"--markers", 0, CLI_INT, "N",
     "find N reference markers (small dark round blobs) per section and align by them; N = "
     "auto: count them",
     WHOLE, .fn = take_markers, .bad = "--markers: '%s' is not a count 2..16 or auto"},
    {"--marker-coords", 0, CLI_PATH, "F",
     "put the model in a known frame: F (contour JSON) gives in its first section where the "
     "reference section's markers belong (pixels)",
     A(o.marker_coords)},
    {"--markers-file", 0, CLI_PATH, "F",
     "take the markers from a contour stack file (JSON): its section i holds the markers of "
     "section i",
     WHOLE, .fn = take_markers},
    {"--marker-radius", 0, CLI_STR, "MIN,MAX",
     "marker radius range in pixels (default 1.5 to image size / 16)", A(o.markers),
     .fn = take_marker_radius, .bad = "--marker-radius: '%s' is not MIN,MAX with 0 < MIN <= MAX"},
    {"--allow-scale", 0, CLI_FLAG, NULL, "fit a uniform scale too (shrinkage)",
     A(o.markers.allow_scale)},
    {"--reference", 0, CLI_INT, "K", "align onto section K (1-based; default: the middle one)",
     A(o.reference), .fn = take_reference, .bad = "--reference: '%s' is not a section number"},
    {"--no-align", 0, CLI_FLAG, NULL, "do not align", A(o.align), .flags = CLI_NEGATE},
    {"--pixel", 0, CLI_DOUBLE, "P", "pixel size (default 1, or the contour file's)", A(o.pixel),
     .flags = CLI_MIN_OPEN, .min = 0, .bad = "--pixel: '%s' is not a size > 0"},
    {"--spacing", 0, CLI_DOUBLE, "S", "distance between sections (default 1, or the file's)",
     A(o.spacing), .flags = CLI_MIN_OPEN, .min = 0,
     .bad = "--spacing: '%s' is not a distance > 0"},
    {"--unit", 0, CLI_STR, "U", "unit of P and S, e.g. um", A(o.unit), .fn = take_unit,
     .bad = "--unit: '%s' is too long"},
    {"--z-spacing", 0, CLI_DOUBLE, "Z", "output slice spacing (default: P, isotropic voxels)",
     A(o.z_spacing), .flags = CLI_MIN_OPEN, .min = 0,
     .bad = "--z-spacing: '%s' is not a distance > 0"},
    {"--no-interpolate", 0, CLI_FLAG, NULL, "copy the nearest section instead of interpolating",
     A(o.interpolate), .flags = CLI_NEGATE},
    {"--simplify", 0, CLI_DOUBLE, "TOL", "simplify traced contours to TOL pixels (default: exact)",
     A(o.simplify), .flags = CLI_MIN, .min = 0,
     .bad = "--simplify: '%s' is not a tolerance >= 0"},
    {"--smooth-contours", 0, CLI_INT, "N", "moving average over 2N+1 contour points (area kept)",
     A(o.contour_smooth), .lo = 0, .hi = 1000,
     .bad = "--smooth-contours: '%s' is not a radius 0..1000"},
    {"--svg-select", 0, CLI_STR, "SEL",
     "SVG sections: read only elements named by SEL, a list of id:NAME, class:NAME, "
     "layer:NAME or NAME (default: every visible outline; a full-canvas background is "
     "skipped)",
     A(o.svg_select)},
    {"--object", 0, CLI_STR, "NAME",
     "a PyReconstruct .jser series: only the traces of object NAME (default: every object)",
     A(o.object)},
    {"--strict", 0, CLI_FLAG, NULL,
     "refuse a contour that crosses itself (default: fill it even-odd and warn)", A(o.strict)},
    {"--save-contours", 0, CLI_PATH, "OUT",
     "the aligned contours: OUT.json, or a folder of SVG files", A(save)},
    {"--report", 0, CLI_PATH, "REPORT.json",
     "per section: markers, transform, residual, fallback; the time of each step",
     A(report_path)},
    {"--save-steps", 0, CLI_PATH, "DIR",
     "each section's steps as PNG files in the folder DIR (created): NAME.1_flat.png "
     "(background corrected), NAME.2_threshold.png, NAME.3_smooth.png, NAME.4_final.png",
     A(o.save_steps), .flags = CLI_DIR},
    /* --quiet itself is the global one (main.c takes it out of the line); -q
     * is this command's, kept from before --quiet was global */
    {"--quiet", 'q', CLI_FLAG, NULL, "no progress and no warnings on stderr", A(quiet),
     .fn = take_quiet},
    {"--output-format", 0, CLI_STR, "NAME", "force the model's format ({formats})", A(wo.format)},
    {"--force", 0, CLI_FLAG, NULL, CLI_FORCE_HELP, A(wo.force)},
    {NULL},
};
static const cli_group recon_group = {"Options", recon_opts, NULL};
static const cli_pos recon_pos[] = {
    {"SECTIONS...", "section images, a folder of them, or one contour file", A(inputs),
     .many = 1},
    {NULL},
};

const cli_spec cli_spec_reconstruct = {
    .name = "reconstruct",
    .summary = "serial section images or traced contours -> aligned model",
    .usage = "SECTIONS... -o MODEL [options]",
    .about = "Reconstruct a binary model from serial sections. SECTIONS: section images\n"
             "(8/16-bit gray or RGB PNG or TIFF, all the same size) in stack order, or one\n"
             "folder of them (natural order: s2.png before s10.png), or one contour file (.json,\n"
             "a folder of .svg, a Reconstruct .ser series), whose markers align it.\n"
             "Per image: background correction, threshold, median smoothing, markers\n"
             "(found and removed from the object), specks, contours (holes kept); then the\n"
             "sections are aligned by their markers onto the middle one (chained\n"
             "neighbour to neighbour) and the aligned contours become the model, with\n"
             "shape-based interpolation between sections to isotropic voxels.\n",
    .pos = recon_pos,
    .uses = {{&recon_group, 0}, CLI_USE_PROCESS},
    .notes = "A section whose markers are not found or do not match keeps its neighbour's\n"
             "transform (a warning names it; the report marks it \"fallback\").\n",
    .examples = "  bvox reconstruct sections/ --markers 3 --pixel 0.5 --spacing 2 --unit um -o model.nii.gz\n"
                "  bvox reconstruct s*.png --background blank.png --bright --no-align -o m.nii\n"
                "  bvox reconstruct traced.json -o model.nii --report report.json\n",
};

typedef struct progress_state {
    int tty;
    int last_step, last_tenth;
} progress_state;

/* On a terminal one line rewritten in place; elsewhere (a log) a line per
 * tenth of the sections and one per later step. */
static void on_progress(void *ctx, bvox_recon_step step, int32_t done, int32_t total)
{
    progress_state *p = ctx;
    const char *what = step == BVOX_RECON_CONTOURS ? "sections" : bvox_recon_step_name(step);
    int tenth = total > 0 ? (int)((int64_t)done * 10 / total) : 10;
    if (p->tty) {
        fprintf(stderr, "\rbvox: reconstruct: %s %d/%d%s", what, (int)done, (int)total,
                done == total ? "\n" : "");
    } else if (p->last_step != (int)step && (tenth > p->last_tenth || done == total)) {
        fprintf(stderr, "bvox: reconstruct: %s %d/%d\n", what, (int)done, (int)total);
    }
    p->last_tenth = done == total ? -1 : tenth;
    if (done == total) p->last_step = (int)step;
    fflush(stderr);
}

static void json_transform(cli_json *j, const char *key, const bvox_sim2 *t)
{
    cli_json_key(j, key);
    cli_json_begin_object(j);
    cli_json_key(j, "angle_deg");
    cli_json_double(j, t->angle * 180 / M_PI);
    cli_json_key(j, "scale");
    cli_json_double(j, t->scale);
    cli_json_key(j, "tx");
    cli_json_double(j, t->tx);
    cli_json_key(j, "ty");
    cli_json_double(j, t->ty);
    cli_json_end_object(j);
}

static void write_report_json(FILE *f, const bvox_recon_report *r, const bvox_volume *vol)
{
    cli_json j;
    cli_json_init(&j, f);
    cli_json_begin_object(&j);
    cli_json_key(&j, "sections");
    cli_json_int(&j, r->nsections);
    cli_json_key(&j, "width");
    cli_json_int(&j, r->width);
    cli_json_key(&j, "height");
    cli_json_int(&j, r->height);
    cli_json_key(&j, "aligned");
    cli_json_bool(&j, r->aligned);
    cli_json_key(&j, "reference");
    if (r->aligned) cli_json_int(&j, r->reference + 1);
    else cli_json_null(&j);
    cli_json_key(&j, "fallbacks");
    cli_json_int(&j, r->fallbacks);
    cli_json_key(&j, "timings_ms");
    cli_json_begin_object(&j);
    for (int s = 0; s < BVOX_RECON_NSTEPS; s++) {
        cli_json_key(&j, bvox_recon_step_name((bvox_recon_step)s));
        cli_json_double(&j, round(r->ms[s] * 1000) / 1000);
    }
    cli_json_end_object(&j);
    if (vol) {
        bvox_dims d = bvox_volume_dims(vol);
        const bvox_geometry *g = bvox_volume_geometry(vol);
        cli_json_key(&j, "model");
        cli_json_begin_object(&j);
        int64_t dims[3] = {d.nx, d.ny, d.nz};
        cli_json_key(&j, "dims");
        cli_json_int_array(&j, dims, 3);
        cli_json_key(&j, "spacing");
        cli_json_double_array(&j, g->spacing, 3);
        cli_json_key(&j, "unit");
        cli_json_string(&j, g->unit);
        cli_json_key(&j, "count");
        cli_json_int(&j, bvox_volume_count(vol));
        cli_json_end_object(&j);
    }
    cli_json_key(&j, "per_section");
    cli_json_begin_array(&j);
    for (int32_t i = 0; i < r->nsections; i++) {
        const bvox_recon_section_report *s = &r->sections[i];
        cli_json_begin_object(&j);
        cli_json_key(&j, "index");
        cli_json_int(&j, i + 1);
        cli_json_key(&j, "name");
        cli_json_string(&j, s->name);
        cli_json_key(&j, "threshold");
        cli_json_double(&j, s->threshold); /* NaN (contour input) becomes null */
        cli_json_key(&j, "area");
        cli_json_int(&j, s->area);
        cli_json_key(&j, "contours");
        cli_json_int(&j, s->ncontours);
        cli_json_key(&j, "markers_found");
        cli_json_int(&j, s->nmarkers);
        cli_json_key(&j, "markers");
        cli_json_begin_array(&j);
        for (int32_t k = 0; k < s->nmarkers; k++) {
            double xy[2] = {s->markers[k].x, s->markers[k].y};
            cli_json_double_array(&j, xy, 2);
        }
        cli_json_end_array(&j);
        cli_json_key(&j, "matched");
        cli_json_int(&j, s->align.matched);
        cli_json_key(&j, "neighbour");
        if (s->align.neighbour >= 0) cli_json_int(&j, s->align.neighbour + 1);
        else cli_json_null(&j);
        json_transform(&j, "transform", &s->align.transform);
        json_transform(&j, "step", &s->align.step);
        cli_json_key(&j, "residual");
        cli_json_double(&j, s->align.residual);
        cli_json_key(&j, "fallback");
        cli_json_bool(&j, s->align.fallback);
        cli_json_key(&j, "message");
        cli_json_string(&j, s->message[0] ? s->message : NULL);
        cli_json_end_object(&j);
    }
    cli_json_end_array(&j);
    cli_json_end_object(&j);
    fputc('\n', f);
}

/* The report is built in memory and written atomically by the library (a
 * temporary file in the target folder, synced, renamed). */
static int save_report(const char *path, const bvox_recon_report *r, const bvox_volume *vol)
{
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    if (!f) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    write_report_json(f, r, vol);
    int bad = fclose(f) != 0;
    bvox_status st = bad ? BVOX_ENOMEM : bvox_write_file_atomic(path, text, size);
    free(text);
    if (bad) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    return st ? cli_fail() : CLI_OK;
}

int cmd_reconstruct(int argc, char **argv)
{
    const char *cmd = "reconstruct";
    recon_args a = {.o = bvox_recon_opts_default(), .wo = BVOX_WRITE_OPTS_INIT};
    a.inputs.items = calloc((size_t)argc + 1, sizeof *a.inputs.items);
    if (!a.inputs.items) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    const char **inputs = a.inputs.items;
#define USAGE(...) do { free(inputs); return cli_usage_error(cmd, __VA_ARGS__); } while (0)
    int r = cli_parse(&cli_spec_reconstruct, argc, argv, &a);
    if (r != CLI_PARSED) {
        free(inputs);
        return r == CLI_PARSE_HELP ? CLI_OK : CLI_USAGE;
    }
    const char *out = a.out, *save = a.save, *report_path = a.report_path;
    bvox_recon_opts o = a.o;
    int32_t nin = a.inputs.n;
    if (nin == 0) USAGE("needs SECTIONS (image files, a folder or a contour file)");
    if (!out && !save && !report_path) USAGE("needs -o MODEL (or --save-contours / --report)");
    if (a.thr_given && a.otsu_given) USAGE("--threshold and --otsu exclude each other");
    if (a.markers_given > 1) USAGE("--markers and --markers-file exclude each other");
    if (a.bg_given > 1) USAGE("--background and --no-background exclude each other");
    int quiet = a.quiet || cli_quiet;
    progress_state ps = {isatty(2), -1, 0};
    if (!quiet) {
        o.progress = on_progress;
        o.progress_ctx = &ps;
    }
#undef USAGE
    bvox_volume *vol = NULL;
    bvox_contour_stack *stack = NULL;
    bvox_recon_report *rep = NULL;
    if (o.save_steps) {
        int err = cli_make_dirs(o.save_steps);
        if (err) {
            fprintf(stderr, "bvox: %s: cannot create the folder: %s\n", o.save_steps, strerror(err));
            free(inputs);
            return CLI_FAIL;
        }
    }
    bvox_status st = bvox_reconstruct(inputs, nin, &o, out ? &vol : NULL, save ? &stack : NULL, &rep);
    free(inputs);
    if (st) return cli_fail();
    int rc = CLI_OK;
    for (int32_t i = 0; i < rep->nsections && !quiet; i++)
        if (rep->sections[i].message[0])
            fprintf(stderr, "bvox: warning: %s\n", rep->sections[i].message);
    if (out && bvox_write(out, vol, &a.wo)) rc = cli_fail();
    if (!rc && save) {
        st = bvox__ends_with_ci(save, ".json") ? bvox_stack_write_json(save, stack)
                                      : bvox_stack_write_svg_dir_opts(save, stack, &a.wo);
        if (st) rc = cli_fail();
    }
    if (!rc && report_path) rc = save_report(report_path, rep, vol);
    if (!rc && !quiet && vol) {
        bvox_dims d = bvox_volume_dims(vol);
        const bvox_geometry *g = bvox_volume_geometry(vol);
        fprintf(stderr, "bvox: reconstruct: %d sections -> %d x %d x %d voxels of %g x %g x %g%s%s, "
                        "%d fallback%s, %.0f ms\n",
                (int)rep->nsections, (int)d.nx, (int)d.ny, (int)d.nz, g->spacing[0], g->spacing[1],
                g->spacing[2], g->unit[0] ? " " : "", g->unit, (int)rep->fallbacks,
                rep->fallbacks == 1 ? "" : "s", rep->ms[BVOX_RECON_TOTAL]);
    }
    bvox_volume_destroy(vol);
    bvox_stack_destroy(stack);
    bvox_recon_report_destroy(rep);
    return rc;
}
