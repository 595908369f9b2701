/* test_json.c — src/common/json.c and strbuf.c: the one JSON writer (commas,
 * nesting, escapes, numbers) into a buffer and into a FILE, byte for byte
 * against hand-written answers, and the text buffer it can write into. */
#include "harness.h"
#include "common/json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A document using every call, written through j. */
static void write_doc(bvox__json *j)
{
    bvox__json_begin_object(j);
    bvox__json_key(j, "a");
    bvox__json_int(j, -12);
    bvox__json_key(j, "list");
    bvox__json_begin_array(j);
    bvox__json_double(j, 0.1);
    bvox__json_double(j, -0.0);
    bvox__json_double(j, INFINITY);
    bvox__json_double(j, 1e300);
    bvox__json_bool(j, 1);
    bvox__json_bool(j, 0);
    bvox__json_null(j);
    bvox__json_string(j, NULL);
    bvox__json_begin_object(j);
    bvox__json_end_object(j);
    bvox__json_end_array(j);
    bvox__json_key(j, "d");
    const double d[3] = {1, 2.5, NAN};
    bvox__json_double_array(j, d, 3);
    bvox__json_key(j, "i");
    const int64_t i[2] = {INT64_MIN, 7};
    bvox__json_int_array(j, i, 2);
    bvox__json_end_object(j);
}

static const char *const doc =
    "{\"a\":-12,\"list\":[0.1,0,null,1e+300,true,false,null,null,{}],"
    "\"d\":[1,2.5,null],\"i\":[-9223372036854775808,7]}";

TEST(writer_into_buffer)
{
    bvox__strbuf b = {0};
    bvox__json j;
    bvox__json_init_buffer(&j, &b);
    write_doc(&j);
    CHECK(!b.failed);
    CHECK(strcmp(b.data, doc) == 0);
    CHECK_EQ(b.len, strlen(doc));
    bvox__sb_free(&b);
    return 0;
}

TEST(writer_into_file_same_bytes)
{
    FILE *f = tmpfile();
    CHECK(f != NULL);
    bvox__json j;
    bvox__json_init(&j, f);
    write_doc(&j);
    long n = ftell(f);
    rewind(f);
    char got[512] = {0};
    CHECK_EQ((size_t)n, fread(got, 1, sizeof got - 1, f));
    fclose(f);
    CHECK(strcmp(got, doc) == 0);
    return 0;
}

TEST(string_escapes)
{
    /* the dialect of json.h: short forms, \u00XX for other controls and DEL,
     * UTF-8 bytes unchanged */
    bvox__strbuf b = {0};
    bvox__sb_json_string(&b, "q\" b\\ \b\f\n\r\t \x01\x1f\x7f \xc3\xa9/");
    CHECK(strcmp(b.data, "\"q\\\" b\\\\ \\b\\f\\n\\r\\t \\u0001\\u001f\\u007f \xc3\xa9/\"") == 0);
    bvox__sb_free(&b);
    bvox__json j;
    bvox__json_init_buffer(&j, &b);
    bvox__json_begin_object(&j);
    bvox__json_key(&j, "k\n");
    bvox__json_string(&j, "");
    bvox__json_key(&j, "x");
    bvox__json_string(&j, "tab\there");
    bvox__json_end_object(&j);
    CHECK(strcmp(b.data, "{\"k\\n\":\"\",\"x\":\"tab\\there\"}") == 0);
    bvox__sb_free(&b);
    return 0;
}

TEST(shortest_round_trip_doubles)
{
    const double v[] = {0.1, 1.0 / 3, 2.0 / 3, 1e-310, 123456789.125, -2.5e-7, 0.3};
    /* the first of 15, 16, 17 digits that reads back: a subnormal keeps 15
     * digits although "1e-310" would do */
    const char *want[] = {"0.1", "0.3333333333333333", "0.6666666666666666",
                          "9.99999999999997e-311",
                          "123456789.125", "-2.5e-07", "0.3"};
    for (int i = 0; i < 7; i++) {
        char buf[40];
        bvox__format_double(buf, sizeof buf, v[i]);
        CHECK(strcmp(buf, want[i]) == 0);
        CHECK(strtod(buf, NULL) == v[i]);
    }
    return 0;
}

TEST(strbuf_grows_and_formats)
{
    bvox__strbuf b = {0};
    for (int i = 0; i < 1000; i++) bvox__sb_puts(&b, "0123456789"); /* past 4096 */
    CHECK_EQ(b.len, 10000);
    CHECK(b.data[b.len] == '\0');
    CHECK(memcmp(b.data + 9990, "0123456789", 10) == 0);
    bvox__sb_free(&b);
    CHECK(b.data == NULL && b.len == 0);

    char big[2000];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    bvox__sb_printf(&b, "<%s|%d>", big, 42); /* longer than printf's stack buffer */
    CHECK_EQ(b.len, 1999 + 5);
    CHECK(strcmp(b.data + 2000, "|42>") == 0);
    bvox__sb_free(&b);

    bvox__sb_double(&b, 12);
    bvox__sb_puts(&b, " ");
    bvox__sb_double(&b, -0.0);
    bvox__sb_puts(&b, " ");
    bvox__sb_double(&b, -3e14);
    bvox__sb_puts(&b, " ");
    bvox__sb_double(&b, 0.1);
    bvox__sb_puts(&b, " ");
    bvox__sb_double(&b, NAN); /* the model holds only finite values: 0 */
    CHECK(strcmp(b.data, "12 0 -300000000000000 0.1 0") == 0);
    bvox__sb_free(&b);
    return 0;
}
