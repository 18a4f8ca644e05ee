/* SPDX-License-Identifier: MIT */
/* sources.c: insertion sources (sources.h; docs/scenes.md, sources): the `sources` list of a
 * scene and the insertion during a run, in the manner of LAMMPS fix pour / MercuryDPM insertion
 * boundaries (random places in a region, no overlap, a retry budget). */
#include "scene/sources.h"

#include "base/util.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- parsing */

/* The scene's extent: its walls, fixed grains and periodic range; 0 when it has none. */
static int scene_extent(const Scene *scene, double box[4])
{
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    int any = 0;
    for (int k = 0; k < scene->def.wall_count; ++k, any = 1) {
        double x0, y0, x1, y1;
        sim_wall_bounds(&scene->walls[k], &x0, &y0, &x1, &y1);
        box[0] = fmin(box[0], x0);
        box[1] = fmin(box[1], y0);
        box[2] = fmax(box[2], x1);
        box[3] = fmax(box[3], y1);
    }
    const SimGrainBuffer *b = &scene->grains;
    for (int i = 0; i < b->count; ++i)
        if (b->flags[i] & SIM_GRAIN_FIXED) {
            box[0] = fmin(box[0], b->x[i] - b->radius[i]);
            box[1] = fmin(box[1], b->y[i] - b->radius[i]);
            box[2] = fmax(box[2], b->x[i] + b->radius[i]);
            box[3] = fmax(box[3], b->y[i] + b->radius[i]);
            any = 1;
        }
    if (scene->def.effects & SIM_EFFECT_PERIODIC_X) {
        box[0] = scene->def.domain_x0;
        box[2] = scene->def.domain_x1;
    }
    return any;
}

/* The region inside the scene's extent, crossed by no wall and clear of fixed grains. */
static int check_region(Loader *L, const config_setting_t *g, const SceneSource *s)
{
    const Scene *scene = L->scene;
    const config_setting_t *at = app_config_member(g, "region");
    double box[4];
    /* the domain: the walls' and fixed grains' extent in x (the periodic range) and from their
     * lowest point up (a source may pour from above the walls) */
    if (scene_extent(scene, box) && !(s->x0 >= box[0] && s->x1 <= box[2] && s->y0 >= box[1]))
        return app_config_fail(&L->p, at,
                               "`region` [%g, %g, %g, %g] is outside the domain: x in [%g, %g], "
                               "y from %g up (the walls' and fixed grains' extent)",
                               s->x0, s->y0, s->x1, s->y1, box[0], box[2], box[1]);
    const SimGrainBuffer *b = &scene->grains;
    for (int i = 0; i < b->count; ++i) /* a fixed grain reaching into the region */
        if ((b->flags[i] & SIM_GRAIN_FIXED) && b->x[i] + b->radius[i] > s->x0 &&
            b->x[i] - b->radius[i] < s->x1 && b->y[i] + b->radius[i] > s->y0 &&
            b->y[i] - b->radius[i] < s->y1)
            return app_config_fail(&L->p, at,
                                   "`region` overlaps the fixed grain at (%g, %g): keep it clear",
                                   b->x[i], b->y[i]);
    for (int k = 0; k < scene->def.wall_count; ++k)
        for (int p = 0; p <= 256; ++p) {
            double x, y;
            sim_wall_point(&scene->walls[k], p / 256.0, &x, &y);
            if (x > s->x0 && x < s->x1 && y > s->y0 && y < s->y1)
                return app_config_fail(&L->p, at, "`region` overlaps wall %d: keep it clear", k);
        }
    return 0;
}

/* radius = [r_min, r_max] (m) or one radius. */
static int parse_radius(Loader *L, const config_setting_t *g, double *r_min, double *r_max)
{
    const config_setting_t *r = app_config_member(g, "radius");
    if (r && config_setting_is_aggregate(r)) {
        double v[2];
        if (app_config_vector(&L->p, g, "radius", v, 2) < 0)
            return -1;
        *r_min = v[0];
        *r_max = v[1];
    } else if (app_config_number(&L->p, g, "radius", r_min) < 0) {
        return -1;
    } else {
        *r_max = *r_min;
    }
    if (!(*r_min > 0.0 && *r_max >= *r_min))
        return app_config_fail(&L->p, r ? r : g,
                               "`radius` must be r > 0 or [r_min, r_max] with "
                               "0 < r_min <= r_max");
    return 0;
}

