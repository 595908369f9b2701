/*
 * markers_detect.c — reference markers in a section image: small dark round
 * blobs. The marker-dark pixels (at or below a threshold) are split into
 * 8-connected components (runs + union-find, section_bitmap.c); those of a
 * marker's size that are round (area against the disc through the farthest
 * pixel) and do not touch the edge are candidates, ranked by roundness and
 * by how close their area is to the candidates' median area.
 */
#include "section_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bvox_marker_opts bvox_marker_opts_default(void)
{
    bvox_marker_opts o;
    memset(&o, 0, sizeof o);
    o.count = 3;
    o.threshold = -1;
    return o;
}

typedef struct cand {
    int32_t comp;
    double cx, cy, area, round, score, mean;
} cand;

static int by_score(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    if (x->score != y->score) return x->score < y->score ? 1 : -1;
    return x->comp - y->comp;
}

static int by_area(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    return (x->area > y->area) - (x->area < y->area);
}

/* Automatic marker threshold: halfway between the median and the 0.05 %
 * darkest level. */
static bvox_status auto_threshold(const bvox_image *img, double *t, double *median)
{
    size_t nb = img->bits == 8 ? 256 : 65536, n = (size_t)img->width * (size_t)img->height;
    uint32_t *hist = bvox__mem_zalloc(nb, sizeof *hist);
    if (!hist) return bvox__fail(BVOX_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++) hist[bvox__gray_at(img, i)]++;
    size_t acc = 0, low = 0, med = 0, want_low = n / 2000, want_med = n / 2;
    int got_low = 0;
    for (size_t v = 0; v < nb; v++) {
        acc += hist[v];
        if (!got_low && acc > want_low) {
            low = v;
            got_low = 1;
        }
        if (acc > want_med) {
            med = v;
            break;
        }
    }
    free(hist);
    *t = floor(((double)low + (double)med) / 2);
    *median = (double)med;
    return BVOX_OK;
}

