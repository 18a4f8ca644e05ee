/* SPDX-License-Identifier: MIT */
/* test_lists.c: the one comma-list reader of the drivers (app_list_item, app_parse_numbers,
 * app_parse_key_values): an empty item (",,", a leading or trailing comma) is malformed in every
 * list (`study --widths 1,,2` once dropped it); then the rules the commands differ in: bne's
 * --vary (the first max read), sediment's --shields (>= 0, more than max malformed) and the
 * discharge study's --widths / --L lists (out-of-range values malformed). */
#include "test.h"

#include "base/util.h"

#include <math.h>
#include <string.h>

static int list_items(void)
{
    const char *list = "1,,2.5,", *item;
    size_t length;
    const char *want[] = {"1", "", "2.5", ""}; /* every comma separates two items */
    int n = 0;
    while ((item = app_list_item(&list, &length)) != NULL) {
        TEST_ASSERT(n < 4 && length == strlen(want[n]) && strncmp(item, want[n], length) == 0);
        ++n;
    }
    TEST_ASSERT(n == 4);
    list = "";
    TEST_ASSERT(app_list_item(&list, &length) != NULL && length == 0);
    TEST_ASSERT(app_list_item(&list, &length) == NULL);
    return 0;
}

static int key_values(void)
{
    char key[16];
    double v[4];
    TEST_ASSERT(app_parse_key_values("bne.gamma=2,3.5", key, sizeof key, v, 4) == 2);
    TEST_ASSERT(strcmp(key, "bne.gamma") == 0 && v[0] == 2.0 && v[1] == 3.5);
    TEST_ASSERT(app_parse_key_values("k=", key, sizeof key, v, 4) == 0);
    TEST_ASSERT(app_parse_key_values("k=1,", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("=1", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k1", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k=1,,2", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k=,1", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k=1 ,2", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k=nan", key, sizeof key, v, 4) == -1);
    TEST_ASSERT(app_parse_key_values("k=1,2,3,x", key, sizeof key, v, 2) == 2); /* first max */
    TEST_ASSERT(app_parse_key_values("a_key_too_long_here=1", key, sizeof key, v, 4) == -1);
    return 0;
}

static int shields_rule(void)
{
    static const AppNumberList how = {.min = 0.0, .exact = 1};
    double v[2];
    TEST_ASSERT(app_parse_numbers("0.1,0.8", &how, v, 2) == 2 && v[1] == 0.8);
    TEST_ASSERT(app_parse_numbers("0.1,", &how, v, 2) == -1);
    TEST_ASSERT(app_parse_numbers("", &how, v, 2) == 0);
    TEST_ASSERT(app_parse_numbers("-1", &how, v, 2) == -1);
    TEST_ASSERT(app_parse_numbers("0.1,,0.2", &how, v, 2) == -1);
    TEST_ASSERT(app_parse_numbers("1,2,3", &how, v, 2) == -1); /* more than max */
    TEST_ASSERT(app_parse_numbers("1e-400", &how, v, 2) == 1); /* underflow is a number */
    return 0;
}

static int widths_rule(void)
{
    static const AppNumberList how = {.min = -INFINITY, .strict = 1};
    double v[3];
    TEST_ASSERT(app_parse_numbers("1.5,2.5", &how, v, 3) == 2 && v[0] == 1.5 && v[1] == 2.5);
    TEST_ASSERT(app_parse_numbers("1,,2", &how, v, 3) == -1); /* was 1, 2 */
    TEST_ASSERT(app_parse_numbers(",1.5", &how, v, 3) == -1);
    TEST_ASSERT(app_parse_numbers("1.5,", &how, v, 3) == -1);
    TEST_ASSERT(app_parse_numbers("1,2,3,4", &how, v, 3) == 3); /* the first max */
    TEST_ASSERT(app_parse_numbers("1e-400", &how, v, 3) == -1);
    TEST_ASSERT(app_parse_numbers("1e999", &how, v, 3) == -1);
    TEST_ASSERT(app_parse_numbers("1,x", &how, v, 3) == -1);
    TEST_ASSERT(app_parse_numbers(",,", &how, v, 3) == -1);
    return 0;
}

TEST_MAIN(TEST_CASE(list_items), TEST_CASE(key_values), TEST_CASE(shields_rule),
          TEST_CASE(widths_rule))
