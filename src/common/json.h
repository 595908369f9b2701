/*
 * json.h — the one JSON writer: a streaming writer that tracks commas and
 * nesting for the caller (the commands' --json output, to a FILE; or into a
 * text buffer), and the one string escaping, also used on its own by writers
 * that lay out their files by hand (contour stacks). Numbers are written in
 * their shortest round-trip form; a non-finite double (which JSON cannot
 * hold) becomes null.
 *
 * Strings: '"' and '\\' are escaped, \b \f \n \r \t by their short forms, the
 * other control characters and DEL as \u00XX; bytes >= 0x80 pass through
 * (UTF-8 text on every system we target).
 */
#ifndef BVOX_COMMON_JSON_H
#define BVOX_COMMON_JSON_H

#include "strbuf.h"

#include <stdint.h>
#include <stdio.h>

#define BVOX__JSON_MAX_DEPTH 32

typedef struct bvox__json {
    FILE *f;          /* the output: f, or ... */
    bvox__strbuf *sb; /* ... this buffer */
    int depth;
    int count[BVOX__JSON_MAX_DEPTH]; /* values written so far at each level */
    int after_key;                   /* a key was written: no comma before the value */
} bvox__json;

void bvox__json_init(bvox__json *j, FILE *f);
void bvox__json_init_buffer(bvox__json *j, bvox__strbuf *sb);
void bvox__json_begin_object(bvox__json *j);
void bvox__json_end_object(bvox__json *j);
void bvox__json_begin_array(bvox__json *j);
void bvox__json_end_array(bvox__json *j);
/* Inside an object: the key of the next value. */
void bvox__json_key(bvox__json *j, const char *key);
void bvox__json_string(bvox__json *j, const char *s); /* NULL writes null */
void bvox__json_double(bvox__json *j, double v);
void bvox__json_int(bvox__json *j, int64_t v);
void bvox__json_bool(bvox__json *j, int v);
void bvox__json_null(bvox__json *j);
/* Convenience: an array of n doubles / ints. */
void bvox__json_double_array(bvox__json *j, const double *v, int n);
void bvox__json_int_array(bvox__json *j, const int64_t *v, int n);

/* The quoted, escaped literal of s appended to b (for hand-laid-out files). */
void bvox__sb_json_string(bvox__strbuf *b, const char *s);

#endif
