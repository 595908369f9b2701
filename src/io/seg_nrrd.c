/*
 * seg_nrrd.c — 3D Slicer segmentations (`.seg.nrrd`): the segments' names,
 * colours, label values and layers from the NRRD header's key/value pairs
 *
 *   Segment<N>_Name:=Liver     Segment<N>_Color:=0.86 0.55 0.47 (0..1)
 *   Segment<N>_LabelValue:=3   Segment<N>_Layer:=0
 *
 * and the samples of a layered one turned into one label volume.
 *  - Segments as labels: a 3D file (one layer) holds each segment's
 *    LabelValue in its voxels: they are the labels as they stand.
 *  - Segments as bit layers: a 4D file whose first axis ("kinds: list ...")
 *    is the layer, where Slicer puts segments that overlap, or (Slicer
 *    before 4.11, no LabelValue) one 0/1 layer per segment. Each segment
 *    becomes label N + 1 (N its number in the header); a voxel in several
 *    segments keeps the last one's label, and how many did so is warned
 *    about (a label volume holds one label per voxel).
 * The label table (names, colours) follows the same numbering, so that
 * `bvox labels x.seg.nrrd` names its rows without --lut.
 */
#include "io.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SEGMENTS 65535

void bvox__segs_release(bvox__segs *s)
{
    free(s->seg);
    memset(s, 0, sizeof *s);
}

static bvox__segment *segment_at(bvox__segs *s, long idx)
{
    if (idx < 0 || idx >= MAX_SEGMENTS) return NULL;
    if (idx >= s->cap) {
        long cap = s->cap ? s->cap : 8;
        while (cap <= idx) cap *= 2;
        bvox__segment *ns = bvox__mem_resize(s->seg, (size_t)cap * sizeof *ns);
        if (!ns) return NULL;
        memset(ns + s->cap, 0, (size_t)(cap - s->cap) * sizeof *ns);
        s->seg = ns;
        s->cap = cap;
    }
    if (idx >= s->n) s->n = idx + 1;
    s->seg[idx].present = true;
    return &s->seg[idx];
}

bvox_status bvox__segs_parse(const uint8_t *data, size_t size, const char *name, bvox__segs *s)
{
    memset(s, 0, sizeof *s);
    size_t pos = 0;
    char line[1024];
    while (pos < size) {
        size_t end = pos;
        while (end < size && data[end] != '\n') end++;
        size_t n = end - pos;
        pos = end < size ? end + 1 : end;
        if (n == 0 || (n == 1 && data[end - 1] == '\r')) break; /* the end of the header */
        if (n >= sizeof line || n < 9 || memcmp(data + end - n, "Segment", 7)) continue;
        memcpy(line, data + end - n, n);
        line[n] = '\0';
        if (line[n - 1] == '\r') line[n - 1] = '\0';
        char *sep = strstr(line, ":=");
        if (!sep || !isdigit((unsigned char)line[7])) continue;
        *sep = '\0';
        char *key_end;
        long idx = strtol(line + 7, &key_end, 10);
        if (*key_end != '_') continue;
        const char *key = key_end + 1, *v = sep + 2;
        bool known = !strcmp(key, "Name") || !strcmp(key, "Color") ||
                     !strcmp(key, "LabelValue") || !strcmp(key, "Layer");
        if (!known) continue;
        bvox__segment *g = segment_at(s, idx);
        if (!g) {
            bvox__segs_release(s);
            return bvox__fail(idx < 0 || idx >= MAX_SEGMENTS ? BVOX_EFORMAT : BVOX_ENOMEM,
                              "%s: segment number %ld (at most %d segments)", name, idx,
                              MAX_SEGMENTS);
        }
        if (!strcmp(key, "Name")) {
            snprintf(g->name, sizeof g->name, "%s", v);
        } else if (!strcmp(key, "Color")) {
            double c[3];
            if (sscanf(v, "%lf %lf %lf", &c[0], &c[1], &c[2]) == 3) {
                for (int k = 0; k < 3; k++) {
                    double x = c[k] < 0 ? 0 : c[k] > 1 ? 1 : c[k];
                    g->rgb[k] = (unsigned char)(x * 255 + 0.5);
                }
                g->has_color = true;
            }
        } else if (!strcmp(key, "LabelValue")) {
            long long lv = atoll(v);
            if (lv > 0) {
                g->label_value = lv;
                g->has_value = true;
            }
        } else {
            g->layer = atol(v);
            g->has_layer = true;
        }
    }
    return BVOX_OK;
}

int64_t bvox__segs_label(const bvox__segs *s, long i, bool layered)
{
    if (layered) return (int64_t)i + 1;
    return s->seg[i].has_value ? s->seg[i].label_value : 1;
}

