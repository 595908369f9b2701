/*
 * stream.c — whole files in memory, gzip decompression with a size cap, and
 * the output sink that never leaves a partial file: everything is written to
 * a temporary file in the target folder, flushed, fsync'ed and renamed over
 * the target only when complete (the rename is atomic within one folder),
 * then the folder is fsync'ed so that the rename survives a power loss.
 * Only regular files are written: a device, FIFO or socket at the output
 * path is refused, a symlink is followed to its final target (the temporary
 * file is made beside that target, so the rename stays within one folder
 * and the link stays a link). Replacing a file keeps its permission bits and
 * group. Folder outputs are in dir_sink.c, temporary names in temp_files.c.
 */
#include "io.h"

#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

/* ------------------------------------------------------------- reading */

/* What a non-regular file is, for messages. */
static const char *file_kind(mode_t m)
{
    return S_ISDIR(m) ? "a folder" : S_ISCHR(m) ? "a character device" : S_ISBLK(m) ? "a block device"
         : S_ISFIFO(m) ? "a FIFO" : S_ISSOCK(m) ? "a socket" : "not a regular file";
}


bvox_status bvox__read_file(const char *path, bvox__bytes *out)
{
    memset(out, 0, sizeof *out);
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait forever for
     * a writer; it is refused below like any file that cannot be sized. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
        return bvox__fail(BVOX_EIO, "%s: cannot open: %s", path, strerror(errno));
    }
    struct stat sb;
    if (fstat(fd, &sb) != 0) {
        int e = errno;
        close(fd);
        return bvox__fail(BVOX_EIO, "%s: cannot open: %s", path, strerror(e));
    }
    if (!S_ISREG(sb.st_mode)) {
        close(fd);
        return bvox__fail(BVOX_EIO, "%s: not a regular file (%s); bvox reads only regular files",
                          path, file_kind(sb.st_mode));
    }
    size_t size = (size_t)sb.st_size;
    bvox_status st;
    uint8_t *buf = bvox__alloc(size, false, "file buffer", &st);
    if (!buf) {
        close(fd);
        bvox__error_prefix(path);
        return st;
    }
    size_t got = 0;
    while (got < size) {
        /* 64 MiB at a time: often enough for the progress callback */
        ssize_t n = read(fd, buf + got, size - got > (1u << 26) ? (1u << 26) : size - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int e = errno;
            close(fd);
            bvox__free(buf, size);
            return bvox__fail(BVOX_EIO, "%s: read failed: %s", path,
                              n < 0 ? strerror(e) : "file shrank while reading");
        }
        got += (size_t)n;
        if ((st = bvox__progress_steps((int64_t)got, (int64_t)size))) {
            close(fd);
            bvox__free(buf, size);
            return st;
        }
    }
    close(fd);
    out->data = buf;
    out->size = size;
    out->alloc_bytes = size;
    return BVOX_OK;
}

void bvox__bytes_release(bvox__bytes *b)
{
    bvox__free(b->data, b->alloc_bytes);
    memset(b, 0, sizeof *b);
}

int bvox__is_gzip(const uint8_t *data, size_t size)
{
    return size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
}

