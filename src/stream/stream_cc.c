/*
 * stream_cc.c — connected components of a volume seen one slab at a time.
 *
 * Each slab (ending with the first slice of the next, so that consecutive
 * slabs share one slice) is labelled by bvox_components_find, its components
 * numbered after those of the slabs before. A voxel of the shared slice
 * belongs to one component of each of the two slabs: those two are one
 * component of the volume (union-find), and the voxel, counted by both, is
 * taken off once. Because the shared slice is labelled in both slabs with all
 * its neighbours on one side, the connectivity needs no special case at the
 * seam. Only the labels of the shared slice are kept between slabs.
 *
 * Components are numbered in slab order, and within a slab largest first;
 * the final order is bvox_components_find's: voxels descending, ties by the
 * first voxel in column order (y * nx + x, then z), kept per component as the
 * smallest key of its pieces.
 */
#include "stream/stream.h"

#include <stdlib.h>
#include <string.h>

typedef struct piece {
    int64_t parent;
    int64_t voxels;  /* counted in its slab, less the shared voxels it gave */
    int64_t key;     /* first voxel: column * nz + z */
    bvox_box bbox;   /* in volume coordinates */
    bool border;     /* touches the volume's border (exclude_border) */
} piece;

struct bvox__stream_cc {
    bvox_dims dims;
    int conn;
    bool background, exclude_border, want_items;
    piece *p;
    int64_t n, cap;
    int64_t *face;     /* labels (piece ids, -1 none) of the last slab's last slice */
    size_t face_bytes;
    bool have_face;
    int32_t next_z;    /* z of the last slab's last slice (the next slab's first) */
};

static int64_t find(piece *p, int64_t i)
{
    while (p[i].parent != i) {
        p[i].parent = p[p[i].parent].parent; /* path halving */
        i = p[i].parent;
    }
    return i;
}

static void unite(piece *p, int64_t a, int64_t b)
{
    a = find(p, a), b = find(p, b);
    if (a == b) return;
    if (b < a) { int64_t t = a; a = b; b = t; }
    p[b].parent = a; /* the older piece stays root: roots come out in slab order */
}

bvox_status bvox__stream_cc_begin(bvox_dims dims, int conn, bool background, bool exclude_border,
                                  bool want_items, bvox__stream_cc **out)
{
    *out = NULL;
    bvox__stream_cc *cc = bvox__mem_zalloc(1, sizeof *cc);
    if (!cc) return bvox__fail(BVOX_ENOMEM, "out of memory");
    cc->dims = dims;
    cc->conn = conn;
    cc->background = background;
    cc->exclude_border = exclude_border;
    cc->want_items = want_items;
    cc->face_bytes = (size_t)dims.nx * (size_t)dims.ny * sizeof(int64_t);
    bvox_status st;
    cc->face = bvox__alloc(cc->face_bytes, false, "component labels of a shared slice", &st);
    if (!cc->face) {
        free(cc);
        return st;
    }
    *out = cc;
    return BVOX_OK;
}

void bvox__stream_cc_abort(bvox__stream_cc *cc)
{
    if (!cc) return;
    bvox__free(cc->face, cc->face_bytes);
    free(cc->p);
    free(cc);
}

static bvox_status grow(bvox__stream_cc *cc, int64_t more)
{
    if (cc->n + more <= cc->cap) return BVOX_OK;
    int64_t cap = cc->cap ? cc->cap : 1024;
    while (cap < cc->n + more) cap *= 2;
    piece *p = bvox__mem_resize(cc->p, (size_t)cap * sizeof *p);
    if (!p) return bvox__fail(BVOX_ENOMEM, "out of memory (%lld components)", (long long)cap);
    cc->p = p;
    cc->cap = cap;
    return BVOX_OK;
}

/* col_of[i] (y * nx + x) and z_of[i] of the first voxel of component i of
 * c (the labelling of v) in column order: the first run start of each
 * column, walked in order, named through the public index_at (so this does
 * not depend on how the labeller stores its runs). */
