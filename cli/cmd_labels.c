/*
 * cmd_labels.c — `bvox labels FILE [--lut TABLE] [--json | --csv]`: one row
 * per label of a label volume (atlas, segmentation): name and colour from
 * the lookup table, voxels, volume, surface area, centroid, bounding box,
 * topology, sphericity, and the labels it touches with the contact area.
 * The volume is read once and split (bvox_labels_read); each label is
 * measured on its own crop (bvox_labelset_measure), giving the numbers
 * `bvox measure FILE --label N` gives.
 *
 * Table problems (duplicates, unreadable lines, labels of the volume missing
 * from the table) are warnings on stderr: the table still names the rest.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct labels_args {
    const char *path, *lut;
    int json, csv;
    int64_t max_labels;
    cli_read_args ra;
} labels_args;

#define A(member) CLI_AT(labels_args, member)

static const cli_opt labels_opts[] = {
    {"--lut", 0, CLI_PATH, "TABLE",
     "label names and colours: FreeSurfer *LUT.txt, 3D Slicer colour table, ITK-SNAP label "
     "description, or the AAL list beside the atlas (aal.nii.txt)",
     A(lut)},
    {"--max-labels", 0, CLI_INT, "N", "refuse volumes with more distinct labels",
     A(max_labels), .def = "65535", .lo = 1, .hi = 2147483647,
     .bad = "--max-labels needs a count from 1 to 2147483647, not '%s'"},
    {"--json", 0, CLI_FLAG, NULL, "one JSON object with a \"labels\" array", A(json)},
    {"--csv", 0, CLI_FLAG, NULL, "one row per label after a header line", A(csv)},
    {NULL},
};
static const cli_group labels_group = {"Options", labels_opts, NULL};
static const cli_pos labels_pos[] = {
    {"FILE", "the label volume", A(path)},
    {NULL},
};

const cli_spec cli_spec_labels = {
    .name = "labels",
    .summary = "label volume: per-label measures, names, neighbours (one pass)",
    .usage = "FILE [--lut TABLE] [--json | --csv] [options]",
    .about = "Measure every label of a label volume (0 is background) in one pass: name,\n"
             "voxels, volume, surface area, centroid, bounding box, 26-connected components,\n"
             "cavities, sphericity, and its neighbours (labels it touches, contact area).\n"
             "Each label's numbers are those of 'bvox measure FILE --label N'.\n",
    .pos = labels_pos,
    .uses = {{&labels_group, 0}, CLI_USE_READ(labels_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox labels /usr/share/mricron/templates/aal.nii.gz \\\n"
                "      --lut /usr/share/mricron/templates/aal.nii.txt --csv > aal.csv\n"
                "  bvox labels seg.nii.gz --lut FreeSurferColorLUT.txt --json\n",
};

typedef struct row {
    bvox_measures m;
    const bvox_label_entry *entry; /* NULL: not in the table */
} row;

/* Per object: the contacts it is part of (indices into set->contacts). */
typedef struct adjacency {
    int64_t *start; /* n + 1 */
    int64_t *list;
} adjacency;

static int adjacency_make(const bvox_labelset *set, adjacency *adj)
{
    adj->start = calloc((size_t)set->n + 1, sizeof *adj->start);
    adj->list = malloc(((size_t)set->ncontacts * 2 + 1) * sizeof *adj->list);
    if (!adj->start || !adj->list) return -1;
    for (int64_t c = 0; c < set->ncontacts; c++) {
        adj->start[set->contacts[c].a + 1]++;
        adj->start[set->contacts[c].b + 1]++;
    }
    for (int64_t i = 0; i < set->n; i++) adj->start[i + 1] += adj->start[i];
    int64_t *fill = calloc((size_t)set->n + 1, sizeof *fill);
    if (!fill) return -1;
    for (int64_t c = 0; c < set->ncontacts; c++) {
        int64_t a = set->contacts[c].a, b = set->contacts[c].b;
        adj->list[adj->start[a] + fill[a]++] = c;
        adj->list[adj->start[b] + fill[b]++] = c;
    }
    free(fill);
    return 0;
}

