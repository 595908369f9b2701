/*
 * labels_read.c — a label volume read once and split into one packed binary
 * volume per label, each cropped to its bounding box grown by one voxel.
 *
 * Two passes over the samples, one z-slice at a time:
 *   1. every sample becomes a label index (a direct table for 8- and 16-bit
 *      samples, an open-addressing hash otherwise); counts, bounding boxes
 *      and the faces between different labels (x and y within the slice, z
 *      against the previous slice) are summed. Distinct labels beyond
 *      max_labels stop the pass before anything per label is allocated, so
 *      10^6 labels (or noise read as labels) cost one small table.
 *   2. the crops are allocated (their sizes are now known) and the slices
 *      are mapped again, each voxel setting its bit in its label's crop.
 * Only two slices of indices are held; memory follows the objects.
 * A sample must be an integer after scl_slope/inter: a float label volume of
 * integers is fine, 1.5 is refused with the voxel named.
 */
#include "io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct acc {
    int64_t label, count;
    int32_t x0, y0, z0, x1, y1, z1; /* inclusive while scanning */
} acc;

typedef struct contact_acc {
    uint32_t a, b; /* discovery indices, a < b */
    int64_t faces[3];
} contact_acc;

typedef struct splitter {
    const bvox__gray *g;
    const char *name;
    int64_t max_labels;
    bool integral;     /* raw samples are the labels (integer type, identity scale) */
    int32_t *direct;   /* 65536 entries (index + 1; 0 unseen) for 8/16-bit integral */
    int64_t direct_bias;
    int64_t *hkeys;    /* hash: label -> index + 1 in hvals (0 empty) */
    uint32_t *hvals;
    size_t hcap;
    acc *objs;
    size_t nobj, capobj;
    contact_acc *cts;  /* hash on (a, b), cap a power of two; a == b == 0 empty */
    size_t ncts, ccap;
} splitter;

/* ------------------------------------------------------------ samples */

static bool small_type(bvox_dtype t)
{
    return t == BVOX_DT_U8 || t == BVOX_DT_I8 || t == BVOX_DT_U16 || t == BVOX_DT_I16;
}

/* The real value of sample i (scaled); *exact_int set when the raw integer
 * itself is the label. Returns false for a value that is not an integer. */
static bool sample_label(const bvox__gray *g, bool integral, size_t i, int64_t *out)
{
    const uint8_t *p = (const uint8_t *)g->data;
    int64_t iv = 0;
    double dv = 0;
    bool is_int = true;
    switch (g->dtype) {
    case BVOX_DT_U8: iv = p[i]; break;
    case BVOX_DT_I8: iv = (int8_t)p[i]; break;
    case BVOX_DT_U16: {
        uint16_t v;
        memcpy(&v, p + 2 * i, 2);
        if (g->byteswap) v = __builtin_bswap16(v);
        iv = v;
        break;
    }
    case BVOX_DT_I16: {
        uint16_t v;
        memcpy(&v, p + 2 * i, 2);
        if (g->byteswap) v = __builtin_bswap16(v);
        iv = (int16_t)v;
        break;
    }
    case BVOX_DT_U32:
    case BVOX_DT_I32:
    case BVOX_DT_F32: {
        uint32_t v;
        memcpy(&v, p + 4 * i, 4);
        if (g->byteswap) v = __builtin_bswap32(v);
        if (g->dtype == BVOX_DT_U32) iv = v;
        else if (g->dtype == BVOX_DT_I32) iv = (int32_t)v;
        else {
            float f;
            memcpy(&f, &v, 4);
            dv = f;
            is_int = false;
        }
        break;
    }
    default: {
        uint64_t v;
        memcpy(&v, p + 8 * i, 8);
        if (g->byteswap) v = __builtin_bswap64(v);
        if (g->dtype == BVOX_DT_U64) {
            if (v > (uint64_t)INT64_MAX) return false;
            iv = (int64_t)v;
        } else if (g->dtype == BVOX_DT_I64) iv = (int64_t)v;
        else {
            memcpy(&dv, &v, 8);
            is_int = false;
        }
        break;
    }
    }
    if (integral) {
        *out = iv;
        return true;
    }
    if (is_int) dv = (double)iv;
    double slope = g->slope == 0 ? 1.0 : g->slope;
    double real = dv * slope + g->inter;
    /* labels are integers a double holds exactly */
    if (!isfinite(real) || real != floor(real) || fabs(real) > 9007199254740992.0) return false;
    *out = (int64_t)real;
    return true;
}

/* ------------------------------------------------------------ label map */

static uint64_t mix(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    return k;
}

