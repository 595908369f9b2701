/*
 * manip.c — helpers of the manipulation commands (see manip.h).
 */
#include "manip.h"
#include "cli.h"

#include <string.h>
#include <sys/stat.h>

int cli_check_output(const char *cmd, const char *out, const bvox_write_opts *wo)
{
    /* A folder, existing or named with a trailing '/', is a PNG stack. */
    struct stat sb;
    size_t len = strlen(out);
    int folder = (len && out[len - 1] == '/') || (stat(out, &sb) == 0 && S_ISDIR(sb.st_mode));
    if (!wo->format && !folder && !bvox_format_for_path(out))
        return cli_usage_error(cmd,
                               "%s: cannot tell the output format from the name; "
                               "use --output-format (one of %s)",
                               out, bvox_format_list());
    return CLI_OK;
}

/* "A,B,C,D", each finite. */
int cli_parse_plane(const char *s, double p[4])
{
    const char *q = s;
    for (int k = 0; k < 4; k++) {
        char buf[64];
        size_t n = strcspn(q, ",");
        if (n == 0 || n >= sizeof buf) return -1;
        memcpy(buf, q, n);
        buf[n] = '\0';
        if (cli_parse_double(buf, &p[k])) return -1;
        q += n;
        if (k < 3 && *q++ != ',') return -1;
    }
    return *q ? -1 : 0;
}

const char *const cli_keep_choices[] = {"above", "below", NULL};

int cli_take_plane(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    cli_plane *pl = target;
    if (cli_parse_plane(v, pl->p)) {
        cli_usage_error(cmd, "%s: '%s' is not A,B,C,D", o->name, v);
        return CLI_OPT_FAILED;
    }
    if (!pl->p[0] && !pl->p[1] && !pl->p[2]) {
        cli_usage_error(cmd, "%s: the normal A,B,C is zero", o->name);
        return CLI_OPT_FAILED;
    }
    pl->given = 1;
    return CLI_OPT_OK;
}

void cli_format_plane(char *buf, size_t size, const double p[4])
{
    static const char *const names[4] = {"*x", "*y", "*z", ""};
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < 4 && n < size; k++) {
        double c = p[k];
        if (c == 0 && (k < 3 || n)) continue;
        const char *sign = c < 0 ? (n ? " - " : "-") : (n ? " + " : "");
        double a = c < 0 ? -c : c;
        if (a == 1 && k < 3)
            n += (size_t)snprintf(buf + n, size - n, "%s%s", sign, names[k] + 1);
        else
            n += (size_t)snprintf(buf + n, size - n, "%s%g%s", sign, a, names[k]);
    }
}

static int box_empty(const bvox_box *b) { return b->x0 >= b->x1 || b->y0 >= b->y1 || b->z0 >= b->z1; }

void cli_print_box(FILE *f, const bvox_box *b)
{
    if (box_empty(b)) {
        fputs("none", f);
        return;
    }
    fprintf(f, "x %d..%d, y %d..%d, z %d..%d", b->x0, b->x1 - 1, b->y0, b->y1 - 1, b->z0,
            b->z1 - 1);
}

void cli_json_box(cli_json *j, const bvox_box *b)
{
    if (box_empty(b)) {
        cli_json_null(j);
        return;
    }
    const int64_t lo[3] = {b->x0, b->y0, b->z0}, hi[3] = {b->x1 - 1, b->y1 - 1, b->z1 - 1};
    cli_json_begin_object(j);
    cli_json_key(j, "min");
    cli_json_int_array(j, lo, 3);
    cli_json_key(j, "max");
    cli_json_int_array(j, hi, 3);
    cli_json_end_object(j);
}

void cli_box_union(bvox_box *acc, const bvox_box *b)
{
    if (box_empty(b)) return;
    if (box_empty(acc)) {
        *acc = *b;
        return;
    }
    if (b->x0 < acc->x0) acc->x0 = b->x0;
    if (b->y0 < acc->y0) acc->y0 = b->y0;
    if (b->z0 < acc->z0) acc->z0 = b->z0;
    if (b->x1 > acc->x1) acc->x1 = b->x1;
    if (b->y1 > acc->y1) acc->y1 = b->y1;
    if (b->z1 > acc->z1) acc->z1 = b->z1;
}

int cli_take_origin(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    cli_grid *g = target;
    if (cli_parse_triple(v, g->origin)) return CLI_OPT_BAD;
    g->origin_given = 1;
    return CLI_OPT_OK;
}

void cli_grid_to_opts(const cli_read_args *ra, const cli_grid *g, bvox_csg_eval_opts *o)
{
    o->dims = ra->opts.raw_dims;
    o->geometry = bvox_geometry_default();
    if (ra->spacing_given) memcpy(o->geometry.spacing, ra->spacing, sizeof ra->spacing);
    if (ra->unit) snprintf(o->geometry.unit, sizeof o->geometry.unit, "%s", ra->unit);
    if (g->origin_given) memcpy(o->geometry.origin, g->origin, sizeof g->origin);
}
