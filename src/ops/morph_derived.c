/*
 * morph_derived.c — operations built from the whole-word primitives of
 * morph.c and components.c: opening, closing, hole filling, hollowing and
 * island removal. Nothing here touches single voxels.
 */
#include "internal.h"

static bvox_status step(const bvox_volume *in, int conn, double radius, bool erode,
                        bvox_volume **out)
{
    if (radius > 0)
        return erode ? bvox_morph_erode_ball(in, radius, out) : bvox_morph_dilate_ball(in, radius, out);
    return erode ? bvox_morph_erode(in, conn, out) : bvox_morph_dilate(in, conn, out);
}

static bvox_status two_steps(const bvox_volume *in, int conn, double radius, bool erode_first,
                             bvox_volume **out)
{
    *out = NULL;
    bvox_volume *mid;
    bvox__progress_scope ps;
    bvox__progress_sub(&ps, 0, 0.5, NULL);
    bvox_status st = step(in, conn, radius, erode_first, &mid);
    bvox__progress_restore(&ps);
    if (st) return st;
    bvox__progress_sub(&ps, 0.5, 1, NULL);
    st = step(mid, conn, radius, !erode_first, out);
    bvox__progress_restore(&ps);
    bvox_volume_destroy(mid);
    return st;
}

bvox_status bvox_morph_open(const bvox_volume *in, int conn, double radius, bvox_volume **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "open");
    bvox_status st = bvox__progress_end(&ps, two_steps(in, conn, radius, true, out));
    BVOX_RETURN_CHECKED(st, BVOX_CHECK_VOLUME, *out);
}

static bvox_status close_padded(const bvox_volume *in, int conn, double radius,
                                bvox_volume **out);

bvox_status bvox_morph_close(const bvox_volume *in, int conn, double radius, bvox_volume **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "close");
    return bvox__progress_end(&ps, close_padded(in, conn, radius, out));
}

static bvox_status close_padded(const bvox_volume *in, int conn, double radius,
                                bvox_volume **out)
{
    /* Closing near the border: dilation may reach past the volume and the
     * erosion then sees the outside as 0; pad by the element's reach so
     * that the border does not eat into the object. */
    *out = NULL;
    int32_t r[3] = {1, 1, 1};
    if (radius > 0)
        for (int a = 0; a < 3; a++) {
            double n = radius / in->geom.spacing[a] + 1;
            r[a] = n > BVOX_MAX_DIM ? BVOX_MAX_DIM : (int32_t)n;
        }
    bvox_volume *padded, *closed;
    bvox_status st = bvox_volume_pad(in, r, r, &padded);
    if (st) return st;
    st = two_steps(padded, conn, radius, false, &closed);
    bvox_volume_destroy(padded);
    if (st) return st;
    st = bvox_volume_crop(closed, (bvox_box){r[0], r[1], r[2], r[0] + in->nx, r[1] + in->ny,
                                             r[2] + in->nz}, out);
    bvox_volume_destroy(closed);
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}

static int is_index(const bvox_component *c, int64_t index, void *ctx)
{
    return index == *(const int64_t *)ctx;
}

static bvox_status fill_holes(const bvox_volume *in, bvox_volume **out);

bvox_status bvox_morph_fill_holes(const bvox_volume *in, bvox_volume **out)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "fill");
    return bvox__progress_end(&ps, fill_holes(in, out));
}

static bvox_status fill_holes(const bvox_volume *in, bvox_volume **out)
{
    /* The background padded by one voxel is one 6-connected region touching
     * the border plus the cavities; everything but that region is object. */
    *out = NULL;
    const int32_t one[3] = {1, 1, 1};
    bvox_volume *bg, *outside;
    bvox_status st = bvox_volume_pad(in, one, one, &bg);
    if (st) return st;
    bvox_volume_complement(bg);
    bvox_components *comps;
    bvox__progress_scope ps;
    bvox__progress_sub(&ps, 0, 0.9, NULL);
    st = bvox_components_find(bg, 6, &comps);
    bvox__progress_restore(&ps);
    bvox_volume_destroy(bg);
    if (st) return st;
    int64_t border = bvox_components_index_at(comps, 0, 0, 0);
    st = bvox_components_keep_if(comps, is_index, &border, &outside);
    bvox_components_destroy(comps);
    if (st) return st;
    bvox_volume_complement(outside);
    st = bvox_volume_crop(outside, (bvox_box){1, 1, 1, 1 + in->nx, 1 + in->ny, 1 + in->nz}, out);
    bvox_volume_destroy(outside);
    if (!st) (*out)->geom = in->geom;
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}

bvox_status bvox_morph_hollow(const bvox_volume *in, double thickness, bvox_volume **out)
{
    *out = NULL;
    if (!(thickness > 0))
        return bvox__fail(BVOX_EINVAL, "shell thickness must be > 0, not %g", thickness);
    bvox_volume *inner;
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "hollow");
    bvox_status st = bvox__progress_end(&ps, bvox_morph_erode_ball(in, thickness, &inner));
    if (st) return st;
    st = bvox_volume_copy(in, out);
    if (!st) st = bvox_csg_apply(*out, BVOX_CSG_DIFFERENCE, inner, NULL);
    bvox_volume_destroy(inner);
    if (st) {
        bvox_volume_destroy(*out); /* a failed call hands nothing out */
        *out = NULL;
    }
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}

static int big_enough(const bvox_component *c, int64_t index, void *ctx)
{
    return c->voxels >= *(const int64_t *)ctx;
}

bvox_status bvox_morph_remove_islands(const bvox_volume *in, int conn, int64_t min_voxels,
                                      bvox_volume **out)
{
    *out = NULL;
    bvox_components *comps;
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "islands");
    bvox__progress_scope sub;
    bvox__progress_sub(&sub, 0, 0.9, NULL);
    bvox_status st = bvox_components_find(in, conn, &comps);
    bvox__progress_restore(&sub);
    if (st) return bvox__progress_end(&ps, st);
    st = bvox_components_keep_if(comps, big_enough, &min_voxels, out);
    bvox_components_destroy(comps);
    if (!st) BVOX_CHECK_VOLUME(*out);
    return bvox__progress_end(&ps, st);
}