static bvox_status hash_grow(splitter *s)
{
    size_t cap = s->hcap ? s->hcap * 2 : 1024;
    bvox_status st;
    int64_t *keys = bvox__alloc(cap * sizeof *keys, false, "label map", &st);
    uint32_t *vals = keys ? bvox__alloc(cap * sizeof *vals, true, "label map", &st) : NULL;
    if (!vals) {
        if (keys) bvox__free(keys, cap * sizeof *keys);
        return st;
    }
    for (size_t i = 0; i < s->hcap; i++) {
        if (!s->hvals[i]) continue;
        size_t h = mix((uint64_t)s->hkeys[i]) & (cap - 1);
        while (vals[h]) h = (h + 1) & (cap - 1);
        keys[h] = s->hkeys[i];
        vals[h] = s->hvals[i];
    }
    if (s->hcap) {
        bvox__free(s->hkeys, s->hcap * sizeof *s->hkeys);
        bvox__free(s->hvals, s->hcap * sizeof *s->hvals);
    }
    s->hkeys = keys;
    s->hvals = vals;
    s->hcap = cap;
    return BVOX_OK;
}

/* A new object for label; BVOX_ETOOBIG past max_labels. */
static bvox_status add_object(splitter *s, int64_t label, uint32_t *index)
{
    if ((int64_t)s->nobj >= s->max_labels)
        return bvox__fail(BVOX_ETOOBIG,
                          "%s: more than %lld distinct labels (the limit; is this a label "
                          "volume? --max-labels raises it)",
                          s->name, (long long)s->max_labels);
    if (s->nobj == s->capobj) {
        size_t cap = s->capobj ? s->capobj * 2 : 64;
        acc *o = bvox__mem_resize(s->objs, cap * sizeof *o);
        if (!o) return bvox__fail(BVOX_ENOMEM, "%s: out of memory for the label list", s->name);
        s->objs = o;
        s->capobj = cap;
    }
    acc *a = &s->objs[s->nobj];
    a->label = label;
    a->count = 0;
    a->x0 = a->y0 = a->z0 = INT32_MAX;
    a->x1 = a->y1 = a->z1 = -1;
    *index = (uint32_t)s->nobj++;
    return BVOX_OK;
}

/* Index + 1 of label (0 for the background); discover adds unseen labels. */
static bvox_status lookup(splitter *s, int64_t label, bool discover, uint32_t *out)
{
    *out = 0;
    if (label == 0) return BVOX_OK;
    if (s->direct) {
        int32_t *slot = &s->direct[label + s->direct_bias];
        if (!*slot) {
            uint32_t i;
            bvox_status st = discover ? add_object(s, label, &i) : BVOX_EINVAL;
            if (st) return st;
            *slot = (int32_t)i + 1;
        }
        *out = (uint32_t)*slot;
        return BVOX_OK;
    }
    if (s->hcap) {
        size_t h = mix((uint64_t)label) & (s->hcap - 1);
        while (s->hvals[h]) {
            if (s->hkeys[h] == label) {
                *out = s->hvals[h];
                return BVOX_OK;
            }
            h = (h + 1) & (s->hcap - 1);
        }
    }
    if (!discover) return bvox__fail(BVOX_EINVAL, "%s: label %lld changed", s->name,
                                     (long long)label);
    uint32_t i;
    bvox_status st = add_object(s, label, &i);
    if (st) return st;
    if ((s->nobj + 1) * 2 > s->hcap && (st = hash_grow(s))) return st;
    size_t h = mix((uint64_t)label) & (s->hcap - 1);
    while (s->hvals[h]) h = (h + 1) & (s->hcap - 1);
    s->hkeys[h] = label;
    s->hvals[h] = i + 1;
    *out = i + 1;
    return BVOX_OK;
}

/* Slice z as label indices + 1 (0 background), x fastest. */
static bvox_status map_slice(splitter *s, int32_t z, bool discover, uint32_t *idx)
{
    const bvox__gray *g = s->g;
    size_t plane = (size_t)g->dims.nx * (size_t)g->dims.ny, base = (size_t)z * plane;
    int64_t last = 0;
    uint32_t last_idx = 0; /* runs of one label are the rule: look up once per run */
    for (size_t i = 0; i < plane; i++) {
        int64_t label;
        if (!sample_label(g, s->integral, base + i, &label)) {
            size_t x = i % (size_t)g->dims.nx, y = i / (size_t)g->dims.nx;
            return bvox__fail(BVOX_EFORMAT,
                              "%s: voxel (%zu, %zu, %ld) is not an integer label (a label "
                              "volume holds integers)",
                              s->name, x, y, (long)z);
        }
        if (label != last) {
            bvox_status st = lookup(s, label, discover, &last_idx);
            if (st) return st;
            last = label;
        }
        idx[i] = label ? last_idx : 0;
    }
    return BVOX_OK;
}

