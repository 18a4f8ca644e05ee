/* SPDX-License-Identifier: MIT */
/* measures.c: the `measures` lists of a scene (top level: every stage; a stage's own: that stage)
 * parsed, checked and run (measures.h, docs/measures.md). Coarse-grained fields are sampled every
 * `every` seconds of a stage and written per sample, or averaged over each `window`; flux counters
 * are updated at every step (sim_flux_update) and written every `every`. */
#include "output/measures.h"

#include "base/checkpoint.h"
#include "base/config.h"
#include "base/util.h"
#include "output/vtk_xml.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum MeasureKind { KIND_GRID, KIND_PROFILE_Y, KIND_PROFILE_X, KIND_FLUX } MeasureKind;

static const char *const kind_names[] = {"grid", "profile_y", "profile_x", "flux", NULL};
static const char *const kernel_names[] = {"lucy", "gaussian", NULL};

#define MEASURE_PATH (SCENE_PATH_MAX + 2 * SCENE_NAME_MAX + 32)

typedef struct Measure {
    char name[SCENE_NAME_MAX];
    MeasureKind kind;
    int stage;            /* -1: every stage */
    double region[4];     /* x0, y0, x1, y1, m */
    double line[4];       /* flux segment, m */
    SimKernel kernel;     /* */
    double width, bin;    /* m */
    double every, window; /* s; window 0 = every sample written */
    int motion;           /* frame: index of a motion, -1 = lab */
    int fields[SIM_CG_FIELD_COUNT], field_count;
    int figures[SIM_CG_FIELD_COUNT], figure_count; /* indices into fields */
    int arrows[2], arrow_count;                    /* indices into fields (grid) */
    int nx, ny;                                    /* nodes */
    /* run */
    SimCoarse *cg;
    SimFlux *flux;
    FILE *csv;
    char path[MEASURE_PATH];
    int vti_count;
    /* samples are due every `every` s of the stage: sample k at k * every after its start, its
     * step rounded from that (never accumulated); the open window j ends at j * window */
    long next_sample, window_index, total_steps, mid_step;
    double t_sum; /* nominal sample times in the open window, s */
    int active;
    int started;  /* 1 once a sample was taken */
    double *last; /* field_count * nodes: the last row written (figures) */
    int have_last;
    long last_count;
    double last_mass, last_t;
    long mid_count;
    double mid_mass, mid_t;
    /* flux: steady mean of each stage's second half (NAN: none) */
    double steady_rate[SCENE_MAX_STAGES], steady_mass_rate[SCENE_MAX_STAGES];
} Measure;

struct AppMeasures {
    const Scene *scene;
    int count;
    Measure m[APP_MEASURES_MAX];
    double *mass; /* per frame index, kg */
    int mass_capacity;
    double frame_vx, frame_vy; /* velocity of the measure's motion, m/s */
};

const AppMeasures *app_measures_of(const Scene *scene)
{
    return scene_experiment_state(scene, &app_measures_experiment);
}

/* ---------------------------------------------------------------- parse */

/* Bounding box of what the scene defines (grains with their radii, walls, the periodic range):
 * the domain a region must lie in. 0, or -1 when the scene has none. */
static int scene_domain(const Scene *scene, double box[4])
{
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    const SimGrainBuffer *g = &scene->grains;
    for (int i = 0; i < g->count; ++i) {
        box[0] = fmin(box[0], g->x[i] - g->radius[i]);
        box[1] = fmin(box[1], g->y[i] - g->radius[i]);
        box[2] = fmax(box[2], g->x[i] + g->radius[i]);
        box[3] = fmax(box[3], g->y[i] + g->radius[i]);
    }
    for (int k = 0; k < scene->def.wall_count; ++k) {
        const SimWall *w = &scene->def.walls[k];
        box[0] = fmin(box[0], fmin(w->x0, w->x1));
        box[1] = fmin(box[1], fmin(w->y0, w->y1));
        box[2] = fmax(box[2], fmax(w->x0, w->x1));
        box[3] = fmax(box[3], fmax(w->y0, w->y1));
    }
    if (scene->def.effects & SIM_EFFECT_PERIODIC_X) {
        box[0] = fmin(box[0], scene->def.domain_x0);
        box[2] = fmax(box[2], scene->def.domain_x1);
    }
    return box[2] > box[0] && box[3] > box[1] ? 0 : -1;
}

/* fields = ["phi", ...] (or figures = [...]): indices into *out. */
static int parse_field_list(AppConfig *p, const config_setting_t *g, const char *key, int *out,
                            int *count)
{
    const config_setting_t *s = app_config_member(g, key);
    *count = 0;
    if (!s)
        return 0;
    int n = config_setting_length(s);
    if ((config_setting_type(s) != CONFIG_TYPE_ARRAY &&
         config_setting_type(s) != CONFIG_TYPE_LIST) ||
        n < 1 || n > SIM_CG_FIELD_COUNT)
        return app_config_fail(p, s, "`%s` must be a list of 1 to %d field names", key,
                               SIM_CG_FIELD_COUNT);
    for (int k = 0; k < n; ++k) {
        const config_setting_t *e = config_setting_get_elem(s, (unsigned)k);
        const char *name =
            config_setting_type(e) == CONFIG_TYPE_STRING ? config_setting_get_string(e) : NULL;
        int f = name ? sim_coarse_field_from_name(name) : -1;
        if (f < 0)
            return app_config_fail(p, e,
                                   "unknown field `%s` in `%s` (phi rho jx jy vx vy T kxx kxy kyy "
                                   "cxx cxy cyx cyy sxx sxy syx syy p z fxx fxy fyy)",
                                   name ? name : "?", key);
        out[(*count)++] = f;
    }
    return 1;
}

