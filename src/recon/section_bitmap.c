/*
 * section_bitmap.c — binary section images, 64 pixels per word along a row:
 * create/copy/access, square dilation and erosion (shifts of whole words
 * along rows, ORs of whole rows down the columns), the median (majority)
 * filter through running column sums, and connected components as runs of
 * set bits joined by a union-find, which also removes specks and fills
 * small holes.
 */
#include "section_internal.h"

#include <stdlib.h>
#include <string.h>

static size_t bitmap_bytes(const bvox_bitmap *bm)
{
    return (size_t)bm->words_per_row * (size_t)bm->height * sizeof(uint64_t);
}

bvox_status bvox_bitmap_create(int32_t width, int32_t height, bvox_bitmap **out)
{
    *out = NULL;
    if (width < 1 || height < 1 || width > BVOX_IMAGE_MAX_DIM || height > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "bitmap size %d x %d is outside 1..%d", (int)width,
                          (int)height, BVOX_IMAGE_MAX_DIM);
    bvox_bitmap *bm = bvox__mem_zalloc(1, sizeof *bm);
    if (!bm) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bm->width = width;
    bm->height = height;
    bm->words_per_row = (width + 63) / 64;
    size_t bytes;
    if (!bvox__mul_size((size_t)bm->words_per_row * (size_t)height, sizeof(uint64_t), &bytes)) {
        free(bm);
        return bvox__fail(BVOX_ETOOBIG, "bitmap %d x %d overflows", (int)width, (int)height);
    }
    bvox_status st;
    bm->words = bvox__alloc(bytes, true, "bitmap", &st);
    if (!bm->words) {
        free(bm);
        return st;
    }
    *out = bm;
    return BVOX_OK;
}

void bvox_bitmap_destroy(bvox_bitmap *bm)
{
    if (!bm) return;
    bvox__free(bm->words, bitmap_bytes(bm));
    free(bm);
}

bvox_status bvox_bitmap_copy(const bvox_bitmap *bm, bvox_bitmap **out)
{
    bvox_status st = bvox_bitmap_create(bm->width, bm->height, out);
    if (st) return st;
    memcpy((*out)->words, bm->words, bitmap_bytes(bm));
    return BVOX_OK;
}

int bvox_bitmap_get(const bvox_bitmap *bm, int32_t x, int32_t y)
{
    if (x < 0 || y < 0 || x >= bm->width || y >= bm->height) return 0;
    return (int)((bvox__bm_row_c(bm, y)[x >> 6] >> (x & 63)) & 1);
}

void bvox_bitmap_set(bvox_bitmap *bm, int32_t x, int32_t y, int value)
{
    if (x < 0 || y < 0 || x >= bm->width || y >= bm->height) return;
    uint64_t *w = &bvox__bm_row(bm, y)[x >> 6], bit = 1ull << (x & 63);
    *w = value ? (*w | bit) : (*w & ~bit);
}

int64_t bvox_bitmap_count(const bvox_bitmap *bm)
{
    size_t n = (size_t)bm->words_per_row * (size_t)bm->height;
    return (int64_t)bvox__simd()->popcount(bm->words, n);
}

bvox_status bvox_bitmap_to_image(const bvox_bitmap *bm, bvox_image **out)
{
    bvox_status st = bvox_image_create(bm->width, bm->height, 1, 8, out);
    if (st) return st;
    for (int32_t y = 0; y < bm->height; y++) {
        const uint64_t *row = bvox__bm_row_c(bm, y);
        uint8_t *dst = (*out)->pixels + (size_t)y * (size_t)bm->width;
        for (int32_t x = 0; x < bm->width; x++) dst[x] = ((row[x >> 6] >> (x & 63)) & 1) ? 255 : 0;
    }
    return BVOX_OK;
}

void bvox__bm_fill_run(uint64_t *row, int32_t x0, int32_t x1, int value)
{
    while (x0 < x1) {
        int32_t k = x0 >> 6, end = (k + 1) * 64 < x1 ? (k + 1) * 64 : x1;
        uint64_t m = bvox__bit_range((unsigned)(x0 & 63), (unsigned)(end - k * 64));
        row[k] = value ? (row[k] | m) : (row[k] & ~m);
        x0 = end;
    }
}

/* ------------------------------------------------------------ morphology */

/* dst = src | src shifted by s (0 < s < 64) towards higher x | towards lower x. */
static void row_spread(uint64_t *dst, const uint64_t *src, int32_t nw, unsigned s, uint64_t tail)
{
    for (int32_t k = 0; k < nw; k++) {
        uint64_t w = src[k];
        uint64_t up = (w << s) | (k > 0 ? src[k - 1] >> (64 - s) : 0);
        uint64_t down = (w >> s) | (k + 1 < nw ? src[k + 1] << (64 - s) : 0);
        dst[k] = w | up | down;
    }
    dst[nw - 1] &= tail;
}

