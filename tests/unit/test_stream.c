/* test_stream.c — whole-file reads, gzip with its size cap, and the output
 * sink: a failed or aborted write leaves no temporary file and the old file
 * unchanged. */
#include "harness.h"
#include "io/io.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fputs(text, f);
    return fclose(f) == 0;
}

static size_t gzip_buffer(const void *in, size_t n, uint8_t *out, size_t cap)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    z.next_in = (Bytef *)in;
    z.avail_in = (uInt)n;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    deflate(&z, Z_FINISH);
    size_t got = cap - z.avail_out;
    deflateEnd(&z);
    return got;
}

TEST(read_file_errors)
{
    bvox__bytes b;
    CHECK_STATUS(bvox__read_file(harness_path("missing.nii"), &b), BVOX_ENOTFOUND);
    CHECK(strstr(bvox_errmsg(), "missing.nii") != NULL);
    CHECK_STATUS(bvox__read_file(harness_tmpdir(), &b), BVOX_EIO);
    CHECK(write_text(harness_path("a.txt"), "hello"));
    CHECK_OK(bvox__read_file(harness_path("a.txt"), &b));
    CHECK_EQ(b.size, 5);
    CHECK(memcmp(b.data, "hello", 5) == 0);
    bvox__bytes_release(&b);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(gunzip_roundtrip_cap_and_corruption)
{
    static uint8_t plain[200000], packed[300000];
    for (size_t i = 0; i < sizeof plain; i++) plain[i] = (uint8_t)(i * 7 / 1000);
    size_t n = gzip_buffer(plain, sizeof plain, packed, sizeof packed);
    CHECK(n > 20);
    bvox__bytes out;
    CHECK_OK(bvox__gunzip(packed, n, "x.gz", 0, &out));
    CHECK_EQ(out.size, sizeof plain);
    CHECK(memcmp(out.data, plain, sizeof plain) == 0);
    bvox__bytes_release(&out);
    /* exactly at the cap is fine, one byte under is a bomb */
    CHECK_OK(bvox__gunzip(packed, n, "x.gz", sizeof plain, &out));
    bvox__bytes_release(&out);
    CHECK_STATUS(bvox__gunzip(packed, n, "x.gz", sizeof plain - 1, &out), BVOX_ETOOBIG);
    CHECK(out.data == NULL);
    /* truncated and corrupt */
    CHECK_STATUS(bvox__gunzip(packed, n / 2, "x.gz", 0, &out), BVOX_EFORMAT);
    CHECK(strstr(bvox_errmsg(), "truncated") != NULL);
    packed[n / 2] ^= 0xff;
    packed[n / 2 + 1] ^= 0x55;
    bvox_status st = bvox__gunzip(packed, n, "x.gz", 0, &out);
    CHECK(st == BVOX_EFORMAT);
    CHECK_EQ(bvox_memory_in_use(), 0);
    return 0;
}

TEST(gunzip_concatenated_members)
{
    uint8_t a[64], packed[512];
    memset(a, 'a', sizeof a);
    size_t n1 = gzip_buffer(a, sizeof a, packed, sizeof packed);
    memset(a, 'b', sizeof a);
    size_t n2 = gzip_buffer(a, sizeof a, packed + n1, sizeof packed - n1);
    bvox__bytes out;
    CHECK_OK(bvox__gunzip(packed, n1 + n2, "cat.gz", 0, &out));
    CHECK_EQ(out.size, 128);
    CHECK_EQ(out.data[0], 'a');
    CHECK_EQ(out.data[127], 'b');
    bvox__bytes_release(&out);
    return 0;
}

TEST(sink_commit_replaces_atomically)
{
    const char *path = harness_path("out.bin");
    CHECK(write_text(path, "old"));
    bvox__sink s;
    CHECK_OK(bvox__sink_open(path, 0, &s));
    CHECK_OK(bvox__sink_write(&s, "new content", 11));
    /* until commit the old file is intact */
    bvox__bytes b;
    CHECK_OK(bvox__read_file(path, &b));
    CHECK_EQ(b.size, 3);
    bvox__bytes_release(&b);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 2);
    CHECK_OK(bvox__sink_commit(&s));
    CHECK_OK(bvox__read_file(path, &b));
    CHECK_EQ(b.size, 11);
    bvox__bytes_release(&b);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    return 0;
}

