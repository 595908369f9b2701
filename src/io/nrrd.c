/*
 * nrrd.c — NRRD volumes (.nrrd with attached data, .nhdr with a detached
 * data file), read: 3D (or 2D, one slice) scalar samples, raw or gzip
 * encoding, either byte order, byte skip / line skip, and the geometry of
 * "space directions" and "space origin" (or "spacings"), in the RAS frame
 * bvox keeps (NIfTI's): a left-posterior-superior file, 3D Slicer's usual
 * one, has its x and y negated.
 *
 * Written by hand rather than through Debian's libteem (teem's nrrd): teem
 * reads from a FILE or a path only (a fuzz target and bvox_read_memory need
 * a memory entry point), reports errors through its global "biff" stack (not
 * thread-safe, and bvox keeps one thread-local message), allocates the
 * samples with plain malloc outside the memory budget, and would add a
 * run-time dependency for a header of a dozen "key: value" lines.
 *
 * Detached data ("data file: NAME") is looked up beside the header when the
 * reader is given the header's path (bvox_read passes it as the name);
 * "LIST" and multi-file forms are refused, as are ascii/hex/bzip2
 * encodings and non-scalar (vector) volumes. A 4D file whose first axis is
 * a list is a 3D Slicer segmentation with layers: seg_nrrd.c turns its
 * samples into one label per voxel. The writer is nrrd_write.c;
 * the same reasons keep it off teem (whose writer also goes through biff).
 */
#include "io.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct nrrd_header {
    int dimension;
    int64_t sizes[4];
    int64_t layers; /* dimension 4: the first ("list") axis, a segmentation's
                       layers (seg_nrrd.c); 0 otherwise */
    bvox_dtype dtype;
    bool have_type, big_endian, gzip, lps, have_dirs, have_origin, have_spacings;
    double dirs[3][3]; /* space direction of axis i: dirs[i] */
    double origin[3], spacings[3];
    char unit[16];
    char data_file[512];
    int64_t line_skip, byte_skip; /* byte_skip -1: the data are the file's last bytes */
    size_t header_end;            /* offset of the attached data */
} nrrd_header;

static int nrrd_sniff(const uint8_t *d, size_t n) { return n >= 8 && !memcmp(d, "NRRD000", 7); }

static char *trim(char *s)
{
    while (*s && isspace((unsigned char)*s)) s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = '\0';
    return s;
}

static int parse_type(const char *v, bvox_dtype *t)
{
    static const struct {
        const char *name;
        bvox_dtype t;
    } types[] = {
        {"signed char", BVOX_DT_I8},       {"int8", BVOX_DT_I8},
        {"int8_t", BVOX_DT_I8},            {"uchar", BVOX_DT_U8},
        {"unsigned char", BVOX_DT_U8},     {"uint8", BVOX_DT_U8},
        {"uint8_t", BVOX_DT_U8},           {"short", BVOX_DT_I16},
        {"short int", BVOX_DT_I16},        {"signed short", BVOX_DT_I16},
        {"signed short int", BVOX_DT_I16}, {"int16", BVOX_DT_I16},
        {"int16_t", BVOX_DT_I16},          {"ushort", BVOX_DT_U16},
        {"unsigned short", BVOX_DT_U16},   {"unsigned short int", BVOX_DT_U16},
        {"uint16", BVOX_DT_U16},           {"uint16_t", BVOX_DT_U16},
        {"int", BVOX_DT_I32},              {"signed int", BVOX_DT_I32},
        {"int32", BVOX_DT_I32},            {"int32_t", BVOX_DT_I32},
        {"uint", BVOX_DT_U32},             {"unsigned int", BVOX_DT_U32},
        {"uint32", BVOX_DT_U32},           {"uint32_t", BVOX_DT_U32},
        {"longlong", BVOX_DT_I64},         {"long long", BVOX_DT_I64},
        {"long long int", BVOX_DT_I64},    {"signed long long", BVOX_DT_I64},
        {"signed long long int", BVOX_DT_I64}, {"int64", BVOX_DT_I64},
        {"int64_t", BVOX_DT_I64},          {"ulonglong", BVOX_DT_U64},
        {"unsigned long long", BVOX_DT_U64}, {"unsigned long long int", BVOX_DT_U64},
        {"uint64", BVOX_DT_U64},           {"uint64_t", BVOX_DT_U64},
        {"float", BVOX_DT_F32},            {"double", BVOX_DT_F64},
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcasecmp(v, types[i].name)) {
            *t = types[i].t;
            return 1;
        }
    return 0;
}