/* The size distribution: `radius` (+ `species`), a `mixture` list, or a `radii` list. */
static int parse_sizes(Loader *L, const config_setting_t *g, const char *what, SceneSource *s)
{
    static const char *const mixture_keys[] = {"species", "fraction", "radius", NULL};
    const config_setting_t *mixture = app_config_member(g, "mixture");
    const int ways = !!app_config_member(g, "radius") + !!mixture + !!app_config_member(g, "radii");
    if (ways != 1)
        return app_config_fail(&L->p, g, "%s: give one of `radius`, `mixture`, `radii`", what);
    if (app_config_member(g, "radii")) {
        int n = 0;
        if (app_config_array(&L->p, g, "radii", SCENE_SOURCE_MAX_RADII, s->radii, &n) < 0)
            return -1;
        for (int k = 0; k < n; ++k)
            if (!(s->radii[k] > 0.0))
                return app_config_fail(&L->p, app_config_member(g, "radii"),
                                       "`radii` must be positive");
        s->radii_count = n;
        s->mixture_count = 1;
        s->fraction[0] = 1.0;
        return loader_get_species(L, g, &s->species[0]) < 0 ? -1 : 0;
    }
    if (!mixture) {
        s->mixture_count = 1;
        s->fraction[0] = 1.0;
        return loader_get_species(L, g, &s->species[0]) < 0 ||
                       parse_radius(L, g, &s->radius_min[0], &s->radius_max[0]) < 0
                   ? -1
                   : 0;
    }
    int n = config_setting_length(mixture);
    if (!config_setting_is_list(mixture) || n < 1 || n > SIM_MAX_SPECIES)
        return app_config_fail(&L->p, mixture,
                               "`mixture` must list 1 to %d groups { species; fraction; radius; }",
                               SIM_MAX_SPECIES);
    double total = 0.0;
    for (int k = 0; k < n; ++k) {
        const config_setting_t *m = config_setting_get_elem(mixture, (unsigned)k);
        if (app_config_keys(&L->p, m, "mixture", mixture_keys, NULL) < 0 ||
            loader_get_species(L, m, &s->species[k]) < 0 ||
            app_config_need_number(&L->p, m, "fraction", "mixture", &s->fraction[k]) < 0 ||
            app_config_positive(&L->p, m, "fraction", s->fraction[k]) < 0 ||
            app_config_need(&L->p, m, "radius", "mixture") < 0 ||
            parse_radius(L, m, &s->radius_min[k], &s->radius_max[k]) < 0)
            return -1;
        total += s->fraction[k];
    }
    for (int k = 0; k < n; ++k)
        s->fraction[k] /= total;
    s->mixture_count = n;
    return 0;
}

/* `stages = ["fill"]` (default: every stage). */
static int parse_source_stages(Loader *L, const config_setting_t *g, SceneSource *s)
{
    const config_setting_t *st = app_config_member(g, "stages");
    s->stages = ~0u;
    if (!st)
        return 0;
    if (!config_setting_is_aggregate(st))
        return app_config_fail(&L->p, st, "`stages` must list stage names");
    s->stages = 0;
    for (int k = 0; k < config_setting_length(st); ++k) {
        const char *name = config_setting_get_string_elem(st, (unsigned)k);
        int index = name ? scene_stage_index(L->scene, name) : -1;
        if (index < 0)
            return app_config_fail(&L->p, st, "`stages`: no stage named `%s`",
                                   name ? name : "(not a string)");
        s->stages |= 1u << index;
    }
    return 0;
}

