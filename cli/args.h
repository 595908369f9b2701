/*
 * args.h — what the subcommands share on top of the option tables of
 * opts.h: strict number parsing, the read options every command that reads a
 * file accepts (binarisation, forced format, raw layout, voxel size) and the
 * process settings (--max-memory, --threads) as shared option groups, and the
 * takers and choice lists several tables use. Parsing only: nothing here
 * reads a file.
 */
#ifndef BVOX_CLI_ARGS_H
#define BVOX_CLI_ARGS_H

#include "bvox.h"
#include "opts.h"

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

/* Options of commands that read a volume. */
typedef struct cli_read_args {
    bvox_read_opts opts;
    int binarize_given;  /* how many of --threshold/--range/--otsu/--label/--nonzero */
    int spacing_given;
    double spacing[3];   /* --voxel-size: raw layout, and overrides any file's */
    const char *unit;    /* --unit (NULL: keep) */
} cli_read_args;

void cli_read_args_init(cli_read_args *a);

/* The read options as three groups of options (binarisation, raw layout,
 * geometry), for a cli_read_args inside a command's args, and the process
 * options (--max-memory, --threads: applied at once, they are process-wide). */
extern const cli_group cli_read_groups[3];
extern const cli_group cli_process_group;
#define CLI_USE_READ(type, member)                                                          \
    {&cli_read_groups[0], offsetof(type, member)}, {&cli_read_groups[1], offsetof(type, member)}, \
    {&cli_read_groups[2], offsetof(type, member)}
#define CLI_USE_PROCESS {&cli_process_group, 0}
/* Takers of --dims, --voxel-size and --unit into a cli_read_args (for
 * commands that build a grid from them without reading). */
int cli_take_dims(const char *cmd, const cli_opt *o, const char *v, void *read_args);
int cli_take_voxel_size(const char *cmd, const cli_opt *o, const char *v, void *read_args);
int cli_take_unit(const char *cmd, const cli_opt *o, const char *v, void *read_args);
/* The messages of a bad --dims, --voxel-size, --unit (one %s: the value). */
#define CLI_BAD_DIMS "--dims: '%s' is not NX,NY,NZ with each in 1..65535" /* BVOX_MAX_DIM */
#define CLI_BAD_VOXEL_SIZE "--voxel-size: '%s' is not SX,SY,SZ (each > 0)"
#define CLI_BAD_UNIT "--unit: '%s' is too long"
/* "6", "18", "26": the connectivities of --conn. */
extern const char *const cli_conn_choices[];
/* "stl", "ply", "obj", "off": the mesh formats (--mesh-format). */
extern const char *const cli_mesh_formats[];
/* --filter F (render, image): a 3x3 filter by name into an int (-1: none). */
extern const char *const cli_filter_choices[];
int cli_take_filter(const char *cmd, const cli_opt *o, const char *v, void *filter);
#define CLI_BAD_FILTER "--filter: '%s' is not highpass, smooth, laplace or sobel"
/* --light AZ,EL (render, image) into a bvox_light. */
int cli_take_light(const char *cmd, const cli_opt *o, const char *v, void *light);
#define CLI_BAD_LIGHT "--light: '%s' is not AZ,EL"
/* --output-format NAME into the const char * member of type. */
#define CLI_OPT_OUTPUT_FORMAT(type, member)                                                 \
    {"--output-format", 0, CLI_STR, "NAME", "force the output format ({formats})",           \
     CLI_AT(type, member)}
/* --force beside it: a folder output may go into a folder holding other files
 * (bvox's own file names are replaced, nothing is removed); the member is
 * the command's bvox_write_opts.force. */
#define CLI_FORCE_HELP                                                                       \
    "a folder output may go into a folder holding other files (bvox's own file names are "  \
    "replaced, nothing is removed)"
#define CLI_OPT_FORCE(type, member) {"--force", 0, CLI_FLAG, NULL, CLI_FORCE_HELP, CLI_AT(type, member)}

/* bvox_read with the parsed options, then the --voxel-size/--unit override
 * (a PNG stack or an uncalibrated TIFF has no z spacing of its own). */
bvox_status cli_read_volume(const char *path, const cli_read_args *a, bvox_volume **out);

/* The format named by --format, or the one the path's extension implies
 * (NULL when neither says). For reports only. */
const char *cli_input_format(const char *path, const cli_read_args *a);

/* 1 if arg is an option (starts with '-' and is not "-" alone). */
int cli_is_option(const char *arg);

/* Strict parsers: the whole string must be consumed; 0 on success. */
int cli_parse_double(const char *s, double *out);     /* finite */
int cli_parse_int64(const char *s, int64_t lo, int64_t hi, int64_t *out);
int cli_parse_size(const char *s, size_t *out);       /* 512, 64K, 512M, 8G, 1T (x1024) */
int cli_parse_dims(const char *s, bvox_dims *out);    /* "NX,NY,NZ" or "NXxNYxNZ" */
int cli_parse_triple(const char *s, double out[3]);   /* "SX,SY,SZ", each finite */

/* mkdir -p: create dir and its missing parents. 0 on success, else errno. */
int cli_make_dirs(const char *dir);

#endif