/* "(a,b,c)" vectors, or "none", n of them. */
static int parse_vectors(const char *v, int n, double out[][3], bool *none)
{
    const char *p = v;
    for (int i = 0; i < n; i++) {
        while (*p && isspace((unsigned char)*p)) p++;
        if (!strncasecmp(p, "none", 4)) {
            none[i] = true;
            p += 4;
            continue;
        }
        none[i] = false;
        if (*p != '(') return 0;
        p++;
        for (int k = 0; k < 3; k++) {
            char *end;
            out[i][k] = strtod(p, &end);
            if (end == p || !isfinite(out[i][k])) return 0;
            p = end;
            while (*p && isspace((unsigned char)*p)) p++;
            if (*p != (k < 2 ? ',' : ')')) return 0;
            p++;
        }
    }
    return 1;
}

static bvox_status parse_header(const uint8_t *data, size_t size, const char *name,
                                nrrd_header *h)
{
    memset(h, 0, sizeof *h);
    h->dimension = 0;
    h->byte_skip = 0;
    if (!nrrd_sniff(data, size)) return bvox__fail(BVOX_EFORMAT, "%s: not a NRRD file", name);
    size_t pos = 0, lineno = 0;
    bool have_sizes = false, have_encoding = false, end_blank = false;
    char line[1024];
    while (pos < size) {
        size_t end = pos;
        while (end < size && data[end] != '\n') end++;
        size_t n = end - pos;
        if (n >= sizeof line)
            return bvox__fail(BVOX_EFORMAT, "%s: header line %zu is too long", name, lineno + 1);
        memcpy(line, data + pos, n);
        line[n] = '\0';
        pos = end < size ? end + 1 : end;
        lineno++;
        if (n && line[n - 1] == '\r') line[--n] = '\0';
        if (lineno == 1) continue; /* the magic */
        if (n == 0) {
            end_blank = true;
            break;
        }
        if (line[0] == '#') continue;
        if (strstr(line, ":=")) continue; /* key/value pairs: not needed */
        char *colon = strstr(line, ": ");
        if (!colon)
            return bvox__fail(BVOX_EFORMAT, "%s: header line %zu is not 'field: value'", name,
                              lineno);
        *colon = '\0';
        char *field = trim(line), *v = trim(colon + 2);
        if (!strcasecmp(field, "type")) {
            if (!parse_type(v, &h->dtype))
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: NRRD type '%s' is not supported",
                                  name, v);
            h->have_type = true;
        } else if (!strcasecmp(field, "dimension")) {
            h->dimension = atoi(v);
            if (h->dimension < 2 || h->dimension > 4)
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: NRRD dimension %s (bvox reads 2D and 3D scalar volumes, "
                                  "and 4D segmentation layers)",
                                  name, v);
        } else if (!strcasecmp(field, "sizes")) {
            if (!h->dimension)
                return bvox__fail(BVOX_EFORMAT, "%s: 'sizes' before 'dimension'", name);
            char *p = v;
            int64_t all[4] = {1, 1, 1, 1};
            for (int i = 0; i < h->dimension; i++) {
                char *e;
                long long s = strtoll(p, &e, 10);
                if (e == p || s < 1 || s > BVOX_MAX_DIM)
                    return bvox__fail(BVOX_EFORMAT,
                                      "%s: NRRD sizes '%s' (each 1..%d)", name, v, BVOX_MAX_DIM);
                all[i] = s;
                p = e;
            }
            if (*trim(p)) return bvox__fail(BVOX_EFORMAT, "%s: NRRD sizes '%s'", name, v);
            int lead = h->dimension == 4; /* the layer axis comes first */
            h->layers = lead ? all[0] : 0;
            for (int i = 0; i < 3; i++) h->sizes[i] = all[i + lead];
            have_sizes = true;
        } else if (!strcasecmp(field, "endian")) {
            h->big_endian = !strcasecmp(v, "big");
        } else if (!strcasecmp(field, "encoding")) {
            if (!strcasecmp(v, "raw")) h->gzip = false;
            else if (!strcasecmp(v, "gzip") || !strcasecmp(v, "gz")) h->gzip = true;
            else
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: NRRD encoding '%s' (bvox reads raw and gzip)", name, v);
            have_encoding = true;
        } else if (!strcasecmp(field, "space")) {
            if (!strcasecmp(v, "left-posterior-superior") || !strcasecmp(v, "LPS")) h->lps = true;
        } else if (!strcasecmp(field, "space dimension")) {
            if (atoi(v) != 3)
                return bvox__fail(BVOX_EUNSUPPORTED, "%s: NRRD space dimension %s", name, v);
        } else if (!strcasecmp(field, "space directions")) {
            if (!h->dimension)
                return bvox__fail(BVOX_EFORMAT, "%s: 'space directions' before 'dimension'", name);
            bool none[4];
            double dirs[4][3];
            int lead = h->dimension == 4; /* "none" for the layer axis */
            if (!parse_vectors(v, h->dimension, dirs, none) || (lead && !none[0]) ||
                none[lead] || none[lead + 1] || (h->dimension >= 3 && none[lead + 2]))
                return bvox__fail(BVOX_EFORMAT, "%s: NRRD space directions '%s'", name, v);
            memcpy(h->dirs, dirs[lead], sizeof h->dirs);
            h->have_dirs = true;
        } else if (!strcasecmp(field, "space origin")) {
            bool none;
            double o[1][3];
            if (!parse_vectors(v, 1, o, &none) || none)
                return bvox__fail(BVOX_EFORMAT, "%s: NRRD space origin '%s'", name, v);
            memcpy(h->origin, o[0], sizeof h->origin);
            h->have_origin = true;
        } else if (!strcasecmp(field, "spacings")) {
            char *p = v;
            for (int i = 0, k = 0; i < h->dimension && k < 3; i++) {
                char *e;
                double x = strtod(p, &e); /* "nan" for the layer axis of a 4D file */
                if (e == p) break;
                p = e;
                if (h->dimension == 4 && i == 0) continue;
                h->spacings[k++] = x;
            }
            h->have_spacings = true;
        } else if (!strcasecmp(field, "space units")) {
            char *q1 = strchr(v, '"'), *q2 = q1 ? strchr(q1 + 1, '"') : NULL;
            if (q1 && q2 && (size_t)(q2 - q1 - 1) < sizeof h->unit) {
                memcpy(h->unit, q1 + 1, (size_t)(q2 - q1 - 1));
                h->unit[q2 - q1 - 1] = '\0';
            }
        } else if (!strcasecmp(field, "data file") || !strcasecmp(field, "datafile")) {
            if (!strncasecmp(v, "LIST", 4) || strchr(v, '%') || strlen(v) >= sizeof h->data_file)
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: NRRD data in several files ('%s') is not supported", name,
                                  v);
            strcpy(h->data_file, v);
        } else if (!strcasecmp(field, "line skip") || !strcasecmp(field, "lineskip")) {
            h->line_skip = atoll(v);
            if (h->line_skip < 0 || h->line_skip > 1000000)
                return bvox__fail(BVOX_EFORMAT, "%s: NRRD line skip %s", name, v);
        } else if (!strcasecmp(field, "byte skip") || !strcasecmp(field, "byteskip")) {
            h->byte_skip = atoll(v);
            if (h->byte_skip < -1 || h->byte_skip > (int64_t)1 << 40)
                return bvox__fail(BVOX_EFORMAT, "%s: NRRD byte skip %s", name, v);
        } else if (!strcasecmp(field, "kinds")) {
            for (char *c = v; *c; c++) *c = (char)tolower((unsigned char)*c);
            if (h->dimension == 4) { /* the first axis is the layers: "list" */
                if (strncmp(v, "list", 4) && strncmp(v, "vector", 6) && strncmp(v, "???", 3) &&
                    strncmp(v, "none", 4))
                    return bvox__fail(BVOX_EUNSUPPORTED,
                                      "%s: NRRD kinds '%s': a 4D file is read as segmentation "
                                      "layers (its first axis a list)",
                                      name, v);
                v += strcspn(v, " \t");
            }
            if (strstr(v, "vector") || strstr(v, "rgb") || strstr(v, "list"))
                return bvox__fail(BVOX_EUNSUPPORTED,
                                  "%s: NRRD kinds '%s': bvox reads scalar volumes", name, v);
        }
        /* other fields (centerings, thicknesses, measurement frame, ...) do not
           change the voxels */
    }
    if (!h->have_type || !h->dimension || !have_sizes || !have_encoding)
        return bvox__fail(BVOX_EFORMAT, "%s: NRRD header lacks %s", name,
                          !h->have_type ? "'type'" : !h->dimension ? "'dimension'"
                          : !have_sizes ? "'sizes'" : "'encoding'");
    if (!h->data_file[0] && !end_blank)
        return bvox__fail(BVOX_EFORMAT, "%s: truncated NRRD header (no blank line before the data)",
                          name);
    if (h->dimension == 2) h->sizes[2] = 1;
    h->header_end = pos;
    return BVOX_OK;
}