static int parse_source(Loader *L, const config_setting_t *g, int k, SceneSource *s)
{
    static const char *const keys[] = {"name",   "region",   "rate",    "mass_rate", "count",
                                       "radius", "species",  "mixture", "radii",     "velocity",
                                       "stages", "attempts", NULL};
    char what[64];
    snprintf(what, sizeof what, "sources.%d", k);
    const char *name = NULL;
    double region[4], velocity[2] = {0.0, 0.0};
    long long count = 0, attempts = 20;
    if (app_config_keys(&L->p, g, what, keys, NULL) < 0 ||
        app_config_string(&L->p, g, "name", &name) < 0 ||
        (name && loader_check_file_name(L, g, "name", name) < 0) ||
        app_config_need(&L->p, g, "region", what) < 0 ||
        app_config_vector(&L->p, g, "region", region, 4) < 0 ||
        app_config_number(&L->p, g, "rate", &s->rate) < 0 ||
        app_config_non_negative(&L->p, g, "rate", s->rate) < 0 ||
        app_config_number(&L->p, g, "mass_rate", &s->mass_rate) < 0 ||
        app_config_non_negative(&L->p, g, "mass_rate", s->mass_rate) < 0 ||
        app_config_int(&L->p, g, "count", &count) < 0 ||
        app_config_int(&L->p, g, "attempts", &attempts) < 0 ||
        app_config_vector(&L->p, g, "velocity", velocity, 2) < 0 ||
        parse_sizes(L, g, what, s) < 0 || parse_source_stages(L, g, s) < 0)
        return -1;
    snprintf(s->name, sizeof s->name, "%s", name ? name : what);
    if (!(region[2] > region[0] && region[3] > region[1]))
        return app_config_fail(&L->p, app_config_member(g, "region"),
                               "`region` = [x0, y0, x1, y1] needs x1 > x0 and y1 > y0");
    if ((s->rate > 0.0) + (s->mass_rate > 0.0) +
            (count > 0 && !(s->rate > 0.0) && !(s->mass_rate > 0.0)) !=
        1)
        return app_config_fail(&L->p, g,
                               "%s: give a `rate` (grains/s), a `mass_rate` (kg/s) or "
                               "a `count` alone",
                               what);
    if (count < 0 || attempts < 1 || attempts > SCENE_SOURCE_MAX_ATTEMPTS)
        return app_config_fail(&L->p, g, "%s: `count` >= 0 and `attempts` in [1, %d]", what,
                               SCENE_SOURCE_MAX_ATTEMPTS);
    s->x0 = region[0];
    s->y0 = region[1];
    s->x1 = region[2];
    s->y1 = region[3];
    s->vx = velocity[0];
    s->vy = velocity[1];
    s->count = (long)count;
    s->attempts = (int)attempts;
    return check_region(L, g, s);
}

/* The smallest radius a source inserts, m. */
static double smallest_radius(const SceneSource *s)
{
    double r = INFINITY;
    for (int k = 0; k < s->radii_count; ++k)
        r = fmin(r, s->radii[k]);
    for (int k = 0; s->radii_count == 0 && k < s->mixture_count; ++k)
        r = fmin(r, s->radius_min[k]);
    return r;
}

/* The most grains of the source that its region can hold at once: disks of diameter d whose
 * centres lie in a w x h rectangle, at most 2 / sqrt 3 w h / d^2 + (w + h) / d + 1 (Oler's
 * bound for centres at least d apart in a convex region). */
static double region_capacity(const SceneSource *s)
{
    const double d = 2.0 * smallest_radius(s), w = s->x1 - s->x0, h = s->y1 - s->y0;
    return floor(2.0 / sqrt(3.0) * (w / d) * (h / d) + (w + h) / d + 1.0);
}

/* What one step may ask of source k: no more grains than its region holds (a `rate` of 1e12
 * grains/s asked 1e9 grains a step, each tried `attempts` times against every grain). The
 * bound is checked at every stage the source is active in, with that stage's time step
 * (stage_dt[stage], s; 0: unknown, not checked). */
static int check_source_bounds(Loader *L, const config_setting_t *g, int k, const double *stage_dt)
{
    const Scene *scene = L->scene;
    const SceneSource *s = &scene->sources[k];
    const double capacity = region_capacity(s);
    if (s->count > 0 && !(s->rate > 0.0) && !(s->mass_rate > 0.0) && s->count > capacity)
        return app_config_fail(&L->p, app_config_member(g, "count"),
                               "sources.%d: `count` %ld alone puts every grain in at the stage "
                               "start, but its region holds at most %.0f grains of radius %g",
                               k, s->count, capacity, smallest_radius(s));
    double lightest = INFINITY; /* kg: a mass rate asks the most grains of the lightest */
    for (int m = 0; m < s->mixture_count; ++m)
        lightest =
            fmin(lightest,
                 sim_grain_mass(scene->def.mass_model, scene->def.materials[s->species[m]].density,
                                s->radii_count > 0 ? smallest_radius(s) : s->radius_min[m]));
    for (int stage = 0; stage < scene->stage_count; ++stage) {
        const double dt = stage_dt[stage];
        if (!((s->stages >> stage) & 1u) || !(dt > 0.0))
            continue;
        if (s->rate > 0.0 && s->rate * dt > capacity)
            return app_config_fail(&L->p, app_config_member(g, "rate"),
                                   "sources.%d: `rate` %g grains/s asks %.3g grains a step (dt = "
                                   "%g s in stage %s), but its region holds at most %.0f grains "
                                   "of radius %g: at most %g grains/s",
                                   k, s->rate, s->rate * dt, dt, scene->stages[stage].name,
                                   capacity, smallest_radius(s), capacity / dt);
        if (s->mass_rate > 0.0 && s->mass_rate * dt > capacity * lightest)
            return app_config_fail(&L->p, app_config_member(g, "mass_rate"),
                                   "sources.%d: `mass_rate` %g kg/s asks %.3g grains a step (dt "
                                   "= %g s in stage %s), but its region holds at most %.0f grains "
                                   "of radius %g: at most %g kg/s",
                                   k, s->mass_rate, s->mass_rate * dt / lightest, dt,
                                   scene->stages[stage].name, capacity, smallest_radius(s),
                                   capacity * lightest / dt);
    }
    return 0;
}

