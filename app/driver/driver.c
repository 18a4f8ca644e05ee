/* SPDX-License-Identifier: MIT */
/* driver.c: the skeleton every multi-run command shares (driver.h). */
#include "driver/driver.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* Empty arguments: no scene, no --out, no sets, --jobs 2. */
static void driver_args_init(AppDriverArgs *a)
{
    memset(a, 0, sizeof *a);
    a->jobs = 2;
}

/* --set or --unset at argv[*i]: 1, 0 when neither, -1 after a message (with the command's own
 * usage message when it has one). */
static int driver_set(const AppDriverSpec *s, AppDriverArgs *a, int argc, char **argv, int *i)
{
    const int max = s->sets_max > 0 ? s->sets_max : APP_MAX_SETS;
    const int m = app_set_option(argc, argv, i, a->sets, &a->set_count, max);
    if (m < 0 && s->set_error)
        app_usage_error(s->usage, s->set_error, NULL);
    return m;
}

static int driver_vary(const AppDriverSpec *s, AppDriverArgs *a, const char *value)
{
    if (s->vary_max == 1) {
        a->vary[0] = value;
        a->vary_count = 1;
        return 1;
    }
    if (a->vary_count >= s->vary_max || a->vary_count >= APP_DRIVER_VARY_MAX) {
        app_usage_error(s->usage, "too many --vary options", NULL);
        return -1;
    }
    a->vary[a->vary_count++] = value;
    return 1;
}

/* The common option at argv[*i] into *a (*i moves past its value): 1 when it was one, 0 when
 * argv[*i] is not a common option, -1 on a usage error (message and usage on stderr). */
static int driver_option(const AppDriverSpec *s, int argc, char **argv, int *i, AppDriverArgs *a)
{
    const char *value = NULL;
    int m;
    if ((m = app_option(argc, argv, i, "--out", &value)) != 0) {
        if (m < 0)
            return -1;
        a->out = value;
        return 1;
    }
    if ((m = driver_set(s, a, argc, argv, i)) != 0)
        return m;
    if (s->vary_max > 0 && (m = app_option(argc, argv, i, "--vary", &value)) != 0)
        return m < 0 ? -1 : driver_vary(s, a, value);
    if ((m = app_option(argc, argv, i, "--jobs", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 1, s->jobs_max, &a->jobs) < 0) {
            char message[64];
            snprintf(message, sizeof message, "--jobs needs a count in [1, %ld], got", s->jobs_max);
            app_usage_error(s->usage, message, m < 0 ? "nothing" : value);
            return -1;
        }
        return 1;
    }
    if (!s->no_quiet && (strcmp(argv[*i], "--quiet") == 0 || strcmp(argv[*i], "-q") == 0)) {
        a->quiet = 1;
        return 1;
    }
    if (strcmp(argv[*i], "--resume") == 0) {
        a->resume = 1;
        return 1;
    }
    return 0;
}

/* A word no option took: the scene (once), or an unknown option. 0, or 2 after a usage error. */
static int driver_scene(const AppDriverSpec *s, const char *arg, AppDriverArgs *a)
{
    if (s->extra_error && a->scene && !(arg[0] == '-' && arg[1]))
        return app_usage_error(s->usage, s->extra_error, arg);
    return app_scene_argument(s->usage, arg, &a->scene);
}

int app_driver_parse(const AppDriverSpec *s, int argc, char **argv, AppDriverArgs *a,
                     int (*own)(void *ctx, int argc, char **argv, int *i), void *ctx)
{
    driver_args_init(a);
    for (int i = 2; i < argc; ++i) {
        int m = driver_option(s, argc, argv, &i, a);
        if (m < 0)
            return 2;
        if (m == 0 && own)
            m = own(ctx, argc, argv, &i);
        if (m > 1)
            return m;
        if (m == 0 && driver_scene(s, argv[i], a) != 0)
            return 2;
    }
    return a->scene ? 0 : app_usage_error(s->usage, s->missing, NULL);
}

void app_driver_default_out(const char *prefix, const char *scene_path, char *out, size_t size)
{
    const char *base = strrchr(scene_path, '/') ? strrchr(scene_path, '/') + 1 : scene_path;
    snprintf(out, size, "out/%s-%.*s", prefix, (int)strcspn(base, "."), base);
}

