/*
 * label_table.c — names and colours of labels from the lookup tables that
 * segmentation tools write. One line per label, '#' comments, blank lines:
 *
 *   FreeSurfer *LUT.txt,   index name R G B A      (A: 0 opaque... FreeSurfer
 *   3D Slicer .ctbl/.txt   index name R G B A       and Slicer differ: see below)
 *   ITK-SNAP description   index R G B A visible mesh "name"   (A: 0..1 opacity)
 *   AAL / mricron .txt     index name code          (no colour)
 *   3D Slicer .seg.nrrd    its Segment<N>_Name/_Color keys (seg_nrrd.c)
 *
 * The kind is told per line: a quoted name means ITK-SNAP; otherwise the
 * second token is the name and three integers 0..255 after it are a colour.
 * FreeSurfer's fourth number is a transparency in files it ships (0 for
 * every label) and Slicer's an opacity (255): both are kept as "alpha"
 * 255 unless the value is 1..254 (a real opacity). A duplicate label keeps
 * its first entry (entries end sorted by label) and an unreadable line is skipped; both are warnings
 * (table->warnings), never failures: tables are hand-edited and users would
 * rather see their volume with a name missing than nothing at all.
 */
#include "io.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Through the library's warning handler (warn.c), counted in the table. */
static void warn(bvox_label_table *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(bvox_label_table *t, const char *fmt, ...)
{
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    bvox__warn("%s", msg);
    t->nwarnings++;
}

/* Next whitespace-separated token of line (NUL-terminated in place). */
static char *token(char **p)
{
    char *s = *p;
    while (*s && isspace((unsigned char)*s)) s++;
    if (!*s) return NULL;
    char *e = s;
    while (*e && !isspace((unsigned char)*e)) e++;
    if (*e) *e++ = '\0';
    *p = e;
    return s;
}

static bool parse_int(const char *s, int64_t *v)
{
    if (!s) return false;
    char *end;
    errno = 0;
    long long x = strtoll(s, &end, 10);
    if (errno || end == s || *end) return false;
    *v = x;
    return true;
}

static bool parse_byte(const char *s, unsigned char *v)
{
    int64_t x;
    if (!parse_int(s, &x) || x < 0 || x > 255) return false;
    *v = (unsigned char)x;
    return true;
}

static void set_name(bvox_label_entry *e, const char *s, size_t n)
{
    if (n >= sizeof e->name) n = sizeof e->name - 1;
    memcpy(e->name, s, n);
    e->name[n] = '\0';
}

/* One line into e; false if it is not an entry. */
static bool parse_line(char *line, bvox_label_entry *e)
{
    memset(e, 0, sizeof *e);
    e->rgba[3] = 255;
    char *q = strchr(line, '"');
    char *p = line;
    if (q) { /* ITK-SNAP: IDX R G B A VIS MSH "LABEL" */
        char *q2 = strrchr(line, '"');
        if (q2 == q) return false;
        *q = '\0';
        if (!parse_int(token(&p), &e->label)) return false;
        unsigned char c[3];
        for (int i = 0; i < 3; i++)
            if (!parse_byte(token(&p), &c[i])) return false;
        memcpy(e->rgba, c, 3);
        char *a = token(&p);
        if (a) {
            double op = strtod(a, NULL);
            if (op >= 0 && op <= 1) e->rgba[3] = (unsigned char)(op * 255 + 0.5);
        }
        e->has_color = 1;
        set_name(e, q + 1, (size_t)(q2 - q - 1));
        return true;
    }
    if (!parse_int(token(&p), &e->label)) return false;
    char *name = token(&p);
    if (!name) return false;
    set_name(e, name, strlen(name));
    char *rest[4];
    int n = 0;
    char *t;
    while (n < 4 && (t = token(&p))) rest[n++] = t;
    unsigned char c[3];
    if (n >= 3 && parse_byte(rest[0], &c[0]) && parse_byte(rest[1], &c[1]) &&
        parse_byte(rest[2], &c[2])) {
        memcpy(e->rgba, c, 3);
        e->has_color = 1;
        unsigned char a;
        if (n >= 4 && parse_byte(rest[3], &a) && a > 0 && a < 255) e->rgba[3] = a;
    }
    return true;
}

static size_t *realloc_lines(size_t *lines, size_t n)
{
    size_t *l = bvox__mem_resize(lines, n * sizeof *l);
    if (!l) free(lines);
    return l;
}

typedef struct keyed {
    bvox_label_entry e;
    size_t line;
} keyed;

static int by_label_line(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->e.label != b->e.label) return (a->e.label > b->e.label) - (a->e.label < b->e.label);
    return (a->line > b->line) - (a->line < b->line);
}

