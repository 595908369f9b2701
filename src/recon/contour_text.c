/*
 * contour_text.c — small text helpers shared by the contour readers and
 * writers (JSON, SVG, Reconstruct XML): a growable string buffer, shortest
 * round-trip number text, escaping, line:column of an offset, UTF-8 output
 * of a code point, and reading a whole text file with a size limit. Writing goes through bvox__sink
 * (temporary file, fsync, rename).
 */
#include "contour_internal.h"
#include "io/io.h"

#include <math.h>
#include <stdarg.h>
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
        char *p = bvox__mem_resize(b->data, cap);
        if (!p) {
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
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (strtod(buf, NULL) == v) break;
    }
    bvox__sb_puts(b, buf);
}

void bvox__sb_json_string(bvox__strbuf *b, const char *s)
{
    bvox__sb_append(b, "\"", 1);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\') {
            char e[2] = {'\\', (char)*p};
            bvox__sb_append(b, e, 2);
        } else if (*p < 0x20) {
            bvox__sb_printf(b, "\\u%04x", *p);
        } else {
            bvox__sb_append(b, (const char *)p, 1);
        }
    }
    bvox__sb_append(b, "\"", 1);
}

void bvox__sb_xml_text(bvox__strbuf *b, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '<': bvox__sb_puts(b, "&lt;"); break;
        case '>': bvox__sb_puts(b, "&gt;"); break;
        case '&': bvox__sb_puts(b, "&amp;"); break;
        case '"': bvox__sb_puts(b, "&quot;"); break;
        case '\'': bvox__sb_puts(b, "&apos;"); break;
        default:
            if (*p < 0x20 && *p != '\t' && *p != '\n' && *p != '\r') bvox__sb_puts(b, "?");
            else bvox__sb_append(b, (const char *)p, 1);
        }
    }
}

void bvox__sb_free(bvox__strbuf *b)
{
    free(b->data);
    memset(b, 0, sizeof *b);
}

bvox_status bvox__sb_write_file(const bvox__strbuf *b, const char *path)
{
    if (b->failed) return bvox__fail(BVOX_ENOMEM, "%s: out of memory for the text", path);
    bvox__sink sink;
    bvox_status st = bvox__sink_open(path, 0, &sink);
    if (st) return st;
    st = bvox__sink_write(&sink, b->data ? b->data : "", b->len);
    if (st) {
        bvox__sink_abort(&sink);
        return st;
    }
    return bvox__sink_commit(&sink);
}

void bvox__line_col(const char *text, size_t pos, int64_t *line, int64_t *col)
{
    int64_t l = 1, c = 1;
    for (size_t i = 0; i < pos; i++) {
        if (text[i] == '\n') {
            l++;
            c = 1;
        } else {
            c++;
        }
    }
    *line = l;
    *col = c;
}

void bvox__put_utf8(char *out, size_t *n, uint32_t c)
{
    if (c < 0x80) {
        out[(*n)++] = (char)c;
    } else if (c < 0x800) {
        out[(*n)++] = (char)(0xC0 | (c >> 6));
        out[(*n)++] = (char)(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        out[(*n)++] = (char)(0xE0 | (c >> 12));
        out[(*n)++] = (char)(0x80 | ((c >> 6) & 0x3F));
        out[(*n)++] = (char)(0x80 | (c & 0x3F));
    } else {
        out[(*n)++] = (char)(0xF0 | (c >> 18));
        out[(*n)++] = (char)(0x80 | ((c >> 12) & 0x3F));
        out[(*n)++] = (char)(0x80 | ((c >> 6) & 0x3F));
        out[(*n)++] = (char)(0x80 | (c & 0x3F));
    }
}

bvox_status bvox__read_text(const char *path, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    bvox__bytes bytes;
    bvox_status st = bvox__read_file(path, &bytes);
    if (st) return st;
    if (bytes.size > BVOX__MAX_TEXT_BYTES) {
        bvox__bytes_release(&bytes);
        return bvox__fail(BVOX_ETOOBIG, "%s: %zu bytes, over the %zu MiB limit of a contour file",
                          path, bytes.size, BVOX__MAX_TEXT_BYTES >> 20);
    }
    char *text = bvox__mem_alloc(bytes.size + 1);
    if (!text) {
        bvox__bytes_release(&bytes);
        return bvox__fail(BVOX_ENOMEM, "%s: out of memory", path);
    }
    if (bytes.size) memcpy(text, bytes.data, bytes.size);
    text[bytes.size] = '\0';
    *size = bytes.size;
    *data = text;
    bvox__bytes_release(&bytes);
    return BVOX_OK;
}