/* The figures: `figure = true` (every field) or `figures = [names]` (each among `fields`). */
static int parse_figures(AppConfig *p, const config_setting_t *g, Measure *m)
{
    int all = 0, named[SIM_CG_FIELD_COUNT], n = 0;
    if (app_config_bool(p, g, "figure", &all) < 0 ||
        parse_field_list(p, g, "figures", named, &n) < 0)
        return -1;
    if (all)
        for (int k = 0; k < m->field_count; ++k)
            m->figures[m->figure_count++] = k;
    for (int k = 0; k < n && !all; ++k) {
        int found = -1;
        for (int q = 0; q < m->field_count; ++q)
            if (m->fields[q] == named[k])
                found = q;
        if (found < 0)
            return app_config_fail(p, app_config_member(g, "figures"),
                                   "figure field `%s` is not in `fields`",
                                   sim_coarse_field_name((SimCoarseField)named[k]));
        m->figures[m->figure_count++] = found;
    }
    int pair[SIM_CG_FIELD_COUNT];
    if (parse_field_list(p, g, "arrows", pair, &n) < 0)
        return -1;
    const config_setting_t *where = app_config_member(g, "arrows");
    if (where && (n != 2 || m->kind != KIND_GRID))
        return app_config_fail(p, where, "`arrows` is two fields of a grid, e.g. [\"vx\", \"vy\"]");
    for (int k = 0; k < n; ++k) {
        m->arrows[k] = -1;
        for (int q = 0; q < m->field_count; ++q)
            if (m->fields[q] == pair[k])
                m->arrows[k] = q;
        if (m->arrows[k] < 0)
            return app_config_fail(p, where, "arrow field `%s` is not in `fields`",
                                   sim_coarse_field_name((SimCoarseField)pair[k]));
    }
    m->arrow_count = n;
    return 0;
}

/* The region inside the domain, the kernel, bins and the node bound. */
static int parse_geometry(AppConfig *p, const config_setting_t *g, const Scene *scene, Measure *m)
{
    double domain[4];
    int have_domain = scene_domain(scene, domain) == 0;
    int found = app_config_vector(p, g, "region", m->region, 4);
    if (found < 0)
        return -1;
    if (!found && !have_domain)
        return app_config_fail(p, g,
                               "`region` = [x0, y0, x1, y1] is required (the scene "
                               "defines no grains or walls to take the domain from)");
    if (!found)
        memcpy(m->region, domain, sizeof domain);
    const config_setting_t *where = app_config_member(g, "region");
    if (!(m->region[2] > m->region[0]) || !(m->region[3] > m->region[1]))
        return app_config_fail(p, where, "`region` must be [x0, y0, x1, y1] with x1 > x0, y1 > y0");
    double slack = 1e-9 * fmax(1.0, fmax(fabs(domain[2] - domain[0]), fabs(domain[3] - domain[1])));
    if (found && have_domain &&
        (m->region[0] < domain[0] - slack || m->region[1] < domain[1] - slack ||
         m->region[2] > domain[2] + slack || m->region[3] > domain[3] + slack))
        return app_config_fail(p, where,
                               "`region` [%g, %g, %g, %g] lies outside the domain [%g, %g, %g, %g] "
                               "(the scene's grains, walls and periodic range)",
                               m->region[0], m->region[1], m->region[2], m->region[3], domain[0],
                               domain[1], domain[2], domain[3]);
    int kernel = 0;
    if (app_config_choice(p, g, "kernel", kernel_names, &kernel) < 0 ||
        app_config_need_number(p, g, "width", "a field measure", &m->width) < 0 ||
        app_config_positive(p, g, "width", m->width) < 0)
        return -1;
    m->kernel = (SimKernel)kernel;
    m->bin = 0.5 * m->width;
    int cells = 0;
    double length =
        m->kind == KIND_PROFILE_X ? m->region[2] - m->region[0] : m->region[3] - m->region[1];
    if (m->kind == KIND_GRID)
        length = m->region[2] - m->region[0];
    if (app_config_number(p, g, "bin", &m->bin) < 0 ||
        app_config_positive(p, g, "bin", m->bin) < 0 ||
        app_config_int_in(p, g, "cells", 1, APP_MEASURES_MAX_NODES, &cells) < 0)
        return -1;
    if (cells > 0 && app_config_member(g, "bin"))
        return app_config_fail(p, app_config_member(g, "cells"), "give `bin` or `cells`, not both");
    if (cells > 0)
        m->bin = length / cells;
    double fx = ceil((m->region[2] - m->region[0]) / m->bin - 1e-9);
    double fy = ceil((m->region[3] - m->region[1]) / m->bin - 1e-9);
    double nodes = m->kind == KIND_GRID ? fx * fy : m->kind == KIND_PROFILE_Y ? fy : fx;
    if (!(nodes <= APP_MEASURES_MAX_NODES))
        return app_config_fail(p, app_config_member(g, cells > 0 ? "cells" : "bin"),
                               "the %s is too fine: %.0f nodes (at most %d; each holds 16 sums)",
                               kind_names[m->kind], nodes, APP_MEASURES_MAX_NODES);
    if (m->width < m->bin)
        return app_config_fail(p, app_config_member(g, "width"),
                               "`width` (%g m) must be at least the cell side (%g m)", m->width,
                               m->bin);
    m->nx = m->kind == KIND_PROFILE_Y ? 1 : (int)fx;
    m->ny = m->kind == KIND_PROFILE_X ? 1 : (int)fy;
    return 0;
}

/* every, window (<= each stage the measure runs in), frame. */
static int parse_timing(AppConfig *p, const config_setting_t *g, const Scene *scene, Measure *m)
{
    m->every = scene->output.energy_every;
    m->window = 0.0;
    const char *frame = NULL;
    if (app_config_number(p, g, "every", &m->every) < 0 ||
        app_config_positive(p, g, "every", m->every) < 0 ||
        app_config_number(p, g, "window", &m->window) < 0 ||
        app_config_non_negative(p, g, "window", m->window) < 0 ||
        app_config_string(p, g, "frame", &frame) < 0)
        return -1;
    if (m->window > 0.0 && m->window < m->every)
        return app_config_fail(p, app_config_member(g, "window"),
                               "`window` (%g s) must be 0 or at least `every` (%g s)", m->window,
                               m->every);
    for (int k = 0; k < scene->stage_count; ++k) {
        const SceneStage *st = &scene->stages[k];
        if ((m->stage >= 0 && k != m->stage) || (m->stage < 0 && !(st->duration > 0.0)))
            continue;
        if (m->window > st->duration)
            return app_config_fail(p, app_config_member(g, "window"),
                                   "`window` (%g s) is longer than stage %s (%g s)", m->window,
                                   st->name, st->duration);
    }
    m->motion = -1;
    for (int k = 0; frame && k < scene->def.motion_count; ++k)
        if (strcmp(scene->motion_names[k], frame) == 0)
            m->motion = k;
    if (frame && m->motion < 0)
        return app_config_fail(p, app_config_member(g, "frame"), "no motion named `%s`", frame);
    return 0;
}

