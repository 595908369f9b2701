/*
 * contour_xml.c — a small pull tokenizer for the XML the contour readers
 * need (SVG, Reconstruct series and sections): start tags with their raw
 * attributes, end tags, end of document. Written here because libbvox has
 * no XML dependency (libxml2 would be a large one for two readers that need
 * only tags and attributes). Well-formedness that matters to the readers is
 * checked (matching end tags, quoted attributes, no '<' in values, a single
 * root, nothing but white space/comments/PIs outside it); DTD entities are not
 * supported: the five predefined entities and character references are.
 */
#include "contour_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void bvox__xml_init(bvox__xml *x, const char *data, size_t size, const char *name)
{
    memset(x, 0, sizeof *x);
    x->start = x->p = data ? data : "";
    x->end = x->start + (data ? size : 0);
    x->name = name ? name : "<memory>";
    if (x->end - x->p >= 3 && (unsigned char)x->p[0] == 0xEF && (unsigned char)x->p[1] == 0xBB &&
        (unsigned char)x->p[2] == 0xBF)
        x->p += 3; /* a UTF-8 byte order mark */
}

bvox_status bvox__xml_fail(const bvox__xml *x, const char *at, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (!at) at = x->at ? x->at : x->p;
    int64_t line, col;
    bvox__line_col(x->start, (size_t)(at - x->start), &line, &col);
    return bvox__fail(BVOX_EFORMAT, "%s:%lld:%lld: %s", x->name, (long long)line, (long long)col,
                      msg);
}

static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
static bool is_name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_' || c == '-' || c == '.' || c == ':' || (unsigned char)c >= 0x80;
}

/* Skip to just after `until` (a string); false if not found. */
static bool skip_past(bvox__xml *x, const char *until)
{
    size_t n = strlen(until);
    while (x->end - x->p >= (ptrdiff_t)n) {
        if (!memcmp(x->p, until, n)) {
            x->p += n;
            return true;
        }
        x->p++;
    }
    x->p = x->end;
    return false;
}

static bool starts(const bvox__xml *x, const char *s)
{
    size_t n = strlen(s);
    return x->end - x->p >= (ptrdiff_t)n && !memcmp(x->p, s, n);
}

static void local_name(const char *name, size_t len, const char **out, size_t *outlen)
{
    const char *colon = memchr(name, ':', len);
    if (colon) {
        *out = colon + 1;
        *outlen = len - (size_t)(colon + 1 - name);
    } else {
        *out = name;
        *outlen = len;
    }
}

