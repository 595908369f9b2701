/*
 * cmd_edit.c — `bvox edit IN -o OUT ACTION...`: voxel edits applied in the
 * order given (set or clear a voxel, fill, clear or keep a box, keep one
 * side of a plane), each one library call (bvox_edit_*, bvox_cut_plane) that
 * reports the region it changed; prints those regions and the count before
 * and after, then writes OUT (temporary file, renamed on success).
 */
#include "cli.h"
#include "manip.h"
#include "opts.h"

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

typedef struct edit_args {
    const char *in, *out;
    int json;
    action *acts; /* room for argc actions, in the order given */
    int nacts;
    bvox_write_opts wo;
    cli_read_args ra;
} edit_args;

#define A(member) CLI_AT(edit_args, member)
#define WHOLE .offset = 0, .size = sizeof(edit_args)

static int take_action(const char *cmd, const cli_opt *o, const char *v, void *target);

static const cli_opt action_opts[] = {
    {"--set", 0, CLI_STR, "X,Y,Z", "set one voxel (outside the volume: an error)", WHOLE,
     .flags = CLI_REPEAT, .fn = take_action},
    {"--clear", 0, CLI_STR, "X,Y,Z", "clear one voxel", WHOLE, .flags = CLI_REPEAT,
     .fn = take_action},
    {"--fill-box", 0, CLI_STR, "BOX", "set every voxel of BOX", WHOLE, .flags = CLI_REPEAT,
     .fn = take_action},
    {"--clear-box", 0, CLI_STR, "BOX", "clear every voxel of BOX", WHOLE, .flags = CLI_REPEAT,
     .fn = take_action},
    {"--keep-box", 0, CLI_STR, "BOX", "clear every voxel outside BOX (spatial selection)", WHOLE,
     .flags = CLI_REPEAT, .fn = take_action},
    {"--keep-above", 0, CLI_STR, "A,B,C,D",
     "clear the voxels whose centre has A*x+B*y+C*z+D < 0", WHOLE, .flags = CLI_REPEAT,
     .fn = take_action},
    {"--keep-below", 0, CLI_STR, "A,B,C,D",
     "clear the voxels whose centre has A*x+B*y+C*z+D >= 0 (x, y, z in world coordinates, as "
     "in 'bvox cut')",
     WHOLE, .flags = CLI_REPEAT, .fn = take_action},
    {NULL},
};
static const cli_group action_group = {
    "Actions", action_opts,
    "\n"
    "BOX is X0:X1,Y0:Y1,Z0:Z1 in voxel indices, both ends included (as the\n"
    "bounding box 'bvox info' prints); an interval may be one index (5), open\n"
    "at an end (5: or :9) or the whole axis (:). Boxes are clipped to the\n"
    "volume.\n"};

static const cli_opt edit_opts[] = {
    {"--output", 'o', CLI_PATH, "OUT", "the file to write (required)", A(out)},
    {"--json", 0, CLI_FLAG, NULL, "print the report as one JSON object", A(json)},
    CLI_OPT_OUTPUT_FORMAT(edit_args, wo.format),
    CLI_OPT_FORCE(edit_args, wo.force),
    {NULL},
};
static const cli_group edit_group = {"Options", edit_opts, NULL};
static const cli_pos edit_pos[] = {
    {"IN", "the volume to edit", A(in)},
    {NULL},
};

const cli_spec cli_spec_edit = {
    .name = "edit",
    .summary = "set or clear voxels and boxes, keep a box or one side of a plane",
    .usage = "IN -o OUT ACTION... [options]",
    .about = "Edit a volume voxel by voxel or region by region; the actions are applied\n"
             "in the order given and each may be repeated. Prints the region each action\n"
             "changed (the voxels whose value changed, as inclusive indices) and the\n"
             "count of 1-voxels before and after.\n",
    .pos = edit_pos,
    .uses = {{&action_group, 0}, {&edit_group, 0}, CLI_USE_READ(edit_args, ra), CLI_USE_PROCESS},
    .examples = "  bvox edit embryo.nii -o fixed.nii --set 10,12,40 --clear 11,12,40\n"
                "  bvox edit embryo.nii -o part.nii --keep-box 20:80,:,0:63\n"
                "  bvox edit scan.nii.gz -o cut.nii.gz --clear-box :,:,100: --keep-above 0,0,1,-5\n",
};

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

/* Every action option: its kind is its name. */
static int take_action(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    edit_args *a = target;
    int k = 0;
    while (k < NKINDS && strcmp(o->name + 2, kind_names[k])) k++;
    if (parse_action(cmd, (kind)k, v, &a->acts[a->nacts]) != CLI_OK) return CLI_OPT_FAILED;
    a->nacts++;
    return CLI_OPT_OK;
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

static void report(const action *acts, int n, int64_t before, int64_t after, const char *in,
                   const char *out, int json)
{
    bvox_box all = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < n; i++) cli_box_union(&all, &acts[i].changed);
    if (json) {
        cli_json j;
        cli_json_init(&j, stdout);
        cli_json_begin_object(&j);
        cli_json_key(&j, "file");
        cli_json_string(&j, out);
        cli_json_io(&j, in, out);
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
    const char *cmd = "edit";
    edit_args a = {.wo = BVOX_WRITE_OPTS_INIT};
    cli_read_args_init(&a.ra);
    a.acts = calloc((size_t)argc, sizeof *a.acts);
    if (!a.acts) {
        fprintf(stderr, "bvox: out of memory\n");
        return CLI_FAIL;
    }
    action *acts = a.acts;
    const char *in, *out;
    int json, nacts, rc = cli_parse(&cli_spec_edit, argc, argv, &a);
    if (rc != CLI_PARSED) {
        rc = rc == CLI_PARSE_HELP ? CLI_OK : CLI_USAGE;
        goto done;
    }
    rc = CLI_USAGE;
    in = a.in, out = a.out, json = a.json, nacts = a.nacts;
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
    if (cli_check_output(cmd, out, &a.wo) != CLI_OK) goto done;

    bvox_volume *vol = NULL;
    rc = CLI_FAIL;
    if (cli_read_volume(in, &a.ra, &vol)) {
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
    if (!st && (st = bvox_write(out, vol, &a.wo))) cli_fail();
    bvox_volume_destroy(vol);
    if (!st) {
        report(acts, nacts, before, after, in, out, json);
        rc = CLI_OK;
    }
done:
    free(acts);
    return rc;
}
