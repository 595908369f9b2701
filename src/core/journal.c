/*
 * journal.c — undo/redo of in-place edits as XOR patches of the changed
 * boxes' words (see include/bvox/journal.h). A patch covers columns
 * [x0, x1) x [y0, y1) and words [k0, k1) of each; its words first hold the
 * old values (record), then old ^ new (sync). Undo and redo both XOR the
 * patch back in, so a step needs no second copy.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct patch {
    int32_t x0, y0, x1, y1;
    size_t k0, k1;
    uint64_t *words; /* (x1-x0)*(y1-y0)*(k1-k0), bvox__alloc */
    size_t bytes;
} patch;

typedef struct step {
    patch *p;
    int n, cap;
} step;

struct bvox_journal {
    bvox_dims dims;
    size_t wpc;
    size_t max_bytes, bytes;
    step *steps;
    int n;        /* steps held (done and undone) */
    int cap;
    int done;     /* steps [0, done) can be undone, [done, n) redone */
    int open;     /* steps[done-1] is open */
    int unsynced; /* patches of the open step not yet synced start here */
};

static void step_free(bvox_journal *j, step *s)
{
    for (int i = 0; i < s->n; i++) {
        bvox__free(s->p[i].words, s->p[i].bytes);
        j->bytes -= s->p[i].bytes + sizeof(patch);
    }
    free(s->p);
    *s = (step){0};
}

bvox_status bvox_journal_create(bvox_dims dims, size_t max_bytes, bvox_journal **out)
{
    *out = NULL;
    if (dims.nx < 1 || dims.ny < 1 || dims.nz < 1)
        return bvox__fail(BVOX_EINVAL, "journal: bad dimensions");
    bvox__clear_error();
    bvox_journal *j = bvox__mem_zalloc(1, sizeof *j);
    if (!j) return bvox__fail(BVOX_ENOMEM, "out of memory");
    j->dims = dims;
    j->wpc = ((size_t)dims.nz + 63) / 64;
    j->max_bytes = max_bytes;
    *out = j;
    return BVOX_OK;
}

void bvox_journal_destroy(bvox_journal *j)
{
    if (!j) return;
    for (int i = 0; i < j->n; i++) step_free(j, &j->steps[i]);
    free(j->steps);
    free(j);
}

static void drop_redo(bvox_journal *j)
{
    while (j->n > j->done) step_free(j, &j->steps[--j->n]);
}

static void drop_oldest(bvox_journal *j)
{
    step_free(j, &j->steps[0]);
    memmove(j->steps, j->steps + 1, (size_t)(j->n - 1) * sizeof(step));
    j->n--;
    j->done--;
}

void bvox_journal_end(bvox_journal *j)
{
    if (!j || !j->open) return;
    j->open = 0;
    if (j->steps[j->done - 1].n == 0) { /* nothing recorded: no step */
        step_free(j, &j->steps[j->done - 1]);
        j->n--;
        j->done--;
        return;
    }
    /* the cap: forget the oldest steps, never the one just made */
    while (j->max_bytes && j->bytes > j->max_bytes && j->done > 1) drop_oldest(j);
}

void bvox_journal_begin(bvox_journal *j)
{
    if (!j) return;
    bvox_journal_end(j);
    drop_redo(j);
    if (j->n == j->cap) {
        int cap = j->cap ? 2 * j->cap : 16;
        step *s = bvox__mem_resize(j->steps, (size_t)cap * sizeof *s);
        if (!s) return; /* record will fail cleanly: no open step */
        j->steps = s;
        j->cap = cap;
    }
    j->steps[j->n++] = (step){0};
    j->done = j->n;
    j->open = 1;
    j->unsynced = 0;
}

static bvox_status check_vol(const bvox_journal *j, const bvox_volume *vol)
{
    if (!j || !vol) return bvox__fail(BVOX_EINVAL, "journal: missing input");
    if (vol->nx != j->dims.nx || vol->ny != j->dims.ny || vol->nz != j->dims.nz)
        return bvox__fail(BVOX_EINVAL, "journal: the volume's dimensions differ from the journal's");
    return BVOX_OK;
}

