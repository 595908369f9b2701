/*
 * samples.c — volumes from and to arrays in the caller's memory (the Python
 * package's NumPy arrays): the binariser of the file readers, pointed at the
 * caller's samples in place, and the writers' unpacker, writing bytes 0/1.
 * Neither copies the array: a volume costs its words (nx*ny*nz/8 bytes) only.
 * bvox_volume_from_words is the inverse of bvox_volume_words (a volume sent
 * to another process as its words).
 */
#include "io.h"

#include <string.h>

bvox_status bvox_volume_from_samples(const void *samples, bvox_dtype dtype, bvox_dims dims,
                                     bvox_order order, const bvox_binarize *how,
                                     bvox_volume **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "array: no output volume");
    *out = NULL;
    if (order != BVOX_ORDER_X_FASTEST && order != BVOX_ORDER_Z_FASTEST)
        return bvox__fail(BVOX_EINVAL, "array: unknown sample order %d", (int)order);
    bvox__gray g;
    bvox__gray_init(&g);
    g.dims = dims;
    g.dtype = dtype;
    g.data = samples;
    g.z_fastest = order == BVOX_ORDER_Z_FASTEST;
    return bvox__binarize(&g, how, "array", out);
}

bvox_status bvox_volume_to_bytes(const bvox_volume *vol, bvox_order order, uint8_t *dst)
{
    if (!vol || !dst) return bvox__fail(BVOX_EINVAL, "array: no volume or no destination");
    if (order == BVOX_ORDER_Z_FASTEST) {
        bvox__unpack_columns(vol, dst);
        return BVOX_OK;
    }
    if (order != BVOX_ORDER_X_FASTEST)
        return bvox__fail(BVOX_EINVAL, "array: unknown sample order %d", (int)order);
    size_t slice = (size_t)vol->nx * (size_t)vol->ny;
    for (int32_t z0 = 0; z0 < vol->nz; z0 += 64) {
        int32_t n = vol->nz - z0 < 64 ? vol->nz - z0 : 64;
        bvox__unpack_slices(vol, z0, n, 1, dst + (size_t)z0 * slice);
    }
    return BVOX_OK;
}

bvox_status bvox_volume_from_words(bvox_dims dims, const uint64_t *words, size_t word_count,
                                   bvox_volume **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "words: no output volume");
    *out = NULL;
    if (!words) return bvox__fail(BVOX_EINVAL, "words: no words given");
    bvox_volume *v;
    bvox_status st = bvox__volume_create_uninit(dims, &v);
    if (st) return st;
    if (word_count != v->nwords) {
        size_t want = v->nwords;
        bvox_volume_destroy(v);
        return bvox__fail(BVOX_EINVAL, "words: %zu words given, %d x %d x %d voxels take %zu",
                          word_count, dims.nx, dims.ny, dims.nz, want);
    }
    /* The tail invariant is checked, not repaired: set bits beyond nz mean
     * the words were laid out for other dimensions. */
    for (size_t c = 0; c < (size_t)v->nx * (size_t)v->ny; c++)
        if (words[c * v->wpc + v->wpc - 1] & ~v->tail_mask) {
            bvox_volume_destroy(v);
            return bvox__fail(BVOX_EINVAL, "words: column (%zu, %zu) has bits set beyond z = %d",
                              c % (size_t)dims.nx, c / (size_t)dims.nx, dims.nz);
        }
    memcpy(v->words, words, v->nwords * sizeof *words);
    *out = v;
    return BVOX_OK;
}
