/*
 * csg_eval.c — bvox_csg_eval: evaluates the tree that csg_expr.c parsed into
 * a volume on the output grid (the first file's, or the one the options
 * give). Every operation is a whole-word one from elsewhere in the library:
 * a file operand is combined with bvox_csg_apply at its offset, straight
 * from the loaded volume; a primitive is drawn straight into the running
 * result with bvox_shape_draw / bvox_halfspace_draw (no temporary); only a
 * parenthesised chain or a complement needs a temporary grid volume. Each
 * distinct file is loaded once and kept until the end.
 */
#include "ops/csg_expr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct loaded {
    const char *name;
    bvox_volume *vol;
} loaded;

typedef struct eval_ctx {
    const bvox__csg_tree *t;
    const bvox_csg_eval_opts *o;
    bvox_dims dims;
    bvox_geometry geom;
    loaded *files;
    int32_t nfiles;
} eval_ctx;

bvox_csg_eval_opts bvox_csg_eval_opts_default(void)
{
    bvox_csg_eval_opts o;
    memset(&o, 0, sizeof o);
    o.geometry = bvox_geometry_default();
    return o;
}

/* Add "csg: column N" in front of the current message. */
static bvox_status at_column(bvox_status st, int col)
{
    char prefix[48];
    snprintf(prefix, sizeof prefix, "csg: column %d", col);
    bvox__error_prefix(prefix);
    return st;
}

static bool same_spacing(const double *a, const double *b)
{
    for (int i = 0; i < 3; i++)
        if (!(fabs(a[i] - b[i]) <= 1e-4 * fmax(fabs(a[i]), fabs(b[i])))) return false;
    return true;
}

/* The loaded volume of a file node (loading it on first use). check: compare
 * its voxel size with the grid's (not for the file that defines the grid). */
static bvox_status file_volume(eval_ctx *c, const bvox__csg_node *n, bool check,
                               const bvox_volume **out)
{
    const char *name = bvox__csg_name(c->t, n);
    for (int32_t i = 0; i < c->nfiles; i++)
        if (!strcmp(c->files[i].name, name)) {
            *out = c->files[i].vol;
            return BVOX_OK;
        }
    bvox_volume *v = NULL;
    bvox_status st = c->o->load ? c->o->load(c->o->load_ctx, name, &v)
                                : bvox_read(name, c->o->read_opts, &v);
    if (!st && !v) st = bvox__fail(BVOX_EINVAL, "%s: the loader returned no volume", name);
    if (st) return at_column(st, n->col);
    c->files[c->nfiles++] = (loaded){name, v};
    const bvox_geometry *g = bvox_volume_geometry(v);
    if (check && !same_spacing(g->spacing, c->geom.spacing))
        return bvox__fail(BVOX_EINVAL,
                          "csg: column %d: %s has voxels of %g x %g x %g, the output grid "
                          "%g x %g x %g: give both the same voxel size",
                          n->col, name, g->spacing[0], g->spacing[1], g->spacing[2],
                          c->geom.spacing[0], c->geom.spacing[1], c->geom.spacing[2]);
    if (check && g->unit[0] && c->geom.unit[0] && strcmp(g->unit, c->geom.unit))
        return bvox__fail(BVOX_EINVAL, "csg: column %d: %s is in %s, the output grid in %s",
                          n->col, name, g->unit, c->geom.unit);
    *out = v;
    return BVOX_OK;
}

static bvox_status grid_volume(const eval_ctx *c, bvox_volume **out)
{
    bvox_volume *v = NULL;
    bvox_status st = bvox_volume_create(c->dims, &v);
    if (!st) st = bvox_volume_set_geometry(v, &c->geom);
    if (st) {
        bvox_volume_destroy(v);
        return st;
    }
    *out = v;
    return BVOX_OK;
}

static bvox_status eval_node(eval_ctx *c, int32_t id, bvox_volume **out);

