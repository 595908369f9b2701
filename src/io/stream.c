/*
 * stream.c — whole files in memory, gzip decompression with a size cap, and
 * the output sink that never leaves a partial file: everything is written to
 * a temporary file in the target folder, flushed, fsync'ed and renamed over
 * the target only when complete (the rename is atomic within one folder).
 */
#include "io.h"

#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

/* ------------------------------------------------------------- reading */

bvox_status bvox__read_file(const char *path, bvox__bytes *out)
{
    memset(out, 0, sizeof *out);
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file", path);
        return bvox__fail(BVOX_EIO, "%s: cannot open: %s", path, strerror(errno));
    }
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return bvox__fail(BVOX_EIO, "%s: not a regular file", path);
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
        ssize_t n = read(fd, buf + got, size - got > (1u << 30) ? (1u << 30) : size - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int e = errno;
            close(fd);
            bvox__free(buf, size);
            return bvox__fail(BVOX_EIO, "%s: read failed: %s", path,
                              n < 0 ? strerror(e) : "file shrank while reading");
        }
        got += (size_t)n;
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
        z.avail_in = in_left > UINT32_MAX ? UINT32_MAX : (uInt)in_left;
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
    }
    inflateEnd(&z);
    out->data = buf;
    out->size = produced;
    out->alloc_bytes = cap;
    return BVOX_OK;
}

/* ------------------------------------------------------------- writing */

static atomic_long sink_fail_countdown;

void bvox__sink_fail_after(long n) { atomic_store(&sink_fail_countdown, n); }

static char *temp_name_for(const char *path)
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

static void sink_release(bvox__sink *s)
{
    if (s->gz) {
        deflateEnd(s->gz);
        free(s->gz);
    }
    if (s->file) fclose(s->file);
    free(s->tmp_path);
    free(s->final_path);
    memset(s, 0, sizeof *s);
}

