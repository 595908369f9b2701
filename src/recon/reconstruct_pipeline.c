/*
 * reconstruct_pipeline.c — bvox_reconstruct: section images (or a contour
 * stack file) to an aligned binary model. Per section, in parallel over the
 * worker threads (bvox__parallel_for, batches so that progress can be
 * reported from the calling thread): read, gray, background, threshold,
 * median, markers (found and erased from the mask), specks, contours. Then
 * the markers' chain of similarity transforms to the reference section, the
 * contours moved onto it, the stack, and bvox_stack_to_volume (shape-based
 * interpolation to the output slice spacing).
 */
#include "section_internal.h"
#include "common/names.h"
#include "contour_internal.h"
#include "io/io.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define MAX_MARKERS 16


static const char *const step_names[BVOX_RECON_NSTEPS] = {
    "read", "background", "threshold", "smooth", "markers",
    "specks", "contours", "align", "volume", "total"};

const char *bvox_recon_step_name(bvox_recon_step step)
{
    return (unsigned)step < BVOX_RECON_NSTEPS ? step_names[step] : "unknown";
}

bvox_recon_opts bvox_recon_opts_default(void)
{
    bvox_recon_opts o;
    memset(&o, 0, sizeof o);
    o.estimate_background = 1;
    o.threshold = -1;
    o.dark = 1;
    o.smooth = 1;
    o.min_area = 16;
    o.markers = bvox_marker_opts_default();
    o.markers.count = 0;
    o.align = 1;
    o.reference = -1;
    o.interpolate = 1;
    return o;
}

