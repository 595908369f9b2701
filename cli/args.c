/*
 * args.c — the option parsing shared by every subcommand (see args.h), and
 * the two ways a command reports a problem: cli_fail for a failed library
 * call (exit 1), cli_usage_error for a wrong command line (exit 2).
 */
#include "args.h"
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int cli_fail(void)
{
    const char *msg = bvox_errmsg();
    fprintf(stderr, "bvox: %s\n", msg && *msg ? msg : "failed (no message)");
    return CLI_FAIL;
}

int cli_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "bvox: %s%s", cmd ? cmd : "", cmd ? ": " : "");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (see 'bvox %s%s--help')\n", cmd ? cmd : "", cmd ? " " : "");
    va_end(ap);
    return CLI_USAGE;
}

/* A usage error inside an option parser: print it, answer CLI_ARG_BAD. */
#define BAD(...) (cli_usage_error(cmd, __VA_ARGS__), CLI_ARG_BAD)

/* ------------------------------------------------------------ numbers */

int cli_parse_double(const char *s, double *out)
{
    if (!s || !*s) return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*end || errno == ERANGE || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

int cli_parse_int64(const char *s, int64_t lo, int64_t hi, int64_t *out)
{
    if (!s || !*s) return -1;
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (*end || errno == ERANGE || v < lo || v > hi) return -1;
    *out = v;
    return 0;
}

int cli_parse_size(const char *s, size_t *out)
{
    if (!s || !*s || *s == '-') return -1;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno == ERANGE || !isfinite(v) || v < 0 || end == s) return -1;
    double mult = 1;
    switch (*end) {
    case 'k': case 'K': mult = 1024.0; end++; break;
    case 'm': case 'M': mult = 1024.0 * 1024; end++; break;
    case 'g': case 'G': mult = 1024.0 * 1024 * 1024; end++; break;
    case 't': case 'T': mult = 1024.0 * 1024 * 1024 * 1024; end++; break;
    default: break;
    }
    if (*end == 'i') end++;           /* "512Mi" */
    if (*end == 'B' || *end == 'b') end++; /* "512MB", "512MiB" */
    if (*end) return -1;
    double bytes = v * mult;
    if (bytes >= 18446744073709551616.0 || bytes > (double)SIZE_MAX) return -1;
    *out = (size_t)bytes;
    return 0;
}

/* Splits "a,b,c" (or "axbxc") into three fields of at most 63 characters. */
static int split3(const char *s, char f[3][64])
{
    const char *p = s;
    for (int k = 0; k < 3; k++) {
        size_t n = strcspn(p, k < 2 ? ",x" : "");
        if (n == 0 || n >= 64) return -1;
        memcpy(f[k], p, n);
        f[k][n] = '\0';
        p += n;
        if (k < 2) {
            if (*p != ',' && *p != 'x') return -1;
            p++;
        }
    }
    return 0;
}

int cli_parse_dims(const char *s, bvox_dims *out)
{
    char f[3][64];
    int64_t v[3];
    if (!s || split3(s, f)) return -1;
    for (int k = 0; k < 3; k++)
        if (cli_parse_int64(f[k], 1, BVOX_MAX_DIM, &v[k])) return -1;
    *out = (bvox_dims){(int32_t)v[0], (int32_t)v[1], (int32_t)v[2]};
    return 0;
}

int cli_parse_triple(const char *s, double out[3])
{
    char f[3][64];
    /* Only commas here: "1e-3x..." would be ambiguous with an 'x' separator. */
    if (!s || strchr(s, 'x')) return -1;
    if (split3(s, f)) return -1;
    for (int k = 0; k < 3; k++)
        if (cli_parse_double(f[k], &out[k])) return -1;
    return 0;
}

/* ------------------------------------------------------------ matching */

int cli_is_option(const char *arg) { return arg[0] == '-' && arg[1] != '\0'; }

int cli_parse_input_arg(const char *cmd, const char *arg, int *options_done, const char **in,
                        void (*help)(FILE *))
{
    if (*options_done || !cli_is_option(arg)) {
        if (*in) return BAD("unexpected argument '%s'", arg);
        *in = arg;
    } else if (!strcmp(arg, "--")) {
        *options_done = 1;
    } else if (!strcmp(arg, "--help") || !strcmp(arg, "-h")) {
        help(stdout);
        return CLI_ARG_HELP;
    } else {
        return CLI_ARG_NOT_MINE;
    }
    return CLI_ARG_USED;
}

