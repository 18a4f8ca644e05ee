/* SPDX-License-Identifier: MIT */
/* study.c: `sablier study` (thesis 004 statistics: independent samples over L and w, run in
 * parallel processes, resumable, reduced to tables, fits and plots). The same pile of a sample is
 * discharged at every width (004 §3.1: "the same samples are discharged at every w"). */
#include "study.h"

#include "drivers.h"

#include "base/util.h"
#include "driver/driver.h"
#include "driver/pool.h"
#include "driver/stats.h"
#include "run/run.h"
#include "sim/sim.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#define PATH         2048
#define MAX_LENGTHS  16
#define MAX_WIDTHS   128
#define NOTHING      ((double)NAN)
#define SPECIES_CELL 5.0 /* side of the species-map cells, d (004 §3.4) */

const char APP_STUDY_USAGE[] =
    "usage: sablier study SCENE [--L 25,50,...] [--widths 1.0:7.0:0.2] [--samples N]\n"
    "                     [--jobs J] [--out DIR] [--set KEY=VALUE]... [--reduce-only] [--resume]\n"
    "\n"
    "Thesis 004 statistics. Each sample (seed = scene seed + sample index) is one pile per L,\n"
    "discharged at every width; samples run in J parallel processes and an interrupted study\n"
    "resumes where it stopped. Writes DIR/L<L>/w<W>.csv (one row per sample), DIR/study.csv\n"
    "(<h>, sigma_h, <s>, arch composition per L and w), DIR/fits.csv (w_t per L from a\n"
    "Gaussian fit of sigma_h, w_c from the linear fit of w_t against 1/L), DIR/L<L>/Fs.csv,\n"
    "DIR/L<L>/profile.csv, plots, and for two-species scenes the maps of the small (or light)\n"
    "grain fraction on 5 d cells, DIR/L<L>/species_map.csv/.png and species_map_jammed.csv.\n"
    "  --L LIST        base lengths, d (default the scene's discharge.base_length)\n"
    "  --widths SPEC   A:B:STEP or a comma list, d (default 1.0:7.0:0.2)\n"
    "  --samples N     samples per L (default 10)\n"
    "  --jobs J        parallel processes (default 2)\n"
    "  --reduce-only   only rebuild tables and plots from finished runs\n"
    "  --resume        accepted for every driver alike: a study always resumes\n"
    "SIGINT or SIGTERM stops the samples (each width done is kept), writes the tables of what\n"
    "finished and exits 130 or 143.\n"
    "\n"
    "exit status: 0 every sample succeeded, 1 a sample failed, 2 bad input (nothing runs) or a\n"
    "table that cannot be written, 130/143 SIGINT/SIGTERM\n";

/* ---------------------------------------------------------------- texts */

/* A growing text (sample tables, map records). */
typedef struct Text {
    char *s;
    size_t len, cap;
} Text;

/* Room for n more bytes: 0, or -1 when out of memory (the text unchanged). */
static int text_reserve(Text *t, size_t n)
{
    if (t->len + n + 1 <= t->cap)
        return 0;
    size_t cap = 2 * (t->len + n + 1);
    char *grown = realloc(t->s, cap);
    if (!grown)
        return -1;
    t->s = grown;
    t->cap = cap;
    return 0;
}

/* Appends n bytes of `add`: 0, or -1 when out of memory (the text unchanged). */
static int text_add(Text *t, const char *add, size_t n)
{
    if (text_reserve(t, n) != 0)
        return -1;
    memcpy(t->s + t->len, add, n);
    t->len += n;
    t->s[t->len] = '\0';
    return 0;
}

/* Appends a formatted string: 0, or -1 when out of memory (the text unchanged). */
__attribute__((format(printf, 2, 3))) static int text_printf(Text *t, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    int n = vsnprintf(NULL, 0, format, args);
    va_end(args);
    if (n < 0 || text_reserve(t, (size_t)n) != 0)
        return -1;
    va_start(args, format);
    vsnprintf(t->s + t->len, t->cap - t->len, format, args);
    va_end(args);
    t->len += (size_t)n;
    return 0;
}

static int out_of_memory(char *err, size_t err_size)
{
    snprintf(err, err_size, "out of memory");
    return -1;
}

/* The pile's map record of a sample (004 §3.4), appended to *text: 1, 0 when the scene has no
 * two distinct species, -1 when out of memory. */
static int map_record(const Scene *scene, SimWorld *world, double L, const char *tag, char **text)
{
    int marked = app_study_species_marked(scene, NULL);
    if (marked < 0)
        return 0;
    AppStudySpeciesMap map;
    if (app_study_species_map_init(&map, L, SPECIES_CELL) != 0)
        return 0;
    SimFrame frame;
    sim_world_frame(world, &frame);
    app_study_species_map_add(&map, &frame, marked);
    int need = app_study_species_map_format(&map, tag, NULL, 0);
    size_t old = *text ? strlen(*text) : 0;
    char *grown = realloc(*text, old + (size_t)need + 2);
    if (grown) {
        app_study_species_map_format(&map, tag, grown + old, (size_t)need + 1);
        memcpy(grown + old + need, "\n", 2);
        *text = grown;
    }
    app_study_species_map_free(&map);
    return grown ? 1 : -1;
}

/* ---------------------------------------------------------------- study: one sample */

typedef struct Study {
    const char *scene_path;
    const char *const *sets;
    int set_count;
    const char *dir;
    double lengths[MAX_LENGTHS];
    int length_count;
    double widths[MAX_WIDTHS];
    int width_count;
    int samples, jobs;
} Study;

static void sample_paths(const char *dir, double L, int sample, char *csv, char *dep, char *pile)
{
    snprintf(csv, PATH, "%s/L%g/samples/s%06d.csv", dir, L, sample);
    snprintf(dep, PATH, "%s/L%g/samples/s%06d.dep", dir, L, sample);
    snprintf(pile, PATH, "%s/L%g/samples/s%06d.state", dir, L, sample);
}

/* Widths already done in a sample file (column 3 of each data row), the file's data rows in
 * *text (NULL when there is no file): their count, or -1 when out of memory. */
static int read_done(const char *path, const double *widths, int count, unsigned char *done,
                     char **text)
{
    *text = NULL;
    memset(done, 0, (size_t)count);
    FILE *f = sim_open_input(path, NULL);
    if (!f)
        return 0;
    Text kept = {NULL, 0, 0};
    char line[1024];
    int n = 0, bad = text_add(&kept, "", 0);
    while (!bad && fgets(line, sizeof line, f)) {
        long sample;
        double L, w;
        if (sscanf(line, "%ld,%lf,%lf", &sample, &L, &w) != 3)
            continue;
        for (int k = 0; k < count; ++k)
            if (fabs(widths[k] - w) < 1e-6 && !done[k]) {
                done[k] = 1;
                ++n;
            }
        bad = text_add(&kept, line, strlen(line));
    }
    fclose(f);
    if (bad) {
        free(kept.s);
        return -1;
    }
    *text = kept.s;
    return n;
}

/* The species-map records of a sample (s<k>.map) worth keeping on resume, into *kept (NULL when
 * none): the pile's, and those of widths already in the sample's table (a record written just
 * before an interruption is redone with its width). 0, or -1 when out of memory. */