void bvox_recon_report_destroy(bvox_recon_report *report)
{
    if (!report) return;
    for (int32_t i = 0; i < report->nsections; i++) {
        free(report->sections[i].name);
        free(report->sections[i].markers);
    }
    free(report->sections);
    free(report);
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = bvox__mem_alloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* ------------------------------------------------------ one section's work */

typedef struct sec_work {
    const char *path;           /* read from here, or */
    const bvox_image *image;    /* given */
    const char *name;
    int32_t width, height;      /* of the image read */
    bvox_contour *contours;
    int32_t ncontours;
    bvox_point2 markers[MAX_MARKERS + 1];
    int32_t nmarkers;
    double threshold;
    int64_t area;
    double ms[BVOX_RECON_NSTEPS];
    bvox_status st;
    char msg[512];
} sec_work;

typedef struct run_ctx {
    sec_work *w;
    int32_t first;              /* batch offset */
    const bvox_recon_opts *opts;
    const bvox_image *background;
    int find_markers;
} run_ctx;

static int is_image_name(const char *s)
{
    return bvox__ends_with_ci(s, ".png") || bvox__ends_with_ci(s, ".tif") ||
           bvox__ends_with_ci(s, ".tiff");
}

/* opts->save_steps: DIR/NAME.K_what.png (NAME without an image extension). */
static bvox_status save_step(const bvox_recon_opts *o, const sec_work *w, const char *what,
                             const bvox_image *img, const bvox_bitmap *bm)
{
    if (!o->save_steps) return BVOX_OK;
    char name[256], path[4096];
    snprintf(name, sizeof name, "%s", w->name);
    char *dot = strrchr(name, '.');
    if (dot && is_image_name(dot)) *dot = '\0';
    for (char *c = name; *c; c++)
        if (*c == '/' || *c == ' ') *c = '_';
    snprintf(path, sizeof path, "%s/%s.%s.png", o->save_steps, name, what);
    if (img) return bvox_image_write_png(img, path);
    bvox_image *tmp = NULL;
    bvox_status st = bvox_bitmap_to_image(bm, &tmp);
    if (!st) st = bvox_image_write_png(tmp, path);
    bvox_image_destroy(tmp);
    return st;
}

static bvox_status process(sec_work *w, const bvox_recon_opts *o, const bvox_image *background,
                           int find_markers)
{
    bvox_image *read = NULL, *gray = NULL, *bg = NULL, *flat = NULL;
    bvox_bitmap *mask = NULL, *smooth = NULL;
    bvox_status st = BVOX_OK;
    double t = now_ms(), t1;
#define LAP(step) (t1 = now_ms(), w->ms[step] += t1 - t, t = t1)
    const bvox_image *img = w->image;
    if (w->path) {
        if ((st = bvox_section_read(w->path, &read))) goto done;
        img = read;
    }
    w->width = img->width;
    w->height = img->height;
    if (img->channels != 1) {
        if ((st = bvox_section_gray(img, &gray))) goto done;
        img = gray;
    }
    LAP(BVOX_RECON_READ);
    /* dark objects: transmitted light, the illumination multiplies (divide);
     * bright objects: fluorescence or dark field, it adds (subtract) */
    bvox_status (*correct)(const bvox_image *, const bvox_image *, bvox_image **) =
        o->dark ? bvox_section_divide_background : bvox_section_subtract_background;
    if (background) {
        if ((st = correct(img, background, &flat))) goto done;
        img = flat;
    } else if (o->estimate_background) {
        if ((st = bvox_section_background_estimate(img, o->dark, &bg))) goto done;
        if ((st = correct(img, bg, &flat))) goto done;
        img = flat;
    }
    LAP(BVOX_RECON_BACKGROUND);
    if ((st = save_step(o, w, "1_flat", img, NULL))) goto done;
    w->threshold = o->threshold;
    if (w->threshold < 0 && (st = bvox_section_otsu(img, &w->threshold))) goto done;
    if ((st = bvox_section_threshold(img, w->threshold, o->dark, &mask))) goto done;
    LAP(BVOX_RECON_THRESHOLD);
    if ((st = save_step(o, w, "2_threshold", NULL, mask))) goto done;
    if ((st = bvox_bitmap_median(mask, o->smooth, &smooth))) goto done;
    LAP(BVOX_RECON_SMOOTH);
    if ((st = save_step(o, w, "3_smooth", NULL, smooth))) goto done;
    if (find_markers) {
        bvox_marker_opts mo = o->markers;
        if (mo.count > MAX_MARKERS) mo.count = MAX_MARKERS;
        if ((st = bvox_section_find_markers(img, &mo, w->markers, &w->nmarkers, smooth))) goto done;
    }
    LAP(BVOX_RECON_MARKERS);
    if ((st = bvox_bitmap_remove_specks(smooth, o->min_area, 1))) goto done;
    w->area = bvox_bitmap_count(smooth);
    LAP(BVOX_RECON_SPECKS);
    if ((st = save_step(o, w, "4_final", NULL, smooth))) goto done;
    t = now_ms(); /* the files are not a step */
    if ((st = bvox_bitmap_trace(smooth, &w->contours, &w->ncontours))) goto done;
    for (int32_t i = 0; i < w->ncontours; i++) {
        if (o->contour_smooth > 0 &&
            (st = bvox_contour_smooth(&w->contours[i], o->contour_smooth, 1)))
            goto done;
        if (o->simplify > 0 && (st = bvox_contour_simplify(&w->contours[i], o->simplify))) goto done;
    }
    LAP(BVOX_RECON_CONTOURS);
#undef LAP
done:
    bvox_image_destroy(read);
    bvox_image_destroy(gray);
    bvox_image_destroy(bg);
    bvox_image_destroy(flat);
    bvox_bitmap_destroy(mask);
    bvox_bitmap_destroy(smooth);
    return st;
}

static void run_range(void *ctx, int64_t begin, int64_t end)
{
    run_ctx *c = ctx;
    for (int64_t i = begin; i < end; i++) {
        sec_work *w = &c->w[c->first + i];
        w->st = process(w, c->opts, c->background, c->find_markers);
        if (w->st) snprintf(w->msg, sizeof w->msg, "section '%s': %s", w->name, bvox_errmsg());
    }
}

/* ------------------------------------------------------------- alignment */

static void fallback_message(bvox_recon_section_report *s, int32_t nmarkers, int32_t expected,
                             const char *neighbour)
{
    if (nmarkers < 2)
        snprintf(s->message, sizeof s->message,
                 "section '%s': %d marker%s found (%d expected): no alignment, it keeps the "
                 "transform of its neighbour '%s'",
                 s->name, (int)nmarkers, nmarkers == 1 ? "" : "s", (int)expected, neighbour);
    else
        snprintf(s->message, sizeof s->message,
                 "section '%s': its %d markers do not match those of '%s': no alignment, it "
                 "keeps that neighbour's transform",
                 s->name, (int)nmarkers, neighbour);
}

/* Align by the report's markers; fills align and message, counts fallbacks. */
static bvox_status align_report(bvox_recon_report *rep, const bvox_recon_opts *o)
{
    int32_t n = rep->nsections;
    const bvox_point2 **pts = bvox__mem_zalloc((size_t)n, sizeof *pts);
    int32_t *counts = bvox__mem_zalloc((size_t)n, sizeof *counts);
    bvox_align_result *res = bvox__mem_zalloc((size_t)n, sizeof *res);
    bvox_status st = BVOX_OK;
    if (!pts || !counts || !res) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    for (int32_t i = 0; i < n; i++) {
        pts[i] = rep->sections[i].markers;
        counts[i] = rep->sections[i].nmarkers > MAX_MARKERS ? MAX_MARKERS : rep->sections[i].nmarkers;
    }
    if ((st = bvox_markers_align(pts, counts, n, o->reference, &o->markers, res))) goto done;
    rep->aligned = 1;
    rep->reference = 0;
    int32_t expected = o->markers.count > 0 ? o->markers.count : 3;
    for (int32_t i = 0; i < n; i++) {
        bvox_recon_section_report *s = &rep->sections[i];
        s->align = res[i];
        if (res[i].neighbour < 0) rep->reference = i;
        if (res[i].fallback) {
            rep->fallbacks++;
            fallback_message(s, s->nmarkers, expected, rep->sections[res[i].neighbour].name);
        }
    }
done:
    free(pts);
    free(counts);
    free(res);
    return st;
}

/* Sections whose markers failed: registered by their contours onto the
 * adjacent section towards the reference, going outwards so that the
 * neighbour is final first (align_contours.c). A section too small to
 * register keeps the old fallback (its neighbour's transform). */
static bvox_status align_by_contours(bvox_recon_report *rep, const sec_work *w)
{
    int32_t n = rep->nsections, ref = rep->reference;
    for (int dir = -1; dir <= 1; dir += 2)
        for (int32_t k = ref + dir; k >= 0 && k < n; k += dir) {
            bvox_recon_section_report *s = &rep->sections[k];
            const bvox_recon_section_report *nb = &rep->sections[k - dir];
            if (!s->align.fallback) continue;
            s->align.neighbour = k - dir;
            s->align.transform = nb->align.transform;
            bvox_sim2 step;
            double rms;
            bvox_status st = bvox__contours_register(w[k].contours, w[k].ncontours,
                                                     w[k - dir].contours, w[k - dir].ncontours,
                                                     &step, &rms);
            if (st == BVOX_ENOMEM) return st;
            if (st) continue;
            s->align.step = step;
            s->align.residual = rms;
            s->align.by_contours = 1;
            s->align.transform = bvox_sim2_compose(&nb->align.transform, &step);
            size_t len = strlen(s->message);
            if (len + 80 < sizeof s->message && len > 0) {
                char *cut = strstr(s->message, ": no alignment");
                if (cut) len = (size_t)(cut - s->message);
                snprintf(s->message + len, sizeof s->message - len,
                         ": aligned by its contours to '%s' instead (residual %.2f px)", nb->name,
                         rms);
            }
        }
    bvox__clear_error();
    return BVOX_OK;
}

/* --marker-coords: the reference section's markers matched with the given
 * positions (any turn; the shift, turn and scale limits of the options
 * otherwise), and every section's transform carried into that frame. */
static bvox_status align_to_frame(bvox_recon_report *rep, const bvox_recon_opts *o)
{
    bvox_contour_stack *f = NULL;
    bvox_status st = bvox_stack_read(o->marker_coords, &f);
    if (st) return st;
    const bvox_recon_section_report *ref = &rep->sections[rep->reference];
    if (f->nsections < 1 || f->sections[0].nmarkers < 2) {
        bvox_stack_destroy(f);
        return bvox__fail(BVOX_EINVAL, "%s: needs at least 2 marker positions in its first section",
                          o->marker_coords);
    }
    bvox_marker_opts mo = o->markers;
    mo.max_angle = M_PI;
    bvox_sim2 g;
    int32_t matched = 0;
    double rms = 0;
    st = bvox_markers_match(ref->markers, ref->nmarkers > MAX_MARKERS ? MAX_MARKERS : ref->nmarkers,
                            f->sections[0].markers, f->sections[0].nmarkers, &mo, &g, NULL,
                            &matched, &rms);
    bvox_stack_destroy(f);
    if (st)
        return bvox__fail(st, "%s: the reference section '%s' has no 2 markers that match the "
                              "given positions",
                          o->marker_coords, ref->name);
    for (int32_t i = 0; i < rep->nsections; i++)
        rep->sections[i].align.transform = bvox_sim2_compose(&g, &rep->sections[i].align.transform);
    return BVOX_OK;
}

static bvox_xform2 to_xform(const bvox_sim2 *t)
{
    return bvox_xform2_similarity(t->angle, t->scale, t->tx, t->ty);
}

static bvox_status report_alloc(int32_t n, bvox_recon_report **out)
{
    *out = NULL;
    bvox_recon_report *r = bvox__mem_zalloc(1, sizeof *r);
    if (!r) return bvox__fail(BVOX_ENOMEM, "out of memory");
    r->sections = bvox__mem_zalloc((size_t)n, sizeof *r->sections);
    if (!r->sections) {
        free(r);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    r->nsections = n;
    r->reference = -1;
    for (int32_t i = 0; i < n; i++) {
        r->sections[i].align.transform = bvox_sim2_identity();
        r->sections[i].align.step = bvox_sim2_identity();
        r->sections[i].align.neighbour = -1;
        r->sections[i].threshold = NAN;
    }
    *out = r;
    return BVOX_OK;
}

static bvox_status set_markers(bvox_recon_section_report *s, const bvox_point2 *m, int32_t n)
{
    free(s->markers);
    s->markers = NULL;
    s->nmarkers = 0;
    if (n <= 0) return BVOX_OK;
    s->markers = bvox__mem_alloc((size_t)n * sizeof *m);
    if (!s->markers) return bvox__fail(BVOX_ENOMEM, "out of memory");
    memcpy(s->markers, m, (size_t)n * sizeof *m);
    s->nmarkers = n;
    return BVOX_OK;
}

/* The options' step callback, then the thread's progress callback
 * (bvox_set_progress), which may cancel: the sections are the first 70 %,
 * the alignment up to 75 %, the volume the rest. */
static bvox_status progress(const bvox_recon_opts *o, bvox_recon_step step, int32_t done,
                            int32_t total)
{
    if (o->progress) o->progress(o->progress_ctx, step, done, total);
    double f = total > 0 ? (double)done / total : 1;
    return bvox__progress(step == BVOX_RECON_CONTOURS ? 0.7 * f
                          : step == BVOX_RECON_ALIGN  ? 0.75
                                                      : 1);
}

/* ------------------------------------------------------- images -> model */

/* The end of both paths (images, contour file): unless st already failed,
 * the aligned stack to a volume (when asked for) and the total time; then
 * the outputs handed over, or everything freed on failure. */
static bvox_status finish(const bvox_recon_opts *o, bvox_status st, double t_start,
                          bvox_contour_stack *stack, bvox_recon_report *rep, bvox_volume **volume,
                          bvox_contour_stack **stack_out, bvox_recon_report **report_out)
{
    bvox_volume *vol = NULL;
    if (!st && volume) {
        double t = now_ms();
        bvox_stack_volume_opts vo = bvox_stack_volume_opts_default();
        vo.z_spacing = o->z_spacing;
        vo.interpolate = o->interpolate;
        bvox__progress_scope ps;
        bvox__progress_sub(&ps, 0.75, 1, "volume");
        st = bvox_stack_to_volume(stack, &vo, &vol);
        bvox__progress_restore(&ps);
        if (!st) {
            rep->ms[BVOX_RECON_VOLUME] = now_ms() - t;
            st = progress(o, BVOX_RECON_VOLUME, stack->nsections, stack->nsections);
        }
    }
    if (st) {
        bvox_recon_report_destroy(rep);
        bvox_stack_destroy(stack);
        bvox_volume_destroy(vol);
        return st;
    }
    rep->ms[BVOX_RECON_TOTAL] = now_ms() - t_start;
    if (volume) *volume = vol;
    if (stack_out) *stack_out = stack;
    else bvox_stack_destroy(stack);
    if (report_out) *report_out = rep;
    else bvox_recon_report_destroy(rep);
    return BVOX_OK;
}

/* --markers auto (markers.count BVOX_MARKERS_AUTO): up to 9 sections spread
 * over the stack go through the same steps with every marker candidate
 * kept; the count is the median of what they found (one section that lost a
 * marker or has a spurious blob does not move it). Under 2: no markers, and
 * a warning (the sections are not aligned). */
static bvox_status auto_marker_count(const sec_work *w, int32_t n, bvox_recon_opts *o,
                                     const bvox_image *background)
{
    int32_t found[9], samples = n < 9 ? n : 9;
    bvox_recon_opts probe = *o;
    probe.markers.count = MAX_MARKERS;
    probe.save_steps = NULL;
    for (int32_t s = 0; s < samples; s++) {
        int32_t i = samples == 1 ? 0 : (int32_t)((int64_t)s * (n - 1) / (samples - 1));
        sec_work tmp;
        memset(&tmp, 0, sizeof tmp);
        tmp.path = w[i].path;
        tmp.image = w[i].image;
        tmp.name = w[i].name;
        bvox_status st = process(&tmp, &probe, background, 1);
        bvox_contours_free(tmp.contours, tmp.ncontours);
        if (st) return st;
        found[s] = tmp.nmarkers > MAX_MARKERS ? MAX_MARKERS : tmp.nmarkers;
    }
    for (int32_t a = 1; a < samples; a++) /* insertion sort: at most 9 */
        for (int32_t b = a; b > 0 && found[b - 1] > found[b]; b--) {
            int32_t t = found[b];
            found[b] = found[b - 1];
            found[b - 1] = t;
        }
    int32_t count = found[samples / 2];
    if (count < 2) {
        bvox__warn("--markers auto: fewer than 2 markers in the sampled sections: not aligned");
        o->markers.count = 0;
    } else {
        bvox__warn("--markers auto: %d markers per section (the median of %d sections)",
                   (int)count, (int)samples);
        o->markers.count = count;
    }
    return BVOX_OK;
}

static bvox_status run_images(sec_work *w, int32_t n, const bvox_recon_opts *opts,
                              const bvox_image *background, bvox_volume **volume,
                              bvox_contour_stack **stack_out, bvox_recon_report **report_out)
{
    double t_start = now_ms();
    bvox_recon_opts auto_opts = *opts;
    const bvox_recon_opts *o = opts;
    if (opts->markers.count == BVOX_MARKERS_AUTO && !opts->markers_file) {
        bvox_status st = auto_marker_count(w, n, &auto_opts, background);
        if (st) return st;
        o = &auto_opts;
    }
    bvox_status st = BVOX_OK;
    bvox_recon_report *rep = NULL;
    bvox_contour_stack *stack = NULL;
    bvox_contour_stack *mfile = NULL;
    if (o->markers_file && (st = bvox_stack_read(o->markers_file, &mfile))) return st;
    if (mfile && mfile->nsections != n) {
        st = bvox__fail(BVOX_EINVAL, "%s: %d sections of markers for %d section images",
                        o->markers_file, (int)mfile->nsections, (int)n);
        bvox_stack_destroy(mfile);
        return st;
    }
    int find_markers = !mfile && o->markers.count > 0;
    /* per-section work in batches (progress between them) */
    int32_t batch = bvox__parallelism() * 2;
    if (batch < 1) batch = 1;
    double t_sections = now_ms();
    for (int32_t first = 0; first < n; first += batch) {
        int32_t m = n - first < batch ? n - first : batch;
        run_ctx c = {w, first, o, background, find_markers};
        bvox__parallel_for(m, 1, run_range, &c);
        for (int32_t i = first; i < first + m; i++)
            if (w[i].st) {
                st = bvox__fail(w[i].st, "%s", w[i].msg);
                goto done;
            }
        if ((st = progress(o, BVOX_RECON_CONTOURS, first + m, n))) goto done;
    }
    double wall = now_ms() - t_sections;
    for (int32_t i = 1; i < n; i++)
        if (w[i].width != w[0].width || w[i].height != w[0].height) {
            st = bvox__fail(BVOX_EINVAL, "section '%s' is %d x %d pixels but '%s' is %d x %d: all "
                            "sections must have the same size", w[i].name, (int)w[i].width,
                            (int)w[i].height, w[0].name, (int)w[0].width, (int)w[0].height);
            goto done;
        }
    if ((st = report_alloc(n, &rep))) goto done;
    rep->width = w[0].width;
    rep->height = w[0].height;
    double cpu = 0;
    for (int32_t i = 0; i < n; i++)
        for (int s = 0; s <= BVOX_RECON_CONTOURS; s++) cpu += w[i].ms[s];
    for (int s = 0; s <= BVOX_RECON_CONTOURS; s++) {
        double sum = 0;
        for (int32_t i = 0; i < n; i++) sum += w[i].ms[s];
        rep->ms[s] = cpu > 0 ? wall * sum / cpu : 0;
    }
    for (int32_t i = 0; i < n; i++) {
        bvox_recon_section_report *s = &rep->sections[i];
        if (!(s->name = dup_str(w[i].name))) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            goto done;
        }
        s->threshold = w[i].threshold;
        s->area = w[i].area;
        s->ncontours = w[i].ncontours;
        if (mfile) st = set_markers(s, mfile->sections[i].markers, mfile->sections[i].nmarkers);
        else st = set_markers(s, w[i].markers, w[i].nmarkers);
        if (st) goto done;
    }
    /* alignment */
    double t0 = now_ms();
    if (o->align && (find_markers || mfile) && (st = align_report(rep, o))) goto done;
    if (rep->aligned && rep->fallbacks && (st = align_by_contours(rep, w))) goto done;
    if (rep->aligned && o->marker_coords && (st = align_to_frame(rep, o))) goto done;
    rep->ms[BVOX_RECON_ALIGN] = now_ms() - t0;
    if ((st = progress(o, BVOX_RECON_ALIGN, n, n))) goto done;
    /* the stack */
    t0 = now_ms();
    if ((st = bvox_stack_create(&stack))) goto done;
    stack->pixel = o->pixel > 0 ? o->pixel : 1;
    stack->spacing = o->spacing > 0 ? o->spacing : 1;
    memcpy(stack->unit, o->unit, sizeof stack->unit);
    stack->unit[sizeof stack->unit - 1] = '\0';
    stack->width = w[0].width;
    stack->height = w[0].height;
    for (int32_t i = 0; i < n; i++) {
        bvox_section *sec = NULL;
        if ((st = bvox_stack_add_section(stack, i * stack->spacing, w[i].name, &sec))) goto done;
        for (int32_t k = 0; k < w[i].ncontours; k++) {
            const bvox_contour *c = &w[i].contours[k];
            if ((st = bvox_section_add_contour(sec, c->points, c->npoints, c->hole, c->parent)))
                goto done;
        }
        for (int32_t k = 0; k < rep->sections[i].nmarkers; k++)
            if ((st = bvox_section_add_marker(sec, rep->sections[i].markers[k]))) goto done;
        if (rep->aligned) {
            bvox_xform2 x = to_xform(&rep->sections[i].align.transform);
            bvox_section_transform(sec, &x);
        }
    }
    rep->ms[BVOX_RECON_ALIGN] += now_ms() - t0;
done:
    bvox_stack_destroy(mfile);
    return finish(o, st, t_start, stack, rep, volume, stack_out, report_out);
}

static bvox_status check_outputs(bvox_volume **volume, bvox_contour_stack **stack,
                                 bvox_recon_report **report)
{
    if (volume) *volume = NULL;
    if (stack) *stack = NULL;
    if (report) *report = NULL;
    if (!volume && !stack && !report)
        return bvox__fail(BVOX_EINVAL, "reconstruct: no output asked for");
    return BVOX_OK;
}

static void free_work(sec_work *w, int32_t n)
{
    if (!w) return;
    for (int32_t i = 0; i < n; i++) bvox_contours_free(w[i].contours, w[i].ncontours);
    free(w);
}

static bvox_status reconstruct_images(const bvox_image *const *images,
                                      const char *const *names, int32_t n,
                                      const bvox_recon_opts *opts, bvox_volume **volume,
                                      bvox_contour_stack **stack, bvox_recon_report **report);

bvox_status bvox_reconstruct_images(const bvox_image *const *images, const char *const *names,
                                    int32_t n, const bvox_recon_opts *opts, bvox_volume **volume,
                                    bvox_contour_stack **stack, bvox_recon_report **report)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "reconstruct");
    return bvox__progress_end(&ps,
                              reconstruct_images(images, names, n, opts, volume, stack, report));
}

