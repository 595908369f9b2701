/* test_reconstruct_steps.c — each image step of the reconstruction against a
 * known answer or a brute-force reference: Otsu, thresholding, the median
 * filter, dilation/erosion, components, specks, contour tracing and
 * nesting, the background estimate, marker detection, the least-squares
 * similarity fit, marker matching and the chain of alignments. */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>
#include <unistd.h>

static double urand(void)
{
    return (double)(harness_rand() >> 11) / 9007199254740992.0;
}

static bvox_bitmap *random_bitmap(int32_t w, int32_t h, double p)
{
    bvox_bitmap *bm = NULL;
    if (bvox_bitmap_create(w, h, &bm)) return NULL;
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) bvox_bitmap_set(bm, x, y, urand() < p);
    return bm;
}

static const int32_t sizes[][2] = {{1, 1}, {5, 3}, {63, 7}, {64, 9}, {65, 4}, {130, 17}, {200, 31}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

/* ------------------------------------------------------------------ Otsu */

/* Brute force: t maximising w0 w1 (m0 - m1)^2 computed from the pixels. */
static double otsu_ref(const bvox_image *img)
{
    size_t n = (size_t)img->width * img->height;
    int maxv = img->bits == 8 ? 255 : 65535, lo = maxv, hi = 0;
    for (size_t i = 0; i < n; i++) {
        int v = img->bits == 8 ? img->pixels[i] : img->pixels16[i];
        if (v < lo) lo = v;
        if (v > hi) hi = v;
    }
    double best = -1;
    int blo = lo, bhi = lo;
    for (int t = lo; t < hi; t++) {
        double w0 = 0, w1 = 0, s0 = 0, s1 = 0;
        for (size_t i = 0; i < n; i++) {
            int v = img->bits == 8 ? img->pixels[i] : img->pixels16[i];
            if (v <= t) w0++, s0 += v;
            else w1++, s1 += v;
        }
        if (!w0 || !w1) continue;
        double var = w0 * w1 * (s0 / w0 - s1 / w1) * (s0 / w0 - s1 / w1);
        if (var > best * (1 + 1e-9)) best = var, blo = bhi = t;
        else if (var >= best * (1 - 1e-9)) bhi = t;
    }
    return (blo + bhi) / 2.0;
}

TEST(otsu_bimodal_plateau)
{
    /* two values only: every t in [50, 199] separates them; the middle */
    bvox_image *img = NULL;
    CHECK_OK(bvox_image_create(40, 30, 1, 8, &img));
    for (int i = 0; i < 40 * 30; i++) img->pixels[i] = i % 3 ? 50 : 200;
    double t = 0;
    CHECK_OK(bvox_section_otsu(img, &t));
    CHECK_NEAR(t, 124.5, 1e-12);
    bvox_image_destroy(img);
    return 0;
}

TEST(otsu_against_brute_force)
{
    for (int bits = 8; bits <= 16; bits += 8) {
        bvox_image *img = NULL;
        CHECK_OK(bvox_image_create(37, 23, 1, bits, &img));
        for (int i = 0; i < 37 * 23; i++) {
            /* three noisy clusters */
            double c = (harness_rand() % 3) * 70 + 40 + (urand() - 0.5) * 40;
            if (bits == 8) img->pixels[i] = (uint8_t)c;
            else img->pixels16[i] = (uint16_t)(c * 37);
        }
        double t = 0, r = otsu_ref(img);
        CHECK_OK(bvox_section_otsu(img, &t));
        CHECK_NEAR(t, r, 1e-9);
        bvox_image_destroy(img);
    }
    return 0;
}

TEST(threshold_polarity)
{
    bvox_image *img = NULL;
    CHECK_OK(bvox_image_create(131, 5, 1, 8, &img));
    for (int i = 0; i < 131 * 5; i++) img->pixels[i] = (uint8_t)(harness_rand() & 255);
    bvox_bitmap *dark = NULL, *bright = NULL;
    CHECK_OK(bvox_section_threshold(img, 99.5, 1, &dark));
    CHECK_OK(bvox_section_threshold(img, 99.5, 0, &bright));
    for (int32_t y = 0; y < 5; y++)
        for (int32_t x = 0; x < 131; x++) {
            int v = img->pixels[y * 131 + x];
            CHECK_EQ(bvox_bitmap_get(dark, x, y), v <= 99);
            CHECK_EQ(bvox_bitmap_get(bright, x, y), v > 99);
        }
    CHECK_EQ(bvox_bitmap_count(dark) + bvox_bitmap_count(bright), 131 * 5);
    bvox_bitmap_destroy(dark);
    bvox_bitmap_destroy(bright);
    bvox_image_destroy(img);
    return 0;
}

/* ------------------------------------------------------------ filters */

TEST(median_against_brute_force)
{
    for (int s = 0; s < NSIZES; s++)
        for (int32_t r = 0; r <= 3; r++) {
            int32_t w = sizes[s][0], h = sizes[s][1];
            bvox_bitmap *in = random_bitmap(w, h, 0.45), *out = NULL;
            CHECK(in);
            CHECK_OK(bvox_bitmap_median(in, r, &out));
            for (int32_t y = 0; y < h; y++)
                for (int32_t x = 0; x < w; x++) {
                    int cnt = 0, valid = 0;
                    for (int32_t dy = -r; dy <= r; dy++)
                        for (int32_t dx = -r; dx <= r; dx++) {
                            int32_t xx = x + dx, yy = y + dy;
                            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                            valid++;
                            cnt += bvox_bitmap_get(in, xx, yy);
                        }
                    CHECK_EQ(bvox_bitmap_get(out, x, y), 2 * cnt > valid);
                }
            /* tail bits stay zero */
            for (int32_t y = 0; y < h; y++)
                if (w & 63) CHECK_EQ(out->words[y * out->words_per_row + out->words_per_row - 1] >> (w & 63), 0);
            bvox_bitmap_destroy(in);
            bvox_bitmap_destroy(out);
        }
    return 0;
}

TEST(dilate_erode_against_brute_force)
{
    for (int s = 0; s < NSIZES; s++)
        for (int32_t r = 0; r <= 4; r++) {
            int32_t w = sizes[s][0], h = sizes[s][1];
            bvox_bitmap *in = random_bitmap(w, h, r ? 0.08 : 0.5), *d = NULL, *e = NULL, *o = NULL,
                        *c = NULL;
            CHECK(in);
            CHECK_OK(bvox_bitmap_dilate(in, r, &d));
            bvox_bitmap *dense = random_bitmap(w, h, 0.92);
            CHECK_OK(bvox_bitmap_erode(dense, r, &e));
            for (int32_t y = 0; y < h; y++)
                for (int32_t x = 0; x < w; x++) {
                    int any = 0, all = 1;
                    for (int32_t dy = -r; dy <= r; dy++)
                        for (int32_t dx = -r; dx <= r; dx++) {
                            int32_t xx = x + dx, yy = y + dy;
                            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue; /* outside: 0 for
                                dilation, object for erosion */
                            any |= bvox_bitmap_get(in, xx, yy);
                            all &= bvox_bitmap_get(dense, xx, yy);
                        }
                    CHECK_EQ(bvox_bitmap_get(d, x, y), any);
                    CHECK_EQ(bvox_bitmap_get(e, x, y), all);
                }
            /* opening is anti-extensive, closing extensive, both idempotent */
            CHECK_OK(bvox_bitmap_open(dense, r, &o));
            CHECK_OK(bvox_bitmap_close(in, r, &c));
            for (int32_t y = 0; y < h; y++)
                for (int32_t x = 0; x < w; x++) {
                    CHECK(bvox_bitmap_get(o, x, y) <= bvox_bitmap_get(dense, x, y));
                    CHECK(bvox_bitmap_get(c, x, y) >= bvox_bitmap_get(in, x, y));
                }
            bvox_bitmap *o2 = NULL;
            CHECK_OK(bvox_bitmap_open(o, r, &o2));
            CHECK(!memcmp(o2->words, o->words, (size_t)h * o->words_per_row * 8));
            bvox_bitmap_destroy(o2);
            bvox_bitmap_destroy(in);
            bvox_bitmap_destroy(dense);
            bvox_bitmap_destroy(d);
            bvox_bitmap_destroy(e);
            bvox_bitmap_destroy(o);
            bvox_bitmap_destroy(c);
        }
    return 0;
}

/* Flood-fill labelling in scan order (the reference). */
static int32_t flood_label(const bvox_bitmap *bm, int conn, int32_t *lab)
{
    int32_t w = bm->width, h = bm->height, n = 0;
    int32_t *stack = malloc((size_t)w * h * sizeof *stack);
    memset(lab, 0, (size_t)w * h * sizeof *lab);
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) {
            if (!bvox_bitmap_get(bm, x, y) || lab[y * w + x]) continue;
            n++;
            int32_t sp = 0;
            stack[sp++] = y * w + x;
            lab[y * w + x] = n;
            while (sp) {
                int32_t p = stack[--sp], px = p % w, py = p / w;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        if (!dx && !dy) continue;
                        if (conn == 4 && dx && dy) continue;
                        int32_t qx = px + dx, qy = py + dy;
                        if (!bvox_bitmap_get(bm, qx, qy) || lab[qy * w + qx]) continue;
                        lab[qy * w + qx] = n;
                        stack[sp++] = qy * w + qx;
                    }
            }
        }
    free(stack);
    return n;
}

