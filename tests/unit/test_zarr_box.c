/* test_zarr_box.c — the Zarr box interface the out-of-core code uses (reads
 * of boxes that decode only the chunks they touch, the chunk-by-chunk
 * writer), the resolution pyramid (each level the OR of 2x2x2 voxels of the
 * level below, against a voxel-by-voxel reference; scale per level; the
 * automatic level count), and the folder rules of a .zarr output (a
 * rewrite needs --force, a folder of the user's is never replaced). */
#include "harness.h"
#include "io/zarr.h"
#include "ref/voxref.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int rnd(int n) { return (int)(harness_rand() % (uint64_t)n); }

/* the reference of one pyramid step: OR over each 2x2x2 block */
static voxref *ref_halve(const voxref *r)
{
    voxref *h = voxref_create((r->nx + 1) / 2, (r->ny + 1) / 2, (r->nz + 1) / 2);
    for (int z = 0; z < r->nz; z++)
        for (int y = 0; y < r->ny; y++)
            for (int x = 0; x < r->nx; x++)
                if (voxref_get(r, x, y, z)) *voxref_at(h, x / 2, y / 2, z / 2) = 1;
    return h;
}

static bool exists(const char *p)
{
    struct stat sb;
    return stat(p, &sb) == 0;
}

TEST(downsample_or_matches_reference)
{
    static const int dims[][3] = {{1, 1, 1}, {2, 2, 64}, {7, 5, 129}, {3, 9, 200}, {4, 4, 63}};
    for (size_t i = 0; i < sizeof dims / sizeof dims[0]; i++) {
        voxref *r = voxref_create(dims[i][0], dims[i][1], dims[i][2]);
        voxref_random(r, 1, 40, harness_rand); /* sparse: most blocks empty, some not */
        bvox_volume *v = voxref_to_volume(r), *h;
        voxref *want = ref_halve(r);
        CHECK_OK(bvox_volume_create((bvox_dims){want->nx, want->ny, want->nz}, &h));
        bvox__downsample_or(v, h);
        CHECK_OK(bvox_volume_check(h)); /* no bits beyond nz */
        CHECK(voxref_matches(want, h));
        bvox_volume_destroy(h);
        bvox_volume_destroy(v);
        voxref_destroy(want);
        voxref_destroy(r);
    }
    return 0;
}

TEST(box_reads_match_reference)
{
    voxref *r = voxref_create(70, 50, 90);
    voxref_random(r, 1, 3, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    CHECK_OK(bvox_volume_set_spacing(v, 0.5, 0.25, 2, "um"));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = 37, wo.chunks[1] = 20, wo.chunks[2] = 33;
    wo.compressor = "blosc";
    const char *p = harness_path("b.zarr");
    CHECK_OK(bvox_write(p, v, &wo));
    bvox__zarr *z;
    CHECK_OK(bvox__zarr_open(p, &z));
    bvox_dims d = bvox__zarr_dims(z);
    CHECK_EQ(d.nx, 70);
    CHECK_EQ(d.ny, 50);
    CHECK_EQ(d.nz, 90);
    int32_t c[3];
    bvox__zarr_chunk_shape(z, c);
    CHECK_EQ(c[0], 37);
    CHECK_EQ(c[1], 20);
    CHECK_EQ(c[2], 33);
    CHECK_EQ(bvox__zarr_dtype(z), BVOX_DT_U8);
    CHECK_EQ(bvox__zarr_geometry(z)->spacing[2], 2.0);
    CHECK(!strcmp(bvox__zarr_geometry(z)->unit, "um"));
    for (int k = 0; k < 40; k++) {
        bvox_box b;
        b.x0 = rnd(70), b.y0 = rnd(50), b.z0 = rnd(90);
        b.x1 = b.x0 + 1 + rnd(70 - b.x0), b.y1 = b.y0 + 1 + rnd(50 - b.y0);
        b.z1 = b.z0 + 1 + rnd(90 - b.z0);
        voxref *want = voxref_crop(r, b);
        bvox_volume *out;
        CHECK_OK(bvox_volume_create((bvox_dims){want->nx, want->ny, want->nz}, &out));
        CHECK_OK(bvox__zarr_read_box(z, b.x0, b.y0, b.z0, want->nx, want->ny, want->nz, NULL,
                                     out));
        CHECK_OK(bvox_volume_check(out));
        CHECK(voxref_matches(want, out));
        bvox_volume_destroy(out);
        voxref_destroy(want);
    }
    /* a box outside, or a volume of the wrong size */
    bvox_volume *out;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 5, 5}, &out));
    CHECK_STATUS(bvox__zarr_read_box(z, 66, 0, 0, 5, 5, 5, NULL, out), BVOX_EINVAL);
    CHECK_STATUS(bvox__zarr_read_box(z, 0, 0, 0, 5, 5, 4, NULL, out), BVOX_EINVAL);
    /* a box that touches one chunk decodes only it: the others may be gone */
    char chunk[4300];
    snprintf(chunk, sizeof chunk, "%s/0/1.1.1", p);
    CHECK(unlink(chunk) == 0 || !exists(chunk));
    CHECK_OK(bvox__zarr_read_box(z, 0, 0, 0, 5, 5, 5, NULL, out));
    bvox_volume_destroy(out);
    bvox__zarr_close(z);
    bvox_volume_destroy(v);
    voxref_destroy(r);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* The chunk-by-chunk writer: slabs of one chunk row written out of order
 * give the same array as the whole volume; boxes off the chunk grid are
 * refused; nothing is visible before commit, nothing left after abort. */
