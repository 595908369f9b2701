/*
 * contour_stack.c — the contour stack data model (include/bvox/contours.h):
 * create, destroy, append sections, contours and markers. Arrays grow by
 * doubling; the capacity of an array is not stored: it is the next power of
 * two at or above its count (so appending needs no extra field in the public
 * structs). Everything is malloc'ed (these are small next to voxel words).
 */
#include "contour_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool bvox__grow(void **ptr, size_t elem, size_t need, size_t *cap, const char *what)
{
    if (need <= *cap) return true;
    size_t n = *cap ? *cap : 8;
    while (n < need) {
        if (n > SIZE_MAX / 2) goto too_big;
        n *= 2;
    }
    size_t bytes;
    if (!bvox__mul_size(n, elem, &bytes)) goto too_big;
    void *p = bvox__mem_resize(*ptr, bytes);
    if (!p) {
        bvox__fail(BVOX_ENOMEM, "out of memory for the %s (%zu bytes)", what, bytes);
        return false;
    }
    *ptr = p;
    *cap = n;
    return true;
too_big:
    bvox__fail(BVOX_ETOOBIG, "too many %s", what);
    return false;
}

/* Capacity implied by a count: 0 -> 0, else the next power of two >= n. */
static size_t implied_cap(size_t n)
{
    if (n == 0) return 0;
    size_t c = 1;
    while (c < n) c *= 2;
    return c;
}

/* Append one element to an array whose capacity is implied by its count. */
static bool append(void **arr, size_t elem, size_t count, const char *what)
{
    size_t cap = implied_cap(count);
    if (count < cap) return true;
    size_t newcap = cap ? cap * 2 : 1;
    return bvox__grow(arr, elem, newcap, &cap, what);
}

const char *bvox__section_label(const bvox_section *sec, int32_t index, char *buf, size_t size)
{
    if (sec && sec->name && sec->name[0])
        snprintf(buf, size, "section '%s' (z = %g)", sec->name, sec->z);
    else if (sec)
        snprintf(buf, size, "section %d (z = %g)", (int)index + 1, sec->z);
    else
        snprintf(buf, size, "section %d", (int)index + 1);
    return buf;
}

/* Every stack is one of these: the public struct, then what its builder
 * charged to the memory budget (refunded by bvox_stack_destroy). */
typedef struct stack_box {
    bvox_contour_stack pub; /* first: a stack pointer is a box pointer */
    size_t charged;
} stack_box;

void bvox__stack_charged(bvox_contour_stack *s, size_t bytes)
{
    ((stack_box *)s)->charged += bytes;
}

bvox_status bvox_stack_create(bvox_contour_stack **out)
{
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_stack_create: out is NULL");
    *out = NULL;
    stack_box *box = bvox__mem_zalloc(1, sizeof *box);
    bvox_contour_stack *s = box ? &box->pub : NULL;
    if (!s) return bvox__fail(BVOX_ENOMEM, "out of memory for a contour stack");
    s->pixel = 1.0;
    s->spacing = 1.0;
    *out = s;
    return BVOX_OK;
}

static void section_free(bvox_section *sec)
{
    for (int32_t c = 0; c < sec->ncontours; c++) free(sec->contours[c].points);
    free(sec->contours);
    free(sec->markers);
    free(sec->name);
}

void bvox__stack_drop_last(bvox_contour_stack *s) { section_free(&s->sections[--s->nsections]); }

void bvox_stack_destroy(bvox_contour_stack *stack)
{
    if (!stack) return;
    for (int32_t i = 0; i < stack->nsections; i++) section_free(&stack->sections[i]);
    free(stack->sections);
    bvox__budget_refund(((stack_box *)stack)->charged);
    free(stack);
}

