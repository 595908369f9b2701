/* test_reconstruct_contours.c — the known answer through the traced-contour
 * path: the specimen's sections (specimen_sections.h), each moved by its
 * random rigid transform, traced (bvox_bitmap_trace), simplified, every
 * point jittered by up to half a pixel each way (a 1-pixel band) and the
 * markers placed with a jitter of a fifth of a pixel (one missing in a
 * section, a spurious one in another), written as a JSON stack and as an
 * SVG folder by the contour writers, read back by bvox_reconstruct and
 * aligned by the markers: Dice >= 0.95; without alignment clearly lower. */
#include "harness.h"
#include "specimen_sections.h"

#include <stdio.h>
#include <string.h>

enum { NSEC = 70, SIZE = 240 };
#define SPACING 2.0

static double jitter(uint64_t *s, double half)
{
    return (spec_urand(s) * 2 - 1) * half;
}

/* The traced, jittered stack of the specimen. */
static bvox_contour_stack *make_stack(const specimen *sp)
{
    bvox_contour_stack *stack = NULL;
    if (bvox_stack_create(&stack)) return NULL;
    stack->pixel = 1;
    stack->spacing = SPACING;
    stack->width = stack->height = sp->size;
    snprintf(stack->unit, sizeof stack->unit, "um");
    bvox_shape sh[4];
    spec_shapes(sp, sh);
    uint64_t s = 4242;
    for (int k = 0; k < sp->n; k++) {
        bvox_bitmap *bm = NULL;
        if (bvox_bitmap_create(sp->size, sp->size, &bm)) goto fail;
        bvox_sim2 inv = bvox_sim2_inverse(&sp->moves[k]);
        for (int32_t y = 0; y < sp->size; y++)
            for (int32_t x = 0; x < sp->size; x++) {
                bvox_point2 p = bvox_sim2_apply(&inv, (bvox_point2){x + 0.5, y + 0.5});
                bvox_bitmap_set(bm, x, y, spec_inside(sh, p.x, p.y, k * SPACING));
            }
        bvox_contour *c = NULL;
        int32_t nc = 0;
        bvox_status st = bvox_bitmap_trace(bm, &c, &nc);
        bvox_bitmap_destroy(bm);
        if (st) goto fail;
        char name[32];
        snprintf(name, sizeof name, "cut%d", k + 1);
        bvox_section *sec = NULL;
        st = bvox_stack_add_section(stack, k * SPACING, name, &sec);
        for (int32_t i = 0; i < nc && !st; i++) {
            st = bvox_contour_simplify(&c[i], 0.75);
            for (int32_t j = 0; j < c[i].npoints; j++) {
                c[i].points[j].x += jitter(&s, 0.5);
                c[i].points[j].y += jitter(&s, 0.5);
            }
            if (!st) st = bvox_section_add_contour(sec, c[i].points, c[i].npoints, c[i].hole, c[i].parent);
        }
        bvox_contours_free(c, nc);
        for (int i = 0; i < 4 && !st; i++) {
            if ((k == 10 && i == 1) || (i == 3 && k != 50)) continue; /* missing, spurious */
            bvox_point2 m = bvox_sim2_apply(&sp->moves[k], spec_marker(sp, i));
            m.x += jitter(&s, 0.2);
            m.y += jitter(&s, 0.2);
            st = bvox_section_add_marker(sec, m);
        }
        if (st) goto fail;
    }
    return stack;
fail:
    fprintf(stderr, "make_stack: %s\n", bvox_errmsg());
    bvox_stack_destroy(stack);
    return NULL;
}

