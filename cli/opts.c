/*
 * opts.c — the parser driven by the option tables of opts.h: defaults from
 * the tables, "--name VALUE", "--name=VALUE", "-o VALUE" and "-o=VALUE",
 * flags, positional arguments and "--"; the built-in value kinds with their
 * bounds, or a command's callback. Every error is one usage line and exit
 * status 2, worded as the commands worded them before the tables.
 */
#include "opts.h"
#include "args.h"
#include "cli.h"

#include <stdarg.h>
#include <string.h>

/* A usage error whose format comes from a table (one %s: the value). */
static void usage_fmt(const char *cmd, const char *fmt, const char *value)
{
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#pragma GCC diagnostic ignored "-Wformat-security"
    cli_usage_error(cmd, fmt, value);
#pragma GCC diagnostic pop
}

static int takes_value(const cli_opt *o) { return o->kind != CLI_FLAG; }

/* 1: arg is o ("--name", "-o"); 2: "--name=V" / "-o=V" (*value set); 0: not o. */
static int match(const cli_opt *o, const char *arg, const char **value)
{
    char shortname[3] = {'-', o->alias, '\0'};
    const char *names[2] = {o->name, o->alias ? shortname : NULL};
    for (int k = 0; k < 2; k++) {
        if (!names[k]) continue;
        size_t n = strlen(names[k]);
        if (strncmp(arg, names[k], n) != 0) continue;
        if (arg[n] == '\0') return 1;
        /* A flag never takes "=V" (it stays an unknown option, as before). */
        if (arg[n] == '=' && takes_value(o)) {
            *value = arg + n + 1;
            return 2;
        }
    }
    return 0;
}

/* 1 if o's name appears in an earlier use or earlier in its own table: the
 * first table that names an option owns it, for the parser and the docs. */
static int shadowed(const cli_spec *s, int use, int index)
{
    const char *name = s->uses[use].group->opts[index].name;
    for (int u = 0; u <= use; u++) {
        const cli_opt *t = s->uses[u].group->opts;
        int end = u == use ? index : -1;
        for (int i = 0; t[i].name && i != end; i++)
            if (!strcmp(t[i].name, name)) return 1;
    }
    return 0;
}

const cli_opt *cli_next_option(const cli_spec *s, int *use, int *index,
                               const cli_group **group_out)
{
    for (; *use < CLI_MAX_USES && s->uses[*use].group; (*use)++, *index = 0) {
        const cli_opt *t = s->uses[*use].group->opts;
        while (t[*index].name) {
            int i = (*index)++;
            if (shadowed(s, *use, i)) continue;
            if (group_out) *group_out = s->uses[*use].group;
            return &t[i];
        }
    }
    return NULL;
}

const cli_opt *cli_find_option(const cli_spec *s, const char *arg, const char **value,
                               size_t *base)
{
    int use = 0, index = 0;
    const cli_opt *o;
    while ((o = cli_next_option(s, &use, &index, NULL))) {
        *value = NULL;
        if (match(o, arg, value)) {
            *base = s->uses[use].base;
            return o;
        }
    }
    return NULL;
}

static void store_int(void *target, size_t size, int64_t v)
{
    switch (size) {
    case 1: *(int8_t *)target = (int8_t)v; break;
    case 2: *(int16_t *)target = (int16_t)v; break;
    case 4: *(int32_t *)target = (int32_t)v; break;
    default: *(int64_t *)target = v; break;
    }
}

static int in_bounds(const cli_opt *o, double v)
{
    if ((o->flags & CLI_MIN) && !(v >= o->min)) return 0;
    if ((o->flags & CLI_MIN_OPEN) && !(v > o->min)) return 0;
    if ((o->flags & CLI_MAX) && !(v <= o->max)) return 0;
    if ((o->flags & CLI_MAX_OPEN) && !(v < o->max)) return 0;
    return 1;
}

/* The built-in parsers: CLI_OPT_OK or CLI_OPT_BAD. */
static int store(const cli_opt *o, const char *v, void *target)
{
    switch (o->kind) {
    case CLI_FLAG: store_int(target, o->size, (o->flags & CLI_NEGATE) ? 0 : 1); return CLI_OPT_OK;
    case CLI_STR:
    case CLI_PATH: *(const char **)target = v; return CLI_OPT_OK;
    case CLI_INT: {
        int64_t n;
        int64_t lo = o->lo || o->hi ? o->lo : INT64_MIN, hi = o->lo || o->hi ? o->hi : INT64_MAX;
        if (cli_parse_int64(v, lo, hi, &n)) return CLI_OPT_BAD;
        if (o->choices) {
            int k = 0;
            int64_t c;
            while (o->choices[k] && !(cli_parse_int64(o->choices[k], lo, hi, &c) == 0 && c == n))
                k++;
            if (!o->choices[k]) return CLI_OPT_BAD;
        }
        store_int(target, o->size, n);
        return CLI_OPT_OK;
    }
    case CLI_DOUBLE: {
        double d;
        if (cli_parse_double(v, &d) || !in_bounds(o, d)) return CLI_OPT_BAD;
        *(double *)target = d;
        return CLI_OPT_OK;
    }
    case CLI_TRIPLE: {
        double t[3];
        if (cli_parse_triple(v, t)) return CLI_OPT_BAD;
        for (int k = 0; k < 3; k++)
            if (!in_bounds(o, t[k])) return CLI_OPT_BAD;
        memcpy(target, t, sizeof t);
        return CLI_OPT_OK;
    }
    case CLI_CHOICE:
        for (int k = 0; o->choices[k]; k++)
            if (!strcmp(v, o->choices[k])) {
                store_int(target, o->size, k);
                return CLI_OPT_OK;
            }
        return CLI_OPT_BAD;
    }
    return CLI_OPT_BAD;
}

