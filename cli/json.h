/*
 * json.h — the commands' --json output: the library's one JSON writer
 * (src/common/json.h), under the names the commands have always used.
 */
#ifndef BVOX_CLI_JSON_H
#define BVOX_CLI_JSON_H

#include "common/json.h"

typedef bvox__json cli_json;

#define cli_json_init bvox__json_init
#define cli_json_begin_object bvox__json_begin_object
#define cli_json_end_object bvox__json_end_object
#define cli_json_begin_array bvox__json_begin_array
#define cli_json_end_array bvox__json_end_array
#define cli_json_key bvox__json_key
#define cli_json_string bvox__json_string
#define cli_json_double bvox__json_double
#define cli_json_int bvox__json_int
#define cli_json_bool bvox__json_bool
#define cli_json_null bvox__json_null
#define cli_json_double_array bvox__json_double_array
#define cli_json_int_array bvox__json_int_array
/* The shortest "%.{15,16,17}g" text of a finite v that reads back as v. */
#define cli_json_format_double bvox__format_double

#endif
