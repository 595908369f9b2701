/*
 * cmd_mesh.c — `bvox mesh IN -o OUT`: bvox_read with the shared read
 * options, bvox_mesh_from_volume (marching cubes or cuberille, optional
 * Taubin smoothing), bvox_mesh_write in the format OUT's extension names
 * (STL, PLY, OBJ, OFF; binary unless --ascii). Prints one summary line.
 * A .zarr over --max-memory is meshed by slabs and written as it goes
 * (bvox__stream_mesh_write): the whole mesh is never in memory.
 * With --labels, a label volume becomes one mesh per label in a folder, or
 * one .ply/.obj file with a coloured object per label (cli/mesh_labels.c).
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"
#include "outofcore.h"

#include <string.h>
#include <sys/stat.h>

typedef struct mesh_args {
    const char *in, *out, *fmt;
    const char *labels, *lut;
    int64_t max_labels;
    int ascii, json;
    bvox_mesh_opts mo;
    cli_read_args ra;
} mesh_args;

#define A(member) CLI_AT(mesh_args, member)

static const char *const methods[] = {"mc", "cuberille", NULL}; /* bvox_mesh_method order */

static const cli_opt mesh_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT", "the mesh file: .stl (binary), .ply (binary), .obj, .off",
     A(out)},
    {"--method", 0, CLI_CHOICE, NULL, "marching cubes or voxel faces", A(mo.method), .def = "mc",
     .choices = methods, .bad = "--method must be mc or cuberille, not '%s'"},
    {"--smooth", 0, CLI_INT, "N", "iterations of Taubin lambda/mu smoothing (keeps the volume)",
     A(mo.smooth), .def = "0", .lo = 0, .hi = 100000,
     .bad = "--smooth needs an integer 0..100000, not '%s'"},
    {"--lambda", 0, CLI_DOUBLE, "L", "Taubin's lambda factor", A(mo.lambda), .def = "0.5",
     .flags = CLI_MIN_OPEN | CLI_MAX_OPEN, .min = 0, .max = 1,
     .bad = "--lambda needs a number in (0, 1), not '%s'"},
    {"--mu", 0, CLI_DOUBLE, "M", "Taubin's mu factor", A(mo.mu), .def = "-0.53",
     .flags = CLI_MIN_OPEN | CLI_MAX_OPEN, .min = -1, .max = 0,
     .bad = "--mu needs a number in (-1, 0), not '%s'"},
    {"--ascii", 0, CLI_FLAG, NULL, "ASCII STL or PLY instead of binary", A(ascii)},
    {"--mesh-format", 0, CLI_STR, "NAME", "stl, ply, obj or off, whatever OUT's extension",
     A(fmt), .choices = cli_mesh_formats},
    {"--labels", 0, CLI_STR, "all|L,L,...",
     "IN is a label volume: one cuberille mesh per label in the folder OUT, named "
     "LABEL_NAME.EXT (--mesh-format, default ply), or with OUT a .ply or .obj file, one "
     "file with one coloured object per label; touching labels share their boundary",
     A(labels)},
    {"--lut", 0, CLI_PATH, "TABLE",
     "label names (and colours) for the file or object names (see 'bvox labels')",
     A(lut)},
    {"--max-labels", 0, CLI_INT, "N", "refuse label volumes with more distinct labels",
     A(max_labels), .def = "65535", .lo = 1, .hi = 2147483647,
     .bad = "--max-labels needs a count from 1 to 2147483647, not '%s'"},
    {"--json", 0, CLI_FLAG, NULL,
     "print one JSON object instead of the summary line: file, format, input, output, method, "
     "smooth, vertices, triangles, volume, surface_area, watertight (not with --labels)",
     A(json)},
    {NULL},
};
static const cli_group mesh_group = {"Options", mesh_opts, NULL};
static const cli_pos mesh_pos[] = {
    {"IN", "the volume to mesh", A(in)},
    {NULL},
};

