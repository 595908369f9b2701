/*
 * strbuf.c — a growable text buffer (strbuf.h) for writers that build their
 * whole output in memory before committing it (contour JSON, SVG, XML; the
 * JSON writer's buffer mode), and the shortest round-trip text of a double.
 */
#include "strbuf.h"
#include "core/alloc.h"
#include "internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void bvox__sb_append(bvox__strbuf *b, const char *s, size_t n)
{
    if (b->failed) return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + n + 1) {
            if (cap > SIZE_MAX / 2) {
                b->failed = true;
                return;
            }
            cap *= 2;
        }
        bvox_status st;
        if (!bvox__budget_charge(cap - b->cap, "text", &st)) {
            b->failed = b->over_budget = true;
            return;
        }
        char *p = bvox__mem_resize(b->data, cap);
        if (!p) {
            bvox__budget_refund(cap - b->cap);
            b->failed = true;
            return;
        }
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
}

void bvox__sb_puts(bvox__strbuf *b, const char *s) { bvox__sb_append(b, s, strlen(s)); }

void bvox__sb_printf(bvox__strbuf *b, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = true;
        return;
    }
    if ((size_t)n < sizeof tmp) {
        bvox__sb_append(b, tmp, (size_t)n);
        return;
    }
    char *big = bvox__mem_alloc((size_t)n + 1);
    if (!big) {
        b->failed = true;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    bvox__sb_append(b, big, (size_t)n);
    free(big);
}

void bvox__sb_double(bvox__strbuf *b, double v)
{
    char buf[40];
    if (!isfinite(v)) v = 0; /* the model holds only finite values */
    if (v == 0) v = 0;       /* no "-0" */
    if (v == floor(v) && fabs(v) < 1e15) { /* integers (traced outlines): no printf */
        long long i = (long long)v;
        unsigned long long u = i < 0 ? 0ull - (unsigned long long)i : (unsigned long long)i;
        char *p = buf + sizeof buf;
        *--p = '\0';
        do {
            *--p = (char)('0' + u % 10);
            u /= 10;
        } while (u);
        if (i < 0) *--p = '-';
        bvox__sb_puts(b, p);
        return;
    }
    bvox__format_double(buf, sizeof buf, v);
    bvox__sb_puts(b, buf);
}

void bvox__format_double(char *buf, size_t size, double v)
{
    /* %.17g always round-trips but prints 0.1 as 0.10000000000000001; try
     * the shorter precisions first and keep the first that reads back. */
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, size, "%.*g", prec, v);
        if (strtod(buf, NULL) == v) break;
    }
}

void bvox__sb_free(bvox__strbuf *b)
{
    free(b->data);
    bvox__budget_refund(b->cap);
    memset(b, 0, sizeof *b);
}