static const char *name_of(const row *r) { return r->entry ? r->entry->name : NULL; }

static void json_box(cli_json *j, bvox_box b)
{
    int64_t lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1 - 1, b.y1 - 1, b.z1 - 1};
    cli_json_begin_object(j);
    cli_json_key(j, "min");
    cli_json_int_array(j, lo, 3);
    cli_json_key(j, "max");
    cli_json_int_array(j, hi, 3);
    cli_json_end_object(j);
}

static void print_json(const char *path, const bvox_labelset *set, const row *rows,
                       const adjacency *adj)
{
    const bvox_geometry *g = &set->geometry;
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_json_key(&j, "file");
    cli_json_string(&j, path);
    cli_json_key(&j, "dims");
    int64_t d[3] = {set->dims.nx, set->dims.ny, set->dims.nz};
    cli_json_int_array(&j, d, 3);
    cli_json_key(&j, "voxel_size");
    cli_json_double_array(&j, g->spacing, 3);
    cli_json_key(&j, "unit");
    cli_json_string(&j, g->unit);
    cli_json_key(&j, "background");
    cli_json_int(&j, set->background);
    cli_json_key(&j, "labels");
    cli_json_begin_array(&j);
    for (int64_t i = 0; i < set->n; i++) {
        const row *r = &rows[i];
        const bvox_measures *m = &r->m;
        cli_json_begin_object(&j);
        cli_json_key(&j, "label");
        cli_json_int(&j, set->objects[i].label);
        cli_json_key(&j, "name");
        cli_json_string(&j, name_of(r));
        cli_json_key(&j, "color");
        if (r->entry && r->entry->has_color) {
            int64_t c[4] = {r->entry->rgba[0], r->entry->rgba[1], r->entry->rgba[2],
                            r->entry->rgba[3]};
            cli_json_int_array(&j, c, 4);
        } else cli_json_null(&j);
        cli_json_key(&j, "count");
        cli_json_int(&j, m->count);
        cli_json_key(&j, "volume");
        cli_json_double(&j, m->volume);
        cli_json_key(&j, "surface_area");
        cli_json_double(&j, m->area);
        cli_json_key(&j, "surface_area_faces");
        cli_json_double(&j, m->area_faces);
        cli_json_key(&j, "faces");
        cli_json_int_array(&j, m->faces, 3);
        cli_json_key(&j, "centroid");
        cli_json_double_array(&j, m->centroid, 3);
        cli_json_key(&j, "bbox");
        json_box(&j, m->bbox);
        cli_json_key(&j, "principal_moments");
        cli_json_double_array(&j, m->principal_moments, 3);
        cli_json_key(&j, "equivalent_diameter");
        cli_json_double(&j, m->equivalent_diameter);
        cli_json_key(&j, "sphericity");
        cli_json_double(&j, m->sphericity);
        cli_json_key(&j, "components");
        cli_json_int(&j, m->components);
        cli_json_key(&j, "cavities");
        cli_json_int(&j, m->cavities);
        cli_json_key(&j, "cavities_26");
        cli_json_int(&j, m->cavities_26);
        cli_json_key(&j, "tunnels");
        cli_json_int(&j, m->tunnels);
        cli_json_key(&j, "euler");
        cli_json_int(&j, m->euler);
        cli_json_key(&j, "neighbours");
        cli_json_begin_array(&j);
        for (int64_t k = adj->start[i]; k < adj->start[i + 1]; k++) {
            const bvox_label_contact *c = &set->contacts[adj->list[k]];
            int64_t other = c->a == i ? c->b : c->a;
            cli_json_begin_object(&j);
            cli_json_key(&j, "label");
            cli_json_int(&j, set->objects[other].label);
            cli_json_key(&j, "name");
            cli_json_string(&j, name_of(&rows[other]));
            cli_json_key(&j, "faces");
            cli_json_int_array(&j, c->faces, 3);
            cli_json_key(&j, "contact_area");
            cli_json_double(&j, c->area);
            cli_json_end_object(&j);
        }
        cli_json_end_array(&j);
        cli_json_end_object(&j);
    }
    cli_json_end_array(&j);
    cli_json_end_object(&j);
    putchar('\n');
}

