/*
 * stream_measure.c — info and measure of a volume seen one slab at a time.
 *
 * Info: counts and bounding boxes of disjoint slabs add up.
 *
 * Measure: bvox__measure_scan's integer sums (count, moments, the Euler
 * number of the cube complex, the 0/1 transitions of the 13 directions) are
 * sums over voxels and over 2x2x2 windows with the outside as background.
 * For slabs A = [z0, z1] and B = [z1, z2] that share slice S = [z1, z1],
 * every window of A u B lies in A or in B, and the windows that reach past
 * A's last slice (or before B's first) into the zero outside are exactly
 * S's windows past its two sides: scan(A u B) = scan(A) + scan(B) - scan(S).
 * Moments are shifted to the volume's z before they are added. The topology
 * (components, cavities) comes from stream_cc.c in the same pass.
 */
#include "stream/stream.h"

#include "measure/measure.h"

#include <string.h>

bvox_status bvox__stream_info(const bvox__slab_source *src, bvox_info *out)
{
    memset(out, 0, sizeof *out);
    out->dims = src->dims;
    out->geometry = src->geom;
    int32_t nz = src->dims.nz, t = bvox__stream_depth(src, 0, src->chunk_z, 1, 0);
    bvox_box box = {0};
    bvox_status st = BVOX_OK;
    int64_t count = 0;
    for (int32_t z0 = 0; !st && z0 < nz; z0 += t) {
        int32_t z1 = z0 + t < nz ? z0 + t : nz;
        bvox_volume *slab = NULL;
        if ((st = src->read(src, z0, z1, &slab))) break;
        bvox_box b;
        if (bvox_volume_bbox(slab, &b)) {
            b.z0 += z0, b.z1 += z0;
            if (!count) box = b;
            if (b.x0 < box.x0) box.x0 = b.x0;
            if (b.y0 < box.y0) box.y0 = b.y0;
            if (b.x1 > box.x1) box.x1 = b.x1;
            if (b.y1 > box.y1) box.y1 = b.y1;
            if (b.z1 > box.z1) box.z1 = b.z1; /* z0 comes from the first slab with voxels */
            count += bvox_volume_count(slab);
        }
        bvox_volume_destroy(slab);
    }
    if (st) return st;
    const double *sp = src->geom.spacing;
    out->count = count;
    out->volume = (double)count * sp[0] * sp[1] * sp[2];
    out->empty = count == 0;
    out->bbox = box;
    return BVOX_OK;
}

/* acc += sign * (s with its z moved by dz). */
static void add_scan(bvox__scan *acc, const bvox__scan *s, int32_t dz, int sign, bool *any)
{
    bvox__wide n = s->count, d = dz, sx = s->s[0], sy = s->s[1], sz = s->s[2];
    bvox__wide sh[3] = {sx, sy, sz + d * n};
    /* ss order: xx yy zz xy xz yz */
    bvox__wide ssh[6] = {s->ss[0], s->ss[1], s->ss[2] + 2 * d * sz + d * d * n, s->ss[3],
                         s->ss[4] + d * sx, s->ss[5] + d * sy};
    acc->count += sign * s->count;
    for (int a = 0; a < 3; a++) acc->s[a] += sign * sh[a];
    for (int k = 0; k < 6; k++) acc->ss[k] += sign * ssh[k];
    acc->euler += sign * s->euler;
    for (int c = 0; c < BVOX__NDIR; c++) acc->trans[c] += sign * s->trans[c];
    if (sign > 0 && s->count) {
        const int32_t b[6] = {s->bbox[0], s->bbox[1], s->bbox[2] + dz,
                              s->bbox[3], s->bbox[4], s->bbox[5] + dz};
        if (!*any) memcpy(acc->bbox, b, sizeof b);
        for (int a = 0; a < 3; a++) {
            if (b[a] < acc->bbox[a]) acc->bbox[a] = b[a];
            if (b[a + 3] > acc->bbox[a + 3]) acc->bbox[a + 3] = b[a + 3];
        }
        *any = true;
    }
}

/* The scan of the slab's last slice (the next slab's first). */
static bvox_status scan_last_slice(const bvox_volume *slab, bvox__scan *s)
{
    bvox_volume *S = NULL;
    bvox_box b = {0, 0, slab->nz - 1, slab->nx, slab->ny, slab->nz};
    bvox_status st = bvox_volume_crop(slab, b, &S);
    if (!st) st = bvox__measure_scan(S, s);
    bvox_volume_destroy(S);
    return st;
}

bvox_status bvox__stream_measure(const bvox__slab_source *src, bvox_measures *out)
{
    memset(out, 0, sizeof *out);
    const bvox_dims d = src->dims;
    bvox__scan acc;
    memset(&acc, 0, sizeof acc);
    bool any = false;
    /* object 26, background 6 and background 26 (cavities), one pass */
    bvox__stream_cc *cc[3] = {NULL, NULL, NULL};
    bvox_status st = bvox__stream_cc_begin(d, 26, false, false, false, &cc[0]);
    if (!st) st = bvox__stream_cc_begin(d, 6, true, true, false, &cc[1]);
    if (!st) st = bvox__stream_cc_begin(d, 26, true, true, false, &cc[2]);
    int32_t nz = d.nz, t = bvox__stream_depth(src, 1, src->chunk_z, 6, 0);
    /* slabs [z0, z1) with z1 the next slab's first slice + 1; the last ends at nz */
    for (int32_t z0 = 0, z1 = 0; !st && z1 < nz; z0 = z1 - 1) {
        z1 = z0 + t + 1 < nz ? z0 + t + 1 : nz;
        bvox_volume *slab = NULL;
        if ((st = src->read(src, z0, z1, &slab))) break;
        bvox__scan s;
        st = bvox__measure_scan(slab, &s);
        if (!st) add_scan(&acc, &s, z0, 1, &any);
        if (!st && z1 < nz) {
            st = scan_last_slice(slab, &s);
            if (!st) add_scan(&acc, &s, z1 - 1, -1, &any);
        }
        for (int k = 0; k < 3 && !st; k++) st = bvox__stream_cc_add(cc[k], slab, z0);
        bvox_volume_destroy(slab);
    }
    int64_t n[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        if (st) bvox__stream_cc_abort(cc[k]);
        else st = bvox__stream_cc_finish(cc[k], src->geom.spacing, &n[k], NULL);
    }
    if (st) return st;
    double weight[BVOX__NDIR];
    bvox__crofton_weights(src->geom.spacing, weight);
    bvox_measures m;
    bvox__measure_from_scan(&acc, &src->geom, weight, NULL, &m);
    if (acc.count) {
        /* as measure.c's topology: no background, no cavities; cavities_26
         * only counted when there are 6-connected ones */
        m.components = n[0];
        m.cavities = n[1];
        m.cavities_26 = n[1] > 0 ? n[2] : 0;
    }
    m.tunnels = m.components + m.cavities - m.euler;
    *out = m;
    return BVOX_OK;
}
