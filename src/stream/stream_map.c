/*
 * stream_map.c — operations whose answer at a voxel depends only on the
 * voxels within a fixed reach (morphology: the structuring element's depth
 * along z; CSG: the voxel itself). Each slab is read with that reach as a
 * halo on both sides (clipped to the volume, so the volume's own border
 * behaves as in memory), handed to the in-memory kernel in one call, cut
 * back to its core and written. Errors of the kernel at the slab's cut
 * faces (which it takes for the volume's border) reach at most the halo
 * into the slab and are cut away.
 */
#include "stream/stream.h"

#include <math.h>
#include <stdlib.h>

bvox_status bvox__stream_map(const bvox__slab_source *const *src, int nsrc, int32_t halo,
                             int copies, bvox__slab_fn fn, void *ctx, bvox__slab_sink *sink)
{
    const bvox__slab_source *s0 = src[0];
    for (int i = 1; i < nsrc; i++)
        if (src[i]->dims.nx != s0->dims.nx || src[i]->dims.ny != s0->dims.ny ||
            src[i]->dims.nz != s0->dims.nz)
            return bvox__fail(BVOX_EINVAL, "%s and %s: the volumes differ in size (%dx%dx%d and "
                              "%dx%dx%d)", s0->name, src[i]->name, (int)s0->dims.nx,
                              (int)s0->dims.ny, (int)s0->dims.nz, (int)src[i]->dims.nx,
                              (int)src[i]->dims.ny, (int)src[i]->dims.nz);
    int32_t nz = s0->dims.nz,
            t = bvox__stream_depth(s0, halo, sink->align, copies + nsrc, sink->bytes);
    bvox_status st = BVOX_OK;
    bvox_volume *in[2] = {NULL, NULL};
    if (nsrc > 2) return bvox__fail(BVOX_EINVAL, "stream: at most two sources");
    for (int32_t z0 = 0; !st && z0 < nz; z0 += t) {
        int32_t z1 = z0 + t < nz ? z0 + t : nz;
        int32_t r0 = z0 - halo > 0 ? z0 - halo : 0;
        int32_t r1 = z1 + halo < nz ? z1 + halo : nz;
        for (int i = 0; i < nsrc && !st; i++) st = src[i]->read(src[i], r0, r1, &in[i]);
        bvox_volume *res = NULL, *core = NULL;
        if (!st) st = fn(ctx, in, nsrc, &res);
        for (int i = 0; i < nsrc && !st; i++)
            if (res == in[i]) in[i] = NULL; /* the kernel worked in place */
        if (!st) {
            bvox_box b = {0, 0, z0 - r0, res->nx, res->ny, z1 - r0};
            if (r0 == z0 && r1 == z1) core = res, res = NULL;
            else st = bvox_volume_crop(res, b, &core);
        }
        if (!st) st = sink->put(sink, core, z0);
        bvox_volume_destroy(core);
        bvox_volume_destroy(res);
        for (int i = 0; i < nsrc; i++) {
            bvox_volume_destroy(in[i]);
            in[i] = NULL;
        }
    }
    return st;
}

typedef struct morph_job {
    bvox__stream_morph_op op;
    int conn;
    double radius;
} morph_job;

static bvox_status morph_slab(void *ctx, bvox_volume *const *in, int nsrc, bvox_volume **out)
{
    (void)nsrc;
    const morph_job *j = ctx;
    bool ball = j->radius > 0;
    switch (j->op) {
    case BVOX__SM_DILATE:
        return ball ? bvox_morph_dilate_ball(in[0], j->radius, out)
                    : bvox_morph_dilate(in[0], j->conn, out);
    case BVOX__SM_ERODE:
        return ball ? bvox_morph_erode_ball(in[0], j->radius, out)
                    : bvox_morph_erode(in[0], j->conn, out);
    case BVOX__SM_OPEN: return bvox_morph_open(in[0], j->conn, j->radius, out);
    case BVOX__SM_CLOSE: return bvox_morph_close(in[0], j->conn, j->radius, out);
    }
    return bvox__fail(BVOX_EINVAL, "stream: unknown morphology");
}

bvox_status bvox__stream_morph(const bvox__slab_source *src, bvox__stream_morph_op op, int conn,
                               double radius, bvox__slab_sink *sink)
{
    /* the element's reach along z, in slices: a ball of radius r holds the
     * offsets k with (k sz)^2 <= r^2 */
    int32_t reach = 1;
    if (radius > 0) {
        double k = floor(radius / src->geom.spacing[2]);
        if (k > 65535) k = 65535;
        reach = (int32_t)k + 1;
    }
    int32_t halo = op == BVOX__SM_OPEN || op == BVOX__SM_CLOSE ? 2 * reach : reach;
    morph_job j = {op, conn, radius};
    const bvox__slab_source *s[1] = {src};
    return bvox__stream_map(s, 1, halo, 4, morph_slab, &j, sink);
}

static bvox_status csg_slab(void *ctx, bvox_volume *const *in, int nsrc, bvox_volume **out)
{
    (void)nsrc;
    bvox_status st = bvox_csg_apply(in[0], *(const bvox_csg_op *)ctx, in[1], NULL);
    if (st) return st;
    *out = in[0]; /* handed over: the slab is the result */
    return BVOX_OK;
}

bvox_status bvox__stream_csg(const bvox__slab_source *a, const bvox__slab_source *b,
                             bvox_csg_op op, bvox__slab_sink *sink)
{
    const bvox__slab_source *s[2] = {a, b};
    return bvox__stream_map(s, 2, 0, 1, csg_slab, &op, sink);
}
