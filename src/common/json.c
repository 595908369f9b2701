/*
 * json.c — the JSON writer of json.h. Output is compact, one value per call,
 * so that a command's whole result is one line a script can parse.
 */
#include "json.h"

#include <math.h>
#include <string.h>

void bvox__json_init(bvox__json *j, FILE *f)
{
    memset(j, 0, sizeof *j);
    j->f = f;
}

void bvox__json_init_buffer(bvox__json *j, bvox__strbuf *sb)
{
    memset(j, 0, sizeof *j);
    j->sb = sb;
}

static void put(bvox__json *j, const char *s, size_t n)
{
    if (j->f) fwrite(s, 1, n, j->f);
    else bvox__sb_append(j->sb, s, n);
}

static void puts_(bvox__json *j, const char *s) { put(j, s, strlen(s)); }

/* Comma before every value but the first of its level (not after a key). */
static void before_value(bvox__json *j)
{
    if (j->after_key) {
        j->after_key = 0;
        return;
    }
    if (j->count[j->depth]++ > 0) put(j, ",", 1);
}

static void open_level(bvox__json *j, const char *c)
{
    before_value(j);
    put(j, c, 1);
    /* Deeper than the limit would be a bug in the caller: clamp, keep writing. */
    if (j->depth + 1 < BVOX__JSON_MAX_DEPTH) j->depth++;
    j->count[j->depth] = 0;
}

static void close_level(bvox__json *j, const char *c)
{
    put(j, c, 1);
    if (j->depth > 0) j->depth--;
}

void bvox__json_begin_object(bvox__json *j) { open_level(j, "{"); }
void bvox__json_end_object(bvox__json *j) { close_level(j, "}"); }
void bvox__json_begin_array(bvox__json *j) { open_level(j, "["); }
void bvox__json_end_array(bvox__json *j) { close_level(j, "]"); }

/* The escaping of json.h's comment, in runs: plain bytes are put a run at a
 * time, an escape on its own. */
static void write_string(bvox__json *j, const char *s)
{
    put(j, "\"", 1);
    const unsigned char *run = (const unsigned char *)s, *p = run;
    for (; *p; p++) {
        const char *e = NULL;
        char u[8];
        switch (*p) {
        case '"': e = "\\\""; break;
        case '\\': e = "\\\\"; break;
        case '\b': e = "\\b"; break;
        case '\f': e = "\\f"; break;
        case '\n': e = "\\n"; break;
        case '\r': e = "\\r"; break;
        case '\t': e = "\\t"; break;
        default:
            if (*p < 0x20 || *p == 0x7f) {
                snprintf(u, sizeof u, "\\u%04x", *p);
                e = u;
            }
        }
        if (!e) continue;
        put(j, (const char *)run, (size_t)(p - run));
        puts_(j, e);
        run = p + 1;
    }
    put(j, (const char *)run, (size_t)(p - run));
    put(j, "\"", 1);
}

void bvox__sb_json_string(bvox__strbuf *b, const char *s)
{
    bvox__json j;
    bvox__json_init_buffer(&j, b);
    write_string(&j, s);
}

void bvox__json_key(bvox__json *j, const char *key)
{
    before_value(j);
    write_string(j, key);
    put(j, ":", 1);
    j->after_key = 1;
}

void bvox__json_string(bvox__json *j, const char *s)
{
    if (!s) {
        bvox__json_null(j);
        return;
    }
    before_value(j);
    write_string(j, s);
}

void bvox__json_double(bvox__json *j, double v)
{
    if (!isfinite(v)) {
        bvox__json_null(j);
        return;
    }
    char buf[40];
    if (v == 0) v = 0; /* -0 (e.g. a negated zero origin) prints as 0 */
    bvox__format_double(buf, sizeof buf, v);
    before_value(j);
    puts_(j, buf);
}

void bvox__json_int(bvox__json *j, int64_t v)
{
    char buf[24];
    snprintf(buf, sizeof buf, "%lld", (long long)v);
    before_value(j);
    puts_(j, buf);
}

void bvox__json_bool(bvox__json *j, int v)
{
    before_value(j);
    puts_(j, v ? "true" : "false");
}

void bvox__json_null(bvox__json *j)
{
    before_value(j);
    puts_(j, "null");
}

void bvox__json_double_array(bvox__json *j, const double *v, int n)
{
    bvox__json_begin_array(j);
    for (int i = 0; i < n; i++) bvox__json_double(j, v[i]);
    bvox__json_end_array(j);
}

void bvox__json_int_array(bvox__json *j, const int64_t *v, int n)
{
    bvox__json_begin_array(j);
    for (int i = 0; i < n; i++) bvox__json_int(j, v[i]);
    bvox__json_end_array(j);
}