bvox_status bvox__segs_table(const uint8_t *data, size_t size, const char *name, bool layered,
                             bvox_label_table **out)
{
    *out = NULL;
    bvox__segs s;
    bvox_status st = bvox__segs_parse(data, size, name, &s);
    if (st) return st;
    long count = 0;
    for (long i = 0; i < s.n; i++) count += s.seg[i].present;
    if (!count) {
        bvox__segs_release(&s);
        return bvox__fail(BVOX_EFORMAT, "%s: a NRRD file without segments (Segment0_Name:=...)",
                          name);
    }
    bvox_label_table *t = bvox__mem_zalloc(1, sizeof *t);
    if (t) t->entries = bvox__mem_zalloc((size_t)count, sizeof *t->entries);
    if (!t || !t->entries) {
        if (t) free(t);
        bvox__segs_release(&s);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    for (long i = 0; i < s.n; i++) {
        if (!s.seg[i].present) continue;
        bvox_label_entry *e = &t->entries[t->n++];
        e->label = bvox__segs_label(&s, i, layered);
        snprintf(e->name, sizeof e->name, "%s", s.seg[i].name);
        memcpy(e->rgba, s.seg[i].rgb, 3);
        e->rgba[3] = 255;
        e->has_color = s.seg[i].has_color;
    }
    bvox__segs_release(&s);
    *out = t; /* not sorted: bvox_label_table_find searches linearly */
    return BVOX_OK;
}

/* Raw integer sample i of a layer buffer (8 or 16 bits, signed or not). */
static int64_t sample(const bvox__gray *g, size_t i)
{
    switch (g->dtype) {
    case BVOX_DT_U8: return ((const uint8_t *)g->data)[i];
    case BVOX_DT_I8: return ((const int8_t *)g->data)[i];
    case BVOX_DT_U16:
    case BVOX_DT_I16: {
        uint16_t u;
        memcpy(&u, (const uint8_t *)g->data + 2 * i, 2);
        if (g->byteswap) u = (uint16_t)(u << 8 | u >> 8);
        return g->dtype == BVOX_DT_U16 ? (int64_t)u : (int64_t)(int16_t)u;
    }
    default: return 0;
    }
}

bvox_status bvox__segs_flatten(bvox__gray *g, int64_t layers, const uint8_t *header,
                               size_t header_size, const char *name)
{
    if (g->dtype != BVOX_DT_U8 && g->dtype != BVOX_DT_I8 && g->dtype != BVOX_DT_U16 &&
        g->dtype != BVOX_DT_I16)
        return bvox__fail(BVOX_EUNSUPPORTED,
                          "%s: a layered segmentation of %s samples (bvox reads 8- and 16-bit "
                          "layers)",
                          name, bvox_dtype_name(g->dtype));
    if (layers < 1 || layers > 256)
        return bvox__fail(BVOX_EUNSUPPORTED, "%s: %lld segmentation layers (at most 256)", name,
                          (long long)layers);
    bvox__segs s;
    bvox_status st = bvox__segs_parse(header, header_size, name, &s);
    if (st) return st;
    bool values = false, layer_keys = false;
    for (long i = 0; i < s.n; i++) {
        values |= s.seg[i].present && s.seg[i].has_value;
        layer_keys |= s.seg[i].present && s.seg[i].has_layer;
    }
    if (s.n > 65535) {
        bvox__segs_release(&s);
        return bvox__fail(BVOX_ETOOBIG, "%s: more than 65535 segments", name);
    }
    /* which label (layer, value) gives: a table per layer over the 8/16-bit values */
    size_t span = (g->dtype == BVOX_DT_U8 || g->dtype == BVOX_DT_I8) ? 256 : 65536;
    size_t tbytes = (size_t)layers * span * sizeof(uint16_t);
    uint16_t *map = bvox__alloc(tbytes, true, "segment table", &st);
    if (!map) {
        bvox__segs_release(&s);
        bvox__error_prefix(name);
        return st;
    }
    for (long i = 0; i < s.n; i++) {
        const bvox__segment *sg = &s.seg[i];
        /* no Layer keys (Slicer before 4.11): segment i is layer i */
        long layer = layer_keys ? sg->layer : i;
        if (!sg->present || layer < 0 || layer >= layers) continue;
        uint16_t label = (uint16_t)(i + 1);
        if (values) {
            if (sg->has_value && sg->label_value < (int64_t)span)
                map[(size_t)layer * span + (size_t)sg->label_value] = label;
        } else { /* one 0/1 layer per segment: every non-zero value */
            for (size_t v = 1; v < span; v++) map[(size_t)layer * span + v] = label;
        }
    }
    bool described = s.n > 0;
    bvox__segs_release(&s);
    size_t n = (size_t)g->dims.nx * (size_t)g->dims.ny * (size_t)g->dims.nz, out_bytes;
    if (!bvox__mul_size(n, 2, &out_bytes)) {
        bvox__free(map, tbytes);
        return bvox__fail(BVOX_ETOOBIG, "%s: too many voxels", name);
    }
    uint16_t *lab = bvox__alloc(out_bytes, false, "label volume", &st);
    if (!lab) {
        bvox__free(map, tbytes);
        bvox__error_prefix(name);
        return st;
    }
    int64_t overlaps = 0, unknown = 0;
    for (size_t i = 0; i < n; i++) {
        uint16_t l = 0;
        for (int64_t k = 0; k < layers; k++) {
            int64_t v = sample(g, i * (size_t)layers + (size_t)k);
            if (!v) continue;
            /* no segment keys: each layer is a segment of its own */
            uint16_t m = !described ? (uint16_t)(k + 1)
                         : v > 0    ? map[(size_t)k * span + (size_t)v]
                                    : 0;
            if (!m) {
                unknown++;
                continue;
            }
            overlaps += l != 0 && l != m;
            l = m;
        }
        lab[i] = l;
    }
    bvox__free(map, tbytes);
    if (overlaps)
        bvox__warn("%s: %lld voxels are in several segments (layers); each keeps the last "
                   "one's label",
                   name, (long long)overlaps);
    if (unknown)
        bvox__warn("%s: %lld voxels hold values no segment describes; they are left 0", name,
                   (long long)unknown);
    if (g->owned) bvox__free(g->owned, g->owned_bytes);
    g->owned = lab;
    g->owned_bytes = out_bytes;
    g->data = lab;
    g->dtype = BVOX_DT_U16;
    g->byteswap = false;
    g->slope = 1.0;
    g->inter = 0.0;
    return BVOX_OK;
}