TEST(label_against_flood_fill)
{
    for (int s = 0; s < NSIZES; s++)
        for (int conn = 4; conn <= 8; conn += 4) {
            int32_t w = sizes[s][0], h = sizes[s][1];
            bvox_bitmap *bm = random_bitmap(w, h, 0.4);
            int32_t *lab = NULL, n = 0, *ref = malloc((size_t)w * h * sizeof *ref);
            CHECK_OK(bvox_bitmap_label(bm, conn, &lab, &n));
            CHECK_EQ(n, flood_label(bm, conn, ref));
            for (int32_t i = 0; i < w * h; i++) CHECK_EQ(lab[i], ref[i]);
            bvox_free(lab);
            free(ref);
            bvox_bitmap_destroy(bm);
        }
    return 0;
}

TEST(specks_and_small_holes)
{
    /* a 10x10 square with a 2x2 hole and a 5x5 hole, a 3-pixel speck, a
     * diagonal pair (8-connected: 2 pixels) and a 20-pixel bar */
    bvox_bitmap *bm = NULL;
    CHECK_OK(bvox_bitmap_create(40, 30, &bm));
    for (int y = 2; y < 22; y++)
        for (int x = 2; x < 22; x++) bvox_bitmap_set(bm, x, y, 1);
    for (int y = 4; y < 6; y++)
        for (int x = 4; x < 6; x++) bvox_bitmap_set(bm, x, y, 0);
    for (int y = 10; y < 15; y++)
        for (int x = 10; x < 15; x++) bvox_bitmap_set(bm, x, y, 0);
    for (int x = 30; x < 33; x++) bvox_bitmap_set(bm, x, 2, 1);
    bvox_bitmap_set(bm, 30, 10, 1);
    bvox_bitmap_set(bm, 31, 11, 1);
    for (int x = 25; x < 35; x++) {
        bvox_bitmap_set(bm, x, 20, 1);
        bvox_bitmap_set(bm, x, 21, 1);
    }
    int64_t before = bvox_bitmap_count(bm);
    CHECK_OK(bvox_bitmap_remove_specks(bm, 5, 1));
    /* speck (3) and pair (2) gone, 2x2 hole (4) filled, 5x5 hole (25) kept */
    CHECK_EQ(bvox_bitmap_count(bm), before - 3 - 2 + 4);
    CHECK_EQ(bvox_bitmap_get(bm, 4, 4), 1);
    CHECK_EQ(bvox_bitmap_get(bm, 12, 12), 0);
    CHECK_EQ(bvox_bitmap_get(bm, 31, 2), 0);
    CHECK_EQ(bvox_bitmap_get(bm, 31, 11), 0);
    CHECK_EQ(bvox_bitmap_get(bm, 34, 21), 1);
    bvox_bitmap_destroy(bm);
    return 0;
}

