/*
 * volume.c — create, destroy, copy, geometry and single-voxel access of a
 * bvox_volume. The data layout (64 voxels per word along z, zero tail bits) is
 * documented in internal.h; every function here keeps the tail bits zero.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bvox_geometry bvox_geometry_default(void)
{
    bvox_geometry g;
    memset(&g, 0, sizeof g);
    g.spacing[0] = g.spacing[1] = g.spacing[2] = 1.0;
    g.direction[0] = g.direction[4] = g.direction[8] = 1.0;
    return g;
}

bvox_status bvox__check_dims(bvox_dims d, const char *what, size_t *bytes)
{
    const char *src = what ? what : "volume";
    if (d.nx < 1 || d.ny < 1 || d.nz < 1 || d.nx > BVOX_MAX_DIM || d.ny > BVOX_MAX_DIM ||
        d.nz > BVOX_MAX_DIM)
        return bvox__fail(BVOX_EINVAL,
                          "%s: dimensions %ld x %ld x %ld are outside 1..%d per axis", src,
                          (long)d.nx, (long)d.ny, (long)d.nz, BVOX_MAX_DIM);
    size_t wpc = ((size_t)d.nz + 63) / 64, n;
    /* With every axis <= 65535 the products below cannot overflow 64 bits,
     * but check anyway so that a future larger limit stays safe. */
    if (!bvox__mul_size((size_t)d.nx, (size_t)d.ny, &n) || !bvox__mul_size(n, wpc, &n) ||
        !bvox__mul_size(n, sizeof(uint64_t), &n))
        return bvox__fail(BVOX_ETOOBIG, "%s: dimensions overflow the address space", src);
    if (n > bvox_memory_budget()) {
        char need[32], lim[32];
        bvox__format_bytes(need, sizeof need, n);
        bvox__format_bytes(lim, sizeof lim, bvox_memory_budget());
        return bvox__fail(BVOX_ETOOBIG,
                          "%s: %ld x %ld x %ld voxels need %s, over the memory budget of %s",
                          src, (long)d.nx, (long)d.ny, (long)d.nz, need, lim);
    }
    *bytes = n;
    return BVOX_OK;
}

static bvox_status create(bvox_dims dims, bool zero, bvox_volume **out)
{
    *out = NULL;
    size_t bytes = 0;
    bvox_status st = bvox__check_dims(dims, NULL, &bytes);
    if (st) return st;
    bvox_volume *v = bvox__mem_zalloc(1, sizeof *v);
    if (!v) return bvox__fail(BVOX_ENOMEM, "out of memory allocating a volume");
    v->nx = dims.nx;
    v->ny = dims.ny;
    v->nz = dims.nz;
    v->wpc = ((size_t)dims.nz + 63) / 64;
    v->nwords = bytes / sizeof(uint64_t);
    unsigned tail = (unsigned)(dims.nz & 63);
    v->tail_mask = tail ? (1ull << tail) - 1 : ~0ull;
    v->geom = bvox_geometry_default();
    v->words = bvox__alloc(bytes, zero, "voxel words", &st);
    if (!v->words) {
        free(v);
        return st;
    }
    *out = v;
    return BVOX_OK;
}

bvox_status bvox_volume_create(bvox_dims dims, bvox_volume **out)
{
    return create(dims, true, out);
}

bvox_status bvox__volume_create_uninit(bvox_dims dims, bvox_volume **out)
{
    return create(dims, false, out);
}

void bvox_volume_destroy(bvox_volume *vol)
{
    if (!vol) return;
    bvox__free(vol->words, vol->nwords * sizeof(uint64_t));
    free(vol);
}

bvox_status bvox_volume_copy(const bvox_volume *vol, bvox_volume **out)
{
    BVOX_CHECK_VOLUME(vol);
    bvox_dims d = {vol->nx, vol->ny, vol->nz};
    bvox_status st = create(d, false, out);
    if (st) return st;
    memcpy((*out)->words, vol->words, vol->nwords * sizeof(uint64_t));
    (*out)->geom = vol->geom;
    BVOX_CHECK_VOLUME(*out);
    return BVOX_OK;
}

bvox_dims bvox_volume_dims(const bvox_volume *vol)
{
    bvox_dims d = {vol->nx, vol->ny, vol->nz};
    return d;
}

