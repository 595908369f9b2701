/*
 * harness.h — a tiny test runner. A test file defines cases with TEST(name)
 * and returns 0 (pass) or 1 (fail) through the CHECK macros, which report the
 * file, the line and both values. The runner lists cases (--list), runs one by
 * name (so CTest registers each case as its own test) or runs all.
 *
 * Registration uses constructors: that is safe here because each case lives in
 * the test executable's own object file, never in a static library.
 */
#ifndef BVOX_TEST_HARNESS_H
#define BVOX_TEST_HARNESS_H

#include "bvox.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

typedef int (*harness_fn)(void);
void harness_register(const char *name, harness_fn fn);
/* A fresh scratch directory for this case (created on first call). */
const char *harness_tmpdir(void);
/* Path inside the scratch directory (static buffer, rotates over 8 slots). */
const char *harness_path(const char *name);
/* Entries of dir other than . and .. (-1 if it cannot be read): what an
 * output folder holds after a write or a failure. */
int harness_count_entries(const char *dir);
/* Deterministic random numbers (xorshift), seeded per case. */
uint64_t harness_rand(void);
/* Folder with the test data files (tests/data). */
const char *harness_data_dir(void);
/* Golden files. harness_golden_path: NAME under tests/data, or under
 * $BVOX_GOLDEN_DIR when that is set (the test of the update mode uses a
 * scratch folder). harness_golden_update: in update mode
 * (BVOX_UPDATE_GOLDEN set and not "0"), write img as golden NAME, say so and
 * return 1: the case must then FAIL (return 1), so that a run which rewrote
 * its own answers never passes; look at the new file, commit it, re-run
 * without the variable. 0 (and nothing written) otherwise. A failed write
 * also returns 1. */
const char *harness_golden_path(const char *name);
int harness_golden_update(const bvox_image *img, const char *name);
/* Compare img with golden NAME (golden/NAME.png) pixel by pixel: same size
 * and channels, mean absolute difference at most max_mean and no sample off
 * by more than max_worst (a moved edge or letter fails). Destroys img. 0 when
 * it matches; 1 (said on stderr) when not, or in update mode (see above). */
int harness_golden_compare(bvox_image *img, const char *name, double max_mean, int max_worst);

#define TEST(name)                                                                     \
    static int test_##name(void);                                                      \
    __attribute__((constructor)) static void register_##name(void)                     \
    {                                                                                  \
        harness_register(#name, test_##name);                                          \
    }                                                                                  \
    static int test_##name(void)

#define CHECK(cond)                                                                    \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);   \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

#define CHECK_EQ(a, b)                                                                 \
    do {                                                                               \
        long long va_ = (long long)(a), vb_ = (long long)(b);                          \
        if (va_ != vb_) {                                                              \
            fprintf(stderr, "%s:%d: CHECK_EQ failed: %s == %s (%lld vs %lld)\n",       \
                    __FILE__, __LINE__, #a, #b, va_, vb_);                             \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                          \
    do {                                                                               \
        double va_ = (double)(a), vb_ = (double)(b);                                   \
        if (!(fabs(va_ - vb_) <= (tol))) {                                             \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s ~ %s (%.9g vs %.9g, tol %g)\n", \
                    __FILE__, __LINE__, #a, #b, va_, vb_, (double)(tol));              \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

/* Expect BVOX_OK; print the library's message otherwise. */
#define CHECK_OK(expr)                                                                 \
    do {                                                                               \
        bvox_status st_ = (expr);                                                      \
        if (st_ != BVOX_OK) {                                                          \
            fprintf(stderr, "%s:%d: %s returned %s: %s\n", __FILE__, __LINE__, #expr,  \
                    bvox_status_name(st_), bvox_errmsg());                             \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

/* Expect a given failure status. */
#define CHECK_STATUS(expr, want)                                                       \
    do {                                                                               \
        bvox_status st_ = (expr);                                                      \
        if (st_ != (want)) {                                                           \
            fprintf(stderr, "%s:%d: %s returned %s, wanted %s (%s)\n", __FILE__,       \
                    __LINE__, #expr, bvox_status_name(st_), bvox_status_name(want),    \
                    bvox_errmsg());                                                    \
            return 1;                                                                  \
        }                                                                              \
    } while (0)

/* The triangles of m as sorted rows of 9 coordinates, each rotated to start
 * at its smallest vertex (orientation kept): two meshes are equal up to
 * order when these rows are. Caller frees. */
double *harness_mesh_canon(const bvox_mesh *m);

#endif