SimTiming app_sources_timing(const Scene *scene, const SimWorldDef *def)
{
    const SimGrainSet *g = &def->grains;
    const int extra = scene->source_count * SIM_MAX_SPECIES, n = g->count + extra;
    double *radius = malloc((size_t)(n > 0 ? n : 1) * sizeof *radius);
    int *species = malloc((size_t)(n > 0 ? n : 1) * sizeof *species);
    unsigned *flags = malloc((size_t)(n > 0 ? n : 1) * sizeof *flags);
    SimWorldDef d = *def;
    int count = 0;
    if (radius && species && flags) {
        for (int i = 0; i < g->count; ++i, ++count) {
            radius[count] = g->radius[i];
            species[count] = g->species ? g->species[i] : 0;
            flags[count] = g->flags ? g->flags[i] : 0u;
        }
        for (int k = 0; k < scene->source_count; ++k) { /* the lightest grain of each species */
            const SceneSource *s = &scene->sources[k];
            for (int m = 0; m < s->mixture_count; ++m, ++count) {
                radius[count] = s->radii_count > 0 ? smallest_radius(s) : s->radius_min[m];
                species[count] = s->species[m];
                flags[count] = 0u;
            }
        }
        d.grains =
            (SimGrainSet){.count = count, .radius = radius, .species = species, .flags = flags};
    }
    const SimTiming t = sim_world_def_timing(&d);
    free(radius);
    free(species);
    free(flags);
    return t;
}

int loader_parse_sources(Loader *L, const config_setting_t *root)
{
    const config_setting_t *list;
    if (app_config_list(&L->p, root, "sources", &list) <= 0)
        return L->p.failed ? -1 : 0;
    int count = config_setting_length(list);
    if (count > SCENE_SOURCE_MAX)
        return app_config_fail(&L->p, list, "at most %d sources", SCENE_SOURCE_MAX);
    L->scene->sources = calloc((size_t)(count > 0 ? count : 1), sizeof *L->scene->sources);
    if (!L->scene->sources)
        return app_config_fail(&L->p, list, "out of memory");
    for (int k = 0; k < count; ++k)
        if (parse_source(L, config_setting_get_elem(list, (unsigned)k), k, &L->scene->sources[k]) <
            0)
            return -1;
    L->scene->source_count = count;
    return 0;
}

int loader_check_sources(Loader *L, const config_setting_t *root, const double *stage_dt)
{
    const config_setting_t *list = app_config_member(root, "sources");
    for (int k = 0; list && k < L->scene->source_count; ++k)
        if (check_source_bounds(L, config_setting_get_elem(list, (unsigned)k), k, stage_dt) < 0)
            return -1;
    return 0;
}

/* ---------------------------------------------------------------- insertion */

typedef struct SourceState {
    SimRng rng;
    long inserted, skipped, stage_inserted;
    double stage_mass; /* kg inserted in this stage */
    int active;
    /* the next grain, drawn ahead (its mass decides when a mass rate makes it due) */
    int next_species;
    double next_radius;
    long next_index; /* position in a `radii` list */
} SourceState;

struct AppSources {
    const Scene *scene;
    int count;
    int signalled; /* a signal was raised before the insertion in progress began */
    SourceState state[SCENE_SOURCE_MAX];
};

static double grain_mass(const Scene *scene, int species, double r)
{
    return sim_grain_mass(scene->def.mass_model, scene->def.materials[species].density, r);
}

