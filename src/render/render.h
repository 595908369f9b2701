/*
 * render.h — private interface shared by the files of src/render/ (the
 * display pipeline: cast -> pre-image -> LUT shade -> image ops -> PNG).
 *
 * Normal codes: a hit voxel's 6 face neighbours are gathered as 6 bits
 * (NB_XM = neighbour at x-1, NB_XP at x+1, ...), and the 27-way normal index
 * is a table lookup on those bits (normal_index_of), so every caster uses the
 * same rule: a 1-neighbour pushes the normal away from itself.
 */
#ifndef BVOX_RENDER_H
#define BVOX_RENDER_H

#include "internal.h"
#include "common/image.h"

enum { NB_XM = 1, NB_XP = 2, NB_YM = 4, NB_YP = 8, NB_ZM = 16, NB_ZP = 32 };

/* Normal index (0..26) of the 6 neighbour bits above. */
extern const uint8_t bvox__normal_index[64];

/* The 3-bit depth cue of a depth in 0..range-1, floor(depth * 8 / range),
 * without a division per pixel: depth >= ceil(k range / 8) iff cue >= k. */
typedef struct bvox__cue {
    int64_t t[7];
} bvox__cue;

static inline void bvox__cue_init(bvox__cue *c, int64_t range)
{
    for (int k = 1; k <= 7; k++) c->t[k - 1] = range > 0 ? (k * range + 7) / 8 : INT64_MAX;
}

static inline unsigned bvox__cue_of(const bvox__cue *c, int64_t depth)
{
    unsigned n = 0;
    for (int k = 0; k < 7; k++) n += depth >= c->t[k];
    return n;
}

static inline uint8_t bvox__code(unsigned neighbours, int64_t depth, const bvox__cue *cue)
{
    return (uint8_t)(bvox__normal_index[neighbours & 63] | bvox__cue_of(cue, depth) << 5);
}

/* Allocate a pre-image of width x height, every pixel background (depth -1,
 * code BVOX_CODE_BACKGROUND); the other fields are zero. */
bvox_status bvox__preimage_alloc(int32_t width, int32_t height, bvox_preimage **out);
/* The same with the pixels left unset, for a caster that writes every one
 * (cast_view.c: a second pass over 5 MiB per 1024^2 frame saved). */
bvox_status bvox__preimage_alloc_unset(int32_t width, int32_t height, bvox_preimage **out);

/* The unit normal (in the eye frame: right, up, towards the viewer) of normal
 * index idx for a pre-image's frame and spacing. "No normal" faces the viewer. */
void bvox__normal_eye(const bvox_preimage *pre, unsigned idx, double n[3]);
/* Unit vector towards the light in the eye frame (right, up, towards viewer). */
void bvox__light_dir(const bvox_light *light, double l[3]);
/* Phong intensity 0..255 (before rounding) of a unit normal in the eye frame;
 * cue 0..7 applies the light's depth cue. */
double bvox__phong(const bvox_light *light, const double l[3], const double n[3], unsigned cue);
/* Checks the numbers of a light (finite, non-negative, depth_cue 0..1). */
bvox_status bvox__light_check(const bvox_light *light);
/* Depth shading: BVOX_EINVAL for a bad curve or values; the intensity of
 * depth t in 0..1 (0 nearest), rounded and clamped. */
bvox_status bvox__depth_check(const bvox_depth_shading *shading);
uint8_t bvox__depth_value(const bvox_depth_shading *shading, double t);
/* The unit surface normal (eye frame: right, up, towards the viewer) of the
 * depth map at a foreground pixel (x, y), from central or Sobel differences
 * in physical units; a background or outside neighbour takes the centre's
 * depth. */
void bvox__depth_normal(const bvox_preimage *pre, bvox_gradient op, int32_t x, int32_t y,
                        double n[3]);
/* The cut face of a projection (shade_table.c): the plane m . p + e, kept
 * side >= 0; a foreground pixel is on the face when its entry point (the
 * middle of its depth step) has m . p + e below half a voxel's extent along
 * m plus half a depth step's: every pixel that shows a face the cut exposed
 * passes (see the proof in bvox__cut_test_init), and only a thin rim of the
 * original surface next to the plane passes with them. */