static int read_maps(const char *path, const double *widths, int count, const unsigned char *done,
                     char **kept)
{
    Text t = {NULL, 0, 0};
    char *line = NULL;
    size_t cap = 0;
    int bad = 0;
    FILE *f = sim_open_input(path, NULL);
    if (f) {
        ssize_t len;
        while (!bad && (len = getline(&line, &cap, f)) > 0) {
            int keep = strncmp(line, "pile,", 5) == 0;
            double w = strtod(line, NULL);
            for (int k = 0; k < count && !keep; ++k)
                keep = done[k] && fabs(widths[k] - w) < 1e-6;
            if (keep)
                bad = text_add(&t, line, (size_t)len);
        }
        fclose(f);
    }
    free(line);
    if (bad)
        free(t.s);
    *kept = bad ? NULL : t.s;
    return bad ? -1 : 0;
}

/* The pile's deposition record: fixed fields, then the profile of the top per d-wide strip
 * (malloc'd, NULL when out of memory). */
static char *deposition_line(SimWorld *world, const AppDischargeDeposit *dep, double L, int sample)
{
    int bins = (int)floor(L + 0.5);
    double *heights = malloc((size_t)(bins + 1) * sizeof *heights);
    size_t size = 512 + 24 * (size_t)bins;
    char *line = malloc(size);
    if (!heights || !line) {
        free(heights);
        free(line);
        return NULL;
    }
    sim_world_surface_profile(world, -0.5 * L, 0.5 * L, bins, heights);
    size_t used =
        (size_t)snprintf(line, size, "%d,%g,%d,%d,%d,%ld,%d,%.10g,%.10g,%ld,%.4g", sample, L,
                         dep->rows, dep->released, dep->pile, dep->lost, dep->equilibrium,
                         dep->height, dep->time, dep->steps, dep->wall_seconds);
    for (int b = 0; b < bins; ++b)
        used += (size_t)snprintf(line + used, size - used, ",%.6g",
                                 isfinite(heights[b]) ? heights[b] : 0.0);
    snprintf(line + used, size - used, "\n");
    free(heights);
    return line;
}

/* A fresh pile record followed by the widths' records of `old` (not an old pile's): the new
 * text, or NULL when out of memory (fresh freed). */
static char *with_width_records(char *fresh, const char *old)
{
    Text t = {fresh, strlen(fresh), strlen(fresh) + 1};
    for (const char *p = old; p && *p;) {
        const char *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - p) + 1 : strlen(p);
        if (strncmp(p, "pile,", 5) != 0 && text_add(&t, p, n) != 0) {
            free(t.s);
            return NULL;
        }
        p += n;
    }
    return t.s;
}

/* Deposits the sample's pile and writes its checkpoint, deposition record and pile map record
 * (kept in *maps): 0, or the sample's exit status. */
static int deposit_sample(const Scene *scene, double L, int sample, const char *pile,
                          const char *dep_path, const char *maps_path, char **maps)
{
    char err[4096] = "";
    AppDischargeDeposit dep;
    SimWorld *world = app_discharge_deposit(scene, scene->seed + (uint64_t)sample, NULL, NULL, &dep,
                                            err, sizeof err);
    if (!world) {
        fprintf(stderr, "sablier: study L = %g sample %d: deposition: %s\n", L, sample, err);
        return 1;
    }
    char *line = deposition_line(world, &dep, L, sample);
    /* the pile's species map before discharge (004 §3.4), kept before the checkpoint */
    char *fresh = NULL;
    int recorded = line ? map_record(scene, world, L, "pile", &fresh) : -1, bad = 0;
    if (recorded > 0) { /* keep the widths' records, not an old pile's */
        fresh = with_width_records(fresh, *maps);
        recorded = fresh ? 1 : -1;
    }
    if (recorded > 0) {
        free(*maps);
        *maps = fresh;
        bad = app_write_atomic(maps_path, *maps) != 0;
    }
    SimError error;
    if (recorded >= 0)
        bad = bad || sim_world_save(world, pile, &error) != SIM_OK ||
              app_write_atomic(dep_path, line);
    sim_world_destroy(world);
    free(line);
    if (recorded < 0) {
        free(fresh);
        fprintf(stderr, "sablier: study: out of memory\n");
        return 2;
    }
    if (bad) {
        fprintf(stderr, "sablier: study: cannot write %s\n", pile);
        return 2;
    }
    return 0;
}

/* Where one sample's files are and what of it is done. */
typedef struct Sample {
    const Scene *scene;
    const Study *st;
    double L;
    int sample;
    char csv[PATH], dep[PATH], pile[PATH], maps_path[PATH];
    unsigned char done[MAX_WIDTHS];
} Sample;

/* Discharges the pile at every width not done yet, each kept in the sample's table (`out`, the
 * rows so far) and its map record (maps) as soon as it is done: 0, or the sample's exit status. */
static int discharge_widths(const Sample *sm, char **maps, char *out, size_t cap)
{
    const Study *st = sm->st;
    char err[4096] = "";
    for (int k = 0; k < st->width_count; ++k) {
        if (sm->done[k])
            continue;
        AppDischarge r;
        SimWorld *world =
            app_discharge(sm->scene, sm->pile, st->widths[k], NULL, &r, err, sizeof err);
        if (!world) {
            fprintf(stderr, "sablier: study L = %g sample %d w = %g: %s\n", sm->L, sm->sample,
                    st->widths[k], err);
            return 1;
        }
        /* species map after a discharge an arch stopped (004 §3.4: jammed samples only) */
        char tag[32];
        snprintf(tag, sizeof tag, "%.10g", st->widths[k]);
        int mapped = r.arch > 0 ? map_record(sm->scene, world, sm->L, tag, maps) : 0;
        sim_world_destroy(world);
        if (mapped < 0) {
            fprintf(stderr, "sablier: study: out of memory\n");
            return 2;
        }
        if (mapped && app_write_atomic(sm->maps_path, *maps) != 0)
            return 2;
        char row[512];
        app_discharge_csv_row(&r, sm->sample, sm->L, row, sizeof row);
        size_t len = strlen(out);
        snprintf(out + len, cap - len, "%s\n", row);
        if (app_write_atomic(sm->csv, out) != 0) /* each width is kept as soon as it is done */
            return 2;
    }
    return 0;
}

/* One sample, in a child process: its pile (deposited unless a checkpoint is there) discharged
 * at every width not done yet. Returns the exit status. */
static int run_sample(const Scene *scene, const Study *st, double L, int sample)
{
    Sample sm = {.scene = scene, .st = st, .L = L, .sample = sample};
    sample_paths(st->dir, L, sample, sm.csv, sm.dep, sm.pile);
    snprintf(sm.maps_path, sizeof sm.maps_path, "%s/L%g/samples/s%06d.map", st->dir, L, sample);
    char *text = NULL, *maps = NULL, *out = NULL;
    int n_done = read_done(sm.csv, st->widths, st->width_count, sm.done, &text);
    if (n_done == st->width_count) {
        free(text);
        return 0;
    }
    int status =
        n_done < 0 || read_maps(sm.maps_path, st->widths, st->width_count, sm.done, &maps) != 0 ? -1
                                                                                                : 0;
    struct stat sb;
    if (status == 0 && stat(sm.pile, &sb) != 0)
        status = deposit_sample(scene, L, sample, sm.pile, sm.dep, sm.maps_path, &maps);
    size_t cap = (text ? strlen(text) : 0) + 256 * (size_t)st->width_count + 512;
    if (status == 0 && !(out = malloc(cap)))
        status = -1;
    if (status == 0) {
        snprintf(out, cap, "%s", text ? text : "");
        status = discharge_widths(&sm, &maps, out, cap);
        if (status == 0)
            remove(sm.pile); /* every width done: the pile is no longer needed */
    }
    if (status < 0) {
        fprintf(stderr, "sablier: study: out of memory\n");
        status = 2;
    }
    free(text);
    free(out);
    free(maps);
    return status;
}

