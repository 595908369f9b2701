/*
 * zarr_meta.c — Zarr v2 array metadata (.zarray) and the NGFF 0.4
 * multiscales attributes (.zattrs), read into plain structs and validated
 * before anything they describe is allocated: 3-D only, C order, no filters,
 * dtype one of bvox's sample types (or bool), compressor null, zlib, gzip or
 * blosc, every shape and chunk entry an integer in range.
 */
#include "zarr.h"

#include <math.h>
#include <string.h>

static bvox_status bad(const char *name, const char *what)
{
    return bvox__fail(BVOX_EFORMAT, "%s: %s", name, what);
}

/* 3 positive integers <= max each. */
static bool triple(const bvox__jtree *j, const bvox__jnode *a, int64_t max, int64_t out[3])
{
    if (!a || a->type != BVOX__JT_ARRAY || a->count != 3) return false;
    for (int i = 0; i < 3; i++) {
        const bvox__jnode *e = bvox__jtree_at(j, a, i);
        if (e->type != BVOX__JT_NUMBER || !e->is_int || e->num < 1 || e->num > (double)max)
            return false;
        out[i] = (int64_t)e->num;
    }
    return true;
}

static bool parse_dtype(const char *s, bvox__zarr_meta *m)
{
    if (strlen(s) != 3) return false;
    char order = s[0], kind = s[1], size = s[2];
    if (order != '<' && order != '>' && order != '|') return false;
    m->big_endian = order == '>';
    m->is_bool = false;
    int n = size - '0';
    if (kind == 'b' && n == 1) {
        m->is_bool = true;
        m->dtype = BVOX_DT_U8;
        return true;
    }
    static const struct {
        char kind;
        int size;
        bvox_dtype t;
    } map[] = {
        {'u', 1, BVOX_DT_U8},  {'i', 1, BVOX_DT_I8},  {'u', 2, BVOX_DT_U16}, {'i', 2, BVOX_DT_I16},
        {'u', 4, BVOX_DT_U32}, {'i', 4, BVOX_DT_I32}, {'u', 8, BVOX_DT_U64}, {'i', 8, BVOX_DT_I64},
        {'f', 4, BVOX_DT_F32}, {'f', 8, BVOX_DT_F64},
    };
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (map[i].kind == kind && map[i].size == n) {
            m->dtype = map[i].t;
            /* one-byte types may say '|' (no byte order); others need one */
            return n == 1 || order != '|';
        }
    return false;
}

