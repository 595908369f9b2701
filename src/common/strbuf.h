/*
 * strbuf.h — a growable text buffer, and the shortest round-trip text of a
 * double (shared by the buffer, the JSON writer and the contour writers).
 */
#ifndef BVOX_COMMON_STRBUF_H
#define BVOX_COMMON_STRBUF_H

#include <stdbool.h>
#include <stddef.h>

/* A growable text buffer, always NUL-terminated once non-empty, its capacity
 * charged to the memory budget until bvox__sb_free. On an allocation failure
 * or the budget reached `failed` is set and further appends are ignored;
 * check it once at the end. Zero-initialise to start. */
typedef struct bvox__strbuf {
    char *data;
    size_t len, cap;  /* cap is charged to the memory budget (--max-memory) */
    bool failed;
    bool over_budget; /* failed because the budget was reached */
} bvox__strbuf;
void bvox__sb_append(bvox__strbuf *b, const char *s, size_t n);
void bvox__sb_puts(bvox__strbuf *b, const char *s);
void bvox__sb_printf(bvox__strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A finite v as bvox__format_double writes it, integers below 1e15 without
 * printf; a non-finite v as 0 and -0 as 0. */
void bvox__sb_double(bvox__strbuf *b, double v);
void bvox__sb_free(bvox__strbuf *b);

/* The shortest "%.{15,16,17}g" text of a finite v that reads back as v. */
void bvox__format_double(char *buf, size_t size, double v);

#endif