bvox_status bvox__gunzip(const uint8_t *data, size_t size, const char *name, size_t max_bytes,
                         bvox__bytes *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "input";
    size_t budget = bvox_memory_budget();
    if (max_bytes == 0 || max_bytes > budget) max_bytes = budget;
    /* Start from the size in the gzip trailer (mod 2^32, so only a hint) and
     * grow geometrically: never more than max_bytes. */
    size_t cap = size * 4 + 4096;
    if (size >= 4) {
        uint32_t isize = (uint32_t)data[size - 4] | (uint32_t)data[size - 3] << 8 |
                         (uint32_t)data[size - 2] << 16 | (uint32_t)data[size - 1] << 24;
        if (isize > cap) cap = isize;
    }
    if (cap > max_bytes) cap = max_bytes;
    if (cap == 0) cap = 1;
    bvox_status st;
    uint8_t *buf = bvox__alloc(cap, false, "decompressed data", &st);
    if (!buf) {
        bvox__error_prefix(name);
        return st;
    }
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 32) != Z_OK) {
        bvox__free(buf, cap);
        return bvox__fail(BVOX_ENOMEM, "%s: cannot start zlib", name);
    }
    size_t in_off = 0, produced = 0;
    int rc = Z_OK;
    for (;;) {
        if (produced == cap) {
            if (cap >= max_bytes) {
                /* more output than allowed: only fail if there is more to come */
                uint8_t probe;
                z.next_out = &probe;
                z.avail_out = 1;
                rc = inflate(&z, Z_NO_FLUSH);
                if (rc == Z_STREAM_END && z.avail_out == 1) break;
                inflateEnd(&z);
                bvox__free(buf, cap);
                return bvox__fail(BVOX_ETOOBIG,
                                  "%s: decompresses to more than %zu bytes (the most this "
                                  "file's header or the memory budget allows)",
                                  name, max_bytes);
            }
            size_t ncap = cap * 2 < cap || cap * 2 > max_bytes ? max_bytes : cap * 2;
            uint8_t *nbuf = bvox__alloc(ncap, false, "decompressed data", &st);
            if (!nbuf) {
                inflateEnd(&z);
                bvox__free(buf, cap);
                bvox__error_prefix(name);
                return st;
            }
            memcpy(nbuf, buf, produced);
            bvox__free(buf, cap);
            buf = nbuf;
            cap = ncap;
        }
        size_t in_left = size - in_off, out_left = cap - produced;
        z.next_in = (Bytef *)(data + in_off);
        /* 4 MiB of input at a time, so that progress is reported */
        z.avail_in = in_left > (1u << 22) ? (1u << 22) : (uInt)in_left;
        z.next_out = buf + produced;
        z.avail_out = out_left > UINT32_MAX ? UINT32_MAX : (uInt)out_left;
        uInt ain = z.avail_in, aout = z.avail_out;
        rc = inflate(&z, Z_NO_FLUSH);
        in_off += ain - z.avail_in;
        produced += aout - z.avail_out;
        if (rc == Z_STREAM_END) {
            /* concatenated gzip members: continue if more input follows */
            if (in_off + 2 <= size && bvox__is_gzip(data + in_off, size - in_off)) {
                inflateReset(&z);
                continue;
            }
            break;
        }
        if (rc == Z_BUF_ERROR && in_off >= size) {
            inflateEnd(&z);
            bvox__free(buf, cap);
            return bvox__fail(BVOX_EFORMAT, "%s: truncated gzip stream", name);
        }
        if (rc != Z_OK && rc != Z_BUF_ERROR) {
            inflateEnd(&z);
            bvox__free(buf, cap);
            return bvox__fail(BVOX_EFORMAT, "%s: corrupt gzip data (%s)", name,
                              z.msg ? z.msg : "zlib error");
        }
        /* decompressing is most of reading a .gz: half of the range */
        if ((st = bvox__progress(0.5 * (double)in_off / (double)size))) {
            inflateEnd(&z);
            bvox__free(buf, cap);
            return st;
        }
    }
    inflateEnd(&z);
    out->data = buf;
    out->size = produced;
    out->alloc_bytes = cap;
    return BVOX_OK;
}

/* ------------------------------------------------------------- writing */

static atomic_long sink_fail_countdown;
static atomic_long folder_syncs;

void bvox__sink_fail_after(long n) { atomic_store(&sink_fail_countdown, n); }
long bvox__folder_syncs(void) { return atomic_load(&folder_syncs); }

bool bvox__sync_parent(const char *path)
{
    /* no allocation here: this runs after the rename, when a failure could
     * only misreport a finished write */
    char dir[PATH_MAX];
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (slash == path ? 1 : (size_t)(slash - path)) : 1;
    if (n >= sizeof dir) return true; /* cannot name it: leave it unsynced */
    if (slash) memcpy(dir, path, n);
    else dir[0] = '.';
    dir[n] = '\0';
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return true; /* a folder we may write but not read: cannot sync it */
    int rc = fsync(fd), e = errno;
    close(fd);
    if (rc == 0) atomic_fetch_add(&folder_syncs, 1);
    errno = e;
    return rc == 0 || e == EINVAL; /* EINVAL: this file system cannot sync folders */
}

/* Follow path while it is a symlink (relative targets are relative to the
 * link's folder). *out: the final path (free() it); *sb its lstat, or
 * *exists = false when nothing is there yet. errno on failure. */
