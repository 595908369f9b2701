/* test_reconstruct.c — the known answer of the reconstruction: a specimen of
 * known shape (specimen_sections.h) cut into 70 noisy, unevenly lit
 * sections, each moved by a random rigid transform, one with a marker
 * missing and one with a spurious blob, reconstructed from a folder of PNG
 * files; the model must match the truth (Dice >= 0.95), the recovered
 * transforms the ones applied, and without alignment the Dice must drop.
 * Bad input: sections of different sizes, an empty folder, a section
 * without markers. */
#include "harness.h"
#include "internal.h"
#include "specimen_sections.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

enum { NSEC = 70, SIZE = 240 };
#define SPACING 2.0
#define MISSING_AT 10
#define SPURIOUS_AT 50

static const char *write_sections(const specimen *sp, const char *dir, int missing_all_at)
{
    static char path[1024];
    mkdir(dir, 0755);
    for (int k = 0; k < sp->n; k++) {
        bvox_image *img = NULL;
        int missing = k == MISSING_AT ? 1 : -1;
        if (spec_render(sp, k, missing, k == SPURIOUS_AT, &img)) return NULL;
        if (k == missing_all_at) /* no marker at all: paint them over with background */
            for (int i = 0; i < sp->size * sp->size; i++)
                if (img->pixels[i] < 50) img->pixels[i] = 175;
        snprintf(path, sizeof path, "%s/s%d.png", dir, k + 1); /* natural order matters */
        bvox_status st = bvox_image_write_png(img, path);
        bvox_image_destroy(img);
        if (st) return NULL;
    }
    return dir;
}

typedef struct prog {
    int calls, last_done, decreasing;
} prog;

static void on_progress(void *ctx, bvox_recon_step step, int32_t done, int32_t total)
{
    prog *p = ctx;
    if (step == BVOX_RECON_CONTOURS) {
        if (done < p->last_done || done > total) p->decreasing = 1;
        p->last_done = done;
    }
    p->calls++;
}

TEST(images_known_answer)
{
    specimen sp;
    CHECK(spec_init(&sp, SIZE, NSEC, SPACING, 12345) == 0);
    const char *dir = write_sections(&sp, harness_path("sections"), -1);
    CHECK(dir);
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    o.spacing = SPACING;
    snprintf(o.unit, sizeof o.unit, "um");
    prog p = {0, 0, 0};
    o.progress = on_progress;
    o.progress_ctx = &p;
    bvox_volume *vol = NULL, *truth = NULL;
    bvox_recon_report *rep = NULL;
    const char *in[1] = {dir};
    CHECK_OK(bvox_reconstruct(in, 1, &o, &vol, NULL, &rep));
    CHECK_OK(bvox_volume_check(vol));
    CHECK(p.calls > 2 && !p.decreasing && p.last_done == NSEC);
    bvox_dims d = bvox_volume_dims(vol);
    CHECK_EQ(d.nx, SIZE);
    CHECK_EQ(d.ny, SIZE);
    CHECK_EQ(d.nz, (int)(NSEC * SPACING)); /* isotropic: one slice per pixel */
    const bvox_geometry *g = bvox_volume_geometry(vol);
    CHECK_NEAR(g->spacing[2], 1, 1e-12);
    CHECK(!strcmp(g->unit, "um"));
    CHECK_OK(spec_truth(&sp, vol, &truth));
    double dice = spec_dice(vol, truth);
    fprintf(stderr, "dice aligned %.4f\n", dice);
    CHECK(dice >= 0.95);
    /* the report: natural order, markers, transforms */
    CHECK_EQ(rep->nsections, NSEC);
    CHECK_EQ(rep->reference, NSEC / 2);
    CHECK_EQ(rep->fallbacks, 0);
    CHECK(!strcmp(rep->sections[9].name, "s10.png"));
    CHECK_EQ(rep->sections[MISSING_AT].nmarkers, 2);
    CHECK_EQ(rep->sections[MISSING_AT].align.matched, 2);
    CHECK_EQ(rep->sections[SPURIOUS_AT].nmarkers, 4);
    CHECK_EQ(rep->sections[SPURIOUS_AT].align.matched, 3);
    double worst_angle = 0, worst_shift = 0;
    for (int k = 0; k < NSEC; k++) {
        const bvox_recon_section_report *s = &rep->sections[k];
        CHECK(s->align.fallback == 0);
        if (k != MISSING_AT && k != SPURIOUS_AT) CHECK_EQ(s->nmarkers, 3);
        /* the true transform onto the reference: moves[k]^-1 (the reference is unmoved) */
        bvox_sim2 want = bvox_sim2_inverse(&sp.moves[k]);
        worst_angle = fmax(worst_angle, fabs(s->align.transform.angle - want.angle));
        /* compare where the image centre goes */
        bvox_point2 c = {SIZE / 2.0, SIZE / 2.0};
        bvox_point2 a = bvox_sim2_apply(&s->align.transform, c), b = bvox_sim2_apply(&want, c);
        worst_shift = fmax(worst_shift, hypot(a.x - b.x, a.y - b.y));
        CHECK(s->threshold > 60 && s->threshold < 160);
        CHECK(s->align.residual < 1.0);
    }
    fprintf(stderr, "worst angle error %.4f deg, centre error %.3f px\n", worst_angle * 180 / M_PI,
            worst_shift);
    CHECK(worst_angle < 0.5 * M_PI / 180);
    CHECK(worst_shift < 1.0);
    for (int s = 0; s < BVOX_RECON_NSTEPS; s++) CHECK(rep->ms[s] >= 0);
    CHECK(rep->ms[BVOX_RECON_TOTAL] >= rep->ms[BVOX_RECON_VOLUME]);
    bvox_recon_report_destroy(rep);
    bvox_volume_destroy(vol);
    bvox_volume_destroy(truth);
    spec_free(&sp);
    return 0;
}

