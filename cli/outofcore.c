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

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cli_ooc_open(const char *path, const cli_read_args *ra, bvox__slab_source *src)
{
    memset(src, 0, sizeof *src);
    const char *f = ra->opts.format;
    if (f ? strcmp(f, "zarr") != 0 : !bvox__slab_source_is_zarr(path)) return 0;
    if (bvox__slab_source_zarr_level(path, ra->opts.zarr_level, &ra->opts.binarize, src)) {
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

/* ------------------------------------------------------------ csg by slabs
 *
 * The expression is evaluated once per slab of the output grid (the first
 * file's), by bvox_csg_eval itself, with a loader that hands out the same
 * slab of every file: each file is a slab source (a .zarr read a box at a
 * time; any other file read once and cut). The slab's origin is moved to its
 * first slice, so primitives land where they do in the whole grid. Placement
 * offsets (FILE@...) would need other slices of a file than the slab's and
 * are refused. */

enum { OOC_MAX_FILES = 16 };

typedef struct csg_slabs {
    const cli_read_args *ra;
    int n;
    char *names[OOC_MAX_FILES];
    bvox__slab_source src[OOC_MAX_FILES];
    bvox_volume *whole[OOC_MAX_FILES]; /* files read whole (not .zarr) */
    int32_t z0, z1;                    /* the slab being evaluated */
    bool probe;                        /* only record the names */
} csg_slabs;

static bvox_status slab_load(void *ctx, const char *name, bvox_volume **out)
{
    csg_slabs *c = ctx;
    int i = 0;
    while (i < c->n && strcmp(c->names[i], name)) i++;
    if (i == c->n) {
        if (c->n == OOC_MAX_FILES)
            return bvox__fail(BVOX_EINVAL, "more than %d files in a streamed expression",
                              OOC_MAX_FILES);
        c->names[i] = bvox__mem_strdup(name);
        if (!c->names[i]) return bvox__fail(BVOX_ENOMEM, "out of memory");
        c->n++;
    }
    if (c->probe) return bvox_volume_create((bvox_dims){1, 1, 1}, out);
    bvox__slab_source *s = &c->src[i];
    if (!s->read) {
        int r = cli_ooc_open(name, c->ra, s);
        if (r == 0) { /* small, or not a .zarr: read once, cut per slab */
            bvox_status st = cli_read_volume(name, c->ra, &c->whole[i]);
            if (st) return st;
            st = bvox__slab_source_memory(c->whole[i], s);
            if (st) return st;
        }
    }
    int32_t z1 = c->z1 < s->dims.nz ? c->z1 : s->dims.nz;
    if (c->z0 >= z1) /* beyond this file's extent: empty */
        return bvox_volume_create((bvox_dims){s->dims.nx, s->dims.ny, 1}, out);
    bvox_status st = s->read(s, c->z0, z1, out);
    if (st) return st;
    bvox_geometry g = s->geom;
    g.origin[2] += c->z0 * g.spacing[2];
    return bvox_volume_set_geometry(*out, &g);
}

static void csg_slabs_release(csg_slabs *c)
{
    for (int i = 0; i < c->n; i++) {
        bvox__slab_source_close(&c->src[i]);
        bvox_volume_destroy(c->whole[i]);
        free(c->names[i]);
    }
}

int cli_ooc_csg(const char *cmd, const char *expr, const bvox_csg_eval_opts *opts,
                const cli_read_args *ra, const char *out, const bvox_write_opts *wo,
                bvox_info *info)
{
    csg_slabs c;
    memset(&c, 0, sizeof c);
    c.ra = ra;
    c.probe = true;
    bvox_csg_eval_opts o = *opts;
    o.load = slab_load;
    o.load_ctx = &c;
    bvox_volume *v = NULL;
    bvox_status st = bvox_csg_eval(expr, &o, &v); /* names only, 1-voxel files */
    bvox_volume_destroy(v);
    bvox__slab_source grid;
    if (st || c.n == 0 || cli_ooc_open(c.names[0], ra, &grid) != 1) {
        csg_slabs_release(&c);
        return 0; /* in memory (an error there is reported there) */
    }
    if (strchr(expr, '@')) {
        cli_ooc_refuse(cmd, c.names[0], "a placement offset (FILE@...)");
        bvox__slab_source_close(&grid);
        csg_slabs_release(&c);
        return -1;
    }
    c.probe = false;
    bvox__slab_sink sink;
    if (!cli_ooc_sink(cmd, out, &grid, wo, &sink)) {
        bvox__slab_source_close(&grid);
        csg_slabs_release(&c);
        return -1;
    }
    memset(info, 0, sizeof *info);
    info->dims = grid.dims;
    info->geometry = grid.geom;
    int32_t nz = grid.dims.nz, t = bvox__stream_depth(&grid, 0, sink.align, 2 + c.n, sink.bytes);
    for (int32_t z0 = 0; !st && z0 < nz; z0 += t) {
        c.z0 = z0;
        c.z1 = z0 + t < nz ? z0 + t : nz;
        v = NULL;
        st = bvox_csg_eval(expr, &o, &v);
        if (!st && bvox_volume_dims(v).nz != c.z1 - z0)
            st = bvox__fail(BVOX_EINVAL, "stream: a slab came out of the wrong depth");
        if (!st) st = sink.put(&sink, v, z0);
        bvox_box b;
        if (!st && bvox_volume_bbox(v, &b)) {
            b.z0 += z0, b.z1 += z0;
            if (!info->count) info->bbox = b;
            bvox_box *B = &info->bbox;
            if (b.x0 < B->x0) B->x0 = b.x0;
            if (b.y0 < B->y0) B->y0 = b.y0;
            if (b.x1 > B->x1) B->x1 = b.x1;
            if (b.y1 > B->y1) B->y1 = b.y1;
            if (b.z1 > B->z1) B->z1 = b.z1;
            info->count += bvox_volume_count(v);
        }
        bvox_volume_destroy(v);
    }
    sink.close(&sink, true, &st);
    const double *sp = grid.geom.spacing;
    info->volume = (double)info->count * sp[0] * sp[1] * sp[2];
    info->empty = info->count == 0;
    bvox__slab_source_close(&grid);
    csg_slabs_release(&c);
    if (st) {
        cli_fail();
        return -1;
    }
    return 1;
}