static void csv_double(double v)
{
    char buf[40];
    if (!isfinite(v)) {
        fputs(",", stdout);
        return;
    }
    cli_json_format_double(buf, sizeof buf, v == 0 ? 0.0 : v);
    printf(",%s", buf);
}

/* RFC 4180: quoted when it holds a comma, quote or line break. */
static void csv_string(const char *s)
{
    putchar(',');
    if (!s) return;
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, stdout);
        return;
    }
    putchar('"');
    for (; *s; s++) {
        if (*s == '"') putchar('"');
        putchar(*s);
    }
    putchar('"');
}

static void print_csv(const bvox_labelset *set, const row *rows, const adjacency *adj)
{
    puts("label,name,voxels,volume,surface_area,surface_area_faces,centroid_x,centroid_y,"
         "centroid_z,bbox_min_x,bbox_min_y,bbox_min_z,bbox_max_x,bbox_max_y,bbox_max_z,"
         "components,cavities,tunnels,euler,equivalent_diameter,sphericity,neighbours,cavities_26");
    for (int64_t i = 0; i < set->n; i++) {
        const bvox_measures *m = &rows[i].m;
        printf("%lld", (long long)set->objects[i].label);
        csv_string(name_of(&rows[i]));
        printf(",%lld", (long long)m->count);
        csv_double(m->volume);
        csv_double(m->area);
        csv_double(m->area_faces);
        for (int a = 0; a < 3; a++) csv_double(m->centroid[a]);
        const bvox_box b = m->bbox;
        printf(",%d,%d,%d,%d,%d,%d", b.x0, b.y0, b.z0, b.x1 - 1, b.y1 - 1, b.z1 - 1);
        printf(",%lld,%lld,%lld,%lld", (long long)m->components, (long long)m->cavities,
               (long long)m->tunnels, (long long)m->euler);
        csv_double(m->equivalent_diameter);
        csv_double(m->sphericity);
        /* neighbours as label:contact_area pairs separated by ';' (one field) */
        putchar(',');
        for (int64_t k = adj->start[i]; k < adj->start[i + 1]; k++) {
            const bvox_label_contact *c = &set->contacts[adj->list[k]];
            int64_t other = c->a == i ? c->b : c->a;
            char buf[40];
            cli_json_format_double(buf, sizeof buf, c->area);
            printf("%s%lld:%s", k > adj->start[i] ? ";" : "", (long long)set->objects[other].label,
                   buf);
        }
        printf(",%lld\n", (long long)m->cavities_26);
    }
}

static void print_text(const char *path, const bvox_labelset *set, const row *rows,
                       const adjacency *adj)
{
    const bvox_geometry *g = &set->geometry;
    printf("%s: %ld x %ld x %ld, %lld labels, %lld background voxels\n", path,
           (long)set->dims.nx, (long)set->dims.ny, (long)set->dims.nz, (long long)set->n,
           (long long)set->background);
    const char *u = g->unit[0] ? g->unit : "units";
    char u3[24], u2[24];
    snprintf(u3, sizeof u3, "%s^3", u);
    snprintf(u2, sizeof u2, "%s^2", u);
    printf("%8s  %-24s %10s %12s %12s %6s %6s %5s\n", "label", "name", "voxels", "volume",
           "area", "comps", "spher", "nbrs");
    printf("%8s  %-24s %10s %12s %12s %6s %6s %5s\n", "", "", "", u3, u2, "", "", "");
    for (int64_t i = 0; i < set->n; i++) {
        const bvox_measures *m = &rows[i].m;
        const char *name = name_of(&rows[i]);
        char sph[16] = "   n/a"; /* under 1000 voxels: not estimated */
        if (!isnan(m->sphericity)) snprintf(sph, sizeof sph, "%6.3f", m->sphericity);
        printf("%8lld  %-24.24s %10lld %12.6g %12.6g %6lld %s %5lld\n",
               (long long)set->objects[i].label, name ? name : "-", (long long)m->count,
               m->volume, m->area, (long long)m->components, sph,
               (long long)(adj->start[i + 1] - adj->start[i]));
    }
}

