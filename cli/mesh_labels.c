/*
 * mesh_labels.c — `bvox mesh IN --labels all|L,L,... -o DIR`: the label
 * volume read once (cli_labels_load), one cuberille mesh per chosen label
 * written into the folder DIR as LABEL_NAME.EXT (bvox_labelset_write_meshes:
 * touching labels share their boundary faces exactly). Names come from
 * --lut; the folder appears only when every mesh is written. With -o
 * FILE.ply or FILE.obj (single): one file, one object per label in the
 * table's colours (bvox_labelset_write_mesh_file).
 */
#include "args.h"
#include "cli.h"

#include <stdlib.h>
#include <string.h>

/* "all" or a comma-separated list of labels -> indices into set->objects. */
static int parse_list(const char *list, const bvox_labelset *set, const char *in, int64_t **out,
                      int64_t *n)
{
    *out = NULL;
    *n = 0;
    int64_t cap = set->n ? set->n : 1, m = 0;
    if (strcmp(list, "all")) {
        cap = 1;
        for (const char *c = list; *c; c++) cap += *c == ',';
    }
    int64_t *idx = malloc((size_t)cap * sizeof *idx);
    if (!idx) return cli_usage_error("mesh", "out of memory");
    if (!strcmp(list, "all")) {
        for (int64_t i = 0; i < set->n; i++) idx[m++] = i;
    } else {
        char *copy = strdup(list), *save = NULL;
        if (!copy) {
            free(idx);
            return cli_usage_error("mesh", "out of memory");
        }
        for (char *t = strtok_r(copy, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
            int64_t label;
            if (cli_parse_int64(t, INT64_MIN, INT64_MAX, &label) || label == 0) {
                free(copy);
                free(idx);
                return cli_usage_error("mesh", "--labels takes 'all' or non-zero labels "
                                               "separated by commas, not '%s'", list);
            }
            int64_t k = bvox_labelset_find(set, label);
            if (k < 0) {
                fprintf(stderr, "bvox: %s: no voxel has label %lld\n", in, (long long)label);
                free(copy);
                free(idx);
                return CLI_FAIL;
            }
            idx[m++] = k;
        }
        free(copy);
    }
    *out = idx;
    *n = m;
    return CLI_OK;
}

int cli_mesh_labels(const char *in, const cli_read_args *ra, const char *labels, const char *lut,
                    int64_t limit, const char *out, const char *fmt, int ascii, int single)
{
    if (!strcmp(labels, "")) return cli_usage_error("mesh", "--labels needs 'all' or a list");
    bvox_labelset *set;
    bvox_label_table *table;
    if (cli_labels_load(in, ra, lut, limit, &set, &table)) return cli_fail();
    int64_t *idx, n;
    int rc = parse_list(labels, set, in, &idx, &n);
    const char **names = NULL;
    unsigned char *rgb = NULL;
    if (rc == CLI_OK && n > 0) {
        names = calloc((size_t)n, sizeof *names);
        rgb = malloc((size_t)n * 3);
        if (!names || !rgb) rc = cli_usage_error("mesh", "out of memory");
        int colored = 0;
        for (int64_t i = 0; names && rgb && i < n; i++) {
            int64_t label = set->objects[idx[i]].label;
            const bvox_label_entry *e = bvox_label_table_find(table, label);
            names[i] = e ? e->name : NULL;
            colored += e && e->has_color;
            if (e && e->has_color) memcpy(rgb + 3 * i, e->rgba, 3);
            else memset(rgb + 3 * i, 200, 3); /* no colour in a table that has some: gray */
        }
        if (!colored) { /* a table without colours (or none): bvox's palette */
            free(rgb);
            rgb = NULL;
        }
    }
    if (rc == CLI_OK && single) {
        if (bvox_labelset_write_mesh_file(set, idx, n, names, rgb, out, ascii)) rc = cli_fail();
        else
            printf("%s: %lld labels in one file (cuberille, coloured objects)\n", out,
                   (long long)n);
    } else if (rc == CLI_OK) {
        if (bvox_labelset_write_meshes(set, idx, n, names, out, fmt, ascii)) rc = cli_fail();
        else
            printf("%s: %lld meshes (cuberille, %s)\n", out, (long long)n, fmt);
    }
    free(rgb);
    free(names);
    free(idx);
    bvox_labelset_destroy(set);
    bvox_label_table_destroy(table);
    return rc;
}