int app_driver_sets_add(AppDriverSets *s, const char *const *sets, int n)
{
    for (int k = 0; n < 0 ? sets && sets[k] : k < n; ++k) {
        if (s->count >= (int)(sizeof s->sets / sizeof s->sets[0]))
            return -1;
        s->sets[s->count++] = sets[k];
    }
    return 0;
}

int app_driver_sets_printf(AppDriverSets *s, const char *format, ...)
{
    if (s->text_count >= (int)(sizeof s->text / sizeof s->text[0]))
        return -1;
    char *text = s->text[s->text_count++];
    va_list ap;
    va_start(ap, format);
    vsnprintf(text, sizeof s->text[0], format, ap);
    va_end(ap);
    const char *one[1] = {text};
    return app_driver_sets_add(s, one, 1);
}

Scene *app_driver_load(const char *path, const AppDriverSets *sets, const AppExperiment *family)
{
    char err[4096] = "";
    Scene *scene = scene_load(path, sets->sets, sets->count, err, sizeof err);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return NULL;
    }
    if (family && !scene_experiment_state(scene, family)) {
        fprintf(stderr, "%s:1: %s: the scene has no `%s` group\n", path, family->name,
                family->group);
        scene_free(scene);
        return NULL;
    }
    return scene;
}

int app_driver_run(Scene *scene, const char *dir, const AppRender *render)
{
    AppRunOptions ro = app_run_options_default();
    ro.out_dir = dir;
    ro.quiet = 1;
    ro.render = render;
    ro.render_off = render == NULL; /* no movies asked for: no "not built" warning */
    return app_run(scene, &ro);
}

int app_driver_member(const char *path, const AppDriverSets *sets, const AppExperiment *family,
                      const char *dir, const AppRender *render)
{
    Scene *scene = app_driver_load(path, sets, family);
    if (!scene)
        return 2;
    int rc = app_driver_run(scene, dir, render);
    scene_free(scene);
    return rc;
}

static int driver_pool_run(void *ctx, int k)
{
    const AppDriverPool *p = ctx;
    return p->run(p->ctx, k);
}

static int driver_pool_start(void *ctx, int k)
{
    const AppDriverPool *p = ctx;
    return p->start(p->ctx, k);
}

static int driver_pool_folder(void *ctx, int k, char *dir, size_t size)
{
    const AppDriverPool *p = ctx;
    return p->folder(p->ctx, k, dir, size);
}

static void driver_pool_done(void *ctx, int k, int status)
{
    AppDriverPool *p = ctx;
    if (status == APP_POOL_NOT_STARTED && p->not_started) {
        fprintf(stderr, "sablier: %s: %s: %s\n", p->command, p->not_started, strerror(errno));
        p->failed = 1;
        if (p->status)
            p->status[k] = 2;
        return;
    }
    const int forked = status != APP_POOL_NOT_STARTED;
    if (p->ended)
        status = p->ended(p->ctx, k, status);
    if (p->status)
        p->status[k] = status;
    p->failed |= status != 0;
    if (!forked) /* `ended` said why */
        return;
    p->finished += status != APP_POOL_INTERRUPTED;
    char line[1024] = "";
    if (!p->quiet && p->progress)
        p->progress(p->ctx, k, status, line, sizeof line);
    if (line[0])
        fprintf(stderr, "sablier: %s: %s\n", p->command, line);
}

int app_driver_pool_run(AppDriverPool *p)
{
    for (int k = 0; p->status && k < p->count; ++k)
        p->status[k] = -1;
    p->finished = 0;
    p->failed = 0;
    p->start_at = sim_clock_seconds(SIM_CLOCK_WALL);
    AppPool pool = {.count = p->count,
                    .jobs = (int)p->jobs,
                    .ctx = p,
                    .start = p->start ? driver_pool_start : NULL,
                    .run = driver_pool_run,
                    .done = driver_pool_done,
                    .signal_status = p->signal_status,
                    .folder = p->folder ? driver_pool_folder : NULL,
                    .resume = p->resume};
    return app_pool_run(&pool);
}

void app_driver_log_to(const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/log.txt", dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        close(fd);
    }
}
