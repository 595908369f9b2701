/*
 * names.h — file names: the case-insensitive suffix test, natural ("human")
 * order, and listing a folder in that order. Shared by the readers (io/,
 * recon/) and by cli/ (which may include src/common/ headers, nothing else of
 * src/).
 */
#ifndef BVOX_COMMON_NAMES_H
#define BVOX_COMMON_NAMES_H

#include "bvox.h"

#include <stdbool.h>
#include <stddef.h>

/* s ends in suffix, ASCII letters compared case-insensitively ("a.PNG" ends
 * in ".png"). */
bool bvox__ends_with_ci(const char *s, const char *suffix);

/* Natural ("human") order of file names: "s2.png" < "s10.png". A total
 * order (qsort gives one answer). */
int bvox__natural_compare(const char *a, const char *b);

/* Which entries of a folder to keep: name is the entry's name (never one
 * that starts with '.'), dir the folder. */
typedef bool (*bvox__name_filter)(const char *dir, const char *name, void *ctx);

/* The entries of dir that keep accepts, in natural order of their names, as
 * malloc'd "dir/name" paths in a malloc'd array (*paths NULL when none). More
 * than max entries: BVOX_ETOOBIG "DIR: more than MAX WHAT". A folder that
 * cannot be opened: BVOX_EIO "DIR: cannot open the folder: REASON", errno
 * kept for callers that word it otherwise. */
bvox_status bvox__list_dir(const char *dir, bvox__name_filter keep, void *ctx, size_t max,
                           const char *what, char ***paths, size_t *n);
/* Free what bvox__list_dir returned. */
void bvox__free_paths(char **paths, size_t n);

#endif
