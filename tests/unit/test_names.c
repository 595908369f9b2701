/* test_names.c — src/common/names.c and dirlist.c: natural order of slice
 * file names (digit runs by value, of any length; letters
 * case-insensitively; a total and antisymmetric order so qsort gives one
 * answer), the case-insensitive suffix test, and a folder listed in that
 * order. */
#include "harness.h"
#include "common/names.h"

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>

#include <stdlib.h>
#include <string.h>

static int sign(int v) { return (v > 0) - (v < 0); }

TEST(pairs)
{
    static const char *const less[][2] = {
        {"s2.png", "s10.png"},
        {"s9", "s10"},
        {"slice_2.png", "slice_10.png"},
        {"a", "b"},
        {"A", "b"},          /* case-insensitive */
        {"a", "a1"},         /* a prefix first */
        {"img1_z3", "img1_z20"},
        {"img2_z1", "img10_z1"},
        {"s1", "s01"},       /* same value: fewer leading zeros first */
        {"s0001.png", "s2.png"},
        {"x99", "x123456789012345678901234567890"}, /* beyond 64 bits */
        {"x123456789012345678901234567890", "x123456789012345678901234567891"},
        {"s.png", "s1.png"},  /* '.' < '1' */
        {"B", "b"},          /* equal but case: strcmp decides */
        {"10", "a"},         /* digits before letters, as in ASCII */
    };
    for (size_t i = 0; i < sizeof less / sizeof less[0]; i++) {
        if (bvox__natural_compare(less[i][0], less[i][1]) >= 0 ||
            bvox__natural_compare(less[i][1], less[i][0]) <= 0) {
            fprintf(stderr, "pair %zu: %s < %s expected\n", i, less[i][0], less[i][1]);
            return 1;
        }
    }
    CHECK_EQ(bvox__natural_compare("s10.png", "s10.png"), 0);
    CHECK_EQ(bvox__natural_compare("", ""), 0);
    CHECK(bvox__natural_compare("", "a") < 0);
    return 0;
}

static int cmp(const void *a, const void *b)
{
    return bvox__natural_compare(*(char *const *)a, *(char *const *)b);
}

TEST(sorted_list)
{
    const char *names[] = {"s10.png", "s2.png", "S3.png", "s1.png", "s100.png",
                           "s20.png", "s02.png", "t1.png"};
    const char *want[] = {"s1.png", "s2.png", "s02.png", "S3.png", "s10.png",
                          "s20.png", "s100.png", "t1.png"};
    qsort(names, 8, sizeof names[0], cmp);
    for (int i = 0; i < 8; i++) CHECK(strcmp(names[i], want[i]) == 0);
    return 0;
}

TEST(total_order_on_random_names)
{
    /* antisymmetry and transitivity on random short names of digits/letters */
    static const char alphabet[] = "0019aZb.";
    char names[60][6];
    for (int i = 0; i < 60; i++) {
        int len = 1 + (int)(harness_rand() % 5);
        for (int k = 0; k < len; k++) names[i][k] = alphabet[harness_rand() % 8];
        names[i][len] = '\0';
    }
    for (int i = 0; i < 60; i++)
        for (int j = 0; j < 60; j++) {
            int a = sign(bvox__natural_compare(names[i], names[j]));
            int b = sign(bvox__natural_compare(names[j], names[i]));
            CHECK_EQ(a, -b);
            CHECK_EQ(a == 0, strcmp(names[i], names[j]) == 0);
            for (int k = 0; k < 60; k++) {
                if (a < 0 && bvox__natural_compare(names[j], names[k]) < 0)
                    CHECK(bvox__natural_compare(names[i], names[k]) < 0);
            }
        }
    return 0;
}

TEST(ends_with_ci)
{
    CHECK(bvox__ends_with_ci("a.png", ".png"));
    CHECK(bvox__ends_with_ci("A.PNG", ".png"));
    CHECK(bvox__ends_with_ci("x.Tiff", ".TIFF"));
    CHECK(bvox__ends_with_ci(".png", ".png"));   /* the whole string */
    CHECK(bvox__ends_with_ci("anything", ""));   /* the empty suffix */
    CHECK(!bvox__ends_with_ci("png", ".png"));   /* shorter than the suffix */
    CHECK(!bvox__ends_with_ci("a.pngx", ".png"));
    CHECK(!bvox__ends_with_ci("a.apng", ".tif"));
    CHECK(!bvox__ends_with_ci("a_png", ".png")); /* '_' is not '.' */
    CHECK(!bvox__ends_with_ci("a.p@g", ".png")); /* '@' | 32 is '`', not 'n' */
    return 0;
}

static bool keep_png(const char *dir, const char *name, void *ctx)
{
    (void)dir;
    (*(int *)ctx)++;
    return bvox__ends_with_ci(name, ".png");
}

static void touch(const char *path)
{
    FILE *f = fopen(path, "wb");
    if (f) fclose(f);
}

TEST(list_dir_natural_order_and_filter)
{
    const char *dir = harness_tmpdir();
    const char *files[] = {"s10.png", "s2.PNG", ".hidden.png", "notes.txt", "s1.png"};
    for (int i = 0; i < 5; i++) touch(harness_path(files[i]));
    char **paths = NULL;
    size_t n = 0;
    int seen = 0;
    CHECK_OK(bvox__list_dir(dir, keep_png, &seen, 100, "PNG files", &paths, &n));
    CHECK_EQ(seen, 4); /* every name but the hidden one went through the filter */
    CHECK_EQ(n, 3);
    const char *want[] = {"s1.png", "s2.PNG", "s10.png"};
    for (size_t i = 0; i < n; i++) {
        char full[4096];
        snprintf(full, sizeof full, "%s/%s", dir, want[i]);
        CHECK(strcmp(paths[i], full) == 0);
    }
    bvox__free_paths(paths, n);

    /* over the limit: ETOOBIG naming what was counted, nothing returned */
    CHECK_STATUS(bvox__list_dir(dir, keep_png, &seen, 2, "PNG files", &paths, &n),
                 BVOX_ETOOBIG);
    CHECK(paths == NULL && n == 0);
    CHECK(strstr(bvox_errmsg(), "more than 2 PNG files") != NULL);
    return 0;
}

TEST(list_dir_missing_folder)
{
    char **paths = (char **)1;
    size_t n = 7;
    int seen = 0;
    CHECK_STATUS(bvox__list_dir(harness_path("no-such-folder"), keep_png, &seen, 10, "files",
                                &paths, &n),
                 BVOX_EIO);
    CHECK_EQ(errno, ENOENT);
    CHECK(paths == NULL && n == 0);
    CHECK(strstr(bvox_errmsg(), "cannot open the folder") != NULL);
    return 0;
}
