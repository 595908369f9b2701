/*
 * csg_expr.h — private interface between the parser of CSG expressions
 * (csg_expr.c: text to tree, with every syntax and parameter error found
 * there, with its column) and the evaluator (csg_eval.c: tree to volume).
 * The language is documented at bvox_csg_eval in bvox.h.
 *
 * The tree is an array of nodes linked by index. A chain "a + b - c" is one
 * CHAIN node whose members (a, b, c) are linked through `next`, each member
 * carrying the operation that combines it into the running result (the first
 * member's op is unused): evaluation walks a chain iteratively, so only
 * nesting (bounded by BVOX_CSG_MAX_DEPTH) costs stack.
 */
#ifndef BVOX_CSG_EXPR_H
#define BVOX_CSG_EXPR_H

#include "internal.h"

typedef enum bvox__csg_kind {
    BVOX__CSG_FILE = 0,
    BVOX__CSG_PRIM = 1,
    BVOX__CSG_NOT = 2,
    BVOX__CSG_CHAIN = 3
} bvox__csg_kind;

/* prim: a bvox_shape_kind, or this for the half-space */
#define BVOX__PRIM_HALFSPACE 100

enum { BVOX__PLACE_NONE = 0, BVOX__PLACE_VOXELS = 1, BVOX__PLACE_PHYSICAL = 2 };

typedef struct bvox__csg_node {
    bvox__csg_kind kind;
    int col;         /* 1-based column where the operand starts (messages) */
    bvox_csg_op op;  /* as a chain member: how it combines with what precedes */
    int32_t child;   /* NOT: the operand; CHAIN: the first member; else -1 */
    int32_t next;    /* next member of the enclosing chain, -1 if last */
    /* FILE */
    size_t name;     /* offset of the NUL-terminated name in the tree's pool */
    int place;       /* BVOX__PLACE_* */
    double offset[3];
    /* PRIM */
    int prim;
    int at_given;    /* 0: centre the shape in the output grid */
    bvox_shape shape;
    double plane[4]; /* half-space a, b, c, d */
} bvox__csg_node;

typedef struct bvox__csg_tree {
    bvox__csg_node *nodes;
    int32_t n, cap;
    char *pool; /* file names */
    size_t pool_used, pool_cap;
    int32_t root;
} bvox__csg_tree;

/* Parse expr into *tree (zeroed first). BVOX_EINVAL with
 * "csg: <what> at column N" on any error, BVOX_ENOMEM; the tree is freed on
 * failure. */
bvox_status bvox__csg_parse(const char *expr, bvox__csg_tree *tree);
void bvox__csg_tree_free(bvox__csg_tree *tree);

static inline const char *bvox__csg_name(const bvox__csg_tree *t, const bvox__csg_node *n)
{
    return t->pool + n->name;
}

#endif
