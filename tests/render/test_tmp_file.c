/* SPDX-License-Identifier: MIT */
/* test_tmp_file.c: the PNG and PDF/SVG writers finish through render_tmp_commit. A write whose
 * rename fails (PATH is a non-empty folder) returns -1 with the reason, leaves no PATH.tmp and
 * does not touch what stands at PATH. */
#include "test.h"

#include "render/internal.h"
#include "render/render_cairo_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

static void draw_nothing(cairo_t *cr, void *context)
{
    (void)context;
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
}

/* A fresh folder under /tmp holding NAME/keep for each name (NULL-ended). */
static int fresh_dir(char *dir, size_t size, const char *const *names)
{
    snprintf(dir, size, "/tmp/sablier_test_tmp_file_%ld", (long)getpid());
    char path[512];
    snprintf(path, sizeof path, "rm -rf '%s'", dir);
    if (system(path) != 0 || mkdir(dir, 0777) != 0)
        return -1;
    for (; *names; ++names) {
        snprintf(path, sizeof path, "%s/%s", dir, *names);
        if (mkdir(path, 0777) != 0)
            return -1;
        snprintf(path, sizeof path, "%s/%s/keep", dir, *names);
        FILE *f = fopen(path, "w");
        if (!f || fclose(f) != 0)
            return -1;
    }
    return 0;
}

static int exists(const char *dir, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return access(path, F_OK) == 0;
}

/* The helpers themselves: PATH.tmp, a kept write, a dropped write. */
static int commit_and_drop(void)
{
    static const char *const none[] = {NULL};
    char dir[256], path[512], err[256] = "";
    TEST_ASSERT(fresh_dir(dir, sizeof dir, none) == 0);
    snprintf(path, sizeof path, "%s/a.txt", dir);
    char *tmp = render_tmp_name(path, err, sizeof err);
    TEST_ASSERT(tmp && strlen(tmp) == strlen(path) + 4 && strcmp(tmp + strlen(path), ".tmp") == 0);
    FILE *f = fopen(tmp, "w");
    TEST_ASSERT(f && fclose(f) == 0);
    TEST_ASSERT(render_tmp_commit(tmp, path, 1, err, sizeof err) == 0);
    TEST_ASSERT(exists(dir, "a.txt") && !exists(dir, "a.txt.tmp"));
    tmp = render_tmp_name(path, err, sizeof err);
    TEST_ASSERT(tmp);
    f = fopen(tmp, "w");
    TEST_ASSERT(f && fputs("half", f) >= 0 && fclose(f) == 0);
    snprintf(err, sizeof err, "the caller's message");
    TEST_ASSERT(render_tmp_commit(tmp, path, 0, err, sizeof err) == -1);
    TEST_ASSERT(strcmp(err, "the caller's message") == 0);
    TEST_ASSERT(!exists(dir, "a.txt.tmp"));
    f = fopen(path, "r");
    TEST_ASSERT(f && fgetc(f) == EOF); /* the earlier, empty a.txt */
    fclose(f);
    snprintf(path, sizeof path, "rm -rf '%s'", dir);
    TEST_ASSERT(system(path) == 0);
    return 0;
}

static int folder_refused(void)
{
    static const char *const blocked[] = {"a.png", "a.svg", "a.pdf", NULL};
    char dir[256], path[512], err[512] = "";
    TEST_ASSERT(fresh_dir(dir, sizeof dir, blocked) == 0);
    RenderImage image;
    TEST_ASSERT(render_image_alloc(&image, 8, 4, RENDER_PIXEL_RGBA) == 0);
    snprintf(path, sizeof path, "%s/a.png", dir);
    TEST_ASSERT(render_png_write(&image, path, NULL, err, sizeof err) == -1);
    render_image_free(&image);
    /* a folder at the output's name is refused before anything is written (sim_open_output) */
    TEST_ASSERT(strstr(err, "/a.png: it is a folder"));
    TEST_ASSERT(!exists(dir, "a.png.tmp") && exists(dir, "a.png/keep"));
    for (int k = 0; k < 2; ++k) {
        const char *name = k ? "a.pdf" : "a.svg";
        snprintf(path, sizeof path, "%s/%s", dir, name);
        err[0] = '\0';
        TEST_ASSERT(render_cairo_write(path, 20, 10, draw_nothing, NULL, NULL, err, sizeof err) ==
                    -1);
        TEST_ASSERT(strstr(err, "it is a folder"));
        char tmp[64], keep[64];
        snprintf(tmp, sizeof tmp, "%s.tmp", name);
        snprintf(keep, sizeof keep, "%s/keep", name);
        TEST_ASSERT(!exists(dir, tmp) && exists(dir, keep));
    }
    snprintf(path, sizeof path, "rm -rf '%s'", dir);
    TEST_ASSERT(system(path) == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(commit_and_drop), TEST_CASE(folder_refused))
