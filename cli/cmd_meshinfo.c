/*
 * cmd_meshinfo.c — `bvox meshinfo MESH`: bvox_mesh_read then
 * bvox_mesh_measure: vertex and triangle counts, enclosed volume (signed
 * tetrahedra), area, bounding box and whether the mesh is closed (every
 * edge on exactly two triangles), as aligned text or one JSON object.
 */
#include "args.h"
#include "cli.h"
#include "json.h"
#include "opts.h"

#include <string.h>

typedef struct meshinfo_args {
    const char *in, *fmt;
    int json;
} meshinfo_args;

#define A(member) CLI_AT(meshinfo_args, member)

static const cli_opt meshinfo_opts[] = {
    {"--json", 0, CLI_FLAG, NULL,
     "one JSON object: vertices, triangles, volume, area, bbox {min, max}, watertight, edges, "
     "boundary_edges, nonmanifold_edges, inconsistent_edges, open_edges",
     A(json)},
    {"--mesh-format", 0, CLI_STR, "NAME", "stl, obj, ply or off (default: by extension/content)",
     A(fmt), .choices = cli_mesh_formats},
    {NULL},
};
static const cli_group meshinfo_group = {"Options", meshinfo_opts, NULL};
static const cli_pos meshinfo_pos[] = {
    {"MESH", "the mesh file", A(in)},
    {NULL},
};

const cli_spec cli_spec_meshinfo = {
    .name = "meshinfo",
    .summary = "mesh counts, volume, area, bounding box, watertightness",
    .usage = "MESH [--json] [options]",
    .about = "Read a mesh (STL binary or ASCII, OBJ, PLY, OFF) and print its vertex and\n"
             "triangle counts, enclosed volume (sum of signed tetrahedra: positive when the\n"
             "triangles face outward), surface area, bounding box, and whether it is\n"
             "watertight (every edge on exactly two triangles); otherwise how many edges\n"
             "are open (on one triangle) or non-manifold (on more than two).\n",
    .pos = meshinfo_pos,
    .uses = {{&meshinfo_group, 0}, CLI_USE_PROCESS},
    .examples = "  bvox meshinfo bunny.off\n"
                "  bvox meshinfo part.stl --json\n",
};

int cmd_meshinfo(int argc, char **argv)
{
    const char *cmd = "meshinfo";
    meshinfo_args a = {0};
    CLI_PARSE_OR_RETURN(&cli_spec_meshinfo, argc, argv, &a);
    const char *in = a.in, *fmt = a.fmt;
    int json = a.json;
    if (!in) return cli_usage_error(cmd, "needs MESH");
    bvox_mesh *m = NULL;
    if (bvox_mesh_read(in, fmt, &m)) return cli_fail();
    bvox_mesh_info info;
    bvox_status st = bvox_mesh_measure(m, &info);
    bvox_mesh_destroy(m);
    if (st) return cli_fail();
    int64_t open_edges = info.boundary_edges + info.nonmanifold_edges;
    if (json) {
        cli_json j;
        cli_json_init(&j, stdout);
        cli_json_begin_object(&j);
        cli_json_key(&j, "file");
        cli_json_string(&j, in);
        cli_json_io(&j, in, NULL);
        cli_json_key(&j, "vertices");
        cli_json_int(&j, info.vertices);
        cli_json_key(&j, "triangles");
        cli_json_int(&j, info.triangles);
        cli_json_key(&j, "volume");
        cli_json_double(&j, info.volume);
        cli_json_key(&j, "area");
        cli_json_double(&j, info.area);
        cli_json_key(&j, "surface_area"); /* = area, the name measure uses */
        cli_json_double(&j, info.area);
        cli_json_key(&j, "bbox");
        cli_json_begin_object(&j);
        cli_json_key(&j, "min");
        cli_json_double_array(&j, info.bbox_min, 3);
        cli_json_key(&j, "max");
        cli_json_double_array(&j, info.bbox_max, 3);
        cli_json_end_object(&j);
        cli_json_key(&j, "watertight");
        cli_json_bool(&j, info.watertight);
        cli_json_key(&j, "edges");
        cli_json_int(&j, info.edges);
        cli_json_key(&j, "open_edges");
        cli_json_int(&j, open_edges);
        cli_json_key(&j, "boundary_edges");
        cli_json_int(&j, info.boundary_edges);
        cli_json_key(&j, "nonmanifold_edges");
        cli_json_int(&j, info.nonmanifold_edges);
        cli_json_key(&j, "inconsistent_edges");
        cli_json_int(&j, info.inconsistent_edges);
        cli_json_key(&j, "degenerate_triangles");
        cli_json_int(&j, info.degenerate_triangles);
        cli_json_end_object(&j);
        putchar('\n');
        return CLI_OK;
    }
    printf("%-14s%s\n", "file:", in);
    printf("%-14s%lld\n", "vertices:", (long long)info.vertices);
    printf("%-14s%lld\n", "triangles:", (long long)info.triangles);
    printf("%-14s%.9g\n", "volume:", info.volume);
    printf("%-14s%.9g\n", "area:", info.area);
    printf("%-14sx %.9g..%.9g, y %.9g..%.9g, z %.9g..%.9g\n", "bbox:", info.bbox_min[0],
           info.bbox_max[0], info.bbox_min[1], info.bbox_max[1], info.bbox_min[2],
           info.bbox_max[2]);
    if (info.watertight) {
        printf("%-14syes\n", "watertight:");
    } else {
        printf("%-14sno: %lld open edges (%lld on one triangle, %lld on more than two)\n",
               "watertight:", (long long)open_edges, (long long)info.boundary_edges,
               (long long)info.nonmanifold_edges);
    }
    if (info.inconsistent_edges)
        printf("%-14s%lld edges where neighbouring triangles disagree\n", "orientation:",
               (long long)info.inconsistent_edges);
    return CLI_OK;
}
