/* SPDX-License-Identifier: MIT */
/* util.c: small helpers shared by the app/ modules. */
#include "base/util.h"

#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int app_series_grow(double **t, double **v, int *capacity, int initial)
{
    int grown = *capacity ? 2 * *capacity : initial;
    double *tt = realloc(*t, (size_t)grown * sizeof *tt);
    if (!tt)
        return -1;
    *t = tt;
    double *vv = realloc(*v, (size_t)grown * sizeof *vv);
    if (!vv)
        return -1;
    *v = vv;
    *capacity = grown;
    return 0;
}

int app_usage_error(const char *usage, const char *message, const char *arg)
{
    fprintf(stderr, "sablier: %s%s%s\n\n%s", message, arg ? " " : "", arg ? arg : "", usage);
    return 2;
}

int app_scene_argument(const char *usage, const char *arg, const char **scene)
{
    if (arg[0] == '-' && arg[1])
        return app_usage_error(usage, "unknown option", arg);
    if (*scene)
        return app_usage_error(usage, "one scene at a time; extra argument", arg);
    *scene = arg;
    return 0;
}

int app_option(int argc, char **argv, int *i, const char *name, const char **value)
{
    size_t n = strlen(name);
    if (strncmp(argv[*i], name, n) != 0)
        return 0;
    if (argv[*i][n] == '=') {
        *value = argv[*i] + n + 1;
        return 1;
    }
    if (argv[*i][n] != '\0')
        return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "sablier: %s needs a value\n", name);
        *value = NULL;
        return -1;
    }
    *value = argv[++*i];
    return 1;
}

/* PATH.tmp in a heap buffer (paths have no fixed bound here). */
static char *tmp_name(const char *path)
{
    size_t n = strlen(path) + 5;
    char *tmp = malloc(n);
    if (tmp)
        snprintf(tmp, n, "%s.tmp", path);
    return tmp;
}

FILE *app_tmp_open(const char *path, const char *header)
{
    FILE *f = sim_open_output(path, NULL);
    if (f && header)
        fprintf(f, "%s\n", header);
    return f;
}

/* The outputs this process committed, by the paths they were committed as (app_output_note). */
static struct {
    char **paths;
    int count, capacity;
} committed;

void app_output_note(const char *path)
{
    if (committed.count == committed.capacity) {
        int capacity = committed.capacity ? 2 * committed.capacity : 64;
        char **grown = realloc(committed.paths, (size_t)capacity * sizeof *grown);
        if (!grown)
            return; /* the manifest then misses it: the next run leaves it, never the reverse */
        committed.paths = grown;
        committed.capacity = capacity;
    }
    if ((committed.paths[committed.count] = strdup(path)) != NULL)
        committed.count++;
}

const char *app_output_committed(int k)
{
    return k >= 0 && k < committed.count ? committed.paths[k] : NULL;
}

static int out_of_space; /* a write failed with ENOSPC or EDQUOT */

static void note_write_error(void)
{
    if (errno == ENOSPC || errno == EDQUOT)
        out_of_space = 1;
}

int app_out_of_space(void)
{
    return out_of_space;
}

int app_failed_for_space(const char *message)
{
    if (errno == ENOSPC || errno == EDQUOT)
        out_of_space = 1;
    return out_of_space ||
           (message && (strstr(message, strerror(ENOSPC)) || strstr(message, strerror(EDQUOT))));
}

int app_tmp_commit(FILE **file, const char *path)
{
    if (!*file)
        return 0;
    /* a write that failed earlier (ENOSPC while the buffer was flushed) leaves the stream's
     * error flag: such a file is truncated and must not get its final name */
    int ok = !ferror(*file);
    ok = fclose(*file) == 0 && ok;
    if (!ok)
        note_write_error();
    *file = NULL;
    char *tmp = tmp_name(path);
    if (!tmp)
        return -1;
    if (!ok || rename(tmp, path) != 0) {
        remove(tmp);
        ok = 0;
    }
    free(tmp);
    if (ok)
        app_output_note(path);
    return ok ? 0 : -1;
}