static int parse_one(AppConfig *p, const config_setting_t *g, const Scene *scene, int stage,
                     Measure *m)
{
    static const char *const keys[] = {"name",   "kind",    "region", "kernel", "width", "bin",
                                       "cells",  "fields",  "every",  "window", "frame", "line",
                                       "figure", "figures", "arrows", NULL};
    static const char *const flux_keys[] = {"name", "kind", "line", "every", NULL};
    const char *name = NULL;
    int kind = 0;
    memset(m, 0, sizeof *m);
    m->stage = stage;
    if (app_config_keys(p, g, "measures", keys, NULL) < 0 ||
        app_config_need(p, g, "name", "a measure") < 0 ||
        app_config_string(p, g, "name", &name) < 0 ||
        app_config_need(p, g, "kind", "a measure") < 0 ||
        app_config_choice(p, g, "kind", kind_names, &kind) < 0)
        return -1;
    Loader names = {.p = *p};
    if (loader_check_file_name(&names, g, "name", name) < 0) {
        p->failed = 1;
        return -1;
    }
    snprintf(m->name, sizeof m->name, "%s", name);
    m->kind = (MeasureKind)kind;
    if (m->kind == KIND_FLUX) {
        if (app_config_keys(p, g, "measures (flux)", flux_keys, NULL) < 0 ||
            app_config_need(p, g, "line", "a flux measure") < 0 ||
            app_config_vector(p, g, "line", m->line, 4) < 0 || parse_timing(p, g, scene, m) < 0)
            return -1;
        if (m->line[0] == m->line[2] && m->line[1] == m->line[3])
            return app_config_fail(p, app_config_member(g, "line"), "`line` has zero length");
        return 0;
    }
    if (app_config_need(p, g, "fields", "a field measure") < 0 ||
        parse_field_list(p, g, "fields", m->fields, &m->field_count) < 0 ||
        parse_geometry(p, g, scene, m) < 0 || parse_timing(p, g, scene, m) < 0 ||
        parse_figures(p, g, m) < 0)
        return -1;
    return 0;
}

/* The files measure m writes (its CSV; a grid's VTK folder; its figures) claimed in the output
 * folder, against the run's, the stages', the figures' and the other measures' files. */
static int claim_files(AppConfig *p, const config_setting_t *g, Scene *scene, const Measure *m)
{
    const config_setting_t *at = app_config_member(g, "name");
    char what[SCENE_NAME_MAX + 16], file[2 * SCENE_NAME_MAX + 16];
    snprintf(what, sizeof what, "measure `%s`", m->name);
    snprintf(file, sizeof file, "%s.csv", m->name);
    int rc = scene_claim_output(scene, p, at, what, file);
    if (rc == 0 && m->kind == KIND_GRID) {
        snprintf(file, sizeof file, "%s/", m->name);
        rc = scene_claim_output(scene, p, at, what, file);
    }
    for (int k = 0; rc == 0 && k < m->figure_count; ++k) {
        snprintf(file, sizeof file, "%s_%s.png", m->name,
                 sim_coarse_field_name((SimCoarseField)m->fields[m->figures[k]]));
        rc = scene_claim_output(scene, p, at, what, file);
    }
    if (rc == 0 && m->arrow_count > 0) {
        snprintf(file, sizeof file, "%s_arrows.png", m->name);
        rc = scene_claim_output(scene, p, at, what, file);
    }
    return rc;
}

/* One `measures` list (top level: stage -1). */
static int parse_list(AppConfig *p, const config_setting_t *list, Scene *scene, int stage,
                      AppMeasures *out)
{
    for (int k = 0; list && k < config_setting_length(list); ++k) {
        const config_setting_t *g = config_setting_get_elem(list, (unsigned)k);
        if (out->count >= APP_MEASURES_MAX)
            return app_config_fail(p, g, "at most %d measures", APP_MEASURES_MAX);
        Measure *m = &out->m[out->count];
        if (parse_one(p, g, scene, stage, m) < 0)
            return -1;
        for (int q = 0; q < out->count; ++q)
            if (strcmp(out->m[q].name, m->name) == 0)
                return app_config_fail(p, app_config_member(g, "name"),
                                       "a measure named `%s` is declared twice", m->name);
        if (claim_files(p, g, scene, m) < 0)
            return -1;
        out->count++;
    }
    return 0;
}

static int measures_parse(const config_setting_t *root, const config_setting_t *group, Scene *scene,
                          void **state, char *err, size_t err_size)
{
    (void)group;
    *state = NULL;
    AppConfig p = {.path = scene->path, .err = err, .err_size = err_size, .group = "measures"};
    AppMeasures *ms = calloc(1, sizeof *ms);
    if (!ms)
        return app_config_fail(&p, NULL, "out of memory");
    const config_setting_t *list = NULL, *stages = config_setting_get_member(root, "stages");
    int rc = app_config_list(&p, root, "measures", &list) < 0 ? -1 : 0;
    if (rc == 0)
        rc = parse_list(&p, list, scene, -1, ms);
    for (int k = 0;
         rc == 0 && stages && k < scene->stage_count && k < config_setting_length(stages); ++k) {
        const config_setting_t *g = config_setting_get_elem(stages, (unsigned)k);
        rc =
            app_config_list(&p, g, "measures", &list) < 0 ? -1 : parse_list(&p, list, scene, k, ms);
    }
    if (rc != 0 || ms->count == 0) {
        free(ms);
        return rc;
    }
    ms->scene = scene;
    *state = ms;
    return 0;
}

static void measure_release(Measure *m)
{
    sim_coarse_destroy(m->cg);
    sim_flux_destroy(m->flux);
    m->cg = NULL;
    m->flux = NULL;
    free(m->last);
    m->last = NULL;
}

static void measures_free(void *state)
{
    AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        app_tmp_discard(&ms->m[k].csv, ms->m[k].path);
        measure_release(&ms->m[k]);
    }
    free(ms->mass);
    free(ms);
}

static void measures_describe_stage(const void *state, int stage, FILE *out)
{
    const AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        const Measure *m = &ms->m[k];
        if (m->stage >= 0 && m->stage != stage)
            continue;
        char length[32], time[32];
        scene_unit_after(ms->scene, SCENE_LENGTH, length, sizeof length);
        scene_unit_after(ms->scene, SCENE_TIME, time, sizeof time);
        fprintf(out, ", measure %s (%s", m->name, kind_names[m->kind]);
        if (m->kind != KIND_FLUX)
            fprintf(out, ", %d x %d nodes, width %g%s", m->nx, m->ny, m->width, length);
        fprintf(out, ", every %g%s)", m->every, time);
    }
}

/* ---------------------------------------------------------------- run */

