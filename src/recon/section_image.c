/*
 * section_image.c — the gray steps of a section: reading (PNG or TIFF, then
 * gray: section_gray.c), background estimate (a quadratic surface fitted robustly to
 * the background's samples), background subtraction, Otsu's threshold and
 * thresholding with the object's polarity into a bitmap.
 */
#include "section_internal.h"
#include "common/names.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bvox_status check_gray(const bvox_image *img, const char *what)
{
    if (!img || img->channels != 1 || (img->bits != 8 && img->bits != 16))
        return bvox__fail(BVOX_EINVAL, "%s must be an 8- or 16-bit gray image", what);
    return BVOX_OK;
}

bvox_status bvox_section_read(const char *path, bvox_image **out)
{
    *out = NULL;
    if (bvox__ends_with_ci(path, ".tif") || bvox__ends_with_ci(path, ".tiff"))
        return bvox__section_tiff_read(path, out);
    bvox_image *img = NULL;
    bvox_status st = bvox_image_read_png(path, &img);
    if (st) return st;
    if (img->channels == 1) {
        *out = img;
        return BVOX_OK;
    }
    st = bvox_section_gray(img, out);
    bvox_image_destroy(img);
    return st;
}

/* ------------------------------------------------------------ background */

/* Solve the 6x6 system a x = b (partial pivoting); 0 if singular. */
static int solve6(double a[6][6], double b[6], double x[6])
{
    for (int c = 0; c < 6; c++) {
        int p = c;
        for (int r = c + 1; r < 6; r++)
            if (fabs(a[r][c]) > fabs(a[p][c])) p = r;
        if (fabs(a[p][c]) < 1e-12) return 0;
        if (p != c) {
            for (int k = 0; k < 6; k++) {
                double t = a[c][k];
                a[c][k] = a[p][k];
                a[p][k] = t;
            }
            double t = b[c];
            b[c] = b[p];
            b[p] = t;
        }
        for (int r = c + 1; r < 6; r++) {
            double f = a[r][c] / a[c][c];
            for (int k = c; k < 6; k++) a[r][k] -= f * a[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int c = 5; c >= 0; c--) {
        double s = b[c];
        for (int k = c + 1; k < 6; k++) s -= a[c][k] * x[k];
        x[c] = s / a[c][c];
    }
    return 1;
}

/* The k-th smallest of v[0..n) (v is reordered; Wirth's selection). */
static double select_kth(double *v, size_t n, size_t k)
{
    ptrdiff_t l = 0, m = (ptrdiff_t)n - 1, kk = (ptrdiff_t)k;
    while (l < m) {
        double x = v[kk];
        ptrdiff_t i = l, j = m;
        do {
            while (v[i] < x) i++;
            while (x < v[j]) j--;
            if (i <= j) {
                double t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                j--;
            }
        } while (i <= j);
        if (j < kk) l = i;
        if (kk < i) m = j;
    }
    return v[kk];
}

bvox_status bvox_section_background_estimate(const bvox_image *img, int dark, bvox_image **bg)
{
    *bg = NULL;
    bvox_status st = check_gray(img, "the section");
    if (st) return st;
    int32_t w = img->width, h = img->height;
    int32_t step = (w < h ? w : h) / 64;
    if (step < 1) step = 1;
    int32_t sx = (w + step - 1) / step, sy = (h + step - 1) / step;
    size_t ns = (size_t)sx * (size_t)sy;
    double *u = bvox__mem_alloc(ns * sizeof *u), *v = bvox__mem_alloc(ns * sizeof *v), *g = bvox__mem_alloc(ns * sizeof *g);
    double *res = bvox__mem_alloc(ns * sizeof *res), *tmp = bvox__mem_alloc(ns * sizeof *tmp);
    uint8_t *keep = bvox__mem_alloc(ns);
    if (!u || !v || !g || !res || !tmp || !keep) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    /* coordinates scaled to about [-1, 1] for a well-conditioned fit */
    double cx = w / 2.0, cy = h / 2.0, s = 2.0 / (w > h ? w : h);
    size_t m = 0;
    for (int32_t y = step / 2; y < h; y += step)
        for (int32_t x = step / 2; x < w; x += step) {
            u[m] = (x + 0.5 - cx) * s;
            v[m] = (y + 0.5 - cy) * s;
            g[m] = bvox__gray_at(img, (size_t)y * (size_t)w + (size_t)x);
            keep[m] = 1;
            m++;
        }
    /* start from the samples on the background side of Otsu's threshold */
    double t0;
    if ((st = bvox_section_otsu(img, &t0))) goto done;
    for (size_t i = 0; i < m; i++) keep[i] = dark ? g[i] > t0 : g[i] <= t0;
    double coef[6] = {0, 0, 0, 0, 0, 0};
    for (int iter = 0; iter < 5; iter++) {
        double a[6][6] = {{0}}, b[6] = {0};
        size_t used = 0;
        for (size_t i = 0; i < m; i++) {
            if (!keep[i]) continue;
            double f[6] = {1, u[i], v[i], u[i] * u[i], u[i] * v[i], v[i] * v[i]};
            for (int r = 0; r < 6; r++) {
                for (int c = 0; c < 6; c++) a[r][c] += f[r] * f[c];
                b[r] += f[r] * g[i];
            }
            used++;
        }
        double x[6];
        if (used < 6 || !solve6(a, b, x)) {
            if (iter == 0) { /* too few background samples: a flat mean */
                double sum = 0;
                for (size_t i = 0; i < m; i++) sum += g[i];
                coef[0] = sum / (double)m;
            }
            break; /* else keep the previous fit */
        }
        memcpy(coef, x, sizeof coef);
        if (iter == 4) break;
        /* robust spread of the kept samples' residuals (median, MAD); the
         * object lies on one side: drop the samples far on that side */
        size_t k = 0;
        for (size_t i = 0; i < m; i++) {
            res[i] = g[i] - (coef[0] + coef[1] * u[i] + coef[2] * v[i] + coef[3] * u[i] * u[i] +
                             coef[4] * u[i] * v[i] + coef[5] * v[i] * v[i]);
            if (keep[i]) tmp[k++] = res[i];
        }
        double med = select_kth(tmp, k, k / 2);
        k = 0;
        for (size_t i = 0; i < m; i++)
            if (keep[i]) tmp[k++] = fabs(res[i] - med);
        double mad = 1.4826 * select_kth(tmp, k, k / 2) + 0.5;
        for (size_t i = 0; i < m; i++)
            keep[i] = dark ? res[i] >= med - 3 * mad : res[i] <= med + 3 * mad;
    }
    st = bvox_image_create(w, h, 1, img->bits, bg);
    if (st) goto done;
    double maxv = img->bits == 8 ? 255 : 65535;
    for (int32_t y = 0; y < h; y++) {
        double vv = (y + 0.5 - cy) * s;
        double c0 = coef[0] + coef[2] * vv + coef[5] * vv * vv, c1 = coef[1] + coef[4] * vv;
        for (int32_t x = 0; x < w; x++) {
            double uu = (x + 0.5 - cx) * s;
            double val = c0 + c1 * uu + coef[3] * uu * uu;
            val = val < 0 ? 0 : val > maxv ? maxv : val;
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            if (img->bits == 8) (*bg)->pixels[i] = (uint8_t)(val + 0.5);
            else (*bg)->pixels16[i] = (uint16_t)(val + 0.5);
        }
    }
done:
    free(u);
    free(v);
    free(g);
    free(res);
    free(tmp);
    free(keep);
    return st;
}

/* out = img - bg + mean(bg) (divide 0) or img * mean(bg) / bg (divide 1). */
static bvox_status correct(const bvox_image *img, const bvox_image *bg, int divide,
                           bvox_image **out)
{
    *out = NULL;
    bvox_status st = check_gray(img, "the section");
    if (!st) st = check_gray(bg, "the background");
    if (st) return st;
    if (img->width != bg->width || img->height != bg->height)
        return bvox__fail(BVOX_EINVAL, "the background is %d x %d pixels but the section %d x %d",
                          (int)bg->width, (int)bg->height, (int)img->width, (int)img->height);
    size_t n = (size_t)img->width * (size_t)img->height;
    double sum = 0;
    for (size_t i = 0; i < n; i++) sum += bvox__gray_at(bg, i);
    double meanf = sum / (double)n;
    int32_t mean = (int32_t)(meanf + 0.5);
    int32_t maxv = img->bits == 8 ? 255 : 65535;
    st = bvox_image_create(img->width, img->height, 1, img->bits, out);
    if (st) return st;
    for (size_t i = 0; i < n; i++) {
        int32_t val, b = bvox__gray_at(bg, i);
        if (divide) val = (int32_t)(bvox__gray_at(img, i) * meanf / (b > 0 ? b : 1) + 0.5);
        else val = bvox__gray_at(img, i) - b + mean;
        val = val < 0 ? 0 : val > maxv ? maxv : val;
        if (img->bits == 8) (*out)->pixels[i] = (uint8_t)val;
        else (*out)->pixels16[i] = (uint16_t)val;
    }
    return BVOX_OK;
}

bvox_status bvox_section_subtract_background(const bvox_image *img, const bvox_image *bg,
                                             bvox_image **out)
{
    return correct(img, bg, 0, out);
}

bvox_status bvox_section_divide_background(const bvox_image *img, const bvox_image *bg,
                                           bvox_image **out)
{
    return correct(img, bg, 1, out);
}

/* ------------------------------------------------------------- threshold */

bvox_status bvox_section_otsu(const bvox_image *img, double *threshold)
{
    bvox_status st = check_gray(img, "the section");
    if (st) return st;
    size_t nb = img->bits == 8 ? 256 : 65536, n = (size_t)img->width * (size_t)img->height;
    uint32_t *hist = bvox__mem_zalloc(nb, sizeof *hist);
    if (!hist) return bvox__fail(BVOX_ENOMEM, "out of memory");
    for (size_t i = 0; i < n; i++) hist[bvox__gray_at(img, i)]++;
    double total = (double)n, sum_all = 0;
    size_t lo = 0, hi = nb - 1;
    while (lo < nb && !hist[lo]) lo++;
    while (hi > lo && !hist[hi]) hi--;
    for (size_t v = lo; v <= hi; v++) sum_all += (double)v * hist[v];
    /* between-class variance w0 w1 (m0 - m1)^2 for {v <= t}, {v > t}; the
     * maximum may be a plateau (empty bins between the modes): its middle */
    double best = -1, w0 = 0, sum0 = 0;
    size_t best_lo = lo, best_hi = lo;
    for (size_t t = lo; t < hi; t++) {
        w0 += hist[t];
        sum0 += (double)t * hist[t];
        double w1 = total - w0;
        if (w0 <= 0 || w1 <= 0) continue;
        double m0 = sum0 / w0, m1 = (sum_all - sum0) / w1;
        double var = w0 * w1 * (m0 - m1) * (m0 - m1);
        if (var > best * (1 + 1e-12)) {
            best = var;
            best_lo = best_hi = t;
        } else if (var >= best * (1 - 1e-12)) {
            best_hi = t;
        }
    }
    free(hist);
    *threshold = lo == hi ? (double)lo : (best_lo + best_hi) / 2.0;
    return BVOX_OK;
}

bvox_status bvox_section_threshold(const bvox_image *img, double threshold, int dark,
                                   bvox_bitmap **out)
{
    *out = NULL;
    bvox_status st = check_gray(img, "the section");
    if (st) return st;
    if (!isfinite(threshold)) return bvox__fail(BVOX_EINVAL, "the threshold is not finite");
    st = bvox_bitmap_create(img->width, img->height, out);
    if (st) return st;
    /* integer comparison: dark v <= floor(t); bright v > floor(t) */
    double ft = floor(threshold);
    int32_t t = ft < -1 ? -1 : ft > 65536 ? 65536 : (int32_t)ft;
    for (int32_t y = 0; y < img->height; y++) {
        uint64_t *row = bvox__bm_row(*out, y);
        size_t base = (size_t)y * (size_t)img->width;
        for (int32_t x0 = 0; x0 < img->width; x0 += 64) {
            int32_t x1 = x0 + 64 < img->width ? x0 + 64 : img->width;
            uint64_t w = 0;
            if (img->bits == 8) {
                const uint8_t *p = img->pixels + base;
                for (int32_t x = x0; x < x1; x++) w |= (uint64_t)(dark ? p[x] <= t : p[x] > t) << (x - x0);
            } else {
                const uint16_t *p = img->pixels16 + base;
                for (int32_t x = x0; x < x1; x++) w |= (uint64_t)(dark ? p[x] <= t : p[x] > t) << (x - x0);
            }
            row[x0 >> 6] = w;
        }
    }
    return BVOX_OK;
}