/* Dilation by the (2r+1)^2 square, outside = background. */
static bvox_status dilate_square(const bvox_bitmap *in, int32_t r, bvox_bitmap **out)
{
    bvox_bitmap *h = NULL, *o = NULL;
    bvox_status st = bvox_bitmap_copy(in, &h);
    if (!st) st = bvox_bitmap_create(in->width, in->height, &o);
    if (st) {
        bvox_bitmap_destroy(h);
        return st;
    }
    int32_t nw = in->words_per_row;
    uint64_t tail = bvox__bm_tail(in);
    uint64_t *tmp = bvox__mem_alloc((size_t)nw * sizeof *tmp);
    if (!tmp) {
        bvox_bitmap_destroy(h);
        bvox_bitmap_destroy(o);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    /* rows: reach grows covered -> covered + s by doubling */
    for (int32_t y = 0; y < in->height; y++) {
        uint64_t *row = bvox__bm_row(h, y);
        int32_t covered = 0;
        while (covered < r) {
            int32_t s = covered + 1 < r - covered ? covered + 1 : r - covered;
            if (s > 63) s = 63;
            row_spread(tmp, row, nw, (unsigned)s, tail);
            memcpy(row, tmp, (size_t)nw * sizeof *tmp);
            covered += s;
        }
    }
    free(tmp);
    /* columns: OR of rows y - r .. y + r */
    for (int32_t y = 0; y < in->height; y++) {
        uint64_t *dst = bvox__bm_row(o, y);
        int32_t y0 = y - r < 0 ? 0 : y - r, y1 = y + r >= in->height ? in->height - 1 : y + r;
        for (int32_t yy = y0; yy <= y1; yy++) {
            const uint64_t *src = bvox__bm_row_c(h, yy);
            for (int32_t k = 0; k < nw; k++) dst[k] |= src[k];
        }
    }
    bvox_bitmap_destroy(h);
    *out = o;
    return BVOX_OK;
}

static void complement(bvox_bitmap *bm)
{
    uint64_t tail = bvox__bm_tail(bm);
    for (int32_t y = 0; y < bm->height; y++) {
        uint64_t *row = bvox__bm_row(bm, y);
        for (int32_t k = 0; k < bm->words_per_row; k++) row[k] = ~row[k];
        row[bm->words_per_row - 1] &= tail;
    }
}

bvox_status bvox_bitmap_dilate(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out)
{
    *out = NULL;
    if (radius < 0 || radius > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "dilation radius %d is negative or too large", (int)radius);
    return dilate_square(in, radius, out);
}

bvox_status bvox_bitmap_erode(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out)
{
    *out = NULL;
    if (radius < 0 || radius > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "erosion radius %d is negative or too large", (int)radius);
    bvox_bitmap *c = NULL;
    bvox_status st = bvox_bitmap_copy(in, &c);
    if (st) return st;
    complement(c);
    st = dilate_square(c, radius, out);
    bvox_bitmap_destroy(c);
    if (!st) complement(*out);
    return st;
}

bvox_status bvox_bitmap_open(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out)
{
    bvox_bitmap *t = NULL;
    bvox_status st = bvox_bitmap_erode(in, radius, &t);
    if (st) {
        *out = NULL;
        return st;
    }
    st = bvox_bitmap_dilate(t, radius, out);
    bvox_bitmap_destroy(t);
    return st;
}

bvox_status bvox_bitmap_close(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out)
{
    bvox_bitmap *t = NULL;
    bvox_status st = bvox_bitmap_dilate(in, radius, &t);
    if (st) {
        *out = NULL;
        return st;
    }
    st = bvox_bitmap_erode(t, radius, out);
    bvox_bitmap_destroy(t);
    return st;
}

/* ---------------------------------------------------------------- median */

/* colsum[x] += sign for every set pixel of row (set bits found a word at a time). */
static void add_row(int32_t *colsum, const uint64_t *row, int32_t nw, int sign)
{
    for (int32_t k = 0; k < nw; k++) {
        uint64_t w = row[k];
        while (w) {
            int b = __builtin_ctzll(w);
            colsum[k * 64 + b] += sign;
            w &= w - 1;
        }
    }
}

bvox_status bvox_bitmap_median(const bvox_bitmap *in, int32_t radius, bvox_bitmap **out)
{
    *out = NULL;
    if (radius < 0 || radius > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "median radius %d is negative or too large", (int)radius);
    if (radius == 0) return bvox_bitmap_copy(in, out);
    bvox_bitmap *o = NULL;
    bvox_status st = bvox_bitmap_create(in->width, in->height, &o);
    if (st) return st;
    int32_t w = in->width, h = in->height, r = radius, nw = in->words_per_row;
    int32_t *colsum = bvox__mem_zalloc((size_t)nw * 64, sizeof *colsum);
    int32_t *prefix = bvox__mem_alloc(((size_t)w + 1) * sizeof *prefix);
    if (!colsum || !prefix) {
        free(colsum);
        free(prefix);
        bvox_bitmap_destroy(o);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    /* window rows y - r .. y + r, clipped */
    for (int32_t y = 0; y < r && y < h; y++) add_row(colsum, bvox__bm_row_c(in, y), nw, 1);
    for (int32_t y = 0; y < h; y++) {
        if (y + r < h) add_row(colsum, bvox__bm_row_c(in, y + r), nw, 1);
        if (y - r - 1 >= 0) add_row(colsum, bvox__bm_row_c(in, y - r - 1), nw, -1);
        int32_t rows = (y + r < h ? y + r : h - 1) - (y - r > 0 ? y - r : 0) + 1;
        prefix[0] = 0;
        for (int32_t x = 0; x < w; x++) prefix[x + 1] = prefix[x] + colsum[x];
        uint64_t *dst = bvox__bm_row(o, y);
        for (int32_t x = 0; x < w; x++) {
            int32_t x0 = x - r < 0 ? 0 : x - r, x1 = x + r >= w ? w - 1 : x + r;
            int64_t cnt = prefix[x1 + 1] - prefix[x0];
            int64_t valid = (int64_t)(x1 - x0 + 1) * rows;
            if (2 * cnt > valid) dst[x >> 6] |= 1ull << (x & 63);
        }
    }
    free(colsum);
    free(prefix);
    *out = o;
    return BVOX_OK;
}

/* ------------------------------------------------------------ components */

static int32_t uf_find(int32_t *parent, int32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(int32_t *parent, int32_t a, int32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a == b) return;
    if (a < b) parent[b] = a;
    else parent[a] = b;
}

void bvox__runs_free(bvox__runs *r)
{
    free(r->runs);
    free(r->area);
    free(r->edge);
    memset(r, 0, sizeof *r);
}

bvox_status bvox__runs_label(const bvox_bitmap *bm, int conn, int invert, bvox__runs *out)
{
    memset(out, 0, sizeof *out);
    if (conn != 4 && conn != 8)
        return bvox__fail(BVOX_EINVAL, "connectivity must be 4 or 8, not %d", conn);
    int32_t nw = bm->words_per_row;
    uint64_t tail = bvox__bm_tail(bm);
    int64_t cap = 1024, n = 0;
    bvox__run *runs = bvox__mem_alloc((size_t)cap * sizeof *runs);
    int64_t *row_start = bvox__mem_alloc(((size_t)bm->height + 1) * sizeof *row_start);
    if (!runs || !row_start) goto nomem;
    /* runs, a word at a time: a run starts at a 0->1 step and ends at 1->0 */
    for (int32_t y = 0; y < bm->height; y++) {
        row_start[y] = n;
        const uint64_t *row = bvox__bm_row_c(bm, y);
        int32_t x0 = -1;
        for (int32_t k = 0; k < nw; k++) {
            uint64_t w = invert ? ~row[k] : row[k];
            if (k == nw - 1) w &= tail;
            uint64_t prev_bit = (x0 >= 0) ? 1 : 0; /* inside a run at the word boundary */
            uint64_t starts = w & ~((w << 1) | prev_bit);
            uint64_t ends = ~w & ((w << 1) | prev_bit); /* first 0 after a 1 */
            uint64_t events = starts | ends;
            while (events) {
                int b = __builtin_ctzll(events);
                events &= events - 1;
                int32_t x = k * 64 + b;
                if (x0 < 0) {
                    x0 = x;
                } else {
                    if (n == cap) {
                        cap *= 2;
                        bvox__run *nr = bvox__mem_resize(runs, (size_t)cap * sizeof *runs);
                        if (!nr) goto nomem;
                        runs = nr;
                    }
                    runs[n++] = (bvox__run){y, x0, x, 0};
                    x0 = -1;
                }
            }
        }
        if (x0 >= 0) {
            if (n == cap) {
                cap *= 2;
                bvox__run *nr = bvox__mem_resize(runs, (size_t)cap * sizeof *runs);
                if (!nr) goto nomem;
                runs = nr;
            }
            runs[n++] = (bvox__run){y, x0, bm->width, 0};
        }
    }
    row_start[bm->height] = n;
    if (n > INT32_MAX) {
        free(runs);
        free(row_start);
        return bvox__fail(BVOX_ETOOBIG, "too many runs in a bitmap");
    }
    int32_t *parent = bvox__mem_alloc((size_t)(n ? n : 1) * sizeof *parent);
    if (!parent) goto nomem;
    for (int64_t i = 0; i < n; i++) parent[i] = (int32_t)i;
    int32_t d = conn == 8 ? 1 : 0;
    for (int32_t y = 1; y < bm->height; y++) {
        int64_t a = row_start[y - 1], ae = row_start[y];
        for (int64_t i = row_start[y]; i < row_start[y + 1]; i++) {
            /* runs of the row above overlapping [x0 - d, x1 + d) */
            while (a < ae && runs[a].x1 + d <= runs[i].x0) a++;
            for (int64_t j = a; j < ae && runs[j].x0 < runs[i].x1 + d; j++)
                uf_union(parent, (int32_t)i, (int32_t)j);
        }
    }
    free(row_start);
    row_start = NULL;
    int32_t ncomp = 0;
    int32_t *compof = bvox__mem_alloc((size_t)(n ? n : 1) * sizeof *compof);
    if (!compof) {
        free(parent);
        goto nomem;
    }
    for (int64_t i = 0; i < n; i++) {
        int32_t root = uf_find(parent, (int32_t)i);
        if (root == i) compof[i] = ncomp++;
        runs[i].comp = compof[root]; /* the root is the component's first run (smallest index) */
    }
    free(compof);
    free(parent);
    out->area = bvox__mem_zalloc((size_t)(ncomp ? ncomp : 1), sizeof *out->area);
    out->edge = bvox__mem_zalloc((size_t)(ncomp ? ncomp : 1), 1);
    if (!out->area || !out->edge) {
        free(out->area);
        free(out->edge);
        out->area = NULL;
        out->edge = NULL;
        goto nomem;
    }
    for (int64_t i = 0; i < n; i++) {
        bvox__run *r = &runs[i];
        out->area[r->comp] += r->x1 - r->x0;
        if (r->y == 0 || r->y == bm->height - 1 || r->x0 == 0 || r->x1 == bm->width)
            out->edge[r->comp] = 1;
    }
    out->runs = runs;
    out->nruns = n;
    out->ncomp = ncomp;
    return BVOX_OK;
nomem:
    free(runs);
    free(row_start);
    return bvox__fail(BVOX_ENOMEM, "out of memory");
}

bvox_status bvox_bitmap_label(const bvox_bitmap *bm, int conn, int32_t **labels, int32_t *count)
{
    *labels = NULL;
    *count = 0;
    bvox__runs r;
    bvox_status st = bvox__runs_label(bm, conn, 0, &r);
    if (st) return st;
    int32_t *lab = bvox__mem_zalloc((size_t)bm->width * (size_t)bm->height, sizeof *lab);
    if (!lab) {
        bvox__runs_free(&r);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    for (int64_t i = 0; i < r.nruns; i++) {
        int32_t *row = lab + (size_t)r.runs[i].y * (size_t)bm->width;
        for (int32_t x = r.runs[i].x0; x < r.runs[i].x1; x++) row[x] = r.runs[i].comp + 1;
    }
    *labels = lab;
    *count = r.ncomp;
    bvox__runs_free(&r);
    return BVOX_OK;
}

bvox_status bvox_bitmap_remove_specks(bvox_bitmap *bm, int64_t min_area, int fill_holes)
{
    if (min_area <= 1) return BVOX_OK;
    bvox__runs r;
    bvox_status st = bvox__runs_label(bm, 8, 0, &r);
    if (st) return st;
    for (int64_t i = 0; i < r.nruns; i++)
        if (r.area[r.runs[i].comp] < min_area)
            bvox__bm_fill_run(bvox__bm_row(bm, r.runs[i].y), r.runs[i].x0, r.runs[i].x1, 0);
    bvox__runs_free(&r);
    if (!fill_holes) return BVOX_OK;
    st = bvox__runs_label(bm, 4, 1, &r);
    if (st) return st;
    for (int64_t i = 0; i < r.nruns; i++) {
        int32_t c = r.runs[i].comp;
        if (r.area[c] < min_area && !r.edge[c])
            bvox__bm_fill_run(bvox__bm_row(bm, r.runs[i].y), r.runs[i].x0, r.runs[i].x1, 1);
    }
    bvox__runs_free(&r);
    return BVOX_OK;
}
