/*
 * contour_read.c — bvox_stack_read: one entry point for every contour stack
 * input, chosen by what the path is:
 *   a folder        its .svg files, one section each, in natural order
 *                   ("s2.svg" before "s10.svg"); or, when it holds no .svg
 *                   but exactly one .ser file, that Reconstruct series;
 *   NAME.json       the JSON stack;  NAME.svg  one section;
 *   NAME.ser        a Reconstruct series (sections NAME.1, NAME.2, ...);
 *   anything else   by content: '{' JSON, <svg SVG, <Series a series,
 *                   <Section one Reconstruct section.
 */
#include "contour_internal.h"
#include "io/io.h"

#include <ctype.h>
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

static int cmp_natural(const void *a, const void *b)
{
    return bvox__natural_compare(*(char *const *)a, *(char *const *)b);
}

static bvox_status read_folder(const char *path, const char *select, bvox_contour_stack **out)
{
    DIR *d = opendir(path);
    if (!d) return bvox__fail(BVOX_EIO, "%s: cannot list the folder", path);
    char **names = NULL, *ser = NULL;
    size_t n = 0, cap = 0;
    int nser = 0;
    bvox_status st = BVOX_OK;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        if (ends_with(e->d_name, ".ser")) {
            nser++;
            free(ser);
            ser = bvox__mem_strdup(e->d_name);
            continue;
        }
        if (!ends_with(e->d_name, ".svg")) continue;
        if (n >= BVOX__MAX_SECTIONS) {
            st = bvox__fail(BVOX_ETOOBIG, "%s: more than %d .svg files", path, BVOX__MAX_SECTIONS);
            break;
        }
        if (!bvox__grow((void **)&names, sizeof *names, n + 1, &cap, "file names")) {
            st = BVOX_ENOMEM;
            break;
        }
        size_t len = strlen(path) + strlen(e->d_name) + 2;
        names[n] = bvox__mem_alloc(len);
        if (!names[n]) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
            break;
        }
        snprintf(names[n], len, "%s/%s", path, e->d_name);
        n++;
    }
    closedir(d);
    if (!st && n == 0 && nser == 1) {
        size_t len = strlen(path) + strlen(ser) + 2;
        char *full = bvox__mem_alloc(len);
        if (!full) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
        } else {
            snprintf(full, len, "%s/%s", path, ser);
            st = bvox__stack_read_reconstruct_series(full, out);
            free(full);
        }
    } else if (!st && n == 0) {
        st = bvox__fail(BVOX_EFORMAT,
                        "%s: the folder has no .svg files (nor a single Reconstruct .ser file)",
                        path);
    } else if (!st) {
        qsort(names, n, sizeof *names, cmp_natural);
        st = bvox__svg_read_files((const char *const *)names, (int32_t)n, select, out);
    }
    for (size_t i = 0; i < n; i++) free(names[i]);
    free(names);
    free(ser);
    return st;
}

bvox_status bvox_stack_read(const char *path, bvox_contour_stack **out)
{
    return bvox_stack_read_with(path, NULL, out);
}

/* A selection that names nothing would give an empty model: refused. */
static bvox_status check_selection(const char *path, const char *select, bvox_contour_stack **out)
{
    if (!select || !*select || !*out) return BVOX_OK;
    for (int32_t i = 0; i < (*out)->nsections; i++)
        if ((*out)->sections[i].ncontours) return BVOX_OK;
    bvox_stack_destroy(*out);
    *out = NULL;
    return bvox__fail(BVOX_EINVAL, "%s: --svg-select '%s' names no outline in any section", path,
                      select);
}

bvox_status bvox_stack_read_with(const char *path, const bvox_stack_read_opts *opts,
                                 bvox_contour_stack **out)
{
    bvox__clear_error();
    const char *select = opts ? opts->svg_select : NULL;
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_read: out is NULL");
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "bvox_stack_read: path is NULL");
    struct stat sb;
    if (stat(path, &sb) != 0) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file or folder", path);
    if (S_ISDIR(sb.st_mode)) {
        bvox_status st = read_folder(path, select, out);
        return st ? st : check_selection(path, select, out);
    }
    if (ends_with(path, ".ser")) return bvox__stack_read_reconstruct_series(path, out);
    char *text;
    size_t size;
    bvox_status st = bvox__read_text(path, &text, &size);
    if (st) return st;
    const char *p = text;
    while (*p && isspace((unsigned char)*p)) p++;
    if (ends_with(path, ".json") || *p == '{') {
        st = bvox_stack_read_json_memory(text, size, path, out);
    } else if (ends_with(path, ".svg") || strstr(text, "<svg") || strstr(text, ":svg")) {
        st = bvox__svg_read(text, size, path, 0, select, out);
        if (!st) st = check_selection(path, select, out);
    } else if (strstr(text, "<Series")) {
        free(text);
        return bvox__stack_read_reconstruct_series(path, out);
    } else if (strstr(text, "<Section")) {
        st = bvox_stack_read_reconstruct_section_memory(text, size, path, out);
    } else {
        st = bvox__fail(BVOX_EFORMAT,
                        "%s: not a contour stack (expected JSON, SVG or a Reconstruct series)", path);
    }
    free(text);
    return st;
}
