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
#include "json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

static void help(FILE *f)
{
    fputs("Usage: bvox reconstruct SECTIONS... -o MODEL [options]\n"
          "\n"
          "Reconstruct a binary model from serial sections. SECTIONS: section images\n"
          "(8/16-bit gray or RGB PNG or TIFF, all the same size) in stack order, or one\n"
          "folder of them (natural order: s2.png before s10.png), or one contour file (.json,\n"
          "a folder of .svg, a Reconstruct .ser series), whose markers align it.\n"
          "Per image: background correction, threshold, median smoothing, markers\n"
          "(found and removed from the object), specks, contours (holes kept); then the\n"
          "sections are aligned by their markers onto the middle one (chained\n"
          "neighbour to neighbour) and the aligned contours become the model, with\n"
          "shape-based interpolation between sections to isotropic voxels.\n"
          "\n"
          "Options:\n"
          "  -o, --output MODEL     the model (format by extension: .nii, .nii.gz, .tif, ...)\n"
          "  --background BG.png    a blank section image subtracted from every section\n"
          "                         (default: a smooth background estimated per section)\n"
          "  --no-background        neither\n"
          "  --threshold T          fixed gray threshold (default: --otsu, per section)\n"
          "  --otsu                 Otsu's threshold per section\n"
          "  --dark, --bright       the object is darker (default) or brighter than the\n"
          "                         background\n"
          "  --smooth R             median filter radius in pixels (default 1; 0: none)\n"
          "  --min-area A           remove specks and fill holes below A pixels (default 16)\n"
          "  --markers N            find N reference markers (small dark round blobs) per\n"
          "                         section and align by them; N = auto: count them\n"
          "  --marker-coords F      put the model in a known frame: F (contour JSON) gives in\n"
          "                         its first section where the reference section's markers\n"
          "                         belong (pixels)\n"
          "  --markers-file F       take the markers from a contour stack file (JSON):\n"
          "                         its section i holds the markers of section i\n"
          "  --marker-radius MIN,MAX  marker radius range in pixels (default 1.5 to\n"
          "                         image size / 16)\n"
          "  --allow-scale          fit a uniform scale too (shrinkage)\n"
          "  --reference K          align onto section K (1-based; default: the middle one)\n"
          "  --no-align             do not align\n"
          "  --pixel P              pixel size (default 1, or the contour file's)\n"
          "  --spacing S            distance between sections (default 1, or the file's)\n"
          "  --unit U               unit of P and S, e.g. um\n"
          "  --z-spacing Z          output slice spacing (default: P, isotropic voxels)\n"
          "  --no-interpolate       copy the nearest section instead of interpolating\n"
          "  --simplify TOL         simplify traced contours to TOL pixels (default: exact)\n"
          "  --smooth-contours N    moving average over 2N+1 contour points (area kept)\n"
          "  --svg-select SEL       SVG sections: read only elements named by SEL, a list of\n"
          "                         id:NAME, class:NAME, layer:NAME or NAME (default: every\n"
          "                         visible outline; a full-canvas background is skipped)\n"
          "  --strict               refuse a contour that crosses itself (default: fill it\n"
          "                         even-odd and warn)\n"
          "  --save-contours OUT    the aligned contours: OUT.json, or a folder of SVG files\n"
          "  --report REPORT.json   per section: markers, transform, residual, fallback;\n"
          "                         the time of each step\n"
          "  --save-steps DIR       each section's steps as PNG files in the folder DIR\n"
          "                         (created): NAME.1_flat.png (background corrected),\n"
          "                         NAME.2_threshold.png, NAME.3_smooth.png, NAME.4_final.png\n"
          "  --quiet, -q            no progress and no warnings on stderr\n"
          "  --output-format NAME   force the model's format\n"
          "  --help                 show this help\n",
          f);
    cli_print_process_options_help(f);
    fputs("\nA section whose markers are not found or do not match keeps its neighbour's\n"
          "transform (a warning names it; the report marks it \"fallback\").\n"
          "\nExamples:\n"
          "  bvox reconstruct sections/ --markers 3 --pixel 0.5 --spacing 2 --unit um -o model.nii.gz\n"
          "  bvox reconstruct s*.png --background blank.png --bright --no-align -o m.nii\n"
          "  bvox reconstruct traced.json -o model.nii --report report.json\n",
          f);
}

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

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && !strcasecmp(s + n - m, suffix);
}

