/*
 * preimage.c — the pre-image (depth + normal code per pixel): allocation,
 * release, its depth map as a 16-bit image, view names, and the normal code
 * rule shared by every caster (a 1-neighbour pushes the normal away).
 */
#include "render.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* Built from the rule n_a = (neighbour at a-1) - (neighbour at a+1). */
#define NI(b) (uint8_t)((((b) & NB_XM ? 1 : 0) - ((b) & NB_XP ? 1 : 0) + 1) * 9 +          \
                        (((b) & NB_YM ? 1 : 0) - ((b) & NB_YP ? 1 : 0) + 1) * 3 +          \
                        (((b) & NB_ZM ? 1 : 0) - ((b) & NB_ZP ? 1 : 0) + 1))
#define NI4(b) NI(b), NI(b + 1), NI(b + 2), NI(b + 3)
#define NI16(b) NI4(b), NI4(b + 4), NI4(b + 8), NI4(b + 12)
const uint8_t bvox__normal_index[64] = {NI16(0), NI16(16), NI16(32), NI16(48)};

static atomic_long cast_count;
long bvox__render_cast_count(void) { return atomic_load(&cast_count); }
void bvox__render_count_cast(void) { atomic_fetch_add(&cast_count, 1); }

static const char *const view_names[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};

const char *bvox_view_name(bvox_view view)
{
    return (unsigned)view < 6u ? view_names[view] : "unknown";
}

int bvox_view_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < 6; i++)
        if (!strcmp(name, view_names[i]) || !strcmp(name, view_names[i] + (i % 2 == 0)))
            return i;
    return -1;
}

typedef struct pre_block {
    bvox_preimage pub; /* first */
    size_t depth_bytes, code_bytes;
} pre_block;

bvox_status bvox__preimage_alloc(int32_t width, int32_t height, bvox_preimage **out)
{
    bvox_status st = bvox__preimage_alloc_unset(width, height, out);
    if (st) return st;
    size_t n = (size_t)width * (size_t)height;
    memset((*out)->depth, 0xff, n * sizeof(int32_t)); /* -1 */
    memset((*out)->code, BVOX_CODE_BACKGROUND, n);
    return BVOX_OK;
}

bvox_status bvox__preimage_alloc_unset(int32_t width, int32_t height, bvox_preimage **out)
{
    *out = NULL;
    if (width < 1 || height < 1 || width > BVOX_IMAGE_MAX_DIM || height > BVOX_IMAGE_MAX_DIM)
        return bvox__fail(BVOX_EINVAL, "pre-image size %d x %d is outside 1..%d", (int)width,
                          (int)height, BVOX_IMAGE_MAX_DIM);
    size_t n = (size_t)width * (size_t)height, dbytes;
    if (!bvox__mul_size(n, sizeof(int32_t), &dbytes))
        return bvox__fail(BVOX_ETOOBIG, "pre-image too large");
    pre_block *b = bvox__mem_zalloc(1, sizeof *b);
    if (!b) return bvox__fail(BVOX_ENOMEM, "out of memory");
    bvox_status st;
    b->pub.depth = bvox__alloc(dbytes, false, "pre-image depths", &st);
    if (b->pub.depth) b->pub.code = bvox__alloc(n, false, "pre-image codes", &st);
    if (!b->pub.code) {
        bvox__free(b->pub.depth, dbytes);
        free(b);
        return st;
    }
    b->depth_bytes = dbytes;
    b->code_bytes = n;
    b->pub.width = width;
    b->pub.height = height;
    *out = &b->pub;
    return BVOX_OK;
}

void bvox_preimage_destroy(bvox_preimage *pre)
{
    if (!pre) return;
    pre_block *b = (pre_block *)pre;
    bvox__free(pre->depth, b->depth_bytes);
    bvox__free(pre->code, b->code_bytes);
    free(b);
}

static bvox_status preimage_check(const bvox_preimage *pre)
{
    if (!pre || !pre->depth || !pre->code || pre->width < 1 || pre->height < 1)
        return bvox__fail(BVOX_EINVAL, "not a valid pre-image");
    return BVOX_OK;
}

bvox_status bvox_preimage_depth_image(const bvox_preimage *pre, bvox_image **out)
{
    *out = NULL;
    bvox_status st = preimage_check(pre);
    if (st) return st;
    st = bvox_image_create(pre->width, pre->height, 1, 16, out);
    if (st) return st;
    size_t n = (size_t)pre->width * (size_t)pre->height;
    for (size_t i = 0; i < n; i++) {
        int32_t d = pre->depth[i];
        (*out)->pixels16[i] = d < 0 ? 65535 : d > 65534 ? 65534 : (uint16_t)d;
    }
    return BVOX_OK;
}

void bvox__normal_eye(const bvox_preimage *pre, unsigned idx, double n[3])
{
    double v[3] = {(double)((int)(idx / 9) - 1), (double)((int)(idx / 3 % 3) - 1),
                   (double)((int)(idx % 3) - 1)};
    /* a gradient in index units becomes a physical one divided by the spacing */
    for (int a = 0; a < 3; a++) v[a] /= pre->spacing[a] > 0 ? pre->spacing[a] : 1.0;
    const double *e = pre->eye;
    double right = e[0] * v[0] + e[1] * v[1] + e[2] * v[2];
    double down = e[3] * v[0] + e[4] * v[1] + e[5] * v[2];
    double view = e[6] * v[0] + e[7] * v[1] + e[8] * v[2];
    double len = sqrt(right * right + down * down + view * view);
    if (idx >= 27 || len == 0) {
        n[0] = 0, n[1] = 0, n[2] = 1; /* a one-voxel sheet seen face on */
        return;
    }
    n[0] = right / len;
    n[1] = -down / len;
    n[2] = -view / len;
}

int bvox__preimage_ok(const bvox_preimage *pre)
{
    if (!pre || pre->width <= 0 || pre->height <= 0 || pre->width > BVOX_IMAGE_MAX_DIM ||
        pre->height > BVOX_IMAGE_MAX_DIM || !pre->depth || !pre->code)
        return 0;
    for (int r = 0; r < 3; r++) {
        const double *e = pre->eye + 3 * r;
        if (!(fabs(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] - 1) < 1e-6)) return 0;
    }
    if (!(pre->depth_step >= 0) || !(pre->pixel_size[0] >= 0) || !(pre->pixel_size[1] >= 0)) return 0;
    const size_t n = (size_t)pre->width * (size_t)pre->height;
    for (size_t i = 0; i < n; i++)
        if (pre->depth[i] < -1 || (pre->depth_range > 0 && pre->depth[i] >= pre->depth_range)) return 0;
    return 1;
}
