/*
 * dirlist.c — a folder's entries in natural order (names.h): the folders of
 * PNG slices, of section images and of SVG contours are all read this way,
 * so "s2.png" comes before "s10.png" everywhere.
 */
#include "internal.h"
#include "names.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_paths(const void *a, const void *b)
{
    /* all paths share the "dir/" prefix: comparing them is comparing names */
    return bvox__natural_compare(*(char *const *)a, *(char *const *)b);
}

void bvox__free_paths(char **paths, size_t n)
{
    for (size_t i = 0; i < n; i++) free(paths[i]);
    free(paths);
}

bvox_status bvox__list_dir(const char *dir, bvox__name_filter keep, void *ctx, size_t max,
                           const char *what, char ***paths, size_t *count)
{
    *paths = NULL;
    *count = 0;
    DIR *d = opendir(dir);
    if (!d) {
        int err = errno;
        bvox_status st = bvox__fail(BVOX_EIO, "%s: cannot open the folder: %s", dir, strerror(err));
        errno = err;
        return st;
    }
    char **names = NULL;
    size_t n = 0, cap = 0;
    bvox_status st = BVOX_OK;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || !keep(dir, e->d_name, ctx)) continue;
        if (n >= max) {
            st = bvox__fail(BVOX_ETOOBIG, "%s: more than %zu %s", dir, max, what);
            break;
        }
        if (n == cap) {
            size_t ncap = cap ? cap * 2 : 64;
            char **grown = bvox__mem_resize(names, ncap * sizeof *names);
            if (!grown) {
                st = bvox__fail(BVOX_ENOMEM, "out of memory listing %s", dir);
                break;
            }
            names = grown;
            cap = ncap;
        }
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if (!(names[n] = bvox__mem_alloc(len))) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory listing %s", dir);
            break;
        }
        snprintf(names[n], len, "%s/%s", dir, e->d_name);
        n++;
    }
    closedir(d);
    if (st) {
        bvox__free_paths(names, n);
        return st;
    }
    if (n > 1) qsort(names, n, sizeof *names, cmp_paths);
    *paths = names;
    *count = n;
    return BVOX_OK;
}