/* --------------------------------------------------------------- tracing */

static double shoelace(const bvox_point2 *p, int32_t n)
{
    double s = 0;
    for (int32_t i = 0, j = n - 1; i < n; j = i++) s += p[j].x * p[i].y - p[i].x * p[j].y;
    return s / 2;
}

/* Even-odd over all contours at the centre of pixel (x, y). */
static int evenodd(const bvox_contour *c, int32_t nc, int32_t x, int32_t y)
{
    double cx = x + 0.5, cy = y + 0.5;
    int in = 0;
    for (int32_t k = 0; k < nc; k++)
        for (int32_t i = 0, j = c[k].npoints - 1; i < c[k].npoints; j = i++) {
            bvox_point2 a = c[k].points[i], b = c[k].points[j];
            if ((a.y > cy) != (b.y > cy) && cx < b.x + (cy - b.y) * (a.x - b.x) / (a.y - b.y))
                in = !in;
        }
    return in;
}

TEST(trace_ring_hole_island)
{
    /* a ring (disc radius 20 minus radius 12) with an island (radius 5) in
     * its hole, and a separate square blob */
    bvox_bitmap *bm = NULL;
    CHECK_OK(bvox_bitmap_create(80, 60, &bm));
    for (int y = 0; y < 60; y++)
        for (int x = 0; x < 80; x++) {
            double d = hypot(x + 0.5 - 30, y + 0.5 - 30);
            bvox_bitmap_set(bm, x, y, (d <= 20 && d > 12) || d <= 5 || (x >= 60 && x < 70 && y >= 5 && y < 15));
        }
    bvox_contour *c = NULL;
    int32_t n = 0;
    CHECK_OK(bvox_bitmap_trace(bm, &c, &n));
    CHECK_EQ(n, 4);
    int ring = -1, hole = -1, island = -1, blob = -1;
    for (int32_t i = 0; i < n; i++) {
        double a = shoelace(c[i].points, c[i].npoints);
        CHECK_EQ(c[i].hole, a < 0);
        double minx = 1e9;
        for (int32_t j = 0; j < c[i].npoints; j++) minx = fmin(minx, c[i].points[j].x);
        if (minx >= 60) blob = i;
        else if (minx <= 11) ring = i;
        else if (c[i].hole) hole = i;
        else island = i;
    }
    CHECK(ring >= 0 && hole >= 0 && island >= 0 && blob >= 0);
    CHECK_EQ(c[ring].parent, -1);
    CHECK_EQ(c[blob].parent, -1);
    CHECK_EQ(c[hole].parent, ring);
    CHECK_EQ(c[island].parent, hole);
    CHECK_EQ(c[blob].npoints, 4);
    CHECK_NEAR(shoelace(c[blob].points, 4), 100, 0);
    bvox_contours_free(c, n);
    bvox_bitmap_destroy(bm);
    return 0;
}