TEST(no_align_is_clearly_worse)
{
    specimen sp;
    CHECK(spec_init(&sp, SIZE, NSEC, SPACING, 777) == 0);
    bvox_image *imgs[NSEC];
    for (int k = 0; k < NSEC; k++) CHECK_OK(spec_render(&sp, k, -1, 0, &imgs[k]));
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    o.spacing = SPACING;
    bvox_volume *aligned = NULL, *raw = NULL, *truth = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, NSEC, &o, &aligned,
                                     NULL, NULL));
    o.align = 0;
    bvox_recon_report *rep = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, NSEC, &o, &raw, NULL,
                                     &rep));
    CHECK_EQ(rep->aligned, 0);
    CHECK(!strcmp(rep->sections[0].name, "section 1"));
    CHECK_OK(spec_truth(&sp, aligned, &truth));
    double da = spec_dice(aligned, truth), dr = spec_dice(raw, truth);
    fprintf(stderr, "dice aligned %.4f, not aligned %.4f\n", da, dr);
    CHECK(da >= 0.95);
    CHECK(dr < 0.85);
    CHECK(da - dr > 0.1);
    /* smoothed and simplified contours: far fewer points, the same model */
    o.align = 1;
    bvox_contour_stack *exact = NULL, *simple = NULL;
    bvox_volume *sv = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, NSEC, &o, NULL, &exact,
                                     NULL));
    o.contour_smooth = 2;
    o.simplify = 0.5;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, NSEC, &o, &sv, &simple,
                                     NULL));
    int64_t pe = 0, ps = 0;
    for (int k = 0; k < NSEC; k++) {
        CHECK_EQ(exact->sections[k].ncontours, simple->sections[k].ncontours);
        for (int i = 0; i < exact->sections[k].ncontours; i++) {
            pe += exact->sections[k].contours[i].npoints;
            ps += simple->sections[k].contours[i].npoints;
        }
    }
    double ds = spec_dice(sv, truth);
    fprintf(stderr, "smoothed + simplified: %lld points instead of %lld, dice %.4f\n",
            (long long)ps, (long long)pe, ds);
    CHECK(ps < pe / 2);
    CHECK(ds >= 0.95);
    bvox_stack_destroy(exact);
    bvox_stack_destroy(simple);
    bvox_volume_destroy(sv);
    for (int k = 0; k < NSEC; k++) bvox_image_destroy(imgs[k]);
    bvox_recon_report_destroy(rep);
    bvox_volume_destroy(aligned);
    bvox_volume_destroy(raw);
    bvox_volume_destroy(truth);
    spec_free(&sp);
    return 0;
}