int cmd_reconstruct(int argc, char **argv)
{
    const char *cmd = "reconstruct", *v = NULL, *out = NULL, *save = NULL, *report_path = NULL;
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    bvox_recon_opts o = bvox_recon_opts_default();
    int r, options_done = 0, quiet = 0, thr_given = 0, otsu_given = 0, pol_given = 0;
    int markers_given = 0, bg_given = 0;
    const char **inputs = calloc((size_t)argc + 1, sizeof *inputs);
    int32_t nin = 0;
    if (!inputs) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
#define USAGE(...) do { free(inputs); return cli_usage_error(cmd, __VA_ARGS__); } while (0)
#define VALUE(name) ((r = cli_match_value(cmd, argc, argv, &i, name, &v)) != CLI_ARG_NOT_MINE)
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        double d;
        int64_t k;
        if (options_done || !cli_is_option(arg)) {
            inputs[nin++] = arg;
        } else if (!strcmp(arg, "--")) {
            options_done = 1;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            free(inputs);
            return CLI_OK;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) {
                free(inputs);
                return CLI_USAGE;
            }
        } else if (VALUE("--background")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            o.background = v;
            bg_given++;
        } else if (!strcmp(arg, "--no-background")) {
            o.estimate_background = 0;
            bg_given++;
        } else if (VALUE("--threshold")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_double(v, &d) || d < 0) USAGE("--threshold: '%s' is not a gray level >= 0", v);
            o.threshold = d;
            thr_given = 1;
        } else if (!strcmp(arg, "--otsu")) {
            otsu_given = 1;
        } else if (!strcmp(arg, "--dark") || !strcmp(arg, "--bright")) {
            if (pol_given && o.dark != !strcmp(arg, "--dark")) USAGE("--dark and --bright exclude each other");
            o.dark = !strcmp(arg, "--dark");
            pol_given = 1;
        } else if (VALUE("--smooth")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_int64(v, 0, 1000, &k)) USAGE("--smooth: '%s' is not a radius 0..1000", v);
            o.smooth = (int32_t)k;
        } else if (VALUE("--min-area")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_int64(v, 0, INT64_MAX / 2, &k)) USAGE("--min-area: '%s' is not a pixel count", v);
            o.min_area = k;
        } else if (VALUE("--markers")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (!strcmp(v, "auto")) k = BVOX_MARKERS_AUTO;
            else if (cli_parse_int64(v, 2, 16, &k))
                USAGE("--markers: '%s' is not a count 2..16 or auto", v);
            o.markers.count = (int32_t)k;
            markers_given++;
        } else if (VALUE("--marker-coords")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            o.marker_coords = v;
        } else if (VALUE("--markers-file")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            o.markers_file = v;
            markers_given++;
        } else if (VALUE("--marker-radius")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            char buf[64], *comma;
            double lo, hi;
            if (strlen(v) >= sizeof buf) USAGE("--marker-radius: '%s' is not MIN,MAX", v);
            strcpy(buf, v);
            comma = strchr(buf, ',');
            if (!comma) USAGE("--marker-radius: '%s' is not MIN,MAX", v);
            *comma = '\0';
            if (cli_parse_double(buf, &lo) || cli_parse_double(comma + 1, &hi) || lo <= 0 || hi < lo)
                USAGE("--marker-radius: '%s' is not MIN,MAX with 0 < MIN <= MAX", v);
            o.markers.min_radius = lo;
            o.markers.max_radius = hi;
        } else if (!strcmp(arg, "--allow-scale")) {
            o.markers.allow_scale = 1;
        } else if (VALUE("--reference")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_int64(v, 1, INT32_MAX, &k)) USAGE("--reference: '%s' is not a section number", v);
            o.reference = (int32_t)(k - 1);
        } else if (!strcmp(arg, "--no-align")) {
            o.align = 0;
        } else if (VALUE("--pixel")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_double(v, &d) || !(d > 0)) USAGE("--pixel: '%s' is not a size > 0", v);
            o.pixel = d;
        } else if (VALUE("--spacing")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_double(v, &d) || !(d > 0)) USAGE("--spacing: '%s' is not a distance > 0", v);
            o.spacing = d;
        } else if (VALUE("--unit")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (strlen(v) >= sizeof o.unit) USAGE("--unit: '%s' is too long", v);
            strcpy(o.unit, v);
        } else if (VALUE("--z-spacing")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_double(v, &d) || !(d > 0)) USAGE("--z-spacing: '%s' is not a distance > 0", v);
            o.z_spacing = d;
        } else if (!strcmp(arg, "--no-interpolate")) {
            o.interpolate = 0;
        } else if (VALUE("--simplify")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_double(v, &d) || d < 0) USAGE("--simplify: '%s' is not a tolerance >= 0", v);
            o.simplify = d;
        } else if (VALUE("--smooth-contours")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            if (cli_parse_int64(v, 0, 1000, &k)) USAGE("--smooth-contours: '%s' is not a radius 0..1000", v);
            o.contour_smooth = (int32_t)k;
        } else if (VALUE("--save-contours")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            save = v;
        } else if (VALUE("--svg-select")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            o.svg_select = v;
        } else if (!strcmp(arg, "--strict")) {
            o.strict = 1;
        } else if (VALUE("--save-steps")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            o.save_steps = v;
        } else if (VALUE("--report")) {
            if (r == CLI_ARG_BAD) goto bad_value;
            report_path = v;
        } else if (!strcmp(arg, "-q")) {
            quiet = 1;
            bvox_set_warning_handler(NULL, NULL);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, NULL) == CLI_ARG_BAD) {
            free(inputs);
            return CLI_USAGE;
        }
    }
#undef VALUE
    if (nin == 0) USAGE("needs SECTIONS (image files, a folder or a contour file)");
    if (!out && !save && !report_path) USAGE("needs -o MODEL (or --save-contours / --report)");
    if (thr_given && otsu_given) USAGE("--threshold and --otsu exclude each other");
    if (markers_given > 1) USAGE("--markers and --markers-file exclude each other");
    if (bg_given > 1) USAGE("--background and --no-background exclude each other");
    if (cli_quiet) quiet = 1;
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
    if (out && bvox_write(out, vol, &wo)) rc = cli_fail();
    if (!rc && save) {
        st = ends_with(save, ".json") ? bvox_stack_write_json(save, stack)
                                      : bvox_stack_write_svg_dir(save, stack);
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
bad_value: /* cli_match_value printed the message */
    free(inputs);
    return CLI_USAGE;
}