static void first_voxels(const bvox_volume *v, const bvox_components *c, int64_t *col_of,
                         int32_t *z_of)
{
    int64_t k = bvox_components_count(c), left = k;
    for (int64_t i = 0; i < k; i++) col_of[i] = -1;
    bvox_words_view wv = bvox_volume_words(v);
    const size_t ncol = (size_t)v->nx * (size_t)v->ny;
    for (size_t col = 0; col < ncol && left; col++) {
        const uint64_t *w = wv.words + col * wv.words_per_column;
        uint64_t carry = 0;
        for (size_t j = 0; j < wv.words_per_column; j++) {
            uint64_t starts = w[j] & ~((w[j] << 1) | carry);
            carry = w[j] >> 63;
            for (; starts; starts &= starts - 1) {
                int32_t z = (int32_t)(j * 64 + (size_t)__builtin_ctzll(starts));
                int64_t i = bvox_components_index_at(c, (int32_t)(col % (size_t)v->nx),
                                                     (int32_t)(col / (size_t)v->nx), z);
                if (i >= 0 && col_of[i] < 0) {
                    col_of[i] = (int64_t)col;
                    z_of[i] = z;
                    left--;
                }
            }
        }
    }
}

/* One slab's components: pieces base .. base + k - 1. */
static bvox_status add_pieces(bvox__stream_cc *cc, const bvox_volume *v,
                              const bvox_components *c, int32_t z0, int32_t depth)
{
    int64_t k = bvox_components_count(c), base = cc->n;
    bvox_status st = grow(cc, k);
    if (st) return st;
    int64_t *col = NULL;
    int32_t *zf = NULL;
    if (cc->want_items && k) {
        col = bvox__mem_alloc((size_t)k * sizeof *col);
        zf = bvox__mem_alloc((size_t)k * sizeof *zf);
        if (!col || !zf) st = bvox__fail(BVOX_ENOMEM, "out of memory");
        else first_voxels(v, c, col, zf);
    }
    bool last = z0 + depth == cc->dims.nz;
    for (int64_t i = 0; !st && i < k; i++) {
        const bvox_component *it = bvox_components_get(c, i);
        piece *p = &cc->p[base + i];
        p->parent = base + i;
        p->voxels = it->voxels;
        p->bbox = it->bbox;
        p->bbox.z0 += z0, p->bbox.z1 += z0;
        p->key = col ? col[i] * (int64_t)cc->dims.nz + z0 + zf[i] : 0;
        p->border = it->bbox.x0 == 0 || it->bbox.y0 == 0 || it->bbox.x1 == cc->dims.nx ||
                    it->bbox.y1 == cc->dims.ny || (z0 == 0 && it->bbox.z0 == 0) ||
                    (last && it->bbox.z1 == depth);
    }
    free(col);
    free(zf);
    if (!st) cc->n = base + k;
    return st;
}

bvox_status bvox__stream_cc_add(bvox__stream_cc *cc, const bvox_volume *slab, int32_t z0)
{
    bvox_status st;
    bvox_volume *bg = NULL;
    if (cc->background) {
        if ((st = bvox_volume_copy(slab, &bg))) return st;
        bvox_volume_complement(bg);
        slab = bg;
    }
    bvox_components *c = NULL;
    st = bvox_components_find(slab, cc->conn, &c);
    int64_t base = cc->n;
    if (!st) st = add_pieces(cc, slab, c, z0, slab->nz);
    const int32_t nx = slab->nx, ny = slab->ny;
    if (!st && cc->have_face) {
        if (cc->next_z != z0) {
            st = bvox__fail(BVOX_EINVAL, "stream: slab at z %d does not start on the shared "
                            "slice %d", (int)z0, (int)cc->next_z);
        } else {
            /* the shared slice: slice 0 here, the last slice of the slab before */
            for (int32_t y = 0; y < ny; y++)
                for (int32_t x = 0; x < nx; x++) {
                    int64_t prev = cc->face[(size_t)y * (size_t)nx + (size_t)x];
                    if (prev < 0) continue;
                    int64_t here = bvox_components_index_at(c, x, y, 0);
                    unite(cc->p, prev, base + here);
                    cc->p[base + here].voxels--;
                }
        }
    }
    cc->have_face = false;
    if (!st && z0 + slab->nz < cc->dims.nz) {
        int32_t zl = slab->nz - 1;
        for (int32_t y = 0; y < ny; y++)
            for (int32_t x = 0; x < nx; x++) {
                int64_t i = bvox_components_index_at(c, x, y, zl);
                cc->face[(size_t)y * (size_t)nx + (size_t)x] = i < 0 ? -1 : base + i;
            }
        cc->have_face = true;
        cc->next_z = z0 + zl;
    }
    bvox_components_destroy(c);
    bvox_volume_destroy(bg);
    return st;
}