/* ------------------------------------------------------------ contacts */

static bvox_status contacts_grow(splitter *s)
{
    size_t cap = s->ccap ? s->ccap * 2 : 256;
    contact_acc *c = bvox__mem_zalloc(cap, sizeof *c);
    if (!c) return bvox__fail(BVOX_ENOMEM, "%s: out of memory for label contacts", s->name);
    for (size_t i = 0; i < s->ccap; i++) {
        contact_acc *o = &s->cts[i];
        if (!o->a && !o->b) continue;
        size_t h = mix(((uint64_t)o->a << 32) | o->b) & (cap - 1);
        while (c[h].a || c[h].b) h = (h + 1) & (cap - 1);
        c[h] = *o;
    }
    free(s->cts);
    s->cts = c;
    s->ccap = cap;
    return BVOX_OK;
}

/* One face between index+1 values p != q (both non-zero) across axis. */
static bvox_status add_face(splitter *s, uint32_t p, uint32_t q, int axis)
{
    uint32_t a = p < q ? p : q, b = p < q ? q : p;
    if ((s->ncts + 1) * 2 > s->ccap) {
        bvox_status st = contacts_grow(s);
        if (st) return st;
    }
    size_t h = mix(((uint64_t)a << 32) | b) & (s->ccap - 1);
    while (s->cts[h].a || s->cts[h].b) {
        if (s->cts[h].a == a && s->cts[h].b == b) {
            s->cts[h].faces[axis]++;
            return BVOX_OK;
        }
        h = (h + 1) & (s->ccap - 1);
    }
    s->cts[h].a = a;
    s->cts[h].b = b;
    s->cts[h].faces[axis] = 1;
    s->ncts++;
    return BVOX_OK;
}

/* Counts, boxes and contacts of slice z (cur) against the previous (prev). */
static bvox_status scan_slice(splitter *s, int32_t z, const uint32_t *cur, const uint32_t *prev)
{
    int32_t nx = s->g->dims.nx, ny = s->g->dims.ny;
    for (int32_t y = 0; y < ny; y++) {
        const uint32_t *row = cur + (size_t)y * nx;
        for (int32_t x = 0; x < nx; x++) {
            uint32_t k = row[x];
            if (!k) continue;
            acc *a = &s->objs[k - 1];
            a->count++;
            if (x < a->x0) a->x0 = x;
            if (x > a->x1) a->x1 = x;
            if (y < a->y0) a->y0 = y;
            if (y > a->y1) a->y1 = y;
            if (z < a->z0) a->z0 = z;
            if (z > a->z1) a->z1 = z;
            bvox_status st = BVOX_OK;
            if (x + 1 < nx && row[x + 1] && row[x + 1] != k) st = add_face(s, k, row[x + 1], 0);
            if (!st && y + 1 < ny && row[x + nx] && row[x + nx] != k)
                st = add_face(s, k, row[x + nx], 1);
            if (!st && prev) {
                uint32_t q = prev[(size_t)y * nx + x];
                if (q && q != k) st = add_face(s, k, q, 2);
            }
            if (st) return st;
        }
    }
    return BVOX_OK;
}

/* ------------------------------------------------------------ the split */

static int by_label(const void *pa, const void *pb)
{
    int64_t a = ((const bvox_label_object *)pa)->label, b = ((const bvox_label_object *)pb)->label;
    return (a > b) - (a < b);
}

static int by_pair(const void *pa, const void *pb)
{
    const bvox_label_contact *a = pa, *b = pb;
    if (a->a != b->a) return (a->a > b->a) - (a->a < b->a);
    return (a->b > b->b) - (a->b < b->b);
}

void bvox_labelset_destroy(bvox_labelset *set)
{
    if (!set) return;
    for (int64_t i = 0; i < set->n; i++) bvox_volume_destroy(set->objects[i].volume);
    free(set->objects);
    free(set->contacts);
    free(set);
}

/* Objects (sorted by label) and their empty crops, from pass 1. remap[k] is
 * the sorted position of discovery index k. */
