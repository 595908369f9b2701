/*
 * dispatch.c — chooses the word kernels once, at first use, from the CPU's
 * features (or BVOX_SIMD=generic|avx2|avx512), race-free through an atomic
 * pointer: two threads racing on first use both store the same table.
 */
#include "internal.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static _Atomic(const bvox__kernels *) active;
static atomic_int active_level;

int bvox_simd_supported(bvox_simd level)
{
    switch (level) {
    case BVOX_SIMD_AUTO:
    case BVOX_SIMD_GENERIC: return 1;
#if defined(__x86_64__)
    case BVOX_SIMD_AVX2:
        return bvox__kernels_avx2.popcount != NULL && __builtin_cpu_supports("avx2");
    case BVOX_SIMD_AVX512:
        return bvox__kernels_avx512.popcount != NULL && __builtin_cpu_supports("avx512f") &&
               __builtin_cpu_supports("avx512vpopcntdq");
#else
    default: return 0;
#endif
    }
    return 0;
}

bool bvox__simd_files(bvox_simd level)
{
    if (bvox_simd_active() < level) return false;
#if defined(__x86_64__)
    /* the flags cmake/simd.cmake gives the src/DIR/NAME_avx2.c and NAME_avx512.c files */
    bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi2") &&
                __builtin_cpu_supports("popcnt");
    if (level == BVOX_SIMD_AVX2) return avx2;
    if (level == BVOX_SIMD_AVX512)
        return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512vpopcntdq");
#endif
    return level == BVOX_SIMD_GENERIC;
}

static bvox_simd best_level(void)
{
    if (bvox_simd_supported(BVOX_SIMD_AVX512)) return BVOX_SIMD_AVX512;
    if (bvox_simd_supported(BVOX_SIMD_AVX2)) return BVOX_SIMD_AVX2;
    return BVOX_SIMD_GENERIC;
}

static const bvox__kernels *table_for(bvox_simd level)
{
    switch (level) {
    case BVOX_SIMD_AVX512: return &bvox__kernels_avx512;
    case BVOX_SIMD_AVX2: return &bvox__kernels_avx2;
    default: return &bvox__kernels_generic;
    }
}

const char *bvox_simd_name(bvox_simd level)
{
    switch (level) {
    case BVOX_SIMD_AUTO: return "auto";
    case BVOX_SIMD_GENERIC: return "generic";
    case BVOX_SIMD_AVX2: return "avx2";
    case BVOX_SIMD_AVX512: return "avx512";
    }
    return "?";
}

bvox_status bvox_simd_set(bvox_simd level)
{
    if (level == BVOX_SIMD_AUTO) level = best_level();
    if (!bvox_simd_supported(level))
        return bvox__fail(BVOX_EUNSUPPORTED, "this CPU or build has no %s path",
                          bvox_simd_name(level));
    atomic_store(&active_level, (int)level);
    atomic_store(&active, table_for(level));
    return BVOX_OK;
}

static void init_from_env(void)
{
    bvox_simd level = best_level();
    const char *env = getenv("BVOX_SIMD");
    if (env && *env) {
        bvox_simd want = BVOX_SIMD_AUTO;
        if (!strcmp(env, "generic")) want = BVOX_SIMD_GENERIC;
        else if (!strcmp(env, "avx2")) want = BVOX_SIMD_AVX2;
        else if (!strcmp(env, "avx512")) want = BVOX_SIMD_AVX512;
        /* An unknown or unsupported request falls back to the best path:
         * the environment must never make a correct program fail. */
        if (want != BVOX_SIMD_AUTO && bvox_simd_supported(want)) level = want;
    }
    atomic_store(&active_level, (int)level);
    atomic_store(&active, table_for(level));
}

const bvox__kernels *bvox__simd(void)
{
    const bvox__kernels *k = atomic_load_explicit(&active, memory_order_acquire);
    if (k) return k;
    init_from_env();
    return atomic_load(&active);
}

bvox_simd bvox_simd_active(void)
{
    bvox__simd();
    return (bvox_simd)atomic_load(&active_level);
}