TEST(trace_fills_back_exactly)
{
    for (int s = 0; s < NSIZES; s++) {
        int32_t w = sizes[s][0], h = sizes[s][1];
        bvox_bitmap *bm = random_bitmap(w, h, 0.5);
        bvox_contour *c = NULL;
        int32_t n = 0;
        CHECK_OK(bvox_bitmap_trace(bm, &c, &n));
        double area = 0;
        for (int32_t k = 0; k < n; k++) {
            CHECK(c[k].npoints >= 4);
            CHECK(c[k].parent < n);
            area += shoelace(c[k].points, c[k].npoints);
            /* a hole's parent is an outer contour and the other way round */
            if (c[k].parent >= 0) CHECK_EQ(c[c[k].parent].hole, !c[k].hole);
            else CHECK_EQ(c[k].hole, 0);
        }
        CHECK_NEAR(area, (double)bvox_bitmap_count(bm), 1e-9);
        /* parents against brute force: the smallest other contour containing
         * a point half a step along the contour's first edge (on no other
         * contour: edges are not shared) */
        for (int32_t k = 0; k < n; k++) {
            bvox_point2 a = c[k].points[0], b = c[k].points[1];
            double len = hypot(b.x - a.x, b.y - a.y);
            bvox_point2 q = {a.x + 0.5 * (b.x - a.x) / len, a.y + 0.5 * (b.y - a.y) / len};
            int32_t want = -1;
            double best = INFINITY;
            for (int32_t j = 0; j < n; j++) {
                if (j == k) continue;
                int in = 0;
                for (int32_t u = 0, v = c[j].npoints - 1; u < c[j].npoints; v = u++) {
                    bvox_point2 e = c[j].points[u], f = c[j].points[v];
                    if ((e.y > q.y) != (f.y > q.y) && q.x < f.x + (q.y - f.y) * (e.x - f.x) / (e.y - f.y))
                        in = !in;
                }
                double aj = fabs(shoelace(c[j].points, c[j].npoints));
                if (in && aj < best) best = aj, want = j;
            }
            CHECK_EQ(c[k].parent, want);
        }
        for (int32_t y = 0; y < h; y++)
            for (int32_t x = 0; x < w; x++) CHECK_EQ(evenodd(c, n, x, y), bvox_bitmap_get(bm, x, y));
        bvox_contours_free(c, n);
        bvox_bitmap_destroy(bm);
    }
    return 0;
}

/* ------------------------------------------------------------ background */