int cli_match_value(const char *cmd, int argc, char **argv, int *i, const char *name,
                    const char **value)
{
    const char *arg = argv[*i];
    size_t n = strlen(name);
    if (strncmp(arg, name, n) != 0) return CLI_ARG_NOT_MINE;
    if (arg[n] == '=') {
        *value = arg + n + 1;
        return CLI_ARG_USED;
    }
    if (arg[n] != '\0') return CLI_ARG_NOT_MINE;
    if (*i + 1 >= argc) {
        cli_usage_error(cmd, "option %s needs a value", name);
        return CLI_ARG_BAD;
    }
    *value = argv[++*i];
    return CLI_ARG_USED;
}

/* ------------------------------------------------------------ read options */

static const char read_options_help[] =
    "\nRead options (how a gray or label image becomes binary; pick one):\n"
    "  --nonzero             voxel is 1 where value != 0 (default)\n"
    "  --threshold T         voxel is 1 where value >= T\n"
    "  --range LO:HI         voxel is 1 where LO <= value <= HI\n"
    "  --otsu                threshold chosen by Otsu's method\n"
    "  --label N             voxel is 1 where value == N (label maps, atlases)\n"
    "  --format NAME         force the input format (%s)\n"
    "\nRaw input (needs --dims and --type):\n"
    "  --dims NX,NY,NZ       dimensions in voxels\n"
    "  --type T              u8 i8 u16 i16 u32 i32 u64 i64 f32 f64\n"
    "  --endian little|big   byte order (default little)\n"
    "  --offset BYTES        bytes to skip before the data (a header)\n"
    "\nGeometry (raw input, or to override what a file says):\n"
    "  --voxel-size SX,SY,SZ voxel size in physical units\n"
    "  --unit U              length unit, e.g. mm or um\n";

static const char process_options_help[] =
    "\nProcess options:\n"
    "  --max-memory SIZE     memory budget for voxel data, e.g. 512M, 8G\n"
    "  --threads N           worker threads (default: all cores)\n";

void cli_print_read_options_help(FILE *f) { fprintf(f, read_options_help, bvox_format_list()); }

void cli_print_process_options_help(FILE *f) { fputs(process_options_help, f); }

void cli_read_args_init(cli_read_args *a)
{
    const bvox_read_opts init = BVOX_READ_OPTS_INIT;
    memset(a, 0, sizeof *a);
    a->opts = init;
}

int cli_parse_read_option(const char *cmd, int argc, char **argv, int *i, cli_read_args *a)
{
    const char *arg = argv[*i], *v = NULL;
    bvox_binarize *b = &a->opts.binarize;
    int r;
    if (!strcmp(arg, "--nonzero")) {
        b->mode = BVOX_BIN_NONZERO;
        a->binarize_given++;
    } else if (!strcmp(arg, "--otsu")) {
        b->mode = BVOX_BIN_OTSU;
        a->binarize_given++;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--threshold", &v))) {
        if (r < 0) return r;
        if (cli_parse_double(v, &b->threshold))
            return BAD("--threshold: '%s' is not a finite number", v);
        b->mode = BVOX_BIN_THRESHOLD;
        a->binarize_given++;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--range", &v))) {
        if (r < 0) return r;
        const char *colon = strchr(v, ':');
        char lo[64];
        size_t n = colon ? (size_t)(colon - v) : 0;
        if (!colon || n == 0 || n >= sizeof lo)
            return BAD("--range: '%s' is not LO:HI", v);
        memcpy(lo, v, n);
        lo[n] = '\0';
        if (cli_parse_double(lo, &b->lo) || cli_parse_double(colon + 1, &b->hi) || b->lo > b->hi)
            return BAD("--range: '%s' is not LO:HI with LO <= HI", v);
        b->mode = BVOX_BIN_RANGE;
        a->binarize_given++;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--label", &v))) {
        if (r < 0) return r;
        if (cli_parse_double(v, &b->label))
            return BAD("--label: '%s' is not a number", v);
        b->mode = BVOX_BIN_LABEL;
        a->binarize_given++;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--format", &v))) {
        if (r < 0) return r;
        a->opts.format = v; /* the library names the known formats if it is wrong */
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--dims", &v))) {
        if (r < 0) return r;
        if (cli_parse_dims(v, &a->opts.raw_dims))
            return BAD("--dims: '%s' is not NX,NY,NZ with each in 1..%d", v,
                                   BVOX_MAX_DIM);
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--type", &v))) {
        if (r < 0) return r;
        int t = bvox_dtype_parse(v);
        if (t < 0)
            return BAD("--type: unknown sample type '%s'", v);
        a->opts.raw_dtype = (bvox_dtype)t;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--endian", &v))) {
        if (r < 0) return r;
        if (!strcmp(v, "little")) a->opts.raw_big_endian = 0;
        else if (!strcmp(v, "big")) a->opts.raw_big_endian = 1;
        else return BAD("--endian: '%s' is not little or big", v);
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--offset", &v))) {
        if (r < 0) return r;
        int64_t off;
        if (cli_parse_int64(v, 0, INT64_MAX, &off))
            return BAD("--offset: '%s' is not a byte count", v);
        a->opts.raw_offset = (uint64_t)off;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--voxel-size", &v))) {
        if (r < 0) return r;
        double s[3];
        if (cli_parse_triple(v, s) || !(s[0] > 0 && s[1] > 0 && s[2] > 0))
            return BAD("--voxel-size: '%s' is not SX,SY,SZ (each > 0)", v);
        memcpy(a->spacing, s, sizeof s);
        memcpy(a->opts.raw_spacing, s, sizeof s);
        a->spacing_given = 1;
    } else if ((r = cli_match_value(cmd, argc, argv, i, "--unit", &v))) {
        if (r < 0) return r;
        if (strlen(v) >= sizeof(((bvox_geometry *)0)->unit))
            return BAD("--unit: '%s' is too long", v);
        a->unit = v;
        a->opts.raw_unit = v;
    } else {
        return CLI_ARG_NOT_MINE;
    }
    if (a->binarize_given > 1)
        return BAD("give only one of --nonzero, --threshold, --range, "
                                    "--otsu, --label");
    return CLI_ARG_USED;
}