static void set_geometry(const nrrd_header *h, bvox_geometry *g)
{
    *g = bvox_geometry_default();
    int naxes = h->dimension < 3 ? h->dimension : 3;
    if (h->have_dirs) {
        for (int i = 0; i < 3; i++) {
            double v[3] = {0, 0, 0};
            if (i < naxes) memcpy(v, h->dirs[i], sizeof v);
            double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if (!(n > 0) || !isfinite(n)) continue; /* keep unit spacing, identity column */
            g->spacing[i] = n;
            for (int r = 0; r < 3; r++) g->direction[r * 3 + i] = v[r] / n;
        }
        /* a degenerate (non-invertible) set of directions falls back to identity */
        const double *d = g->direction;
        double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) +
                     d[2] * (d[3] * d[7] - d[4] * d[6]);
        if (!(fabs(det) > 1e-6)) {
            bvox_geometry def = bvox_geometry_default();
            memcpy(g->direction, def.direction, sizeof def.direction);
        }
    } else if (h->have_spacings) {
        for (int i = 0; i < naxes && i < 3; i++)
            if (h->spacings[i] > 0 && isfinite(h->spacings[i])) g->spacing[i] = h->spacings[i];
    }
    if (h->have_origin) memcpy(g->origin, h->origin, sizeof g->origin);
    if (h->lps) bvox__geometry_flip_lps(g);
    if (strlen(h->unit) < sizeof g->unit) strcpy(g->unit, h->unit);
}