TEST(section_without_markers_falls_back)
{
    specimen sp;
    CHECK(spec_init(&sp, 160, 12, SPACING, 99) == 0);
    bvox_image *imgs[12];
    const char *names[12];
    char buf[12][16];
    for (int k = 0; k < 12; k++) {
        CHECK_OK(spec_render(&sp, k, -1, 0, &imgs[k]));
        snprintf(buf[k], sizeof buf[k], "cut%02d", k);
        names[k] = buf[k];
    }
    for (int i = 0; i < 160 * 160; i++) /* section 3: markers painted over */
        if (imgs[3]->pixels[i] < 50) imgs[3]->pixels[i] = 175;
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    bvox_volume *vol = NULL;
    bvox_recon_report *rep = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, names, 12, &o, &vol, NULL,
                                     &rep));
    CHECK_EQ(rep->fallbacks, 1);
    CHECK(rep->sections[3].nmarkers < 2); /* at most a shape's dark tip */
    CHECK_EQ(rep->sections[3].align.fallback, 1);
    CHECK_EQ(rep->sections[3].align.neighbour, 4);
    CHECK(strstr(rep->sections[3].message, "cut03"));
    CHECK(strstr(rep->sections[3].message, "cut04"));
    /* it is aligned by its contours onto section 4 (no longer given 4's
     * transform, which is wrong when sections move independently); section
     * 2 skips it and matches 4 by markers */
    CHECK_EQ(rep->sections[3].align.by_contours, 1);
    CHECK(strstr(rep->sections[3].message, "aligned by its contours"));
    bvox_sim2 want3 = bvox_sim2_inverse(&sp.moves[3]);
    CHECK_NEAR(rep->sections[3].align.transform.angle, want3.angle, 0.5 * M_PI / 180);
    CHECK_EQ(rep->sections[2].align.neighbour, 4);
    CHECK_EQ(rep->sections[2].align.fallback, 0);
    for (int k = 0; k < 12; k++) bvox_image_destroy(imgs[k]);
    bvox_recon_report_destroy(rep);
    bvox_volume_destroy(vol);
    spec_free(&sp);
    return 0;
}