bool bvox__resolve_output(const char *path, char **out, struct stat *sb, bool *exists)
{
    char *cur = bvox__mem_strdup(path);
    if (!cur) errno = ENOMEM;
    for (int hops = 0; cur; hops++) {
        if (lstat(cur, sb) != 0) {
            if (errno != ENOENT) break;
            *exists = false;
            *out = cur;
            return true;
        }
        if (!S_ISLNK(sb->st_mode)) {
            *exists = true;
            *out = cur;
            return true;
        }
        if (hops == 40) {
            errno = ELOOP;
            break;
        }
        char link[PATH_MAX];
        ssize_t n = readlink(cur, link, sizeof link - 1);
        if (n < 0) break;
        link[n] = '\0';
        const char *slash = strrchr(cur, '/');
        size_t dirlen = link[0] != '/' && slash ? (size_t)(slash - cur + 1) : 0;
        char *next = bvox__mem_alloc(dirlen + (size_t)n + 1);
        if (next) {
            memcpy(next, cur, dirlen);
            memcpy(next + dirlen, link, (size_t)n + 1);
        }
        free(cur);
        cur = next;
        if (!cur) errno = ENOMEM;
    }
    int e = errno;
    free(cur);
    errno = e;
    return false;
}

static void sink_release(bvox__sink *s)
{
    if (s->gz) {
        deflateEnd(s->gz);
        free(s->gz);
    }
    if (s->file) fclose(s->file);
    bvox__temp_unregister(s->slot);
    free(s->tmp_path);
    free(s->final_path);
    free(s->name);
    memset(s, 0, sizeof *s);
    s->slot = -1;
}