int cli_labels_load(const char *path, const cli_read_args *ra, const char *lut,
                    int64_t max_labels, bvox_labelset **set_out, bvox_label_table **table_out)
{
    *set_out = NULL;
    *table_out = NULL;
    bvox_label_table *table = NULL;
    /* a Slicer segmentation names its own segments */
    size_t plen = strlen(path);
    if (!lut && plen > 9 && !strcasecmp(path + plen - 9, ".seg.nrrd")) lut = path;
    if (lut && bvox_label_table_read(lut, &table)) return -1;
    bvox_labelset *set = NULL;
    if (bvox_labels_read(path, &ra->opts, max_labels, &set)) {
        bvox_label_table_destroy(table);
        return -1;
    }
    if (ra->spacing_given || ra->unit) { /* as cli_read_volume does for one volume */
        bvox_geometry g = set->geometry;
        if (ra->spacing_given) memcpy(g.spacing, ra->spacing, sizeof g.spacing);
        if (ra->unit) snprintf(g.unit, sizeof g.unit, "%s", ra->unit);
        if (bvox_labelset_set_geometry(set, &g)) {
            bvox_labelset_destroy(set);
            bvox_label_table_destroy(table);
            return -1;
        }
    }
    if (table && !cli_quiet) { /* the table's own warnings went to the handler */
        int64_t missing = 0;
        for (int64_t i = 0; i < set->n; i++)
            if (!bvox_label_table_find(table, set->objects[i].label) && missing++ < 8)
                fprintf(stderr, "bvox: warning: label %lld is not in %s\n",
                        (long long)set->objects[i].label, lut);
        if (missing > 8)
            fprintf(stderr, "bvox: warning: %lld labels in all are not in %s\n",
                    (long long)missing, lut);
    }
    *set_out = set;
    *table_out = table;
    return 0;
}

int cmd_labels(int argc, char **argv)
{
    const char *cmd = "labels";
    labels_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_labels, argc, argv, &a);
    const char *path = a.path, *lut = a.lut;
    int json = a.json, csv = a.csv;
    cli_read_args ra = a.ra;
    int64_t max_labels = a.max_labels;
    if (!path) return cli_usage_error(cmd, "missing the label volume FILE");
    if (json && csv) return cli_usage_error(cmd, "give --json or --csv, not both");
    if (ra.binarize_given)
        return cli_usage_error(cmd, "every label is measured: --label, --threshold, --range, "
                                    "--otsu and --nonzero do not apply");

    bvox_label_table *table = NULL;
    bvox_labelset *set = NULL;
    if (cli_labels_load(path, &ra, lut, max_labels, &set, &table)) return cli_fail();
    row *rows = calloc((size_t)set->n + 1, sizeof *rows);
    adjacency adj = {0};
    int rc = CLI_OK;
    if (!rows || adjacency_make(set, &adj)) {
        fprintf(stderr, "bvox: out of memory\n");
        rc = CLI_FAIL;
        goto done;
    }
    for (int64_t i = 0; i < set->n && rc == CLI_OK; i++) {
        if (bvox_labelset_measure(set, i, &rows[i].m)) rc = cli_fail();
        rows[i].entry = bvox_label_table_find(table, set->objects[i].label);
    }
    if (rc != CLI_OK) goto done;
    if (json) print_json(path, set, rows, &adj);
    else if (csv) print_csv(set, rows, &adj);
    else print_text(path, set, rows, &adj);
done:
    free(rows);
    free(adj.start);
    free(adj.list);
    bvox_labelset_destroy(set);
    bvox_label_table_destroy(table);
    return rc;
}