/* ---------------------------------------------------------------- study: scheduling */

typedef struct Task {
    int length, sample;
} Task;

/* The samples' pool: the tasks still to run. */
typedef struct StudyRun {
    const Study *st;
    Scene **scenes;
    const Task *tasks;
    const AppDriverPool *pool; /* its count, finished members and start, for the ETA */
} StudyRun;

static int study_run_task(void *ctx, int index)
{
    const StudyRun *run = ctx;
    Task t = run->tasks[index];
    return run_sample(run->scenes[t.length], run->st, run->st->lengths[t.length], t.sample);
}

static void study_progress(void *ctx, int index, int status, char *line, size_t size)
{
    const StudyRun *run = ctx;
    Task t = run->tasks[index];
    double L = run->st->lengths[t.length];
    if (status == APP_POOL_INTERRUPTED) {
        snprintf(line, size, "L = %g sample %d interrupted", L, t.sample);
        return;
    }
    int finished = run->pool->finished, count = run->pool->count;
    double elapsed = sim_clock_seconds(SIM_CLOCK_WALL) - run->pool->start_at;
    snprintf(line, size, "L = %g sample %d %s (%d/%d, %.0f s, ETA %.0f s)", L, t.sample,
             status == 0 ? "done" : "FAILED", finished, count, elapsed,
             elapsed / finished * (count - finished));
}

/* The samples not finished yet, samples outer (every L advances together): their count, or -1
 * when out of memory. */
static int pending_tasks(const Study *st, Task *tasks)
{
    int n = 0;
    for (int s = 0; s < st->samples; ++s)
        for (int l = 0; l < st->length_count; ++l) {
            char csv[PATH], dep[PATH], pile[PATH];
            sample_paths(st->dir, st->lengths[l], s, csv, dep, pile);
            unsigned char done[MAX_WIDTHS];
            char *text;
            int k = read_done(csv, st->widths, st->width_count, done, &text);
            free(text);
            if (k < 0)
                return -1;
            if (k == st->width_count)
                continue;
            tasks[n++] = (Task){l, s};
        }
    return n;
}

/* Runs the samples not finished yet: 0, 1 when one failed, 2 when out of memory, 128 + the
 * signal that stopped the pool. */
static int run_study(const Study *st, Scene **scenes)
{
    int total = st->length_count * st->samples;
    Task *tasks = calloc((size_t)total + 1, sizeof *tasks);
    int n = tasks ? pending_tasks(st, tasks) : -1;
    if (n < 0) {
        fprintf(stderr, "sablier: study: out of memory\n");
        free(tasks);
        return 2;
    }
    fprintf(stderr, "sablier: study: %d of %d samples to run (%d jobs)\n", n, total,
            app_pool_width(st->jobs));
    StudyRun run = {st, scenes, tasks, NULL};
    AppDriverPool pool = {.command = "study",
                          .not_started = "fork failed",
                          .count = n,
                          .jobs = st->jobs,
                          .signal_status = 1,
                          .ctx = &run,
                          .run = study_run_task,
                          .progress = study_progress};
    run.pool = &pool;
    int rc = app_driver_pool_run(&pool);
    free(tasks);
    return rc > APP_EXIT_SIGNAL ? rc : rc != 0 || pool.failed ? 1 : 0;
}

/* ---------------------------------------------------------------- reduction */

/* A one-panel plot of the reduction: the series' fields in order, and same = 1 for the colour
 * of the series before (a fit drawn with its data). */
#define SERIES(label_, count_, x_, y_, y_err_, line_, dashed_, marker_, same_)                     \
    ((AppPlotSeries){.label = (label_),                                                            \
                     .count = (count_),                                                            \
                     .x = (x_),                                                                    \
                     .y = (y_),                                                                    \
                     .y_err = (y_err_),                                                            \
                     .line = (line_),                                                              \
                     .dashed = (dashed_),                                                          \
                     .marker = (AppMarker)(marker_),                                               \
                     .rgb = (same_) ? APP_RGB_PREVIOUS : APP_RGB_AUTO})

typedef struct StudyPlot {
    const char *title, *x_label, *y_label;
    int y_log;
    int series_count;
    const AppPlotSeries *series;
    int data_beside; /* 1: the study writes the plot's .csv itself (AppPlot.data_beside) */
} StudyPlot;

static int study_plot(const AppRender *render, const Scene *scene, const StudyPlot *p,
                      const char *path, char *err, size_t err_size)
{
    AppPlotPanel panel = {.x_label = p->x_label,
                          .y_label = p->y_label,
                          .y_log = p->y_log,
                          .legend = APP_LEGEND_UPPER_RIGHT,
                          .series_count = p->series_count < 64 ? p->series_count : 64,
                          .series = p->series};
    AppPlot plot = {.title = p->title,
                    .width = 1000,
                    .height = 700,
                    .panel_count = 1,
                    .panels = &panel,
                    .scene = scene->name,
                    .seed = scene->seed,
                    .print = &scene->style,
                    .data_beside = p->data_beside};
    return render->plot(render->context, &plot, path, err, err_size);
}

static void gaussian_fit(const double *w, const double *sigma, int n, double *peak, double *A,
                         double *B, double *C)
{
    int best = -1;
    for (int k = 0; k < n; ++k)
        if (isfinite(sigma[k]) && (best < 0 || sigma[k] > sigma[best]))
            best = k;
    *peak = best >= 0 ? w[best] : NOTHING;
    *A = *B = *C = NAN;
    if (best < 0 || !(sigma[best] > 0.0))
        return;
    /* least squares of log sigma = A + B w + C w^2 over the points above half the maximum */
    double s[5] = {0}, t[3] = {0};
    int m = 0;
    for (int k = 0; k < n; ++k) {
        if (!(sigma[k] > 0.5 * sigma[best]))
            continue;
        double x = w[k] - w[best], y = log(sigma[k]), p = 1.0;
        for (int j = 0; j < 5; ++j, p *= x)
            s[j] += p;
        t[0] += y;
        t[1] += x * y;
        t[2] += x * x * y;
        ++m;
    }
    if (m < 3)
        return;
    double M[3][4] = {{s[0], s[1], s[2], t[0]}, {s[1], s[2], s[3], t[1]}, {s[2], s[3], s[4], t[2]}};
    for (int c = 0; c < 3; ++c) { /* Gaussian elimination with partial pivoting */
        int piv = c;
        for (int r = c + 1; r < 3; ++r)
            if (fabs(M[r][c]) > fabs(M[piv][c]))
                piv = r;
        if (!(fabs(M[piv][c]) > 1e-300))
            return;
        for (int j = 0; j < 4; ++j) {
            double tmp = M[c][j];
            M[c][j] = M[piv][j];
            M[piv][j] = tmp;
        }
        for (int r = 0; r < 3; ++r) {
            if (r == c)
                continue;
            double f = M[r][c] / M[c][c];
            for (int j = c; j < 4; ++j)
                M[r][j] -= f * M[c][j];
        }
    }
    double a = M[0][3] / M[0][0], b = M[1][3] / M[1][1], c2 = M[2][3] / M[2][2];
    if (!(c2 < 0.0))
        return;
    double x0 = -b / (2.0 * c2);
    if (fabs(x0) > 2.0 * (w[n - 1] - w[0]) + 1.0)
        return;
    *peak = w[best] + x0;
    /* in absolute w: log sigma = A + B w + C w^2 */
    double o = w[best];
    *C = c2;
    *B = b - 2.0 * c2 * o;
    *A = a - b * o + c2 * o * o;
}