TEST(chunk_by_chunk_writer)
{
    voxref *r = voxref_create(45, 61, 100);
    voxref_random(r, 1, 5, harness_rand);
    const int32_t chunks[3] = {16, 24, 40};
    const char *p = harness_path("w.zarr");
    bvox__zarr_writer *w;
    bvox_geometry g = bvox_geometry_default();
    g.spacing[0] = 3;
    CHECK_OK(bvox__zarr_create(p, (bvox_dims){45, 61, 100}, chunks, "zlib", &g, 0, false, &w));
    int32_t c[3];
    bvox__zarr_writer_chunk_shape(w, c);
    CHECK_EQ(c[2], 40);
    for (int zs = 2; zs >= 0; zs--) { /* z slabs 80..99, 40..79, 0..39 */
        bvox_box b = {0, 0, zs * 40, 45, 61, zs == 2 ? 100 : zs * 40 + 40};
        voxref *part = voxref_crop(r, b);
        bvox_volume *pv = voxref_to_volume(part);
        CHECK_OK(bvox__zarr_write_box(w, 0, 0, b.z0, pv));
        bvox_volume_destroy(pv);
        voxref_destroy(part);
    }
    bvox_volume *off;
    CHECK_OK(bvox_volume_create((bvox_dims){16, 24, 40}, &off));
    CHECK_STATUS(bvox__zarr_write_box(w, 8, 0, 0, off), BVOX_EINVAL);   /* not on the grid */
    CHECK_STATUS(bvox__zarr_write_box(w, 32, 0, 0, off), BVOX_EINVAL);  /* past the end */
    bvox_volume_destroy(off);
    CHECK(!exists(p));
    CHECK_OK(bvox__zarr_commit(w));
    bvox_volume *back;
    CHECK_OK(bvox_read(p, NULL, &back));
    CHECK(voxref_matches(r, back));
    CHECK_EQ(bvox_volume_geometry(back)->spacing[0], 3.0);
    bvox_volume_destroy(back);
    /* abort leaves nothing */
    const char *q = harness_path("gone.zarr");
    CHECK_OK(bvox__zarr_create(q, (bvox_dims){4, 4, 4}, NULL, NULL, NULL, 1, false, &w));
    bvox__zarr_abort(w);
    CHECK(!exists(q));
    CHECK_EQ(harness_count_entries(harness_path("")), 1); /* w.zarr only */
    voxref_destroy(r);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Each level is the OR-halving of the one below; its scale doubles; the
 * automatic count stops at the first level with a side under one chunk. */
TEST(pyramid_levels)
{
    voxref *r = voxref_create(67, 45, 131);
    voxref_random(r, 1, 60, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    CHECK_OK(bvox_volume_set_spacing(v, 0.5, 1, 4, "mm"));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = wo.chunks[1] = 16;
    wo.chunks[2] = 40; /* a coarse chunk is made from 80 fine slices: two words */
    const char *p = harness_path("p.zarr");
    CHECK_OK(bvox_write(p, v, &wo));
    /* 67x45x131 -> 34x23x66 -> 17x12x33 (12 < 16): three levels */
    bvox__zarr *z;
    CHECK_OK(bvox__zarr_open(p, &z));
    CHECK_EQ(bvox__zarr_levels(z), 3);
    bvox__zarr_close(z);
    voxref *want = voxref_copy(r);
    for (int32_t l = 0; l < 3; l++) {
        bvox_read_opts ro = BVOX_READ_OPTS_INIT;
        ro.zarr_level = l;
        bvox_volume *got;
        CHECK_OK(bvox_read(p, &ro, &got));
        CHECK(voxref_matches(want, got));
        const bvox_geometry *g = bvox_volume_geometry(got);
        CHECK_EQ(g->spacing[0], 0.5 * (1 << l));
        CHECK_EQ(g->spacing[1], 1.0 * (1 << l));
        CHECK_EQ(g->spacing[2], 4.0 * (1 << l));
        CHECK(!strcmp(g->unit, "mm"));
        bvox_volume_destroy(got);
        voxref *next = ref_halve(want);
        voxref_destroy(want);
        want = next;
    }
    voxref_destroy(want);
    bvox_read_opts ro = BVOX_READ_OPTS_INIT;
    ro.zarr_level = 3;
    bvox_volume *none;
    CHECK_STATUS(bvox_read(p, &ro, &none), BVOX_EINVAL);
    char lvl[4300];
    snprintf(lvl, sizeof lvl, "%s/3", p);
    CHECK(!exists(lvl));
    /* one level when asked */
    wo.zarr_levels = 1;
    const char *one = harness_path("one.zarr");
    CHECK_OK(bvox_write(one, v, &wo));
    snprintf(lvl, sizeof lvl, "%s/1", one);
    CHECK(!exists(lvl));
    bvox_volume_destroy(v);
    voxref_destroy(r);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* The volume's origin is level 0's translation; a coarse level's voxel 0
 * is centred on the 2^l fine voxels it covers: origin + spacing (2^l - 1)/2,
 * and a read of that level keeps it as the volume's origin. */
TEST(pyramid_levels_keep_the_origin)
{
    voxref *r = voxref_create(40, 36, 50);
    voxref_random(r, 1, 30, harness_rand);
    bvox_volume *v = voxref_to_volume(r);
    bvox_geometry g = *bvox_volume_geometry(v);
    g.spacing[0] = 0.5, g.spacing[1] = 0.25, g.spacing[2] = 2;
    g.origin[0] = 10, g.origin[1] = -3, g.origin[2] = 0.75;
    CHECK_OK(bvox_volume_set_geometry(v, &g));
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.chunks[0] = wo.chunks[1] = wo.chunks[2] = 8;
    wo.zarr_levels = 3;
    const char *p = harness_path("origin.zarr");
    CHECK_OK(bvox_write(p, v, &wo));
    const double want[3][3] = {{10, -3, 0.75}, {10.25, -2.875, 1.75}, {10.75, -2.625, 3.75}};
    for (int32_t l = 0; l < 3; l++) {
        bvox_read_opts ro = BVOX_READ_OPTS_INIT;
        ro.zarr_level = l;
        bvox_volume *got;
        CHECK_OK(bvox_read(p, &ro, &got));
        const bvox_geometry *gg = bvox_volume_geometry(got);
        for (int a = 0; a < 3; a++) CHECK_EQ(gg->origin[a], want[l][a]);
        CHECK_EQ(gg->spacing[2], 2.0 * (1 << l));
        bvox_volume_destroy(got);
    }
    bvox_volume_destroy(v);
    voxref_destroy(r);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* A rewrite of bvox's own .zarr needs force; a folder holding anything of
 * the user's is refused even then and keeps its files; an empty folder is
 * taken. */
TEST(rewrite_needs_force)
{
    bvox_volume *a, *b, *got;
    CHECK_OK(bvox_volume_create((bvox_dims){9, 8, 70}, &a));
    CHECK_OK(bvox_volume_create((bvox_dims){5, 5, 5}, &b));
    bvox_volume_set(a, 1, 2, 3, 1);
    bvox_volume_set(b, 4, 4, 4, 1);
    const char *p = harness_path("r.zarr");
    CHECK_OK(bvox_write(p, a, NULL));
    CHECK_STATUS(bvox_write(p, b, NULL), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "--force"));
    CHECK_OK(bvox_read(p, NULL, &got));
    CHECK_EQ(bvox_volume_dims(got).nz, 70); /* untouched */
    bvox_volume_destroy(got);
    bvox_write_opts wo = BVOX_WRITE_OPTS_INIT;
    wo.force = 1;
    CHECK_OK(bvox_write(p, b, &wo));
    CHECK_OK(bvox_read(p, NULL, &got));
    CHECK_EQ(bvox_volume_dims(got).nz, 5);
    CHECK_EQ(bvox_volume_count(got), 1);
    CHECK(bvox_volume_get(got, 4, 4, 4));
    bvox_volume_destroy(got);
    CHECK_EQ(harness_count_entries(harness_path("")), 1); /* the old tree is gone */
    /* a user's folder */
    const char *u = harness_path("user.zarr");
    CHECK(mkdir(u, 0777) == 0);
    char note[4300];
    snprintf(note, sizeof note, "%s/notes.txt", u);
    FILE *f = fopen(note, "w");
    CHECK(f != NULL);
    fputs("mine\n", f);
    fclose(f);
    CHECK_STATUS(bvox_write(u, a, &wo), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "notes.txt"));
    CHECK(exists(note));
    CHECK_EQ(harness_count_entries(u), 1);
    /* an empty folder */
    const char *e = harness_path("empty.zarr");
    CHECK(mkdir(e, 0777) == 0);
    CHECK_OK(bvox_write(e, a, NULL));
    CHECK_OK(bvox_read(e, NULL, &got));
    CHECK_EQ(bvox_volume_count(got), 1);
    bvox_volume_destroy(got);
    bvox_volume_destroy(a);
    bvox_volume_destroy(b);
    return 0;
}

/* An array larger than the memory budget is created, written box by box and
 * read box by box; only the whole-volume read refuses it. */
TEST(beyond_the_memory_budget)
{
    size_t old = bvox_memory_budget();
    bvox_set_memory_budget((size_t)8 << 20);
    const char *p = harness_path("big.zarr");
    const bvox_dims d = {3000, 2000, 2500}; /* 1.7 GiB as bits */
    const int32_t chunks[3] = {64, 64, 64};
    bvox__zarr_writer *w;
    CHECK_OK(bvox__zarr_create(p, d, chunks, "blosc", NULL, 0, false, &w));
    bvox_volume *box;
    CHECK_OK(bvox_volume_create((bvox_dims){56, 128, 64}, &box));
    bvox_volume_fill_box(box, (bvox_box){10, 70, 0, 30, 128, 64}, 1);
    CHECK_OK(bvox__zarr_write_box(w, 2944, 1024, 2432, box)); /* 2944 + 56: the edge */
    bvox_volume_destroy(box);
    CHECK_OK(bvox__zarr_commit(w));
    bvox__zarr *z;
    CHECK_OK(bvox__zarr_open(p, &z));
    CHECK_EQ(bvox__zarr_dims(z).nx, 3000);
    /* 3000x2000x2500 -> 1500x1000x1250 -> 750x500x625 -> 375x250x313 ->
     * 188x125x157 -> 94x63x79 (63 under 64): six levels */
    CHECK_EQ(bvox__zarr_levels(z), 6);
    bvox_volume *out;
    CHECK_OK(bvox_volume_create((bvox_dims){40, 100, 68}, &out));
    CHECK_OK(bvox__zarr_read_box(z, 2944, 1024, 2400, 40, 100, 68, NULL, out));
    /* the box's voxels x 10..29 (of 56 in the array), y 70..99, z 32..67 */
    CHECK_EQ(bvox_volume_count(out), 20 * 30 * 36);
    CHECK(bvox_volume_get(out, 10, 70, 32) && !bvox_volume_get(out, 9, 70, 32));
    bvox_volume_destroy(out);
    bvox__zarr_close(z);
    /* the coarsest level still holds the object */
    CHECK_OK(bvox__zarr_open_level(p, 5, &z));
    CHECK_EQ(bvox__zarr_dims(z).ny, 63);
    CHECK_OK(bvox_volume_create((bvox_dims){94, 63, 79}, &out));
    CHECK_OK(bvox__zarr_read_box(z, 0, 0, 0, 94, 63, 79, NULL, out));
    /* x 2954..2973 -> 92..92, y 1094..1151 -> 34..35, z 2432..2495 -> 76..77 */
    CHECK_EQ(bvox_volume_count(out), 1 * 2 * 2);
    CHECK(bvox_volume_get(out, 92, 34, 76) && bvox_volume_get(out, 92, 35, 77));
    bvox_volume_destroy(out);
    bvox__zarr_close(z);
    bvox_volume *all;
    CHECK_STATUS(bvox_read(p, NULL, &all), BVOX_ETOOBIG);
    bvox_set_memory_budget(old);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

/* Metadata claiming 65535^3 float64 samples in one chunk: opened (only
 * metadata is read), a box of a missing chunk is the fill value without any
 * allocation, a present chunk is refused before its buffer is allocated,
 * and the whole-volume read is refused by the budget. */
TEST(huge_shape_refused_before_allocation)
{
    const char *p = harness_path("huge.zarr");
    char f[4300];
    CHECK(mkdir(p, 0777) == 0);
    snprintf(f, sizeof f, "%s/.zarray", p);
    FILE *fp = fopen(f, "w");
    CHECK(fp != NULL);
    fputs("{\"zarr_format\": 2, \"shape\": [65535, 65535, 65535], \"chunks\": [65535, 65535, "
          "65535], \"dtype\": \"<f8\", \"compressor\": null, \"fill_value\": 0, \"order\": \"C\", "
          "\"filters\": null}", fp);
    fclose(fp);
    bvox__zarr *z;
    CHECK_OK(bvox__zarr_open(p, &z));
    bvox_volume *one;
    CHECK_OK(bvox_volume_create((bvox_dims){1, 1, 1}, &one));
    CHECK_OK(bvox__zarr_read_box(z, 5, 5, 5, 1, 1, 1, NULL, one));
    CHECK_EQ(bvox_volume_count(one), 0);
    snprintf(f, sizeof f, "%s/0.0.0", p);
    fp = fopen(f, "w");
    CHECK(fp != NULL);
    fputs("not 2 PB", fp);
    fclose(fp);
    CHECK_STATUS(bvox__zarr_read_box(z, 5, 5, 5, 1, 1, 1, NULL, one), BVOX_ETOOBIG);
    CHECK(strstr(bvox_errmsg(), "memory budget"));
    bvox_volume_destroy(one);
    bvox__zarr_close(z);
    bvox_volume *all;
    CHECK_STATUS(bvox_read(p, NULL, &all), BVOX_ETOOBIG);
    CHECK(strstr(bvox_errmsg(), "memory budget"));
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
