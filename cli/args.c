/*
 * args.c — the options shared by the subcommands (see args.h): the read and
 * process option groups, strict number parsing, and
 * the two ways a command reports a problem: cli_fail for a failed library
 * call (exit 1), cli_usage_error for a wrong command line (exit 2).
 */
#include "args.h"
#include "cli.h"
#include "opts.h"
#include "progress.h"

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
    cli_progress_clear();
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

/* ------------------------------------------------------------ read options */

void cli_read_args_init(cli_read_args *a)
{
    const bvox_read_opts init = BVOX_READ_OPTS_INIT;
    memset(a, 0, sizeof *a);
    a->opts = init;
}

_Static_assert(BVOX_MAX_DIM == 65535, "CLI_BAD_DIMS names BVOX_MAX_DIM");

/* One binarisation chosen: mode set, and only one of them on a command line. */
static int binarize_chosen(const char *cmd, cli_read_args *a, bvox_binarize_mode mode)
{
    a->opts.binarize.mode = mode;
    if (++a->binarize_given > 1) {
        cli_usage_error(cmd, "give only one of --nonzero, --threshold, --range, --otsu, --label");
        return CLI_OPT_FAILED;
    }
    return CLI_OPT_OK;
}

static int take_nonzero(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    return binarize_chosen(cmd, t, BVOX_BIN_NONZERO);
}

static int take_otsu(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    return binarize_chosen(cmd, t, BVOX_BIN_OTSU);
}

static int take_threshold(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    cli_read_args *a = t;
    if (cli_parse_double(v, &a->opts.binarize.threshold)) return CLI_OPT_BAD;
    return binarize_chosen(cmd, a, BVOX_BIN_THRESHOLD);
}

static int take_range(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    cli_read_args *a = t;
    bvox_binarize *b = &a->opts.binarize;
    const char *colon = strchr(v, ':');
    char lo[64];
    size_t n = colon ? (size_t)(colon - v) : 0;
    if (!colon || n == 0 || n >= sizeof lo) {
        cli_usage_error(cmd, "--range: '%s' is not LO:HI", v);
        return CLI_OPT_FAILED;
    }
    memcpy(lo, v, n);
    lo[n] = '\0';
    if (cli_parse_double(lo, &b->lo) || cli_parse_double(colon + 1, &b->hi) || b->lo > b->hi)
        return CLI_OPT_BAD;
    return binarize_chosen(cmd, a, BVOX_BIN_RANGE);
}

static int take_label(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    cli_read_args *a = t;
    if (cli_parse_double(v, &a->opts.binarize.label)) return CLI_OPT_BAD;
    return binarize_chosen(cmd, a, BVOX_BIN_LABEL);
}

int cli_take_dims(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    return cli_parse_dims(v, &((cli_read_args *)t)->opts.raw_dims) ? CLI_OPT_BAD : CLI_OPT_OK;
}

static int take_type(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    int type = bvox_dtype_parse(v);
    if (type < 0) return CLI_OPT_BAD;
    ((cli_read_args *)t)->opts.raw_dtype = (bvox_dtype)type;
    return CLI_OPT_OK;
}

int cli_take_voxel_size(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    cli_read_args *a = t;
    double s[3];
    if (cli_parse_triple(v, s) || !(s[0] > 0 && s[1] > 0 && s[2] > 0)) return CLI_OPT_BAD;
    memcpy(a->spacing, s, sizeof s);
    memcpy(a->opts.raw_spacing, s, sizeof s);
    a->spacing_given = 1;
    return CLI_OPT_OK;
}

int cli_take_unit(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    cli_read_args *a = t;
    if (strlen(v) >= sizeof(((bvox_geometry *)0)->unit)) return CLI_OPT_BAD;
    a->unit = v;
    a->opts.raw_unit = v;
    return CLI_OPT_OK;
}

#define R(member) CLI_AT(cli_read_args, member)
#define WHOLE .offset = 0, .size = sizeof(cli_read_args)

static const cli_opt binarize_opts[] = {
    {"--nonzero", 0, CLI_FLAG, NULL, "voxel is 1 where value != 0 (default)", WHOLE,
     .fn = take_nonzero},
    {"--threshold", 0, CLI_DOUBLE, "T", "voxel is 1 where value >= T", WHOLE,
     .fn = take_threshold, .bad = "--threshold: '%s' is not a finite number"},
    {"--range", 0, CLI_STR, "LO:HI", "voxel is 1 where LO <= value <= HI", WHOLE,
     .fn = take_range, .bad = "--range: '%s' is not LO:HI with LO <= HI"},
    {"--otsu", 0, CLI_FLAG, NULL, "threshold chosen by Otsu's method", WHOLE, .fn = take_otsu},
    {"--label", 0, CLI_DOUBLE, "N", "voxel is 1 where value == N (label maps, atlases)", WHOLE,
     .fn = take_label, .bad = "--label: '%s' is not a number"},
    /* the library names the known formats if it is wrong */
    {"--format", 0, CLI_STR, "NAME", "force the input format ({formats})", R(opts.format)},
    {"--level", 0, CLI_INT, "K", "resolution level of an OME-Zarr input (0: the finest)",
     R(opts.zarr_level), .lo = 0, .hi = 15, .bad = "--level: '%s' is not a level 0..15"},
    {NULL},
};

