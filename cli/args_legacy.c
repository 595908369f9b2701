/*
 * args_legacy.c — the hand-written option parsers of the commands not yet
 * converted to the tables of opts.h (temporary, removed with the last one).
 */
#include "args.h"
#include "cli.h"

#include <stdio.h>
#include <string.h>

#define BAD(...) (cli_usage_error(cmd, __VA_ARGS__), CLI_ARG_BAD)

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

