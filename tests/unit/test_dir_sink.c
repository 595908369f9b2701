/* test_dir_sink.c — folder outputs never delete a file bvox did not write:
 * a new or empty folder is filled, bvox's own earlier output (its manifest)
 * is replaced file by file, anything else is refused unless forced, and
 * forcing removes nothing; no temporary folder is ever left beside the
 * target, also with concurrent writers. */
#include "harness.h"
#include "io/io.h"

#include <dirent.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fputs(text, f);
    return fclose(f) == 0;
}

/* The first line of path, or "" (static buffer). */
static const char *read_text(const char *path)
{
    static char buf[256];
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f) return buf;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

static int exists(const char *dir, const char *name)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    struct stat sb;
    return lstat(p, &sb) == 0;
}

/* Write the named files (content: the name and tag) through a folder sink. */
static bvox_status put(const char *target, bvox__dir_kind kind, bool force, const char *tag,
                       const char *const *files)
{
    bvox__dir_sink d;
    bvox_status st = bvox__dir_sink_open(target, kind, force, &d);
    if (st) return st;
    for (int i = 0; files[i]; i++) {
        char p[1200], text[200];
        snprintf(p, sizeof p, "%s/%s", d.tmp, files[i]);
        snprintf(text, sizeof text, "%s %s", files[i], tag);
        if (!write_text(p, text)) {
            bvox__dir_sink_abort(&d);
            return BVOX_EIO;
        }
    }
    return bvox__dir_sink_commit(&d);
}

static const char *const three[] = {"slice_0000.png", "slice_0001.png", "slice_0002.png", NULL};
static const char *const two[] = {"slice_0000.png", "slice_0001.png", NULL};

TEST(new_folder_gets_files_and_manifest)
{
    const char *target = harness_path("p");
    CHECK_OK(put(target, BVOX__DIR_PNG_SLICES, false, "a", three));
    CHECK_EQ(harness_count_entries(target), 4);
    CHECK(exists(target, BVOX__MANIFEST_NAME));
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1); /* nothing left beside it */
    char m[1200];
    snprintf(m, sizeof m, "%s/%s", target, BVOX__MANIFEST_NAME);
    CHECK(strcmp(read_text(m), "bvox output manifest 1\nkind png-slices\nslice_0000.png\n"
                               "slice_0001.png\nslice_0002.png\n") == 0);
    return 0;
}

/* The reproducer: a folder of the user's is refused and untouched. */
TEST(foreign_folder_refused_untouched)
{
    const char *target = harness_path("p");
    char sub[1200], thesis[1200];
    snprintf(sub, sizeof sub, "%s/sub", target);
    snprintf(thesis, sizeof thesis, "%s/thesis.txt", target);
    CHECK(mkdir(target, 0777) == 0 && mkdir(sub, 0777) == 0);
    CHECK(write_text(thesis, "x"));
    CHECK_STATUS(put(target, BVOX__DIR_PNG_SLICES, false, "a", three), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "did not write") != NULL);
    CHECK(strstr(bvox_errmsg(), "thesis.txt") != NULL || strstr(bvox_errmsg(), "sub") != NULL);
    CHECK_EQ(harness_count_entries(target), 2);
    CHECK(strcmp(read_text(thesis), "x") == 0);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    return 0;
}

/* bvox's own earlier output is replaced exactly: the file not written again
 * goes, the others get the new content, the folder itself stays. */
TEST(own_output_replaced)
{
    const char *target = harness_path("p");
    CHECK_OK(put(target, BVOX__DIR_PNG_SLICES, false, "old", three));
    CHECK(chmod(target, 0750) == 0);
    struct stat before;
    CHECK(stat(target, &before) == 0);
    CHECK_OK(put(target, BVOX__DIR_PNG_SLICES, false, "new", two));
    CHECK_EQ(harness_count_entries(target), 3);
    CHECK(!exists(target, "slice_0002.png"));
    char p[1200];
    snprintf(p, sizeof p, "%s/slice_0001.png", target);
    CHECK(strcmp(read_text(p), "slice_0001.png new") == 0);
    struct stat after;
    CHECK(stat(target, &after) == 0);
    CHECK_EQ(after.st_ino, before.st_ino);
    CHECK_EQ(after.st_mode & 0777, 0750);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    return 0;
}

