/* test_temp_files.c — temporary names follow the umask, and a process killed
 * by SIGINT, SIGTERM or SIGHUP in the middle of a write leaves no temporary
 * file or folder behind (bvox_cleanup_on_signals): a child is stopped
 * mid-write, killed, and the folder listed. */
#include "harness.h"
#include "io/io.h"
#include "io/zarr.h"

#include <dirent.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* In the child: start a write into dir (a file, or a PNG folder with one
 * slice written), tell the parent, and wait to be killed. */
static void child(const char *dir, int folder, int ready)
{
    if (bvox_cleanup_on_signals()) _exit(3);
    char path[1100];
    snprintf(path, sizeof path, "%s/out%s", dir, folder == 2 ? ".zarr" : folder ? "" : ".nii");
    bvox__sink s;
    bvox__dir_sink d;
    if (folder == 2) { /* a Zarr tree: level folders holding chunk files */
        bvox__zarr_writer *w;
        bvox_volume *v;
        const int32_t chunks[3] = {4, 4, 4};
        if (bvox__zarr_create(path, (bvox_dims){8, 8, 8}, chunks, NULL, NULL, 0, false, &w) ||
            bvox_volume_create((bvox_dims){4, 4, 4}, &v) || bvox_volume_set(v, 1, 2, 3, 1) ||
            bvox__zarr_write_box(w, 4, 0, 4, v))
            _exit(4);
    } else if (folder) {
        if (bvox__dir_sink_open(path, BVOX__DIR_PNG_SLICES, false, &d)) _exit(4);
        char f[1200];
        snprintf(f, sizeof f, "%s/slice_0000.png", d.tmp);
        FILE *fp = fopen(f, "wb");
        if (!fp || fputs("partial", fp) < 0 || fclose(fp)) _exit(5);
    } else {
        if (bvox__sink_open(path, 1, &s) || bvox__sink_write(&s, "partial", 7)) _exit(4);
        fflush(s.file);
    }
    if (write(ready, "x", 1) != 1) _exit(6);
    for (;;) pause();
}

static int kill_mid_write(int sig, int folder)
{
    char dir[1100];
    snprintf(dir, sizeof dir, "%s", harness_path(folder == 2 ? "zarr" : folder ? "dir" : "file"));
    CHECK(mkdir(dir, 0777) == 0);
    int p[2];
    CHECK(pipe(p) == 0);
    pid_t pid = fork();
    CHECK(pid >= 0);
    if (pid == 0) {
        close(p[0]);
        child(dir, folder, p[1]);
    }
    close(p[1]);
    char c;
    CHECK_EQ(read(p[0], &c, 1), 1);
    close(p[0]);
    CHECK_EQ(harness_count_entries(dir), 1); /* the temporary is there */
    CHECK(kill(pid, sig) == 0);
    int status;
    CHECK(waitpid(pid, &status, 0) == pid);
    CHECK(WIFSIGNALED(status)); /* ended by the signal, as without the handler */
    CHECK_EQ(WTERMSIG(status), sig);
    CHECK_EQ(harness_count_entries(dir), 0); /* and nothing left */
    return 0;
}

TEST(sigint_removes_temp_file) { return kill_mid_write(SIGINT, 0); }
TEST(sigterm_removes_temp_file) { return kill_mid_write(SIGTERM, 0); }
TEST(sighup_removes_temp_file) { return kill_mid_write(SIGHUP, 0); }
TEST(sigint_removes_temp_folder) { return kill_mid_write(SIGINT, 1); }
TEST(sigterm_removes_temp_folder) { return kill_mid_write(SIGTERM, 1); }
TEST(sigterm_removes_temp_zarr_tree) { return kill_mid_write(SIGTERM, 2); }

/* An ignored signal stays ignored (nohup): the handler is not installed. */
TEST(ignored_signal_left_alone)
{
    struct sigaction old, ign, now;
    memset(&ign, 0, sizeof ign);
    ign.sa_handler = SIG_IGN;
    CHECK(sigaction(SIGHUP, &ign, &old) == 0);
    CHECK_OK(bvox_cleanup_on_signals());
    CHECK(sigaction(SIGHUP, &old, &now) == 0);
    CHECK(now.sa_handler == SIG_IGN);
    return 0;
}

/* Temporary files and folders get 0666 / 0777 less the umask (mkstemp's
 * 0600 used to be widened with a hard-coded 022 for folders). */
TEST(temp_names_follow_umask)
{
    mode_t old = umask(027);
    char *t = bvox__temp_name(harness_path("x.nii"));
    CHECK(t != NULL);
    int fd = bvox__temp_create(t, false);
    CHECK(fd >= 0);
    struct stat sb;
    CHECK(fstat(fd, &sb) == 0);
    CHECK_EQ(sb.st_mode & 0777, 0640);
    close(fd);
    CHECK(strstr(t, "/.x.nii.") != NULL);
    unlink(t);
    free(t);
    t = bvox__temp_name(harness_path("slices"));
    CHECK(bvox__temp_create(t, true) == 0);
    CHECK(stat(t, &sb) == 0);
    CHECK_EQ(sb.st_mode & 0777, 0750);
    rmdir(t);
    free(t);
    umask(old);
    return 0;
}
