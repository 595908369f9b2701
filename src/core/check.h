/*
 * check.h — internal invariants asserted at module boundaries in debug
 * builds. Public operations check the objects they are given on entry and
 * the objects they hand out on exit (BVOX_CHECK_VOLUME and friends), so a
 * broken invariant (a tail bit set beyond nz, a triangle naming a vertex
 * that does not exist) is caught in the function that broke it, not three
 * calls later. With NDEBUG (release builds) every macro here compiles to
 * nothing and its argument is not evaluated.
 *
 * A failed check is a bug in bvox, never bad input: it prints one line on
 * stderr (the only place the library prints) and aborts, as assert() does.
 */
#ifndef BVOX_CORE_CHECK_H
#define BVOX_CORE_CHECK_H

#include "bvox.h"
#include "bvox/contours.h"
#include "bvox/mesh.h"

void bvox__check_failed(const char *what, const char *file, int line, const char *func)
    __attribute__((noreturn));
/* The checkers: return NULL when the object keeps its invariants, else a
 * description of the first broken one. NULL objects pass (an out-parameter
 * of a failed call). */
const char *bvox__volume_broken(const bvox_volume *vol);
const char *bvox__image_broken(const bvox_image *img);
const char *bvox__mesh_broken(const bvox_mesh *mesh);
const char *bvox__stack_broken(const bvox_contour_stack *stack);

#ifdef NDEBUG
#define BVOX_ASSERT(cond) ((void)sizeof(cond))
#define BVOX__CHECK_WITH(fn, obj) ((void)sizeof(obj))
#else
#define BVOX_ASSERT(cond) \
    ((cond) ? (void)0 : bvox__check_failed(#cond, __FILE__, __LINE__, __func__))
#define BVOX__CHECK_WITH(fn, obj)                                                      \
    do {                                                                               \
        const char *broken_ = fn(obj);                                                 \
        if (broken_) bvox__check_failed(broken_, __FILE__, __LINE__, __func__);        \
    } while (0)
#endif

#define BVOX_CHECK_VOLUME(vol) BVOX__CHECK_WITH(bvox__volume_broken, (vol))
#define BVOX_CHECK_IMAGE(img) BVOX__CHECK_WITH(bvox__image_broken, (img))
#define BVOX_CHECK_MESH(mesh) BVOX__CHECK_WITH(bvox__mesh_broken, (mesh))
#define BVOX_CHECK_STACK(stack) BVOX__CHECK_WITH(bvox__stack_broken, (stack))

/* Return the status of expr, first checking obj (an out-parameter's value)
 * with check when expr succeeded: the exit check of a public operation.
 *   BVOX_RETURN_CHECKED(dilate(in, out), BVOX_CHECK_VOLUME, *out); */
#define BVOX_RETURN_CHECKED(expr, check, obj)                                          \
    do {                                                                               \
        bvox_status checked_st_ = (expr);                                              \
        if (checked_st_ == BVOX_OK) check(obj);                                        \
        return checked_st_;                                                            \
    } while (0)

#endif