const cli_spec cli_spec_mesh = {
    .name = "mesh",
    .summary = "surface mesh (marching cubes or voxel faces) as STL, PLY, OBJ, OFF",
    .usage = "IN -o OUT.stl|ply|obj|off [--method mc|cuberille] [--smooth N] [--ascii] [options]",
    .about = "The surface of the 1-voxels of IN as a closed, manifold triangle mesh, in the\n"
             "world coordinates of IN's voxel size and origin, triangles facing outward,\n"
             "vertices shared. Marching cubes puts vertices at the midpoints of the voxel\n"
             "edges that cross the surface; cuberille gives the voxel faces themselves\n"
             "(its volume is the voxel volume exactly). Where voxels touch only along an\n"
             "edge or at a corner, the 1-voxels are taken as 6-connected (separate sheets).\n",
    .pos = mesh_pos,
    .uses = {{&mesh_group, 0}, CLI_USE_READ(mesh_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox mesh embryo.nii.gz -o embryo.stl\n"
                "  bvox mesh atlas.nii.gz --label 37 -o hippocampus.ply --smooth 10\n"
                "  bvox mesh cells.tif -o cells.obj --method cuberille\n"
                "  bvox mesh aal.nii.gz --labels all --lut aal.nii.txt -o aal_meshes/\n"
                "  bvox mesh seg.nii.gz --labels 1,5,7 --lut colors.txt -o organs.ply\n",
};

/* The keys of meshinfo --json where they mean the same (vertices,
 * triangles, volume, surface_area, watertight), and what was made. */
static void print_json(const bvox_mesh_info *mi, const char *in, const char *out,
                       const char *fmt, const bvox_mesh_opts *mo)
{
    cli_json j;
    cli_json_init(&j, stdout);
    cli_json_begin_object(&j);
    cli_json_key(&j, "file");
    cli_json_string(&j, out);
    cli_json_key(&j, "format");
    cli_json_string(&j, fmt);
    cli_json_io(&j, in, out);
    cli_json_key(&j, "method");
    cli_json_string(&j, mo->method == BVOX_MESH_MC ? "mc" : "cuberille");
    cli_json_key(&j, "smooth");
    cli_json_int(&j, mo->smooth);
    cli_json_key(&j, "vertices");
    cli_json_int(&j, mi->vertices);
    cli_json_key(&j, "triangles");
    cli_json_int(&j, mi->triangles);
    cli_json_key(&j, "volume");
    cli_json_double(&j, mi->volume);
    cli_json_key(&j, "surface_area");
    cli_json_double(&j, mi->area);
    cli_json_key(&j, "watertight");
    cli_json_bool(&j, mi->watertight);
    cli_json_end_object(&j);
    fputc('\n', stdout);
}

int cmd_mesh(int argc, char **argv)
{
    const char *cmd = "mesh";
    mesh_args a = {.mo = BVOX_MESH_OPTS_INIT};
    cli_read_args_init(&a.ra);
    CLI_PARSE_OR_RETURN(&cli_spec_mesh, argc, argv, &a);
    const char *in = a.in, *out = a.out, *fmt = a.fmt;
    bvox_mesh_opts mo = a.mo;
    if (!in) return cli_usage_error(cmd, "needs IN");
    int method_given = 0; /* the table's default cannot tell */
    for (int i = 1; i < argc && strcmp(argv[i], "--"); i++)
        if (!strncmp(argv[i], "--method", 8)) method_given = 1;
    if (a.labels || a.lut) {
        if (!a.labels) return cli_usage_error(cmd, "--lut goes with --labels");
        if (!out) return cli_usage_error(cmd, "needs -o FOLDER for the per-label meshes");
        /* OUT.ply / OUT.obj that is not an existing folder: one file */
        const char *ext = bvox_mesh_format_for_path(out);
        struct stat sb;
        size_t olen = strlen(out);
        int single = ext && (!strcmp(ext, "ply") || !strcmp(ext, "obj")) &&
                     out[olen - 1] != '/' && !(stat(out, &sb) == 0 && S_ISDIR(sb.st_mode));
        if (single && fmt && strcmp(fmt, ext))
            return cli_usage_error(cmd, "--mesh-format %s does not match %s", fmt, out);
        if (method_given && mo.method != BVOX_MESH_CUBERILLE)
            return cli_usage_error(cmd, "per-label meshes are cuberille (shared boundaries); "
                                        "--method mc does not apply");
        if (mo.smooth > 0)
            return cli_usage_error(cmd, "per-label meshes are not smoothed (shared "
                                        "boundaries would part)");
        if (a.json) return cli_usage_error(cmd, "--json goes with one mesh, not --labels");
        return cli_mesh_labels(in, &a.ra, a.labels, a.lut, a.max_labels, out, fmt ? fmt : "ply",
                               a.ascii, single);
    }
    if (!out) return cli_usage_error(cmd, "needs -o OUT (.stl, .ply, .obj or .off)");
    if (!fmt && !bvox_mesh_format_for_path(out))
        return cli_usage_error(cmd, "%s: the extension must be .stl, .ply, .obj or .off", out);
    if (fmt && strcmp(fmt, "stl") && strcmp(fmt, "ply") && strcmp(fmt, "obj") &&
        strcmp(fmt, "off"))
        return cli_usage_error(cmd, "--mesh-format must be stl, ply, obj or off");
    if (mo.lambda > -mo.mu - 1e-12 && mo.smooth > 0)
        return cli_usage_error(cmd, "Taubin smoothing needs mu < -lambda");

    bvox_mesh *m = NULL;
    bvox_status st;
    bvox__slab_source src;
    if (cli_ooc_open(in, &a.ra, &src) == 1) { /* a .zarr over --max-memory: by slabs */
        const char *what = mo.method != BVOX_MESH_MC ? "--method cuberille"
                           : mo.smooth > 0           ? "--smooth"
                                                     : NULL;
        if (what) {
            bvox__slab_source_close(&src);
            return cli_ooc_refuse(cmd, in, what);
        }
        /* written slab by slab as it is made: the mesh is never held whole */
        bvox_mesh_info mi;
        st = bvox__stream_mesh_write(&src, out, fmt, a.ascii, &mi, a.json);
        bvox__slab_source_close(&src);
        if (st) return cli_fail();
        if (a.json) print_json(&mi, in, out, fmt ? fmt : bvox_mesh_format_for_path(out), &mo);
        else
            printf("%s: %lld vertices, %lld triangles (marching cubes)\n", out,
                   (long long)mi.vertices, (long long)mi.triangles);
        return CLI_OK;
    } else {
        bvox_volume *vol = NULL;
        if (cli_read_volume(in, &a.ra, &vol)) return cli_fail();
        st = bvox_mesh_from_volume(vol, &mo, &m);
        bvox_volume_destroy(vol);
    }
    if (!st) st = bvox_mesh_write(out, m, fmt, a.ascii);
    if (!st && a.json) {
        bvox_mesh_info mi;
        st = bvox_mesh_measure(m, &mi);
        if (!st) print_json(&mi, in, out, fmt ? fmt : bvox_mesh_format_for_path(out), &mo);
    } else if (!st) {
        printf("%s: %lld vertices, %lld triangles (%s%s)\n", out, (long long)m->nvertices,
               (long long)m->ntriangles, mo.method == BVOX_MESH_MC ? "marching cubes" : "cuberille",
               mo.smooth ? ", smoothed" : "");
    }
    bvox_mesh_destroy(m);
    return st ? cli_fail() : CLI_OK;
}
