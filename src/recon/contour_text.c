/*
 * contour_text.c — small text helpers shared by the contour readers and
 * writers (JSON, SVG, Reconstruct XML): XML escaping, line:column of an
 * offset, UTF-8 output of a code point, reading a whole text file with a size
 * limit, and writing a text buffer (src/common/strbuf.h) through bvox__sink
 * (temporary file, fsync, rename).
 */
#include "contour_internal.h"
#include "io/io.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

bvox_status bvox__sb_write_file(const bvox__strbuf *b, const char *path)
{
    if (b->over_budget) {
        char have[32], lim[32];
        bvox__format_bytes(have, sizeof have, b->cap);
        bvox__format_bytes(lim, sizeof lim, bvox_memory_budget());
        return bvox__fail(BVOX_ETOOBIG, "%s: the text grew past %s and reached the memory "
                          "budget of %s", path, have, lim);
    }
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

bvox_status bvox__text_input_check(const char *fn, const char *data, size_t size,
                                   const char **name)
{
    if (!data && size) return bvox__fail(BVOX_EINVAL, "%s: no data", fn);
    if (!*name) *name = "<memory>";
    if (size > BVOX__MAX_TEXT_BYTES)
        return bvox__fail(BVOX_ETOOBIG, "%s: %zu bytes, over the limit of a contour file", *name,
                          size);
    return BVOX_OK;
}
