/*
 * cmd_measure.c — `bvox measure IN`: what `bvox info` says plus the measures
 * of bvox_measure (surface area, centroid, principal axes and moments,
 * topology), as aligned text or one JSON object (the info keys first, so a
 * script reading `info --json` reads this too); --csv gives one row per
 * 26-connected component from bvox_measure_components instead.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"
#include "outofcore.h"

#include <math.h>
#include <string.h>

typedef struct measure_args {
    const char *path;
    int json, csv;
    cli_read_args ra;
} measure_args;

#define A(member) CLI_AT(measure_args, member)

static const cli_opt measure_opts[] = {
    {"--json", 0, CLI_FLAG, NULL,
     "one JSON object: the keys of 'bvox info --json', then surface_area, centroid, "
     "principal_axes, components...",
     A(json)},
    {"--csv", 0, CLI_FLAG, NULL,
     "one row per 26-connected component (largest first), after a header line", A(csv)},
    {NULL},
};
static const cli_group measure_group = {"Options", measure_opts, NULL};
static const cli_pos measure_pos[] = {
    {"IN", "the volume to measure", A(path)},
    {NULL},
};

const cli_spec cli_spec_measure = {
    .name = "measure",
    .summary = "surface area, centroid, principal axes, topology, per component",
    .usage = "IN [--json | --csv] [options]",
    .about = "Measure the object in a volume, in the physical units of the file: count,\n"
             "volume and bounding box (as 'bvox info'), surface area (a smooth estimate,\n"
             "and the area of the voxel faces), centroid, principal axes and moments,\n"
             "inertia, sphericity, and the topology: 26-connected components, cavities,\n"
             "tunnels and the Euler number.\n",
    .pos = measure_pos,
    .uses = {{&measure_group, 0}, CLI_USE_READ(measure_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox measure embryo.nii.gz\n"
                "  bvox measure atlas.nii.gz --label 37 --json\n"
                "  bvox measure cells.tif --csv > cells.csv\n",
};

/* unit^2 as info names unit^3: the file's unit, "voxel" for unit cubes. */
static void area_unit(const bvox_geometry *g, char *buf, size_t size)
{
    if (g->unit[0]) snprintf(buf, size, "%s^2", g->unit);
    else if (g->spacing[0] == 1 && g->spacing[1] == 1 && g->spacing[2] == 1)
        snprintf(buf, size, "voxel^2");
    else snprintf(buf, size, "units^2");
}

static void print_text(const bvox_info *info, const bvox_measures *m, const char *path,
                       const char *format)
{
    cli_print_info_text(stdout, info, path, format);
    const bvox_geometry *g = &info->geometry;
    const char *sep = g->unit[0] ? " " : "", *unit = g->unit;
    char au[32];
    area_unit(g, au, sizeof au);
    printf("%-14s%.6g %s (area of the voxel faces: %.6g %s)\n", "surface area:", m->area, au,
           m->area_faces, au);
    if (m->count > 0) {
        printf("%-14s%.6g, %.6g, %.6g%s%s\n", "centroid:", m->centroid[0] + 0.0,
               m->centroid[1] + 0.0, m->centroid[2] + 0.0, sep, unit);
        for (int a = 0; a < 3; a++) {
            const double *ax = m->principal_axes + 3 * a;
            char label[24];
            snprintf(label, sizeof label, "axis %d:", a + 1);
            /* the square root of a moment is the spread along the axis */
            printf("%-14s(%.4f, %.4f, %.4f), sd %.6g%s%s\n", label, ax[0] + 0.0, ax[1] + 0.0,
                   ax[2] + 0.0, sqrt(m->principal_moments[a] > 0 ? m->principal_moments[a] : 0),
                   sep, unit);
        }
        printf("%-14s%.6g%s%s\n", "eq. diameter:", m->equivalent_diameter, sep, unit);
        if (isnan(m->sphericity))
            printf("%-14s%s\n", "sphericity:", "n/a (under 1000 voxels: the area estimate is too rough)");
        else printf("%-14s%.4f\n", "sphericity:", m->sphericity);
    }
    printf("%-14s%lld (26-connected)\n", "components:", (long long)m->components);
    printf("%-14s%lld (6-connected background; 26-connected: %lld)\n", "cavities:",
           (long long)m->cavities, (long long)m->cavities_26);
    printf("%-14s%lld\n", "tunnels:", (long long)m->tunnels);
    printf("%-14s%lld\n", "euler:", (long long)m->euler);
}

static void matrix(cli_json *j, const double *v)
{
    cli_json_begin_array(j);
    for (int r = 0; r < 3; r++) cli_json_double_array(j, v + 3 * r, 3);
    cli_json_end_array(j);
}