bvox_status bvox_stack_add_section(bvox_contour_stack *stack, double z, const char *name,
                                   bvox_section **out)
{
    if (out) *out = NULL;
    if (!stack) return bvox__fail(BVOX_EINVAL, "bvox_stack_add_section: stack is NULL");
    if (!isfinite(z)) return bvox__fail(BVOX_EINVAL, "section z is not a finite number");
    if (stack->nsections >= BVOX__MAX_SECTIONS)
        return bvox__fail(BVOX_ETOOBIG, "more than %d sections", BVOX__MAX_SECTIONS);
    char *copy = NULL;
    if (name) {
        copy = bvox__mem_strdup(name);
        if (!copy) return bvox__fail(BVOX_ENOMEM, "out of memory for a section name");
    }
    if (!append((void **)&stack->sections, sizeof *stack->sections, (size_t)stack->nsections,
                "sections")) {
        free(copy);
        return bvox__fail(BVOX_ENOMEM, "out of memory for the sections");
    }
    bvox_section *sec = &stack->sections[stack->nsections++];
    memset(sec, 0, sizeof *sec);
    sec->z = z;
    sec->name = copy;
    if (out) *out = sec;
    return BVOX_OK;
}

bvox_status bvox_section_add_contour(bvox_section *sec, const bvox_point2 *points, int32_t n,
                                     int hole, int32_t parent)
{
    if (!sec || (!points && n > 0))
        return bvox__fail(BVOX_EINVAL, "bvox_section_add_contour: NULL argument");
    if (n < 3) return bvox__fail(BVOX_EINVAL, "a contour needs at least 3 points (it has %d)", (int)n);
    if (n > BVOX__MAX_POINTS)
        return bvox__fail(BVOX_ETOOBIG, "a contour of %d points (at most %d)", (int)n,
                          BVOX__MAX_POINTS);
    if (sec->ncontours >= BVOX__MAX_CONTOURS)
        return bvox__fail(BVOX_ETOOBIG, "more than %d contours in a section", BVOX__MAX_CONTOURS);
    if (parent < -1 || parent >= sec->ncontours)
        return bvox__fail(BVOX_EINVAL, "contour parent %d is not an earlier contour", (int)parent);
    for (int32_t i = 0; i < n; i++)
        if (!isfinite(points[i].x) || !isfinite(points[i].y) ||
            fabs(points[i].x) > BVOX__MAX_COORD || fabs(points[i].y) > BVOX__MAX_COORD)
            return bvox__fail(BVOX_EINVAL,
                              "contour point %d is not finite or beyond +-%g pixels", (int)i + 1,
                              BVOX__MAX_COORD);
    bvox_point2 *copy = bvox__mem_alloc((size_t)n * sizeof *copy);
    if (!copy) return bvox__fail(BVOX_ENOMEM, "out of memory for a contour of %d points", (int)n);
    memcpy(copy, points, (size_t)n * sizeof *copy);
    if (!append((void **)&sec->contours, sizeof *sec->contours, (size_t)sec->ncontours,
                "contours")) {
        free(copy);
        return bvox__fail(BVOX_ENOMEM, "out of memory for the contours");
    }
    bvox_contour *c = &sec->contours[sec->ncontours++];
    c->points = copy;
    c->npoints = n;
    c->hole = hole ? 1 : 0;
    c->parent = parent;
    return BVOX_OK;
}

bvox_status bvox_section_add_marker(bvox_section *sec, bvox_point2 marker)
{
    if (!sec) return bvox__fail(BVOX_EINVAL, "bvox_section_add_marker: section is NULL");
    if (!isfinite(marker.x) || !isfinite(marker.y) || fabs(marker.x) > BVOX__MAX_COORD ||
        fabs(marker.y) > BVOX__MAX_COORD)
        return bvox__fail(BVOX_EINVAL, "a marker position is not finite or beyond +-%g pixels",
                          BVOX__MAX_COORD);
    if (sec->nmarkers >= BVOX__MAX_MARKERS)
        return bvox__fail(BVOX_ETOOBIG, "more than %d markers in a section", BVOX__MAX_MARKERS);
    if (!append((void **)&sec->markers, sizeof *sec->markers, (size_t)sec->nmarkers, "markers"))
        return bvox__fail(BVOX_ENOMEM, "out of memory for the markers");
    sec->markers[sec->nmarkers++] = marker;
    return BVOX_OK;
}
