/*
 * mesh_from_volume.c — bvox_mesh_from_volume: the dispatcher over the
 * meshing methods (marching cubes in mc.c, cuberille faces in cuberille.c)
 * and the optional Taubin smoothing (smooth.c). Kept apart from the container
 * (mesh.c), which the methods build on, so that no file both serves and
 * calls them.
 */
#include "mesh_private.h"

static bvox_status mesh_from_volume(const bvox_volume *vol, const bvox_mesh_opts *opts,
                                    bvox_mesh **out);

bvox_status bvox_mesh_from_volume(const bvox_volume *vol, const bvox_mesh_opts *opts,
                                  bvox_mesh **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "mesh");
    return bvox__progress_end(&ps, mesh_from_volume(vol, opts, out));
}

/* Progress: the meshing, then the smoothing (when asked) in the second half. */
static bvox_status mesh_from_volume(const bvox_volume *vol, const bvox_mesh_opts *opts,
                                    bvox_mesh **out)
{
    BVOX_CHECK_VOLUME(vol);
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_mesh_from_volume: out is NULL");
    *out = NULL;
    if (!vol) return bvox__fail(BVOX_EINVAL, "bvox_mesh_from_volume: volume is NULL");
    bvox_mesh_opts o = BVOX_MESH_OPTS_INIT;
    if (opts) o = *opts;
    if (o.method != BVOX_MESH_MC && o.method != BVOX_MESH_CUBERILLE)
        return bvox__fail(BVOX_EINVAL, "unknown meshing method %d", (int)o.method);
    if (o.smooth < 0) return bvox__fail(BVOX_EINVAL, "smoothing iterations must be >= 0");
    bvox_mesh *m;
    bvox_status st = bvox_mesh_create(&m);
    if (st) return st;
    bvox__progress_scope ps;
    bvox__progress_sub(&ps, 0, o.smooth > 0 ? 0.5 : 1, NULL);
    st = o.method == BVOX_MESH_MC ? bvox__mesh_mc(vol, m) : bvox__mesh_cuberille(vol, m);
    if (!st) st = bvox__progress(1);
    bvox__progress_restore(&ps);
    if (!st && o.smooth > 0) {
        bvox__progress_sub(&ps, 0.5, 1, "smooth");
        st = bvox_mesh_smooth(m, o.smooth, o.lambda == 0 ? 0.5 : o.lambda,
                              o.mu == 0 ? -0.53 : o.mu);
        bvox__progress_restore(&ps);
    }
    if (st) {
        bvox_mesh_destroy(m);
        return st;
    }
    *out = m;
    BVOX_CHECK_MESH(*out);
    return BVOX_OK;
}