/* Draws the next grain's species and radius. */
static void draw_next(const SceneSource *s, SourceState *st)
{
    if (s->radii_count > 0) {
        st->next_species = s->species[0];
        st->next_radius = s->radii[st->next_index++ % s->radii_count];
        return;
    }
    double u = sim_rng_uniform(&st->rng), sum = 0.0;
    int k = 0;
    while (k < s->mixture_count - 1 && u >= sum + s->fraction[k])
        sum += s->fraction[k++];
    st->next_species = s->species[k];
    st->next_radius =
        s->radius_min[k] + sim_rng_uniform(&st->rng) * (s->radius_max[k] - s->radius_min[k]);
}

AppSources *app_sources_create(const Scene *scene, int *failed)
{
    *failed = 0;
    if (scene->source_count <= 0)
        return NULL;
    AppSources *a = calloc(1, sizeof *a);
    if (!a) {
        *failed = 1;
        return NULL;
    }
    a->scene = scene;
    a->count = scene->source_count;
    for (int k = 0; k < a->count; ++k) { /* one stream per source, from the scene's seed */
        sim_rng_seed(&a->state[k].rng, scene->seed * 1000003u + 7919u * (uint64_t)(k + 1));
        draw_next(&scene->sources[k], &a->state[k]);
    }
    return a;
}

void app_sources_free(AppSources *a)
{
    free(a);
}

void app_sources_stage_begin(AppSources *a, int stage)
{
    for (int k = 0; a && k < a->count; ++k) {
        SourceState *st = &a->state[k];
        st->active = (a->scene->sources[k].stages >> stage) & 1u;
        st->stage_inserted = 0;
        st->stage_mass = 0.0;
    }
}

/* 1 when source k may still insert (its count not reached). */
static int has_more(const SceneSource *s, const SourceState *st)
{
    return st->active && (s->count <= 0 || st->inserted + st->skipped < s->count);
}

/* The step (from the stage start) at which source k's next grain is due. */
static long due_step(const AppSources *a, int k, double dt)
{
    const SceneSource *s = &a->scene->sources[k];
    const SourceState *st = &a->state[k];
    if (!has_more(s, st))
        return -1;
    double t; /* s into the stage */
    if (s->rate > 0.0)
        t = (double)(st->stage_inserted + 1) / s->rate;
    else if (s->mass_rate > 0.0)
        t = (st->stage_mass + grain_mass(a->scene, st->next_species, st->next_radius)) /
            s->mass_rate;
    else
        t = 0.0; /* a count alone: all at the stage start */
    return (long)ceil(t / dt - 1e-9);
}

long app_sources_next_step(const AppSources *a, long done, double dt, long limit)
{
    long next = limit;
    for (int k = 0; a && k < a->count; ++k) {
        long s = due_step(a, k, dt);
        if (s >= 0)
            next = s <= done ? done + 1 : (s < next ? s : next);
    }
    return next;
}

/* 1 when a grain of radius r at (x, y) touches nothing in the frame, the walls or the batch. */
static int place_free(const SimFrame *f, const SimGrainBuffer *batch, double x, double y, double r)
{
    const double span = f->domain_x1 - f->domain_x0;
    for (int i = 0; i < f->count; ++i) {
        double dx = f->x[i] - x, dy = f->y[i] - y, c = f->radius[i] + r;
        if (f->periodic)
            dx -= span * floor(dx / span + 0.5);
        if (dx * dx + dy * dy < c * c)
            return 0;
    }
    for (int i = 0; i < batch->count; ++i) {
        double dx = batch->x[i] - x, dy = batch->y[i] - y, c = batch->radius[i] + r;
        if (f->periodic)
            dx -= span * floor(dx / span + 0.5);
        if (dx * dx + dy * dy < c * c)
            return 0;
    }
    for (int k = 0; k < f->wall_count; ++k)
        if (sim_wall_contact_distance(&f->walls[k], x, y, r) < r)
            return 0;
    return 1;
}

/* 1 when a signal raised during the insertion in progress asks the run to stop. One raised before
 * it (while the world stepped) lets it end as usual: the run stops after this step's outputs,
 * and a resumed run continues it to the bit. */
static int stop_asked(const AppSources *a)
{
    return !a->signalled && app_run_signal() != 0;
}