static int measures_begin(void *state, AppContext *c)
{
    AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        Measure *m = &ms->m[k];
        char header[64 + SIM_CG_FIELD_COUNT * 8];
        int n = snprintf(header, sizeof header, "%s",
                         m->kind == KIND_FLUX        ? "t,count,mass,rate,mass_rate"
                         : m->kind == KIND_GRID      ? "t,x,y"
                         : m->kind == KIND_PROFILE_Y ? "t,y"
                                                     : "t,x");
        for (int f = 0; f < m->field_count; ++f)
            n += snprintf(header + n, sizeof header - (size_t)n, ",%s",
                          sim_coarse_field_name((SimCoarseField)m->fields[f]));
        snprintf(m->path, sizeof m->path, "%s/%s.csv", c->out_dir, m->name);
        m->csv = app_tmp_open(m->path, header);
        if (!m->csv) {
            snprintf(c->err, c->err_size, "cannot write %s.tmp", m->path);
            return -1;
        }
        for (int s = 0; s < SCENE_MAX_STAGES; ++s)
            m->steady_rate[s] = m->steady_mass_rate[s] = NAN;
        if (m->kind == KIND_GRID) {
            char dir[MEASURE_PATH];
            snprintf(dir, sizeof dir, "%s/%s", c->out_dir, m->name);
            if (app_make_dirs(dir) != 0) {
                snprintf(c->err, c->err_size, "cannot create %s", dir);
                return -1;
            }
        }
    }
    return 0;
}

static SimCoarseDef coarse_def(const Measure *m)
{
    SimCoarseDef d = sim_coarse_def_default();
    d.kernel = m->kernel;
    d.width = m->width;
    d.geometry = m->kind == KIND_GRID        ? SIM_COARSE_GRID
                 : m->kind == KIND_PROFILE_Y ? SIM_COARSE_PROFILE_Y
                                             : SIM_COARSE_PROFILE_X;
    d.x0 = m->region[0];
    d.y0 = m->region[1];
    d.x1 = m->region[2];
    d.y1 = m->region[3];
    d.cell_x = d.cell_y = m->bin;
    d.nx = m->nx;
    d.ny = m->ny;
    for (int f = 0; f < m->field_count; ++f)
        d.contacts |= sim_coarse_field_needs_contacts((SimCoarseField)m->fields[f]);
    return d;
}

/* The measure's counter (updated at the world as it is) or its coarse-graining sums and last
 * row, made when missing. 0, or -1 with the message. */
static int measure_objects(Measure *m, AppContext *c)
{
    if (m->kind == KIND_FLUX) {
        if (!m->flux)
            m->flux = sim_flux_create(m->line[0], m->line[1], m->line[2], m->line[3]);
        if (!m->flux || sim_flux_update(m->flux, c->world) != SIM_OK) {
            snprintf(c->err, c->err_size, "measure %s: out of memory", m->name);
            return -1;
        }
        return 0;
    }
    if (!m->cg) {
        SimError e;
        SimCoarseDef d = coarse_def(m);
        m->cg = sim_coarse_create(&d, &e);
        m->last = calloc((size_t)m->field_count * (size_t)(m->nx * m->ny), sizeof *m->last);
        if (!m->cg || !m->last) {
            snprintf(c->err, c->err_size, "measure %s: %s", m->name,
                     m->cg ? "out of memory" : e.message);
            return -1;
        }
    }
    return 0;
}

static int measures_stage_begin(void *state, AppContext *c)
{
    AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        Measure *m = &ms->m[k];
        m->active = m->stage < 0 || m->stage == c->stage;
        if (!m->active)
            continue;
        /* a sample at the stage's start only in the first stage the measure runs in, and not
           into a window (flux: no row at the start) */
        m->next_sample = m->kind != KIND_FLUX && !m->started && m->window == 0.0 ? 0 : 1;
        m->window_index = 1;
        m->total_steps = c->stage_steps;
        m->mid_step = c->stage_steps / 2;
        m->t_sum = 0.0;
        if (measure_objects(m, c) != 0)
            return -1;
        if (m->kind == KIND_FLUX) {
            sim_flux_totals(m->flux, &m->last_count, &m->last_mass);
            m->last_t = sim_world_time(c->world);
            m->mid_count = m->last_count;
            m->mid_mass = m->last_mass;
            m->mid_t = m->last_t;
            continue;
        }
        sim_coarse_clear(m->cg);
    }
    return 0;
}

/* Velocity of the measure's frame (its motion, as the walls move: A sin(2 pi f t + phase)). */
static void frame_velocity(const AppContext *c, const Measure *m, double t, double *vx, double *vy)
{
    *vx = *vy = 0.0;
    if (m->motion < 0)
        return;
    SimWorldDef def = scene_world_def(c->scene, c->stage); /* the stage's motions */
    const SimMotion *mo = &def.motions[m->motion];
    double w = 2.0 * SIM_PI * mo->frequency;
    double speed = mo->amplitude * w * cos(w * t + mo->phase);
    *vx = speed * mo->direction_x;
    *vy = speed * mo->direction_y;
}

/* A per-mass mean (v_x, v_y, T = sum m v / sum m) is undefined in a bin without grains (the
 * coarse-grained density rho is 0 there): those values become NaN in m->last, so the CSV says
 * "nan" and the plots lift their pen there instead of drawing 0 (docs/measures.md#empty-bins). */
static int empty_bins(Measure *m)
{
    int nodes = sim_coarse_nodes(m->cg), masked = 0;
    for (int f = 0; f < m->field_count; ++f)
        masked |=
            m->fields[f] == SIM_CG_VX || m->fields[f] == SIM_CG_VY || m->fields[f] == SIM_CG_T;
    if (!masked)
        return 0;
    double *rho = malloc((size_t)nodes * sizeof *rho);
    if (!rho)
        return -1;
    sim_coarse_field(m->cg, SIM_CG_RHO, rho);
    for (int f = 0; f < m->field_count; ++f) {
        if (m->fields[f] != SIM_CG_VX && m->fields[f] != SIM_CG_VY && m->fields[f] != SIM_CG_T)
            continue;
        for (int k = 0; k < nodes; ++k)
            if (!(rho[k] > 0.0))
                m->last[(size_t)f * nodes + k] = (double)NAN;
    }
    free(rho);
    return 0;
}