int cli_parse_process_option(const char *cmd, int argc, char **argv, int *i)
{
    const char *v = NULL;
    int r;
    if ((r = cli_match_value(cmd, argc, argv, i, "--max-memory", &v))) {
        if (r < 0) return r;
        size_t bytes;
        if (cli_parse_size(v, &bytes) || bytes == 0)
            return BAD("--max-memory: '%s' is not a size like 512M or 8G", v);
        bvox_set_memory_budget(bytes);
        return CLI_ARG_USED;
    }
    if ((r = cli_match_value(cmd, argc, argv, i, "--threads", &v))) {
        if (r < 0) return r;
        int64_t n;
        if (cli_parse_int64(v, 1, 1024, &n))
            return BAD("--threads: '%s' is not a count in 1..1024", v);
        bvox_set_threads((int)n);
        return CLI_ARG_USED;
    }
    return CLI_ARG_NOT_MINE;
}

int cli_parse_shared_option(const char *cmd, int argc, char **argv, int *i, cli_read_args *a)
{
    int r = a ? cli_parse_read_option(cmd, argc, argv, i, a) : CLI_ARG_NOT_MINE;
    if (r == CLI_ARG_NOT_MINE) r = cli_parse_process_option(cmd, argc, argv, i);
    if (r == CLI_ARG_NOT_MINE) r = BAD("unknown option '%s'", argv[*i]);
    return r;
}

/* ------------------------------------------------------------ reading */

bvox_status cli_read_volume(const char *path, const cli_read_args *a, bvox_volume **out)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_read(path, &a->opts, &v);
    if (st) return st;
    if (a->spacing_given || a->unit) {
        const double *s = a->spacing_given ? a->spacing : bvox_volume_geometry(v)->spacing;
        st = bvox_volume_set_spacing(v, s[0], s[1], s[2], a->unit);
        if (st) {
            bvox_volume_destroy(v);
            return st;
        }
    }
    *out = v;
    return BVOX_OK;
}

const char *cli_input_format(const char *path, const cli_read_args *a)
{
    return a->opts.format ? a->opts.format : bvox_format_for_path(path);
}

int cli_parse_output_option(const char *cmd, int argc, char **argv, int *i, const char **out,
                            bvox_write_opts *wo)
{
    const char *v = NULL;
    int r;
    if ((r = cli_match_value(cmd, argc, argv, i, "-o", &v)) ||
        (r = cli_match_value(cmd, argc, argv, i, "--output", &v))) {
        if (r == CLI_ARG_USED) *out = v;
        return r;
    }
    if (!strcmp(argv[*i], "--force")) { /* folder outputs: see bvox_write_opts.force */
        wo->force = 1;
        return CLI_ARG_USED;
    }
    if ((r = cli_match_value(cmd, argc, argv, i, "--output-format", &v)) == CLI_ARG_USED)
        wo->format = v;
    return r;
}

/* mkdir -p: create dir and its missing parents. 0 on success, else errno. */
int cli_make_dirs(const char *dir)
{
    char *p = strdup(dir);
    if (!p) return ENOMEM;
    int err = 0;
    for (char *s = p + 1;; s++) {
        if (*s != '/' && *s != '\0') continue;
        char c = *s;
        *s = '\0';
        if (mkdir(p, 0777) != 0 && errno != EEXIST) {
            err = errno;
            break;
        }
        *s = c;
        if (!c) break;
    }
    struct stat st;
    if (!err && (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))) err = ENOTDIR;
    free(p);
    return err;
}
