/*
 * mesh_text.c — the small text tokenizer the OBJ, OFF, PLY and ASCII STL
 * readers share: bounded tokens, line numbers for messages, strict numbers
 * (the whole token, finite). Apart from the dispatcher (mesh_read.c), which
 * calls the readers that use it.
 */
#include "mesh_private.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void bvox__text_init(bvox__text *t, const uint8_t *d, size_t n, const char *name)
{
    t->p = (const char *)d;
    t->end = (const char *)d + n;
    t->name = name;
    t->line = 1;
}

void bvox__text_skip_blank(bvox__text *t)
{
    while (t->p < t->end && (*t->p == ' ' || *t->p == '\t' || *t->p == '\r')) t->p++;
}

void bvox__text_next_line(bvox__text *t)
{
    while (t->p < t->end && *t->p != '\n') t->p++;
    if (t->p < t->end) {
        t->p++;
        t->line++;
    }
}

void bvox__text_skip_ws(bvox__text *t)
{
    for (;;) {
        bvox__text_skip_blank(t);
        if (t->p >= t->end) return;
        if (*t->p == '\n') {
            t->p++;
            t->line++;
        } else if (*t->p == '#') {
            bvox__text_next_line(t);
        } else {
            return;
        }
    }
}

int bvox__text_token(bvox__text *t, char *buf, size_t size, int same_line)
{
    if (same_line) bvox__text_skip_blank(t);
    else bvox__text_skip_ws(t);
    if (t->p >= t->end || *t->p == '\n' || (same_line && *t->p == '#')) return 0;
    size_t n = 0;
    int too_long = 0;
    while (t->p < t->end && *t->p != ' ' && *t->p != '\t' && *t->p != '\r' && *t->p != '\n') {
        if (n + 1 < size) buf[n++] = *t->p;
        else too_long = 1;
        t->p++;
    }
    if (too_long) { /* never a number or keyword; messages say "(too long)" */
        buf[0] = '\x01';
        n = 1;
    }
    buf[n] = 0;
    return 1;
}

bvox_status bvox__text_double(bvox__text *t, int same_line, const char *what, double *out)
{
    char tok[64];
    if (!bvox__text_token(t, tok, sizeof tok, same_line))
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: missing %s (truncated?)", t->name,
                          (long long)t->line, what);
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (end == tok || *end || !isfinite(v))
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: bad %s '%s' (a finite number is needed)",
                          t->name, (long long)t->line, what, tok[0] == 1 ? "(too long)" : tok);
    *out = v;
    return BVOX_OK;
}

bvox_status bvox__text_int(bvox__text *t, int same_line, const char *what, int64_t lo,
                           int64_t hi, int64_t *out)
{
    char tok[64];
    if (!bvox__text_token(t, tok, sizeof tok, same_line))
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: missing %s (truncated?)", t->name,
                          (long long)t->line, what);
    char *end;
    errno = 0;
    long long v = strtoll(tok, &end, 10);
    if (end == tok || *end || errno == ERANGE || v < lo || v > hi)
        return bvox__fail(BVOX_EFORMAT, "%s: line %lld: bad %s '%s' (an integer in %lld..%lld)",
                          t->name, (long long)t->line, what, tok[0] == 1 ? "(too long)" : tok,
                          (long long)lo, (long long)hi);
    *out = v;
    return BVOX_OK;
}