bvox_status bvox__xml_next(bvox__xml *x)
{
    if (x->pending_end) { /* the END of <tag/> */
        x->pending_end = false;
        x->kind = BVOX__XML_END;
        x->nattrs = 0;
        x->depth--;
        return BVOX_OK;
    }
    for (;;) {
        /* text up to the next '<' (skipped; outside the root only white space) */
        const char *text = x->p;
        while (x->p < x->end && *x->p != '<') x->p++;
        if (x->depth == 0)
            for (const char *q = text; q < x->p; q++)
                if (!is_space(*q)) return bvox__xml_fail(x, q, "text outside the root element");
        if (x->p >= x->end) {
            if (x->depth > 0)
                return bvox__xml_fail(x, x->p, "the file ends inside <%.*s>",
                                      (int)x->stacklen[x->depth - 1], x->stack[x->depth - 1]);
            x->kind = BVOX__XML_EOF;
            x->at = x->p;
            return BVOX_OK;
        }
        x->at = x->p;
        if (starts(x, "<!--")) {
            if (!skip_past(x, "-->")) return bvox__xml_fail(x, x->at, "unterminated comment");
            continue;
        }
        if (starts(x, "<![CDATA[")) {
            if (x->depth == 0) return bvox__xml_fail(x, x->at, "CDATA outside the root element");
            if (!skip_past(x, "]]>")) return bvox__xml_fail(x, x->at, "unterminated CDATA");
            continue;
        }
        if (starts(x, "<?")) {
            if (!skip_past(x, "?>")) return bvox__xml_fail(x, x->at, "unterminated <?...?>");
            continue;
        }
        if (starts(x, "<!")) { /* DOCTYPE, possibly with an internal subset [...] */
            int bracket = 0;
            x->p += 2;
            while (x->p < x->end && (bracket || *x->p != '>')) {
                if (*x->p == '[') bracket++;
                else if (*x->p == ']' && bracket) bracket--;
                x->p++;
            }
            if (x->p >= x->end) return bvox__xml_fail(x, x->at, "unterminated <!...>");
            x->p++;
            continue;
        }
        x->p++; /* '<' */
        bool end = false;
        if (x->p < x->end && *x->p == '/') {
            end = true;
            x->p++;
        }
        const char *name = x->p;
        while (x->p < x->end && is_name_char(*x->p)) x->p++;
        size_t nlen = (size_t)(x->p - name);
        if (nlen == 0) return bvox__xml_fail(x, x->at, "a '<' not followed by a tag name");
        if (end) {
            while (x->p < x->end && is_space(*x->p)) x->p++;
            if (x->p >= x->end || *x->p != '>')
                return bvox__xml_fail(x, x->at, "expected '>' closing </%.*s", (int)nlen, name);
            x->p++;
            if (x->depth == 0)
                return bvox__xml_fail(x, x->at, "</%.*s> without a start tag", (int)nlen, name);
            if (x->stacklen[x->depth - 1] != nlen || memcmp(x->stack[x->depth - 1], name, nlen))
                return bvox__xml_fail(x, x->at, "</%.*s> closes <%.*s>", (int)nlen, name,
                                      (int)x->stacklen[x->depth - 1], x->stack[x->depth - 1]);
            x->depth--;
            x->kind = BVOX__XML_END;
            local_name(name, nlen, &x->tag, &x->taglen);
            x->nattrs = 0;
            return BVOX_OK;
        }
        if (x->depth >= BVOX__MAX_DEPTH)
            return bvox__xml_fail(x, x->at, "elements nested deeper than %d", BVOX__MAX_DEPTH);
        if (x->depth == 0 && x->stack[0] != NULL)
            return bvox__xml_fail(x, x->at, "a second root element <%.*s>", (int)nlen, name);
        x->nattrs = 0;
        x->empty = false;
        for (;;) {
            const char *before = x->p;
            while (x->p < x->end && is_space(*x->p)) x->p++;
            if (x->p >= x->end) return bvox__xml_fail(x, x->at, "unterminated <%.*s", (int)nlen, name);
            if (*x->p == '>') {
                x->p++;
                break;
            }
            if (*x->p == '/') {
                if (x->end - x->p < 2 || x->p[1] != '>')
                    return bvox__xml_fail(x, x->p, "expected '/>'");
                x->p += 2;
                x->empty = true;
                break;
            }
            if (x->p == before) return bvox__xml_fail(x, x->p, "expected white space before an attribute");
            const char *an = x->p;
            while (x->p < x->end && is_name_char(*x->p)) x->p++;
            size_t anl = (size_t)(x->p - an);
            if (anl == 0) return bvox__xml_fail(x, x->p, "expected an attribute name");
            while (x->p < x->end && is_space(*x->p)) x->p++;
            if (x->p >= x->end || *x->p != '=')
                return bvox__xml_fail(x, x->p, "expected '=' after attribute %.*s", (int)anl, an);
            x->p++;
            while (x->p < x->end && is_space(*x->p)) x->p++;
            if (x->p >= x->end || (*x->p != '"' && *x->p != '\''))
                return bvox__xml_fail(x, x->p, "attribute %.*s: expected a quoted value", (int)anl, an);
            char q = *x->p++;
            const char *v = x->p;
            while (x->p < x->end && *x->p != q) {
                if (*x->p == '<') return bvox__xml_fail(x, x->p, "'<' in an attribute value");
                x->p++;
            }
            if (x->p >= x->end) return bvox__xml_fail(x, v - 1, "unterminated attribute value");
            size_t vl = (size_t)(x->p - v);
            x->p++;
            if (x->nattrs >= BVOX__XML_MAX_ATTRS)
                return bvox__xml_fail(x, an, "more than %d attributes", BVOX__XML_MAX_ATTRS);
            x->attrs[x->nattrs++] = (bvox__xml_attr){an, v, anl, vl};
        }
        x->stack[x->depth] = name;
        x->stacklen[x->depth] = nlen;
        x->depth++;
        x->kind = BVOX__XML_START;
        local_name(name, nlen, &x->tag, &x->taglen);
        x->pending_end = x->empty;
        return BVOX_OK;
    }
}