TEST(background_estimate_ignores_a_large_object)
{
    int32_t w = 200, h = 150;
    bvox_image *img = NULL, *bg = NULL, *flat = NULL;
    CHECK_OK(bvox_image_create(w, h, 1, 8, &img));
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) {
            double b = 150 + 40.0 * x / w - 30.0 * ((y - 75) / 75.0) * ((y - 75) / 75.0);
            int obj = hypot(x - 90, y - 70) < 55;
            double v = (obj ? b - 90 : b) + (urand() - 0.5) * 10;
            img->pixels[y * w + x] = (uint8_t)lround(v);
        }
    CHECK_OK(bvox_section_background_estimate(img, 1, &bg));
    double worst = 0;
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) {
            double b = 150 + 40.0 * x / w - 30.0 * ((y - 75) / 75.0) * ((y - 75) / 75.0);
            worst = fmax(worst, fabs(bg->pixels[y * w + x] - b));
        }
    if (!(worst < 4)) fprintf(stderr, "worst background error %g\n", worst);
    CHECK(worst < 4);
    CHECK_OK(bvox_section_subtract_background(img, bg, &flat));
    /* flattened: Otsu separates the object exactly but for noise */
    double t;
    CHECK_OK(bvox_section_otsu(flat, &t));
    bvox_bitmap *m = NULL;
    CHECK_OK(bvox_section_threshold(flat, t, 1, &m));
    int64_t wrong = 0;
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) wrong += bvox_bitmap_get(m, x, y) != (hypot(x - 90, y - 70) < 55);
    CHECK_EQ(wrong, 0);
    bvox_image *small = NULL;
    CHECK_OK(bvox_image_create(w - 1, h, 1, 8, &small));
    bvox_image *bad = NULL;
    CHECK_STATUS(bvox_section_subtract_background(small, bg, &bad), BVOX_EINVAL);
    CHECK(bad == NULL);
    bvox_image_destroy(small);
    bvox_bitmap_destroy(m);
    bvox_image_destroy(img);
    bvox_image_destroy(bg);
    bvox_image_destroy(flat);
    return 0;
}

/* ---------------------------------------------------------------- markers */

TEST(markers_found_at_their_centres)
{
    int32_t w = 256, h = 200;
    const bvox_point2 truth[3] = {{30.3, 40.7}, {220.5, 50.2}, {120.8, 170.4}};
    bvox_image *img = NULL;
    CHECK_OK(bvox_image_create(w, h, 1, 8, &img));
    for (int32_t y = 0; y < h; y++)
        for (int32_t x = 0; x < w; x++) {
            double v = 190 + (urand() - 0.5) * 20;
            if (hypot(x + 0.5 - 120, y + 0.5 - 90) < 50) v = 90 + (urand() - 0.5) * 20;
            for (int k = 0; k < 3; k++)
                if (hypot(x + 0.5 - truth[k].x, y + 0.5 - truth[k].y) <= 5) v = 25;
            if (x >= 200 && x < 230 && y >= 150 && y < 153) v = 25; /* dark but long: no marker */
            img->pixels[y * w + x] = (uint8_t)v;
        }
    bvox_marker_opts o = bvox_marker_opts_default();
    bvox_point2 m[4];
    int32_t found = 0;
    bvox_bitmap *mask = NULL;
    CHECK_OK(bvox_section_threshold(img, 140, 1, &mask));
    CHECK_OK(bvox_section_find_markers(img, &o, m, &found, mask));
    CHECK_EQ(found, 3);
    for (int k = 0; k < 3; k++) {
        double best = 1e9;
        for (int i = 0; i < found; i++) best = fmin(best, hypot(m[i].x - truth[k].x, m[i].y - truth[k].y));
        CHECK(best < 0.3);
        /* erased from the mask (and 2 pixels around) */
        CHECK_EQ(bvox_bitmap_get(mask, (int32_t)truth[k].x, (int32_t)truth[k].y), 0);
    }
    CHECK_EQ(bvox_bitmap_get(mask, 120, 90), 1);
    bvox_bitmap_destroy(mask);
    bvox_image_destroy(img);
    return 0;
}

/* ------------------------------------------------------------ transforms */

TEST(kabsch_exact_point_sets)
{
    for (int trial = 0; trial < 20; trial++) {
        bvox_sim2 t = {(urand() - 0.5) * 6, 0.7 + urand() * 0.6, (urand() - 0.5) * 100,
                       (urand() - 0.5) * 100};
        int scaled = trial & 1;
        if (!scaled) t.scale = 1;
        int32_t n = 2 + trial % 5;
        bvox_point2 a[8], b[8];
        for (int32_t i = 0; i < n; i++) {
            a[i] = (bvox_point2){urand() * 500, urand() * 500};
            b[i] = bvox_sim2_apply(&t, a[i]);
        }
        bvox_sim2 f;
        double rms = 1;
        CHECK_OK(bvox_sim2_fit(a, b, n, scaled, &f, &rms));
        CHECK_NEAR(f.angle, t.angle, 1e-9);
        CHECK_NEAR(f.scale, t.scale, 1e-9);
        CHECK_NEAR(f.tx, t.tx, 1e-7);
        CHECK_NEAR(f.ty, t.ty, 1e-7);
        CHECK_NEAR(rms, 0, 1e-7);
        /* inverse and composition */
        bvox_sim2 inv = bvox_sim2_inverse(&t), id = bvox_sim2_compose(&inv, &t);
        bvox_point2 p = bvox_sim2_apply(&id, a[0]);
        CHECK_NEAR(p.x, a[0].x, 1e-9);
        CHECK_NEAR(p.y, a[0].y, 1e-9);
    }
    /* a quarter turn by hand: (1, 0) -> (0, 1) */
    bvox_point2 a[2] = {{0, 0}, {1, 0}}, b[2] = {{5, 5}, {5, 6}};
    bvox_sim2 f;
    CHECK_OK(bvox_sim2_fit(a, b, 2, 0, &f, NULL));
    CHECK_NEAR(f.angle, M_PI / 2, 1e-12);
    CHECK_NEAR(f.tx, 5, 1e-12);
    CHECK_STATUS(bvox_sim2_fit(a, b, 1, 0, &f, NULL), BVOX_EINVAL);
    return 0;
}