bvox_status bvox_journal_record(bvox_journal *j, const bvox_volume *vol, bvox_box box)
{
    bvox_status st = check_vol(j, vol);
    if (st) return st;
    bvox__clear_error();
    if (!j->open) bvox_journal_begin(j);
    if (!j->open) return bvox__fail(BVOX_ENOMEM, "out of memory");
    /* clip */
    int32_t lo[3] = {box.x0, box.y0, box.z0}, hi[3] = {box.x1, box.y1, box.z1};
    const int32_t n[3] = {vol->nx, vol->ny, vol->nz};
    for (int a = 0; a < 3; a++) {
        lo[a] = lo[a] < 0 ? 0 : lo[a];
        hi[a] = hi[a] > n[a] ? n[a] : hi[a];
        if (lo[a] >= hi[a]) return BVOX_OK; /* empty: nothing can change */
    }
    patch p = {lo[0], lo[1], hi[0], hi[1], (size_t)lo[2] / 64, ((size_t)hi[2] + 63) / 64, NULL, 0};
    size_t per = p.k1 - p.k0, cols = (size_t)(p.x1 - p.x0) * (size_t)(p.y1 - p.y0), words;
    if (!bvox__mul_size(cols, per, &words) || !bvox__mul_size(words, sizeof(uint64_t), &p.bytes))
        return bvox__fail(BVOX_ETOOBIG, "journal: patch too large");
    step *s = &j->steps[j->done - 1];
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 8;
        patch *np = bvox__mem_resize(s->p, (size_t)cap * sizeof *np);
        if (!np) return bvox__fail(BVOX_ENOMEM, "out of memory");
        s->p = np;
        s->cap = cap;
    }
    p.words = bvox__alloc(p.bytes, false, "undo patch", &st);
    if (!p.words) return st;
    uint64_t *w = p.words;
    for (int32_t y = p.y0; y < p.y1; y++)
        for (int32_t x = p.x0; x < p.x1; x++, w += per)
            memcpy(w, bvox__column_c(vol, x, y) + p.k0, per * sizeof(uint64_t));
    s->p[s->n++] = p;
    j->bytes += p.bytes + sizeof(patch);
    return BVOX_OK;
}

/* into_vol: vol ^= patch (undo, redo); else patch ^= vol (old -> delta).
 * Returns whether the patch holds any set bit afterwards. */
static int xor_patch(const patch *p, const bvox_volume *vol, int into_vol)
{
    size_t per = p->k1 - p->k0;
    uint64_t any = 0, *w = p->words;
    for (int32_t y = p->y0; y < p->y1; y++)
        for (int32_t x = p->x0; x < p->x1; x++, w += per) {
            uint64_t *col = (uint64_t *)bvox__column_c(vol, x, y) + p->k0;
            for (size_t k = 0; k < per; k++) {
                if (into_vol) col[k] ^= w[k];
                else w[k] ^= col[k];
                any |= w[k];
            }
        }
    return any != 0;
}

bvox_status bvox_journal_sync(bvox_journal *j, const bvox_volume *vol)
{
    bvox_status st = check_vol(j, vol);
    if (st) return st;
    if (!j->open) return BVOX_OK;
    step *s = &j->steps[j->done - 1];
    int keep = j->unsynced;
    for (int i = j->unsynced; i < s->n; i++) {
        if (xor_patch(&s->p[i], vol, 0)) {
            s->p[keep++] = s->p[i];
        } else { /* nothing changed there */
            bvox__free(s->p[i].words, s->p[i].bytes);
            j->bytes -= s->p[i].bytes + sizeof(patch);
        }
    }
    s->n = keep;
    j->unsynced = keep;
    return BVOX_OK;
}

static void apply(const step *s, bvox_volume *vol, bvox_box *changed)
{
    bvox_box b = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN, INT32_MIN};
    for (int i = s->n - 1; i >= 0; i--) {
        const patch *p = &s->p[i];
        xor_patch(p, vol, 1);
        int32_t z0 = (int32_t)(p->k0 * 64), z1 = (int32_t)(p->k1 * 64);
        z1 = z1 > vol->nz ? vol->nz : z1;
        b.x0 = p->x0 < b.x0 ? p->x0 : b.x0;
        b.y0 = p->y0 < b.y0 ? p->y0 : b.y0;
        b.z0 = z0 < b.z0 ? z0 : b.z0;
        b.x1 = p->x1 > b.x1 ? p->x1 : b.x1;
        b.y1 = p->y1 > b.y1 ? p->y1 : b.y1;
        b.z1 = z1 > b.z1 ? z1 : b.z1;
    }
    if (s->n == 0) b = (bvox_box){0, 0, 0, 0, 0, 0};
    if (changed) *changed = b;
}

bvox_status bvox_journal_undo(bvox_journal *j, bvox_volume *vol, int *done, bvox_box *changed)
{
    *done = 0;
    if (changed) *changed = (bvox_box){0, 0, 0, 0, 0, 0};
    bvox_status st = check_vol(j, vol);
    if (st) return st;
    if (j->open) {
        st = bvox_journal_sync(j, vol);
        if (st) return st;
        bvox_journal_end(j);
    }
    if (j->done == 0) return BVOX_OK;
    apply(&j->steps[--j->done], vol, changed);
    *done = 1;
    return BVOX_OK;
}

bvox_status bvox_journal_redo(bvox_journal *j, bvox_volume *vol, int *done, bvox_box *changed)
{
    *done = 0;
    if (changed) *changed = (bvox_box){0, 0, 0, 0, 0, 0};
    bvox_status st = check_vol(j, vol);
    if (st) return st;
    if (j->open || j->done == j->n) return BVOX_OK;
    apply(&j->steps[j->done++], vol, changed);
    *done = 1;
    return BVOX_OK;
}

int bvox_journal_can_undo(const bvox_journal *j) { return j && j->done > 0; }
int bvox_journal_can_redo(const bvox_journal *j) { return j && !j->open && j->done < j->n; }
size_t bvox_journal_bytes(const bvox_journal *j) { return j ? j->bytes : 0; }
int bvox_journal_steps(const bvox_journal *j) { return j ? j->done : 0; }
