/*
 * fuzz_csg_expr.c — libFuzzer target for the CSG expression language
 * (bvox_csg_eval). The input is the expression text. It is parsed alone
 * (parse_only), then evaluated on a small grid with a loader that serves
 * every file name from memory (one of three small volumes of awkward sizes,
 * chosen by the name's length), so the evaluator runs without touching the
 * file system. Checks: a parse error is the evaluation's error too, a result
 * keeps the volume invariants, and nothing leaks from the budgeted allocator.
 */
#include "bvox.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static bvox_status load(void *ctx, const char *name, bvox_volume **out)
{
    static const bvox_dims dims[3] = {{7, 5, 65}, {3, 9, 1}, {9, 7, 70}};
    bvox_dims d = dims[strlen(name) % 3];
    bvox_volume *v = NULL;
    bvox_status st = bvox_volume_create(d, &v);
    if (st) return st;
    /* a few voxels so that the operations have something to do */
    for (int32_t x = 0; x < d.nx; x += 2)
        for (int32_t z = x % 3; z < d.nz; z += 5) bvox_volume_set(v, x, x % d.ny, z, 1);
    *out = v;
    return BVOX_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 4096) return 0; /* long inputs only slow the fuzzer down */
    char *expr = malloc(size + 1);
    if (!expr) return 0;
    memcpy(expr, data, size);
    expr[size] = '\0';
    bvox_set_memory_budget((size_t)64 << 20);
    bvox_csg_eval_opts o = bvox_csg_eval_opts_default();
    o.dims = (bvox_dims){9, 7, 70};
    o.load = load;
    o.parse_only = 1;
    bvox_volume *vol = NULL;
    bvox_status parsed = bvox_csg_eval(expr, &o, &vol);
    if (vol) abort();
    o.parse_only = 0;
    bvox_status st = bvox_csg_eval(expr, &o, &vol);
    if (parsed != BVOX_OK && st != parsed) abort();
    if (st == BVOX_OK) {
        if (!vol || bvox_volume_check(vol) != BVOX_OK) abort();
        (void)bvox_volume_count(vol);
        bvox_volume_destroy(vol);
    } else if (vol) {
        abort();
    }
    free(expr);
    if (bvox_memory_in_use() != 0) abort();
    return 0;
}
