/* test_nifti_labels.c — bvox_write_labels_nifti: hand-made label volumes read
 * back with the independent reader (tests/ref/nifti_ref.c: datatype, bitpix,
 * dimensions, voxel size, every value) and with bvox_read --label; the
 * uint16 / uint32 choice at its boundary; .nii.gz; a real component
 * labelling round trip (each label read back is exactly that component);
 * refused names and sizes; failed writes leave no file. */
#include "harness.h"
#include "io/io.h"
#include "ref/nifti_ref.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* 16-bit field of an uncompressed file's header (this CPU's byte order). */
static int header_i16(const char *path, long offset)
{
    FILE *f = fopen(path, "rb");
    int16_t v = -1;
    if (!f) return -1;
    if (fseek(f, offset, SEEK_SET) != 0 || fread(&v, 2, 1, f) != 1) v = -1;
    fclose(f);
    return v;
}

/* Labels of a 5 x 4 x 3 volume: value (x + 2y + 3z) % 5 for x odd, else 0,
 * and one sample set to `top`. */
static uint32_t *make_labels(uint32_t top)
{
    uint32_t *l = calloc(5 * 4 * 3, sizeof *l);
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 5; x++)
                l[(z * 4 + y) * 5 + x] = x % 2 ? (uint32_t)((x + 2 * y + 3 * z) % 5) : 0;
    l[(2 * 4 + 3) * 5 + 4] = top; /* voxel (4, 3, 2) */
    return l;
}

/* Writes labels with top as the largest, reads them back independently and
 * checks the sample type and every value. */
static int roundtrip(const char *name, uint32_t top, int want_datatype, int want_bitpix)
{
    bvox_volume *like;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 4, 3}, &like));
    CHECK_OK(bvox_volume_set_spacing(like, 0.5, 0.25, 2.0, "mm"));
    uint32_t *l = make_labels(top);
    const char *path = harness_path(name);
    CHECK_OK(bvox_write_labels_nifti(path, like, l));
    nifti_ref r;
    CHECK_EQ(nifti_ref_read(path, &r), 0);
    CHECK_EQ(r.datatype, want_datatype);
    CHECK_EQ(r.bitpix, want_bitpix);
    CHECK_EQ(r.dim[0], 3);
    CHECK_EQ(r.dim[1], 5);
    CHECK_EQ(r.dim[2], 4);
    CHECK_EQ(r.dim[3], 3);
    CHECK_NEAR(r.pixdim[1], 0.5, 1e-7);
    CHECK_NEAR(r.pixdim[2], 0.25, 1e-7);
    CHECK_NEAR(r.pixdim[3], 2.0, 1e-7);
    CHECK_EQ(r.xyzt_units & 7, 2); /* mm */
    CHECK_EQ(r.nvox, 60);
    for (int i = 0; i < 60; i++) CHECK_EQ((int64_t)r.values[i], (int64_t)l[i]);
    nifti_ref_free(&r);
    /* bvox_read with --label k gives exactly the voxels holding k */
    for (uint32_t k = 1; k <= 4; k++) {
        bvox_read_opts o = BVOX_READ_OPTS_INIT;
        o.binarize.mode = BVOX_BIN_LABEL;
        o.binarize.label = k;
        bvox_volume *v;
        CHECK_OK(bvox_read(path, &o, &v));
        for (int z = 0; z < 3; z++)
            for (int y = 0; y < 4; y++)
                for (int x = 0; x < 5; x++)
                    CHECK_EQ(bvox_volume_get(v, x, y, z), l[(z * 4 + y) * 5 + x] == k);
        CHECK_NEAR(bvox_volume_geometry(v)->spacing[1], 0.25, 1e-7);
        bvox_volume_destroy(v);
    }
    free(l);
    bvox_volume_destroy(like);
    return 0;
}