double app_study_gaussian_peak(const double *w, const double *sigma, int n)
{
    double peak, A, B, C;
    gaussian_fit(w, sigma, n, &peak, &A, &B, &C);
    return peak;
}

typedef struct Cell {
    int n, jammed, catastrophic;
    double h, h2, s, s2, edges, arch;
    double pile0, pile_all, arch0, arch_all, arch_ratio; /* species 0 fractions */
    int arch_ratio_n;
    long *sizes;
    int size_count, size_cap;
} Cell;

static int compare_long(const void *a, const void *b)
{
    long x = *(const long *)a, y = *(const long *)b;
    return (x > y) - (x < y);
}

/* ---------------------------------------------------------------- species maps of a study */

/* Every sample's map records of one L, summed: maps[0] the piles before discharge, maps[k + 1]
 * after the discharges at widths[k] an arch stopped; piles[] the records of each. */
static void read_species_maps(const char *dir, double L, const double *widths, int width_count,
                              int samples, AppStudySpeciesMap *maps, int *piles)
{
    char path[PATH + 64], *line = NULL;
    size_t cap = 0;
    for (int s = 0; s < samples; ++s) {
        snprintf(path, sizeof path, "%s/L%g/samples/s%06d.map", dir, L, s);
        FILE *f = sim_open_input(path, NULL);
        if (!f)
            continue;
        while (getline(&line, &cap, f) > 0) {
            char *comma = strchr(line, ',');
            if (!comma)
                continue;
            int k = -1;
            if (strncmp(line, "pile,", 5) == 0)
                k = 0;
            else
                for (int j = 0; j < width_count && k < 0; ++j)
                    if (fabs(widths[j] - strtod(line, NULL)) < 1e-6)
                        k = j + 1;
            if (k >= 0 && app_study_species_map_parse(&maps[k], comma + 1) == 0)
                ++piles[k];
        }
        fclose(f);
    }
    free(line);
}

/* What the species maps of one L are written from. */
typedef struct MapOutput {
    const Scene *scene;
    const char *dir, *what;
    double L;
    const AppRender *render;
    char *text; /* room for every map's CSV */
    size_t text_cap;
    char *err;
    size_t err_size;
} MapOutput;

/* The map of the piles before discharge: species_map.csv and .png. 0, or -1. */
static int write_pile_map(const MapOutput *o, const AppStudySpeciesMap *m, int piles,
                          double *values)
{
    int status = 0;
    char path[PATH + 64];
    size_t cells = (size_t)m->nx * (size_t)m->ny;
    size_t used = (size_t)snprintf(o->text, o->text_cap, "x,y,count,fraction\n");
    for (int j = 0; j < m->ny; ++j)
        for (int i = 0; i < m->nx; ++i) {
            values[(size_t)j * (size_t)m->nx + (size_t)i] = app_study_species_map_fraction(m, i, j);
            used += (size_t)snprintf(o->text + used, o->text_cap - used, "%.6g,%.6g,%ld,%.8g\n",
                                     m->x0 + (i + 0.5) * m->cell, m->y0 + (j + 0.5) * m->cell,
                                     m->count[(size_t)j * (size_t)m->nx + (size_t)i],
                                     values[(size_t)j * (size_t)m->nx + (size_t)i]);
        }
    snprintf(path, sizeof path, "%s/L%g/species_map.csv", o->dir, o->L);
    if (piles > 0 && app_write_atomic(path, o->text) != 0)
        status = -1;
    if (piles > 0 && o->render && o->render->map) {
        char title[192], bar[64];
        snprintf(title, sizeof title,
                 "fraction of %s grains before discharge, L = %g d, %d piles, %g d cells (004 "
                 "fig. 3.4)",
                 o->what, o->L, piles, SPECIES_CELL);
        snprintf(bar, sizeof bar, "%s (1)", strcmp(o->what, "small") == 0 ? "q_s" : "q_d");
        int rows = 1; /* drawn up to the highest row with grains */
        for (size_t c = 0; c < cells; ++c)
            if (m->count[c] > 0)
                rows = (int)(c / (size_t)m->nx) + 1;
        AppMap map = {title, "x / d", "y / d", bar,  m->nx, rows, m->x0,
                      m->y0, m->cell, values,  NULL, NULL,  NULL};
        snprintf(path, sizeof path, "%s/L%g/species_map.png", o->dir, o->L);
        if (o->render->map(o->render->context, o->scene, &map, path, o->err, o->err_size) != 0)
            status = -1;
    }
    return status;
}

/* The maps after the discharges an arch stopped, per width: species_map_jammed.csv. 0, or -1;
 * *any = 1 when there is one. */
static int write_jammed_maps(const MapOutput *o, const AppStudySpeciesMap *maps, const int *piles,
                             const double *widths, int width_count, int *any)
{
    size_t used = (size_t)snprintf(o->text, o->text_cap, "w,jammed,x,y,count,fraction\n");
    *any = 0;
    for (int k = 1; k <= width_count; ++k) {
        const AppStudySpeciesMap *a = &maps[k];
        if (piles[k] == 0)
            continue;
        *any = 1;
        for (int j = 0; j < a->ny; ++j)
            for (int i = 0; i < a->nx; ++i)
                used += (size_t)snprintf(o->text + used, o->text_cap - used,
                                         "%.10g,%d,%.6g,%.6g,%ld,%.8g\n", widths[k - 1], piles[k],
                                         a->x0 + (i + 0.5) * a->cell, a->y0 + (j + 0.5) * a->cell,
                                         a->count[(size_t)j * (size_t)a->nx + (size_t)i],
                                         app_study_species_map_fraction(a, i, j));
    }
    char path[PATH + 64];
    snprintf(path, sizeof path, "%s/L%g/species_map_jammed.csv", o->dir, o->L);
    return *any && app_write_atomic(path, o->text) != 0 ? -1 : 0;
}

/* Species maps of one L (004 §3.4, fig. 3.4): the piles before discharge, and after the
 * discharges an arch stopped, per width; fractions are ratios of sums over samples. 0, -1 when a
 * file could not be written or drawn, -2 when out of memory. */