bvox_status bvox__zarr_meta_parse(const char *text, size_t size, const char *name,
                                  bvox__zarr_meta *out)
{
    memset(out, 0, sizeof *out);
    out->sep = '.';
    bvox__jtree j;
    bvox_status st = bvox__jtree_parse(text, size, name, &j);
    if (st) return st;
    const bvox__jnode *root = &j.nodes[0], *n;
    if (root->type != BVOX__JT_OBJECT) {
        st = bad(name, "not a JSON object");
        goto done;
    }
    n = bvox__jtree_get(&j, root, "zarr_format");
    if (!n || n->type != BVOX__JT_NUMBER || n->num != 2) {
        st = bvox__fail(BVOX_EUNSUPPORTED, "%s: zarr_format must be 2 (Zarr v2)", name);
        goto done;
    }
    n = bvox__jtree_get(&j, root, "shape");
    if (!n || n->type != BVOX__JT_ARRAY || n->count != 3) {
        st = bvox__fail(BVOX_EUNSUPPORTED, "%s: \"shape\" must have 3 dimensions (z, y, x)",
                        name);
        goto done;
    }
    if (!triple(&j, n, BVOX_MAX_DIM, out->shape)) {
        st = bvox__fail(BVOX_EFORMAT, "%s: \"shape\" entries must be integers in 1..%d", name,
                        BVOX_MAX_DIM);
        goto done;
    }
    if (!triple(&j, bvox__jtree_get(&j, root, "chunks"), BVOX_MAX_DIM, out->chunks)) {
        st = bad(name, "\"chunks\" must be 3 integers in 1..65535");
        goto done;
    }
    n = bvox__jtree_get(&j, root, "dtype");
    if (!n || n->type != BVOX__JT_STRING || !parse_dtype(n->str, out)) {
        st = bvox__fail(BVOX_EUNSUPPORTED,
                        "%s: dtype %s%s%s is not supported (integers, floats or bool, e.g. "
                        "\"|u1\", \"<i2\", \"<f4\")",
                        name, n && n->type == BVOX__JT_STRING ? "\"" : "",
                        n && n->type == BVOX__JT_STRING ? n->str : "(missing)",
                        n && n->type == BVOX__JT_STRING ? "\"" : "");
        goto done;
    }
    n = bvox__jtree_get(&j, root, "order");
    if (!n || n->type != BVOX__JT_STRING || strcmp(n->str, "C")) {
        st = bvox__fail(BVOX_EUNSUPPORTED, "%s: only order \"C\" is supported", name);
        goto done;
    }
    n = bvox__jtree_get(&j, root, "filters");
    if (n && !(n->type == BVOX__JT_NULL ||
               (n->type == BVOX__JT_ARRAY && n->count == 0))) {
        st = bvox__fail(BVOX_EUNSUPPORTED, "%s: filters are not supported", name);
        goto done;
    }
    n = bvox__jtree_get(&j, root, "compressor");
    if (!n || n->type == BVOX__JT_NULL) {
        out->codec = BVOX__ZARR_RAW;
    } else {
        const bvox__jnode *id = bvox__jtree_get(&j, n, "id");
        if (!id || id->type != BVOX__JT_STRING) {
            st = bad(name, "compressor without an \"id\"");
            goto done;
        }
        if (!strcmp(id->str, "zlib")) out->codec = BVOX__ZARR_ZLIB;
        else if (!strcmp(id->str, "gzip")) out->codec = BVOX__ZARR_GZIP;
        else if (!strcmp(id->str, "blosc")) out->codec = BVOX__ZARR_BLOSC;
        else {
            st = bvox__fail(BVOX_EUNSUPPORTED,
                            "%s: unknown compressor \"%.40s\" (supported: zlib, gzip, blosc)",
                            name, id->str);
            goto done;
        }
    }
    n = bvox__jtree_get(&j, root, "fill_value");
    if (n && n->type == BVOX__JT_NUMBER) {
        out->has_fill = true;
        out->fill = n->num;
    } else if (n && n->type == BVOX__JT_STRING &&
               (!strcmp(n->str, "NaN") || !strcmp(n->str, "Infinity") ||
                !strcmp(n->str, "-Infinity"))) {
        out->has_fill = true;
        out->fill = !strcmp(n->str, "NaN") ? NAN : n->str[0] == '-' ? -INFINITY : INFINITY;
    } else if (n && (n->type == BVOX__JT_FALSE || n->type == BVOX__JT_TRUE)) {
        out->has_fill = true;
        out->fill = n->type == BVOX__JT_TRUE;
    }
    n = bvox__jtree_get(&j, root, "dimension_separator");
    if (n) {
        if (n->type != BVOX__JT_STRING || (strcmp(n->str, ".") && strcmp(n->str, "/"))) {
            st = bad(name, "dimension_separator must be \".\" or \"/\"");
            goto done;
        }
        out->sep = n->str[0];
    }
done:
    bvox__jtree_release(&j);
    return st;
}

bvox_status bvox__zarr_attrs_parse(const char *text, size_t size, const char *name,
                                   bvox__zarr_attrs *out)
{
    return bvox__zarr_attrs_parse_level(text, size, name, 0, out);
}