static bvox_status make_set(splitter *s, uint32_t *remap, bvox_labelset **out)
{
    const bvox__gray *g = s->g;
    bvox_labelset *set = bvox__mem_zalloc(1, sizeof *set);
    if (!set) return bvox__fail(BVOX_ENOMEM, "%s: out of memory", s->name);
    set->dims = g->dims;
    set->geometry = g->geom;
    set->dtype = g->dtype;
    set->objects = bvox__mem_zalloc(s->nobj ? s->nobj : 1, sizeof *set->objects);
    set->contacts = bvox__mem_zalloc(s->ncts ? s->ncts : 1, sizeof *set->contacts);
    if (!set->objects || !set->contacts) {
        bvox_labelset_destroy(set);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", s->name);
    }
    int64_t total = (int64_t)g->dims.nx * g->dims.ny * g->dims.nz, fg = 0;
    for (size_t k = 0; k < s->nobj; k++) {
        bvox_label_object *o = &set->objects[k];
        const acc *a = &s->objs[k];
        o->label = a->label;
        o->count = a->count;
        o->bbox = (bvox_box){a->x0, a->y0, a->z0, a->x1 + 1, a->y1 + 1, a->z1 + 1};
        /* index k for now: remembered in crop.x0's place until sorted */
        o->crop.x0 = (int32_t)k;
        fg += a->count;
    }
    set->n = (int64_t)s->nobj;
    set->background = total - fg;
    qsort(set->objects, s->nobj, sizeof *set->objects, by_label);
    for (size_t i = 0; i < s->nobj; i++) remap[set->objects[i].crop.x0] = (uint32_t)i;
    for (size_t i = 0; i < s->nobj; i++) {
        bvox_label_object *o = &set->objects[i];
        bvox_box b = o->bbox;
        /* grown by one voxel: a crop boundary never cuts the object's surface */
        o->crop = (bvox_box){b.x0 > 0 ? b.x0 - 1 : 0,
                             b.y0 > 0 ? b.y0 - 1 : 0,
                             b.z0 > 0 ? b.z0 - 1 : 0,
                             b.x1 < g->dims.nx ? b.x1 + 1 : b.x1,
                             b.y1 < g->dims.ny ? b.y1 + 1 : b.y1,
                             b.z1 < g->dims.nz ? b.z1 + 1 : b.z1};
        bvox_dims d = {o->crop.x1 - o->crop.x0, o->crop.y1 - o->crop.y0, o->crop.z1 - o->crop.z0};
        bvox_status st = bvox_volume_create(d, &o->volume);
        if (st) {
            bvox__error_prefix(s->name);
            bvox_labelset_destroy(set);
            return st;
        }
        bvox_geometry geom = g->geom;
        bvox__geometry_shift(&geom, o->crop.x0, o->crop.y0, o->crop.z0);
        o->volume->geom = geom;
    }
    size_t m = 0;
    for (size_t i = 0; i < s->ccap; i++) {
        const contact_acc *c = &s->cts[i];
        if (!c->a && !c->b) continue;
        bvox_label_contact *t = &set->contacts[m++];
        int64_t a = remap[c->a - 1], b = remap[c->b - 1];
        t->a = a < b ? a : b;
        t->b = a < b ? b : a;
        memcpy(t->faces, c->faces, sizeof t->faces);
        const double *sp = g->geom.spacing;
        t->area = (double)c->faces[0] * sp[1] * sp[2] + (double)c->faces[1] * sp[0] * sp[2] +
                  (double)c->faces[2] * sp[0] * sp[1];
    }
    set->ncontacts = (int64_t)m;
    qsort(set->contacts, m, sizeof *set->contacts, by_pair);
    *out = set;
    return BVOX_OK;
}

/* Pass 2 for slice z: each voxel sets its bit in its label's crop. */
static void fill_slice(bvox_labelset *set, const uint32_t *remap, int32_t z, const uint32_t *idx)
{
    int32_t nx = set->dims.nx, ny = set->dims.ny;
    for (int32_t y = 0; y < ny; y++)
        for (int32_t x = 0; x < nx; x++) {
            uint32_t k = idx[(size_t)y * nx + x];
            if (!k) continue;
            bvox_label_object *o = &set->objects[remap[k - 1]];
            bvox_volume *v = o->volume;
            int32_t cz = z - o->crop.z0;
            v->words[((size_t)(y - o->crop.y0) * v->nx + (size_t)(x - o->crop.x0)) * v->wpc +
                     (size_t)(cz >> 6)] |= 1ull << (cz & 63);
        }
}

static void splitter_release(splitter *s)
{
    if (s->direct) bvox__free(s->direct, 65536 * sizeof *s->direct);
    if (s->hcap) {
        bvox__free(s->hkeys, s->hcap * sizeof *s->hkeys);
        bvox__free(s->hvals, s->hcap * sizeof *s->hvals);
    }
    free(s->objs);
    free(s->cts);
}

