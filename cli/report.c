/*
 * report.c — prints a bvox_info (from bvox_info_compute) for people (aligned
 * text) or for scripts (one JSON object). Shared by `info` and `demo` so that
 * both say the same thing about a volume. Only presentation lives here: the
 * numbers come from the library; this file converts units and box corners
 * for display.
 */
#include "cli.h"
#include "json.h"

#include <math.h>
#include <string.h>

/* How the volume's unit^3 is named: the file's unit, "voxel^3" when there is
 * no unit and voxels are unit cubes (volume == count), else "units^3". */
static const char *cube_unit(const bvox_info *info, char *buf, size_t size)
{
    const bvox_geometry *g = &info->geometry;
    if (g->unit[0]) snprintf(buf, size, "%s^3", g->unit);
    else if (g->spacing[0] == 1 && g->spacing[1] == 1 && g->spacing[2] == 1)
        snprintf(buf, size, "voxel^3");
    else snprintf(buf, size, "units^3");
    return buf;
}

/* Factor from unit^3 to mm^3 for the common length units, 0 if unknown. */
static double to_mm3(const char *unit)
{
    static const struct {
        const char *name;
        double mm;
    } units[] = {{"nm", 1e-6}, {"um", 1e-3}, {"\xc2\xb5m", 1e-3}, {"micron", 1e-3},
                 {"mm", 1},    {"cm", 10},   {"m", 1e3}};
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
        if (!strcmp(unit, units[i].name)) return units[i].mm * units[i].mm * units[i].mm;
    return 0;
}

/* World-space bounds of the bbox's voxels (their outer faces, not centres):
 * world = origin + direction * (index * spacing), min/max over the 8 corners,
 * so a rotated volume still gets a correct axis-aligned extent. */
static void bbox_physical(const bvox_info *info, double lo[3], double hi[3])
{
    const bvox_geometry *g = &info->geometry;
    const double idx_lo[3] = {info->bbox.x0 - 0.5, info->bbox.y0 - 0.5, info->bbox.z0 - 0.5};
    const double idx_hi[3] = {info->bbox.x1 - 0.5, info->bbox.y1 - 0.5, info->bbox.z1 - 0.5};
    for (int a = 0; a < 3; a++) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (int c = 0; c < 8; c++) {
        double p[3];
        for (int k = 0; k < 3; k++) p[k] = ((c >> k) & 1 ? idx_hi[k] : idx_lo[k]) * g->spacing[k];
        for (int a = 0; a < 3; a++) {
            double w = g->origin[a];
            for (int k = 0; k < 3; k++) w += g->direction[a * 3 + k] * p[k];
            if (w < lo[a]) lo[a] = w;
            if (w > hi[a]) hi[a] = w;
        }
    }
}

void cli_print_info_text(FILE *f, const bvox_info *info, const char *source, const char *format)
{
    const bvox_geometry *g = &info->geometry;
    const char *unit = g->unit[0] ? g->unit : "";
    const char *sep = g->unit[0] ? " " : "";
    char cu[32];
    const bvox_dims d = info->dims;
    double total = (double)d.nx * (double)d.ny * (double)d.nz;

    if (source) fprintf(f, "%-14s%s\n", "file:", source);
    if (format) fprintf(f, "%-14s%s\n", "format:", format);
    fprintf(f, "%-14s%d x %d x %d voxels\n", "dimensions:", d.nx, d.ny, d.nz);
    fprintf(f, "%-14s%g x %g x %g %s\n", "voxel size:", g->spacing[0], g->spacing[1],
            g->spacing[2], g->unit[0] ? g->unit : "(no unit)");
    /* + 0.0 turns a -0 (a negated zero origin) into 0 for display. */
    fprintf(f, "%-14s%g, %g, %g%s%s\n", "origin:", g->origin[0] + 0.0, g->origin[1] + 0.0,
            g->origin[2] + 0.0, sep, unit);
    fprintf(f, "%-14s%lld voxels (%.4g%% of %.0f)\n", "count:", (long long)info->count,
            total > 0 ? 100.0 * (double)info->count / total : 0.0, total);
    fprintf(f, "%-14s%.6g %s", "volume:", info->volume, cube_unit(info, cu, sizeof cu));
    double k = to_mm3(g->unit);
    if (k > 0 && strcmp(g->unit, "mm") != 0) fprintf(f, " (%.6g mm^3)", info->volume * k);
    fputc('\n', f);
    if (info->empty) {
        fprintf(f, "%-14s%s\n", "bounding box:", "none (no 1-voxels)");
        return;
    }
    const bvox_box b = info->bbox;
    fprintf(f, "%-14sx %d..%d, y %d..%d, z %d..%d (voxel indices, inclusive)\n",
            "bounding box:", b.x0, b.x1 - 1, b.y0, b.y1 - 1, b.z0, b.z1 - 1);
    fprintf(f, "%-14s%g x %g x %g%s%s\n", "extent:", (b.x1 - b.x0) * g->spacing[0],
            (b.y1 - b.y0) * g->spacing[1], (b.z1 - b.z0) * g->spacing[2], sep, unit);
    double lo[3], hi[3];
    bbox_physical(info, lo, hi);
    fprintf(f, "%-14sx %g..%g, y %g..%g, z %g..%g%s%s\n", "position:", lo[0], hi[0], lo[1],
            hi[1], lo[2], hi[2], sep, unit);
}