TEST(sink_injected_failure_keeps_old_file)
{
    const char *path = harness_path("keep.bin");
    CHECK(write_text(path, "precious"));
    for (long nth = 1; nth <= 3; nth++) {
        bvox__sink s;
        CHECK_OK(bvox__sink_open(path, 0, &s));
        bvox__sink_fail_after(nth);
        bvox_status st = BVOX_OK;
        for (int i = 0; i < 3 && !st; i++) st = bvox__sink_write(&s, "xxxx", 4);
        if (!st) st = bvox__sink_commit(&s);
        else bvox__sink_commit(&s); /* commit after a failure must refuse and clean */
        bvox__sink_fail_after(0);
        CHECK_EQ(st, BVOX_EIO);
        bvox__bytes b;
        CHECK_OK(bvox__read_file(path, &b));
        CHECK_EQ(b.size, 8);
        CHECK(memcmp(b.data, "precious", 8) == 0);
        bvox__bytes_release(&b);
        CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    }
    return 0;
}

TEST(sink_gzip_and_abort)
{
    const char *path = harness_path("z.gz");
    bvox__sink s;
    CHECK_OK(bvox__sink_open(path, 1, &s));
    char text[1000];
    memset(text, 'q', sizeof text);
    CHECK_OK(bvox__sink_write(&s, text, sizeof text));
    CHECK_OK(bvox__sink_commit(&s));
    bvox__bytes f, out;
    CHECK_OK(bvox__read_file(path, &f));
    CHECK(bvox__is_gzip(f.data, f.size));
    CHECK_OK(bvox__gunzip(f.data, f.size, path, 0, &out));
    CHECK_EQ(out.size, sizeof text);
    bvox__bytes_release(&f);
    bvox__bytes_release(&out);
    CHECK_OK(bvox__sink_open(harness_path("never.bin"), 0, &s));
    CHECK_OK(bvox__sink_write(&s, "abc", 3));
    bvox__sink_abort(&s);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    /* a folder that does not exist */
    CHECK_STATUS(bvox__sink_open(harness_path("nodir/x.bin"), 0, &s), BVOX_ENOTFOUND);
    return 0;
}

/* The public one-shot writer: content replaced whole, and a failed write
 * leaves the old file and no temporary file. */
TEST(write_file_atomic)
{
    const char *path = harness_path("report.json");
    CHECK(write_text(path, "old"));
    CHECK_OK(bvox_write_file_atomic(path, "{\"a\": 1}\n", 9));
    bvox__bytes b;
    CHECK_OK(bvox__read_file(path, &b));
    CHECK_EQ(b.size, 9);
    CHECK(memcmp(b.data, "{\"a\": 1}\n", 9) == 0);
    bvox__bytes_release(&b);
    bvox__sink_fail_after(1);
    CHECK_STATUS(bvox_write_file_atomic(path, "new", 3), BVOX_EIO);
    bvox__sink_fail_after(0);
    CHECK_OK(bvox__read_file(path, &b));
    CHECK_EQ(b.size, 9);
    bvox__bytes_release(&b);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    CHECK_STATUS(bvox_write_file_atomic(harness_path("no/such/dir/x"), "x", 1), BVOX_ENOTFOUND);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 1);
    return 0;
}

/* Output names of 248..255 bytes are valid, but ".NAME.XXXXXX" is not: the
 * temporary name is cut to fit NAME_MAX, and the output keeps its name. */
TEST(sink_long_names)
{
    for (int len = 240; len <= 255; len += 5) {
        char name[300];
        memset(name, 'n', (size_t)len);
        name[len] = '\0';
        memcpy(name + len - 4, ".raw", 4);
        const char *path = harness_path(name);
        bvox__sink s;
        CHECK_OK(bvox__sink_open(path, 0, &s));
        CHECK_OK(bvox__sink_write(&s, "abc", 3));
        CHECK_OK(bvox__sink_commit(&s));
        struct stat sb;
        CHECK(stat(path, &sb) == 0 && sb.st_size == 3);
        CHECK(unlink(path) == 0);
    }
    return 0;
}

/* A FIFO given as input used to hang in open(2) forever, waiting for a
 * writer: it is refused at once (the alarm fails the test if it hangs). */
TEST(read_file_refuses_fifo)
{
    const char *path = harness_path("f.nii");
    CHECK(mkfifo(path, 0600) == 0);
    alarm(20);
    bvox__bytes b;
    CHECK_STATUS(bvox__read_file(path, &b), BVOX_EIO);
    alarm(0);
    CHECK(strstr(bvox_errmsg(), "a FIFO") != NULL);
    return 0;
}

/* Output paths that are not regular files: a FIFO (or device, socket) is
 * refused and stays what it was; a folder is refused. */