/* One CSV row per node (and a .vti for a grid) of the sums so far, then cleared. */
static int write_fields(Measure *m, const AppContext *c)
{
    int nodes = sim_coarse_nodes(m->cg), samples = sim_coarse_samples(m->cg);
    if (samples == 0)
        return 0;
    double t = m->t_sum / samples;
    for (int f = 0; f < m->field_count; ++f)
        sim_coarse_field(m->cg, (SimCoarseField)m->fields[f], m->last + (size_t)f * nodes);
    if (empty_bins(m) != 0)
        return -1;
    m->have_last = 1;
    for (int k = 0; k < nodes; ++k) {
        double x, y;
        sim_coarse_node(m->cg, k, &x, &y);
        fprintf(m->csv, "%.9g", t);
        if (m->kind != KIND_PROFILE_Y)
            fprintf(m->csv, ",%.9g", x);
        if (m->kind != KIND_PROFILE_X)
            fprintf(m->csv, ",%.9g", y);
        for (int f = 0; f < m->field_count; ++f)
            fprintf(m->csv, ",%.9g", m->last[(size_t)f * nodes + k]);
        fputc('\n', m->csv);
    }
    sim_coarse_clear(m->cg);
    m->t_sum = 0.0;
    if (m->kind != KIND_GRID)
        return 0;
    /* VTK XML ImageData: point data on the nodes (ParaView, VTK's XML reader), the sample time
     * as TimeValue; raw binary above APP_VTK_BINARY_POINTS nodes as the dumps */
    char path[MEASURE_PATH + SCENE_NAME_MAX + 16], attributes[256];
    snprintf(path, sizeof path, "%s/%s/%s_%05d.vti", c->out_dir, m->name, m->name, m->vti_count++);
    snprintf(attributes, sizeof attributes,
             "WholeExtent=\"0 %d 0 %d 0 0\" Origin=\"%.17g %.17g 0\" Spacing=\"%.17g %.17g 1\"",
             m->nx - 1, m->ny - 1, m->region[0] + 0.5 * m->bin, m->region[1] + 0.5 * m->bin, m->bin,
             m->bin);
    AppVtk v;
    if (app_vtk_begin(&v, path, "ImageData", attributes, nodes > APP_VTK_BINARY_POINTS, t) != 0)
        return -1;
    fprintf(v.out, "<Piece Extent=\"0 %d 0 %d 0 0\">\n<PointData>\n", m->nx - 1, m->ny - 1);
    for (int f = 0; f < m->field_count; ++f)
        app_vtk_doubles(&v, sim_coarse_field_name((SimCoarseField)m->fields[f]), 1, (size_t)nodes,
                        m->last + (size_t)f * nodes);
    fputs("</PointData>\n</Piece>\n", v.out);
    return app_vtk_end(&v, path);
}

static int frame_masses(AppMeasures *ms, SimWorld *world, SimFrame *frame)
{
    sim_world_frame(world, frame);
    if (frame->count > ms->mass_capacity) {
        double *p = realloc(ms->mass, (size_t)frame->count * sizeof *p);
        if (!p)
            return -1;
        ms->mass = p;
        ms->mass_capacity = frame->count;
    }
    sim_world_masses(world, ms->mass);
    return 0;
}

static void flux_row(Measure *m, const AppContext *c)
{
    long count;
    double mass, t = sim_world_time(c->world);
    sim_flux_totals(m->flux, &count, &mass);
    double span = t - m->last_t;
    fprintf(m->csv, "%.9g,%ld,%.9g,%.9g,%.9g\n", t, count, mass,
            span > 0.0 ? (double)(count - m->last_count) / span : 0.0,
            span > 0.0 ? (mass - m->last_mass) / span : 0.0);
    m->last_count = count;
    m->last_mass = mass;
    m->last_t = t;
}

/* The step of the stage at which sample k is due: k * every after the stage's start, rounded to
 * a step from k (never accumulated), the stage's last step at the latest so that a sample at its
 * end is taken; -1 when k lies past the stage's end. */
static long sample_step(const Measure *m, const AppContext *c, long k)
{
    double dt = sim_world_time_step(c->world), t = (double)k * m->every;
    if (t > c->scene->stages[c->stage].duration + 0.5 * dt)
        return -1;
    long step = (long)llround(t / dt);
    return step < c->stage_steps ? step : c->stage_steps;
}

/* 1 when a sample is due at step `done`, its index in *k (the last one due when `every` is
 * shorter than a step); the next sample's index advanced past it. */
static int sample_due(Measure *m, const AppContext *c, long done, long *k)
{
    long step = sample_step(m, c, m->next_sample);
    if (step < 0 || step > done)
        return 0;
    while ((step = sample_step(m, c, m->next_sample + 1)) >= 0 && step <= done)
        ++m->next_sample;
    *k = m->next_sample++;
    return 1;
}

/* 1 when the open window closes at step `done`, where sample k (-1: none) was just added: its
 * end j * window reached by the sample's time, or the stage's last step when the window ends
 * with the stage. The next window's index set from the sample's time. */
static int window_closes(Measure *m, const AppContext *c, long done, long k)
{
    const double eps = 1e-9 * m->every;
    const double end = (double)m->window_index * m->window;
    const double dt = sim_world_time_step(c->world);
    int close = k >= 0 && (double)k * m->every >= end - eps;
    if (!close && done == c->stage_steps && end <= c->scene->stages[c->stage].duration + 0.5 * dt)
        close = sim_coarse_samples(m->cg) > 0;
    if (close)
        m->window_index = k >= 0 ? (long)floor(((double)k * m->every + eps) / m->window) + 1
                                 : m->window_index + 1;
    return close;
}

static void measures_step(void *state, AppContext *c, long done)
{
    AppMeasures *ms = state;
    SimFrame frame;
    int framed = 0;
    for (int j = 0; j < ms->count; ++j) {
        Measure *m = &ms->m[j];
        if (!m->active)
            continue;
        long k = -1;
        int sample = sample_due(m, c, done, &k);
        if (m->kind == KIND_FLUX) {
            if (done > 0 && sim_flux_update(m->flux, c->world) != SIM_OK)
                continue; /* out of memory: the count stops (reported by the step soon after) */
            if (done == m->mid_step) {
                sim_flux_totals(m->flux, &m->mid_count, &m->mid_mass);
                m->mid_t = sim_world_time(c->world);
            }
            if (sample)
                flux_row(m, c);
            continue;
        }
        if (sample) {
            m->started = 1;
            if (!framed && frame_masses(ms, c->world, &frame) != 0)
                return;
            framed = 1;
            double vx, vy;
            frame_velocity(c, m, sim_world_time(c->world), &vx, &vy);
            if (sim_coarse_add(m->cg, &frame, ms->mass, vx, vy) != SIM_OK)
                continue;
            m->t_sum += c->stage_start + (double)k * m->every; /* the declared sample time */
        }
        if (m->window > 0.0 && !window_closes(m, c, done, sample ? k : -1))
            continue; /* the window is still open */
        if ((sample || m->window > 0.0) && write_fields(m, c) != 0)
            fprintf(stderr, "sablier: warning: measure %s: cannot write its .vti file\n", m->name);
    }
}