TEST(bad_input)
{
    /* sections of different sizes: named */
    bvox_image *a = NULL, *b = NULL;
    CHECK_OK(bvox_image_create(50, 40, 1, 8, &a));
    CHECK_OK(bvox_image_create(50, 41, 1, 8, &b));
    memset(a->pixels, 200, 50 * 40);
    memset(b->pixels, 200, 50 * 41);
    const bvox_image *imgs[2] = {a, b};
    const char *names[2] = {"first.png", "second.png"};
    bvox_volume *vol = NULL;
    CHECK_STATUS(bvox_reconstruct_images(imgs, names, 2, NULL, &vol, NULL, NULL), BVOX_EINVAL);
    CHECK(vol == NULL);
    CHECK(strstr(bvox_errmsg(), "second.png"));
    CHECK(strstr(bvox_errmsg(), "50 x 41"));
    /* files: an empty folder, a missing file */
    const char *dir = harness_path("empty");
    mkdir(dir, 0755);
    const char *in[1] = {dir};
    CHECK_STATUS(bvox_reconstruct(in, 1, NULL, &vol, NULL, NULL), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "empty"));
    CHECK_OK(bvox_image_write_png(a, harness_path("a.png")));
    const char *two[2] = {harness_path("a.png"), harness_path("nothere.png")};
    CHECK(bvox_reconstruct(two, 2, NULL, &vol, NULL, NULL) != BVOX_OK);
    CHECK(strstr(bvox_errmsg(), "nothere.png"));
    CHECK(vol == NULL);
    /* a background of another size: named */
    bvox_recon_opts o = bvox_recon_opts_default();
    o.background_image = b;
    const bvox_image *one[1] = {a};
    CHECK_STATUS(bvox_reconstruct_images(one, names, 1, &o, &vol, NULL, NULL), BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "first.png"));
    CHECK_STATUS(bvox_reconstruct_images(one, names, 1, NULL, NULL, NULL, NULL), BVOX_EINVAL);
    bvox_image_destroy(a);
    bvox_image_destroy(b);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(allocation_failures_are_clean)
{
    /* every budgeted allocation of a small reconstruction fails in turn: a
     * clean error, no output, nothing left allocated */
    specimen sp;
    CHECK(spec_init(&sp, 96, 6, SPACING, 3) == 0);
    bvox_image *imgs[6];
    for (int k = 0; k < 6; k++) CHECK_OK(spec_render(&sp, k, -1, 0, &imgs[k]));
    size_t base = bvox_memory_in_use();
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    int failures = 0;
    for (long n = 1; n < 400; n++) {
        bvox_volume *vol = NULL;
        bvox_contour_stack *stack = NULL;
        bvox_recon_report *rep = NULL;
        bvox__alloc_fail_after(n);
        bvox_status st = bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, 6, &o, &vol,
                                                 &stack, &rep);
        bvox__alloc_fail_after(0);
        if (st == BVOX_OK) {
            CHECK(vol && stack && rep);
            bvox_volume_destroy(vol);
            bvox_stack_destroy(stack);
            bvox_recon_report_destroy(rep);
            break;
        }
        failures++;
        CHECK(st == BVOX_ENOMEM || st == BVOX_ETOOBIG);
        CHECK(vol == NULL && stack == NULL && rep == NULL);
        CHECK_EQ(bvox_memory_in_use(), base);
    }
    CHECK(failures > 10);
    for (int k = 0; k < 6; k++) bvox_image_destroy(imgs[k]);
    spec_free(&sp);
    return 0;
}

TEST(bright_objects_same_model)
{
    /* the sections inverted (bright object on a dark field) with --bright
     * give the model of the originals with --dark; markers (bright in the
     * inverted images) go as specks in both */
    specimen sp;
    CHECK(spec_init(&sp, 160, 12, SPACING, 8) == 0);
    bvox_image *imgs[12], *inv[12];
    for (int k = 0; k < 12; k++) {
        CHECK_OK(spec_render(&sp, k, -1, 0, &imgs[k]));
        CHECK_OK(bvox_image_copy(imgs[k], &inv[k]));
        for (int i = 0; i < 160 * 160; i++) inv[k]->pixels[i] = (uint8_t)(255 - imgs[k]->pixels[i]);
    }
    bvox_recon_opts o = bvox_recon_opts_default();
    o.min_area = 200;
    o.align = 0;
    bvox_volume *a = NULL, *b = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, 12, &o, &a, NULL, NULL));
    o.dark = 0;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)inv, NULL, 12, &o, &b, NULL, NULL));
    double d = spec_dice(a, b);
    fprintf(stderr, "dark vs bright: dice %.4f, %lld voxels\n", d, (long long)bvox_volume_count(a));
    CHECK(bvox_volume_count(a) > 10000);
    CHECK(d >= 0.98);
    for (int k = 0; k < 12; k++) {
        bvox_image_destroy(imgs[k]);
        bvox_image_destroy(inv[k]);
    }
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    spec_free(&sp);
    return 0;
}

