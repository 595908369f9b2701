/*
 * interpolate.c — fill the slices of a mask that were not annotated
 * (bvox_interpolate_slices): shape-based interpolation (Raya and Udupa;
 * Herman's "shape-based interpolation") between each pair of consecutive
 * annotated z slices, through the same signed distance maps and the same
 * blend rule as the reconstruction of contour stacks (stack_volume.c):
 * slice z between annotated slices a < b is (1 - t) d_a + t d_b <= 0 with
 * t = (z - a) / (b - a). Annotated slices are copied unchanged; slices
 * before the first and after the last annotated one stay empty (nothing to
 * interpolate from). An annotated slice is one with any 1-voxel unless the
 * caller lists them (an annotated empty slice then closes a shape).
 */
#include "contour_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Slice z of vol as a bitmap (rows of wpr words, x fastest). */
static void get_slice(const bvox_volume *v, int32_t z, size_t wpr, uint64_t *bits)
{
    memset(bits, 0, (size_t)v->ny * wpr * sizeof *bits);
    size_t w = (size_t)z >> 6;
    unsigned b = (unsigned)z & 63;
    for (int32_t y = 0; y < v->ny; y++)
        for (int32_t x = 0; x < v->nx; x++)
            if ((bvox__column_c(v, x, y)[w] >> b) & 1)
                bits[(size_t)y * wpr + ((size_t)x >> 6)] |= 1ull << (x & 63);
}

bvox_status bvox_interpolate_slices(const bvox_volume *in, const uint8_t *annotated,
                                    bvox_volume **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_interpolate_slices: out is NULL");
    *out = NULL;
    if (!in) return bvox__fail(BVOX_EINVAL, "bvox_interpolate_slices: volume is NULL");
    int32_t nx = in->nx, ny = in->ny, nz = in->nz;
    size_t wpr = ((size_t)nx + 63) / 64, plane = (size_t)nx * ny;
    bvox_status st;
    bvox_volume *o;
    st = bvox_volume_copy(in, &o);
    if (st) return st;
    /* which slices are annotated */
    uint8_t *ann = bvox__mem_alloc((size_t)nz);
    if (!ann) {
        bvox_volume_destroy(o);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    if (annotated) memcpy(ann, annotated, (size_t)nz);
    else {
        memset(ann, 0, (size_t)nz);
        for (int32_t y = 0; y < ny; y++)
            for (int32_t x = 0; x < nx; x++) {
                const uint64_t *c = bvox__column_c(in, x, y);
                for (size_t w = 0; w < in->wpc; w++)
                    for (uint64_t m = c[w]; m; m &= m - 1)
                        ann[w * 64 + (size_t)__builtin_ctzll(m)] = 1;
            }
    }
    size_t nbits = (size_t)ny * wpr;
    size_t scratch = bvox__edt_scratch_doubles(nx, ny);
    uint64_t *bits = bvox__alloc(nbits * sizeof *bits, false, "slice bitmap", &st);
    float *da = bits ? bvox__alloc(2 * plane * sizeof *da, false, "distance maps", &st) : NULL;
    double *tmp = da ? bvox__alloc(scratch * sizeof *tmp, false, "distance scratch", &st) : NULL;
    if (!tmp) goto done;
    float *db = da + plane;
    const float cap = (float)(nx + ny);
    int32_t prev = -1;
    for (int32_t z = 0; z < nz; z++) {
        if (!ann[z]) continue;
        if (prev >= 0 && z - prev > 1) {
            get_slice(in, prev, wpr, bits);
            bvox__signed_edt(bits, wpr, nx, ny, cap, tmp, da);
            get_slice(in, z, wpr, bits);
            bvox__signed_edt(bits, wpr, nx, ny, cap, tmp, db);
            for (int32_t k = prev + 1; k < z; k++) {
                float t = (float)(k - prev) / (float)(z - prev), s = 1.0f - t;
                size_t w = (size_t)k >> 6;
                uint64_t bit = 1ull << (k & 63);
                for (int32_t y = 0; y < ny; y++)
                    for (int32_t x = 0; x < nx; x++) {
                        size_t i = (size_t)y * nx + x;
                        uint64_t *c = bvox__column(o, x, y);
                        if (s * da[i] + t * db[i] <= 0.0f) c[w] |= bit;
                        else c[w] &= ~bit;
                    }
            }
        }
        prev = z;
    }
done:
    if (bits) bvox__free(bits, nbits * sizeof *bits);
    if (da) bvox__free(da, 2 * plane * sizeof *da);
    if (tmp) bvox__free(tmp, scratch * sizeof *tmp);
    free(ann);
    if (st) {
        bvox_volume_destroy(o);
        return st;
    }
    *out = o;
    return BVOX_OK;
}