typedef struct bvox__cut_test {
    double m[3], e, limit;
} bvox__cut_test;
void bvox__cut_test_init(bvox__cut_test *t, const double m[3], double e, const bvox_preimage *pre);
int bvox__cut_test_at(const bvox__cut_test *t, const bvox_preimage *pre, int32_t c, int32_t r,
                      int32_t d);
/* The plane normal m as a unit vector in the eye frame, facing the viewer. */
void bvox__cut_normal_eye(const bvox_preimage *pre, const double m[3], double n[3]);
/* Debug invariant of a pre-image handed across the render boundary: sane
 * size, arrays present, unit eye rows, depths in -1 .. depth_range-1.
 * Used in assert() only (compiled out in release builds). */
int bvox__preimage_ok(const bvox_preimage *pre);

/* ---- smooth.c: normals per pixel in the eye frame (right, up, towards the
 * viewer), as bvox_preimage_normals documents them ---- */
/* Smooth normals are interpolated between the ball moments of the 8 voxels
 * around a pixel's hit point; neighbouring pixels (and rows) share most of
 * them, so each chunk of rows keeps the moments it computed in a
 * direct-mapped cache (bvox__moment_cache_new: a zeroed one, or NULL when
 * memory is short, which only costs time; NULL means none). */
#define BVOX_MOMENT_CACHE 8191
typedef struct bvox__moment_cache {
    uint64_t key[BVOX_MOMENT_CACHE]; /* 0: empty */
    int32_t m[BVOX_MOMENT_CACHE][3];
    bvox_normal_cache *shared; /* behind it, kept across calls (NULL: none) */
} bvox__moment_cache;
static inline bvox__moment_cache *bvox__moment_cache_new(void)
{
    return bvox__mem_zalloc(1, sizeof(bvox__moment_cache));
}
void bvox__smooth_normal_eye(const bvox_volume *vol, const bvox_preimage *p, int radius,
                             int32_t c, int32_t r, double n[3], bvox__moment_cache *mc);
/* A pixel's voxels for its smooth normal: count 8 (the cell around its
 * entry point, fractions f towards base + 1) or 1 (the nearest voxel, when
 * pixels are as large as voxels), 0 for the background. */
typedef struct bvox__smooth_cell {
    int32_t base[3];
    int count;
    double f[3];
} bvox__smooth_cell;
/* The cells of row r (p->width of them), the shared cache's entries of
 * their voxels asked of the memory on the way (a row later they are there). */
void bvox__smooth_cells_row(const bvox_volume *vol, const bvox_preimage *p, int32_t r,
                            bvox__smooth_cell *cells, const bvox__moment_cache *mc);
/* bvox__smooth_normal_eye of a foreground pixel with its cell made. */
void bvox__smooth_normal_cell(const bvox_volume *vol, const bvox_preimage *p, int radius,
                              int32_t c, int32_t r, const bvox__smooth_cell *cell, double n[3],
                              bvox__moment_cache *mc);
void bvox__preimage_binary_normal(const bvox_preimage *p, int32_t x, int32_t y, double n[3]);
void bvox__pixel_normal(const bvox_volume *vol, const bvox_preimage *p, bvox_shade_mode mode,
                        int radius, int32_t x, int32_t y, double n[3], bvox__moment_cache *mc);

/* ---- shade_smooth.c ----
 * An 8-bit gray picture lit (bvox__phong, the code's 3-bit cue) with the
 * normals of bvox__pixel_normal. */
bvox_status bvox__shade_normals(const bvox_volume *vol, const bvox_preimage *pre,
                                bvox_shade_mode mode, int radius, const bvox_light *light,
                                bvox_image **out);
/* Multiply img (pre's size, 1 or 3 channels) by the ambient occlusion and
 * the shadow factor of every foreground pixel (see bvox_render_opts). */
bvox_status bvox__apply_depth_cues(const bvox_volume *vol, const bvox_preimage *pre,
                                   const bvox_light *light, int radius, int ao, int shadows,
                                   bvox_image *img);
/* Each factor x factor block of an 8-bit image averaged (rounded) into one
 * pixel: supersampling's reduction. */
bvox_status bvox__image_shrink(const bvox_image *in, int factor, bvox_image **out);

/* For the tests: number of casts (axis and projection) made in this process. */
long bvox__render_cast_count(void);
void bvox__render_count_cast(void);