/* An existing empty folder is filled, and kept (mode, inode). */
TEST(empty_folder_filled_and_kept)
{
    const char *target = harness_path("p");
    CHECK(mkdir(target, 0700) == 0);
    struct stat before, after;
    CHECK(stat(target, &before) == 0);
    CHECK_OK(put(target, BVOX__DIR_SVG_SECTIONS, false, "a",
                 (const char *const[]){"section_0001.svg", NULL}));
    CHECK(stat(target, &after) == 0);
    CHECK_EQ(after.st_ino, before.st_ino);
    CHECK_EQ(after.st_mode & 0777, 0700);
    CHECK_EQ(harness_count_entries(target), 2);
    return 0;
}

/* A user's file added to bvox's output makes the folder foreign; forcing
 * replaces bvox's names (and removes bvox's listed files not written
 * again) but never the user's file. */
TEST(force_removes_nothing_else)
{
    const char *target = harness_path("p");
    CHECK_OK(put(target, BVOX__DIR_PNG_SLICES, false, "old", three));
    char notes[1200];
    snprintf(notes, sizeof notes, "%s/notes.txt", target);
    CHECK(write_text(notes, "mine"));
    CHECK_STATUS(put(target, BVOX__DIR_PNG_SLICES, false, "new", two), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "notes.txt") != NULL);
    CHECK_OK(put(target, BVOX__DIR_PNG_SLICES, true, "new", two));
    CHECK(strcmp(read_text(notes), "mine") == 0);
    CHECK(!exists(target, "slice_0002.png")); /* listed as bvox's: removed */
    char p[1200];
    snprintf(p, sizeof p, "%s/slice_0000.png", target);
    CHECK(strcmp(read_text(p), "slice_0000.png new") == 0);
    /* forced into a folder of a user's own slice_*.png: replaced, but
     * the user's other files stay */
    const char *t2 = harness_path("q");
    CHECK(mkdir(t2, 0777) == 0);
    snprintf(p, sizeof p, "%s/slice_0009.png", t2);
    CHECK(write_text(p, "user slice"));
    snprintf(p, sizeof p, "%s/slice_0000.png", t2);
    CHECK(write_text(p, "user slice"));
    CHECK_OK(put(t2, BVOX__DIR_PNG_SLICES, true, "new", two));
    CHECK(strcmp(read_text(p), "slice_0000.png new") == 0);
    CHECK(exists(t2, "slice_0009.png"));
    CHECK_EQ(harness_count_entries(t2), 4);
    /* a folder of one of the new names: refused before anything moves */
    const char *t3 = harness_path("r");
    CHECK(mkdir(t3, 0777) == 0);
    snprintf(p, sizeof p, "%s/slice_0001.png", t3);
    CHECK(mkdir(p, 0777) == 0);
    CHECK_STATUS(put(t3, BVOX__DIR_PNG_SLICES, true, "new", two), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "not a regular file") != NULL);
    CHECK_EQ(harness_count_entries(t3), 1);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 3);
    return 0;
}

/* A manifest can only vouch for names of bvox's pattern: one that lists a
 * user's file makes the folder foreign, and the file survives. */
TEST(forged_manifest_refused)
{
    const char *target = harness_path("p");
    CHECK(mkdir(target, 0777) == 0);
    char p[1200];
    snprintf(p, sizeof p, "%s/%s", target, BVOX__MANIFEST_NAME);
    CHECK(write_text(p, "bvox output manifest 1\nkind png-slices\nthesis.txt\n"));
    snprintf(p, sizeof p, "%s/thesis.txt", target);
    CHECK(write_text(p, "x"));
    CHECK_STATUS(put(target, BVOX__DIR_PNG_SLICES, false, "a", three), BVOX_EIO);
    CHECK_STATUS(put(target, BVOX__DIR_PNG_SLICES, true, "a", three), BVOX_OK);
    CHECK(strcmp(read_text(p), "x") == 0);
    /* listing ../ names is impossible too: only slice_<digits>.png */
    return 0;
}

