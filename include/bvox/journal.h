/*
 * bvox/journal.h — undo and redo for in-place edits, with memory that grows
 * with the size of the edits, not of the volume. Included by bvox.h.
 *
 * Before an edit, bvox_journal_record saves the words of the box it may
 * change (whole z-words of the box's columns); bvox_journal_sync then turns
 * each saved word into the XOR of its old and new value, so one patch both
 * undoes and redoes its edit (a XOR is its own inverse). A step groups the
 * patches of one user action (a brush stroke is one step of many small
 * patches). A brush stroke on a 1024^3 model stores only the words of the
 * balls it touched. Patches that turn out all zero (the edit changed nothing
 * there) are dropped.
 */
#ifndef BVOX_JOURNAL_H
#define BVOX_JOURNAL_H

typedef struct bvox_journal bvox_journal;

/* An empty journal for edits of vol's dimensions; max_bytes caps the memory
 * of the kept steps (0: no cap): when a new step goes over it, the oldest
 * steps are forgotten. */
BVOX_API bvox_status bvox_journal_create(bvox_dims dims, size_t max_bytes, bvox_journal **out);
BVOX_API void bvox_journal_destroy(bvox_journal *j);

/* Open a new step (closing an open one); the steps that could be redone are
 * dropped. */
BVOX_API void bvox_journal_begin(bvox_journal *j);
/* Save the words of box (half-open, clipped to the volume; empty: nothing)
 * into the open step (one is opened if none is), before an edit that changes
 * only voxels inside it. BVOX_EINVAL for a volume of other dimensions,
 * BVOX_ETOOBIG/BVOX_ENOMEM for memory (then nothing is recorded). */
BVOX_API bvox_status bvox_journal_record(bvox_journal *j, const bvox_volume *vol, bvox_box box);
/* After the edit: turn the patches recorded since the last sync into XOR
 * deltas against vol (the edited volume). */
BVOX_API bvox_status bvox_journal_sync(bvox_journal *j, const bvox_volume *vol);
/* Close the open step (sync first); an empty step is dropped. */
BVOX_API void bvox_journal_end(bvox_journal *j);

/* Undo the last closed step (closing an open one first) / redo the last
 * undone one. *changed (may be NULL) receives the box of the words touched
 * (half-open, all zero when nothing). Returns BVOX_OK with *done = 0 when
 * there is nothing to undo or redo. */
BVOX_API bvox_status bvox_journal_undo(bvox_journal *j, bvox_volume *vol, int *done,
                                       bvox_box *changed);
BVOX_API bvox_status bvox_journal_redo(bvox_journal *j, bvox_volume *vol, int *done,
                                       bvox_box *changed);
BVOX_API int bvox_journal_can_undo(const bvox_journal *j);
BVOX_API int bvox_journal_can_redo(const bvox_journal *j);
/* Bytes held by the patches (saved words plus bookkeeping), and the number
 * of steps that can be undone. */
BVOX_API size_t bvox_journal_bytes(const bvox_journal *j);
BVOX_API int bvox_journal_steps(const bvox_journal *j);

#endif /* BVOX_JOURNAL_H */