bvox_status bvox__zarr_attrs_parse_level(const char *text, size_t size, const char *name,
                                         int32_t level, bvox__zarr_attrs *out)
{
    memset(out, 0, sizeof *out);
    out->spacing[0] = out->spacing[1] = out->spacing[2] = 1.0;
    bvox__jtree j;
    bvox_status st = bvox__jtree_parse(text, size, name, &j);
    if (st) return st;
    const bvox__jnode *ms = bvox__jtree_get(&j, &j.nodes[0], "multiscales");
    const bvox__jnode *m0 = bvox__jtree_at(&j, ms, 0);
    if (!m0) { /* a plain group: no NGFF metadata, only level 0 (its array "0") */
        if (level > 0)
            st = bvox__fail(BVOX_EINVAL, "%s: no resolution level %d (no multiscales)", name,
                            (int)level);
        goto done;
    }
    const bvox__jnode *axes = bvox__jtree_get(&j, m0, "axes");
    /* the last three axes are z, y, x (NGFF puts time and channel first) */
    int32_t naxes = axes && axes->type == BVOX__JT_ARRAY ? axes->count : 0;
    if (naxes && naxes != 3) {
        st = bvox__fail(BVOX_EUNSUPPORTED, "%s: %d axes; bvox reads 3-D (z, y, x) images",
                        name, (int)naxes);
        goto done;
    }
    for (int32_t a = 0; a < naxes; a++) {
        const bvox__jnode *u = bvox__jtree_get(&j, bvox__jtree_at(&j, axes, a), "unit");
        if (u && u->type == BVOX__JT_STRING) {
            const char *s = u->str;
            /* NGFF units are UDUNITS names; bvox's are the short forms */
            if (!strcmp(s, "micrometer")) s = "um";
            else if (!strcmp(s, "millimeter")) s = "mm";
            else if (!strcmp(s, "nanometer")) s = "nm";
            else if (!strcmp(s, "centimeter")) s = "cm";
            else if (!strcmp(s, "meter")) s = "m";
            snprintf(out->unit, sizeof out->unit, "%s", s);
        }
    }
    const bvox__jnode *dsets = bvox__jtree_get(&j, m0, "datasets");
    out->nlevels = dsets && dsets->type == BVOX__JT_ARRAY ? dsets->count : 0;
    if (level > 0 && level >= out->nlevels) {
        st = bvox__fail(BVOX_EINVAL, "%s: no resolution level %d (the multiscales has %d)", name,
                        (int)level, (int)out->nlevels);
        goto done;
    }
    const bvox__jnode *ds = bvox__jtree_at(&j, dsets, level);
    const bvox__jnode *path = bvox__jtree_get(&j, ds, "path");
    if (path && path->type == BVOX__JT_STRING) {
        if (path->len == 0 || path->len >= sizeof out->path || strstr(path->str, "..") ||
            path->str[0] == '/' || memchr(path->str, '\0', path->len)) {
            st = bad(name, "multiscales dataset path is empty, too long or leaves the folder");
            goto done;
        }
        memcpy(out->path, path->str, path->len + 1);
    }
    const bvox__jnode *ct = bvox__jtree_get(&j, ds, "coordinateTransformations");
    for (int32_t k = 0; ct && k < ct->count; k++) {
        const bvox__jnode *t = bvox__jtree_at(&j, ct, k);
        const bvox__jnode *type = bvox__jtree_get(&j, t, "type");
        if (type && type->type == BVOX__JT_STRING && !strcmp(type->str, "translation")) {
            const bvox__jnode *tr = bvox__jtree_get(&j, t, "translation");
            if (!tr || tr->type != BVOX__JT_ARRAY || tr->count != 3) {
                st = bad(name, "translation transform must have 3 entries (z, y, x)");
                goto done;
            }
            for (int a = 0; a < 3; a++) {
                const bvox__jnode *e = bvox__jtree_at(&j, tr, a);
                if (e->type != BVOX__JT_NUMBER || !isfinite(e->num)) {
                    st = bad(name, "translation entries must be finite numbers");
                    goto done;
                }
                out->origin[2 - a] = e->num;
            }
            out->have_translation = true;
            continue;
        }
        if (!type || type->type != BVOX__JT_STRING || strcmp(type->str, "scale")) continue;
        const bvox__jnode *sc = bvox__jtree_get(&j, t, "scale");
        if (!sc || sc->type != BVOX__JT_ARRAY || sc->count != 3) {
            st = bad(name, "scale transform must have 3 entries (z, y, x)");
            goto done;
        }
        for (int a = 0; a < 3; a++) {
            const bvox__jnode *e = bvox__jtree_at(&j, sc, a);
            if (e->type != BVOX__JT_NUMBER || !(e->num > 0)) {
                st = bad(name, "scale entries must be positive numbers");
                goto done;
            }
            out->spacing[2 - a] = e->num;
        }
        out->have_scale = true;
    }
done:
    bvox__jtree_release(&j);
    return st;
}