TEST(other_kind_refused)
{
    const char *target = harness_path("p");
    CHECK_OK(put(target, BVOX__DIR_SVG_SECTIONS, false, "a",
                 (const char *const[]){"section_0001.svg", NULL}));
    CHECK_STATUS(put(target, BVOX__DIR_PNG_SLICES, false, "a", three), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "svg-sections") != NULL);
    CHECK(exists(target, "section_0001.svg"));
    return 0;
}

TEST(not_a_folder_and_abort)
{
    const char *target = harness_path("f");
    CHECK(write_text(target, "file"));
    bvox__dir_sink d;
    CHECK_STATUS(bvox__dir_sink_open(target, BVOX__DIR_PNG_SLICES, true, &d), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "not a folder") != NULL);
    CHECK_OK(bvox__dir_sink_open(harness_path("g"), BVOX__DIR_PNG_SLICES, false, &d));
    char p[1200];
    snprintf(p, sizeof p, "%s/slice_0000.png", d.tmp);
    CHECK(write_text(p, "x"));
    bvox__dir_sink_abort(&d);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    CHECK_STATUS(bvox__dir_sink_open(harness_path("no/such/g"), BVOX__DIR_PNG_SLICES, false, &d),
                 BVOX_ENOTFOUND);
    return 0;
}

/* A symlink to a folder: the folder it names is written, the link stays. */
TEST(symlink_to_folder)
{
    const char *real = harness_path("real");
    CHECK(mkdir(real, 0777) == 0);
    CHECK(symlink("real", harness_path("link")) == 0);
    CHECK_OK(put(harness_path("link"), BVOX__DIR_PNG_SLICES, false, "a", two));
    CHECK_EQ(harness_count_entries(real), 3);
    struct stat sb;
    CHECK(lstat(harness_path("link"), &sb) == 0 && S_ISLNK(sb.st_mode));
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 2);
    return 0;
}

/* Eight writers of the same new PNG folder at once: every one succeeds (the
 * first renames the folder into place, the others replace it in place),
 * and nothing is left beside it (the old code left NAME.old.* folders). */
typedef struct {
    const char *target;
    const bvox_volume *vol;
    bvox_status st;
} writer_job;

static void *write_job(void *arg)
{
    writer_job *j = arg;
    j->st = bvox_write(j->target, j->vol, NULL);
    return NULL;
}

TEST(concurrent_writers_leave_nothing)
{
    bvox_volume *v = NULL;
    CHECK_OK(bvox_volume_create((bvox_dims){5, 4, 3}, &v));
    bvox_volume_set(v, 1, 2, 1, 1);
    char target[1200];
    snprintf(target, sizeof target, "%s/", harness_path("stack"));
    for (int round = 0; round < 3; round++) {
        writer_job jobs[8];
        pthread_t th[8];
        for (int i = 0; i < 8; i++) {
            jobs[i] = (writer_job){target, v, BVOX_OK};
            CHECK(pthread_create(&th[i], NULL, write_job, &jobs[i]) == 0);
        }
        for (int i = 0; i < 8; i++) pthread_join(th[i], NULL);
        for (int i = 0; i < 8; i++) CHECK_OK(jobs[i].st);
        CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
        CHECK_EQ(harness_count_entries(harness_path("stack")), 5); /* 3 slices, voxel_size.txt, manifest */
    }
    bvox_volume *back = NULL;
    CHECK_OK(bvox_read(target, NULL, &back));
    CHECK(bvox_volume_equal(back, v));
    bvox_volume_destroy(back);
    bvox_volume_destroy(v);
    return 0;
}
