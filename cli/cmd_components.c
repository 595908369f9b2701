/*
 * cmd_components.c — `bvox components IN`: the connected components of a
 * volume (bvox_components_find), largest first, as a table or one JSON
 * object; optionally the N largest written as a volume (-o, with
 * --keep-largest) and every component written as a NIfTI label volume
 * (--labels: label i+1 is the i-th largest, 0 the background).
 */
#include "args.h"
#include "cli.h"
#include "json.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void help(FILE *f)
{
    fputs("Usage: bvox components IN [options]\n"
          "\n"
          "List the connected components of a volume, largest first: voxels, volume\n"
          "and bounding box (inclusive voxel indices) of each.\n"
          "\n"
          "Options:\n"
          "  --conn 6|18|26        connectivity: faces, faces+edges, all neighbours\n"
          "                        (default 26)\n"
          "  --json                print {\"count\": N, \"components\": [{\"voxels\",\n"
          "                        \"volume\", \"bbox\": {\"min\", \"max\"}}, ...]}\n"
          "  --keep-largest N      with -o: write a volume holding the N largest\n"
          "  -o, --output OUT      the file for --keep-largest\n"
          "  --labels OUT.nii      write a NIfTI label volume (.nii or .nii.gz): 0 for\n"
          "                        the background, i for the i-th largest component;\n"
          "                        uint16 when there are at most 65535, else uint32\n",
          f);
    fprintf(f, "  --output-format NAME  force the format of -o (%s)\n", bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox components mask.nii.gz --conn 6\n"
          "  bvox components cells.tif --json --labels cells-labels.nii.gz\n"
          "  bvox components noisy.nii --keep-largest 1 -o organ.nii\n",
          f);
}

static void print_text(const bvox_components *c, int conn, const bvox_geometry *g)
{
    int64_t n = bvox_components_count(c);
    printf("%-14s%lld (%d-connected)\n", "components:", (long long)n, conn);
    if (n == 0) return;
    char vh[40] = "volume";
    if (g->unit[0]) snprintf(vh, sizeof vh, "volume (%s^3)", g->unit);
    printf("%8s %12s %14s  %s\n", "#", "voxels", vh, "bounding box (voxel indices, inclusive)");
    for (int64_t i = 0; i < n; i++) {
        const bvox_component *it = bvox_components_get(c, i);
        const bvox_box b = it->bbox;
        printf("%8lld %12lld %14.6g  x %d..%d, y %d..%d, z %d..%d\n", (long long)(i + 1),
               (long long)it->voxels, it->volume, b.x0, b.x1 - 1, b.y0, b.y1 - 1, b.z0,
               b.z1 - 1);
    }
}

static void print_json(const bvox_components *c)
{
    cli_json j;
    cli_json_init(&j, stdout);
    int64_t n = bvox_components_count(c);
    cli_json_begin_object(&j);
    cli_json_key(&j, "count");
    cli_json_int(&j, n);
    cli_json_key(&j, "components");
    cli_json_begin_array(&j);
    for (int64_t i = 0; i < n; i++) {
        const bvox_component *it = bvox_components_get(c, i);
        const bvox_box b = it->bbox;
        const int64_t lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1 - 1, b.y1 - 1, b.z1 - 1};
        cli_json_begin_object(&j);
        cli_json_key(&j, "voxels");
        cli_json_int(&j, it->voxels);
        cli_json_key(&j, "volume");
        cli_json_double(&j, it->volume);
        cli_json_key(&j, "bbox");
        cli_json_begin_object(&j);
        cli_json_key(&j, "min");
        cli_json_int_array(&j, lo, 3);
        cli_json_key(&j, "max");
        cli_json_int_array(&j, hi, 3);
        cli_json_end_object(&j);
        cli_json_end_object(&j);
    }
    cli_json_end_array(&j);
    cli_json_end_object(&j);
    putchar('\n');
}

/* The label volume needs 4 bytes per voxel for a moment: refuse it over the
 * memory budget like the library would, rather than swapping. Allocated
 * before -o is written, so that the likeliest failure leaves no output. */
static uint32_t *alloc_labels(const char *path, const bvox_volume *vol)
{
    bvox_dims d = bvox_volume_dims(vol);
    size_t n = (size_t)d.nx * (size_t)d.ny * (size_t)d.nz;
    size_t bytes = n * sizeof(uint32_t), budget = bvox_memory_budget(),
           used = bvox_memory_in_use();
    if (bytes / sizeof(uint32_t) != n || bytes > budget - (used < budget ? used : budget)) {
        fprintf(stderr, "bvox: %s: the label volume needs %zu bytes, over the memory budget "
                        "(%zu bytes; see --max-memory)\n",
                path, bytes, budget);
        return NULL;
    }
    uint32_t *labels = malloc(bytes ? bytes : 1);
    if (!labels)
        fprintf(stderr, "bvox: %s: out of memory for the label volume (%zu bytes)\n", path,
                bytes);
    return labels;
}

int cmd_components(int argc, char **argv)
{
    const char *cmd = "components", *in = NULL, *out = NULL, *labels = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, conn = 26, json = 0;
    int64_t keep = -1, n;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--labels", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            labels = v;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--conn", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 0, 26, &n) || (n != 6 && n != 18 && n != 26))
                return cli_usage_error(cmd, "--conn: '%s' is not 6, 18 or 26", v);
            conn = (int)n;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--keep-largest", &v))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            if (cli_parse_int64(v, 1, INT64_MAX, &keep))
                return cli_usage_error(cmd, "--keep-largest: '%s' is not a count >= 1", v);
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
    if (!in) return cli_usage_error(cmd, "missing the input file IN");
    if (keep >= 0 && !out) return cli_usage_error(cmd, "--keep-largest needs -o OUT");
    if (out && keep < 0) return cli_usage_error(cmd, "-o needs --keep-largest N");
    if (wo.format && !out) return cli_usage_error(cmd, "--output-format needs -o OUT");
    /* Refuse output names of unknown format before reading a large input. */
    struct stat sb;
    size_t len = out ? strlen(out) : 0;
    int folder = out && ((len && out[len - 1] == '/') ||
                         (stat(out, &sb) == 0 && S_ISDIR(sb.st_mode)));
    if (out && !wo.format && !folder && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; "
                               "use --output-format (one of %s)",
                               out, bvox_format_list());
    const char *lf = labels ? bvox_format_for_path(labels) : NULL;
    if (labels && (!lf || strcmp(lf, "nifti") != 0))
        return cli_usage_error(cmd, "--labels: '%s' must end in .nii or .nii.gz", labels);

    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &ra, &vol)) return cli_fail();
    bvox_components *c = NULL;
    uint32_t *lv = NULL;
    int rc = CLI_OK;
    if (bvox_components_find(vol, conn, &c)) rc = cli_fail();
    else if (labels && !(lv = alloc_labels(labels, vol))) rc = CLI_FAIL;
    if (rc == CLI_OK && out) {
        bvox_volume *kept = NULL;
        bvox_status st = bvox_components_keep(c, keep, &kept);
        if (!st) st = bvox_write(out, kept, &wo);
        bvox_volume_destroy(kept);
        if (st) rc = cli_fail();
    }
    if (rc == CLI_OK && labels) {
        bvox_components_labels(c, lv);
        if (bvox_write_labels_nifti(labels, vol, lv)) rc = cli_fail();
    }
    if (rc == CLI_OK) {
        if (json) print_json(c);
        else print_text(c, conn, bvox_volume_geometry(vol));
    }
    free(lv);
    bvox_components_destroy(c);
    bvox_volume_destroy(vol);
    return rc;
}