static const char *const endians[] = {"little", "big", NULL};

static const cli_opt raw_opts[] = {
    {"--dims", 0, CLI_STR, "NX,NY,NZ", "dimensions in voxels", WHOLE, .fn = cli_take_dims,
     .bad = CLI_BAD_DIMS},
    {"--type", 0, CLI_STR, "T", "u8 i8 u16 i16 u32 i32 u64 i64 f32 f64", WHOLE, .fn = take_type,
     .bad = "--type: unknown sample type '%s'"},
    {"--endian", 0, CLI_CHOICE, NULL, "byte order", R(opts.raw_big_endian), .def = "little",
     .choices = endians},
    {"--offset", 0, CLI_INT, "BYTES", "bytes to skip before the data (a header)",
     R(opts.raw_offset), .lo = 0, .hi = INT64_MAX, .bad = "--offset: '%s' is not a byte count"},
    {NULL},
};

static const cli_opt geometry_opts[] = {
    {"--voxel-size", 0, CLI_TRIPLE, "SX,SY,SZ", "voxel size in physical units", WHOLE,
     .fn = cli_take_voxel_size, .bad = CLI_BAD_VOXEL_SIZE},
    {"--unit", 0, CLI_STR, "U", "length unit, e.g. mm or um", WHOLE, .fn = cli_take_unit,
     .bad = CLI_BAD_UNIT},
    {NULL},
};

const cli_group cli_read_groups[3] = {
    {"Read options (how a gray or label image becomes binary; pick one)", binarize_opts, NULL},
    {"Raw input (needs --dims and --type)", raw_opts, NULL},
    {"Geometry (raw input, or to override what a file says)", geometry_opts, NULL},
};

const char *const cli_conn_choices[] = {"6", "18", "26", NULL};
const char *const cli_mesh_formats[] = {"stl", "ply", "obj", "off", NULL};

const char *const cli_filter_choices[] = {"highpass", "smooth", "laplace", "sobel", NULL};

/* The filter names of the CLI: the library's, and "laplace". */
int cli_take_filter(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    int f = !strcmp(v, "laplace") ? BVOX_FILTER_LAPLACIAN : bvox_filter_parse(v);
    if (f < 0) return CLI_OPT_BAD;
    *(int *)target = f;
    return CLI_OPT_OK;
}

/* --light AZ,EL (render, image): two finite numbers into a bvox_light's
 * azimuth and elevation. */
int cli_take_light(const char *cmd, const cli_opt *o, const char *v, void *target)
{
    char buf[128];
    const char *comma = strchr(v, ',');
    if (!comma || (size_t)(comma - v) >= sizeof buf) return CLI_OPT_BAD;
    memcpy(buf, v, (size_t)(comma - v));
    buf[comma - v] = '\0';
    double az, el;
    if (cli_parse_double(buf, &az) || cli_parse_double(comma + 1, &el)) return CLI_OPT_BAD;
    bvox_light *light = target;
    light->azimuth = az, light->elevation = el;
    return CLI_OPT_OK;
}

/* ------------------------------------------------------------ process options */

static int take_max_memory(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    size_t bytes;
    if (cli_parse_size(v, &bytes) || bytes == 0) return CLI_OPT_BAD;
    bvox_set_memory_budget(bytes);
    return CLI_OPT_OK;
}

static int take_threads(const char *cmd, const cli_opt *o, const char *v, void *t)
{
    int64_t n;
    if (cli_parse_int64(v, 1, 1024, &n)) return CLI_OPT_BAD;
    bvox_set_threads((int)n);
    return CLI_OPT_OK;
}

static const cli_opt process_opts[] = {
    {"--max-memory", 0, CLI_STR, "SIZE", "memory budget for voxel data, e.g. 512M, 8G",
     .fn = take_max_memory, .bad = "--max-memory: '%s' is not a size like 512M or 8G"},
    {"--threads", 0, CLI_INT, "N", "worker threads (default: all cores)", .fn = take_threads,
     .bad = "--threads: '%s' is not a count in 1..1024"},
    {NULL},
};

const cli_group cli_process_group = {"Process options", process_opts, NULL};

/* ------------------------------------------------------------ reading */

bvox_status cli_read_volume(const char *path, const cli_read_args *a, bvox_volume **out)
{
    /* --voxel-size / --unit go to the reader, which applies them to any
     * format and so knows not to warn about a voxel size the file lacks */
    bvox_read_opts o = a->opts;
    if (a->spacing_given) memcpy(o.spacing, a->spacing, sizeof o.spacing);
    if (a->unit) o.unit = a->unit;
    return bvox_read(path, &o, out);
}

const char *cli_input_format(const char *path, const cli_read_args *a)
{
    return a->opts.format ? a->opts.format : bvox_format_for_path(path);
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