static void print_json(const bvox_info *info, const bvox_measures *m, const char *path,
                       const char *format)
{
    int empty = m->count == 0;
    char au[32];
    area_unit(&info->geometry, au, sizeof au);
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_info_json_fields(&j, info, path, format);
    cli_json_io(&j, path, NULL);
    cli_json_key(&j, "surface_area");
    cli_json_double(&j, m->area);
    cli_json_key(&j, "surface_area_faces");
    cli_json_double(&j, m->area_faces);
    cli_json_key(&j, "area_unit");
    cli_json_string(&j, au);
    cli_json_key(&j, "faces");
    cli_json_int_array(&j, m->faces, 3);
    /* null, like bbox, where an empty volume has no value */
    cli_json_key(&j, "centroid");
    if (empty) cli_json_null(&j);
    else cli_json_double_array(&j, m->centroid, 3);
    cli_json_key(&j, "principal_axes"); /* rows: unit vectors, largest spread first */
    if (empty) cli_json_null(&j);
    else matrix(&j, m->principal_axes);
    cli_json_key(&j, "principal_moments");
    cli_json_double_array(&j, m->principal_moments, 3);
    cli_json_key(&j, "principal_inertia");
    cli_json_double_array(&j, m->principal_inertia, 3);
    cli_json_key(&j, "covariance");
    matrix(&j, m->covariance);
    cli_json_key(&j, "inertia");
    matrix(&j, m->inertia);
    cli_json_key(&j, "equivalent_diameter");
    cli_json_double(&j, m->equivalent_diameter);
    cli_json_key(&j, "sphericity");
    if (empty) cli_json_null(&j);
    else cli_json_double(&j, m->sphericity);
    cli_json_key(&j, "components");
    cli_json_int(&j, m->components);
    cli_json_key(&j, "component_count"); /* the name `components --json` shares */
    cli_json_int(&j, m->components);
    cli_json_key(&j, "cavities");
    cli_json_int(&j, m->cavities);
    cli_json_key(&j, "cavities_6"); /* the same: the background's connectivity named */
    cli_json_int(&j, m->cavities);
    cli_json_key(&j, "cavities_26");
    cli_json_int(&j, m->cavities_26);
    cli_json_key(&j, "tunnels");
    cli_json_int(&j, m->tunnels);
    cli_json_key(&j, "euler");
    cli_json_int(&j, m->euler);
    cli_json_end_object(&j);
    putchar('\n');
}

static void csv_double(double v)
{
    char buf[40];
    if (!isfinite(v)) {
        fputs(",", stdout); /* empty field */
        return;
    }
    cli_json_format_double(buf, sizeof buf, v == 0 ? 0.0 : v);
    printf(",%s", buf);
}

static void print_csv(const bvox_measures *all, int64_t n)
{
    puts("component,voxels,volume,surface_area,surface_area_faces,centroid_x,centroid_y,"
         "centroid_z,bbox_min_x,bbox_min_y,bbox_min_z,bbox_max_x,bbox_max_y,bbox_max_z,"
         "axis1_x,axis1_y,axis1_z,moment1,moment2,moment3,equivalent_diameter,sphericity,"
         "cavities,tunnels,euler,cavities_26");
    for (int64_t i = 0; i < n; i++) {
        const bvox_measures *m = &all[i];
        printf("%lld,%lld", (long long)(i + 1), (long long)m->count);
        csv_double(m->volume);
        csv_double(m->area);
        csv_double(m->area_faces);
        for (int a = 0; a < 3; a++) csv_double(m->centroid[a]);
        const bvox_box b = m->bbox; /* inclusive, as in the JSON outputs */
        printf(",%d,%d,%d,%d,%d,%d", b.x0, b.y0, b.z0, b.x1 - 1, b.y1 - 1, b.z1 - 1);
        for (int a = 0; a < 3; a++) csv_double(m->principal_axes[a]);
        for (int a = 0; a < 3; a++) csv_double(m->principal_moments[a]);
        csv_double(m->equivalent_diameter);
        csv_double(m->sphericity);
        printf(",%lld,%lld,%lld,%lld\n", (long long)m->cavities, (long long)m->tunnels,
               (long long)m->euler, (long long)m->cavities_26);
    }
}

int cmd_measure(int argc, char **argv)
{
    const char *cmd = "measure";
    measure_args a = {0};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_measure, argc, argv, &a);
    const char *path = a.path;
    int json = a.json, csv = a.csv;
    if (!path) return cli_usage_error(cmd, "missing the FILE to measure");
    if (json && csv) return cli_usage_error(cmd, "give --json or --csv, not both");

    bvox_status st;
    bvox__slab_source src;
    int ooc = cli_ooc_open(path, &a.ra, &src);
    if (ooc == 1) { /* a .zarr over --max-memory: every measure by slabs, one pass */
        if (csv) {
            bvox__slab_source_close(&src);
            return cli_ooc_refuse(cmd, path, "--csv (the measures of every component)");
        }
        bvox_measures m;
        st = bvox__stream_measure(&src, &m);
        bvox_info info = {src.dims, src.geom, m.count, m.volume, m.count == 0, m.bbox};
        bvox__slab_source_close(&src);
        if (st) return cli_fail();
        const char *format = cli_input_format(path, &a.ra);
        if (json) print_json(&info, &m, path, format);
        else print_text(&info, &m, path, format);
        return CLI_OK;
    }
    bvox_volume *vol = NULL;
    if (cli_read_volume(path, &a.ra, &vol)) return cli_fail();
    if (csv) {
        bvox_measures *all = NULL;
        int64_t n = 0;
        st = bvox_measure_components(vol, 26, &all, &n);
        bvox_volume_destroy(vol);
        if (st) return cli_fail();
        print_csv(all, n);
        bvox_free(all);
        return CLI_OK;
    }
    bvox_info info;
    bvox_measures m;
    st = bvox_info_compute(vol, &info);
    if (!st) st = bvox_measure(vol, &m);
    bvox_volume_destroy(vol);
    if (st) return cli_fail();
    const char *format = cli_input_format(path, &a.ra);
    if (json) print_json(&info, &m, path, format);
    else print_text(&info, &m, path, format);
    return CLI_OK;
}
