/*
 * json.h — a minimal streaming JSON writer for the commands' --json output:
 * commas and nesting are tracked for the caller, strings are escaped, numbers
 * are written in their shortest round-trip form, and a non-finite double
 * (which JSON cannot hold) becomes null.
 */
#ifndef BVOX_CLI_JSON_H
#define BVOX_CLI_JSON_H

#include <stdint.h>
#include <stdio.h>

#define CLI_JSON_MAX_DEPTH 32

typedef struct cli_json {
    FILE *f;
    int depth;
    int count[CLI_JSON_MAX_DEPTH]; /* values written so far at each level */
    int after_key;                 /* a key was written: no comma before the value */
} cli_json;

void cli_json_init(cli_json *j, FILE *f);
void cli_json_begin_object(cli_json *j);
void cli_json_end_object(cli_json *j);
void cli_json_begin_array(cli_json *j);
void cli_json_end_array(cli_json *j);
/* Inside an object: the key of the next value. */
void cli_json_key(cli_json *j, const char *key);
void cli_json_string(cli_json *j, const char *s); /* NULL writes null */
void cli_json_double(cli_json *j, double v);
void cli_json_int(cli_json *j, int64_t v);
void cli_json_bool(cli_json *j, int v);
void cli_json_null(cli_json *j);
/* Convenience: an array of n doubles / ints. */
void cli_json_double_array(cli_json *j, const double *v, int n);
void cli_json_int_array(cli_json *j, const int64_t *v, int n);

/* The shortest "%.{15,16,17}g" text of a finite v that reads back as v. */
void cli_json_format_double(char *buf, size_t size, double v);

#endif
