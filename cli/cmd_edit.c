/*
 * cmd_edit.c — `bvox edit IN -o OUT ACTION...`: voxel edits applied in the
 * order given (set or clear a voxel, fill, clear or keep a box, keep one
 * side of a plane), each one library call (bvox_edit_*, bvox_cut_plane) that
 * reports the region it changed; prints those regions and the count before
 * and after, then writes OUT (temporary file, renamed on success).
 */
#include "cli.h"
#include "manip.h"

#include <stdlib.h>
#include <string.h>

typedef enum kind { SET, CLEAR, FILL_BOX, CLEAR_BOX, KEEP_BOX, KEEP_ABOVE, KEEP_BELOW, NKINDS } kind;
static const char *const kind_names[NKINDS] = {"set",      "clear",      "fill-box",  "clear-box",
                                               "keep-box", "keep-above", "keep-below"};

typedef struct action {
    kind k;
    const char *arg;
    int32_t v[3];
    bvox_box box;
    double plane[4];
    bvox_box changed;
} action;

static void help(FILE *f)
{
    fputs("Usage: bvox edit IN -o OUT ACTION... [options]\n"
          "\n"
          "Edit a volume voxel by voxel or region by region; the actions are applied\n"
          "in the order given and each may be repeated. Prints the region each action\n"
          "changed (the voxels whose value changed, as inclusive indices) and the\n"
          "count of 1-voxels before and after.\n"
          "\n"
          "Actions:\n"
          "  --set X,Y,Z           set one voxel (outside the volume: an error)\n"
          "  --clear X,Y,Z         clear one voxel\n"
          "  --fill-box BOX        set every voxel of BOX\n"
          "  --clear-box BOX       clear every voxel of BOX\n"
          "  --keep-box BOX        clear every voxel outside BOX (spatial selection)\n"
          "  --keep-above A,B,C,D  clear the voxels whose centre has A*x+B*y+C*z+D < 0\n"
          "  --keep-below A,B,C,D  clear the voxels whose centre has A*x+B*y+C*z+D >= 0\n"
          "                        (x, y, z in world coordinates, as in 'bvox cut')\n"
          "\n"
          "BOX is X0:X1,Y0:Y1,Z0:Z1 in voxel indices, both ends included (as the\n"
          "bounding box 'bvox info' prints); an interval may be one index (5), open\n"
          "at an end (5: or :9) or the whole axis (:). Boxes are clipped to the\n"
          "volume.\n"
          "\n"
          "Options:\n"
          "  -o, --output OUT      the file to write (required)\n"
          "  --json                print the report as one JSON object\n",
          f);
    fprintf(f, "  --output-format NAME  force the output format (%s)\n", bvox_format_list());
    fputs(CLI_FORCE_HELP, f);
    fputs("  --help                show this help\n", f);
    cli_print_read_options_help(f);
    cli_print_process_options_help(f);
    fputs("\nExamples:\n"
          "  bvox edit embryo.nii -o fixed.nii --set 10,12,40 --clear 11,12,40\n"
          "  bvox edit embryo.nii -o part.nii --keep-box 20:80,:,0:63\n"
          "  bvox edit scan.nii.gz -o cut.nii.gz --clear-box :,:,100: --keep-above 0,0,1,-5\n",
          f);
}

/* One inclusive interval "A:B", "A", "A:", ":B", ":" into half-open [lo, hi). */
static int parse_interval(const char *s, size_t n, int32_t *lo, int32_t *hi)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *colon = strchr(buf, ':');
    int64_t a = INT32_MIN, b = INT32_MAX - 1;
    const int64_t lim = 1000000000;
    if (!colon) {
        if (cli_parse_int64(buf, -lim, lim, &a)) return -1;
        b = a;
    } else {
        *colon = '\0';
        if (buf[0] && cli_parse_int64(buf, -lim, lim, &a)) return -1;
        if (colon[1] && cli_parse_int64(colon + 1, -lim, lim, &b)) return -1;
        if (a > b) return -1;
    }
    *lo = (int32_t)a;
    *hi = (int32_t)(b + 1);
    return 0;
}