static int species_maps(const Scene *scene, const char *dir, double L, const double *widths,
                        int width_count, int samples, const AppRender *render, char *err,
                        size_t err_size)
{
    MapOutput o = {scene, dir, NULL, L, render, NULL, 0, err, err_size};
    if (app_study_species_marked(scene, &o.what) < 0)
        return 0;
    AppStudySpeciesMap *maps = calloc((size_t)width_count + 1, sizeof *maps); /* [0] = before */
    int *piles = calloc((size_t)width_count + 1, sizeof *piles);
    int ready = maps && piles, status = 0;
    for (int k = 0; ready && k <= width_count; ++k)
        ready = app_study_species_map_init(&maps[k], L, SPECIES_CELL) == 0;
    double *values = NULL;
    if (ready) {
        read_species_maps(dir, L, widths, width_count, samples, maps, piles);
        size_t cells = (size_t)maps[0].nx * (size_t)maps[0].ny;
        o.text_cap = 64 + 96 * cells * (size_t)(width_count + 1);
        o.text = malloc(o.text_cap);
        values = malloc(cells * sizeof *values);
        ready = o.text && values;
    }
    if (ready) {
        int any = 0;
        if (write_pile_map(&o, &maps[0], piles[0], values) != 0)
            status = -1;
        if (write_jammed_maps(&o, maps, piles, widths, width_count, &any) != 0)
            status = -1;
        fprintf(stderr,
                "sablier: study: L = %g d: species maps (%s grains) over %d piles before "
                "discharge%s\n",
                L, o.what, piles[0], any ? ", and jammed piles per width" : "");
    }
    free(o.text);
    free(values);
    for (int k = 0; maps && k <= width_count; ++k)
        app_study_species_map_free(&maps[k]);
    free(maps);
    free(piles);
    return ready ? status : -2;
}

/* ---------------------------------------------------------------- reduction */

/* A study's reduction: the inputs, the cells and statistics per (L, w) at [l * width_count + k],
 * and the fits per L. */
typedef struct Reduction {
    const Scene *scene;
    const char *dir;
    const double *lengths, *widths;
    int length_count, width_count, samples;
    const AppRender *render;
    char *err;
    size_t err_size;
    int status; /* -1 once a file could not be written or a plot drawn */
    Cell *cells;
    double *h_mean, *h_sd, *h_err, *qs_pile, *qs_arch;
    Text study; /* study.csv */
    double w_t[MAX_LENGTHS], fitA[MAX_LENGTHS], fitB[MAX_LENGTHS], fitC[MAX_LENGTHS];
    double inv[MAX_LENGTHS], wc, slope, wc_err; /* w_t against 1/L */
    int fit_n;
} Reduction;

static void reduction_free(Reduction *R)
{
    size_t cells_n = (size_t)R->length_count * (size_t)R->width_count;
    for (size_t i = 0; R->cells && i < cells_n; ++i)
        free(R->cells[i].sizes);
    free(R->cells);
    free(R->h_mean);
    free(R->h_sd);
    free(R->h_err);
    free(R->qs_pile);
    free(R->qs_arch);
    free(R->study.s);
}

/* 0, or -1 when out of memory. */
static int reduction_init(Reduction *R)
{
    size_t cells_n = (size_t)R->length_count * (size_t)R->width_count;
    R->cells = calloc(cells_n + 1, sizeof *R->cells);
    R->h_mean = calloc(cells_n + 1, sizeof(double));
    R->h_sd = calloc(cells_n + 1, sizeof(double));
    R->h_err = calloc(cells_n + 1, sizeof(double));
    R->qs_pile = calloc(cells_n + 1, sizeof(double));
    R->qs_arch = calloc(cells_n + 1, sizeof(double));
    if (!R->cells || !R->h_mean || !R->h_sd || !R->h_err || !R->qs_pile || !R->qs_arch)
        return -1;
    return text_printf(&R->study, "L,w,samples,h_mean,h_sd,h_err,s_mean,s_sd,edges_mean,jammed,"
                                  "catastrophic,arch_mean,qs_pile,qs_arch,qs_arch_mean\n");
}

/* Sums over the piles' deposition records of one L: the profile (and its squares); returns the
 * records read. */
static int read_profiles(const Reduction *R, double L, int bins, double *profile, double *profile2)
{
    int profiles = 0;
    for (int s = 0; s < R->samples; ++s) {
        char csv[PATH], dep[PATH], pile[PATH];
        sample_paths(R->dir, L, s, csv, dep, pile);
        FILE *f = sim_open_input(dep, NULL);
        if (!f)
            continue;
        static char line[1 << 16];
        if (fgets(line, sizeof line, f)) {
            char *p = line;
            for (int field = 0; field < 11 && p; ++field) {
                p = strchr(p, ',');
                p = p ? p + 1 : NULL;
            }
            for (int b = 0; b < bins && p; ++b) {
                double v = strtod(p, NULL);
                profile[b] += v;
                profile2[b] += v * v;
                p = strchr(p, ',');
                p = p ? p + 1 : NULL;
            }
            ++profiles;
        }
        fclose(f);
    }
    return profiles;
}

/* One sample's row (s through, edges, h, the pile and its arch) into its cell: 0, or -1 when out
 * of memory. */
static int cell_add(Cell *c, long through, long edges, double h, int pile_n, int arch, int a0,
                    int p0)
{
    ++c->n;
    c->h += h;
    c->h2 += h * h;
    c->s += (double)through;
    c->s2 += (double)through * (double)through;
    c->edges += (double)edges;
    c->jammed += arch > 0;
    c->catastrophic += h == 0.0;
    c->arch += arch;
    c->pile0 += p0;
    c->pile_all += pile_n;
    if (arch > 0) {
        c->arch0 += a0;
        c->arch_all += arch;
        c->arch_ratio += (double)a0 / arch;
        ++c->arch_ratio_n;
    }
    if (c->size_count == c->size_cap) {
        int size_cap = c->size_cap ? 2 * c->size_cap : 64;
        long *grown = realloc(c->sizes, (size_t)size_cap * sizeof *grown);
        if (!grown)
            return -1;
        c->sizes = grown;
        c->size_cap = size_cap;
    }
    c->sizes[c->size_count++] = through;
    return 0;
}

/* Every sample table of L = lengths[l], row by row, into the per-width tables and cells: 0, or
 * -1 when out of memory. */
static int read_sample_rows(Reduction *R, int l, Text *tables)
{
    double L = R->lengths[l];
    for (int s = 0; s < R->samples; ++s) {
        char csv[PATH], dep[PATH], pile[PATH];
        sample_paths(R->dir, L, s, csv, dep, pile);
        FILE *f = sim_open_input(csv, NULL);
        if (!f)
            continue;
        char line[1024];
        int bad = 0;
        while (!bad && fgets(line, sizeof line, f)) {
            long sample, through, edges;
            double Lr, w, h;
            int pile_n, arch, a0, a1, p0, p1;
            if (sscanf(line, "%ld,%lf,%lf,%ld,%ld,%lf,%d,%d,%d,%d,%d,%d", &sample, &Lr, &w,
                       &through, &edges, &h, &pile_n, &arch, &a0, &a1, &p0, &p1) != 12)
                continue;
            int k = 0;
            while (k < R->width_count && fabs(R->widths[k] - w) > 1e-6)
                ++k;
            if (k == R->width_count)
                continue;
            Cell *c = &R->cells[(size_t)l * (size_t)R->width_count + (size_t)k];
            bad = text_add(&tables[k], line, strlen(line)) != 0 ||
                  cell_add(c, through, edges, h, pile_n, arch, a0, p0) != 0;
        }
        fclose(f);
        if (bad)
            return -1;
    }
    return 0;
}