/* "a, b or c" from a NULL-terminated list. */
static void join_choices(char *buf, size_t size, const char *const *c)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; c[k] && n < size; k++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k == 0 ? "" : c[k + 1] ? ", " : " or ",
                              c[k]);
}

static int bad_value(const char *cmd, const cli_opt *o, const char *v)
{
    if (o->bad) {
        usage_fmt(cmd, o->bad, v);
    } else if (o->choices) {
        char list[256];
        join_choices(list, sizeof list, o->choices);
        cli_usage_error(cmd, "%s: '%s' is not %s", o->name, v, list);
    } else {
        cli_usage_error(cmd, "%s: '%s' is not a valid value", o->name, v);
    }
    return CLI_PARSE_ERROR;
}

/* Offers one option with its value (NULL for a flag) to its taker. */
static int take(const char *cmd, const cli_opt *o, const char *v, char *args, size_t base)
{
    void *target = args + base + o->offset;
    int r = o->fn ? o->fn(cmd, o, v, target) : store(o, v, target);
    if (r == CLI_OPT_OK) return CLI_PARSED;
    if (r == CLI_OPT_BAD) return bad_value(cmd, o, v);
    return CLI_PARSE_ERROR;
}

static int positional(const cli_spec *s, const char *arg, int *npos, char *args)
{
    const cli_pos *p = s->pos ? &s->pos[*npos] : NULL;
    if (!p || !p->name) {
        usage_fmt(s->name, s->too_many ? s->too_many : "unexpected argument '%s'", arg);
        return CLI_PARSE_ERROR;
    }
    if (p->many) {
        cli_list *l = (cli_list *)(args + p->offset);
        l->items[l->n++] = arg;
    } else {
        *(const char **)(args + p->offset) = arg;
        (*npos)++;
    }
    return CLI_PARSED;
}

int cli_parse(const cli_spec *s, int argc, char **argv, void *vargs)
{
    char *args = vargs;
    const char *cmd = s->name;
    int use = 0, index = 0, npos = 0, done = 0, r;
    const cli_opt *o;
    /* Defaults through the options' own takers, so that the table's word is
     * the one that counts. */
    while ((o = cli_next_option(s, &use, &index, NULL)))
        if (o->def && o->kind != CLI_FLAG &&
            take(cmd, o, o->def, args, s->uses[use].base) != CLI_PARSED)
            return CLI_PARSE_ERROR;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i], *v = NULL;
        size_t base = 0;
        if (done || !cli_is_option(arg)) {
            r = positional(s, arg, &npos, args);
        } else if (!strcmp(arg, "--")) {
            done = 1;
            continue;
        } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
            cli_print_help(stdout, s);
            return CLI_PARSE_HELP;
        } else if (!(o = cli_find_option(s, arg, &v, &base))) {
            r = cli_usage_error(cmd, "unknown option '%s'", arg);
        } else if (takes_value(o) && !v && i + 1 >= argc) {
            r = cli_usage_error(cmd, "option %s needs a value", arg);
        } else {
            if (takes_value(o) && !v) v = argv[++i];
            r = take(cmd, o, v, args, base);
        }
        if (r != CLI_PARSED) return CLI_PARSE_ERROR;
    }
    return CLI_PARSED;
}

const char *cli_opt_metavar(const cli_opt *o, char *buf, size_t size)
{
    if (o->kind == CLI_FLAG) return NULL;
    if (o->metavar) return o->metavar;
    if (!o->choices) return "VALUE";
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; o->choices[k] && n < size; k++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k ? "|" : "", o->choices[k]);
    return buf;
}

void cli_opt_help_text(const cli_opt *o, char *buf, size_t size)
{
    const char *h = o->help ? o->help : "", *p = strstr(h, "{formats}");
    if (p)
        snprintf(buf, size, "%.*s%s%s", (int)(p - h), h, bvox_format_list(), p + 9);
    else
        snprintf(buf, size, "%s", h);
    if (o->def) {
        size_t n = strlen(buf);
        snprintf(buf + n, size - n, "%s(default %s)", n ? " " : "", o->def);
    }
}