static bvox_status split(const bvox__gray *g, const char *name, int64_t max_labels,
                         bvox_labelset **out)
{
    splitter s = {0};
    s.g = g;
    s.name = name;
    s.max_labels = max_labels > 0 ? max_labels : BVOX_LABELS_MAX_DEFAULT;
    bool identity = (g->slope == 0 || g->slope == 1) && g->inter == 0;
    s.integral = identity && g->dtype != BVOX_DT_F32 && g->dtype != BVOX_DT_F64;
    bvox_status st = BVOX_OK;
    if (s.integral && small_type(g->dtype)) {
        s.direct = bvox__alloc(65536 * sizeof *s.direct, true, "label map", &st);
        if (!s.direct) return st;
        s.direct_bias = (g->dtype == BVOX_DT_I8) ? 128 : (g->dtype == BVOX_DT_I16) ? 32768 : 0;
    }
    size_t plane = (size_t)g->dims.nx * (size_t)g->dims.ny;
    uint32_t *buf = bvox__alloc(2 * plane * sizeof *buf, false, "label slices", &st);
    uint32_t *remap = NULL;
    bvox_labelset *set = NULL;
    if (!buf) goto done;
    uint32_t *cur = buf, *prev = buf + plane;
    for (int32_t z = 0; z < g->dims.nz && !st; z++) {
        st = map_slice(&s, z, true, cur);
        if (!st) st = scan_slice(&s, z, cur, z ? prev : NULL);
        uint32_t *t = cur;
        cur = prev;
        prev = t;
    }
    if (st) goto done;
    remap = bvox__mem_alloc((s.nobj ? s.nobj : 1) * sizeof *remap);
    if (!remap) {
        st = bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
        goto done;
    }
    st = make_set(&s, remap, &set);
    for (int32_t z = 0; z < g->dims.nz && !st; z++) {
        st = map_slice(&s, z, false, buf);
        if (!st) fill_slice(set, remap, z, buf);
    }
done:
    if (buf) bvox__free(buf, 2 * plane * sizeof *buf);
    free(remap);
    splitter_release(&s);
    if (st) {
        bvox_labelset_destroy(set);
        return st;
    }
    *out = set;
    return BVOX_OK;
}

bvox_status bvox_labels_read_memory(const void *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, int64_t max_labels,
                                    bvox_labelset **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_labels_read_memory: NULL argument");
    *out = NULL;
    if (!data) return bvox__fail(BVOX_EINVAL, "bvox_labels_read_memory: NULL argument");
    if (!name) name = "input";
    bvox__gray g;
    bvox_status st = bvox__read_gray_memory(data, size, name, opts, &g);
    if (st) return st;
    st = split(&g, name, max_labels, out);
    bvox__gray_release(&g);
    return st;
}

bvox_status bvox_labels_read(const char *path, const bvox_read_opts *opts, int64_t max_labels,
                             bvox_labelset **out)
{
    bvox__clear_error();
    if (!out) return bvox__fail(BVOX_EINVAL, "bvox_labels_read: NULL argument");
    *out = NULL;
    if (!path) return bvox__fail(BVOX_EINVAL, "bvox_labels_read: NULL argument");
    bvox__bytes file;
    bvox__gray g;
    bvox_status st = bvox__read_gray(path, opts, &file, &g);
    if (st) return st;
    st = split(&g, path, max_labels, out);
    bvox__gray_release(&g);
    if (file.data) bvox__bytes_release(&file);
    return st;
}

int64_t bvox_labelset_find(const bvox_labelset *set, int64_t label)
{
    if (!set) return -1;
    int64_t lo = 0, hi = set->n;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (set->objects[mid].label < label) lo = mid + 1;
        else hi = mid;
    }
    return lo < set->n && set->objects[lo].label == label ? lo : -1;
}

bvox_status bvox_labelset_set_geometry(bvox_labelset *set, const bvox_geometry *geom)
{
    bvox__clear_error();
    if (!set || !geom) return bvox__fail(BVOX_EINVAL, "bvox_labelset_set_geometry: NULL argument");
    for (int64_t i = 0; i < set->n; i++) {
        bvox_label_object *o = &set->objects[i];
        bvox_geometry g = *geom;
        bvox__geometry_shift(&g, o->crop.x0, o->crop.y0, o->crop.z0);
        bvox_status st = bvox_volume_set_geometry(o->volume, &g);
        if (st) return st; /* checked on the first: every crop gets the same spacing */
    }
    set->geometry = *geom;
    return BVOX_OK;
}