/* Skip `lines` lines of data. */
static size_t skip_lines(const uint8_t *d, size_t size, size_t pos, int64_t lines)
{
    for (int64_t i = 0; i < lines && pos < size; i++) {
        while (pos < size && d[pos] != '\n') pos++;
        if (pos < size) pos++;
    }
    return pos;
}

static bvox_status nrrd_gray_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox__gray *g)
{
    (void)opts;
    bvox__gray_init(g);
    if (!name) name = "input";
    nrrd_header h;
    bvox_status st = parse_header(data, size, name, &h);
    if (st) return st;
    bvox_dims d = {(int32_t)h.sizes[0], (int32_t)h.sizes[1], (int32_t)h.sizes[2]};
    size_t words_bytes, n, need, elem = bvox_dtype_size(h.dtype);
    st = bvox__check_dims(d, name, &words_bytes);
    if (st) return st;
    if (!bvox__mul_size((size_t)d.nx * (size_t)d.ny, (size_t)d.nz, &n) ||
        !bvox__mul_size(n, h.layers ? (size_t)h.layers : 1, &n) || !bvox__mul_size(n, elem, &need))
        return bvox__fail(BVOX_ETOOBIG, "%s: NRRD sizes overflow", name);

    bvox__bytes detached = {0};
    const uint8_t *src = data + h.header_end;
    size_t avail = size - h.header_end;
    if (h.data_file[0]) {
        st = bvox__read_beside(name, h.data_file, &detached);
        if (st) return st;
        src = detached.data;
        avail = detached.size;
    }
    size_t start = skip_lines(src, avail, 0, h.line_skip);
    bvox__bytes unz = {0};
    if (h.gzip) {
        if (h.byte_skip < 0 || (uint64_t)h.byte_skip > avail - start) {
            st = bvox__fail(BVOX_EFORMAT, "%s: NRRD byte skip beyond the data", name);
            goto fail;
        }
        start += (size_t)h.byte_skip;
        st = bvox__gunzip(src + start, avail - start, name, need + 64, &unz);
        if (st) goto fail;
        if (unz.size < need) {
            st = bvox__fail(BVOX_EFORMAT,
                            "%s: truncated: NRRD sizes need %zu bytes of samples, the gzip "
                            "data hold %zu",
                            name, need, unz.size);
            goto fail;
        }
        g->data = unz.data;
        g->owned = unz.data;
        g->owned_bytes = unz.alloc_bytes;
        unz.data = NULL;
        if (detached.data) bvox__bytes_release(&detached);
    } else {
        if (h.byte_skip == -1) { /* the samples are the last bytes */
            if (need > avail - start) goto truncated;
            start = avail - need;
        } else {
            if ((uint64_t)h.byte_skip > avail - start) goto truncated;
            start += (size_t)h.byte_skip;
        }
        if (need > avail - start) goto truncated;
        if (detached.data) { /* the gray keeps the data file */
            g->owned = detached.data;
            g->owned_bytes = detached.alloc_bytes;
        }
        g->data = src + start;
    }
    g->dims = d;
    g->dtype = h.dtype;
    {
        const uint16_t probe = 1;
        bool host_big = *(const uint8_t *)&probe == 0;
        g->byteswap = elem > 1 && h.big_endian != host_big;
    }
    set_geometry(&h, &g->geom);
    if (h.layers) { /* a layered segmentation: one label per voxel (seg_nrrd.c) */
        st = bvox__segs_flatten(g, h.layers, data, h.header_end, name);
        if (st) {
            bvox__gray_release(g);
            return st;
        }
    }
    return BVOX_OK;
truncated:
    st = bvox__fail(BVOX_EFORMAT,
                    "%s: truncated: NRRD sizes %ld x %ld x %ld of %s need %zu bytes of samples, "
                    "%zu remain",
                    name, (long)d.nx, (long)d.ny, (long)d.nz, bvox_dtype_name(h.dtype), need,
                    avail - start);
fail:
    if (unz.data) bvox__bytes_release(&unz);
    if (detached.data) bvox__bytes_release(&detached);
    bvox__gray_init(g);
    return st;
}

static bvox_status nrrd_read_memory(const uint8_t *data, size_t size, const char *name,
                                    const bvox_read_opts *opts, bvox_volume **out)
{
    *out = NULL;
    if (!name) name = "input";
    bvox__gray g;
    bvox_status st = nrrd_gray_memory(data, size, name, opts, &g);
    if (st) return st;
    st = bvox__binarize(&g, opts ? &opts->binarize : NULL, name, out);
    bvox__gray_release(&g);
    return st;
}

bool bvox__nrrd_layered(const uint8_t *data, size_t size)
{
    nrrd_header h;
    bvox_status st = parse_header(data, size, "table", &h);
    bvox__clear_error();
    return !st && h.layers > 0;
}

static const char *const nrrd_extensions[] = {".nrrd", ".nhdr", NULL};

const bvox__format bvox__format_nrrd = {
    "nrrd", nrrd_extensions, nrrd_sniff, nrrd_read_memory, NULL, bvox__nrrd_write, NULL, NULL,
    nrrd_gray_memory,
};
