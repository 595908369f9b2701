/*
 * args.h — command-line parsing shared by the subcommands: option matching
 * ("--name VALUE" and "--name=VALUE"), strict number parsing, and the read
 * options every command that reads a file accepts (binarisation, forced
 * format, raw layout, voxel size) plus the process settings (--max-memory,
 * --threads). Parsing only: nothing here reads a file.
 */
#ifndef BVOX_CLI_ARGS_H
#define BVOX_CLI_ARGS_H

#include "bvox.h"

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

/* Result of offering argv[*i] to a parser (CLI_ARG_HELP: cli_parse_input_arg
 * printed the help; the command returns CLI_OK). */
enum { CLI_ARG_NOT_MINE = 0, CLI_ARG_USED = 1, CLI_ARG_BAD = -1, CLI_ARG_HELP = 2 };

/* Options of commands that read a volume. */
typedef struct cli_read_args {
    bvox_read_opts opts;
    int binarize_given;  /* how many of --threshold/--range/--otsu/--label/--nonzero */
    int spacing_given;
    double spacing[3];   /* --voxel-size: raw layout, and overrides any file's */
    const char *unit;    /* --unit (NULL: keep) */
} cli_read_args;

void cli_read_args_init(cli_read_args *a);

/* Offer argv[*i] to the read-option parser. On CLI_ARG_USED *i points at the
 * last argument consumed; CLI_ARG_BAD has already printed a usage message. */
int cli_parse_read_option(const char *cmd, int argc, char **argv, int *i, cli_read_args *a);

/* --max-memory SIZE and --threads N, applied at once (they are process-wide). */
int cli_parse_process_option(const char *cmd, int argc, char **argv, int *i);

/* Read options (if a is not NULL), then process options; anything else is
 * an unknown option (usage message printed). Returns CLI_ARG_USED or
 * CLI_ARG_BAD, never CLI_ARG_NOT_MINE: call it after the command's own. */
int cli_parse_shared_option(const char *cmd, int argc, char **argv, int *i, cli_read_args *a);

/* Help text of the options above, for the subcommands' --help. */
void cli_print_read_options_help(FILE *f);
void cli_print_process_options_help(FILE *f);

/* bvox_read with the parsed options, then the --voxel-size/--unit override
 * (a PNG stack or an uncalibrated TIFF has no z spacing of its own). */
bvox_status cli_read_volume(const char *path, const cli_read_args *a, bvox_volume **out);

/* The format named by --format, or the one the path's extension implies
 * (NULL when neither says). For reports only. */
const char *cli_input_format(const char *path, const cli_read_args *a);

/* If argv[*i] is "--name" (value in the next argument) or "--name=VALUE",
 * sets *value and returns CLI_ARG_USED; CLI_ARG_NOT_MINE if it is something
 * else; CLI_ARG_BAD (message printed) if the value is missing. */
int cli_match_value(const char *cmd, int argc, char **argv, int *i, const char *name,
                    const char **value);

/* 1 if arg is an option (starts with '-' and is not "-" alone). */
int cli_is_option(const char *arg);

/* The start of the argument loop of a command that takes one input IN:
 * arg is IN (the first argument that is not an option, or one after "--";
 * a second one is a usage error), "--" (sets *options_done) or --help/-h
 * (help(stdout)). Returns CLI_ARG_USED, CLI_ARG_BAD (message printed),
 * CLI_ARG_HELP, or CLI_ARG_NOT_MINE for the command's own options:
 *     if ((r = cli_parse_input_arg(cmd, arg, &options_done, &in, help))) {
 *         if (r != CLI_ARG_USED) return r == CLI_ARG_HELP ? CLI_OK : CLI_USAGE;
 *     } else if (...the command's options...) */
int cli_parse_input_arg(const char *cmd, const char *arg, int *options_done, const char **in,
                        void (*help)(FILE *));

/* -o/--output OUT (sets *out), --output-format NAME (sets wo->format) and
 * --force (sets wo->force: a folder output may go into a folder holding
 * other files; nothing is removed), for the commands that write a volume.
 * Same returns as cli_match_value. */
int cli_parse_output_option(const char *cmd, int argc, char **argv, int *i, const char **out,
                            bvox_write_opts *wo);
/* The help line of --force, for the commands that take it. */
#define CLI_FORCE_HELP \
    "  --force               a folder output may go into a folder holding other files\n" \
    "                        (bvox's own file names are replaced, nothing is removed)\n"


/* Strict parsers: the whole string must be consumed; 0 on success. */
int cli_parse_double(const char *s, double *out);     /* finite */
int cli_parse_int64(const char *s, int64_t lo, int64_t hi, int64_t *out);
int cli_parse_size(const char *s, size_t *out);       /* 512, 64K, 512M, 8G, 1T (x1024) */
int cli_parse_dims(const char *s, bvox_dims *out);    /* "NX,NY,NZ" or "NXxNYxNZ" */
int cli_parse_triple(const char *s, double out[3]);   /* "SX,SY,SZ", each finite */

/* mkdir -p: create dir and its missing parents. 0 on success, else errno. */
int cli_make_dirs(const char *dir);

#endif
