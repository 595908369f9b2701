/*
 * dir_sink.c — folder outputs (PNG slices, SVG sections) that never delete a
 * file bvox did not write.
 *
 * The files are written into a temporary folder beside the target, then put
 * in place (io.h gives the rules): a new folder is renamed into place whole;
 * an empty folder, or one that holds only bvox's earlier output of the same
 * kind, gets the new files renamed into it one by one and loses only the
 * files of the earlier output that are not written again; anything else is
 * refused unless forced, and forcing only adds or replaces files of bvox's
 * own names. The earlier output is recognised by a manifest, MANIFEST_NAME:
 *
 *     bvox output manifest 1
 *     kind png-slices
 *     slice_0000.png
 *     ...
 *
 * Every listed name must have the kind's pattern (slice_<digits>.png, and
 * the slices' voxel_size.txt), so a
 * manifest made by someone else can at most name files that look like
 * bvox's. While files are moved in, the manifest lists the old and the new
 * files together, so an interrupted replace leaves nothing unlisted and the
 * next run cleans up. The folder itself (its mode, owner, inode) is kept.
 * The replace is atomic per file, not for the folder as a whole.
 *
 * A Zarr tree (kind zarr) holds folders of chunk files, so it is put in
 * place whole instead (commit_tree): renamed onto a new or empty target, or,
 * when forced, swapped with bvox's own earlier tree, which is then removed.
 */
#define _GNU_SOURCE /* renameat2 (RENAME_EXCHANGE) */
#include "io.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const struct {
    const char *name, *prefix, *suffix;
} kinds[] = {
    [BVOX__DIR_PNG_SLICES] = {"png-slices", "slice_", ".png"},
    [BVOX__DIR_SVG_SECTIONS] = {"svg-sections", "section_", ".svg"},
    [BVOX__DIR_LABEL_MESHES] = {"label-meshes", "", ""},
    [BVOX__DIR_ZARR] = {"zarr", "", ""},
    [BVOX__DIR_DEMO] = {"demo", "section_", ".png"},
};

const char *const bvox__demo_file_names[] = {
    "specimen.nii.gz", "specimen.tif", "model.nii.gz", "picture1.png", "picture2.png",
    "picture3.png",    "picture4.png", "turntable.gif",
    /* issue 18: the smooth-shaded pictures beside the paper's */
    "picture1_smooth.png", "picture3_smooth.png",
    /* issue 18, item 3: the paper's pre-image methods in its pictures */
    "picture1_preimage.png", "picture2_enlarged.png", "picture3_enlarged.png", NULL};
#define NKINDS (sizeof kinds / sizeof kinds[0])
#define MANIFEST_HEADER "bvox output manifest 1"
#define MANIFEST_MAX (16u << 20) /* 65535 names of ~20 bytes fit many times */

/* prefix, one or more digits, suffix: the only names bvox ever removes */
/* LABEL[_NAME].EXT: digits, then '_' and the cleaned name's characters
 * (bvox_label_file_name), then a mesh extension */
static bool label_mesh_name(const char *s)
{
    size_t i = 0, n = strlen(s);
    while (i < n && s[i] >= '0' && s[i] <= '9') i++;
    if (i == 0) return false;
    const char *dot = strrchr(s, '.');
    if (!dot || (size_t)(dot - s) < i) return false;
    if (strcmp(dot, ".stl") && strcmp(dot, ".ply") && strcmp(dot, ".obj") && strcmp(dot, ".off"))
        return false;
    if (s + i != dot && s[i] != '_') return false;
    for (const char *p = s + i; p < dot; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
              *p == '-' || *p == '_' || *p == '.'))
            return false;
    return true;
}

/* the top of a Zarr group: its metadata and level folders named by digits */
static bool zarr_top_name(const char *s)
{
    if (!strcmp(s, ".zgroup") || !strcmp(s, ".zattrs") || !strcmp(s, ".zarray")) return true;
    if (!*s || strlen(s) > 9) return false;
    for (; *s; s++)
        if (*s < '0' || *s > '9') return false;
    return true;
}

