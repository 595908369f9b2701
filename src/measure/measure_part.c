/*
 * measure_part.c — bvox_measure_part and bvox_measure_from_sums: the measure
 * scan of one part of a partition (a Dask chunk), such that the parts' sums
 * add up to the whole volume's scan.
 *
 * Why it adds up: along one axis, for boxes A = [a, m] and B = [m, b] that
 * share plane S = [m, m], every 2x2x2 window of A u B lies in A or in B, and
 * the windows of A (of B) that reach past S into the zero outside are exactly
 * S's windows on that side: scan(A u B) = scan(A) + scan(B) - scan(S) (as
 * src/stream/stream_measure.c uses along z). Applied along x, y and z in
 * turn, a part with a one-voxel overlap on each high side that has a
 * neighbour contributes sum over the subsets T of those sides of
 * (-1)^|T| scan(the part cut to its last plane along each axis of T).
 * Moments are shifted to the whole volume's indices before they are added.
 */
#include "measure/measure.h"

#include <math.h>
#include <string.h>

static bvox_int128 to_i128(bvox__wide v)
{
    bvox_int128 r;
#ifdef __SIZEOF_INT128__
    r.hi = (int64_t)(v >> 64);
    r.lo = (uint64_t)v;
#else
    long double h = floorl(v / 18446744073709551616.0L);
    r.hi = (int64_t)h;
    r.lo = (uint64_t)(v - h * 18446744073709551616.0L);
#endif
    return r;
}

static bvox__wide from_i128(bvox_int128 v)
{
#ifdef __SIZEOF_INT128__
    return (bvox__wide)(((unsigned __int128)(uint64_t)v.hi << 64) | v.lo);
#else
    return (long double)v.hi * 18446744073709551616.0L + (long double)v.lo;
#endif
}

/* acc += sign * (s moved by d). ss order: xx yy zz xy xz yz. */
static void add_shifted(bvox__scan *acc, const bvox__scan *s, const int32_t d[3], int sign)
{
    bvox__wide n = s->count, sh[3], dd[3];
    for (int a = 0; a < 3; a++) {
        dd[a] = d[a];
        sh[a] = s->s[a] + dd[a] * n;
    }
    static const int pa[6] = {0, 1, 2, 0, 0, 1}, pb[6] = {0, 1, 2, 1, 2, 2};
    acc->count += sign * s->count;
    for (int a = 0; a < 3; a++) acc->s[a] += sign * sh[a];
    for (int k = 0; k < 6; k++) {
        int a = pa[k], b = pb[k];
        /* sum (p + da)(q + db) = ss + da sum q + db sum p + da db n */
        acc->ss[k] += sign * (s->ss[k] + dd[a] * s->s[b] + dd[b] * s->s[a] + dd[a] * dd[b] * n);
    }
    acc->euler += sign * s->euler;
    for (int c = 0; c < BVOX__NDIR; c++) acc->trans[c] += sign * s->trans[c];
}

bvox_status bvox_measure_part(const bvox_volume *part, const int32_t core[3],
                              const int32_t offset[3], bvox_measure_sums *out)
{
    memset(out, 0, sizeof *out);
    if (!part || !core || !offset)
        return bvox__fail(BVOX_EINVAL, "measure part: NULL argument");
    const int32_t n[3] = {part->nx, part->ny, part->nz};
    int over[3];
    for (int a = 0; a < 3; a++) {
        if (core[a] != n[a] && core[a] != n[a] - 1)
            return bvox__fail(BVOX_EINVAL,
                              "measure part: core %d along axis %d must be the part's size %d "
                              "or one less", (int)core[a], a, (int)n[a]);
        if (core[a] < 1) return bvox__fail(BVOX_EINVAL, "measure part: empty core");
        over[a] = core[a] < n[a];
    }
    bvox__scan acc;
    memset(&acc, 0, sizeof acc);
    bvox_status st = BVOX_OK;
    for (int t = 0; t < 8 && !st; t++) {
        if ((t & 1 && !over[0]) || (t & 2 && !over[1]) || (t & 4 && !over[2])) continue;
        bvox_box b = {0, 0, 0, n[0], n[1], n[2]};
        int32_t d[3] = {offset[0], offset[1], offset[2]};
        int sign = 1;
        int32_t *lo[3] = {&b.x0, &b.y0, &b.z0};
        for (int a = 0; a < 3; a++)
            if (t >> a & 1) *lo[a] = n[a] - 1, d[a] += n[a] - 1, sign = -sign;
        bvox__scan s;
        if (t == 0) {
            st = bvox__measure_scan(part, &s);
        } else {
            bvox_volume *plane = NULL;
            st = bvox_volume_crop(part, b, &plane);
            if (!st) st = bvox__measure_scan(plane, &s);
            bvox_volume_destroy(plane);
        }
        if (!st) add_shifted(&acc, &s, d, sign);
    }
    /* the bbox of the core alone (the overlap belongs to the neighbours) */
    bvox_box cb = {0, 0, 0, core[0], core[1], core[2]}, bb;
    bool any = false;
    if (!st && (over[0] || over[1] || over[2])) {
        bvox_volume *c = NULL;
        st = bvox_volume_crop(part, cb, &c);
        if (!st) any = bvox_volume_bbox(c, &bb);
        bvox_volume_destroy(c);
    } else if (!st) {
        any = bvox_volume_bbox(part, &bb);
    }
    if (st) return st;
    out->count = acc.count;
    for (int a = 0; a < 3; a++) out->s[a] = to_i128(acc.s[a]);
    for (int k = 0; k < 6; k++) out->ss[k] = to_i128(acc.ss[k]);
    if (any) {
        const int32_t b[6] = {bb.x0 + offset[0], bb.y0 + offset[1], bb.z0 + offset[2],
                              bb.x1 + offset[0], bb.y1 + offset[1], bb.z1 + offset[2]};
        memcpy(out->bbox, b, sizeof b);
    }
    out->euler = acc.euler;
    for (int c = 0; c < BVOX__NDIR; c++) out->trans[c] = acc.trans[c];
    return BVOX_OK;
}

bvox_status bvox_measure_from_sums(const bvox_measure_sums *sums, const bvox_geometry *geom,
                                   bvox_measures *out)
{
    if (!sums || !geom || !out) return bvox__fail(BVOX_EINVAL, "measure from sums: NULL argument");
    bvox__scan s;
    memset(&s, 0, sizeof s);
    s.count = sums->count;
    for (int a = 0; a < 3; a++) s.s[a] = from_i128(sums->s[a]);
    for (int k = 0; k < 6; k++) s.ss[k] = from_i128(sums->ss[k]);
    memcpy(s.bbox, sums->bbox, sizeof s.bbox);
    s.euler = sums->euler;
    for (int c = 0; c < BVOX__NDIR; c++) s.trans[c] = sums->trans[c];
    double weight[BVOX__NDIR];
    bvox__crofton_weights(geom->spacing, weight);
    bvox__measure_from_scan(&s, geom, weight, NULL, out);
    out->tunnels = 0;
    return BVOX_OK;
}
