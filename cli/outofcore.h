/*
 * outofcore.h — the commands' door to the out-of-core operations
 * (src/stream/): a .zarr input whose volume does not fit --max-memory is
 * opened as a slab source instead of being read whole.
 */
#ifndef BVOX_CLI_OUTOFCORE_H
#define BVOX_CLI_OUTOFCORE_H

#include "args.h"
#include "stream/stream.h"

/* 1: path is a .zarr too large for the budget and *src is open (with the
 * read options' binarisation and --voxel-size/--unit applied); 0: read it
 * in memory as usual; -1: error (printed). */
int cli_ooc_open(const char *path, const cli_read_args *ra, bvox__slab_source *src);
/* "bvox: IN: WHAT needs the whole volume in memory (...)" ; returns CLI_USAGE. */
int cli_ooc_refuse(const char *cmd, const char *in, const char *what);
/* Output of a streamed volume: a .zarr sink at out (1 ok, else error printed
 * and 0). */
int cli_ooc_sink(const char *cmd, const char *out, const bvox__slab_source *src,
                 const bvox_write_opts *wo, bvox__slab_sink *sink);

/* `bvox csg EXPR -o OUT` by slabs when EXPR's first file (the output grid)
 * is a .zarr over the budget: 1 done (info filled, as bvox_info_compute of
 * the result), 0 not streamed (evaluate in memory), -1 error (printed). */
int cli_ooc_csg(const char *cmd, const char *expr, const bvox_csg_eval_opts *opts,
                const cli_read_args *ra, const char *out, const bvox_write_opts *wo,
                bvox_info *info);

#endif
