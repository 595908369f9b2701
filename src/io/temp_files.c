/*
 * temp_files.c — the temporary files and folders of writes in progress, and
 * their removal when the process is killed by SIGINT, SIGTERM or SIGHUP.
 *
 * Every writer builds its output under a hidden temporary name beside the
 * target (stream.c, dir_sink.c) and renames it into place only when it is
 * complete. A Ctrl-C in the middle used to leave that temporary behind
 * (hundreds of MB of ".name.XXXXXX"). The names live here, in a fixed table
 * of slots, so that a signal handler can remove them: the handler may call
 * only async-signal-safe functions (no malloc, no stdio, no opendir), so the
 * table is static memory, a slot is published with an atomic store after its
 * path is copied, and a temporary folder is emptied with open, getdents64,
 * unlinkat and rmdir. A slot that is reused while the handler runs can only
 * name a path that is already gone (renamed or removed): unlinking it fails
 * harmlessly.
 *
 * Temporary names are made here too, with open(O_CREAT|O_EXCL, 0666) or
 * mkdir(0777) so that the umask applies (mkstemp makes 0600, and reading the
 * umask to correct it is a process-wide race between threads).
 */
#include "io.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

/* FREE -> BUSY (path being copied) -> FILE/DIR (live) -> FREE, or -> GONE
 * when the signal handler takes it: then the slot is never reused, so the
 * handler cannot read a path while another thread copies a new one in. */
enum { SLOT_FREE, SLOT_BUSY, SLOT_FILE, SLOT_DIR, SLOT_GONE };
#define NSLOTS 64

static struct {
    atomic_int state;
    char path[PATH_MAX];
} slots[NSLOTS];

int bvox__temp_register(const char *path, bool is_dir)
{
    size_t n = strlen(path);
    if (n >= PATH_MAX) return -1; /* not cleaned up on a signal, still on every error */
    for (int i = 0; i < NSLOTS; i++) {
        int expect = SLOT_FREE;
        if (!atomic_compare_exchange_strong(&slots[i].state, &expect, SLOT_BUSY)) continue;
        memcpy(slots[i].path, path, n + 1);
        atomic_store(&slots[i].state, is_dir ? SLOT_DIR : SLOT_FILE);
        return i;
    }
    return -1; /* more than NSLOTS writes at once: the rest are not tracked */
}

void bvox__temp_unregister(int slot)
{
    if (slot < 0 || slot >= NSLOTS) return;
    int s = atomic_load(&slots[slot].state);
    if (s == SLOT_FILE || s == SLOT_DIR) /* not if the handler took it */
        atomic_compare_exchange_strong(&slots[slot].state, &s, SLOT_FREE);
}

/* ------------------------------------------------- temporary names */

static atomic_uint_fast64_t name_counter;

/* Replace the trailing "XXXXXX" of t with 6 characters from a per-process
 * counter mixed with the pid and the clock: O_EXCL decides uniqueness. */
static void fill_name(char *t)
{
    static const char digits[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t x = atomic_fetch_add(&name_counter, 1) * 0x9E3779B97F4A7C15ull;
    x ^= (uint64_t)getpid() << 32 ^ (uint64_t)ts.tv_nsec ^ (uint64_t)ts.tv_sec << 20;
    x ^= x >> 29;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 32;
    char *p = t + strlen(t) - 6;
    for (int i = 0; i < 6; i++, x /= 62) p[i] = digits[x % 62];
}

char *bvox__temp_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path + 1) : 0;
    const char *base = slash ? slash + 1 : path;
    size_t n = strlen(path) + 16;
    char *t = bvox__mem_alloc(n);
    /* ".NAME.XXXXXX" must itself be a valid name: a long NAME is cut */
    int keep = (int)strlen(base) > NAME_MAX - 8 ? NAME_MAX - 8 : (int)strlen(base);
    if (t) snprintf(t, n, "%.*s.%.*s.XXXXXX", (int)dirlen, path, keep, base);
    return t;
}