static bool owned_name(int kind, const char *s)
{
    if (kind == BVOX__DIR_LABEL_MESHES) return label_mesh_name(s);
    if (kind == BVOX__DIR_DEMO)
        for (const char *const *f = bvox__demo_file_names; *f; f++)
            if (!strcmp(s, *f)) return true;
    if (kind == BVOX__DIR_PNG_SLICES && !strcmp(s, BVOX__VOXEL_SIZE_NAME)) return true;
    if (kind == BVOX__DIR_ZARR) return zarr_top_name(s);
    size_t np = strlen(kinds[kind].prefix), ns = strlen(kinds[kind].suffix), n = strlen(s);
    if (n <= np + ns || strncmp(s, kinds[kind].prefix, np) || strcmp(s + n - ns, kinds[kind].suffix))
        return false;
    for (size_t i = np; i < n - ns; i++)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}

typedef struct {
    char **v;
    size_t n, cap;
} names;

static void names_free(names *l)
{
    for (size_t i = 0; i < l->n; i++) free(l->v[i]);
    free(l->v);
    memset(l, 0, sizeof *l);
}

static bool names_add(names *l, const char *s, size_t len)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 64;
        char **v = bvox__mem_resize(l->v, cap * sizeof *v);
        if (!v) return false;
        l->v = v;
        l->cap = cap;
    }
    char *c = bvox__mem_strndup(s, len);
    if (!c) return false;
    l->v[l->n++] = c;
    return true;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void names_sort(names *l)
{
    if (l->n) qsort(l->v, l->n, sizeof *l->v, cmp_str);
}

static bool names_has(const names *l, const char *s)
{
    return l->n && bsearch(&s, l->v, l->n, sizeof *l->v, cmp_str) != NULL;
}

/* ---------------------------------------------------------- manifest */

enum { MF_NONE, MF_OK, MF_OTHER_KIND, MF_BAD, MF_NOMEM };

/* Read dir's manifest into *listed (sorted). *other: the kind it names when
 * MF_OTHER_KIND. */
