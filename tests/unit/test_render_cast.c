/* test_render_cast.c — the six axis views against a voxel-by-voxel reference
 * cast written here (depth and code of every pixel) on random and structured
 * volumes of awkward sizes; hand-computed normal codes of a box's faces,
 * edges and corners; the pre-image geometry fields. */
#include "harness.h"
#include "ref/voxref.h"
#include "render/render.h"

#include <string.h>

static const int sizes[][3] = {{1, 1, 1},  {7, 5, 1},   {5, 9, 63}, {9, 3, 64},
                               {3, 7, 65}, {11, 5, 130}, {1, 13, 70}, {13, 1, 129}};
#define NSIZES (int)(sizeof sizes / sizeof sizes[0])

/* The reference: per pixel, step voxel by voxel along the view. */
static int check_view(const voxref *r, const bvox_volume *vol, bvox_view view)
{
    bvox_preimage *pre = NULL;
    CHECK_OK(bvox_cast_axis(vol, view, &pre));
    const int n[3] = {r->nx, r->ny, r->nz};
    const int axis = (int)view / 2, dir = (int)view % 2 ? -1 : 1;
    const int cu = axis == 0 ? 1 : 0, cv = axis == 2 ? 1 : 2;
    CHECK_EQ(pre->width, n[cu]);
    CHECK_EQ(pre->height, n[cv]);
    CHECK_EQ(pre->depth_range, n[axis]);
    int bad = 0;
    for (int row = 0; row < n[cv]; row++)
        for (int colm = 0; colm < n[cu]; colm++) {
            int want_d = -1, want_c = BVOX_CODE_BACKGROUND;
            for (int s = 0; s < n[axis]; s++) {
                int p[3];
                p[cu] = colm, p[cv] = row, p[axis] = dir > 0 ? s : n[axis] - 1 - s;
                if (!voxref_get(r, p[0], p[1], p[2])) continue;
                int nx = voxref_get(r, p[0] - 1, p[1], p[2]) - voxref_get(r, p[0] + 1, p[1], p[2]);
                int ny = voxref_get(r, p[0], p[1] - 1, p[2]) - voxref_get(r, p[0], p[1] + 1, p[2]);
                int nz = voxref_get(r, p[0], p[1], p[2] - 1) - voxref_get(r, p[0], p[1], p[2] + 1);
                want_d = s;
                want_c = ((nx + 1) * 9 + (ny + 1) * 3 + (nz + 1)) | (s * 8 / n[axis]) << 5;
                break;
            }
            size_t i = (size_t)row * (size_t)n[cu] + (size_t)colm;
            if ((pre->depth[i] != want_d || pre->code[i] != want_c) && bad++ < 3)
                fprintf(stderr, "%dx%dx%d view %s pixel (%d, %d): depth %d code %d, want %d %d\n",
                        r->nx, r->ny, r->nz, bvox_view_name(view), colm, row, pre->depth[i],
                        pre->code[i], want_d, want_c);
        }
    bvox_preimage_destroy(pre);
    CHECK_EQ(bad, 0);
    return 0;
}

static int check_all_views(const voxref *r)
{
    bvox_volume *vol = voxref_to_volume(r);
    CHECK(vol != NULL);
    for (int v = 0; v < 6; v++) {
        if (check_view(r, vol, (bvox_view)v)) {
            bvox_volume_destroy(vol);
            return 1;
        }
    }
    bvox_volume_destroy(vol);
    return 0;
}

TEST(axis_views_random)
{
    static const unsigned dens[][2] = {{1, 2}, {1, 12}, {1, 80}, {0, 1}, {1, 1}};
    for (int s = 0; s < NSIZES; s++)
        for (int d = 0; d < 5; d++) {
            voxref *r = voxref_create(sizes[s][0], sizes[s][1], sizes[s][2]);
            voxref_random(r, dens[d][0], dens[d][1], harness_rand);
            int fail = check_all_views(r);
            voxref_destroy(r);
            CHECK_EQ(fail, 0);
        }
    return 0;
}

