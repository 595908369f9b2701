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
#include "manip.h"
#include "opts.h"
#include "outofcore.h"

#include <stdlib.h>
#include <string.h>

typedef struct components_args {
    const char *in, *out, *labels;
    int64_t conn, keep;
    int json;
    bvox_write_opts wo;
    cli_read_args ra;
} components_args;

#define A(member) CLI_AT(components_args, member)

static const cli_opt components_opts[] = {
    {"--conn", 0, CLI_INT, NULL, "connectivity: faces, faces+edges, all neighbours", A(conn),
     .def = "26", .lo = 0, .hi = 26, .choices = cli_conn_choices,
     .bad = "--conn: '%s' is not 6, 18 or 26"},
    {"--json", 0, CLI_FLAG, NULL,
     "print {\"count\": N, \"components\": [{\"voxels\", \"volume\", \"bbox\": {\"min\", "
     "\"max\"}}, ...]}",
     A(json)},
    {"--keep-largest", 0, CLI_INT, "N", "with -o: write a volume holding the N largest", A(keep),
     .lo = 1, .hi = INT64_MAX, .bad = "--keep-largest: '%s' is not a count >= 1"},
    {"--output", 'o', CLI_PATH, "OUT", "the file for --keep-largest", A(out)},
    {"--labels", 0, CLI_PATH, "OUT.nii",
     "write a NIfTI label volume (.nii or .nii.gz): 0 for the background, i for the i-th "
     "largest component; uint16 when there are at most 65535, else uint32 (also .nrrd, "
     ".nhdr, .seg.nrrd, .mha, .mhd: the smallest of uint8, uint16, uint32)",
     A(labels)},
    {"--output-format", 0, CLI_STR, "NAME", "force the format of -o ({formats})", A(wo.format)},
    {"--force", 0, CLI_FLAG, NULL, CLI_FORCE_HELP, A(wo.force)},
    {NULL},
};
static const cli_group components_group = {"Options", components_opts, NULL};
static const cli_pos components_pos[] = {
    {"IN", "the volume to read", A(in)},
    {NULL},
};

const cli_spec cli_spec_components = {
    .name = "components",
    .summary = "list connected components; keep the largest; label map",
    .usage = "IN [options]",
    .about = "List the connected components of a volume, largest first: voxels, volume\n"
             "and bounding box (inclusive voxel indices) of each.\n",
    .pos = components_pos,
    .uses = {{&components_group, 0}, CLI_USE_READ(components_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox components mask.nii.gz --conn 6\n"
                "  bvox components cells.tif --json --labels cells-labels.nii.gz\n"
                "  bvox components noisy.nii --keep-largest 1 -o organ.nii\n",
};

/* Component i: from the in-memory labelling, or from the out-of-core list. */
static const bvox_component *item(const bvox_components *c, const bvox_component *list,
                                  int64_t i)
{
    return c ? bvox_components_get(c, i) : &list[i];
}

static void print_text(const bvox_components *c, const bvox_component *list, int64_t n,
                       int conn, const bvox_geometry *g)
{
    printf("%-14s%lld (%d-connected)\n", "components:", (long long)n, conn);
    if (n == 0) return;
    char vh[40] = "volume";
    if (g->unit[0]) snprintf(vh, sizeof vh, "volume (%s^3)", g->unit);
    printf("%8s %12s %14s  %s\n", "#", "voxels", vh, "bounding box (voxel indices, inclusive)");
    for (int64_t i = 0; i < n; i++) {
        const bvox_component *it = item(c, list, i);
        const bvox_box b = it->bbox;
        printf("%8lld %12lld %14.6g  x %d..%d, y %d..%d, z %d..%d\n", (long long)(i + 1),
               (long long)it->voxels, it->volume, b.x0, b.x1 - 1, b.y0, b.y1 - 1, b.z0,
               b.z1 - 1);
    }
}

static void print_json(const bvox_components *c, const bvox_component *list, int64_t n,
                       const char *in, const char *out)
{
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_json_key(&j, "count");
    cli_json_int(&j, n);
    cli_json_key(&j, "component_count"); /* = count, the name measure shares */
    cli_json_int(&j, n);
    cli_json_io(&j, in, out);
    cli_json_key(&j, "components");
    cli_json_begin_array(&j);
    for (int64_t i = 0; i < n; i++) {
        const bvox_component *it = item(c, list, i);
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
    const char *cmd = "components";
    components_args a = {.keep = -1, .wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_components, argc, argv, &a);
    const char *in = a.in, *out = a.out, *labels = a.labels;
    int conn = (int)a.conn, json = a.json;
    int64_t keep = a.keep;
    if (!in) return cli_usage_error(cmd, "missing the input file IN");
    if (keep >= 0 && !out) return cli_usage_error(cmd, "--keep-largest needs -o OUT");
    if (out && keep < 0) return cli_usage_error(cmd, "-o needs --keep-largest N");
    if (a.wo.format && !out) return cli_usage_error(cmd, "--output-format needs -o OUT");
    /* Refuse output names of unknown format before reading a large input. */
    if (out && cli_check_output(cmd, out, &a.wo) != CLI_OK) return CLI_USAGE;
    const char *lf = labels ? bvox_format_for_path(labels) : NULL;
    if (labels && (!lf || (strcmp(lf, "nifti") && strcmp(lf, "nrrd") && strcmp(lf, "metaimage"))))
        return cli_usage_error(cmd,
                               "--labels: '%s' must end in .nii or .nii.gz (or .nrrd, .nhdr, "
                               ".seg.nrrd, .mha, .mhd)",
                               labels);

    bvox__slab_source src;
    if (cli_ooc_open(in, &a.ra, &src) == 1) { /* a .zarr over --max-memory: by slabs */
        const char *what = out ? "--keep-largest" : labels ? "--labels" : NULL;
        if (what) {
            bvox__slab_source_close(&src);
            return cli_ooc_refuse(cmd, in, what);
        }
        int64_t n = 0;
        bvox_component *list = NULL;
        bvox_status st = bvox__stream_components(&src, conn, &n, &list);
        if (!st) {
            if (json) print_json(NULL, list, n, in, out);
            else print_text(NULL, list, n, conn, &src.geom);
        }
        free(list);
        bvox__slab_source_close(&src);
        return st ? cli_fail() : CLI_OK;
    }
    bvox_volume *vol = NULL;
    if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
    bvox_components *c = NULL;
    uint32_t *lv = NULL;
    int rc = CLI_OK;
    if (bvox_components_find(vol, conn, &c)) rc = cli_fail();
    else if (labels && !(lv = alloc_labels(labels, vol))) rc = CLI_FAIL;
    if (rc == CLI_OK && out) {
        bvox_volume *kept = NULL;
        bvox_status st = bvox_components_keep(c, keep, &kept);
        if (!st) st = bvox_write(out, kept, &a.wo);
        bvox_volume_destroy(kept);
        if (st) rc = cli_fail();
    }
    if (rc == CLI_OK && labels) {
        bvox_components_labels(c, lv);
        bool nifti = !strcmp(lf, "nifti"); /* NIfTI keeps its uint16/uint32 choice */
        if (nifti ? bvox_write_labels_nifti(labels, vol, lv)
                  : bvox_write_labels(labels, vol, lv, -1, NULL))
            rc = cli_fail();
    }
    if (rc == CLI_OK) {
        int64_t n = bvox_components_count(c);
        if (json) print_json(c, NULL, n, in, out);
        else print_text(c, NULL, n, conn, bvox_volume_geometry(vol));
    }
    free(lv);
    bvox_components_destroy(c);
    bvox_volume_destroy(vol);
    return rc;
}
