/*
 * contour_repair.c — what reconstruct does with traced contours that cross.
 * A hand-traced outline that crosses itself by a fraction of a pixel (tablet
 * jitter where the pen closes the loop) is ordinary; refusing the whole
 * series for it helps nobody. Its even-odd fill, which the scan conversion
 * uses anyway, is well defined: the tiny loop is a sliver in or out. So by
 * default a self-crossing contour is kept and warned about (section, contour,
 * edges, position), and `strict` refuses it as before. Two different
 * contours crossing each other is not jitter (even-odd would punch their
 * overlap out of the object): always refused.
 */
#include "contour_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The section with only the contours that keep[] marks (a shallow view). */
static bvox_section view_of(const bvox_section *sec, bvox_contour *buf, const uint8_t *keep)
{
    bvox_section v = *sec;
    int32_t n = 0;
    for (int32_t c = 0; c < sec->ncontours; c++)
        if (!keep || keep[c]) buf[n++] = sec->contours[c];
    v.contours = buf;
    v.ncontours = n;
    return v;
}

static bvox_status check_section(const char *path, const bvox_section *sec, int32_t index,
                                 int strict)
{
    bvox_status st = bvox_section_check_simple(sec, index);
    if (st != BVOX_EFORMAT || strict) return st;
    bvox_contour *buf = bvox__mem_alloc((size_t)sec->ncontours * sizeof *buf);
    uint8_t *keep = bvox__mem_alloc((size_t)sec->ncontours);
    if (!buf || !keep) {
        free(buf);
        free(keep);
        return bvox__fail(BVOX_ENOMEM, "out of memory checking contours");
    }
    char label[200];
    bvox__section_label(sec, index, label, sizeof label);
    int repaired = 0;
    st = BVOX_OK;
    for (int32_t c = 0; c < sec->ncontours && !st; c++) {
        bvox_section one = *sec;
        one.contours = &buf[0];
        buf[0] = sec->contours[c];
        one.ncontours = 1;
        bvox_status s1 = bvox_section_check_simple(&one, index);
        keep[c] = s1 == BVOX_OK;
        if (s1 == BVOX_EFORMAT) {
            const char *detail = strstr(bvox_errmsg(), "(edges");
            bvox__warn("%s: %s: contour %d crosses itself %s; filled even-odd (--strict refuses it)",
                       path, label, (int)c + 1, detail ? detail : "");
            repaired++;
        } else if (s1) {
            st = s1;
        }
    }
    if (!st && !repaired) { /* only crossings between contours: refused, as strict */
        st = bvox_section_check_simple(sec, index);
    } else if (!st) {
        bvox_section rest = view_of(sec, buf, keep);
        st = bvox_section_check_simple(&rest, index);
        if (st == BVOX_EFORMAT) /* numbering of the view differs: name the section only */
            st = bvox__fail(BVOX_EFORMAT, "%s: contours cross each other", label);
    }
    free(buf);
    free(keep);
    return st;
}

bvox_status bvox__stack_check_crossings(const char *path, const bvox_contour_stack *s, int strict)
{
    for (int32_t i = 0; i < s->nsections; i++) {
        bvox_status st = check_section(path, &s->sections[i], i, strict);
        if (st) {
            char msg[512];
            snprintf(msg, sizeof msg, "%s", bvox_errmsg());
            return bvox__fail(st, "%s: %s", path, msg);
        }
    }
    return BVOX_OK;
}