/* acc = acc OP node */
static bvox_status apply_node(eval_ctx *c, bvox_volume *acc, bvox_csg_op op, int32_t id)
{
    const bvox__csg_node *n = &c->t->nodes[id];
    bvox_status st;
    if (n->kind == BVOX__CSG_FILE) {
        const bvox_volume *f;
        if ((st = file_volume(c, n, true, &f))) return st;
        int32_t off[3] = {0, 0, 0};
        for (int i = 0; i < 3; i++) {
            double v = n->offset[i];
            if (n->place == BVOX__PLACE_PHYSICAL) v = round(v / c->geom.spacing[i]);
            if (!(fabs(v) <= 1e9))
                return bvox__fail(BVOX_EINVAL, "csg: column %d: offset too large", n->col);
            off[i] = (int32_t)v;
        }
        return bvox_csg_apply(acc, op, f, off);
    }
    if (n->kind == BVOX__CSG_PRIM) {
        if (n->prim == BVOX__PRIM_HALFSPACE)
            st = bvox_halfspace_draw(acc, n->plane[0], n->plane[1], n->plane[2], n->plane[3],
                                     op, NULL);
        else {
            bvox_shape s = n->shape;
            if (!n->at_given) /* the centre of the grid, in the shapes' frame */
                for (int i = 0; i < 3; i++) {
                    int32_t d = i == 0 ? c->dims.nx : i == 1 ? c->dims.ny : c->dims.nz;
                    s.center[i] = c->geom.origin[i] + (d - 1) / 2.0 * c->geom.spacing[i];
                }
            st = bvox_shape_draw(acc, &s, op);
        }
        return st ? at_column(st, n->col) : BVOX_OK;
    }
    bvox_volume *tmp = NULL;
    if ((st = eval_node(c, id, &tmp))) return st;
    st = bvox_csg_apply(acc, op, tmp, NULL);
    bvox_volume_destroy(tmp);
    return st;
}

/* A new grid volume holding the node. */
static bvox_status eval_node(eval_ctx *c, int32_t id, bvox_volume **out)
{
    const bvox__csg_node *n = &c->t->nodes[id];
    bvox_volume *acc = NULL;
    bvox_status st;
    if (n->kind == BVOX__CSG_NOT) {
        if ((st = eval_node(c, n->child, &acc))) return st;
        bvox_volume_complement(acc);
    } else if (n->kind == BVOX__CSG_CHAIN) {
        if ((st = eval_node(c, n->child, &acc))) return st;
        for (int32_t m = c->t->nodes[n->child].next; m >= 0; m = c->t->nodes[m].next)
            if ((st = apply_node(c, acc, c->t->nodes[m].op, m))) {
                bvox_volume_destroy(acc);
                return st;
            }
    } else {
        if ((st = grid_volume(c, &acc))) return st;
        if ((st = apply_node(c, acc, BVOX_CSG_UNION, id))) {
            bvox_volume_destroy(acc);
            return st;
        }
    }
    *out = acc;
    return BVOX_OK;
}

bvox_status bvox_csg_eval(const char *expr, const bvox_csg_eval_opts *opts, bvox_volume **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "csg: no output");
    *out = NULL;
    bvox_csg_eval_opts defaults = bvox_csg_eval_opts_default();
    if (!opts) opts = &defaults;
    bvox__csg_tree t;
    bvox_status st = bvox__csg_parse(expr, &t);
    if (st || opts->parse_only) {
        if (!st) bvox__csg_tree_free(&t);
        return st;
    }
    eval_ctx c = {&t, opts, opts->dims, opts->geometry, NULL, 0};
    int32_t first = -1, nfile = 0;
    for (int32_t i = 0; i < t.n; i++)
        if (t.nodes[i].kind == BVOX__CSG_FILE) {
            nfile++;
            if (first < 0 || t.nodes[i].col < t.nodes[first].col) first = i;
        }
    if (nfile && !(c.files = bvox__mem_zalloc((size_t)nfile, sizeof *c.files)))
        st = bvox__fail(BVOX_ENOMEM, "csg: out of memory");
    if (!st && first >= 0) {
        const bvox_volume *g;
        if (!(st = file_volume(&c, &t.nodes[first], false, &g))) {
            c.dims = bvox_volume_dims(g);
            c.geom = *bvox_volume_geometry(g);
        }
    } else if (!st && (c.dims.nx <= 0 || c.dims.ny <= 0 || c.dims.nz <= 0)) {
        st = bvox__fail(BVOX_EINVAL, "csg: the expression has no file operand and no "
                                     "output grid dimensions were given");
    }
    if (!st) st = eval_node(&c, t.root, out);
    for (int32_t i = 0; i < c.nfiles; i++) bvox_volume_destroy(c.files[i].vol);
    free(c.files);
    bvox__csg_tree_free(&t);
    if (!st) BVOX_CHECK_VOLUME(*out);
    return st;
}