TEST(sink_refuses_special_files)
{
    const char *fifo = harness_path("o.nii");
    CHECK(mkfifo(fifo, 0600) == 0);
    CHECK_STATUS(bvox_write_file_atomic(fifo, "abc", 3), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "is a FIFO") != NULL);
    struct stat sb;
    CHECK(lstat(fifo, &sb) == 0 && S_ISFIFO(sb.st_mode));
    const char *dir = harness_path("d.nii");
    CHECK(mkdir(dir, 0777) == 0);
    CHECK_STATUS(bvox_write_file_atomic(dir, "abc", 3), BVOX_EIO);
    CHECK(strstr(bvox_errmsg(), "is a folder") != NULL);
    /* a symlink to a FIFO is refused the same way */
    CHECK(symlink("o.nii", harness_path("l.nii")) == 0);
    CHECK_STATUS(bvox_write_file_atomic(harness_path("l.nii"), "abc", 3), BVOX_EIO);
    CHECK(lstat(fifo, &sb) == 0 && S_ISFIFO(sb.st_mode));
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 3);
    return 0;
}

/* A symlink is written through: its final target (two hops, one relative
 * into another folder) is replaced atomically with the temporary file
 * beside it, and the links stay links. A dangling link creates its target. */
TEST(sink_writes_through_symlinks)
{
    char sub[1100];
    snprintf(sub, sizeof sub, "%s", harness_path("sub"));
    CHECK(mkdir(sub, 0777) == 0);
    char real[1200];
    snprintf(real, sizeof real, "%s/real.json", sub);
    CHECK(write_text(real, "old"));
    CHECK(symlink("sub/real.json", harness_path("mid.json")) == 0);
    CHECK(symlink("mid.json", harness_path("link.json")) == 0);
    CHECK_OK(bvox_write_file_atomic(harness_path("link.json"), "new!", 4));
    struct stat sb;
    CHECK(lstat(harness_path("link.json"), &sb) == 0 && S_ISLNK(sb.st_mode));
    CHECK(lstat(harness_path("mid.json"), &sb) == 0 && S_ISLNK(sb.st_mode));
    bvox__bytes b;
    CHECK_OK(bvox__read_file(real, &b));
    CHECK_EQ(b.size, 4);
    CHECK(memcmp(b.data, "new!", 4) == 0);
    bvox__bytes_release(&b);
    CHECK_EQ(harness_count_entries(sub), 1);
    CHECK_EQ(harness_count_entries(harness_tmpdir()), 3);
    CHECK(symlink("sub/made.json", harness_path("dangling.json")) == 0);
    CHECK_OK(bvox_write_file_atomic(harness_path("dangling.json"), "x", 1));
    CHECK_EQ(harness_count_entries(sub), 2);
    CHECK(lstat(harness_path("dangling.json"), &sb) == 0 && S_ISLNK(sb.st_mode));
    return 0;
}

/* Replacing a file keeps its permission bits (a 0600 file used to become
 * 0644); a new file gets 0666 less the umask. */
TEST(sink_keeps_mode_new_follows_umask)
{
    const char *path = harness_path("secret.nii");
    CHECK(write_text(path, "old"));
    CHECK(chmod(path, 0600) == 0);
    CHECK_OK(bvox_write_file_atomic(path, "new", 3));
    struct stat sb;
    CHECK(stat(path, &sb) == 0);
    CHECK_EQ(sb.st_mode & 07777, 0600);
    CHECK(chmod(path, 0751) == 0);
    CHECK_OK(bvox_write_file_atomic(path, "newer", 5));
    CHECK(stat(path, &sb) == 0);
    CHECK_EQ(sb.st_mode & 07777, 0751);
    CHECK_EQ(sb.st_gid, getegid());
    mode_t old = umask(077);
    CHECK_OK(bvox_write_file_atomic(harness_path("fresh.nii"), "x", 1));
    umask(old);
    CHECK(stat(harness_path("fresh.nii"), &sb) == 0);
    CHECK_EQ(sb.st_mode & 07777, 0600);
    return 0;
}

/* The folder is fsync'ed after the rename (else a power loss can undo a
 * committed write): one folder sync per commit. */
TEST(sink_commit_syncs_folder)
{
    long before = bvox__folder_syncs();
    CHECK_OK(bvox_write_file_atomic(harness_path("a.json"), "{}", 2));
    CHECK_EQ(bvox__folder_syncs() - before, 1);
    bvox__sink_fail_after(1);
    CHECK_STATUS(bvox_write_file_atomic(harness_path("a.json"), "{}", 2), BVOX_EIO);
    bvox__sink_fail_after(0);
    CHECK_EQ(bvox__folder_syncs() - before, 1); /* nothing renamed, nothing synced */
    return 0;
}
