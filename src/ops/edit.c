/*
 * edit.c — in-place edits that say which region they changed, so that a
 * display can redo only that part: one voxel, fill or clear a box, keep a box
 * (the paper's spatial selection: clear everything outside x, y, z
 * intervals). A box is a bit run per column, changed with whole-word masks
 * (bvox__run_apply in edit.h), rows split over the worker threads; the
 * reported box is tight: exactly the voxels whose value changed.
 */
#include "ops/edit.h"

#include <string.h>

/* ---- changed-region bookkeeping (edit.h) ---- */

void bvox__change_shared_init(bvox__change_shared *s)
{
    pthread_mutex_init(&s->lock, NULL);
    bvox__change_init(&s->c);
}

void bvox__change_merge(bvox__change_shared *s, const bvox__change *p)
{
    if (p->x0 > p->x1) return; /* nothing changed in this chunk */
    pthread_mutex_lock(&s->lock);
    bvox__change *c = &s->c;
    if (p->x0 < c->x0) c->x0 = p->x0;
    if (p->y0 < c->y0) c->y0 = p->y0;
    if (p->z0 < c->z0) c->z0 = p->z0;
    if (p->x1 > c->x1) c->x1 = p->x1;
    if (p->y1 > c->y1) c->y1 = p->y1;
    if (p->z1 > c->z1) c->z1 = p->z1;
    pthread_mutex_unlock(&s->lock);
}

void bvox__change_shared_done(bvox__change_shared *s) { pthread_mutex_destroy(&s->lock); }

void bvox__change_to_box(const bvox__change *c, bvox_box *out)
{
    if (!out) return;
    if (c->x0 > c->x1) {
        memset(out, 0, sizeof *out);
        return;
    }
    *out = (bvox_box){c->x0, c->y0, c->z0, c->x1 + 1, c->y1 + 1, c->z1 + 1};
}

/* ---- one voxel ---- */

bvox_status bvox_edit_voxel(bvox_volume *vol, int32_t x, int32_t y, int32_t z, int value,
                            bvox_box *changed)
{
    bvox__clear_error();
    if (changed) memset(changed, 0, sizeof *changed);
    if (!vol) return bvox__fail(BVOX_EINVAL, "edit: no volume");
    if (x < 0 || y < 0 || z < 0 || x >= vol->nx || y >= vol->ny || z >= vol->nz)
        return bvox__fail(BVOX_EINVAL, "edit: voxel (%ld, %ld, %ld) is outside the %ldx%ldx%ld volume",
                          (long)x, (long)y, (long)z, (long)vol->nx, (long)vol->ny,
                          (long)vol->nz);
    bvox__change c;
    bvox__change_init(&c);
    bvox__run_apply(bvox__column(vol, x, y), z, (int64_t)z + 1,
                    value ? BVOX__RUN_SET : BVOX__RUN_CLEAR, x, y, &c);
    bvox__change_to_box(&c, changed);
    return BVOX_OK;
}

/* ---- boxes ---- */

typedef struct box_job {
    bvox_volume *vol;
    bvox_box box;  /* clipped */
    int keep;      /* 1: clear outside the box; 0: fill (value) inside */
    int value;
    bvox__change_shared shared;
} box_job;

static void box_rows(void *ctx, int64_t begin, int64_t end)
{
    box_job *j = ctx;
    bvox_volume *v = j->vol;
    const bvox_box b = j->box;
    bvox__change c;
    bvox__change_init(&c);
    int32_t first = j->keep ? 0 : b.y0;
    for (int64_t r = begin; r < end; r++) {
        int32_t y = (int32_t)(first + r);
        for (int32_t x = 0; x < v->nx; x++) {
            bool in_xy = x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1;
            uint64_t *col = bvox__column(v, x, y);
            if (!j->keep) {
                if (!in_xy) continue;
                bvox__run_apply(col, b.z0, b.z1, j->value ? BVOX__RUN_SET : BVOX__RUN_CLEAR,
                                x, y, &c);
            } else if (!in_xy) {
                bvox__run_apply(col, 0, v->nz, BVOX__RUN_CLEAR, x, y, &c);
            } else {
                bvox__run_apply(col, 0, b.z0, BVOX__RUN_CLEAR, x, y, &c);
                bvox__run_apply(col, b.z1, v->nz, BVOX__RUN_CLEAR, x, y, &c);
            }
        }
    }
    bvox__change_merge(&j->shared, &c);
}

static bvox_box clip_box(const bvox_volume *v, bvox_box b)
{
    b = bvox__box_clip(v, b);
    if (b.x0 >= b.x1 || b.y0 >= b.y1 || b.z0 >= b.z1) memset(&b, 0, sizeof b);
    return b;
}

static bvox_status box_edit(bvox_volume *vol, bvox_box box, int keep, int value,
                            bvox_box *changed)
{
    bvox__clear_error();
    if (changed) memset(changed, 0, sizeof *changed);
    if (!vol) return bvox__fail(BVOX_EINVAL, "edit: no volume");
    box_job j = {.vol = vol, .box = clip_box(vol, box), .keep = keep, .value = value != 0};
    bool empty = j.box.x0 >= j.box.x1;
    if (empty && !keep) return BVOX_OK;
    bvox__change_shared_init(&j.shared);
    /* keep visits every row (everything outside the box is cleared) */
    int64_t rows = keep ? vol->ny : (int64_t)j.box.y1 - j.box.y0;
    bvox__parallel_for(rows, 8, box_rows, &j);
    bvox__change_to_box(&j.shared.c, changed);
    bvox__change_shared_done(&j.shared);
    return BVOX_OK;
}

bvox_status bvox_edit_fill_box(bvox_volume *vol, bvox_box box, int value, bvox_box *changed)
{
    return box_edit(vol, box, 0, value, changed);
}

bvox_status bvox_edit_keep_box(bvox_volume *vol, bvox_box box, bvox_box *changed)
{
    return box_edit(vol, box, 1, 0, changed);
}