TEST(match_permutation_missing_spurious)
{
    bvox_point2 src[3] = {{40, 50}, {400, 80}, {220, 420}};
    bvox_sim2 t = {0.1, 1, 12, -7};
    const int perm[3] = {2, 0, 1};
    bvox_point2 dst[4];
    for (int i = 0; i < 3; i++) dst[perm[i]] = bvox_sim2_apply(&t, src[i]);
    bvox_marker_opts o = bvox_marker_opts_default();
    bvox_sim2 f;
    int32_t match[4], nm = 0;
    double rms;
    CHECK_OK(bvox_markers_match(src, 3, dst, 3, &o, &f, match, &nm, &rms));
    CHECK_EQ(nm, 3);
    for (int i = 0; i < 3; i++) CHECK_EQ(match[i], perm[i]);
    CHECK_NEAR(f.angle, 0.1, 1e-9);
    CHECK_NEAR(f.tx, 12, 1e-7);
    /* the neighbour misses one marker */
    CHECK_OK(bvox_markers_match(src, 3, dst, 2, &o, &f, match, &nm, &rms));
    CHECK_EQ(nm, 2);
    CHECK_NEAR(f.angle, 0.1, 1e-9);
    /* a spurious blob on this side */
    bvox_point2 src4[4] = {src[0], {300, 300}, src[1], src[2]};
    CHECK_OK(bvox_markers_match(src4, 4, dst, 3, &o, &f, match, &nm, &rms));
    CHECK_EQ(nm, 3);
    CHECK_EQ(match[1], -1);
    CHECK_EQ(match[0], perm[0]);
    CHECK_NEAR(f.ty, -7, 1e-7);
    /* a spurious one on the other side, one missing here */
    dst[3] = (bvox_point2){100, 300};
    CHECK_OK(bvox_markers_match(src + 1, 2, dst, 4, &o, &f, match, &nm, &rms));
    CHECK_EQ(nm, 2);
    CHECK_NEAR(f.angle, 0.1, 1e-9);
    /* implausible: a half turn is refused (at best 2 markers fit some
     * plausible transform by chance, never all 3) */
    bvox_sim2 half = {M_PI, 1, 0, 0};
    for (int i = 0; i < 3; i++) dst[i] = bvox_sim2_apply(&half, src[i]);
    if (bvox_markers_match(src, 3, dst, 3, &o, &f, match, &nm, &rms) == BVOX_OK) {
        CHECK(nm < 3);
        CHECK(fabs(f.angle) <= M_PI / 6 + 1e-9);
    }
    CHECK_STATUS(bvox_markers_match(src, 1, dst, 3, &o, &f, match, &nm, &rms), BVOX_ENOTFOUND);
    return 0;
}

TEST(align_chain_to_reference)
{
    /* 7 sections: the markers of section k are the block's markers moved by
     * T_k; aligned, every section's markers land on the reference's */
    enum { N = 7 };
    bvox_point2 block[3] = {{50, 60}, {450, 90}, {240, 430}};
    bvox_sim2 tk[N];
    bvox_point2 pts[N][3];
    const bvox_point2 *ptr[N];
    int32_t counts[N];
    for (int k = 0; k < N; k++) {
        tk[k] = (bvox_sim2){(urand() - 0.5) * 0.28, 1, (urand() - 0.5) * 40, (urand() - 0.5) * 40};
        for (int i = 0; i < 3; i++) pts[k][i] = bvox_sim2_apply(&tk[k], block[i]);
        ptr[k] = pts[k];
        counts[k] = 3;
    }
    counts[1] = 2; /* one missing: still aligned */
    counts[5] = 1; /* too few: fallback to its neighbour's transform */
    bvox_align_result r[N];
    bvox_marker_opts o = bvox_marker_opts_default();
    CHECK_OK(bvox_markers_align(ptr, counts, N, -1, &o, r));
    CHECK_EQ(r[3].neighbour, -1);
    CHECK_EQ(r[1].fallback, 0);
    CHECK_EQ(r[1].matched, 2);
    CHECK_EQ(r[5].fallback, 1);
    CHECK_EQ(r[5].neighbour, 4);
    CHECK_EQ(r[6].neighbour, 4); /* skips the fallback section */
    CHECK_EQ(r[0].neighbour, 1);
    for (int k = 0; k < N; k++) {
        if (k == 5) continue;
        for (int i = 0; i < 3; i++) {
            bvox_point2 p = bvox_sim2_apply(&r[k].transform, pts[k][i]);
            CHECK_NEAR(p.x, pts[3][i].x, 1e-6);
            CHECK_NEAR(p.y, pts[3][i].y, 1e-6);
        }
    }
    CHECK_NEAR(r[5].transform.angle, r[4].transform.angle, 0);
    return 0;
}

