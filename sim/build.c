/* SPDX-License-Identifier: MIT */
/* build.c: the deterministic RNG and grain builders (fixed-grain walls, rain-like lattice). */
#include "internal.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

void sim_rng_seed(SimRng *rng, uint64_t seed)
{
    uint64_t s = seed;
    for (int k = 0; k < 4; ++k)
        rng->s[k] = splitmix64(&s);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

/* xoshiro256** (Blackman & Vigna), written from the published recurrence. */
uint64_t sim_rng_next(SimRng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double sim_rng_uniform(SimRng *rng)
{
    return (double)(sim_rng_next(rng) >> 11) * 0x1.0p-53;
}

void sim_grain_buffer_init(SimGrainBuffer *b)
{
    memset(b, 0, sizeof *b);
}

void sim_grain_buffer_free(SimGrainBuffer *b)
{
    free(b->x);
    free(b->y);
    free(b->radius);
    free(b->vx);
    free(b->vy);
    free(b->angle);
    free(b->omega);
    free(b->species);
    free(b->motion);
    free(b->flags);
    free(b->id);
    memset(b, 0, sizeof *b);
}

static void *grow(void *p, size_t n, size_t size)
{
    void *q = realloc(p, n * size);
    if (!q)
        abort(); /* the builders return nothing (or an index or count their callers use without
                  * a check) and run at set-up, before any world: out of memory there is fatal */
    return q;
}

int sim_grain_buffer_add(SimGrainBuffer *b, double x, double y, double radius, int species,
                         unsigned flags, int motion)
{
    if (b->count == b->capacity) {
        size_t cap = b->capacity ? 2 * (size_t)b->capacity : 256;
        b->x = grow(b->x, cap, sizeof *b->x);
        b->y = grow(b->y, cap, sizeof *b->y);
        b->radius = grow(b->radius, cap, sizeof *b->radius);
        b->vx = grow(b->vx, cap, sizeof *b->vx);
        b->vy = grow(b->vy, cap, sizeof *b->vy);
        b->angle = grow(b->angle, cap, sizeof *b->angle);
        b->omega = grow(b->omega, cap, sizeof *b->omega);
        b->species = grow(b->species, cap, sizeof *b->species);
        b->motion = grow(b->motion, cap, sizeof *b->motion);
        b->flags = grow(b->flags, cap, sizeof *b->flags);
        b->id = grow(b->id, cap, sizeof *b->id);
        b->capacity = (int)cap;
    }
    int k = b->count++;
    b->x[k] = x;
    b->y[k] = y;
    b->radius[k] = radius;
    b->vx[k] = b->vy[k] = b->angle[k] = b->omega[k] = 0.0;
    b->species[k] = species;
    b->motion[k] = motion;
    b->flags[k] = flags;
    b->id[k] = (uint32_t)k;
    return k;
}

SimGrainSet sim_grain_buffer_view(const SimGrainBuffer *b)
{
    return (SimGrainSet){.count = b->count,
                         .x = b->x,
                         .y = b->y,
                         .radius = b->radius,
                         .vx = b->vx,
                         .vy = b->vy,
                         .angle = b->angle,
                         .omega = b->omega,
                         .species = b->species,
                         .flags = b->flags,
                         .motion = b->motion,
                         .id = b->id};
}

/* floor(n) as a loop count: -1 for NaN or negative, at most INT_MAX - 2 (no out-of-range
 * conversion; callers bound their sizes, app/scene/scene_grains.c refuses over 1e7 grains). */
static int lattice_count(double n)
{
    n = floor(n);
    return n >= 0.0 ? (n < (double)(INT_MAX - 2) ? (int)n : INT_MAX - 2) : -1;
}

void sim_build_fixed_row(SimGrainBuffer *b, double x0, double x1, double y, double radius,
                         int species, int motion)
{
    int n = lattice_count((x1 - x0) / (2.0 * radius) + 1e-9) + 1;
    for (int k = 0; k < n; ++k)
        sim_grain_buffer_add(b, x0 + 2.0 * radius * k, y, radius, species, SIM_GRAIN_FIXED, motion);
}

void sim_build_fixed_column(SimGrainBuffer *b, double x, double y0, double y1, double radius,
                            int species, int motion)
{
    int n = lattice_count((y1 - y0) / (2.0 * radius) + 1e-9) + 1;
    for (int k = 0; k < n; ++k)
        sim_grain_buffer_add(b, x, y0 + 2.0 * radius * k, radius, species, SIM_GRAIN_FIXED, motion);
}

/* 000 §6.1 rain-like lattice: columns 2 r_pitch + column_gap apart, rows 2 r_pitch + row_gap
 * apart; every row and every column gets its own random offset (uniform, +- jitter x pitch),
 * then each grain a radius from r_med (1 +- polydispersity). The thesis leaves "5 % / 8 % of
 * what" open (notes §4.2): we take them as fractions of the gap-free pitch 2 r_pitch. */
int sim_build_rain(SimGrainBuffer *b, const SimRainDef *def, SimRng *rng)
{
    const double pitch_x = 2.0 * def->pitch_radius + def->column_gap;
    const double pitch_y = 2.0 * def->pitch_radius + def->row_gap;
    const double r_hi = def->radius_mean * (1.0 + def->polydispersity);
    int columns = lattice_count((def->x1 - def->x0 - 2.0 * r_hi) / pitch_x) + 1;
    int rows = lattice_count((def->y1 - def->y0 - 2.0 * r_hi) / pitch_y) + 1;
    if (columns < 1 || rows < 1)
        return 0;
    double total = 0.0;
    for (int s = 0; s < SIM_MAX_SPECIES; ++s)
        total += def->species_fraction[s] > 0.0 ? def->species_fraction[s] : 0.0;
    /* Column offsets drawn once; row offsets per row (separate draws, as in the thesis). */
    double *column_offset = malloc((size_t)columns * sizeof *column_offset);
    if (!column_offset)
        abort(); /* as in grow(): a builder has no error return */
    const double jitter_room_x = fmax(0.0, 0.5 * (pitch_x - 2.0 * r_hi)); /* never overlap */
    for (int c = 0; c < columns; ++c)
        column_offset[c] = (2.0 * sim_rng_uniform(rng) - 1.0) *
                           fmin(def->column_jitter * 2.0 * def->pitch_radius, jitter_room_x);
    int added = 0;
    const double jitter_room_y = fmax(0.0, 0.5 * (pitch_y - 2.0 * r_hi));
    for (int r = 0; r < rows; ++r) {
        double row_offset = (2.0 * sim_rng_uniform(rng) - 1.0) *
                            fmin(def->row_jitter * 2.0 * def->pitch_radius, jitter_room_y);
        double y = def->y0 + r_hi + r * pitch_y + row_offset;
        for (int c = 0; c < columns; ++c) {
            if (def->max_count > 0 && added >= def->max_count)
                goto done;
            double x = def->x0 + r_hi + c * pitch_x + column_offset[c];
            int species = def->species;
            double radius = def->radius_mean;
            if (total > 0.0) {
                double u = sim_rng_uniform(rng) * total, acc = 0.0;
                for (int s = 0; s < SIM_MAX_SPECIES; ++s) {
                    if (!(def->species_fraction[s] > 0.0))
                        continue;
                    acc += def->species_fraction[s];
                    species = s;
                    if (u < acc)
                        break;
                }
                if (def->species_radius[species] > 0.0)
                    radius = def->species_radius[species];
            }
            radius *= 1.0 + def->polydispersity * (2.0 * sim_rng_uniform(rng) - 1.0);
            sim_grain_buffer_add(b, x, y, radius, species, 0, -1);
            ++added;
        }
    }
done:
    free(column_offset);
    return added;
}

SimRainDef sim_rain_def_thesis000(double x0, double x1, double y0, double y1, int max_count)
{
    const double r_max = 0.105;
    return (SimRainDef){.x0 = x0,
                        .x1 = x1,
                        .y0 = y0,
                        .y1 = y1,
                        .radius_mean = 0.08,
                        .polydispersity = 0.08,
                        .pitch_radius = r_max,
                        .column_gap = 0.005 * r_max,
                        .row_gap = 0.75 * r_max,
                        .column_jitter = 0.05,
                        .row_jitter = 0.08,
                        .max_count = max_count};
}

void sim_build_fixed_box(SimGrainBuffer *b, double x0, double x1, double y0, double wall_top,
                         double radius, int species)
{
    sim_build_fixed_row(b, x0, x1, y0, radius, species, -1);
    sim_build_fixed_column(b, x0, y0 + 2.0 * radius, wall_top, radius, species, -1);
    sim_build_fixed_column(b, x1, y0 + 2.0 * radius, wall_top, radius, species, -1);
}