static bvox_status reconstruct_images(const bvox_image *const *images,
                                      const char *const *names, int32_t n,
                                      const bvox_recon_opts *opts, bvox_volume **volume,
                                      bvox_contour_stack **stack, bvox_recon_report **report)
{
    bvox__clear_error();
    bvox_status st = check_outputs(volume, stack, report);
    if (st) return st;
    bvox_recon_opts o = opts ? *opts : bvox_recon_opts_default();
    if (n < 1 || !images) return bvox__fail(BVOX_EINVAL, "reconstruct: no sections");
    sec_work *w = bvox__mem_zalloc((size_t)n, sizeof *w);
    char (*auto_names)[32] = bvox__mem_zalloc((size_t)n, sizeof *auto_names);
    if (!w || !auto_names) {
        free(w);
        free(auto_names);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    for (int32_t i = 0; i < n; i++) {
        snprintf(auto_names[i], sizeof auto_names[i], "section %d", (int)(i + 1));
        w[i].image = images[i];
        w[i].name = names && names[i] ? names[i] : auto_names[i];
        if (!images[i]) {
            st = bvox__fail(BVOX_EINVAL, "reconstruct: %s is missing", w[i].name);
            break;
        }
    }
    if (!st) st = run_images(w, n, &o, o.background_image, volume, stack, report);
    free_work(w, n);
    free(auto_names);
    if (!st) {
        if (volume) BVOX_CHECK_VOLUME(*volume);
        if (stack) BVOX_CHECK_STACK(*stack);
    }
    return st;
}

/* ------------------------------------------------- contour stacks -> model */

bvox_status bvox_stack_align(bvox_contour_stack *stack, const bvox_recon_opts *opts,
                             bvox_recon_report **report)
{
    bvox__clear_error();
    if (report) *report = NULL;
    bvox_recon_opts o = opts ? *opts : bvox_recon_opts_default();
    if (!stack || stack->nsections < 1) return bvox__fail(BVOX_EINVAL, "align: no sections");
    bvox_recon_report *rep = NULL;
    bvox_status st = report_alloc(stack->nsections, &rep);
    if (st) return st;
    double t0 = now_ms();
    for (int32_t i = 0; i < stack->nsections && !st; i++) {
        bvox_recon_section_report *s = &rep->sections[i];
        char buf[32];
        snprintf(buf, sizeof buf, "section %d", (int)(i + 1));
        s->name = dup_str(stack->sections[i].name ? stack->sections[i].name : buf);
        if (!s->name) st = bvox__fail(BVOX_ENOMEM, "out of memory");
        else st = set_markers(s, stack->sections[i].markers, stack->sections[i].nmarkers);
        s->ncontours = stack->sections[i].ncontours;
    }
    if (!st) st = align_report(rep, &o);
    if (!st)
        for (int32_t i = 0; i < stack->nsections; i++) {
            bvox_xform2 x = to_xform(&rep->sections[i].align.transform);
            bvox_section_transform(&stack->sections[i], &x);
        }
    rep->ms[BVOX_RECON_ALIGN] = now_ms() - t0;
    if (st || !report) bvox_recon_report_destroy(rep);
    else *report = rep;
    return st;
}

/* Keeps the section images of a folder; notes whether it holds .svg files. */
static bool keep_image(const char *dir, const char *name, void *svg)
{
    (void)dir;
    if (bvox__ends_with_ci(name, ".svg")) *(int *)svg = 1;
    return is_image_name(name);
}

/* The image files of dir in natural order (*out: malloc'd paths); *svg set
 * when the folder holds .svg files instead. */
static bvox_status list_dir(const char *dir, char ***out, int32_t *n, int *svg)
{
    *svg = 0;
    size_t m = 0;
    bvox_status st = bvox__list_dir(dir, keep_image, svg, INT32_MAX, "section images", out, &m);
    if (st == BVOX_EIO) return bvox__fail(BVOX_ENOTFOUND, "%s: cannot open the folder", dir);
    *n = (int32_t)m;
    return st;
}

/* The options' pixel, spacing and unit override the file's. Sections whose
 * file gave no z sit at index x spacing, so a spacing given now re-places
 * them (three SVGs with --spacing 5 are 5 apart, not 1). What neither the file
 * nor the options said is a default the user must hear about: one warning. */
static void apply_scale(const char *path, const bvox_recon_opts *o, bvox_contour_stack *stack)
{
    if (o->pixel > 0) stack->pixel = o->pixel;
    if (o->spacing > 0) {
        stack->spacing = o->spacing;
        for (int32_t i = 0; i < stack->nsections; i++)
            if (stack->sections[i].z_from_index) stack->sections[i].z = i * o->spacing;
    }
    if (o->unit[0]) {
        memcpy(stack->unit, o->unit, sizeof stack->unit);
        stack->unit[sizeof stack->unit - 1] = '\0';
    }
    int implicit_z = 0;
    for (int32_t i = 0; i < stack->nsections; i++) implicit_z |= stack->sections[i].z_from_index;
    char missing[96] = "";
    if (!(o->pixel > 0) && !(stack->given & BVOX_STACK_GIVEN_PIXEL))
        strcat(missing, ", pixel size 1 (--pixel)");
    if (stack->nsections > 1 && implicit_z && !(o->spacing > 0) &&
        !(stack->given & BVOX_STACK_GIVEN_SPACING))
        strcat(missing, ", section spacing 1 (--spacing)");
    if (!o->unit[0] && !stack->unit[0]) strcat(missing, ", no unit (--unit)");
    if (missing[0])
        bvox__warn("%s: not stated in the file or the options, assumed:%s", path, missing + 1);
}

static bvox_status run_stack(const char *path, const bvox_recon_opts *o, bvox_volume **volume,
                             bvox_contour_stack **stack_out, bvox_recon_report **report_out)
{
    double t0 = now_ms();
    bvox_contour_stack *stack = NULL;
    bvox_recon_report *rep = NULL;
    if (o->markers_file)
        return bvox__fail(BVOX_EINVAL, "%s: a markers file goes with section images; a contour "
                                       "file carries its own markers", path);
    bvox_stack_read_opts ro = {o->svg_select, o->object};
    bvox_status st = bvox_stack_read_with(path, &ro, &stack);
    if (st) return st;
    /* contours crossing each other are a tracing mistake: refused, naming the
     * section; one crossing itself (jitter) is kept and warned about unless
     * strict (contour_repair.c) */
    if ((st = bvox__stack_check_crossings(path, stack, o->strict))) goto done;
    double t_read = now_ms() - t0;
    apply_scale(path, o, stack);
    int any_markers = 0;
    for (int32_t i = 0; i < stack->nsections; i++) any_markers |= stack->sections[i].nmarkers > 0;
    if (o->align && any_markers) {
        if ((st = bvox_stack_align(stack, o, &rep))) goto done;
    } else {
        if ((st = report_alloc(stack->nsections, &rep))) goto done;
        for (int32_t i = 0; i < stack->nsections && !st; i++) {
            char buf[32];
            snprintf(buf, sizeof buf, "section %d", (int)(i + 1));
            bvox_recon_section_report *s = &rep->sections[i];
            s->name = dup_str(stack->sections[i].name ? stack->sections[i].name : buf);
            if (!s->name) st = bvox__fail(BVOX_ENOMEM, "out of memory");
            else st = set_markers(s, stack->sections[i].markers, stack->sections[i].nmarkers);
            s->ncontours = stack->sections[i].ncontours;
        }
        if (st) goto done;
    }
    rep->ms[BVOX_RECON_READ] = t_read;
    rep->width = stack->width;
    rep->height = stack->height;
    st = progress(o, BVOX_RECON_ALIGN, stack->nsections, stack->nsections);
done:
    return finish(o, st, t0, stack, rep, volume, stack_out, report_out);
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static int same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

/* blank.png, flatfield.tif, background_01.png, Flat-Field.TIF, empty.png */
static int looks_blank(const char *name)
{
    static const char *const words[] = {"blank", "flat", "background", "empty", "dark"};
    char low[64];
    size_t n = strlen(name);
    if (n >= sizeof low) return 0;
    for (size_t i = 0; i <= n; i++) low[i] = (char)tolower((unsigned char)name[i]);
    for (size_t i = 0; i < sizeof words / sizeof words[0]; i++)
        if (!strncmp(low, words[i], strlen(words[i]))) return 1;
    return 0;
}

/* Section images carry no spacing between them, and bvox does not read a
 * pixel size from them: what the options do not give is assumed and said. */
static void warn_image_scale(const bvox_recon_opts *o)
{
    char missing[96] = "";
    if (!(o->pixel > 0)) strcat(missing, ", pixel size 1 (--pixel)");
    if (!(o->spacing > 0)) strcat(missing, ", section spacing 1 (--spacing)");
    if (!o->unit[0]) strcat(missing, ", no unit (--unit)");
    if (missing[0]) bvox__warn("section images: not given, assumed:%s", missing + 1);
}

static bvox_status reconstruct(const char *const *inputs, int32_t n,
                               const bvox_recon_opts *opts, bvox_volume **volume,
                               bvox_contour_stack **stack, bvox_recon_report **report);

bvox_status bvox_reconstruct(const char *const *inputs, int32_t n, const bvox_recon_opts *opts,
                             bvox_volume **volume, bvox_contour_stack **stack,
                             bvox_recon_report **report)
{
    bvox__progress_scope ps;
    bvox__progress_begin(&ps, "reconstruct");
    return bvox__progress_end(&ps, reconstruct(inputs, n, opts, volume, stack, report));
}

static bvox_status reconstruct(const char *const *inputs, int32_t n,
                               const bvox_recon_opts *opts, bvox_volume **volume,
                               bvox_contour_stack **stack, bvox_recon_report **report)
{
    bvox__clear_error();
    bvox_status st = check_outputs(volume, stack, report);
    if (st) return st;
    bvox_recon_opts o = opts ? *opts : bvox_recon_opts_default();
    if (n < 1 || !inputs) return bvox__fail(BVOX_EINVAL, "reconstruct: no sections given");
    char **listed = NULL;
    int32_t nlisted = 0;
    const char *const *paths = inputs;
    struct stat sb;
    if (n == 1 && stat(inputs[0], &sb) == 0 && S_ISDIR(sb.st_mode)) {
        int svg = 0;
        if ((st = list_dir(inputs[0], &listed, &nlisted, &svg))) return st;
        if (nlisted == 0) {
            free(listed);
            if (svg) return run_stack(inputs[0], &o, volume, stack, report);
            return bvox__fail(BVOX_ENOTFOUND, "%s: the folder holds no section images (.png, "
                                              ".tif) and no contours (.svg)", inputs[0]);
        }
        paths = (const char *const *)listed;
        n = nlisted;
    } else if (n == 1 && !is_image_name(inputs[0])) {
        return run_stack(inputs[0], &o, volume, stack, report);
    } else {
        for (int32_t i = 0; i < n; i++)
            if (!is_image_name(inputs[i]))
                return bvox__fail(BVOX_EINVAL, "%s: not a section image (.png, .tif); a contour "
                                               "file must be the only input", inputs[i]);
    }
    if (o.object && *o.object) {
        for (int32_t i = 0; i < nlisted; i++) free(listed[i]);
        free(listed);
        return bvox__fail(BVOX_EINVAL, "reconstruct: --object '%s' selects the traces of a "
                                       "PyReconstruct .jser series, not of section images",
                          o.object);
    }
    bvox_image *background = NULL;
    sec_work *w = bvox__mem_zalloc((size_t)n, sizeof *w);
    if (!w) {
        st = bvox__fail(BVOX_ENOMEM, "out of memory");
        goto done;
    }
    int32_t nsec = 0;
    for (int32_t i = 0; i < n; i++) {
        /* the blank given as --background is not also a section */
        if (o.background && same_file(paths[i], o.background)) continue;
        if (!o.background && !o.background_image && looks_blank(base_name(paths[i])))
            bvox__warn("%s: named like a blank (flat-field) image, but used as a section; give "
                       "it as --background to correct the light with it",
                       paths[i]);
        w[nsec].path = paths[i];
        w[nsec].name = base_name(paths[i]);
        nsec++;
    }
    n = nsec;
    if (n < 1) {
        st = bvox__fail(BVOX_EINVAL, "reconstruct: no sections besides the background image");
        goto done;
    }
    warn_image_scale(&o);
    if (!o.background_image && o.background) {
        if ((st = bvox_section_read(o.background, &background))) goto done;
        o.background_image = background;
    }
    st = run_images(w, n, &o, o.background_image, volume, stack, report);
done:
    free_work(w, n);
    bvox_image_destroy(background);
    bvox__free_paths(listed, (size_t)nlisted);
    return st;
}