/* The statistics of cell i (L and w) and its study.csv row: 0, or -1 when out of memory. */
static int cell_stats(Reduction *R, size_t i, double L, double w)
{
    Cell *c = &R->cells[i];
    double n = c->n;
    R->h_mean[i] = n > 0 ? c->h / n : NOTHING;
    R->h_sd[i] = n > 1 ? sqrt(fmax(0.0, (c->h2 - c->h * c->h / n) / (n - 1.0))) : NOTHING;
    R->h_err[i] = n > 1 ? R->h_sd[i] / sqrt(n) : NOTHING;
    R->qs_pile[i] = c->pile_all > 0 ? c->pile0 / c->pile_all : NOTHING;
    R->qs_arch[i] = c->arch_all > 0 ? c->arch0 / c->arch_all : NOTHING;
    double s_mean = n > 0 ? c->s / n : NOTHING;
    double s_sd = n > 1 ? sqrt(fmax(0.0, (c->s2 - c->s * c->s / n) / (n - 1.0))) : NOTHING;
    return text_printf(
        &R->study, "%g,%.10g,%d,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", L,
        w, c->n, R->h_mean[i], R->h_sd[i], R->h_err[i], s_mean, s_sd,
        n > 0 ? c->edges / n : NOTHING, n > 0 ? c->jammed / n : NOTHING,
        n > 0 ? c->catastrophic / n : NOTHING, n > 0 ? c->arch / n : NOTHING, R->qs_pile[i],
        R->qs_arch[i], c->arch_ratio_n ? c->arch_ratio / c->arch_ratio_n : NOTHING);
}

/* F(s) = P(size >= s) of one cell (004 fig. 2.16), its sizes sorted, into fs: 0, or -1 when out
 * of memory. */
static int cell_fs(Cell *c, double w, Text *fs)
{
    if (c->size_count == 0)
        return 0;
    qsort(c->sizes, (size_t)c->size_count, sizeof *c->sizes, compare_long);
    for (int j = 0; j < c->size_count; ++j) {
        if (j > 0 && c->sizes[j] == c->sizes[j - 1])
            continue;
        if (text_printf(fs, "%.10g,%ld,%.8g\n", w, c->sizes[j],
                        (double)(c->size_count - j) / c->size_count) != 0)
            return -1;
    }
    return 0;
}

/* Per width of L = lengths[l]: L<L>/w<W>.csv, the cell's statistics and study.csv row; then
 * L<L>/Fs.csv. 0, or -1 when out of memory. */
static int write_width_tables(Reduction *R, int l, const Text *tables)
{
    double L = R->lengths[l];
    char path[PATH + 64];
    Text fs = {NULL, 0, 0};
    int bad = text_printf(&fs, "w,s,F\n");
    for (int k = 0; !bad && k < R->width_count; ++k) {
        char wname[32];
        app_discharge_width_name(R->widths[k], wname, sizeof wname);
        snprintf(path, sizeof path, "%s/L%g/%s.csv", R->dir, L, wname);
        if (app_write_atomic(path, tables[k].s) != 0)
            R->status = -1;
        size_t i = (size_t)l * (size_t)R->width_count + (size_t)k;
        bad = cell_stats(R, i, L, R->widths[k]) != 0 || cell_fs(&R->cells[i], R->widths[k], &fs);
    }
    snprintf(path, sizeof path, "%s/L%g/Fs.csv", R->dir, L);
    if (!bad && app_write_atomic(path, fs.s) != 0)
        R->status = -1;
    free(fs.s);
    return bad ? -1 : 0;
}

/* The mean profile and local slope over l = 10 d of L (004 figs. 2.9-2.10): L<L>/profile.csv.
 * 0, or -1 when out of memory. */
static int write_profile(Reduction *R, double L, int bins, const double *profile,
                         const double *profile2, int profiles)
{
    Text text = {NULL, 0, 0};
    int bad = text_printf(&text, "x,h_mean,h_sd,slope\n");
    for (int b = 0; !bad && b < bins; ++b) {
        double m = profile[b] / profiles;
        double sd =
            profiles > 1 ? sqrt(fmax(0.0, (profile2[b] - profile[b] * m) / (profiles - 1.0))) : 0.0;
        int lo = b - 5, hi = b + 5;
        double slope =
            lo >= 0 && hi < bins ? (profile[hi] - profile[lo]) / profiles / 10.0 : NOTHING;
        bad = text_printf(&text, "%.6g,%.8g,%.8g,%.8g\n", -0.5 * L + b + 0.5, m, sd, slope);
    }
    char path[PATH + 64];
    snprintf(path, sizeof path, "%s/L%g/profile.csv", R->dir, L);
    if (!bad && app_write_atomic(path, text.s) != 0)
        R->status = -1;
    free(text.s);
    return bad ? -1 : 0;
}

/* The tables of L = lengths[l]: per width, F(s), the mean profile, the species maps, and the
 * Gaussian fit of sigma_h. 0, or -1 when out of memory. */
static int reduce_length(Reduction *R, int l)
{
    double L = R->lengths[l];
    int bins = (int)floor(L + 0.5), bad = 0;
    Text *tables = calloc((size_t)R->width_count, sizeof *tables); /* every sample's row */
    double *profile = calloc((size_t)bins + 1, sizeof(double));
    double *profile2 = calloc((size_t)bins + 1, sizeof(double));
    bad = !tables || !profile || !profile2;
    for (int k = 0; !bad && k < R->width_count; ++k)
        bad = text_printf(&tables[k], "%s\n", app_discharge_csv_header());
    int profiles = bad ? 0 : read_profiles(R, L, bins, profile, profile2);
    bad = bad || read_sample_rows(R, l, tables) != 0 || write_width_tables(R, l, tables) != 0;
    if (!bad && profiles > 0)
        bad = write_profile(R, L, bins, profile, profile2, profiles);
    for (int k = 0; tables && k < R->width_count; ++k)
        free(tables[k].s);
    free(tables);
    free(profile);
    free(profile2);
    if (bad)
        return out_of_memory(R->err, R->err_size);
    int maps = species_maps(R->scene, R->dir, L, R->widths, R->width_count, R->samples, R->render,
                            R->err, R->err_size);
    if (maps == -2)
        return out_of_memory(R->err, R->err_size);
    if (maps != 0)
        R->status = -1;
    size_t o = (size_t)l * (size_t)R->width_count;
    gaussian_fit(R->widths, R->h_sd + o, R->width_count, &R->w_t[l], &R->fitA[l], &R->fitB[l],
                 &R->fitC[l]);
    return 0;
}

/* w_t against 1/L, w_c the intercept (004 fig. 2.15): fits.csv and its line on stderr. 0, or
 * -1 when out of memory. */
static int write_fits(Reduction *R)
{
    double fit_x[MAX_LENGTHS] = {0}, fit_y[MAX_LENGTHS] = {0};
    R->wc = R->slope = NAN;
    R->wc_err = 0.0;
    R->fit_n = 0;
    for (int l = 0; l < R->length_count; ++l) {
        R->inv[l] = 1.0 / R->lengths[l];
        if (isfinite(R->w_t[l])) {
            fit_x[R->fit_n] = R->inv[l];
            fit_y[R->fit_n++] = R->w_t[l];
        }
    }
    app_linear_fit(fit_x, fit_y, R->fit_n, &R->wc, &R->slope, &R->wc_err);
    Text text = {NULL, 0, 0};
    int bad = text_printf(&text, "L,inv_L,w_t\n");
    for (int l = 0; !bad && l < R->length_count; ++l)
        bad = text_printf(&text, "%g,%.8g,%.8g\n", R->lengths[l], R->inv[l], R->w_t[l]);
    bad = bad || text_printf(&text, "# w_c = %.6g +- %.3g d, slope %.6g d^2\n", R->wc, R->wc_err,
                             R->slope);
    char path[PATH + 64];
    snprintf(path, sizeof path, "%s/fits.csv", R->dir);
    if (!bad && app_write_atomic(path, text.s) != 0)
        R->status = -1;
    free(text.s);
    if (bad)
        return out_of_memory(R->err, R->err_size);
    fprintf(stderr, "sablier: study: w_t =");
    for (int l = 0; l < R->length_count; ++l)
        fprintf(stderr, " %.3g (L = %g)", R->w_t[l], R->lengths[l]);
    fprintf(stderr, "; w_c = %.3g +- %.2g d (%d lengths)\n", R->wc, R->wc_err, R->fit_n);
    return 0;
}

