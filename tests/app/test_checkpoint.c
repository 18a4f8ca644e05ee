/* SPDX-License-Identifier: MIT */
/* test_checkpoint.c: the sections of a checkpoint record (app/base/checkpoint.h). Numbers written
 * with app_checkpoint_put read back to the bit (subnormals, signed zero, infinities, integers up to
 * 2^53; NaN stays NaN), a key is never confused with a longer one that starts like it, a missing
 * or short line is refused; an append file is continued at its recorded length, from PATH.tmp when
 * a killed run left it there, else from PATH. */
#include "test.h"

#include "base/checkpoint.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The record `text` as written to a temporary file (put writes to a FILE). */
static char *written(void (*write)(FILE *))
{
    char path[32];
    if (test_tmp_file(path) != 0)
        return NULL;
    FILE *f = fopen(path, "w");
    if (!f)
        return NULL;
    write(f);
    fclose(f);
    char *text = test_read_file(path, NULL);
    remove(path);
    return text;
}

static const double NUMBERS[8] = {
    0.1, -0.0, 4.9406564584124654e-324, 1e308, 9007199254740992.0, -3.0, 0.0, 1.0 / 3.0};

static void write_numbers(FILE *f)
{
    double v[8];
    memcpy(v, NUMBERS, sizeof v);
    app_checkpoint_put(f, "pf_times", v, 2);
    app_checkpoint_put(f, "pf", v, 8);
    const double odd[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    app_checkpoint_put(f, "odd", odd, 3);
    app_checkpoint_put(f, "none", v, 0);
}

static int numbers_exact(void)
{
    char *text = written(write_numbers);
    TEST_ASSERT(text);
    double v[8], odd[3];
    TEST_ASSERT(app_checkpoint_take(text, "pf", v, 8) == 0); /* not pf_times, the line before */
    TEST_ASSERT(memcmp(v, NUMBERS, sizeof v) == 0);
    TEST_ASSERT(app_checkpoint_take(text, "pf_times", v, 2) == 0 && v[0] == 0.1);
    TEST_ASSERT(app_checkpoint_take(text, "odd", odd, 3) == 0);
    TEST_ASSERT(isnan(odd[0]) && odd[1] == (double)INFINITY && odd[2] == -(double)INFINITY);
    TEST_ASSERT(app_checkpoint_take(text, "none", v, 0) == 0);
    TEST_ASSERT(app_checkpoint_take(text, "none", v, 1) != 0);     /* short */
    TEST_ASSERT(app_checkpoint_take(text, "pf_times", v, 3) != 0); /* short */
    TEST_ASSERT(app_checkpoint_take(text, "p", v, 1) != 0);        /* no such key */
    TEST_ASSERT(app_checkpoint_take(NULL, "pf", v, 1) != 0);
    free(text);
    return 0;
}

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    return f && fputs(text, f) >= 0 && fclose(f) == 0 ? 0 : -1;
}

/* DIR/rows.csv continued at 8 bytes: from rows.csv, then from a longer rows.csv.tmp. */
static int append_file_continued(void)
{
    char dir[] = "/tmp/sablier-test-ckpt-XXXXXX", path[64], tmp[72], record[64];
    TEST_ASSERT(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/rows.csv", dir);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    snprintf(record, sizeof record, "x 1\nfile rows.csv.old 2\nfile rows.csv 8\n");
    TEST_ASSERT(write_text(path, "t,v\n1,2\n3,4\njunk\n") == 0);
    FILE *f = fopen(tmp, "w"); /* what a begin hook opened afresh */
    TEST_ASSERT(f && fputs("t,v\n", f) >= 0);
    TEST_ASSERT(app_checkpoint_reopen(record, path, &f) == 0 && f);
    fputs("5,6\n", f);
    TEST_ASSERT(fclose(f) == 0);
    char *text = test_read_file(tmp, NULL);
    TEST_ASSERT(text && strcmp(text, "t,v\n1,2\n5,6\n") == 0);
    free(text);
    /* a killed run: rows.csv.tmp holds the bytes, rows.csv is older; kept before reopening */
    TEST_ASSERT(write_text(tmp, "t,v\n7,8\n9,9\n") == 0);
    TEST_ASSERT(write_text(path, "t,v\n") == 0);
    app_checkpoint_keep_files(record, dir);
    TEST_ASSERT(access(tmp, F_OK) != 0);
    f = fopen(tmp, "w");
    TEST_ASSERT(f && app_checkpoint_reopen(record, path, &f) == 0);
    TEST_ASSERT(fclose(f) == 0);
    text = test_read_file(tmp, NULL);
    TEST_ASSERT(text && strcmp(text, "t,v\n7,8\n") == 0);
    free(text);
    /* no record of the file, or a file shorter than recorded: refused */
    f = NULL;
    TEST_ASSERT(app_checkpoint_reopen("x 1\n", path, &f) != 0 && !f);
    TEST_ASSERT(app_checkpoint_reopen("file rows.csv 999\n", path, &f) != 0 && !f);
    remove(tmp);
    remove(path);
    TEST_ASSERT(rmdir(dir) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(numbers_exact), TEST_CASE(append_file_continued))