const bvox_geometry *bvox_volume_geometry(const bvox_volume *vol) { return &vol->geom; }

bvox_status bvox_volume_set_geometry(bvox_volume *vol, const bvox_geometry *g)
{
    for (int i = 0; i < 3; i++) {
        if (!isfinite(g->spacing[i]) || g->spacing[i] <= 0)
            return bvox__fail(BVOX_EINVAL, "voxel size %g is not a positive finite number",
                              g->spacing[i]);
        if (!isfinite(g->origin[i]))
            return bvox__fail(BVOX_EINVAL, "origin is not finite");
    }
    for (int i = 0; i < 9; i++)
        if (!isfinite(g->direction[i]))
            return bvox__fail(BVOX_EINVAL, "direction matrix is not finite");
    if (!memchr(g->unit, '\0', sizeof g->unit))
        return bvox__fail(BVOX_EINVAL, "unit name is longer than %zu characters",
                          sizeof g->unit - 1);
    vol->geom = *g;
    return BVOX_OK;
}

bvox_status bvox_volume_set_spacing(bvox_volume *vol, double sx, double sy, double sz,
                                    const char *unit)
{
    bvox_geometry g = vol->geom;
    g.spacing[0] = sx;
    g.spacing[1] = sy;
    g.spacing[2] = sz;
    if (unit) {
        if (strlen(unit) >= sizeof g.unit)
            return bvox__fail(BVOX_EINVAL, "unit name '%s' is too long", unit);
        strcpy(g.unit, unit);
    }
    return bvox_volume_set_geometry(vol, &g);
}

static bool inside(const bvox_volume *v, int32_t x, int32_t y, int32_t z)
{
    return x >= 0 && y >= 0 && z >= 0 && x < v->nx && y < v->ny && z < v->nz;
}

int bvox_volume_get(const bvox_volume *vol, int32_t x, int32_t y, int32_t z)
{
    if (!inside(vol, x, y, z)) return 0;
    return (int)((bvox__column_c(vol, x, y)[z >> 6] >> (z & 63)) & 1u);
}

bvox_status bvox_volume_set(bvox_volume *vol, int32_t x, int32_t y, int32_t z, int value)
{
    if (!inside(vol, x, y, z))
        return bvox__fail(BVOX_EINVAL, "voxel (%ld, %ld, %ld) is outside %ld x %ld x %ld",
                          (long)x, (long)y, (long)z, (long)vol->nx, (long)vol->ny,
                          (long)vol->nz);
    uint64_t *w = &bvox__column(vol, x, y)[z >> 6];
    uint64_t bit = 1ull << (z & 63);
    *w = value ? (*w | bit) : (*w & ~bit);
    return BVOX_OK;
}

bvox_words_view bvox_volume_words(const bvox_volume *vol)
{
    bvox_words_view view = {vol->words, vol->wpc, vol->nwords};
    return view;
}

bvox_status bvox_volume_check(const bvox_volume *vol)
{
    if (!vol) return bvox__fail(BVOX_EINVAL, "no volume");
    if (vol->nx < 1 || vol->ny < 1 || vol->nz < 1 || vol->nx > BVOX_MAX_DIM ||
        vol->ny > BVOX_MAX_DIM || vol->nz > BVOX_MAX_DIM)
        return bvox__fail(BVOX_EFORMAT, "dimensions out of range");
    if (vol->wpc != ((size_t)vol->nz + 63) / 64 ||
        vol->nwords != (size_t)vol->nx * (size_t)vol->ny * vol->wpc)
        return bvox__fail(BVOX_EFORMAT, "word counts inconsistent with dimensions");
    if ((vol->nz & 63) == 0) return BVOX_OK;
    uint64_t bad = ~vol->tail_mask;
    size_t ncol = (size_t)vol->nx * (size_t)vol->ny;
    for (size_t c = 0; c < ncol; c++) {
        if (vol->words[c * vol->wpc + vol->wpc - 1] & bad)
            return bvox__fail(BVOX_EFORMAT,
                              "tail bits beyond nz=%ld set in column x=%zu y=%zu",
                              (long)vol->nz, c % (size_t)vol->nx, c / (size_t)vol->nx);
    }
    return BVOX_OK;
}
