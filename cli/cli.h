/*
 * cli.h — what the files of the `bvox` command share: the command table's
 * entry type, the subcommands' entry points and the exit-code convention.
 * Each cmd_<name>.c parses its arguments, makes one library call, prints the
 * result and maps the status to an exit code; no algorithm lives in cli/.
 */
#ifndef BVOX_CLI_H
#define BVOX_CLI_H

#include "bvox.h"

#include <stdio.h>

/* Exit codes: 0 success, 1 the operation failed (message from bvox_errmsg()),
 * 2 the command line was wrong. */
enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

/* argv[0] is the subcommand's name; argv[argc] is NULL. */
typedef int (*cli_run_fn)(int argc, char **argv);

/* A subcommand: its entry point and its description as data (opts.h),
 * which holds its name, summary, options and help. */
struct cli_spec;
typedef struct cli_command {
    cli_run_fn run;
    const struct cli_spec *spec;
} cli_command;

/* Each cmd_<name>.c: the entry point and the spec (name, options, help). */
int cmd_info(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_demo(int argc, char **argv);
int cmd_morph(int argc, char **argv);
int cmd_components(int argc, char **argv);
int cmd_measure(int argc, char **argv);
int cmd_labels(int argc, char **argv);
int cmd_interpolate(int argc, char **argv);
/* cli/mesh_labels.c: `bvox mesh IN --labels LIST -o DIR` after cmd_mesh's
 * parsing; returns the exit status. */
struct cli_read_args;
/* cmd_labels.c: read the lookup table (if lut) and the label volume, apply
 * --voxel-size/--unit; the table's warnings go to the warning handler, the
 * labels it lacks are warned about here (not with --quiet). 0, or -1 with bvox_errmsg() set. */
int cli_labels_load(const char *path, const struct cli_read_args *ra, const char *lut,
                    int64_t max_labels, bvox_labelset **set, bvox_label_table **table);
int cli_mesh_labels(const char *in, const struct cli_read_args *ra, const char *labels,
                    const char *lut, int64_t max_labels, const char *out, const char *fmt,
                    int ascii, int single);
int cmd_edit(int argc, char **argv);
int cmd_cut(int argc, char **argv);
int cmd_csg(int argc, char **argv);
int cmd_shape(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_mosaic(int argc, char **argv);
int cmd_image(int argc, char **argv);
int cmd_reconstruct(int argc, char **argv);
int cmd_view(int argc, char **argv);
int cmd_mesh(int argc, char **argv);
int cmd_voxelize(int argc, char **argv);
int cmd_meshinfo(int argc, char **argv);
int cmd_contours(int argc, char **argv);

extern const struct cli_spec cli_spec_info;
extern const struct cli_spec cli_spec_convert;
extern const struct cli_spec cli_spec_demo;
extern const struct cli_spec cli_spec_morph;
extern const struct cli_spec cli_spec_components;
extern const struct cli_spec cli_spec_measure;
extern const struct cli_spec cli_spec_labels;
extern const struct cli_spec cli_spec_interpolate;
extern const struct cli_spec cli_spec_edit;
extern const struct cli_spec cli_spec_cut;
extern const struct cli_spec cli_spec_csg;
extern const struct cli_spec cli_spec_shape;
extern const struct cli_spec cli_spec_render;
extern const struct cli_spec cli_spec_mosaic;
extern const struct cli_spec cli_spec_image;
extern const struct cli_spec cli_spec_reconstruct;
extern const struct cli_spec cli_spec_view;
extern const struct cli_spec cli_spec_mesh;
extern const struct cli_spec cli_spec_voxelize;
extern const struct cli_spec cli_spec_meshinfo;
extern const struct cli_spec cli_spec_contours;

/* "bvox: <message>" on stderr for a failed library call; returns CLI_FAIL. */
int cli_fail(void);
/* Set by the global --quiet (main.c): no warnings, no progress on stderr. */
extern int cli_quiet;
/* "bvox: <cmd>: <message> (see 'bvox <cmd> --help')" on stderr; returns CLI_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* report.c: the result of bvox_info_compute, as aligned text or one JSON
 * object. source (a file name) and format may be NULL. */
void cli_print_info_text(FILE *f, const bvox_info *info, const char *source, const char *format);
/* The info keys (cli_print_info_json_io), written into an object the caller has
 * opened (commands that report more, like measure, start with them). */
struct bvox__json; /* cli_json (json.h) */
void cli_info_json_fields(struct bvox__json *j, const bvox_info *info, const char *source,
                          const char *format);
/* "input" and "output": the file the command read and the file it wrote
 * (null when none), the same in every command whatever its "file" means. */
void cli_json_io(struct bvox__json *j, const char *input, const char *output);
/* For commands that write a volume (convert, morph, voxelize): on stdout
 * one JSON object, the info keys of vol with "file" the output and "format"
 * its writer (format, else by OUT's name), input, output, then what extra
 * adds (may be NULL). BVOX_ENOMEM from bvox_info_compute. */
bvox_status cli_print_volume_json(const bvox_volume *vol, const char *input, const char *output,
                                  const char *format,
                                  void (*extra)(struct bvox__json *j, const bvox_volume *vol,
                                                void *ctx),
                                  void *ctx);
/* One JSON object: the info keys, then input and output. */
void cli_print_info_json_io(FILE *f, const bvox_info *info, const char *source,
                            const char *format, const char *input, const char *output);

#endif
