/*
 * manip.h — what the manipulation commands (edit, cut, csg, shape) share:
 * refusing an output name of unknown format before any work, printing a
 * changed region (inclusive voxel indices, like `bvox info`), and the output
 * grid that csg and shape build from --dims, --voxel-size, --unit, --origin.
 */
#ifndef BVOX_CLI_MANIP_H
#define BVOX_CLI_MANIP_H

#include "args.h"
#include "json.h"

/* CLI_OK, or CLI_USAGE (message printed) when neither --output-format nor
 * the name of out says which format to write. */
int cli_check_output(const char *cmd, const char *out, const bvox_write_opts *wo);

/* "A,B,C,D" (a plane), each finite; 0 on success. */
int cli_parse_plane(const char *s, double p[4]);

/* A plane option's value (--plane, --cut): "A,B,C,D" with A,B,C not all
 * zero; given is set once it is. The taker's messages name the option. */
typedef struct cli_plane {
    double p[4];
    int given;
} cli_plane;
int cli_take_plane(const char *cmd, const cli_opt *o, const char *v, void *plane);
/* "above", "below": the sides of --keep (index 1: below). */
extern const char *const cli_keep_choices[];

/* "0.5*x - y + 2*z - 12" for the plane p (zero terms left out). */
void cli_format_plane(char *buf, size_t size, const double p[4]);

/* "x 3..5, y 0..9, z 64..64" (inclusive) or "none" for an empty box. */
void cli_print_box(FILE *f, const bvox_box *box);
/* {"min":[x,y,z],"max":[x,y,z]} (inclusive) or null for an empty box. */
void cli_json_box(cli_json *j, const bvox_box *box);
/* Grow acc (half-open) to hold box; empty boxes change nothing. */
void cli_box_union(bvox_box *acc, const bvox_box *box);

/* The grid of csg and shape: dims from --dims (0 when not given), spacing
 * from --voxel-size (default 1), unit from --unit, origin from --origin. */
typedef struct cli_grid {
    int origin_given;
    double origin[3];
} cli_grid;
/* Taker of --origin X,Y,Z into a cli_grid. */
int cli_take_origin(const char *cmd, const cli_opt *o, const char *v, void *grid);
void cli_grid_to_opts(const cli_read_args *ra, const cli_grid *g, bvox_csg_eval_opts *o);

#endif