bvox_status bvox_section_find_markers(const bvox_image *img, const bvox_marker_opts *opts,
                                      bvox_point2 *markers, int32_t *found, bvox_bitmap *erase)
{
    *found = 0;
    if (!opts || opts->count < 1 || opts->count > 1000)
        return bvox__fail(BVOX_EINVAL, "the expected marker count must be 1..1000");
    if (!img || img->channels != 1)
        return bvox__fail(BVOX_EINVAL, "markers are found in gray images");
    if (erase && (erase->width != img->width || erase->height != img->height))
        return bvox__fail(BVOX_EINVAL, "the mask to erase markers from has another size");
    double rmin = opts->min_radius > 0 ? opts->min_radius : 1.5;
    double rmax = opts->max_radius > 0 ? opts->max_radius
                                       : (img->width < img->height ? img->width : img->height) / 16.0;
    if (rmax < rmin) rmax = rmin;
    double t = opts->threshold, median_level = 0;
    bvox_status st = auto_threshold(img, &t, &median_level);
    if (st) return st;
    if (opts->threshold >= 0) t = opts->threshold;
    bvox_bitmap *mask = NULL;
    if ((st = bvox_section_threshold(img, t, 1, &mask))) return st;
    bvox__runs r;
    st = bvox__runs_label(mask, 8, 0, &r);
    bvox_bitmap_destroy(mask);
    if (st) return st;
    double *sx = bvox__mem_zalloc((size_t)r.ncomp + 1, sizeof *sx), *sy = bvox__mem_zalloc((size_t)r.ncomp + 1, sizeof *sy);
    double *far = bvox__mem_zalloc((size_t)r.ncomp + 1, sizeof *far);
    double *gsum = bvox__mem_zalloc((size_t)r.ncomp + 1, sizeof *gsum);
    cand *c = bvox__mem_zalloc((size_t)r.ncomp + 1, sizeof *c);
    if (!sx || !sy || !far || !gsum || !c) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    double amin = M_PI * rmin * rmin, amax = M_PI * rmax * rmax;
    for (int64_t i = 0; i < r.nruns; i++) {
        const bvox__run *u = &r.runs[i];
        double len = u->x1 - u->x0;
        sx[u->comp] += len * (u->x0 + u->x1) / 2.0; /* sum of pixel centres */
        sy[u->comp] += len * (u->y + 0.5);
    }
    for (int32_t k = 0; k < r.ncomp; k++) {
        sx[k] /= (double)r.area[k];
        sy[k] /= (double)r.area[k];
    }
    for (int64_t i = 0; i < r.nruns; i++) {
        const bvox__run *u = &r.runs[i];
        if (r.area[u->comp] < amin * 0.5 || r.area[u->comp] > amax * 1.5) continue;
        double dy = u->y + 0.5 - sy[u->comp];
        double dx0 = u->x0 + 0.5 - sx[u->comp], dx1 = u->x1 - 0.5 - sx[u->comp];
        double d = sqrt(dy * dy + (dx0 * dx0 > dx1 * dx1 ? dx0 * dx0 : dx1 * dx1));
        if (d > far[u->comp]) far[u->comp] = d;
        size_t base = (size_t)u->y * (size_t)img->width;
        for (int32_t x = u->x0; x < u->x1; x++) gsum[u->comp] += bvox__gray_at(img, base + (size_t)x);
    }
    int32_t nc = 0;
    for (int32_t k = 0; k < r.ncomp; k++) {
        double a = (double)r.area[k];
        if (a < amin || a > amax || r.edge[k]) continue;
        double rf = far[k] + 0.5;
        double round = a / (M_PI * rf * rf);
        if (round < 0.5) continue;
        c[nc++] = (cand){k, sx[k], sy[k], a, round, 0, gsum[k] / a};
    }
    /* markers are the darkest blobs: drop candidates much brighter than the
     * darkest one (a dark object's small round tip, when the markers are
     * darker than the object) */
    if (nc > 0) {
        double darkest = c[0].mean;
        for (int32_t i = 1; i < nc; i++) darkest = fmin(darkest, c[i].mean);
        double limit = darkest + 0.25 * (median_level - darkest);
        int32_t m = 0;
        for (int32_t i = 0; i < nc; i++)
            if (c[i].mean <= limit) c[m++] = c[i];
        nc = m;
    }
    if (nc > 0) {
        qsort(c, (size_t)nc, sizeof *c, by_area);
        double med = c[nc / 2].area;
        for (int32_t i = 0; i < nc; i++) c[i].score = c[i].round - fabs(c[i].area - med) / med;
        qsort(c, (size_t)nc, sizeof *c, by_score);
    }
    int32_t keep = nc < opts->count + 1 ? nc : opts->count + 1;
    for (int32_t i = 0; i < keep; i++) markers[i] = (bvox_point2){c[i].cx, c[i].cy};
    *found = keep;
    if (erase && keep > 0) {
        uint8_t *kept = bvox__mem_zalloc((size_t)r.ncomp + 1, 1);
        if (!kept) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            *found = 0;
            goto done;
        }
        for (int32_t i = 0; i < keep; i++) kept[c[i].comp] = 1;
        for (int64_t i = 0; i < r.nruns; i++) {
            const bvox__run *u = &r.runs[i];
            if (!kept[u->comp]) continue;
            int32_t x0 = u->x0 - 2 < 0 ? 0 : u->x0 - 2;
            int32_t x1 = u->x1 + 2 > erase->width ? erase->width : u->x1 + 2;
            for (int32_t y = u->y - 2; y <= u->y + 2; y++)
                if (y >= 0 && y < erase->height) bvox__bm_fill_run(bvox__bm_row(erase, y), x0, x1, 0);
        }
        free(kept);
    }
done:
    free(sx);
    free(sy);
    free(far);
    free(gsum);
    free(c);
    bvox__runs_free(&r);
    return st;
}