void app_tmp_discard(FILE **file, const char *path)
{
    if (!*file)
        return;
    fclose(*file);
    *file = NULL;
    char *tmp = tmp_name(path);
    if (tmp)
        remove(tmp);
    free(tmp);
}

int app_write_atomic(const char *path, const char *text)
{
    FILE *f = app_tmp_open(path, NULL);
    if (!f)
        return -1;
    int ok = fputs(text, f) >= 0;
    return app_tmp_commit(&f, path) == 0 && ok ? 0 : -1;
}

int app_state_save(SimWorld *world, const char *path, SimError *error)
{
    if (sim_world_save(world, path, error) != SIM_OK)
        return -1;
    app_output_note(path);
    return 0;
}

int app_set_option(int argc, char **argv, int *i, const char **sets, int *count, int max)
{
    const char *value;
    int m = app_option(argc, argv, i, "--set", &value), unset = 0;
    if (m == 0)
        unset = (m = app_option(argc, argv, i, "--unset", &value)) != 0;
    if (m <= 0)
        return m;
    if (!unset && !strchr(value, '=')) {
        fprintf(stderr, "sablier: --set %s: expected KEY=VALUE (--unset KEY removes a key)\n",
                value);
        return -1;
    }
    if (unset && (!*value || strchr(value, '='))) {
        fprintf(stderr, "sablier: --unset %s: expected a KEY alone, without `=`\n", value);
        return -1;
    }
    if (*count >= max) {
        fprintf(stderr, "sablier: at most %d --set and --unset options\n", max);
        return -1;
    }
    sets[(*count)++] = value;
    return 1;
}

const char *app_set_option_name(const char *entry)
{
    return strchr(entry, '=') ? "--set" : "--unset";
}

int app_parse_count(const char *text, long min, long max, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

int app_parse_key_values(const char *text, char *key, size_t key_size, double *values, int max)
{
    const char *eq = text ? strchr(text, '=') : NULL;
    if (!eq || eq == text || (size_t)(eq - text) >= key_size)
        return -1;
    snprintf(key, key_size, "%.*s", (int)(eq - text), text);
    static const AppNumberList how = {.min = -INFINITY};
    return app_parse_numbers(eq + 1, &how, values, max);
}

const char *app_list_item(const char **list, size_t *length)
{
    const char *item = *list;
    if (!item)
        return NULL;
    size_t n = strcspn(item, ",");
    *length = n;
    *list = item[n] == ',' ? item + n + 1 : NULL;
    return item;
}

int app_parse_numbers(const char *text, const AppNumberList *how, double *values, int max)
{
    int n = 0;
    size_t length;
    if (!text || !*text)
        return 0;
    for (const char *item; (item = app_list_item(&text, &length)) != NULL;) {
        if (length == 0)
            return -1;
        if (n == max)
            return how->exact ? -1 : n;
        char *end;
        errno = 0;
        double v = strtod(item, &end);
        if (end == item || end != item + length || !isfinite(v) || v < how->min ||
            (how->strict && errno))
            return -1;
        values[n++] = v;
    }
    return n;
}

int app_make_dirs(const char *path)
{
    char buffer[APP_PATH_MAX + 2 * APP_NAME_MAX]; /* the longest output path (run.c) */
    if (strlen(path) >= sizeof buffer || !path[0])
        return -1;
    strcpy(buffer, path);
    for (char *p = buffer + 1; *p; ++p) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buffer, 0777) != 0 && errno != EEXIST)
            return -1;
        *p = '/';
    }
    if (mkdir(buffer, 0777) != 0 && errno != EEXIST)
        return -1;
    struct stat st;
    return stat(buffer, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
}

/* What differs between a checkpoint's wall and the scene's: NULL when nothing does. */
static const char *wall_difference(const SimWall *saved, const SimWall *scene)
{
    if (saved->motion != scene->motion)
        return "motion";
    if (saved->species != scene->species)
        return "species";
    const double a[] = {saved->x0,     saved->y0,       saved->x1,
                        saved->y1,     saved->center_x, saved->center_y,
                        saved->radius, saved->angle0,   saved->angle1};
    const double b[] = {scene->x0,     scene->y0,       scene->x1,
                        scene->y1,     scene->center_x, scene->center_y,
                        scene->radius, scene->angle0,   scene->angle1};
    int same = saved->shape == scene->shape && saved->side == scene->side;
    for (size_t k = 0; same && k < sizeof a / sizeof a[0]; ++k)
        same = a[k] == b[k];
    return same ? NULL : "position or shape";
}

