/*
 * json.c — the streaming JSON writer of json.h. Output is compact, one value
 * per call, so that a command's whole result is one line a script can parse.
 */
#include "json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void cli_json_init(cli_json *j, FILE *f)
{
    memset(j, 0, sizeof *j);
    j->f = f;
}

/* Comma before every value but the first of its level (not after a key). */
static void before_value(cli_json *j)
{
    if (j->after_key) {
        j->after_key = 0;
        return;
    }
    if (j->count[j->depth]++ > 0) fputc(',', j->f);
}

static void open_level(cli_json *j, char c)
{
    before_value(j);
    fputc(c, j->f);
    /* Deeper than the limit would be a bug in the caller: clamp, keep writing. */
    if (j->depth + 1 < CLI_JSON_MAX_DEPTH) j->depth++;
    j->count[j->depth] = 0;
}

static void close_level(cli_json *j, char c)
{
    fputc(c, j->f);
    if (j->depth > 0) j->depth--;
}

void cli_json_begin_object(cli_json *j) { open_level(j, '{'); }
void cli_json_end_object(cli_json *j) { close_level(j, '}'); }
void cli_json_begin_array(cli_json *j) { open_level(j, '['); }
void cli_json_end_array(cli_json *j) { close_level(j, ']'); }

static void write_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\b': fputs("\\b", f); break;
        case '\f': fputs("\\f", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            /* Other control characters must be escaped; bytes >= 0x80 pass
             * through (file names are UTF-8 on any system we target). */
            if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\u%04x", *p);
            else fputc(*p, f);
        }
    }
    fputc('"', f);
}

void cli_json_key(cli_json *j, const char *key)
{
    before_value(j);
    write_string(j->f, key);
    fputc(':', j->f);
    j->after_key = 1;
}

void cli_json_string(cli_json *j, const char *s)
{
    if (!s) {
        cli_json_null(j);
        return;
    }
    before_value(j);
    write_string(j->f, s);
}

void cli_json_format_double(char *buf, size_t size, double v)
{
    /* %.17g always round-trips but prints 0.1 as 0.10000000000000001; try
     * the shorter precisions first and keep the first that reads back. */
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, size, "%.*g", prec, v);
        if (strtod(buf, NULL) == v) break;
    }
}

void cli_json_double(cli_json *j, double v)
{
    if (!isfinite(v)) {
        cli_json_null(j);
        return;
    }
    char buf[40];
    if (v == 0) v = 0; /* -0 (e.g. a negated zero origin) prints as 0 */
    cli_json_format_double(buf, sizeof buf, v);
    before_value(j);
    fputs(buf, j->f);
}

void cli_json_int(cli_json *j, int64_t v)
{
    before_value(j);
    fprintf(j->f, "%lld", (long long)v);
}

void cli_json_bool(cli_json *j, int v)
{
    before_value(j);
    fputs(v ? "true" : "false", j->f);
}

void cli_json_null(cli_json *j)
{
    before_value(j);
    fputs("null", j->f);
}

void cli_json_double_array(cli_json *j, const double *v, int n)
{
    cli_json_begin_array(j);
    for (int i = 0; i < n; i++) cli_json_double(j, v[i]);
    cli_json_end_array(j);
}

void cli_json_int_array(cli_json *j, const int64_t *v, int n)
{
    cli_json_begin_array(j);
    for (int i = 0; i < n; i++) cli_json_int(j, v[i]);
    cli_json_end_array(j);
}