void cli_print_info_json_io(FILE *f, const bvox_info *info, const char *source,
                            const char *format, const char *input, const char *output)
{
    cli_json j;
    cli_json_init(&j, f);
    cli_json_begin_object(&j);
    cli_info_json_fields(&j, info, source, format);
    cli_json_io(&j, input, output);
    cli_json_end_object(&j);
    fputc('\n', f);
}

bvox_status cli_print_volume_json(const bvox_volume *vol, const char *input, const char *output,
                                  const char *format,
                                  void (*extra)(cli_json *j, const bvox_volume *vol, void *ctx),
                                  void *ctx)
{
    bvox_info info;
    bvox_status st = bvox_info_compute(vol, &info);
    if (st) return st;
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_info_json_fields(&j, &info, output, format ? format : bvox_format_for_path(output));
    cli_json_io(&j, input, output);
    if (extra) extra(&j, vol, ctx);
    cli_json_end_object(&j);
    fputc('\n', stdout);
    return BVOX_OK;
}

void cli_json_io(cli_json *j, const char *input, const char *output)
{
    cli_json_key(j, "input");
    cli_json_string(j, input);
    cli_json_key(j, "output");
    cli_json_string(j, output);
}

void cli_info_json_fields(cli_json *j, const bvox_info *info, const char *source,
                          const char *format)
{
    const bvox_geometry *g = &info->geometry;
    char cu[32];
    cli_json_key(j, "file");
    cli_json_string(j, source);
    cli_json_key(j, "format");
    cli_json_string(j, format);
    cli_json_key(j, "dims");
    const int64_t dims[3] = {info->dims.nx, info->dims.ny, info->dims.nz};
    cli_json_int_array(j, dims, 3);
    cli_json_key(j, "voxel_size");
    cli_json_double_array(j, g->spacing, 3);
    /* the same under the name the library, Python and reconstruct's report
     * use (docs/JSON.md: keys are added, never renamed) */
    cli_json_key(j, "spacing");
    cli_json_double_array(j, g->spacing, 3);
    cli_json_key(j, "unit");
    cli_json_string(j, g->unit);
    cli_json_key(j, "origin");
    cli_json_double_array(j, g->origin, 3);
    cli_json_key(j, "count");
    cli_json_int(j, info->count);
    cli_json_key(j, "voxels"); /* = count; "count" means components in `components` */
    cli_json_int(j, info->count);
    cli_json_key(j, "volume");
    cli_json_double(j, info->volume);
    cli_json_key(j, "volume_unit");
    cli_json_string(j, cube_unit(info, cu, sizeof cu));
    double k = to_mm3(g->unit);
    cli_json_key(j, "volume_mm3");
    if (k > 0) cli_json_double(j, info->volume * k);
    else cli_json_null(j);
    /* Inclusive voxel indices (the library's box is half-open). */
    cli_json_key(j, "bbox");
    if (info->empty) {
        cli_json_null(j);
    } else {
        const bvox_box b = info->bbox;
        const int64_t lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1 - 1, b.y1 - 1, b.z1 - 1};
        cli_json_begin_object(j);
        cli_json_key(j, "min");
        cli_json_int_array(j, lo, 3);
        cli_json_key(j, "max");
        cli_json_int_array(j, hi, 3);
        cli_json_end_object(j);
    }
    /* Outer faces of those voxels in world coordinates. */
    cli_json_key(j, "bbox_physical");
    if (info->empty) {
        cli_json_null(j);
    } else {
        double lo[3], hi[3];
        bbox_physical(info, lo, hi);
        cli_json_begin_object(j);
        cli_json_key(j, "min");
        cli_json_double_array(j, lo, 3);
        cli_json_key(j, "max");
        cli_json_double_array(j, hi, 3);
        cli_json_end_object(j);
    }
}