/* One grain of source k into the batch (or skipped after `attempts` tries). */
static void place_one(AppSources *a, int k, const SimFrame *f, SimGrainBuffer *batch)
{
    const SceneSource *s = &a->scene->sources[k];
    SourceState *st = &a->state[k];
    const double r = st->next_radius;
    int placed = 0;
    for (int t = 0; t < s->attempts && !placed && !stop_asked(a); ++t) {
        double x = s->x0 + sim_rng_uniform(&st->rng) * (s->x1 - s->x0);
        double y = s->y0 + sim_rng_uniform(&st->rng) * (s->y1 - s->y0);
        if (place_free(f, batch, x, y, r)) {
            int i = sim_grain_buffer_add(batch, x, y, r, st->next_species, 0u, -1);
            batch->vx[i] = s->vx;
            batch->vy[i] = s->vy;
            placed = 1;
        }
    }
    if (placed)
        st->inserted++;
    else
        st->skipped++;
    st->stage_inserted++; /* a skipped grain uses its turn: the rate counts attempts */
    st->stage_mass += grain_mass(a->scene, st->next_species, r);
    draw_next(s, st);
}

int app_sources_insert(AppSources *a, SimWorld *world, long done, double dt, char *err,
                       size_t err_size)
{
    if (!a)
        return 0;
    SimGrainBuffer batch;
    sim_grain_buffer_init(&batch);
    SimFrame f;
    sim_world_frame(world, &f);
    SourceState before[SCENE_SOURCE_MAX];
    memcpy(before, a->state, sizeof before);
    a->signalled = app_run_signal() != 0;
    for (int k = 0; k < a->count && !stop_asked(a); ++k)
        for (long s = due_step(a, k, dt); s >= 0 && s <= done && !stop_asked(a);
             s = due_step(a, k, dt))
            place_one(a, k, &f, &batch);
    int status = 0;
    if (stop_asked(a)) { /* the step's grains put off whole: the sources as they were */
        memcpy(a->state, before, sizeof before);
        batch.count = 0;
    }
    if (batch.count > 0) {
        SimGrainSet set = sim_grain_buffer_view(&batch);
        set.id = NULL;                    /* fresh ids above every id in use */
        if (a->scene->added_id_end > 0) { /* and above the grains the stages add */
            uint32_t next = a->scene->added_id_end;
            for (int i = 0; i < f.count; ++i)
                next = f.id[i] >= next ? f.id[i] + 1 : next;
            for (int i = 0; i < batch.count; ++i)
                batch.id[i] = next++;
            set.id = batch.id;
        }
        SimError error;
        if (sim_world_add_grains(world, &set, &error) != SIM_OK) {
            snprintf(err, err_size, "source insertion: %s: %s", error.field, error.message);
            status = -1;
        }
    }
    sim_grain_buffer_free(&batch);
    return status;
}

long app_sources_inserted(const AppSources *a, int k)
{
    return a && k >= 0 && k < a->count ? a->state[k].inserted : 0;
}

void app_sources_json(const AppSources *a, char *out, size_t size)
{
    out[0] = '\0';
    if (!a)
        return;
    size_t n = (size_t)snprintf(out, size, "  \"sources\": [");
    for (int k = 0; k < a->count && n < size; ++k)
        n += (size_t)snprintf(
            out + n, size - n, "%s{\"name\": \"%s\", \"inserted\": %ld, \"skipped\": %ld}",
            k ? ", " : "", a->scene->sources[k].name, a->state[k].inserted, a->state[k].skipped);
    if (n < size)
        snprintf(out + n, size - n, "],\n");
}

void app_sources_checkpoint(const AppSources *a, char *out, size_t size)
{
    size_t n = 0;
    if (size > 0)
        out[0] = '\0';
    for (int k = 0; a && k < a->count && n < size; ++k) {
        const SourceState *st = &a->state[k];
        n += (size_t)snprintf(out + n, size - n,
                              "source %d %llx %llx %llx %llx %ld %ld %ld %a %d %d %a %ld\n", k,
                              (unsigned long long)st->rng.s[0], (unsigned long long)st->rng.s[1],
                              (unsigned long long)st->rng.s[2], (unsigned long long)st->rng.s[3],
                              st->inserted, st->skipped, st->stage_inserted, st->stage_mass,
                              st->active, st->next_species, st->next_radius, st->next_index);
    }
}

int app_sources_restore(AppSources *a, const char *line)
{
    int k;
    unsigned long long r[4];
    SourceState st;
    if (!a ||
        sscanf(line, "source %d %llx %llx %llx %llx %ld %ld %ld %la %d %d %la %ld", &k, &r[0],
               &r[1], &r[2], &r[3], &st.inserted, &st.skipped, &st.stage_inserted, &st.stage_mass,
               &st.active, &st.next_species, &st.next_radius, &st.next_index) != 13 ||
        k < 0 || k >= a->count)
        return -1;
    for (int q = 0; q < 4; ++q)
        st.rng.s[q] = (uint64_t)r[q];
    a->state[k] = st;
    return 0;
}