static int manifest_read(int dirfd, int kind, names *listed, const char **other)
{
    memset(listed, 0, sizeof *listed);
    int fd = openat(dirfd, BVOX__MANIFEST_NAME, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return errno == ENOENT ? MF_NONE : MF_BAD;
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || (uint64_t)sb.st_size > MANIFEST_MAX) {
        close(fd);
        return MF_BAD;
    }
    size_t size = (size_t)sb.st_size, got = 0;
    char *buf = bvox__mem_alloc(size + 1);
    if (!buf) {
        close(fd);
        return MF_NOMEM;
    }
    while (buf && got < size) {
        ssize_t n = read(fd, buf + got, size - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fd);
    if (!buf || got != size) {
        free(buf);
        return MF_BAD;
    }
    buf[size] = '\0';
    int result = MF_OK, line_no = 0;
    const char *kind_name = NULL;
    for (char *p = buf; *p && result == MF_OK; line_no++) {
        char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        p[len] = '\0';
        if (line_no == 0) {
            if (strcmp(p, MANIFEST_HEADER)) result = MF_BAD;
        } else if (line_no == 1) {
            if (strncmp(p, "kind ", 5)) result = MF_BAD;
            kind_name = p + 5;
            for (size_t k = 0; k < NKINDS && result == MF_OK; k++)
                if (!strcmp(kind_name, kinds[k].name) && (int)k != kind) {
                    *other = kinds[k].name;
                    result = MF_OTHER_KIND;
                }
            if (result == MF_OK && strcmp(kind_name, kinds[kind].name)) result = MF_BAD;
        } else if (len && !owned_name(kind, p)) {
            result = MF_BAD;
        } else if (len && !names_add(listed, p, len)) {
            result = MF_NOMEM;
        }
        p += len + (e ? 1 : 0);
    }
    if (line_no < 2 && result == MF_OK) result = MF_BAD;
    free(buf);
    if (result != MF_OK) names_free(listed);
    names_sort(listed);
    return result;
}

/* Write dir/MANIFEST_NAME listing l, atomically (through the file sink). */
static bvox_status manifest_write(const char *dir, int kind, const names *l)
{
    size_t n = strlen(dir) + sizeof BVOX__MANIFEST_NAME + 1;
    char *path = bvox__mem_alloc(n);
    if (!path) return bvox__fail(BVOX_ENOMEM, "out of memory");
    snprintf(path, n, "%s/%s", dir, BVOX__MANIFEST_NAME);
    bvox__sink s;
    bvox_status st = bvox__sink_open(path, 0, &s);
    free(path);
    if (st) return st;
    char head[64];
    int hn = snprintf(head, sizeof head, "%s\nkind %s\n", MANIFEST_HEADER, kinds[kind].name);
    st = bvox__sink_write(&s, head, (size_t)hn);
    for (size_t i = 0; i < l->n && !st; i++) {
        st = bvox__sink_write(&s, l->v[i], strlen(l->v[i]));
        if (!st) st = bvox__sink_write(&s, "\n", 1);
    }
    if (st) {
        bvox__sink_abort(&s);
        return st;
    }
    return bvox__sink_commit(&s);
}

/* ---------------------------------------------------------- survey */

enum { T_ABSENT, T_EMPTY, T_OURS, T_FOREIGN, T_NOTDIR, T_ERROR, T_NOMEM };

typedef struct {
    int state;
    names listed;        /* the manifest's names (T_OURS, or T_FOREIGN with a usable manifest) */
    char offender[256];  /* a name that makes it foreign, for the message */
    const char *other;   /* the other kind, when the manifest names one */
    int err;             /* errno for T_ERROR */
} survey_result;

static void survey(const char *target, int kind, survey_result *r)
{
    memset(r, 0, sizeof *r);
    struct stat sb;
    if (stat(target, &sb) != 0) {
        r->err = errno;
        r->state = errno == ENOENT ? T_ABSENT : T_ERROR;
        return;
    }
    if (!S_ISDIR(sb.st_mode)) {
        r->state = T_NOTDIR;
        return;
    }
    DIR *d = opendir(target);
    if (!d) {
        r->err = errno;
        r->state = T_ERROR;
        return;
    }
    int mf = manifest_read(dirfd(d), kind, &r->listed, &r->other);
    if (mf == MF_NOMEM) {
        closedir(d);
        r->state = T_NOMEM;
        return;
    }
    bool any = false, foreign = false;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *s = e->d_name;
        if (!strcmp(s, ".") || !strcmp(s, "..")) continue;
        any = true;
        if (mf == MF_OK && (!strcmp(s, BVOX__MANIFEST_NAME) || names_has(&r->listed, s))) continue;
        /* the manifest's own temporary file (".<manifest>.XXXXXX"): a writer
         * beside us is replacing it */
        if (!strncmp(s, "." BVOX__MANIFEST_NAME ".", sizeof BVOX__MANIFEST_NAME + 1) &&
            strlen(s) == sizeof BVOX__MANIFEST_NAME + 7)
            continue;
        /* name the first in byte order, a user's file before the manifest */
        bool manifest = !strcmp(s, BVOX__MANIFEST_NAME);
        if (!foreign || (!manifest && (strcmp(s, r->offender) < 0 ||
                                       !strcmp(r->offender, BVOX__MANIFEST_NAME))))
            snprintf(r->offender, sizeof r->offender, "%s", s);
        foreign = true;
    }
    closedir(d);
    r->state = !any ? T_EMPTY : foreign ? T_FOREIGN : T_OURS;
    if (mf != MF_OTHER_KIND) r->other = NULL;
}

/* A Zarr tree replaces a folder whole: only bvox's own earlier tree, and
 * only when forced. */
static bool tree_refused(const survey_result *r, bool force)
{
    return r->state == T_FOREIGN || (r->state == T_OURS && !force);
}

static bvox_status refuse(const char *name, int kind, const survey_result *r, bool force)
{
    if (r->state == T_NOMEM) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    if (r->state == T_NOTDIR) return bvox__fail(BVOX_EIO, "%s: exists and is not a folder", name);
    if (r->state == T_ERROR)
        return bvox__fail(BVOX_EIO, "%s: cannot look into the folder: %s", name, strerror(r->err));
    if (kind == BVOX__DIR_ZARR && r->state == T_OURS && !force)
        return bvox__fail(BVOX_EIO, "%s: exists (bvox's earlier .zarr output); --force replaces it",
                          name);
    if (kind == BVOX__DIR_ZARR && !r->other)
        return bvox__fail(BVOX_EIO, "%s: the folder holds files bvox did not write (such as "
                          "'%s'); a .zarr output goes only into a new or empty folder, or over "
                          "bvox's own earlier .zarr output with --force", name, r->offender);
    if (r->other)
        return bvox__fail(BVOX_EIO, "%s: holds bvox's %s output, not %s; bvox replaces only its "
                          "own output of the same kind (--force adds its files, removing nothing)",
                          name, r->other, kinds[kind].name);
    return bvox__fail(BVOX_EIO, "%s: the folder holds files bvox did not write (such as '%s'); "
                      "a folder output goes only into a new or empty folder or over bvox's own "
                      "earlier output (--force writes into it anyway, removing nothing)",
                      name, r->offender);
}