/* Reconstruct path aligned and not; check the Dice of both. */
static int check_path(const specimen *sp, const char *path, const bvox_recon_opts *base)
{
    bvox_recon_opts o = base ? *base : bvox_recon_opts_default();
    bvox_volume *vol = NULL, *raw = NULL, *truth = NULL;
    bvox_recon_report *rep = NULL;
    const char *in[1] = {path};
    CHECK_OK(bvox_reconstruct(in, 1, &o, &vol, NULL, &rep));
    CHECK_OK(bvox_volume_check(vol));
    CHECK_EQ(rep->nsections, NSEC);
    CHECK_EQ(rep->aligned, 1);
    CHECK_EQ(rep->fallbacks, 0);
    CHECK_EQ(rep->reference, NSEC / 2);
    CHECK_EQ(rep->sections[10].nmarkers, 2);
    CHECK_EQ(rep->sections[50].nmarkers, 4);
    CHECK_EQ(rep->sections[50].align.matched, 3);
    bvox_dims d = bvox_volume_dims(vol);
    CHECK_EQ(d.nx, SIZE);
    CHECK_EQ(d.nz, (int)(NSEC * SPACING));
    CHECK_OK(spec_truth(sp, vol, &truth));
    double da = spec_dice(vol, truth);
    o.align = 0;
    CHECK_OK(bvox_reconstruct(in, 1, &o, &raw, NULL, NULL));
    double dr = spec_dice(raw, truth);
    fprintf(stderr, "%s: dice aligned %.4f, not aligned %.4f\n", path, da, dr);
    CHECK(da >= 0.95);
    CHECK(dr < 0.85);
    bvox_recon_report_destroy(rep);
    bvox_volume_destroy(vol);
    bvox_volume_destroy(raw);
    bvox_volume_destroy(truth);
    return 0;
}

TEST(json_known_answer)
{
    specimen sp;
    CHECK(spec_init(&sp, SIZE, NSEC, SPACING, 31337) == 0);
    bvox_contour_stack *stack = make_stack(&sp);
    CHECK(stack);
    const char *path = harness_path("traced.json");
    CHECK_OK(bvox_stack_write_json(path, stack));
    bvox_stack_destroy(stack);
    if (check_path(&sp, path, NULL)) return 1;
    spec_free(&sp);
    return 0;
}

TEST(svg_known_answer)
{
    specimen sp;
    CHECK(spec_init(&sp, SIZE, NSEC, SPACING, 4711) == 0);
    bvox_contour_stack *stack = make_stack(&sp);
    CHECK(stack);
    const char *dir = harness_path("traced_svg");
    CHECK_OK(bvox_stack_write_svg_dir(dir, stack));
    bvox_stack_destroy(stack);
    if (check_path(&sp, dir, NULL)) return 1;
    spec_free(&sp);
    return 0;
}

TEST(markers_file_aligns_images)
{
    /* the images' markers painted over; their positions come from a file */
    specimen sp;
    CHECK(spec_init(&sp, 160, 12, SPACING, 5) == 0);
    bvox_contour_stack *m = NULL;
    CHECK_OK(bvox_stack_create(&m));
    bvox_image *imgs[12];
    for (int k = 0; k < 12; k++) {
        CHECK_OK(spec_render(&sp, k, -1, 0, &imgs[k]));
        for (int i = 0; i < 160 * 160; i++)
            if (imgs[k]->pixels[i] < 50) imgs[k]->pixels[i] = 175;
        bvox_section *sec = NULL;
        CHECK_OK(bvox_stack_add_section(m, k, NULL, &sec));
        for (int i = 0; i < 3; i++)
            CHECK_OK(bvox_section_add_marker(sec, bvox_sim2_apply(&sp.moves[k], spec_marker(&sp, i))));
    }
    const char *path = harness_path("markers.json");
    CHECK_OK(bvox_stack_write_json(path, m));
    bvox_recon_opts o = bvox_recon_opts_default();
    o.markers_file = path;
    o.spacing = SPACING;
    bvox_recon_report *rep = NULL;
    CHECK_OK(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, 12, &o, NULL, NULL, &rep));
    CHECK_EQ(rep->aligned, 1);
    CHECK_EQ(rep->fallbacks, 0);
    for (int k = 0; k < 12; k++) {
        bvox_sim2 want = bvox_sim2_inverse(&sp.moves[k]);
        CHECK_NEAR(rep->sections[k].align.transform.angle, want.angle, 1e-6);
        CHECK_NEAR(rep->sections[k].align.transform.tx, want.tx, 1e-4);
    }
    bvox_recon_report_destroy(rep);
    /* a file with another number of sections */
    bvox_section *extra = NULL;
    CHECK_OK(bvox_stack_add_section(m, 99, NULL, &extra));
    CHECK_OK(bvox_stack_write_json(path, m));
    CHECK_STATUS(bvox_reconstruct_images((const bvox_image *const *)imgs, NULL, 12, &o, NULL, NULL, &rep),
                 BVOX_EINVAL);
    CHECK(strstr(bvox_errmsg(), "13 sections of markers for 12"));
    for (int k = 0; k < 12; k++) bvox_image_destroy(imgs[k]);
    bvox_stack_destroy(m);
    spec_free(&sp);
    return 0;
}