TEST(uint16_and_uint32_at_the_boundary)
{
    CHECK_EQ(roundtrip("a.nii", 4, 512, 16), 0);
    CHECK_EQ(roundtrip("b.nii", 65535, 512, 16), 0);
    CHECK_EQ(roundtrip("c.nii", 65536, 768, 32), 0);
    CHECK_EQ(roundtrip("d.nii", 4000000000u, 768, 32), 0);
    CHECK_EQ(roundtrip("e.nii.gz", 7, 512, 16), 0);
    CHECK_EQ(roundtrip("f.nii.gz", 70000, 768, 32), 0);
    /* the label intent (1002) in the header, for viewers' colour tables */
    CHECK_EQ(header_i16(harness_path("a.nii"), 68), 1002);
    CHECK_EQ(header_i16(harness_path("c.nii"), 68), 1002);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(all_background)
{
    bvox_volume *like;
    CHECK_OK(bvox_volume_create((bvox_dims){3, 2, 1}, &like));
    uint32_t l[6] = {0};
    CHECK_OK(bvox_write_labels_nifti(harness_path("zero.nii"), like, l));
    nifti_ref r;
    CHECK_EQ(nifti_ref_read(harness_path("zero.nii"), &r), 0);
    CHECK_EQ(r.datatype, 512);
    CHECK_EQ(nifti_ref_count_nonzero(&r), 0);
    nifti_ref_free(&r);
    bvox_volume_destroy(like);
    return 0;
}

static int is_index(const bvox_component *c, int64_t index, void *ctx)
{
    (void)c;
    return index == *(const int64_t *)ctx;
}

/* A random volume at an awkward size (nz = 65: two words per column),
 * labelled with 6-connectivity: every label read back is its component. */
TEST(components_roundtrip)
{
    bvox_dims d = {13, 11, 65};
    bvox_volume *v;
    CHECK_OK(bvox_volume_create(d, &v));
    for (int z = 0; z < d.nz; z++)
        for (int y = 0; y < d.ny; y++)
            for (int x = 0; x < d.nx; x++)
                if (harness_rand() % 4 == 0) CHECK_OK(bvox_volume_set(v, x, y, z, 1));
    bvox_components *c;
    CHECK_OK(bvox_components_find(v, 6, &c));
    int64_t n = bvox_components_count(c);
    CHECK(n > 20); /* sparse: many small components */
    size_t nvox = (size_t)d.nx * d.ny * d.nz;
    uint32_t *labels = malloc(nvox * sizeof *labels);
    bvox_components_labels(c, labels);
    const char *path = harness_path("comps.nii.gz");
    CHECK_OK(bvox_write_labels_nifti(path, v, labels));
    nifti_ref r;
    CHECK_EQ(nifti_ref_read(path, &r), 0);
    CHECK_EQ(r.datatype, 512);
    CHECK_EQ(nifti_ref_count_nonzero(&r), bvox_volume_count(v));
    nifti_ref_free(&r);
    for (int64_t k = 0; k < n; k += (n / 7 ? n / 7 : 1)) {
        bvox_read_opts o = BVOX_READ_OPTS_INIT;
        o.binarize.mode = BVOX_BIN_LABEL;
        o.binarize.label = (double)(k + 1);
        bvox_volume *back, *want;
        CHECK_OK(bvox_read(path, &o, &back));
        CHECK_OK(bvox_components_keep_if(c, is_index, &k, &want));
        CHECK(bvox_volume_equal(back, want));
        CHECK_EQ(bvox_volume_count(back), bvox_components_get(c, k)->voxels);
        bvox_volume_destroy(back);
        bvox_volume_destroy(want);
    }
    free(labels);
    bvox_components_destroy(c);
    bvox_volume_destroy(v);
    return 0;
}

TEST(refused_names_and_sizes)
{
    bvox_volume *like;
    uint32_t l[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    CHECK_OK(bvox_volume_create((bvox_dims){2, 2, 2}, &like));
    CHECK_STATUS(bvox_write_labels_nifti(harness_path("x.tif"), like, l), BVOX_EUNSUPPORTED);
    CHECK(!exists(harness_path("x.tif")));
    CHECK_STATUS(bvox_write_labels_nifti(harness_path("noext"), like, l), BVOX_EUNSUPPORTED);
    CHECK(strstr(bvox_errmsg(), "NIfTI") != NULL);
    CHECK(bvox_write_labels_nifti("/nonexistent-dir/x.nii", like, l) != BVOX_OK);
    CHECK_STATUS(bvox_write_labels_nifti(NULL, like, l), BVOX_EINVAL);
    bvox_volume_destroy(like);
    /* NIfTI-1 dimensions are int16 */
    CHECK_OK(bvox_volume_create((bvox_dims){40000, 1, 1}, &like));
    uint32_t *big = calloc(40000, sizeof *big);
    CHECK_STATUS(bvox_write_labels_nifti(harness_path("big.nii"), like, big), BVOX_EUNSUPPORTED);
    CHECK(!exists(harness_path("big.nii")));
    free(big);
    bvox_volume_destroy(like);
    return 0;
}

/* 70 x 70 x 60 = 294000 samples: the header and two chunks are three writes;
 * each may fail, and the chunk buffer's allocation may fail. */
TEST(failures_leave_no_file)
{
    bvox_volume *like;
    CHECK_OK(bvox_volume_create((bvox_dims){70, 70, 60}, &like));
    size_t n = 70 * 70 * 60;
    uint32_t *l = malloc(n * sizeof *l);
    for (size_t i = 0; i < n; i++) l[i] = (uint32_t)(i % 300);
    const char *path = harness_path("fail.nii");
    for (long k = 1; k <= 3; k++) {
        bvox__sink_fail_after(k);
        bvox_status st = bvox_write_labels_nifti(path, like, l);
        bvox__sink_fail_after(0);
        CHECK_STATUS(st, BVOX_EIO);
        CHECK(!exists(path));
    }
    bvox__alloc_fail_after(1);
    bvox_status st = bvox_write_labels_nifti(path, like, l);
    bvox__alloc_fail_after(0);
    CHECK_STATUS(st, BVOX_ENOMEM);
    CHECK(!exists(path));
    /* and it does succeed without the faults */
    CHECK_OK(bvox_write_labels_nifti(path, like, l));
    nifti_ref r;
    CHECK_EQ(nifti_ref_read(path, &r), 0);
    for (size_t i = 0; i < n; i++) CHECK_EQ((int64_t)r.values[i], (int64_t)l[i]);
    nifti_ref_free(&r);
    free(l);
    bvox_volume_destroy(like);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}