/* A specimen whose sections change slowly (as thin serial sections do): an
 * ellipse that widens and flattens a little along z (about its own centre:
 * an object that drifts is indistinguishable from a section that moved),
 * with a disc on its side so that no turn maps it onto itself. No markers. Section k moved by
 * sp->moves[k] (turns up to 8 degrees, shifts up to 20 pixels), the same
 * uneven light and noise as the other specimen. */
static bvox_status render_tube(const specimen *sp, int32_t k, bvox_image **out)
{
    bvox_status st = bvox_image_create(sp->size, sp->size, 1, 8, out);
    if (st) return st;
    bvox_sim2 inv = bvox_sim2_inverse(&sp->moves[k]);
    uint64_t s = sp->seed * 2654435761u + (uint64_t)k * 97 + 1;
    double n = sp->size;
    for (int32_t y = 0; y < sp->size; y++)
        for (int32_t x = 0; x < sp->size; x++) {
            bvox_point2 p = bvox_sim2_apply(&inv, (bvox_point2){x + 0.5, y + 0.5});
            double u = (p.x - 115) / (48 + 0.15 * k), v = (p.y - 112) / (30 - 0.1 * k);
            int in = u * u + v * v <= 1 || hypot(p.x - 150, p.y - 146) <= 20;
            double light = 165 + 35 * x / n - 40 * ((y - n / 2) / n) * ((y - n / 2) / n) * 4;
            double val = light * (in ? 0.5 : 1) + (spec_urand(&s) - 0.5) * 24;
            (*out)->pixels[(size_t)y * sp->size + x] = (uint8_t)(val < 0 ? 0 : val > 255 ? 255 : val);
        }
    return BVOX_OK;
}

/* All markers lost (none in any section): each section is aligned by its
 * traced contours onto its neighbour, outwards from the middle one, and
 * comes back within 0.5 degree and 1 pixel (at the image centre) of its
 * true place; the report says which were aligned so, with residuals. */
TEST(markers_lost_aligned_by_contours)
{
    enum { N = 24 };
    specimen sp;
    CHECK(spec_init(&sp, SIZE, N, 2.0, 777) == 0);
    bvox_image *imgs[N];
    for (int k = 0; k < N; k++) CHECK_OK(render_tube(&sp, k, &imgs[k]));
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers.count = 3;
    bvox_recon_report *rep = NULL;
    bvox_volume *vol = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, N, &o, &vol, NULL,
                                     &rep));
    int ref = rep->reference;
    CHECK_EQ(ref, N / 2);
    CHECK_EQ(rep->fallbacks, N - 1);
    double worst_angle = 0, worst_shift = 0;
    for (int k = 0; k < N; k++) {
        const bvox_recon_section_report *s = &rep->sections[k];
        if (k == ref) continue;
        CHECK_EQ(s->align.by_contours, 1);
        CHECK(s->align.residual < 1.0);
        CHECK(strstr(s->message, "aligned by its contours"));
        /* section k -> the specimen's frame -> the reference section */
        bvox_sim2 back = bvox_sim2_inverse(&sp.moves[k]);
        bvox_sim2 want = bvox_sim2_compose(&sp.moves[ref], &back);
        worst_angle = fmax(worst_angle, fabs(s->align.transform.angle - want.angle));
        bvox_point2 c = {SIZE / 2.0, SIZE / 2.0};
        bvox_point2 a = bvox_sim2_apply(&s->align.transform, c), b = bvox_sim2_apply(&want, c);
        worst_shift = fmax(worst_shift, hypot(a.x - b.x, a.y - b.y));
    }
    fprintf(stderr, "by contours: worst angle error %.3f deg, centre error %.3f px\n",
            worst_angle * 180 / M_PI, worst_shift);
    CHECK(worst_angle < 0.5 * M_PI / 180);
    CHECK(worst_shift < 1.0);
    for (int k = 0; k < N; k++) bvox_image_destroy(imgs[k]);
    bvox_recon_report_destroy(rep);
    bvox_volume_destroy(vol);
    spec_free(&sp);
    return 0;
}