/* ---------------------------------------------------------- the sink */

static void dir_release(bvox__dir_sink *d)
{
    bvox__temp_unregister(d->slot);
    free(d->target);
    free(d->tmp);
    memset(d, 0, sizeof *d);
    d->slot = -1;
}

/* Remove a folder bvox made (the temporary one, or its own earlier Zarr
 * tree): plain files, and folders up to a few levels (Zarr's level folders
 * and nested chunk keys); links are removed, never followed. */
static void remove_tree_at(int parent, const char *name, int depth)
{
    int fd = openat(parent, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    DIR *d = fd >= 0 ? fdopendir(fd) : NULL;
    if (!d && fd >= 0) close(fd);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d))) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
            if (unlinkat(dirfd(d), e->d_name, 0) != 0 && (errno == EISDIR || errno == EPERM) &&
                depth > 0)
                remove_tree_at(dirfd(d), e->d_name, depth - 1);
        }
        closedir(d);
    }
    unlinkat(parent, name, AT_REMOVEDIR);
}

static void remove_tmp(const char *dir) { remove_tree_at(AT_FDCWD, dir, 4); }

void bvox__dir_sink_abort(bvox__dir_sink *d)
{
    if (d->tmp) remove_tmp(d->tmp);
    dir_release(d);
}