TEST(gray_read_and_bitmap_image)
{
    /* RGB -> luminance 0.299 R + 0.587 G + 0.114 B, rounded; through a PNG */
    bvox_image *rgb = NULL, *gray = NULL, *back = NULL;
    CHECK_OK(bvox_image_create(3, 2, 3, 8, &rgb));
    const uint8_t px[18] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 200, 100, 50, 0, 0, 0};
    memcpy(rgb->pixels, px, sizeof px);
    CHECK_OK(bvox_section_gray(rgb, &gray));
    const int want[6] = {76, 150, 29, 18, 124, 0};
    for (int i = 0; i < 6; i++) CHECK_EQ(gray->pixels[i], want[i]);
    const char *path = harness_path("rgb.png");
    CHECK_OK(bvox_image_write_png(rgb, path));
    CHECK_OK(bvox_section_read(path, &back));
    CHECK_EQ(back->channels, 1);
    CHECK(!memcmp(back->pixels, gray->pixels, 6));
    bvox_image *none = NULL;
    CHECK(bvox_section_read(harness_path("missing.png"), &none) != BVOX_OK);
    CHECK(none == NULL);
    CHECK_STATUS(bvox_section_read(harness_path("missing.tif"), &none), BVOX_ENOTFOUND);
    /* a bitmap as an image: 255 where set */
    bvox_bitmap *bm = random_bitmap(70, 3, 0.5);
    bvox_image *im = NULL;
    CHECK_OK(bvox_bitmap_to_image(bm, &im));
    for (int32_t y = 0; y < 3; y++)
        for (int32_t x = 0; x < 70; x++) CHECK_EQ(im->pixels[y * 70 + x], bvox_bitmap_get(bm, x, y) ? 255 : 0);
    bvox_bitmap *bad = NULL;
    CHECK_STATUS(bvox_bitmap_create(0, 5, &bad), BVOX_EINVAL);
    CHECK(bad == NULL);
    bvox_bitmap_destroy(bm);
    bvox_image_destroy(im);
    bvox_image_destroy(rgb);
    bvox_image_destroy(gray);
    bvox_image_destroy(back);
    return 0;
}

TEST(sixteen_bit_sections)
{
    /* the same steps on 16-bit samples: threshold, markers */
    bvox_image *img = NULL;
    CHECK_OK(bvox_image_create(120, 100, 1, 16, &img));
    for (int32_t y = 0; y < 100; y++)
        for (int32_t x = 0; x < 120; x++) {
            double v = 50000 + (urand() - 0.5) * 2000;
            if (hypot(x + 0.5 - 60, y + 0.5 - 50) < 25) v = 20000 + (urand() - 0.5) * 2000;
            if (hypot(x + 0.5 - 15.5, y + 0.5 - 15.5) <= 4) v = 3000;
            if (hypot(x + 0.5 - 100.5, y + 0.5 - 85.5) <= 4) v = 3000;
            img->pixels16[y * 120 + x] = (uint16_t)v;
        }
    double t;
    CHECK_OK(bvox_section_otsu(img, &t));
    CHECK(t > 21000 && t < 49000);
    bvox_marker_opts o = bvox_marker_opts_default();
    o.count = 2;
    bvox_point2 m[3];
    int32_t found = 0;
    CHECK_OK(bvox_section_find_markers(img, &o, m, &found, NULL));
    CHECK_EQ(found, 2);
    CHECK(hypot(m[0].x - 15.5, m[0].y - 15.5) < 0.2 || hypot(m[1].x - 15.5, m[1].y - 15.5) < 0.2);
    bvox_image_destroy(img);
    return 0;
}

/* A TIFF written by libtiff: w x h, spp samples of bps bits, photometric,
 * tiled or strips; sample i of the raster is f(i). */