static long measures_next_step(const void *state, const AppContext *c, long done, long next)
{
    const AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        const Measure *m = &ms->m[k];
        if (!m->active)
            continue;
        long due = m->kind == KIND_FLUX ? done + 1 : sample_step(m, c, m->next_sample);
        if (due > done && due < next)
            next = due;
    }
    return next;
}

/* A heat map (grid) or a profile plot (field against height or x) of the last row written. */
/* The map of a grid measure's node values (heat map), with its title and colour-bar label. */
static AppMap grid_map(const Measure *m, const char *title, const char *label, const double *values,
                       const char *const axes[2])
{
    return (AppMap){.title = title,
                    .x_label = axes[0],
                    .y_label = axes[1],
                    .bar_label = label,
                    .nx = m->nx,
                    .ny = m->ny,
                    .x0 = m->region[0],
                    .y0 = m->region[1],
                    .cell = m->bin,
                    .values = values};
}

/* The axes of a measure's figures, and a field's label: in a scene of its own units
 * (units = "normalised") lengths in d and the field without an SI unit. */
typedef struct FigureLabels {
    char x[32], y[32];
    const char *axes[2];
} FigureLabels;

static void figure_labels(const AppContext *c, FigureLabels *l)
{
    scene_axis_label(c->scene, "x", SCENE_LENGTH, l->x, sizeof l->x);
    scene_axis_label(c->scene, "y", SCENE_LENGTH, l->y, sizeof l->y);
    l->axes[0] = l->x;
    l->axes[1] = l->y;
}

/* The quantity of a field (scene_unit; SI as sim_coarse_field_unit lists them). */
static SceneQuantity field_quantity(SimCoarseField field)
{
    if (field == SIM_CG_PHI || field == SIM_CG_Z || field == SIM_CG_FXX || field == SIM_CG_FXY ||
        field == SIM_CG_FYY)
        return SCENE_DIMENSIONLESS;
    if (field == SIM_CG_RHO)
        return SCENE_AREAL_DENSITY;
    if (field == SIM_CG_JX || field == SIM_CG_JY)
        return SCENE_MOMENTUM_DENSITY;
    if (field == SIM_CG_VX || field == SIM_CG_VY)
        return SCENE_SPEED;
    if (field == SIM_CG_T)
        return SCENE_SPEED_SQUARED;
    return SCENE_STRESS; /* stresses and pressure */
}

/* A field's unit in the scene's units (scene_unit). */
static const char *field_unit(const Scene *scene, SimCoarseField field, int figure)
{
    return scene_unit(scene, field_quantity(field), figure);
}

/* A field's name as plot markup (docs/figures.md#markup): phi as \phi, syy as \sigma_{yy}. */
static const char *field_markup(const char *name)
{
    static const char *const names[][2] = {{"phi", "\\phi"},
                                           {"rho", "\\rho"},
                                           {"jx", "j_x"},
                                           {"jy", "j_y"},
                                           {"vx", "v_x"},
                                           {"vy", "v_y"},
                                           {"kxx", "\\sigma^k_{xx}"},
                                           {"kxy", "\\sigma^k_{xy}"},
                                           {"kyy", "\\sigma^k_{yy}"},
                                           {"cxx", "\\sigma^c_{xx}"},
                                           {"cxy", "\\sigma^c_{xy}"},
                                           {"cyx", "\\sigma^c_{yx}"},
                                           {"cyy", "\\sigma^c_{yy}"},
                                           {"sxx", "\\sigma_{xx}"},
                                           {"sxy", "\\sigma_{xy}"},
                                           {"syx", "\\sigma_{yx}"},
                                           {"syy", "\\sigma_{yy}"},
                                           {"z", "Z"},
                                           {"fxx", "F_{xx}"},
                                           {"fxy", "F_{xy}"},
                                           {"fyy", "F_{yy}"}};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (strcmp(names[k][0], name) == 0)
            return names[k][1];
    return name;
}

/* A field's axis or colour-bar label: its markup name and unit in the scene's units. */
static void field_label(const AppContext *c, const char *name, SimCoarseField field, char *buf,
                        size_t size)
{
    scene_axis_label(c->scene, field_markup(name), field_quantity(field), buf, size);
}

static int draw_arrows(const Measure *m, const AppContext *c)
{
    int nodes = m->nx * m->ny;
    const double *u = m->last + (size_t)m->arrows[0] * nodes;
    const double *v = m->last + (size_t)m->arrows[1] * nodes;
    double *size = malloc((size_t)nodes * sizeof *size);
    if (!size)
        return -1;
    for (int k = 0; k < nodes; ++k)
        size[k] = hypot(u[k], v[k]);
    SimCoarseField fu = (SimCoarseField)m->fields[m->arrows[0]];
    SimCoarseField fv = (SimCoarseField)m->fields[m->arrows[1]];
    char path[MEASURE_PATH + SCENE_NAME_MAX], title[160], label[80], err[512] = "";
    snprintf(path, sizeof path, "%s/%s_arrows.png", c->out_dir, m->name);
    snprintf(title, sizeof title, "%s: (%s, %s) (%s)", m->name,
             field_markup(sim_coarse_field_name(fu)), field_markup(sim_coarse_field_name(fv)),
             m->window > 0.0 ? "window average" : "last sample");
    char name[64];
    snprintf(name, sizeof name, "|(%s, %s)|", sim_coarse_field_name(fu), sim_coarse_field_name(fv));
    field_label(c, name, fu, label, sizeof label);
    FigureLabels axes;
    figure_labels(c, &axes);
    AppMap map = grid_map(m, title, label, size, axes.axes);
    map.arrow_x = u;
    map.arrow_y = v;
    map.arrow_unit = field_unit(c->scene, fu, 1);
    int rc = c->render->map(c->render->context, c->scene, &map, path, err, sizeof err);
    if (rc != 0)
        snprintf(c->err, c->err_size, "measure %s: figure %s: %s", m->name, path, err);
    free(size);
    return rc;
}