/* ---------------------------------------------------------------- reduction plots */

/* One study plot into DIR/NAME: 0, or -1 (err says why). */
static int reduction_plot(const Reduction *R, const StudyPlot *plot, const char *name)
{
    char path[PATH + 64];
    snprintf(path, sizeof path, "%s/%s", R->dir, name);
    return study_plot(R->render, R->scene, plot, path, R->err, R->err_size);
}

/* <h> with error bars, and sigma_h with its Gaussian fits (004 figs. 2.13-2.14). */
static int plot_heights(const Reduction *R)
{
    AppPlotSeries series[2 * MAX_LENGTHS + 2];
    char labels[MAX_LENGTHS][32];
    double curve_x[MAX_LENGTHS][200], curve_y[MAX_LENGTHS][200];
    const double *widths = R->widths;
    int width_count = R->width_count, ns = 0, status = 0;
    for (int l = 0; l < R->length_count; ++l) {
        snprintf(labels[l], sizeof labels[l], "L = %g d", R->lengths[l]);
        size_t o = (size_t)l * (size_t)width_count;
        series[ns++] =
            SERIES(labels[l], width_count, widths, R->h_mean + o, R->h_err + o, 1, 0, 1 + l % 4, 0);
    }
    StudyPlot plot = {"<h> after discharge (004 fig. 2.13)", "w / d", "<h> / d", 0, ns, series, 0};
    status |= reduction_plot(R, &plot, "h_mean.png");
    ns = 0;
    for (int l = 0; l < R->length_count; ++l) {
        size_t o = (size_t)l * (size_t)width_count;
        series[ns++] =
            SERIES(labels[l], width_count, widths, R->h_sd + o, NULL, 0, 0, 1 + l % 4, 0);
        if (isfinite(R->fitC[l])) {
            for (int j = 0; j < 200; ++j) {
                double w = widths[0] + (widths[width_count - 1] - widths[0]) * j / 199.0;
                curve_x[l][j] = w;
                curve_y[l][j] = exp(R->fitA[l] + R->fitB[l] * w + R->fitC[l] * w * w);
            }
            series[ns++] = SERIES(NULL, 200, curve_x[l], curve_y[l], NULL, 1, 0, 0, 1);
        }
    }
    plot = (StudyPlot){
        "sigma_h and Gaussian fits (004 fig. 2.14)", "w / d", "sigma_h / d", 0, ns, series, 0};
    status |= reduction_plot(R, &plot, "sigma_h.png");
    return status;
}

/* w_t against 1/L with its line (004 fig. 2.15), and the arch composition (004 figs. 3.6,
 * 3.8). */
static int plot_fits(const Reduction *R)
{
    AppPlotSeries series[2 * MAX_LENGTHS + 2];
    char labels[MAX_LENGTHS][32], title[128];
    int status = 0, ns = 0;
    double line_x[2] = {0.0, 0.0}, line_y[2];
    for (int l = 0; l < R->length_count; ++l)
        line_x[1] = fmax(line_x[1], R->inv[l]);
    line_y[0] = R->wc;
    line_y[1] = R->wc + R->slope * line_x[1];
    series[0] = SERIES("w_t", R->length_count, R->inv, R->w_t, NULL, 0, 0, 1, 0);
    series[1] = SERIES("linear fit", 2, line_x, line_y, NULL, 1, 1, 0, 0);
    snprintf(title, sizeof title, "w_t against 1/L: w_c = %.3g +- %.2g d (004 fig. 2.15)", R->wc,
             R->wc_err);
    StudyPlot plot = {title, "1/L (1/d)", "w_t / d", 0, isfinite(R->wc) ? 2 : 1, series, 0};
    status |= reduction_plot(R, &plot, "wt.png");
    for (int l = 0; l < R->length_count && ns + 2 <= 2 * MAX_LENGTHS; ++l) {
        snprintf(labels[l], sizeof labels[l], "L = %g d", R->lengths[l]);
        size_t o = (size_t)l * (size_t)R->width_count;
        series[ns++] =
            SERIES(labels[l], R->width_count, R->widths, R->qs_pile + o, NULL, 1, 1, 1 + l % 4, 0);
        series[ns++] =
            SERIES(NULL, R->width_count, R->widths, R->qs_arch + o, NULL, 1, 0, 1 + l % 4, 1);
    }
    plot = (StudyPlot){"species-0 fraction: pile (dashed) and arch (004 figs. 3.6, 3.8)",
                       "w / d",
                       "q (1)",
                       0,
                       ns,
                       series,
                       0};
    status |= reduction_plot(R, &plot, "composition.png");
    return status;
}

/* F(s) on semi-log axes for L = lengths[l], a few widths (004 fig. 2.16): 0, -1 when not drawn,
 * -2 when out of memory. */
static int plot_fs(const Reduction *R, int l)
{
    AppPlotSeries series[8];
    int samples = R->samples, width_count = R->width_count, ns = 0, status = 0;
    double *xs = calloc((size_t)samples * 8 + 8, sizeof(double));
    double *ys = calloc((size_t)samples * 8 + 8, sizeof(double));
    char wl[8][32], title[128], path[PATH + 64];
    if (!xs || !ys) {
        free(xs);
        free(ys);
        return -2;
    }
    size_t off = 0;
    for (int j = 0; j < 8 && j < width_count; ++j) {
        int k = width_count <= 8 ? j : j * (width_count - 1) / 7;
        const Cell *c = &R->cells[(size_t)l * (size_t)width_count + (size_t)k];
        if (c->size_count == 0)
            continue;
        int m = 0;
        for (int q = 0; q < c->size_count && m < samples; ++q) {
            if (q > 0 && c->sizes[q] == c->sizes[q - 1])
                continue;
            xs[off + (size_t)m] = (double)c->sizes[q];
            ys[off + (size_t)m] = (double)(c->size_count - q) / c->size_count;
            ++m;
        }
        snprintf(wl[j], sizeof wl[j], "w = %g d", R->widths[k]);
        series[ns++] = SERIES(wl[j], m, xs + off, ys + off, NULL, 1, 0, 1 + j % 4, 0);
        off += (size_t)samples;
    }
    snprintf(title, sizeof title, "F(s), L = %g d (004 fig. 2.16)", R->lengths[l]);
    StudyPlot plot = {title, "s (grains)", "F(s) = P(size >= s)", 1, ns, series, 1};
    snprintf(path, sizeof path, "%s/L%g/Fs.png", R->dir, R->lengths[l]);
    if (ns > 0)
        status = study_plot(R->render, R->scene, &plot, path, R->err, R->err_size);
    free(xs);
    free(ys);
    return status ? -1 : 0;
}