int bvox__temp_create(char *templ, bool is_dir)
{
    for (int tries = 0; tries < 100; tries++) {
        fill_name(templ);
        if (is_dir) {
            if (mkdir(templ, 0777) == 0) return 0;
        } else {
            int fd = open(templ, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (fd >= 0) return fd;
        }
        if (errno != EEXIST) return -1;
    }
    return -1;
}

/* --------------------------------------------------- signal cleanup */

struct dirent64_raw { /* the kernel's struct linux_dirent64 */
    uint64_t ino;
    int64_t off;
    unsigned short reclen;
    unsigned char type;
    char name[];
};

/* Empty and remove a temporary folder, async-signal-safely. The writers put
 * plain files in their temporary folders, and the Zarr writer folders of
 * them (levels, nested chunk keys): depth bounds the descent. */
static bool remove_dir_signal_safe_at(int parent, const char *dir, int depth)
{
    int fd = openat(parent, dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
    if (fd >= 0) {
        char buf[4096] __attribute__((aligned(8)));
        for (;;) {
            long n = syscall(SYS_getdents64, fd, buf, sizeof buf);
            if (n <= 0) break;
            for (long off = 0; off < n;) {
                struct dirent64_raw *e = (struct dirent64_raw *)(buf + off);
                off += e->reclen;
                const char *s = e->name;
                if (s[0] == '.' && (!s[1] || (s[1] == '.' && !s[2]))) continue;
                if (unlinkat(fd, s, 0) != 0 && errno == EISDIR && depth > 0 &&
                    remove_dir_signal_safe_at(fd, s, depth - 1)) {
                    /* the entries after it may move: read the folder again */
                    lseek(fd, 0, SEEK_SET);
                    break;
                }
            }
        }
        close(fd);
    }
    return unlinkat(parent, dir, AT_REMOVEDIR) == 0;
}

static void remove_dir_signal_safe(const char *dir)
{
    (void)remove_dir_signal_safe_at(AT_FDCWD, dir, 3);
}

void bvox__temp_remove_all_signal_safe(void)
{
    for (int i = 0; i < NSLOTS; i++) {
        int s = atomic_load(&slots[i].state);
        if ((s != SLOT_FILE && s != SLOT_DIR) ||
            !atomic_compare_exchange_strong(&slots[i].state, &s, SLOT_GONE))
            continue;
        if (s == SLOT_FILE) unlink(slots[i].path);
        else remove_dir_signal_safe(slots[i].path);
    }
}

void bvox_remove_temp_files(void) { bvox__temp_remove_all_signal_safe(); }

static const int cleanup_signals[] = {SIGINT, SIGTERM, SIGHUP};

static void on_signal(int sig)
{
    int saved = errno;
    bvox__temp_remove_all_signal_safe();
    /* SA_RESETHAND put the default action back: raise the signal again so the
     * process ends the way it would have without us (exit status, core). */
    raise(sig);
    errno = saved;
}

bvox_status bvox_cleanup_on_signals(void)
{
    bvox__clear_error();
    for (size_t i = 0; i < sizeof cleanup_signals / sizeof cleanup_signals[0]; i++) {
        struct sigaction old;
        if (sigaction(cleanup_signals[i], NULL, &old) != 0)
            return bvox__fail(BVOX_EIO, "cannot read the action of signal %d", cleanup_signals[i]);
        /* ignored (nohup) or handled by the application: leave it so */
        if ((old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        for (size_t k = 0; k < sizeof cleanup_signals / sizeof cleanup_signals[0]; k++)
            sigaddset(&sa.sa_mask, cleanup_signals[k]); /* one cleanup at a time */
        sa.sa_flags = SA_RESETHAND;
        if (sigaction(cleanup_signals[i], &sa, NULL) != 0)
            return bvox__fail(BVOX_EIO, "cannot install a handler for signal %d", cleanup_signals[i]);
    }
    return BVOX_OK;
}