static int draw_figure(const Measure *m, const AppContext *c, int figure)
{
    int f = m->figures[figure], nodes = m->nx * m->ny;
    SimCoarseField field = (SimCoarseField)m->fields[f];
    const double *values = m->last + (size_t)f * nodes;
    char path[MEASURE_PATH + SCENE_NAME_MAX], title[160], label[64], err[512] = "";
    snprintf(path, sizeof path, "%s/%s_%s.png", c->out_dir, m->name, sim_coarse_field_name(field));
    snprintf(title, sizeof title, "%s: %s (%s)", m->name,
             field_markup(sim_coarse_field_name(field)),
             m->window > 0.0 ? "window average" : "last sample");
    field_label(c, sim_coarse_field_name(field), field, label, sizeof label);
    FigureLabels axes;
    figure_labels(c, &axes);
    int rc = 0;
    if (m->kind == KIND_GRID) {
        AppMap map = grid_map(m, title, label, values, axes.axes);
        rc = c->render->map
                 ? c->render->map(c->render->context, c->scene, &map, path, err, sizeof err)
                 : 0;
    } else {
        double *pos = malloc((size_t)nodes * sizeof *pos);
        if (!pos)
            return -1;
        for (int k = 0; k < nodes; ++k) {
            double x, y;
            sim_coarse_node(m->cg, k, &x, &y);
            pos[k] = m->kind == KIND_PROFILE_Y ? y : x;
        }
        int along_y = m->kind == KIND_PROFILE_Y;
        AppPlotSeries s = {.label = NULL,
                           .count = nodes,
                           .x = along_y ? values : pos,
                           .y = along_y ? pos : values,
                           .line = 1,
                           .rgb = APP_RGB_AUTO};
        AppPlotPanel panel = {.x_label = along_y ? label : axes.x,
                              .y_label = along_y ? axes.y : label,
                              .legend = APP_LEGEND_NONE,
                              .series_count = 1,
                              .series = &s};
        AppPlot plot = {.title = title,
                        .width = along_y ? 700 : 1000,
                        .height = along_y ? 900 : 600,
                        .panel_count = 1,
                        .panels = &panel,
                        .scene = c->scene->name,
                        .seed = c->scene->seed,
                        .print = &c->scene->style};
        rc =
            c->render->plot ? c->render->plot(c->render->context, &plot, path, err, sizeof err) : 0;
        free(pos);
    }
    if (rc != 0)
        snprintf(c->err, c->err_size, "measure %s: figure %s: %s", m->name, path, err);
    return rc;
}

static int measures_stage_end(void *state, AppContext *c)
{
    AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        Measure *m = &ms->m[k];
        if (!m->active)
            continue;
        m->active = m->stage < 0; /* a stage's own measure ends with it */
        if (m->kind == KIND_FLUX) {
            long count;
            double mass, t = sim_world_time(c->world);
            sim_flux_totals(m->flux, &count, &mass);
            if (t > m->mid_t && c->stage >= 0 && c->stage < SCENE_MAX_STAGES) {
                m->steady_rate[c->stage] = (double)(count - m->mid_count) / (t - m->mid_t);
                m->steady_mass_rate[c->stage] = (mass - m->mid_mass) / (t - m->mid_t);
            }
            continue;
        }
        for (int f = 0; c->render && m->have_last && f < m->figure_count; ++f)
            if (draw_figure(m, c, f) != 0)
                return -1;
        if (c->render && c->render->map && m->have_last && m->arrow_count == 2 &&
            draw_arrows(m, c) != 0)
            return -1;
    }
    return 0;
}

/* DIR/<measure>.pvd: the grid's .vti files with the times they hold (read back from each file,
 * so a resumed run lists the files of both its parts). 0, or -1. */
static int write_vti_pvd(const Measure *m, const AppContext *c)
{
    char path[MEASURE_PATH + SCENE_NAME_MAX + 16], file[MEASURE_PATH + SCENE_NAME_MAX + 16];
    snprintf(path, sizeof path, "%s/%s.pvd", c->out_dir, m->name);
    FILE *out = app_pvd_open(path);
    if (!out)
        return -1;
    for (int k = 0; k < m->vti_count; ++k) {
        snprintf(file, sizeof file, "%s/%s/%s_%05d.vti", c->out_dir, m->name, m->name, k);
        double t = app_vtk_time_value(file);
        snprintf(file, sizeof file, "%s/%s_%05d.vti", m->name, m->name, k);
        if (t == t) /* a file that is gone (NAN) is not listed */
            app_pvd_entry(out, t, 0, file);
    }
    return app_pvd_commit(&out, path);
}

static int measures_end(void *state, AppContext *c, int ok)
{
    (void)ok;
    AppMeasures *ms = state;
    int rc = 0;
    for (int k = 0; k < ms->count; ++k) {
        const char *bad = NULL;
        if (app_tmp_commit(&ms->m[k].csv, ms->m[k].path) != 0)
            bad = ms->m[k].path;
        else if (ms->m[k].kind == KIND_GRID && ms->m[k].vti_count > 0 &&
                 write_vti_pvd(&ms->m[k], c) != 0)
            bad = "a measure's .pvd";
        if (bad && rc == 0) {
            snprintf(c->err, c->err_size, "cannot write %s", bad);
            rc = -1;
        }
    }
    return rc;
}

/* ---------------------------------------------------------------- checkpoints */

/* The numbers of a measure's checkpoint line `measure_K`, in order: copied into v (load = 0) or
 * from v. */
#define MEASURE_NUMBERS 18

static void measure_numbers(Measure *m, double *v, int load)
{
    long spare = 0; /* a slot kept so that the line keeps its length */
    long *l[7] = {&m->next_sample, &m->window_index, &spare,       &m->total_steps,
                  &m->mid_step,    &m->last_count,   &m->mid_count};
    double *d[4] = {&m->t_sum, &m->last_mass, &m->last_t, &m->mid_mass};
    int *n[4] = {&m->active, &m->started, &m->vti_count, &m->have_last};
    for (int k = 0; k < 7; ++k)
        if (load)
            *l[k] = (long)v[k];
        else
            v[k] = (double)*l[k];
    for (int k = 0; k < 4; ++k)
        if (load)
            *d[k] = v[7 + k];
        else
            v[7 + k] = *d[k];
    for (int k = 0; k < 4; ++k)
        if (load)
            *n[k] = (int)v[11 + k];
        else
            v[11 + k] = (double)*n[k];
    if (load) {
        m->mid_t = v[15];
    } else {
        v[15] = m->mid_t;
        v[16] = m->cg ? 1.0 : 0.0;
        v[17] = m->flux ? 1.0 : 0.0;
    }
}

static void measure_key(char *key, size_t size, const char *what, int k)
{
    snprintf(key, size, "%s_%d", what, k);
}