static int write_tiff(const char *path, int w, int h, int spp, int bps, int photo, int tiled,
                      unsigned (*f)(size_t))
{
    TIFF *t = TIFFOpen(path, "w");
    if (!t) return -1;
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, spp);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, bps);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, photo);
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_LZW);
    size_t row = (size_t)w * spp * (bps / 8);
    if (tiled) {
        TIFFSetField(t, TIFFTAG_TILEWIDTH, 16);
        TIFFSetField(t, TIFFTAG_TILELENGTH, 16);
        uint8_t tile[16 * 16 * 3];
        for (int ty = 0; ty < h; ty += 16)
            for (int tx = 0; tx < w; tx += 16) {
                memset(tile, 0, sizeof tile);
                for (int y = 0; y < 16 && ty + y < h; y++)
                    for (int x = 0; x < 16 && tx + x < w; x++)
                        for (int c = 0; c < spp; c++)
                            tile[(y * 16 + x) * spp + c] = (uint8_t)f(((size_t)(ty + y) * w + tx + x) * spp + c);
                TIFFWriteTile(t, tile, (uint32_t)tx, (uint32_t)ty, 0, 0);
            }
    } else {
        uint8_t *buf = malloc(row);
        for (int y = 0; y < h; y++) {
            for (size_t i = 0; i < (size_t)w * spp; i++) {
                unsigned v = f((size_t)y * w * spp + i);
                if (bps == 8) buf[i] = (uint8_t)v;
                else ((uint16_t *)buf)[i] = (uint16_t)v;
            }
            TIFFWriteScanline(t, buf, (uint32_t)y, 0);
        }
        free(buf);
    }
    TIFFClose(t);
    return 0;
}

static unsigned pattern8(size_t i) { return (unsigned)((i * 37 + 11) & 255); }
static unsigned pattern16(size_t i) { return (unsigned)((i * 7919 + 3) & 65535); }

TEST(tiff_sections)
{
    int w = 37, h = 21;
    const char *p8 = harness_path("g8.tif"), *p16 = harness_path("g16.tif");
    const char *pw = harness_path("white.tif"), *prgb = harness_path("rgb.tif");
    const char *ptile = harness_path("tiled.tif");
    CHECK(!write_tiff(p8, w, h, 1, 8, PHOTOMETRIC_MINISBLACK, 0, pattern8));
    CHECK(!write_tiff(p16, w, h, 1, 16, PHOTOMETRIC_MINISBLACK, 0, pattern16));
    CHECK(!write_tiff(pw, w, h, 1, 8, PHOTOMETRIC_MINISWHITE, 0, pattern8));
    CHECK(!write_tiff(prgb, w, h, 3, 8, PHOTOMETRIC_RGB, 0, pattern8));
    CHECK(!write_tiff(ptile, w, h, 1, 8, PHOTOMETRIC_MINISBLACK, 1, pattern8));
    bvox_image *img = NULL;
    CHECK_OK(bvox_section_read(p8, &img));
    CHECK(img->width == w && img->height == h && img->bits == 8 && img->channels == 1);
    for (int i = 0; i < w * h; i++) CHECK_EQ(img->pixels[i], pattern8((size_t)i));
    bvox_image_destroy(img);
    CHECK_OK(bvox_section_read(p16, &img));
    CHECK(img->bits == 16);
    for (int i = 0; i < w * h; i++) CHECK_EQ(img->pixels16[i], pattern16((size_t)i));
    bvox_image_destroy(img);
    CHECK_OK(bvox_section_read(pw, &img));
    for (int i = 0; i < w * h; i++) CHECK_EQ(img->pixels[i], 255 - pattern8((size_t)i));
    bvox_image_destroy(img);
    CHECK_OK(bvox_section_read(prgb, &img));
    CHECK_EQ(img->channels, 1);
    for (int i = 0; i < w * h; i++) {
        double l = 0.299 * pattern8(3 * (size_t)i) + 0.587 * pattern8(3 * (size_t)i + 1) +
                   0.114 * pattern8(3 * (size_t)i + 2);
        CHECK_EQ(img->pixels[i], (int)(l + 0.5));
    }
    bvox_image_destroy(img);
    /* tiles: libtiff's RGBA path, gray replicated into R = G = B */
    CHECK_OK(bvox_section_read(ptile, &img));
    for (int i = 0; i < w * h; i++) CHECK_EQ(img->pixels[i], pattern8((size_t)i));
    bvox_image_destroy(img);
    /* a truncated file: a clean error naming it */
    FILE *f = fopen(p8, "r+b");
    CHECK(f);
    CHECK(ftruncate(fileno(f), 40) == 0);
    fclose(f);
    CHECK(bvox_section_read(p8, &img) != BVOX_OK);
    CHECK(img == NULL);
    CHECK(strstr(bvox_errmsg(), "g8.tif"));
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