/* ---- surface.c / cast_view.c: boundary voxels for arbitrary views ----
 * Entry: x | y << 16 | z << 32 | neighbour bits (NB_*) << 48.
 * The entries, grouped by class and in (y, x, z) order within a class, are
 * not one array but runs laid end to end: the build's per-band lists are
 * the surface itself, so the build does not copy every entry a second time
 * into fresh pages (a sixth of the 1024^3 atlas's build). */
typedef struct bvox__surface_run {
    const uint64_t *at;
    int64_t n;
} bvox__surface_run;

typedef struct bvox__surface_block { /* memory the runs point into, from bvox__alloc */
    uint64_t *at;
    size_t bytes;    /* charged to the memory budget (the rest was refunded) */
    size_t capacity; /* entries allocated (a rebuild reuses blocks of its size) */
} bvox__surface_block;

struct bvox_surface {
    bvox__surface_run *runs;   /* class k's runs: [class_run[k], class_run[k + 1]) */
    int64_t class_run[65];
    bvox__surface_block *blocks;
    int nblocks;
    int64_t count;
    int64_t class_start[65]; /* entries of neighbour class k: [start[k], start[k+1]) */
    bvox_dims dims;
    double spacing[3];
    bvox_box bbox; /* of the 1-voxels */
    int empty;
};

/* surface.c: every entry, in order, into out (count entries): the tests
 * compare surfaces whose runs split the entries differently. */
void bvox__surface_flatten(const bvox_surface *s, uint64_t *out);
/* surface.c: frees what a surface's runs point into, and the runs. */
void bvox__surface_release(bvox_surface *s);

#define SURF_X(e) ((int32_t)((e) & 0xffff))
#define SURF_Y(e) ((int32_t)((e) >> 16 & 0xffff))
#define SURF_Z(e) ((int32_t)((e) >> 32 & 0xffff))
#define SURF_NB(e) ((unsigned)((e) >> 48 & 63))

/* The 6 neighbour words of word w of column (x, y) (-x, +x, -y, +y, -z, +z;
 * outside the volume reads 0): a surface build and its update in a box. */
static inline void bvox__surface_neighbours(const bvox_volume *v, int32_t x, int32_t y,
                                            size_t w, uint64_t nb[6])
{
    const uint64_t *col = bvox__column_c(v, x, y);
    const size_t wpc = v->wpc, row = (size_t)v->nx * wpc;
    uint64_t word = col[w];
    nb[0] = x > 0 ? col[w - wpc] : 0;
    nb[1] = x + 1 < v->nx ? col[w + wpc] : 0;
    nb[2] = y > 0 ? col[w - row] : 0;
    nb[3] = y + 1 < v->ny ? col[w + row] : 0;
    nb[4] = word << 1 | (w > 0 ? col[w - 1] >> 63 : 0);
    nb[5] = word >> 1 | (w + 1 < wpc ? col[w + 1] << 63 : 0);
}

/* The NB_* bits of the voxel at bit k of the neighbour words nb. */
static inline uint64_t bvox__surface_nb_bits(const uint64_t nb[6], unsigned k)
{
    return (nb[0] >> k & 1) * NB_XM | (nb[1] >> k & 1) * NB_XP | (nb[2] >> k & 1) * NB_YM |
           (nb[3] >> k & 1) * NB_YP | (nb[4] >> k & 1) * NB_ZM | (nb[5] >> k & 1) * NB_ZP;
}

/* pictures.c: the demo's picture k (1 or 3) smooth-shaded, 512 x 512: the
 * view (and for 3 the cut) of bvox_demo_picture k; bvox_demo_pictures
 * writes them as picture1_smooth.png and picture3_smooth.png. */
bvox_status bvox__demo_picture_smooth(const bvox_volume *vol, int k, bvox_image **out);
/* pictures.c: the demo's picture k (1..3) by the paper's pre-image methods:
 * 1 the binary gradient operator over the pre-image (with the depth cue),
 * 2 and 3 the gradient over the pre-image enlarged x2 (Figure 5), 512 x 512;
 * written as picture1_preimage.png, picture2_enlarged.png and
 * picture3_enlarged.png. */
bvox_status bvox__demo_picture_paper(const bvox_volume *vol, int k, bvox_image **out);

#endif