bvox_status bvox__dir_sink_open(const char *path, bvox__dir_kind kind, bool force,
                                bvox__dir_sink *d)
{
    memset(d, 0, sizeof *d);
    d->slot = -1;
    d->name = path;
    d->kind = kind;
    d->force = force;
    size_t len = strlen(path);
    while (len > 1 && path[len - 1] == '/') len--;
    d->target = bvox__mem_strndup(path, len);
    if (!d->target) return bvox__fail(BVOX_ENOMEM, "out of memory");
    /* a link to a folder (or to where one will be): work beside the final
     * target, so the temporary folder is on the same file system and the
     * link stays a link */
    struct stat sb;
    bool exists;
    char *real = NULL;
    if (!bvox__resolve_output(d->target, &real, &sb, &exists)) {
        bvox_status st = bvox__fail(errno == ENOMEM ? BVOX_ENOMEM : BVOX_EIO,
                                    "%s: cannot follow the path: %s", path, strerror(errno));
        dir_release(d);
        return st;
    }
    free(d->target);
    d->target = real;
    /* refuse before any work is done; checked again at commit */
    survey_result r;
    survey(d->target, kind, &r);
    names_free(&r.listed);
    if (r.state == T_NOTDIR || r.state == T_ERROR || r.state == T_NOMEM || (r.state == T_FOREIGN && !force) ||
        (kind == BVOX__DIR_ZARR && tree_refused(&r, force))) {
        bvox_status st = refuse(path, kind, &r, force);
        dir_release(d);
        return st;
    }
    d->tmp = bvox__temp_name(d->target);
    if (!d->tmp) {
        dir_release(d);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    if (bvox__temp_create(d->tmp, true) != 0) {
        int e = errno;
        free(d->tmp);
        d->tmp = NULL;
        dir_release(d);
        return bvox__fail(e == ENOENT ? BVOX_ENOTFOUND : BVOX_EIO, "%s: cannot create: %s", path,
                          e == ENOENT ? "no such parent folder" : strerror(e));
    }
    d->slot = bvox__temp_register(d->tmp, true);
    return BVOX_OK;
}

/* fsync every file under the open folder fd (which stays open). */
static bool sync_tree(int fd, int depth)
{
    int dup_fd = dup(fd);
    DIR *d = dup_fd >= 0 ? fdopendir(dup_fd) : NULL;
    if (!d) {
        if (dup_fd >= 0) close(dup_fd);
        return false;
    }
    bool ok = true;
    struct dirent *e;
    while (ok && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        int f = openat(dirfd(d), e->d_name, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
        struct stat sb;
        if (f < 0 || fsync(f) != 0) ok = false;
        if (ok && depth > 0 && fstat(f, &sb) == 0 && S_ISDIR(sb.st_mode)) ok = sync_tree(f, depth - 1);
        if (f >= 0) close(f);
    }
    closedir(d);
    return ok;
}

/* The files written into the temporary folder, each fsync'ed. */
static bool list_and_sync(const char *dir, names *out, bool *nomem)
{
    memset(out, 0, sizeof *out);
    *nomem = false;
    DIR *d = opendir(dir);
    if (!d) return false;
    bool ok = true;
    struct dirent *e;
    while (ok && (e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        int fd = openat(dirfd(d), e->d_name, O_RDONLY | O_CLOEXEC);
        struct stat sb;
        if (fd < 0 || fsync(fd) != 0) ok = false;
        /* a Zarr level folder: its chunk files too */
        if (ok && fstat(fd, &sb) == 0 && S_ISDIR(sb.st_mode)) ok = sync_tree(fd, 4);
        if (fd >= 0) close(fd);
        if (ok && strcmp(e->d_name, BVOX__MANIFEST_NAME) &&
            !names_add(out, e->d_name, strlen(e->d_name)))
            ok = false, *nomem = true;
    }
    if (ok && fsync(dirfd(d)) != 0) ok = false;
    int err = errno;
    closedir(d);
    names_sort(out);
    errno = err;
    return ok;
}

/* Move the new files into an existing folder (empty, ours, or forced). */
static bvox_status replace_in(bvox__dir_sink *d, survey_result *r, const names *fresh)
{
    const char *name = d->name;
    names all = {0};
    bvox_status st = BVOX_OK;
    for (size_t i = 0; i < r->listed.n && !st; i++)
        if (!names_add(&all, r->listed.v[i], strlen(r->listed.v[i]))) st = BVOX_ENOMEM;
    for (size_t i = 0; i < fresh->n && !st; i++)
        if (!names_has(&r->listed, fresh->v[i]) && !names_add(&all, fresh->v[i], strlen(fresh->v[i])))
            st = BVOX_ENOMEM;
    if (st) {
        names_free(&all);
        return bvox__fail(BVOX_ENOMEM, "out of memory");
    }
    names_sort(&all);
    int from = open(d->tmp, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    int to = open(d->target, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (from < 0 || to < 0) st = bvox__fail(BVOX_EIO, "%s: cannot open the folder: %s", name, strerror(errno));
    /* a folder or link of a new file's name (possible when forced): refuse
     * before anything is moved */
    for (size_t i = 0; i < fresh->n && !st; i++) {
        struct stat sb;
        if (fstatat(to, fresh->v[i], &sb, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISREG(sb.st_mode))
            st = bvox__fail(BVOX_EIO, "%s/%s: exists and is not a regular file", name, fresh->v[i]);
    }
    /* first the manifest of old and new together: whatever happens next,
     * every file of bvox's in the folder is listed */
    if (!st) st = manifest_write(d->target, d->kind, &all);
    names_free(&all);
    for (size_t i = 0; i < fresh->n && !st; i++) {
        if (renameat(from, fresh->v[i], to, fresh->v[i]) != 0)
            st = bvox__fail(BVOX_EIO, "%s/%s: cannot rename the finished file into place: %s", name,
                            fresh->v[i], strerror(errno));
    }
    /* the earlier output's files that were not written again */
    for (size_t i = 0; i < r->listed.n && !st; i++)
        if (!names_has(fresh, r->listed.v[i]) && unlinkat(to, r->listed.v[i], 0) != 0 &&
            errno != ENOENT)
            st = bvox__fail(BVOX_EIO, "%s/%s: cannot remove the earlier output's file: %s", name,
                            r->listed.v[i], strerror(errno));
    if (!st) st = manifest_write(d->target, d->kind, fresh);
    if (!st && fsync(to) != 0 && errno != EINVAL)
        st = bvox__fail(BVOX_EIO, "%s: cannot sync the folder: %s", name, strerror(errno));
    if (from >= 0) close(from);
    if (to >= 0) close(to);
    return st;
}

/* Put a whole tree in place (kind zarr): onto a new or empty target by one
 * rename; over bvox's own earlier tree (forced) by an atomic swap, after
 * which the old tree, now at the temporary name, is removed. */
static bvox_status commit_tree(bvox__dir_sink *d)
{
    names top = {0};
    bvox_status st = BVOX_OK;
    survey_result r;
    survey(d->target, d->kind, &r);
    DIR *t = opendir(d->tmp);
    struct dirent *e;
    while (t && !st && (e = readdir(t)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") &&
            strcmp(e->d_name, BVOX__MANIFEST_NAME) && !names_add(&top, e->d_name, strlen(e->d_name)))
            st = bvox__fail(BVOX_ENOMEM, "%s: out of memory", d->name);
    if (t) closedir(t);
    names_sort(&top);
    if (!st) st = manifest_write(d->tmp, d->kind, &top);
    names_free(&top);
    if (!st && (r.state == T_ABSENT || r.state == T_EMPTY)) {
        /* rename(2) puts a folder onto an empty one in one step */
        if (rename(d->tmp, d->target) != 0)
            st = bvox__fail(BVOX_EIO, "%s: cannot rename the finished folder into place: %s",
                            d->name, errno == ENOTEMPTY || errno == EEXIST
                                         ? "another program wrote into it meanwhile"
                                         : strerror(errno));
    } else if (!st && r.state == T_OURS && d->force) {
        if (renameat2(AT_FDCWD, d->tmp, AT_FDCWD, d->target, RENAME_EXCHANGE) != 0)
            st = bvox__fail(BVOX_EIO, "%s: cannot swap the finished folder into place: %s",
                            d->name, strerror(errno));
    } else if (!st) {
        st = refuse(d->name, d->kind, &r, d->force);
    }
    names_free(&r.listed);
    if (!st && !bvox__sync_parent(d->target))
        st = bvox__fail(BVOX_EIO, "%s: written, but its folder could not be synced: %s", d->name,
                        strerror(errno));
    /* after a rename nothing is left at tmp (removing fails harmlessly);
     * after a swap the old tree is there */
    bvox__dir_sink_abort(d);
    return st;
}

bvox_status bvox__dir_sink_commit(bvox__dir_sink *d)
{
    names fresh;
    bvox_status st = BVOX_OK;
    bool nomem;
    if (!list_and_sync(d->tmp, &fresh, &nomem)) {
        st = nomem ? bvox__fail(BVOX_ENOMEM, "%s: out of memory", d->name)
                   : bvox__fail(BVOX_EIO, "%s: cannot sync the written files: %s", d->name,
                                strerror(errno));
        names_free(&fresh);
        bvox__dir_sink_abort(d);
        return st;
    }
    if (d->kind == BVOX__DIR_ZARR) {
        names_free(&fresh);
        return commit_tree(d);
    }
    /* A concurrent writer may create the folder between the survey and the
     * rename: then look again (a few times) and replace in place. */
    for (int attempt = 0;; attempt++) {
        survey_result r;
        survey(d->target, d->kind, &r);
        if (r.state == T_ABSENT) {
            st = manifest_write(d->tmp, d->kind, &fresh);
            if (!st && rename(d->tmp, d->target) == 0) {
                if (!bvox__sync_parent(d->target))
                    st = bvox__fail(BVOX_EIO, "%s: written, but its folder could not be synced: %s",
                                    d->name, strerror(errno));
                names_free(&r.listed);
                names_free(&fresh);
                free(d->tmp); /* renamed: nothing left to remove */
                d->tmp = NULL;
                dir_release(d);
                return st;
            }
            if (!st && (errno != EEXIST && errno != ENOTEMPTY) )
                st = bvox__fail(BVOX_EIO, "%s: cannot rename the finished folder into place: %s",
                                d->name, strerror(errno));
            if (!st && attempt >= 4)
                st = bvox__fail(BVOX_EIO, "%s: another program keeps changing the folder", d->name);
            names_free(&r.listed);
            if (st) break;
            continue;
        }
        if (r.state == T_NOTDIR || r.state == T_ERROR || r.state == T_NOMEM || (r.state == T_FOREIGN && !d->force)) {
            st = refuse(d->name, d->kind, &r, d->force);
        } else {
            /* forced into a foreign folder: its manifest, if any of this kind,
             * still says which files were bvox's */
            st = replace_in(d, &r, &fresh);
        }
        names_free(&r.listed);
        break;
    }
    names_free(&fresh);
    bvox__dir_sink_abort(d); /* the temporary folder: empty after a replace */
    return st;
}
