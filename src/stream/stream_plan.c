/*
 * stream_plan.c — when a volume goes out of core and how deep its slabs are.
 *
 * The in-memory operations hold the volume's words several times over (the
 * measure labels a complement copy, morphology keeps input and output, the
 * labeller copies the words and adds run tables): a volume whose words times
 * STREAM_COPIES exceed the budget is streamed. A slab is sized the same way,
 * with a fixed cost per column for the labeller's tables and the faces kept
 * between slabs.
 */
#include "stream/stream.h"

enum { STREAM_COPIES = 6, COLUMN_BYTES = 64 };

static double words_bytes(bvox_dims d, double slices)
{
    return (double)d.nx * (double)d.ny * 8.0 * ((slices + 63.0) / 64.0);
}

bool bvox__stream_needed(bvox_dims d)
{
    return words_bytes(d, d.nz) * STREAM_COPIES > (double)bvox_memory_budget();
}

static _Atomic int32_t depth_cap; /* test hook, 0 = none */

void bvox__stream_set_depth_cap(int32_t cap) { depth_cap = cap; }

int32_t bvox__stream_depth(const bvox__slab_source *src, int32_t halo, int32_t align, int copies,
                           size_t extra)
{
    const bvox_dims d = src->dims;
    if (align < 1) align = 1;
    double budget = (double)bvox_memory_budget();
    double fixed =
        (double)d.nx * (double)d.ny * COLUMN_BYTES + (double)src->read_bytes + (double)extra;
    int32_t best = align;
    /* the deepest multiple of align that fits; slabs deeper than the volume
     * gain nothing */
    for (int64_t t = align; t < (int64_t)d.nz + align; t += align) {
        double need = words_bytes(d, (double)t + 2.0 * halo) * (copies < 1 ? 1 : copies) + fixed;
        if (need > budget * 0.75) break;
        best = (int32_t)t;
    }
    int32_t cap = depth_cap;
    if (cap > 0 && best > cap) best = cap < align ? align : cap / align * align;
    return best;
}