TEST(axis_views_structured)
{
    /* spheres and boxes whose surfaces cross word boundaries */
    static const int dims[][3] = {{17, 19, 130}, {21, 15, 65}, {31, 33, 64}, {9, 11, 63}};
    for (int s = 0; s < 4; s++) {
        bvox_volume *vol;
        CHECK_OK(bvox_volume_create((bvox_dims){dims[s][0], dims[s][1], dims[s][2]}, &vol));
        bvox_shape sph = {BVOX_SHAPE_SPHERE, {dims[s][0] / 2.0, dims[s][1] / 2.0, dims[s][2] / 2.0},
                          {0, 0, 0}, {0, 0, 0}, dims[s][0] / 2.5, 0, 0};
        CHECK_OK(bvox_shape_draw(vol, &sph, BVOX_CSG_UNION));
        bvox_volume_fill_box(vol, (bvox_box){1, 2, dims[s][2] / 3, 5, 6, dims[s][2] - 1}, 1);
        bvox_volume_fill_box(vol, (bvox_box){2, 3, dims[s][2] / 2, 4, 5, dims[s][2] - 3}, 0);
        voxref *r = voxref_from_volume(vol);
        bvox_volume_destroy(vol);
        int fail = check_all_views(r);
        voxref_destroy(r);
        CHECK_EQ(fail, 0);
    }
    return 0;
}

static int code_at(const bvox_preimage *p, int c, int r) { return p->code[r * p->width + c]; }
static int depth_at(const bvox_preimage *p, int c, int r) { return p->depth[r * p->width + c]; }
#define IDX(nx, ny, nz) (((nx) + 1) * 9 + ((ny) + 1) * 3 + ((nz) + 1))

TEST(box_normal_codes)
{
    /* box x, y, z in 2..7 of a 10^3 volume */
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){10, 10, 10}, &vol));
    bvox_volume_fill_box(vol, (bvox_box){2, 2, 2, 8, 8, 8}, 1);
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Z, &p));
    /* depth 2 of 10: cue 2*8/10 = 1 */
    CHECK_EQ(depth_at(p, 4, 4), 2);
    CHECK_EQ(code_at(p, 4, 4), 12 | 1 << 5); /* face: (0, 0, -1) */
    CHECK_EQ(code_at(p, 2, 4), 3 | 1 << 5);  /* edge at x = 2: (-1, 0, -1) */
    CHECK_EQ(code_at(p, 7, 4), 21 | 1 << 5); /* edge at x = 7: (1, 0, -1) */
    CHECK_EQ(code_at(p, 4, 2), 9 | 1 << 5);  /* edge at y = 2: (0, -1, -1) */
    CHECK_EQ(code_at(p, 2, 2), 0 | 1 << 5);  /* corner: (-1, -1, -1) */
    CHECK_EQ(code_at(p, 7, 7), 24 | 1 << 5); /* corner: (1, 1, -1) */
    CHECK_EQ(code_at(p, 2, 2) & 31, IDX(-1, -1, -1));
    CHECK_EQ(code_at(p, 7, 7) & 31, IDX(1, 1, -1));
    CHECK_EQ(depth_at(p, 1, 4), -1);
    CHECK_EQ(code_at(p, 1, 4), BVOX_CODE_BACKGROUND);
    CHECK_EQ(code_at(p, 9, 9), BVOX_CODE_BACKGROUND);
    bvox_preimage_destroy(p);

    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_NEG_X, &p)); /* column = y, row = z */
    CHECK_EQ(depth_at(p, 4, 4), 2);                     /* x = 7 is 2 steps from x = 9 */
    CHECK_EQ(code_at(p, 4, 4) & 31, IDX(1, 0, 0));      /* 22 */
    CHECK_EQ(code_at(p, 4, 4) & 31, 22);
    CHECK_EQ(code_at(p, 2, 4) & 31, IDX(1, -1, 0));     /* edge at y = 2 */
    CHECK_EQ(code_at(p, 4, 7) & 31, IDX(1, 0, 1));      /* edge at z = 7 */
    CHECK_EQ(code_at(p, 7, 2) & 31, IDX(1, 1, -1));     /* corner y = 7, z = 2 */
    bvox_preimage_destroy(p);

    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_POS_Y, &p)); /* column = x, row = z */
    CHECK_EQ(code_at(p, 5, 5) & 31, IDX(0, -1, 0));     /* 10 */
    CHECK_EQ(code_at(p, 2, 7) & 31, IDX(-1, -1, 1));
    bvox_preimage_destroy(p);

    /* a one-voxel sheet seen face on has no normal along the view */
    bvox_volume_fill(vol, 0);
    bvox_volume_fill_box(vol, (bvox_box){0, 0, 5, 10, 10, 6}, 1);
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_NEG_Z, &p));
    CHECK_EQ(code_at(p, 5, 5) & 31, BVOX_NORMAL_NONE);
    CHECK_EQ(depth_at(p, 5, 5), 4);
    CHECK_EQ(code_at(p, 0, 5) & 31, IDX(-1, 0, 0)); /* outside counts as 0 */
    bvox_preimage_destroy(p);
    bvox_volume_destroy(vol);
    return 0;
}