bool bvox__xml_is(const bvox__xml *x, const char *tag)
{
    size_t n = strlen(tag);
    return x->taglen == n && !memcmp(x->tag, tag, n);
}

const bvox__xml_attr *bvox__xml_attr_get(const bvox__xml *x, const char *name)
{
    size_t n = strlen(name);
    for (int i = 0; i < x->nattrs; i++)
        if (x->attrs[i].nlen == n && !memcmp(x->attrs[i].name, name, n)) return &x->attrs[i];
    return NULL;
}

char *bvox__xml_attr_dup(const bvox__xml *x, const bvox__xml_attr *a, bvox_status *st)
{
    *st = BVOX_OK;
    /* a character reference (>= 3 bytes) decodes to at most 4: +2 per & */
    size_t amps = 0;
    for (size_t i = 0; i < a->vlen; i++) amps += a->value[i] == '&';
    char *out = bvox__mem_alloc(a->vlen + 2 * amps + 1);
    if (!out) {
        *st = bvox__fail(BVOX_ENOMEM, "%s: out of memory for an attribute", x->name);
        return NULL;
    }
    size_t n = 0;
    for (size_t i = 0; i < a->vlen; i++) {
        char c = a->value[i];
        if (c != '&') {
            out[n++] = c;
            continue;
        }
        const char *semi = memchr(a->value + i, ';', a->vlen - i);
        size_t len = semi ? (size_t)(semi - (a->value + i)) + 1 : 0;
        const char *e = a->value + i;
        static const struct { const char *name; char c; } ents[] = {
            {"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool done = false;
        for (size_t k = 0; k < 5 && !done; k++)
            if (len == strlen(ents[k].name) && !memcmp(e, ents[k].name, len)) {
                out[n++] = ents[k].c;
                done = true;
            }
        if (!done && len >= 4 && e[1] == '#') {
            unsigned long v = 0;
            bool hex = e[2] == 'x' || e[2] == 'X', ok = true;
            size_t digits = 0;
            for (size_t k = hex ? 3 : 2; k + 1 < len; k++, digits++) {
                char d = e[k];
                int dv = d >= '0' && d <= '9' ? d - '0'
                         : hex && d >= 'a' && d <= 'f' ? d - 'a' + 10
                         : hex && d >= 'A' && d <= 'F' ? d - 'A' + 10
                                                       : -1;
                if (dv < 0 || v > 0x10FFFF) ok = false;
                else v = v * (hex ? 16 : 10) + (unsigned long)dv;
            }
            if (ok && digits > 0 && v > 0 && v <= 0x10FFFF) {
                bvox__put_utf8(out, &n, (uint32_t)v);
                done = true;
            }
        }
        if (!done) {
            free(out);
            *st = bvox__xml_fail(x, e, "unknown entity or bad character reference in attribute %.*s",
                           (int)a->nlen, a->name);
            return NULL;
        }
        i += len - 1;
    }
    out[n] = '\0';
    return out;
}