bvox_status bvox__sink_open(const char *path, int gzip, bvox__sink *s)
{
    memset(s, 0, sizeof *s);
    s->slot = -1;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    if (!*base) return bvox__fail(BVOX_EINVAL, "%s: output path names a folder, not a file", path);
    if (!(s->name = bvox__mem_strdup(path))) return bvox__fail(BVOX_ENOMEM, "out of memory");
    struct stat old;
    bool exists;
    if (!bvox__resolve_output(path, &s->final_path, &old, &exists)) {
        int e = errno;
        sink_release(s);
        return bvox__fail(e == ENOMEM ? BVOX_ENOMEM : BVOX_EIO, "%s: cannot follow the path: %s",
                          path, strerror(e));
    }
    /* bvox writes regular files only: renaming over a device or a FIFO
     * would replace it (run as root against /dev/null, the system's). */
    if (exists && !S_ISREG(old.st_mode)) {
        sink_release(s);
        return bvox__fail(BVOX_EIO, "%s: is %s; bvox writes only regular files", path,
                          file_kind(old.st_mode));
    }
    s->tmp_path = bvox__temp_name(s->final_path);
    if (!s->tmp_path) {
        sink_release(s);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    int fd = bvox__temp_create(s->tmp_path, false);
    if (fd < 0) {
        int e = errno;
        sink_release(s);
        return bvox__fail(e == ENOENT ? BVOX_ENOTFOUND : BVOX_EIO, "%s: cannot create: %s",
                          path, e == ENOENT ? "no such folder" : strerror(e));
    }
    s->slot = bvox__temp_register(s->tmp_path, false);
    if (exists) {
        /* replacing a file keeps its permissions and group (the owner too
         * when run as root); new files got 0666 less the umask from open */
        if (fchown(fd, old.st_uid, old.st_gid) != 0 && fchown(fd, (uid_t)-1, old.st_gid) != 0) {
            /* not a member of that group: the file keeps ours */
        }
        fchmod(fd, old.st_mode & 01777); /* never set-user/group-ID on new content */
    }
    s->file = fdopen(fd, "wb");
    if (!s->file) {
        close(fd);
        unlink(s->tmp_path);
        sink_release(s);
        return bvox__fail(BVOX_EIO, "%s: cannot open for writing", path);
    }
    if (gzip) {
        bvox_status st = bvox__sink_compress(s, gzip);
        if (st) {
            bvox__sink_abort(s);
            return st;
        }
    }
    return BVOX_OK;
}

bvox_status bvox__sink_compress(bvox__sink *s, int mode)
{
    if (s->gz) return BVOX_OK;
    z_stream *z = bvox__mem_zalloc(1, sizeof *z);
    if (!z || deflateInit2(z, 6, Z_DEFLATED, mode == BVOX__SINK_ZLIB ? 15 : 15 + 16, 8,
                           Z_DEFAULT_STRATEGY) != Z_OK) {
        free(z);
        s->failed = true;
        return s->status = bvox__fail(BVOX_ENOMEM, "%s: cannot start zlib", s->name);
    }
    s->gz = z;
    return BVOX_OK;
}

static bool raw_write(bvox__sink *s, const void *data, size_t size)
{
    long c = atomic_load(&sink_fail_countdown);
    if (c > 0 && atomic_fetch_sub(&sink_fail_countdown, 1) == 1) {
        errno = ENOSPC; /* injected */
        return false;
    }
    return fwrite(data, 1, size, s->file) == size;
}

static bvox_status write_failed(bvox__sink *s)
{
    s->failed = true;
    s->status = bvox__fail(BVOX_EIO, "%s: write failed: %s", s->name, strerror(errno));
    return s->status;
}

static bvox_status deflate_some(bvox__sink *s, int flush)
{
    z_stream *z = s->gz;
    uint8_t out[1 << 16];
    int rc;
    do {
        z->next_out = out;
        z->avail_out = sizeof out;
        rc = deflate(z, flush);
        if (rc == Z_STREAM_ERROR) {
            s->failed = true;
            return s->status = bvox__fail(BVOX_EIO, "%s: zlib error", s->name);
        }
        size_t n = sizeof out - z->avail_out;
        if (n && !raw_write(s, out, n)) return write_failed(s);
    } while (z->avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
    return BVOX_OK;
}

bvox_status bvox__sink_write(bvox__sink *s, const void *data, size_t size)
{
    if (s->failed) return s->status;
    if (!s->gz) return raw_write(s, data, size) ? BVOX_OK : write_failed(s);
    const uint8_t *p = data;
    while (size) {
        size_t n = size > (1u << 30) ? (1u << 30) : size;
        ((z_stream *)s->gz)->next_in = (Bytef *)p;
        ((z_stream *)s->gz)->avail_in = (uInt)n;
        bvox_status st = deflate_some(s, Z_NO_FLUSH);
        if (st) return st;
        p += n;
        size -= n;
    }
    return BVOX_OK;
}

bvox_status bvox__sink_commit(bvox__sink *s)
{
    bvox_status st = s->failed ? s->status : BVOX_OK;
    if (!st && s->gz) st = deflate_some(s, Z_FINISH);
    if (!st && fflush(s->file) != 0) st = write_failed(s);
    if (!st && fsync(fileno(s->file)) != 0) st = write_failed(s);
    if (st) {
        bvox__sink_abort(s);
        return st;
    }
    int rc = fclose(s->file);
    s->file = NULL;
    if (rc != 0) {
        st = write_failed(s);
        bvox__sink_abort(s);
        return st;
    }
    /* the target may have become a folder or a device since the open */
    struct stat sb;
    if (lstat(s->final_path, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        st = bvox__fail(BVOX_EIO, "%s: is %s; bvox writes only regular files", s->name,
                        file_kind(sb.st_mode));
        bvox__sink_abort(s);
        return st;
    }
    if (rename(s->tmp_path, s->final_path) != 0) {
        st = bvox__fail(BVOX_EIO, "%s: cannot rename the finished file into place: %s",
                        s->name, strerror(errno));
        bvox__sink_abort(s);
        return st;
    }
    /* the rename itself is on disk only once the folder is */
    if (!bvox__sync_parent(s->final_path))
        st = bvox__fail(BVOX_EIO, "%s: written, but its folder could not be synced: %s", s->name,
                        strerror(errno));
    sink_release(s);
    return st;
}

bvox_status bvox__sink_pwrite(bvox__sink *s, uint64_t offset, const void *data, size_t size)
{
    if (s->failed) return s->status;
    if (s->gz) return bvox__fail(BVOX_EINVAL, "%s: cannot overwrite compressed output", s->name);
    if (fflush(s->file) != 0) return write_failed(s);
    const uint8_t *p = data;
    while (size) {
        ssize_t k = pwrite(fileno(s->file), p, size, (off_t)offset);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return write_failed(s);
        p += k;
        offset += (uint64_t)k;
        size -= (size_t)k;
    }
    return BVOX_OK;
}

void bvox__sink_abort(bvox__sink *s)
{
    if (s->file) {
        fclose(s->file);
        s->file = NULL;
    }
    if (s->tmp_path) unlink(s->tmp_path);
    sink_release(s);
}

bvox_status bvox_write_file_atomic(const char *path, const void *data, size_t size)
{
    bvox__clear_error();
    if (!path || (!data && size)) return bvox__fail(BVOX_EINVAL, "bvox_write_file_atomic: NULL argument");
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, 0, &s);
    if (st) return st;
    if (size) st = bvox__sink_write(&s, data, size);
    if (st) {
        bvox__sink_abort(&s);
        return st;
    }
    return bvox__sink_commit(&s);
}