/* A checkpoint: each measure's cadences and windows, its open sums (coarse-grained) or its
 * totals (flux), its last row, its steady rates and the length of its CSV file. */
static int measures_checkpoint(const void *state, const AppContext *c, FILE *out)
{
    const AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k) {
        Measure m = ms->m[k]; /* read only */
        char key[48];
        double v[MEASURE_NUMBERS];
        measure_numbers(&m, v, 0);
        measure_key(key, sizeof key, "measure", k);
        app_checkpoint_put(out, key, v, MEASURE_NUMBERS);
        measure_key(key, sizeof key, "steady", k);
        app_checkpoint_put(out, key, m.steady_rate, SCENE_MAX_STAGES);
        measure_key(key, sizeof key, "steady_mass", k);
        app_checkpoint_put(out, key, m.steady_mass_rate, SCENE_MAX_STAGES);
        if (m.flux) {
            double totals[2];
            long count;
            sim_flux_totals(m.flux, &count, &totals[1]);
            totals[0] = (double)count;
            measure_key(key, sizeof key, "flux", k);
            app_checkpoint_put(out, key, totals, 2);
        }
        if (m.cg) {
            long n = sim_coarse_sum_count(m.cg);
            double *sums = malloc((size_t)(n + 1) * sizeof *sums);
            if (!sums) {
                snprintf(c->err, c->err_size, "measure %s: out of memory", m.name);
                return -1;
            }
            sums[0] = sim_coarse_samples(m.cg);
            sim_coarse_get_sums(m.cg, sums + 1);
            measure_key(key, sizeof key, "sums", k);
            app_checkpoint_put(out, key, sums, n + 1);
            free(sums);
            measure_key(key, sizeof key, "last", k);
            app_checkpoint_put(out, key, m.last, (long)m.field_count * m.nx * m.ny);
        }
        app_checkpoint_file(out, m.path, m.csv);
    }
    return 0;
}

/* One measure from its lines (begin opened its file; its counter or sums made here). */
static int measure_resume(Measure *m, int k, AppContext *c, const char *record)
{
    char key[48];
    double v[MEASURE_NUMBERS], totals[2];
    measure_key(key, sizeof key, "measure", k);
    if (app_checkpoint_take(record, key, v, MEASURE_NUMBERS) != 0)
        return -1;
    measure_numbers(m, v, 1);
    measure_key(key, sizeof key, "steady", k);
    int bad = app_checkpoint_take(record, key, m->steady_rate, SCENE_MAX_STAGES) != 0;
    measure_key(key, sizeof key, "steady_mass", k);
    bad = bad || app_checkpoint_take(record, key, m->steady_mass_rate, SCENE_MAX_STAGES) != 0;
    if (bad || ((v[16] != 0.0 || v[17] != 0.0) && measure_objects(m, c) != 0))
        return -1;
    measure_key(key, sizeof key, "flux", k);
    if (m->flux && app_checkpoint_take(record, key, totals, 2) == 0)
        sim_flux_set_totals(m->flux, (long)totals[0], totals[1]);
    else if (m->flux)
        return -1;
    if (m->cg) {
        long n = sim_coarse_sum_count(m->cg);
        double *sums = malloc((size_t)(n + 1) * sizeof *sums);
        measure_key(key, sizeof key, "sums", k);
        bad = !sums || app_checkpoint_take(record, key, sums, n + 1) != 0;
        if (!bad)
            sim_coarse_set_sums(m->cg, sums + 1, (int)sums[0]);
        free(sums);
        measure_key(key, sizeof key, "last", k);
        if (bad ||
            app_checkpoint_take(record, key, m->last, (long)m->field_count * m->nx * m->ny) != 0)
            return -1;
    }
    return app_checkpoint_reopen(record, m->path, &m->csv);
}

static int measures_resume(void *state, AppContext *c, const char *record)
{
    AppMeasures *ms = state;
    for (int k = 0; k < ms->count; ++k)
        if (measure_resume(&ms->m[k], k, c, record) != 0) {
            if (!c->err[0] || !strstr(c->err, ms->m[k].name))
                snprintf(c->err, c->err_size,
                         "--resume: measure %s: the checkpoint's record is malformed, or %s is "
                         "shorter than it records",
                         ms->m[k].name, ms->m[k].path);
            return -1;
        }
    return 0;
}

/* "measures": {"NAME": {"count": N, "mass": kg, "steady": [{"stage": S, "rate": 1/s,
 * "mass_rate": kg/s}, ...]}, ...} for the flux counters. */
static void measures_summary_json(const void *state, char *out, size_t size)
{
    const AppMeasures *ms = state;
    size_t n = 0;
    int any = 0;
    for (int k = 0; k < ms->count && n < size; ++k) {
        const Measure *m = &ms->m[k];
        if (m->kind != KIND_FLUX || !m->flux)
            continue;
        long count;
        double mass;
        sim_flux_totals(m->flux, &count, &mass);
        n += (size_t)snprintf(out + n, size - n,
                              "%s\"%s\": {\"count\": %ld, \"mass\": %.10g, "
                              "\"steady\": [",
                              any ? ", " : "  \"measures\": {", m->name, count, mass);
        int first = 1;
        for (int s = 0; s < SCENE_MAX_STAGES && n < size; ++s) {
            if (!isfinite(m->steady_rate[s]))
                continue;
            n += (size_t)snprintf(out + n, size - n,
                                  "%s{\"stage\": \"%s\", \"rate\": %.10g, \"mass_rate\": %.10g}",
                                  first ? "" : ", ", ms->scene->stages[s].name, m->steady_rate[s],
                                  m->steady_mass_rate[s]);
            first = 0;
        }
        if (n < size)
            n += (size_t)snprintf(out + n, size - n, "]}");
        any = 1;
    }
    if (any && n < size)
        snprintf(out + n, size - n, "},\n");
    else if (!any && size > 0)
        out[0] = '\0';
}

static const char *const stage_keys[] = {"measures", NULL};

const AppExperiment app_measures_experiment = {
    .name = "measures",
    .group = "measures",
    .stage_keys = stage_keys,
    .parse = measures_parse,
    .free = measures_free,
    .describe_stage = measures_describe_stage,
    .begin = measures_begin,
    .stage_begin = measures_stage_begin,
    .next_step = measures_next_step,
    .step = measures_step,
    .stage_end = measures_stage_end,
    .end = measures_end,
    .checkpoint = measures_checkpoint,
    .resume = measures_resume,
    .summary_json = measures_summary_json,
};