bvox_status bvox__sink_open(const char *path, int gzip, bvox__sink *s)
{
    memset(s, 0, sizeof *s);
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    if (!*base) return bvox__fail(BVOX_EINVAL, "%s: output path names a folder, not a file", path);
    s->final_path = bvox__mem_strdup(path);
    s->tmp_path = temp_name_for(path);
    if (!s->final_path || !s->tmp_path) {
        sink_release(s);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    int fd = mkstemp(s->tmp_path);
    if (fd < 0) {
        int e = errno;
        sink_release(s);
        return bvox__fail(e == ENOENT ? BVOX_ENOTFOUND : BVOX_EIO, "%s: cannot create: %s",
                          path, e == ENOENT ? "no such folder" : strerror(e));
    }
    /* mkstemp makes 0600; give the file the usual permissions (umask applies) */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    s->file = fdopen(fd, "wb");
    if (!s->file) {
        close(fd);
        unlink(s->tmp_path);
        sink_release(s);
        return bvox__fail(BVOX_EIO, "%s: cannot open for writing", path);
    }
    if (gzip) {
        z_stream *z = bvox__mem_zalloc(1, sizeof *z);
        if (!z || deflateInit2(z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
            free(z);
            bvox__sink_abort(s);
            return bvox__fail(BVOX_ENOMEM, "%s: cannot start zlib", path);
        }
        s->gz = z;
    }
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
    s->status = bvox__fail(BVOX_EIO, "%s: write failed: %s", s->final_path, strerror(errno));
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
            return s->status = bvox__fail(BVOX_EIO, "%s: zlib error", s->final_path);
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
    if (rename(s->tmp_path, s->final_path) != 0) {
        st = bvox__fail(BVOX_EIO, "%s: cannot rename the finished file into place: %s",
                        s->final_path, strerror(errno));
        bvox__sink_abort(s);
        return st;
    }
    sink_release(s);
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

/* ---------------------------------------------------- folder outputs */

bvox_status bvox__dir_sink_open(const char *path, char **tmp_dir)
{
    *tmp_dir = NULL;
    size_t len = strlen(path);
    while (len > 1 && path[len - 1] == '/') len--;
    char *trimmed = bvox__mem_strndup(path, len);
    if (!trimmed) return bvox__fail(BVOX_ENOMEM, "out of memory");
    struct stat sb;
    if (stat(trimmed, &sb) == 0 && !S_ISDIR(sb.st_mode)) {
        free(trimmed);
        return bvox__fail(BVOX_EIO, "%s: exists and is not a folder", path);
    }
    char *t = temp_name_for(trimmed);
    free(trimmed);
    if (!t) return bvox__fail(BVOX_ENOMEM, "out of memory");
    if (!mkdtemp(t)) {
        int e = errno;
        free(t);
        return bvox__fail(e == ENOENT ? BVOX_ENOTFOUND : BVOX_EIO, "%s: cannot create: %s",
                          path, e == ENOENT ? "no such parent folder" : strerror(e));
    }
    chmod(t, 0777 & ~(mode_t)0022);
    *tmp_dir = t;
    return BVOX_OK;
}

static void remove_dir_tree(const char *dir);
static bool sync_dir_files(const char *dir);

static bvox_status dir_commit(const char *tmp_dir, const char *path);

bvox_status bvox__dir_sink_commit(const char *tmp_dir, const char *path)
{
    bvox_status st = dir_commit(tmp_dir, path);
    if (st) remove_dir_tree(tmp_dir); /* a failed commit leaves no partial folder */
    return st;
}

static bvox_status dir_commit(const char *tmp_dir, const char *path)
{
    /* the files must be on disk before the folder is renamed into place */
    if (!sync_dir_files(tmp_dir))
        return bvox__fail(BVOX_EIO, "%s: cannot sync the written files: %s", path,
                          strerror(errno));
    size_t len = strlen(path);
    while (len > 1 && path[len - 1] == '/') len--;
    char *target = bvox__mem_strndup(path, len);
    if (!target) return bvox__fail(BVOX_ENOMEM, "out of memory");
    /* rename(2) replaces an empty folder only: move an existing one aside first,
     * and remove it once the new one is in place. */
    char *old = NULL;
    struct stat sb;
    if (stat(target, &sb) == 0) {
        size_t n = len + 16;
        old = bvox__mem_alloc(n);
        if (!old) {
            free(target);
            return bvox__fail(BVOX_ENOMEM, "out of memory");
        }
        snprintf(old, n, "%s.old.XXXXXX", target);
        if (!mkdtemp(old) || rename(target, old) != 0) {
            bvox_status st = bvox__fail(BVOX_EIO, "%s: cannot replace the existing folder: %s",
                                        path, strerror(errno));
            rmdir(old);
            free(old);
            free(target);
            return st;
        }
    }
    if (rename(tmp_dir, target) != 0) {
        bvox_status st = bvox__fail(BVOX_EIO, "%s: cannot rename the finished folder into place: %s",
                                    path, strerror(errno));
        if (old) rename(old, target); /* put the old one back */
        free(old);
        free(target);
        return st;
    }
    if (old) remove_dir_tree(old);
    free(old);
    free(target);
    return BVOX_OK;
}

#include <dirent.h>

static bool sync_dir_files(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return false;
    bool ok = true;
    struct dirent *e;
    while (ok && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        int fd = openat(dirfd(d), e->d_name, O_RDONLY | O_CLOEXEC);
        if (fd < 0 || fsync(fd) != 0) ok = false;
        if (fd >= 0) close(fd);
    }
    if (ok && fsync(dirfd(d)) != 0) ok = false;
    closedir(d);
    return ok;
}

/* Remove what the folder open as dfd holds, then close dfd. Works on names
 * relative to the folder, so cleaning up after a failed write never needs
 * an allocation that could itself fail. */
static void remove_dir_contents(int dfd)
{
    DIR *d = fdopendir(dfd);
    if (!d) {
        close(dfd);
        return;
    }
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        struct stat sb;
        if (fstatat(dirfd(d), e->d_name, &sb, AT_SYMLINK_NOFOLLOW) == 0 && S_ISDIR(sb.st_mode)) {
            int sub = openat(dirfd(d), e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
            if (sub >= 0) remove_dir_contents(sub);
            unlinkat(dirfd(d), e->d_name, AT_REMOVEDIR);
        } else {
            unlinkat(dirfd(d), e->d_name, 0);
        }
    }
    closedir(d);
}

static void remove_dir_tree(const char *dir)
{
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0) remove_dir_contents(fd);
    rmdir(dir);
}

void bvox__dir_sink_abort(const char *tmp_dir)
{
    if (tmp_dir) remove_dir_tree(tmp_dir);
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
