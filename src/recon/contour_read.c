/*
 * contour_read.c — bvox_stack_read: one entry point for every contour stack
 * input, chosen by what the path is:
 *   a folder        its .svg files, one section each, in natural order
 *                   ("s2.svg" before "s10.svg"); or, when it holds no .svg
 *                   but exactly one .ser file, that Reconstruct series;
 *   NAME.json       the JSON stack;  NAME.svg  one section;
 *   NAME.ser        a Reconstruct series (sections NAME.1, NAME.2, ...);
 *   NAME.jser       a PyReconstruct series (a JSON object with "tforms"
 *                   in it, under another name, too);
 *   anything else   by content: '{' JSON, <svg SVG, <Series a series,
 *                   <Section one Reconstruct section.
 */
#include "common/names.h"
#include "contour_internal.h"
#include "io/io.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The folder's .svg files are kept; a lone Reconstruct .ser file is noted. */
typedef struct folder_scan {
    char *ser;
    int nser;
    bool failed;
} folder_scan;

static bool keep_svg(const char *dir, const char *name, void *ctx)
{
    (void)dir;
    folder_scan *f = ctx;
    if (bvox__ends_with_ci(name, ".ser")) {
        f->nser++;
        free(f->ser);
        if (!(f->ser = bvox__mem_strdup(name))) f->failed = true;
        return false;
    }
    return bvox__ends_with_ci(name, ".svg");
}

static bvox_status read_folder(const char *path, const char *select, bvox_contour_stack **out)
{
    char **names = NULL;
    size_t n = 0;
    folder_scan f = {NULL, 0, false};
    bvox_status st =
        bvox__list_dir(path, keep_svg, &f, BVOX__MAX_SECTIONS, ".svg files", &names, &n);
    if (st == BVOX_EIO) st = bvox__fail(BVOX_EIO, "%s: cannot list the folder", path);
    if (!st && f.failed) st = bvox__fail(BVOX_ENOMEM, "out of memory");
    if (!st && n == 0 && f.nser == 1) {
        size_t len = strlen(path) + strlen(f.ser) + 2;
        char *full = bvox__mem_alloc(len);
        if (!full) {
            st = bvox__fail(BVOX_ENOMEM, "out of memory");
        } else {
            snprintf(full, len, "%s/%s", path, f.ser);
            st = bvox__stack_read_reconstruct_series(full, out);
            free(full);
        }
    } else if (!st && n == 0) {
        st = bvox__fail(BVOX_EFORMAT,
                        "%s: the folder has no .svg files (nor a single Reconstruct .ser file)",
                        path);
    } else if (!st) {
        st = bvox__svg_read_files((const char *const *)names, (int32_t)n, select, out);
    }
    bvox__free_paths(names, n);
    free(f.ser);
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

static bvox_status not_jser(const char *path, const char *object)
{
    return bvox__fail(BVOX_EINVAL, "%s: --object '%s' selects the traces of a PyReconstruct "
                                   ".jser series; this is not one", path, object);
}

bvox_status bvox_stack_read_with(const char *path, const bvox_stack_read_opts *opts,
                                 bvox_contour_stack **out)
{
    bvox__clear_error();
    const char *select = opts ? opts->svg_select : NULL;
    const char *object = opts && opts->object && *opts->object ? opts->object : NULL;
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_read: out is NULL");
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "bvox_stack_read: path is NULL");
    struct stat sb;
    if (stat(path, &sb) != 0) return bvox__fail(BVOX_ENOTFOUND, "%s: no such file or folder", path);
    if (object && (S_ISDIR(sb.st_mode) || bvox__ends_with_ci(path, ".ser")))
        return not_jser(path, object);
    if (S_ISDIR(sb.st_mode)) {
        bvox_status st = read_folder(path, select, out);
        return st ? st : check_selection(path, select, out);
    }
    if (bvox__ends_with_ci(path, ".ser")) return bvox__stack_read_reconstruct_series(path, out);
    char *text;
    size_t size;
    bvox_status st = bvox__read_text(path, &text, &size);
    if (st) return st;
    const char *p = text;
    while (*p && isspace((unsigned char)*p)) p++;
    if (bvox__ends_with_ci(path, ".jser") ||
        (*p == '{' && !bvox__ends_with_ci(path, ".json") && strstr(text, "\"tforms\""))) {
        st = bvox_stack_read_jser_memory(text, size, path, object, out);
    } else if (object) {
        st = not_jser(path, object);
    } else if (bvox__ends_with_ci(path, ".json") || *p == '{') {
        st = bvox_stack_read_json_memory(text, size, path, out);
    } else if (bvox__ends_with_ci(path, ".svg") || strstr(text, "<svg") || strstr(text, ":svg")) {
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
