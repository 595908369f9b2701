/*
 * cmd_meshinfo.c — `bvox meshinfo MESH`: bvox_mesh_read then
 * bvox_mesh_measure: vertex and triangle counts, enclosed volume (signed
 * tetrahedra), area, bounding box and whether the mesh is closed (every
 * edge on exactly two triangles), as aligned text or one JSON object.
 */
#include "args.h"
#include "cli.h"
#include "json.h"

#include <string.h>

static void help(FILE *f)
{
    fputs("Usage: bvox meshinfo MESH [--json] [options]\n"
          "\n"
          "Read a mesh (STL binary or ASCII, OBJ, PLY, OFF) and print its vertex and\n"
          "triangle counts, enclosed volume (sum of signed tetrahedra: positive when the\n"
          "triangles face outward), surface area, bounding box, and whether it is\n"
          "watertight (every edge on exactly two triangles); otherwise how many edges\n"
          "are open (on one triangle) or non-manifold (on more than two).\n"
          "\n"
          "Options:\n"
          "  --json                one JSON object: vertices, triangles, volume, area,\n"
          "                        bbox {min, max}, watertight, edges, boundary_edges,\n"
          "                        nonmanifold_edges, inconsistent_edges, open_edges\n"
          "  --mesh-format NAME    stl, obj, ply or off (default: by extension/content)\n"
          "  --help                show this help\n",
          f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox meshinfo bunny.off\n"
          "  bvox meshinfo part.stl --json\n",
          f);
}

int cmd_meshinfo(int argc, char **argv)
{
    const char *cmd = "meshinfo", *in = NULL, *value = NULL, *fmt = NULL;
    int json = 0, options_done = 0, r;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
            if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
        } else if (!strcmp(arg, "--json")) {
            json = 1;
        } else if ((r = cli_match_value(cmd, argc, argv, &i, "--mesh-format", &value))) {
            if (r == CLI_ARG_BAD) return CLI_USAGE;
            fmt = value;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, NULL) == CLI_ARG_BAD) {
            return CLI_USAGE;
        }
    }
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