static int parse_box(const char *s, bvox_box *box)
{
    int32_t lo[3], hi[3];
    const char *p = s;
    for (int k = 0; k < 3; k++) {
        size_t n = strcspn(p, ",");
        if (parse_interval(p, n, &lo[k], &hi[k])) return -1;
        p += n;
        if (k < 2 && *p++ != ',') return -1;
    }
    if (*p) return -1;
    *box = (bvox_box){lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
    return 0;
}

static int parse_voxel(const char *s, int32_t v[3])
{
    double d[3];
    if (cli_parse_triple(s, d)) return -1;
    for (int k = 0; k < 3; k++) {
        if (d[k] != (double)(int32_t)d[k]) return -1;
        v[k] = (int32_t)d[k];
    }
    return 0;
}

static int parse_action(const char *cmd, kind k, const char *v, action *a)
{
    a->k = k;
    a->arg = v;
    switch (k) {
    case SET:
    case CLEAR:
        if (parse_voxel(v, a->v))
            return cli_usage_error(cmd, "--%s: '%s' is not X,Y,Z (voxel indices)", kind_names[k], v);
        break;
    case FILL_BOX:
    case CLEAR_BOX:
    case KEEP_BOX:
        if (parse_box(v, &a->box))
            return cli_usage_error(cmd, "--%s: '%s' is not X0:X1,Y0:Y1,Z0:Z1 (inclusive indices)",
                                   kind_names[k], v);
        break;
    default:
        if (cli_parse_plane(v, a->plane))
            return cli_usage_error(cmd, "--%s: '%s' is not A,B,C,D", kind_names[k], v);
        if (!a->plane[0] && !a->plane[1] && !a->plane[2])
            return cli_usage_error(cmd, "--%s: the plane normal A,B,C is zero", kind_names[k]);
        break;
    }
    return CLI_OK;
}

static bvox_status apply(bvox_volume *vol, action *a)
{
    switch (a->k) {
    case SET:
    case CLEAR:
        return bvox_edit_voxel(vol, a->v[0], a->v[1], a->v[2], a->k == SET, &a->changed);
    case FILL_BOX:
    case CLEAR_BOX: return bvox_edit_fill_box(vol, a->box, a->k == FILL_BOX, &a->changed);
    case KEEP_BOX: return bvox_edit_keep_box(vol, a->box, &a->changed);
    default:
        return bvox_cut_plane(vol, a->plane[0], a->plane[1], a->plane[2], a->plane[3],
                              a->k == KEEP_ABOVE, &a->changed);
    }
}

static void report(const action *acts, int n, int64_t before, int64_t after, const char *out,
                   int json)
{
    bvox_box all = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < n; i++) cli_box_union(&all, &acts[i].changed);
    if (json) {
        cli_json j;
        cli_json_init(&j, stdout);
        cli_json_begin_object(&j);
        cli_json_key(&j, "file");
        cli_json_string(&j, out);
        cli_json_key(&j, "actions");
        cli_json_begin_array(&j);
        for (int i = 0; i < n; i++) {
            cli_json_begin_object(&j);
            cli_json_key(&j, "action");
            cli_json_string(&j, kind_names[acts[i].k]);
            cli_json_key(&j, "arg");
            cli_json_string(&j, acts[i].arg);
            cli_json_key(&j, "changed");
            cli_json_box(&j, &acts[i].changed);
            cli_json_end_object(&j);
        }
        cli_json_end_array(&j);
        cli_json_key(&j, "changed");
        cli_json_box(&j, &all);
        cli_json_key(&j, "count_before");
        cli_json_int(&j, before);
        cli_json_key(&j, "count_after");
        cli_json_int(&j, after);
        cli_json_end_object(&j);
        fputc('\n', stdout);
        return;
    }
    for (int i = 0; i < n; i++) {
        printf("--%s %s -> ", kind_names[acts[i].k], acts[i].arg);
        if (acts[i].changed.x0 >= acts[i].changed.x1) {
            puts("no change");
        } else {
            fputs("changed ", stdout);
            cli_print_box(stdout, &acts[i].changed);
            fputc('\n', stdout);
        }
    }
    printf("%-14s", "changed:");
    cli_print_box(stdout, &all);
    puts(all.x0 < all.x1 ? " (voxel indices, inclusive)" : "");
    printf("%-14s%lld -> %lld voxels\n", "count:", (long long)before, (long long)after);
}

int cmd_edit(int argc, char **argv)
{
    const char *cmd = "edit", *in = NULL, *out = NULL, *v = NULL;
    cli_read_args ra;
    cli_read_args_init(&ra);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    int options_done = 0, r, json = 0, nacts = 0;
    action *acts = calloc((size_t)argc, sizeof *acts);
    if (!acts) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    int rc = CLI_USAGE;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int k = -1;
        if (options_done || !cli_is_option(arg)) {
            if (in) {
                cli_usage_error(cmd, "unexpected argument '%s'", arg);
                goto done;
            }
            in = arg;
            continue;
        }
        if (!strcmp(arg, "--")) {
            options_done = 1;
            continue;
        }
        if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            help(stdout);
            rc = CLI_OK;
            goto done;
        }
        if (!strcmp(arg, "--json")) {
            json = 1;
            continue;
        }
        if ((r = cli_parse_output_option(cmd, argc, argv, &i, &out, &wo))) {
            if (r == CLI_ARG_BAD) goto done;
            continue;
        }
        for (int t = 0; t < NKINDS && k < 0; t++) {
            char name[32];
            snprintf(name, sizeof name, "--%s", kind_names[t]);
            if ((r = cli_match_value(cmd, argc, argv, &i, name, &v))) {
                if (r == CLI_ARG_BAD) goto done;
                k = t;
            }
        }
        if (k >= 0) {
            if (parse_action(cmd, (kind)k, v, &acts[nacts]) != CLI_OK) goto done;
            nacts++;
        } else if (cli_parse_shared_option(cmd, argc, argv, &i, &ra) == CLI_ARG_BAD) {
            goto done;
        }
    }
    if (!in) {
        cli_usage_error(cmd, "missing the input file IN");
        goto done;
    }
    if (!out) {
        cli_usage_error(cmd, "missing -o OUT");
        goto done;
    }
    if (!nacts) {
        cli_usage_error(cmd, "no action given (--set, --clear, --fill-box, ...)");
        goto done;
    }
    if (cli_check_output(cmd, out, &wo) != CLI_OK) goto done;

    bvox_volume *vol = NULL;
    rc = CLI_FAIL;
    if (cli_read_volume(in, &ra, &vol)) {
        cli_fail();
        goto done;
    }
    int64_t before = bvox_volume_count(vol);
    bvox_status st = BVOX_OK;
    for (int i = 0; i < nacts && !st; i++) {
        st = apply(vol, &acts[i]);
        if (st) {
            char msg[1100];
            snprintf(msg, sizeof msg, "%s", bvox_errmsg());
            fprintf(stderr, "bvox: --%s %s: %s\n", kind_names[acts[i].k], acts[i].arg, msg);
        }
    }
    int64_t after = bvox_volume_count(vol);
    if (!st && (st = bvox_write(out, vol, &wo))) cli_fail();
    bvox_volume_destroy(vol);
    if (!st) {
        report(acts, nacts, before, after, out, json);
        rc = CLI_OK;
    }
done:
    free(acts);
    return rc;
}
