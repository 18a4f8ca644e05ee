/* SPDX-License-Identifier: MIT */
/* test.h: sablier's tiny test harness. Each test file defines `static int name(void)` functions
 * returning 0 on success and lists them in TEST_MAIN; `prog NAME` runs one, `prog` runs all. */
#ifndef SABLIER_TEST_H
#define SABLIER_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TEST_ASSERT(cond)                                                                          \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: assertion failed: %s\n", __FILE__, __LINE__, #cond);           \
            return 1;                                                                              \
        }                                                                                          \
    } while (0)

/* |actual - expected| <= tol, printing all three on failure. */
#define TEST_NEAR(actual, expected, tol)                                                           \
    do {                                                                                           \
        double test_a_ = (actual), test_e_ = (expected), test_t_ = (tol);                          \
        if (!(fabs(test_a_ - test_e_) <= test_t_)) {                                               \
            fprintf(stderr, "%s:%d: %s = %.17g, expected %.17g within %.3g (off by %.3g)\n",       \
                    __FILE__, __LINE__, #actual, test_a_, test_e_, test_t_,                        \
                    fabs(test_a_ - test_e_));                                                      \
            return 1;                                                                              \
        }                                                                                          \
    } while (0)

/* Relative closeness: |a - e| <= rel * |e|. */
#define TEST_REL(actual, expected, rel)                                                            \
    TEST_NEAR(actual, expected, fabs((double)(expected)) * (rel))

/* The whole file, malloc'd and NUL-ended (NULL when unreadable); its length in *size when size is
 * not NULL. The test frees it. */
static inline char *test_read_file(const char *path, long *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *data = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (data = malloc((size_t)n + 1)) != NULL) {
        if (fread(data, 1, (size_t)n, f) == (size_t)n) {
            data[n] = '\0';
        } else {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    if (data && size)
        *size = n;
    return data;
}

/* 1 when the two files hold the same bytes (both readable). */
static inline int test_same_bytes(const char *a, const char *b)
{
    long na = 0, nb = 0;
    unsigned char *pa = (unsigned char *)test_read_file(a, &na),
                  *pb = (unsigned char *)test_read_file(b, &nb);
    int same = pa && pb && na == nb && memcmp(pa, pb, (size_t)na) == 0;
    free(pa);
    free(pb);
    return same;
}

/* A new empty file for a test's output, named /tmp/sablier-test-XXXXXX made unique by mkstemp,
 * in path (32 bytes). 0, or -1 when it cannot be made. The test removes it. */
static inline int test_tmp_file(char path[32])
{
    strcpy(path, "/tmp/sablier-test-XXXXXX");
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL; /* fclose closes fd (no unistd.h here) */
    return f && fclose(f) == 0 ? 0 : -1;
}

typedef struct TestCase {
    const char *name;
    int (*run)(void);
} TestCase;

#define TEST_CASE(fn)                                                                              \
    {                                                                                              \
#fn, fn                                                                                    \
    }

/* Runs the named case (argv[1]) or all; prints "N passed, N failed". */
#define TEST_MAIN(...)                                                                             \
    int main(int argc, char **argv)                                                                \
    {                                                                                              \
        static const TestCase cases[] = {__VA_ARGS__};                                             \
        int passed = 0, failed = 0, found = 0;                                                     \
        for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {                              \
            if (argc > 1 && strcmp(argv[1], cases[k].name) != 0)                                   \
                continue;                                                                          \
            found = 1;                                                                             \
            int rc = cases[k].run();                                                               \
            printf("%s %s\n", rc == 0 ? "ok  " : "FAIL", cases[k].name);                           \
            if (rc == 0)                                                                           \
                ++passed;                                                                          \
            else                                                                                   \
                ++failed;                                                                          \
        }                                                                                          \
        if (!found) {                                                                              \
            fprintf(stderr, "no test named %s\n", argc > 1 ? argv[1] : "(none)");                  \
            return 2;                                                                              \
        }                                                                                          \
        printf("%d passed, %d failed\n", passed, failed);                                          \
        return failed ? 1 : 0;                                                                     \
    }

#endif