/* 0 when the checkpoint's walls are the scene's, else -1 with why in err. */
static int same_walls(const char *path, const SimWall *saved, int saved_count, const SimWall *walls,
                      int wall_count, char *err, size_t err_size)
{
    const char *rule = "a stage that loads a checkpoint keeps its walls, which must be the "
                       "scene's (docs/scenes.md, stages)";
    if (saved_count != wall_count) {
        snprintf(err, err_size, "checkpoint `%s` has %d walls, the scene %d: %s", path, saved_count,
                 wall_count, rule);
        return -1;
    }
    for (int k = 0; k < wall_count; ++k) {
        const char *what = wall_difference(&saved[k], &walls[k]);
        if (what) {
            snprintf(err, err_size,
                     "checkpoint `%s`: its wall %d differs from the scene's in %s: %s", path, k,
                     what, rule);
            return -1;
        }
    }
    return 0;
}

/* The first grain of `grains` whose species or motion the scene lacks: 0, or -1 with why. */
static int state_grains_fit(const char *path, const SimGrainSet *grains, int species_count,
                            int motion_count, char *err, size_t err_size)
{
    for (int i = 0; i < grains->count; ++i) {
        int species = grains->species[i], motion = grains->motion[i];
        if (species < 0 || species >= species_count) {
            snprintf(err, err_size,
                     "checkpoint `%s`: grain %u has species %d; the scene has species 0 to %d",
                     path, grains->id[i], species, species_count - 1);
            return -1;
        }
        if (motion < -1 || motion >= motion_count) {
            snprintf(err, err_size,
                     "checkpoint `%s`: grain %u follows motion %d; the scene has %d motion(s)",
                     path, grains->id[i], motion, motion_count);
            return -1;
        }
    }
    return 0;
}

void app_catch_signals(void (*handler)(int), int flags, struct sigaction *saved, int restore)
{
    const int signals[2] = {SIGINT, SIGTERM};
    for (int k = 0; k < 2; ++k) {
        if (restore) {
            sigaction(signals[k], &saved[k], NULL);
            continue;
        }
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = handler;
        sa.sa_flags = flags;
        sigemptyset(&sa.sa_mask);
        sigaction(signals[k], &sa, &saved[k]);
    }
}

/* The signal that asked the run in progress to stop (0: none). */
static volatile sig_atomic_t run_signal;

static void on_run_signal(int signo)
{
    run_signal = signo; /* the handler is reset (SA_RESETHAND): a second signal kills */
}

int app_run_signal(void)
{
    return run_signal;
}

void app_run_signal_catch(struct sigaction *saved, int restore)
{
    if (!restore)
        run_signal = 0;
    app_catch_signals(on_run_signal, SA_RESETHAND | SA_RESTART, saved, restore);
}

int app_state_check(const char *path, const SimWorldDef *def, char *err, size_t err_size)
{
    const char *why = NULL;
    FILE *f = sim_open_input(path, &why);
    if (!f) {
        snprintf(err, err_size, "cannot read checkpoint `%s`: %s", path, why);
        return -1;
    }
    fclose(f);
    SimGrainSet grains;
    SimWall *saved = NULL;
    int saved_count = 0;
    double time = 0.0;
    SimError error;
    if (sim_state_load(path, &grains, &saved, &saved_count, &time, &error) != SIM_OK) {
        snprintf(err, err_size, "checkpoint `%s`: %s", path, error.message);
        return -1;
    }
    int rc = 0;
    if (def)
        rc = state_grains_fit(path, &grains, def->species_count, def->motion_count, err, err_size);
    if (def && rc == 0)
        rc = same_walls(path, saved, saved_count, def->walls, def->wall_count, err, err_size);
    sim_grain_set_free(&grains);
    free(saved);
    return rc;
}
