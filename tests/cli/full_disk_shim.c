/* SPDX-License-Identifier: MIT */
/* full_disk_shim.c: an LD_PRELOAD library for the CLI tests that stands in for a full disk
 * without mounting one: a file opened for writing whose name ends with $SABLIER_TEST_FULL (e.g.
 * "energy.csv.tmp") is /dev/full instead, so its writes fail with ENOSPC as on a full disk. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int open(const char *path, int flags, ...);
FILE *fopen(const char *path, const char *mode);

static int full(const char *path)
{
    const char *suffix = getenv("SABLIER_TEST_FULL");
    size_t n = path ? strlen(path) : 0, m = suffix ? strlen(suffix) : 0;
    return m > 0 && n >= m && strcmp(path + n - m, suffix) == 0;
}

typedef int (*OpenFn)(const char *, int, ...);
typedef FILE *(*FopenFn)(const char *, const char *);

static int shim_open(const char *name, const char *path, int flags, mode_t mode)
{
    OpenFn real = (OpenFn)dlsym(RTLD_NEXT, name);
    if (full(path) && (flags & (O_WRONLY | O_RDWR)))
        return real("/dev/full", O_WRONLY | (flags & O_CLOEXEC));
    return real(path, flags, mode);
}

static FILE *shim_fopen(const char *name, const char *path, const char *mode)
{
    FopenFn real = (FopenFn)dlsym(RTLD_NEXT, name);
    return real(full(path) && mode[0] != 'r' ? "/dev/full" : path, mode);
}

static mode_t mode_of(int flags, va_list args)
{
    return (flags & O_CREAT) ? (mode_t)va_arg(args, int) : 0;
}

int open(const char *path, int flags, ...)
{
    va_list args;
    va_start(args, flags);
    mode_t mode = mode_of(flags, args);
    va_end(args);
    return shim_open("open", path, flags, mode);
}

FILE *fopen(const char *path, const char *mode)
{
    return shim_fopen("fopen", path, mode);
}

/* the 64-bit names are the same calls on a 64-bit system */
int open64(const char *path, int flags, ...) __attribute__((alias("open")));
FILE *fopen64(const char *path, const char *mode) __attribute__((alias("fopen")));