static int by_size_then_key(const void *a, const void *b)
{
    const piece *p = a, *q = b;
    if (p->voxels != q->voxels) return p->voxels > q->voxels ? -1 : 1;
    return (p->key > q->key) - (p->key < q->key);
}

bvox_status bvox__stream_cc_finish(bvox__stream_cc *cc, const double spacing[3], int64_t *count,
                                   bvox_component **items)
{
    if (items) *items = NULL;
    piece *p = cc->p;
    /* fold every piece into its root */
    for (int64_t i = 0; i < cc->n; i++) {
        int64_t r = find(p, i);
        if (r == i) continue;
        piece *R = &p[r];
        R->voxels += p[i].voxels;
        R->border |= p[i].border;
        if (p[i].key < R->key) R->key = p[i].key;
        if (p[i].bbox.x0 < R->bbox.x0) R->bbox.x0 = p[i].bbox.x0;
        if (p[i].bbox.y0 < R->bbox.y0) R->bbox.y0 = p[i].bbox.y0;
        if (p[i].bbox.z0 < R->bbox.z0) R->bbox.z0 = p[i].bbox.z0;
        if (p[i].bbox.x1 > R->bbox.x1) R->bbox.x1 = p[i].bbox.x1;
        if (p[i].bbox.y1 > R->bbox.y1) R->bbox.y1 = p[i].bbox.y1;
        if (p[i].bbox.z1 > R->bbox.z1) R->bbox.z1 = p[i].bbox.z1;
    }
    /* roots, compacted to the front */
    int64_t m = 0;
    for (int64_t i = 0; i < cc->n; i++)
        if (p[i].parent == i && !(cc->exclude_border && p[i].border)) p[m++] = p[i];
    *count = m;
    bvox_status st = BVOX_OK;
    if (items) {
        qsort(p, (size_t)m, sizeof *p, by_size_then_key);
        bvox_component *out = bvox__mem_alloc((size_t)(m ? m : 1) * sizeof *out);
        if (!out) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
        } else {
            double vv = spacing[0] * spacing[1] * spacing[2];
            for (int64_t i = 0; i < m; i++)
                out[i] = (bvox_component){p[i].voxels, (double)p[i].voxels * vv, p[i].bbox};
            *items = out;
        }
    }
    bvox__stream_cc_abort(cc);
    return st;
}

bvox_status bvox__stream_components(const bvox__slab_source *src, int conn, int64_t *count,
                                    bvox_component **items)
{
    *count = 0;
    if (items) *items = NULL;
    bvox__stream_cc *cc = NULL;
    bvox_status st = bvox__stream_cc_begin(src->dims, conn, false, false, items != NULL, &cc);
    if (st) return st;
    int32_t nz = src->dims.nz, t = bvox__stream_depth(src, 1, src->chunk_z, 4, 0);
    /* slabs [z0, z1) with z1 the next slab's first slice + 1; the last ends at nz */
    for (int32_t z0 = 0, z1 = 0; !st && z1 < nz; z0 = z1 - 1) {
        z1 = z0 + t + 1 < nz ? z0 + t + 1 : nz; /* and the next slab's first slice */
        bvox_volume *slab = NULL;
        st = src->read(src, z0, z1, &slab);
        if (!st) st = bvox__stream_cc_add(cc, slab, z0);
        bvox_volume_destroy(slab);
    }
    if (st) {
        bvox__stream_cc_abort(cc);
        return st;
    }
    return bvox__stream_cc_finish(cc, src->geom.spacing, count, items);
}