TEST(preimage_geometry)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){4, 6, 8}, &vol));
    CHECK_OK(bvox_volume_set_spacing(vol, 0.5, 0.25, 2.0, "mm"));
    bvox_preimage *p;
    CHECK_OK(bvox_cast_axis(vol, BVOX_VIEW_NEG_X, &p));
    CHECK_EQ(p->width, 6);
    CHECK_EQ(p->height, 8);
    CHECK_NEAR(p->depth_step, 0.5, 0);
    CHECK_NEAR(p->pixel_size[0], 0.25, 0);
    CHECK_NEAR(p->pixel_size[1], 2.0, 0);
    CHECK_NEAR(p->eye[1], 1, 0);  /* right = +y */
    CHECK_NEAR(p->eye[5], 1, 0);  /* down = +z */
    CHECK_NEAR(p->eye[6], -1, 0); /* view = -x */
    CHECK_NEAR(p->origin[0], 1.5, 1e-12); /* depth 0 is x = 3 */
    CHECK_EQ(bvox_memory_in_use() > 0, 1);
    bvox_image *d;
    CHECK_OK(bvox_preimage_depth_image(p, &d));
    CHECK_EQ(d->bits, 16);
    CHECK_EQ(d->pixels16[0], 65535); /* empty volume: all background */
    bvox_image_destroy(d);
    bvox_preimage_destroy(p);
    bvox_volume_destroy(vol);
    CHECK_EQ(bvox_memory_in_use(), 0);
    CHECK_EQ(bvox_view_parse("-y"), BVOX_VIEW_NEG_Y);
    CHECK_EQ(bvox_view_parse("z"), BVOX_VIEW_POS_Z);
    CHECK_EQ(bvox_view_parse("+q"), -1);
    CHECK(strcmp(bvox_view_name(BVOX_VIEW_NEG_Z), "-z") == 0);
    return 0;
}

TEST(cast_errors_and_oom)
{
    bvox_volume *vol;
    CHECK_OK(bvox_volume_create((bvox_dims){70, 9, 65}, &vol));
    bvox_volume_fill(vol, 1);
    bvox_preimage *p = (bvox_preimage *)1;
    CHECK_STATUS(bvox_cast_axis(vol, (bvox_view)6, &p), BVOX_EINVAL);
    CHECK(p == NULL);
    CHECK_STATUS(bvox_cast_axis(NULL, BVOX_VIEW_POS_Z, &p), BVOX_EINVAL);
    /* every allocation of every view fails cleanly */
    for (int v = 0; v < 6; v++)
        for (long k = 1; k <= 3; k++) {
            bvox__alloc_fail_after(k);
            bvox_status st = bvox_cast_axis(vol, (bvox_view)v, &p);
            bvox__alloc_fail_after(0);
            if (st == BVOX_OK) {
                bvox_preimage_destroy(p);
                continue;
            }
            CHECK_EQ(st, BVOX_ENOMEM);
            CHECK(p == NULL);
        }
    bvox_volume_destroy(vol);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