/* Sort by label (binary search in find) and keep the first of duplicates. */
static void dedupe(bvox_label_table *t, const size_t *lines, const char *name)
{
    keyed *k = bvox__mem_alloc((size_t)t->n * sizeof *k);
    if (!k) return; /* left unsorted: find falls back to a scan */
    for (int64_t i = 0; i < t->n; i++) k[i] = (keyed){t->entries[i], lines[i]};
    qsort(k, (size_t)t->n, sizeof *k, by_label_line);
    int64_t m = 0;
    for (int64_t i = 0; i < t->n; i++) {
        if (m && k[i].e.label == t->entries[m - 1].label) {
            warn(t, "%s:%zu: label %lld is listed again, the first entry is kept", name,
                 k[i].line, (long long)k[i].e.label);
            continue;
        }
        t->entries[m++] = k[i].e;
    }
    t->n = m;
    t->sorted = 1;
    free(k);
}

void bvox_label_table_destroy(bvox_label_table *table)
{
    if (!table) return;
    free(table->entries);
    free(table);
}

const bvox_label_entry *bvox_label_table_find(const bvox_label_table *table, int64_t label)
{
    if (!table) return NULL;
    if (table->sorted) {
        int64_t lo = 0, hi = table->n;
        while (lo < hi) {
            int64_t mid = lo + (hi - lo) / 2;
            if (table->entries[mid].label < label) lo = mid + 1;
            else hi = mid;
        }
        return lo < table->n && table->entries[lo].label == label ? &table->entries[lo] : NULL;
    }
    for (int64_t i = 0; i < table->n; i++)
        if (table->entries[i].label == label) return &table->entries[i];
    return NULL;
}

bvox_status bvox_label_table_parse(const char *text, size_t size, const char *name,
                                   bvox_label_table **out)
{
    bvox__clear_error();
    if (!out || (!text && size)) return bvox__fail(BVOX_EINVAL, "bvox_label_table_parse: NULL");
    *out = NULL;
    if (!name) name = "table";
    if (size >= 8 && !memcmp(text, "NRRD000", 7)) /* a Slicer .seg.nrrd: its segments */
        return bvox__segs_table((const uint8_t *)text, size, name,
                                bvox__nrrd_layered((const uint8_t *)text, size), out);
    bvox_label_table *t = bvox__mem_zalloc(1, sizeof *t);
    char *line = bvox__mem_alloc(size + 1);
    if (!t || !line) {
        free(t);
        free(line);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
    }
    size_t cap = 0, pos = 0, lineno = 0, *lines = NULL;
    int64_t bad = 0;
    while (pos < size) {
        size_t end = pos;
        while (end < size && text[end] != '\n') end++;
        size_t n = end - pos;
        memcpy(line, text + pos, n);
        line[n] = '\0';
        pos = end + 1;
        lineno++;
        for (size_t i = 0; i < n; i++)
            if (line[i] == '\r' || line[i] == '\0') line[i] = ' ';
        char *hash = strchr(line, '#');
        if (hash && !strchr(line, '"')) *hash = '\0'; /* quoted ITK-SNAP names may hold '#' */
        char *s = line;
        while (*s && isspace((unsigned char)*s)) s++;
        if (!*s || *s == '#') continue;
        bvox_label_entry e;
        if (!parse_line(s, &e)) {
            bad++;
            warn(t, "%s:%zu: not a label line, skipped", name, lineno);
            continue;
        }
        if ((size_t)t->n == cap) {
            cap = cap ? cap * 2 : 64;
            bvox_label_entry *ne = bvox__mem_resize(t->entries, cap * sizeof *ne);
            if (!ne) {
                free(line);
                bvox_label_table_destroy(t);
                return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
            }
            t->entries = ne;
        }
        t->entries[t->n] = e;
        lines = realloc_lines(lines, (size_t)t->n + 1);
        if (!lines) {
            free(line);
            bvox_label_table_destroy(t);
            return bvox__fail(BVOX_ENOMEM, "%s: out of memory", name);
        }
        lines[t->n++] = lineno;
    }
    free(line);
    dedupe(t, lines, name);
    free(lines);
    if (t->n == 0) {
        bvox_label_table_destroy(t);
        return bvox__fail(BVOX_EFORMAT, "%s: no label lines (expected 'index name ...' or "
                                        "ITK-SNAP's 'index R G B A vis mesh \"name\"')",
                          name);
    }
    (void)bad;
    *out = t;
    return BVOX_OK;
}

bvox_status bvox_label_table_read(const char *path, bvox_label_table **out)
{
    bvox__clear_error();
    if (!out || !path) return bvox__fail(BVOX_EINVAL, "bvox_label_table_read: NULL argument");
    *out = NULL;
    bvox__bytes file;
    bvox_status st = bvox__read_file(path, &file);
    if (st) return st;
    st = bvox_label_table_parse((const char *)file.data, file.size, path, out);
    bvox__bytes_release(&file);
    return st;
}
