/*
 * outofcore.c — choosing between the in-memory and the out-of-core path for
 * a command's input, and the .zarr output of a streamed volume.
 *
 * Only .zarr inputs stream (their chunks can be read a box at a time); a
 * .zarr whose words (and the copies an operation takes) fit the budget is
 * read whole, so small inputs behave exactly as before.
 */
#include "outofcore.h"

#include "cli.h"
#include "io/zarr.h"

#include <stdio.h>
#include <string.h>

int cli_ooc_open(const char *path, const cli_read_args *ra, bvox__slab_source *src)
{
    memset(src, 0, sizeof *src);
    const char *f = ra->opts.format;
    if (f ? strcmp(f, "zarr") != 0 : !bvox__zarr_is_dir(path)) return 0;
    if (bvox__slab_source_zarr(path, &ra->opts.binarize, src)) {
        /* not streamable (Otsu, bad metadata): the in-memory reader says why,
         * or reads it when it fits */
        bvox__slab_source_close(src);
        return 0;
    }
    if (!bvox__stream_needed(src->dims)) {
        bvox__slab_source_close(src);
        return 0;
    }
    if (ra->spacing_given)
        for (int a = 0; a < 3; a++) src->geom.spacing[a] = ra->spacing[a];
    if (ra->unit) snprintf(src->geom.unit, sizeof src->geom.unit, "%s", ra->unit);
    return 1;
}

int cli_ooc_refuse(const char *cmd, const char *in, const char *what)
{
    fprintf(stderr, "bvox: %s: %s: %s needs the whole volume in memory, and it does not fit "
                    "--max-memory (%zu bytes); raise --max-memory\n",
            cmd, in, what, bvox_memory_budget());
    return CLI_FAIL;
}

int cli_ooc_sink(const char *cmd, const char *out, const bvox__slab_source *src,
                 const bvox_write_opts *wo, bvox__slab_sink *sink)
{
    const char *f = wo->format ? wo->format : bvox_format_for_path(out);
    if (!f || strcmp(f, "zarr")) {
        fprintf(stderr, "bvox: %s: %s: a volume larger than --max-memory is written as .zarr "
                        "(slab by slab); name the output NAME.zarr\n", cmd, out);
        return 0;
    }
    if (bvox__slab_sink_zarr(out, src->dims, &src->geom, wo, sink)) {
        cli_fail();
        return 0;
    }
    return 1;
}
