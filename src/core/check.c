/*
 * check.c — the checkers behind check.h's debug assertions: one function per
 * object, each naming the first invariant it finds broken. They read only
 * and never set the thread-local message, so an operation's caller sees the
 * same bvox_errmsg() whether or not the checks ran.
 */
#include "internal.h"
#include "core/check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void bvox__check_failed(const char *what, const char *file, int line, const char *func)
{
    fprintf(stderr, "bvox: internal check failed in %s (%s:%d): %s\n", func, file, line, what);
    abort();
}

const char *bvox__volume_broken(const bvox_volume *v)
{
    if (!v) return NULL;
    if (v->nx < 1 || v->ny < 1 || v->nz < 1 || v->nx > BVOX_MAX_DIM || v->ny > BVOX_MAX_DIM ||
        v->nz > BVOX_MAX_DIM)
        return "volume dimensions out of range";
    if (v->wpc != ((size_t)v->nz + 63) / 64 || v->nwords != (size_t)v->nx * (size_t)v->ny * v->wpc)
        return "volume word counts inconsistent with its dimensions";
    uint64_t mask = (v->nz & 63) ? ((uint64_t)1 << (v->nz & 63)) - 1 : ~(uint64_t)0;
    if (v->tail_mask != mask) return "volume tail mask does not match nz";
    if (!v->words) return "volume without words";
    for (int i = 0; i < 3; i++)
        if (!isfinite(v->geom.spacing[i]) || v->geom.spacing[i] <= 0 ||
            !isfinite(v->geom.origin[i]))
            return "volume geometry not finite or voxel size not positive";
    if (!memchr(v->geom.unit, '\0', sizeof v->geom.unit)) return "volume unit not terminated";
    if (mask == ~(uint64_t)0) return NULL;
    size_t ncol = (size_t)v->nx * (size_t)v->ny;
    for (size_t c = 0; c < ncol; c++)
        if (v->words[c * v->wpc + v->wpc - 1] & ~mask) return "volume tail bits beyond nz set";
    return NULL;
}

const char *bvox__image_broken(const bvox_image *img)
{
    if (!img) return NULL;
    if (img->width < 1 || img->height < 1 || img->width > BVOX_IMAGE_MAX_DIM ||
        img->height > BVOX_IMAGE_MAX_DIM)
        return "image size out of range";
    if (img->channels != 1 && img->channels != 3 && img->channels != 4)
        return "image channels not 1, 3 or 4";
    if (img->bits == 8) return img->pixels && !img->pixels16 ? NULL : "8-bit image samples wrong";
    if (img->bits == 16) return img->pixels16 && !img->pixels ? NULL : "16-bit image samples wrong";
    return "image bits not 8 or 16";
}

const char *bvox__mesh_broken(const bvox_mesh *m)
{
    if (!m) return NULL;
    if (m->nvertices < 0 || m->ntriangles < 0 || m->nvertices > m->vcap ||
        m->ntriangles > m->tcap)
        return "mesh counts outside 0..capacity";
    if ((m->nvertices && !m->vertices) || (m->ntriangles && !m->triangles))
        return "mesh without its arrays";
    for (int64_t i = 0; i < 3 * m->ntriangles; i++)
        if (m->triangles[i] < 0 || m->triangles[i] >= m->nvertices)
            return "mesh triangle names a vertex that does not exist";
    for (int64_t i = 0; i < 3 * m->nvertices; i++)
        if (!isfinite(m->vertices[i])) return "mesh vertex not finite";
    return NULL;
}

const char *bvox__stack_broken(const bvox_contour_stack *s)
{
    if (!s) return NULL;
    if (s->nsections < 0 || (s->nsections && !s->sections)) return "stack sections missing";
    if (!memchr(s->unit, '\0', sizeof s->unit)) return "stack unit not terminated";
    for (int32_t i = 0; i < s->nsections; i++) {
        const bvox_section *sec = &s->sections[i];
        if (sec->ncontours < 0 || (sec->ncontours && !sec->contours))
            return "stack section contours missing";
        if (sec->nmarkers < 0 || (sec->nmarkers && !sec->markers))
            return "stack section markers missing";
        for (int32_t k = 0; k < sec->ncontours; k++) {
            const bvox_contour *c = &sec->contours[k];
            if (c->npoints < 0 || (c->npoints && !c->points)) return "stack contour points missing";
            if (c->parent < -1 || c->parent >= sec->ncontours || c->parent == k)
                return "stack contour parent out of range";
        }
    }
    return NULL;
}