/* Every plot of the reduction: 0, -1 when one was not drawn, -2 when out of memory. */
static int reduction_plots(const Reduction *R)
{
    int status = plot_heights(R);
    status |= plot_fits(R);
    for (int l = 0; l < R->length_count; ++l) {
        int rc = plot_fs(R, l);
        if (rc == -2)
            return -2;
        status |= rc;
    }
    return status ? -1 : 0;
}

int app_study_reduce(const Scene *scene, const char *dir, const double *lengths, int length_count,
                     const double *widths, int width_count, int samples, const AppRender *render,
                     char *err, size_t err_size)
{
    Reduction R = {.scene = scene,
                   .dir = dir,
                   .lengths = lengths,
                   .widths = widths,
                   .length_count = length_count,
                   .width_count = width_count,
                   .samples = samples,
                   .render = render,
                   .err = err,
                   .err_size = err_size};
    int rc = reduction_init(&R) != 0 ? out_of_memory(err, err_size) : 0;
    for (int l = 0; rc == 0 && l < length_count; ++l)
        rc = reduce_length(&R, l);
    if (rc == 0) {
        if (app_study_species_marked(scene, NULL) < 0)
            fprintf(stderr, "sablier: study: no species maps: the scene's discharge rows have "
                            "one species (or two of the same diameter and density)\n");
        char path[PATH + 64];
        snprintf(path, sizeof path, "%s/study.csv", dir);
        if (app_write_atomic(path, R.study.s) != 0)
            R.status = -1;
        rc = write_fits(&R);
    }
    if (rc == 0 && render && render->plot && R.status == 0) {
        int plots = reduction_plots(&R);
        if (plots == -2)
            rc = out_of_memory(err, err_size);
        else if (plots != 0)
            R.status = -1;
    }
    reduction_free(&R);
    return rc != 0 || R.status != 0 ? -1 : 0;
}

/* ---------------------------------------------------------------- sablier study */

/* The command line of `sablier study`: the common options (driver.h; --resume is accepted and
 * changes nothing, a study always resumes) and its own (the lists and counts go into its Study). */
typedef struct StudyArgs {
    AppDriverArgs d;
    const char *lengths_text, *widths_text;
    long samples;
    int reduce_only;
} StudyArgs;

static const AppDriverSpec STUDY_SPEC = {.usage = APP_STUDY_USAGE,
                                         .jobs_max = 256,
                                         .set_error = "bad --set",
                                         .no_quiet = 1,
                                         .missing = "missing SCENE"};

/* --L and --widths into st: 0, or the exit status of a bad list. */
static int parse_lists(Study *st, const char *lengths_text, const char *widths_text)
{
    st->width_count = app_discharge_parse_widths(widths_text, st->widths, MAX_WIDTHS);
    if (st->width_count <= 0)
        return app_usage_error(APP_STUDY_USAGE, "--widths must be A:B:STEP or a list, got",
                               widths_text);
    if (lengths_text) {
        st->length_count = app_discharge_parse_widths(lengths_text, st->lengths, MAX_LENGTHS);
        if (st->length_count <= 0)
            return app_usage_error(APP_STUDY_USAGE, "--L must be a list of lengths, got",
                                   lengths_text);
        for (int l = 0; l < st->length_count; ++l)
            if (!(st->lengths[l] >= 2.0))
                return app_usage_error(APP_STUDY_USAGE, "--L lengths must be >= 2 d, got",
                                       lengths_text);
    }
    return 0;
}

/* The options of `sablier study` alone (app_driver_parse's `own`). */
static int study_option(void *ctx, int argc, char **argv, int *i)
{
    StudyArgs *a = ctx;
    const char *value;
    int m;
    if ((m = app_option(argc, argv, i, "--L", &value)) != 0) {
        a->lengths_text = value;
    } else if ((m = app_option(argc, argv, i, "--widths", &value)) != 0) {
        a->widths_text = value;
    } else if ((m = app_option(argc, argv, i, "--samples", &value)) != 0) {
        if (m < 0 || app_parse_count(value, 1, 1000000, &a->samples) < 0)
            return app_usage_error(APP_STUDY_USAGE, "--samples needs a count in [1, 1e6], got",
                                   m < 0 ? "nothing" : value);
    } else if (strcmp(argv[*i], "--reduce-only") == 0) {
        a->reduce_only = m = 1;
    }
    return m < 0 ? 2 : m;
}

/* 0, or the exit status of a bad command line (message on stderr). */
static int parse_study_args(int argc, char **argv, StudyArgs *a, Study *st)
{
    memset(a, 0, sizeof *a);
    a->widths_text = "1.0:7.0:0.2";
    a->samples = 10;
    int rc = app_driver_parse(&STUDY_SPEC, argc, argv, &a->d, study_option, a);
    if (rc != 0)
        return rc;
    st->samples = (int)a->samples;
    st->jobs = (int)a->d.jobs;
    return parse_lists(st, a->lengths_text, a->widths_text);
}

int app_study_parse(int argc, char **argv)
{
    Study st;
    memset(&st, 0, sizeof st);
    StudyArgs args;
    return parse_study_args(argc, argv, &args, &st);
}

int app_study_command(int argc, char **argv, const AppEnv *env)
{
    const AppRender *render = env ? env->render : NULL;
    Study st;
    memset(&st, 0, sizeof st);
    StudyArgs args;
    int rc = parse_study_args(argc, argv, &args, &st);
    if (rc != 0)
        return rc;
    const char *scene_path = args.d.scene, *out = args.d.out, *const *sets = args.d.sets;
    int set_count = args.d.set_count, reduce_only = args.reduce_only;
    char err[4096] = "";
    Scene *scenes[MAX_LENGTHS] = {NULL};
    Scene *base = app_discharge_load_scene(scene_path, sets, set_count, 0.0, err, sizeof err);
    if (!base) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    if (st.length_count == 0) {
        st.lengths[0] = app_discharge_of(base)->base_length;
        st.length_count = 1;
    }
    int status = 0;
    for (int l = 0; l < st.length_count && status == 0; ++l)
        if (!(scenes[l] = app_discharge_load_scene(scene_path, sets, set_count, st.lengths[l], err,
                                                   sizeof err)) ||
            app_discharge_check_widths(scenes[l], st.widths, st.width_count, "study: --widths", err,
                                       sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            status = 2;
        }
    char dir[PATH];
    snprintf(dir, sizeof dir, "%s%s%s", out ? "" : "out/", out ? out : base->name,
             out ? "" : "-study");
    st.scene_path = scene_path;
    st.sets = sets;
    st.set_count = set_count;
    st.dir = dir;
    for (int l = 0; l < st.length_count && status == 0; ++l) {
        char sub[PATH + 64];
        snprintf(sub, sizeof sub, "%s/L%g/samples", dir, st.lengths[l]);
        if (app_make_dirs(sub) != 0) {
            fprintf(stderr, "sablier: cannot create %s: %s\n", sub, strerror(errno));
            status = 2;
        }
    }
    if (status == 0 && !reduce_only)
        status = run_study(&st, scenes);
    if (status != 2 && app_study_reduce(base, dir, st.lengths, st.length_count, st.widths,
                                        st.width_count, st.samples, render, err, sizeof err) != 0) {
        fprintf(stderr, "sablier: study: %s\n", err[0] ? err : "cannot write the tables");
        status = 2;
    }
    for (int l = 0; l < st.length_count; ++l)
        scene_free(scenes[l]);
    scene_free(base);
    return status;
}
