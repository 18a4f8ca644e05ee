/* SPDX-License-Identifier: MIT */
/* fixture.h: synthetic frames for render tests and benchmarks (no simulation: hand-made arrays),
 * and reference-image checks. A bed is a jittered triangular lattice of grains with a fixed base
 * row, contacts between near neighbours and exponentially distributed normal forces, all from a
 * small local generator so nothing depends on sim's implementation. */
#ifndef RENDER_FIXTURE_H
#define RENDER_FIXTURE_H

#include "render/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct Fixture {
    SimFrame frame;
    int capacity, contact_capacity;
    double *x, *y, *radius, *angle, *vx, *vy, *omega, *force;
    int *species;
    unsigned *flags;
    uint32_t *id;
    SimContact *contacts;
    SimWall walls[4];
    uint64_t rng;
} Fixture;

/* 64-bit LCG (Knuth's MMIX constants), top 53 bits as a double in [0, 1). */
static inline double fixture_uniform(Fixture *f)
{
    f->rng = f->rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(f->rng >> 11) * (1.0 / 9007199254740992.0);
}

static inline int fixture_init(Fixture *f, int capacity, int contact_capacity, uint64_t seed)
{
    memset(f, 0, sizeof *f);
    f->capacity = capacity;
    f->contact_capacity = contact_capacity;
    f->rng = seed * 2654435761ull + 1;
    size_t n = (size_t)capacity;
    f->x = calloc(n, sizeof(double));
    f->y = calloc(n, sizeof(double));
    f->radius = calloc(n, sizeof(double));
    f->angle = calloc(n, sizeof(double));
    f->vx = calloc(n, sizeof(double));
    f->vy = calloc(n, sizeof(double));
    f->omega = calloc(n, sizeof(double));
    f->force = calloc(n, sizeof(double));
    f->species = calloc(n, sizeof(int));
    f->flags = calloc(n, sizeof(unsigned));
    f->id = calloc(n, sizeof(uint32_t));
    f->contacts = calloc((size_t)(contact_capacity > 0 ? contact_capacity : 1), sizeof(SimContact));
    SimFrame *fr = &f->frame;
    fr->x = f->x;
    fr->y = f->y;
    fr->radius = f->radius;
    fr->angle = f->angle;
    fr->vx = f->vx;
    fr->vy = f->vy;
    fr->omega = f->omega;
    fr->force = f->force;
    fr->species = f->species;
    fr->flags = f->flags;
    fr->id = f->id;
    fr->contacts = f->contacts;
    fr->walls = f->walls;
    return f->x && f->y && f->radius && f->angle && f->vx && f->vy && f->omega && f->force &&
                   f->species && f->flags && f->id && f->contacts
               ? 0
               : -1;
}

static inline void fixture_free(Fixture *f)
{
    free(f->x);
    free(f->y);
    free(f->radius);
    free(f->angle);
    free(f->vx);
    free(f->vy);
    free(f->omega);
    free(f->force);
    free(f->species);
    free(f->flags);
    free(f->id);
    free(f->contacts);
    memset(f, 0, sizeof *f);
}

static inline int fixture_add(Fixture *f, double x, double y, double r, unsigned flags)
{
    int i = f->frame.count;
    if (i >= f->capacity)
        return -1;
    f->x[i] = x;
    f->y[i] = y;
    f->radius[i] = r;
    f->flags[i] = flags;
    f->id[i] = (uint32_t)i;
    f->frame.count++;
    if (!(flags & SIM_GRAIN_FIXED))
        f->frame.mobile_count++;
    return i;
}

static inline void fixture_contact(Fixture *f, int i, int j, double fn, double cx, double cy)
{
    if (f->frame.contact_count >= f->contact_capacity)
        return;
    SimContact *c = &f->contacts[f->frame.contact_count++];
    c->i = i;
    c->j = j;
    c->normal_force = fn;
    c->tangential_force = 0.1 * fn;
    c->overlap = 0;
    c->x = cx;
    c->y = cy;
    f->force[i] += fn;
    if (j >= 0)
        f->force[j] += fn;
}

/* Contacts between grains closer than r_i + r_j + slack, found with a cell grid, forces
 * F = -mean ln(u) (exponential tail of granular force networks). */
static inline void fixture_find_contacts(Fixture *f, double slack, double mean_force)
{
    int n = f->frame.count;
    double rmax = 0, x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < n; ++i) {
        rmax = fmax(rmax, f->radius[i]);
        x0 = fmin(x0, f->x[i]);
        x1 = fmax(x1, f->x[i]);
        y0 = fmin(y0, f->y[i]);
        y1 = fmax(y1, f->y[i]);
    }
    if (n <= 0)
        return;
    double cell = 2 * rmax + slack;
    int nx = (int)((x1 - x0) / cell) + 1, ny = (int)((y1 - y0) / cell) + 1;
    if (nx < 1 || ny < 1 || nx > 100000 || ny > 100000)
        return;
    int *head = malloc((size_t)nx * (size_t)ny * sizeof(int));
    int *next = malloc((size_t)n * sizeof(int));
    if (!head || !next) {
        free(head);
        free(next);
        return;
    }
    for (int k = 0; k < nx * ny; ++k)
        head[k] = -1;
    for (int i = n - 1; i >= 0; --i) {
        int cx = (int)((f->x[i] - x0) / cell), cy = (int)((f->y[i] - y0) / cell);
        next[i] = head[cy * nx + cx];
        head[cy * nx + cx] = i;
    }
    for (int i = 0; i < n; ++i) {
        int cx = (int)((f->x[i] - x0) / cell), cy = (int)((f->y[i] - y0) / cell);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                int gx = cx + dx, gy = cy + dy;
                if (gx < 0 || gy < 0 || gx >= nx || gy >= ny)
                    continue;
                for (int j = head[gy * nx + gx]; j >= 0; j = next[j]) {
                    if (j <= i)
                        continue;
                    if ((f->flags[i] & SIM_GRAIN_FIXED) && (f->flags[j] & SIM_GRAIN_FIXED))
                        continue;
                    double ddx = f->x[j] - f->x[i], ddy = f->y[j] - f->y[i];
                    double d = sqrt(ddx * ddx + ddy * ddy);
                    if (d < f->radius[i] + f->radius[j] + slack) {
                        double fn = -mean_force * log(1.0 - fixture_uniform(f));
                        double t = f->radius[i] / (f->radius[i] + f->radius[j]);
                        fixture_contact(f, i, j, fn, f->x[i] + t * ddx, f->y[i] + t * ddy);
                    }
                }
            }
    }
    free(head);
    free(next);
}

/* A packed bed: `cols` x `rows` mobile grains of mean radius r on a jittered triangular lattice,
 * a row of fixed base grains, two side walls; gravity-like force gradient, a gentle vortex
 * velocity field, random angles, two species. */
static inline int fixture_bed(Fixture *f, int cols, int rows, double r, uint64_t seed)
{
    int cap = cols * rows + 2 * cols + 8;
    if (fixture_init(f, cap, 4 * cap, seed) != 0)
        return -1;
    double pitch = 2 * r, h = pitch * sqrt(3.0) / 2;
    double width = cols * pitch + r;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i) {
            double ri = r * (0.90 + 0.08 * fixture_uniform(f));
            double x = r + (i + 0.5 * (j % 2)) * pitch + 0.04 * r * (fixture_uniform(f) - 0.5);
            double y = 2 * r + j * h + 0.04 * r * (fixture_uniform(f) - 0.5);
            int g = fixture_add(f, x, y, ri, 0);
            f->angle[g] = 6.283185307179586 * fixture_uniform(f);
            double cxv = 0.5 * width, cyv = 2 * r + 0.5 * rows * h;
            f->vx[g] = -(y - cyv) * 0.8;
            f->vy[g] = (x - cxv) * 0.8;
            f->species[g] = fixture_uniform(f) < 0.3 ? 1 : 0;
        }
    int base = (int)(width / (1.6 * r)) + 1;
    for (int i = 0; i < base; ++i)
        fixture_add(f, 0.8 * r + i * 1.6 * r, 0.8 * r, 0.8 * r, SIM_GRAIN_FIXED);
    fixture_find_contacts(f, 0.12 * r, 1.0);
    /* Deeper grains carry more: scale by depth so the network shows a gradient. */
    double top = 2 * r + rows * h;
    for (int c = 0; c < f->frame.contact_count; ++c) {
        SimContact *ct = &f->contacts[c];
        double depth = (top - ct->y) / top;
        double old = ct->normal_force;
        ct->normal_force = old * (0.3 + 1.7 * depth);
        f->force[ct->i] += ct->normal_force - old;
        if (ct->j >= 0)
            f->force[ct->j] += ct->normal_force - old;
    }
    f->frame.wall_count = 2;
    f->walls[0] = (SimWall){.x0 = 0, .y0 = 0, .x1 = 0, .y1 = top + r, .species = 0, .motion = -1};
    f->walls[1] =
        (SimWall){.x0 = width, .y0 = 0, .x1 = width, .y1 = top + r, .species = 0, .motion = -1};
    f->frame.time = 0.125;
    f->frame.time_scale = 0.0142784;
    f->frame.step = 12500;
    return 0;
}

/* ---- files ---- */

/* Reads up to `size` bytes of the file at `path` into buf: the count read, or -1 when it cannot
 * be opened. */
static inline long fixture_read(const char *path, void *buf, long size)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return -1;
    long n = (long)fread(buf, 1, (size_t)size, fp);
    fclose(fp);
    return n;
}

/* ---- reference images ---- */

static inline void fixture_mkdirs(void)
{
    mkdir("out", 0777);
    mkdir("out/render-tests", 0777);
}

/* Compares an image with tests/render/reference/<name>.png using the default diff (channel
 * threshold 32, one-pixel shift tolerance, no differing pixel allowed). With
 * SABLIER_UPDATE_REFERENCES=1 writes the reference instead. On mismatch writes
 * out/render-tests/<name>.out.png and <name>.diff.png. Returns 0 on match. */
static inline int fixture_check_reference(const char *name, const RenderImage *image)
{
    char ref[512], out[512], diff[512], err[512];
    snprintf(ref, sizeof ref, "tests/render/reference/%s.png", name);
    snprintf(out, sizeof out, "out/render-tests/%s.out.png", name);
    snprintf(diff, sizeof diff, "out/render-tests/%s.diff.png", name);
    const char *update = getenv("SABLIER_UPDATE_REFERENCES");
    if (update && strcmp(update, "1") == 0) {
        if (render_png_write(image, ref, NULL, err, sizeof err) != 0) {
            fprintf(stderr, "%s\n", err);
            return 1;
        }
        fprintf(stderr, "updated %s\n", ref);
        return 0;
    }
    fixture_mkdirs();
    if (render_png_write(image, out, NULL, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    RenderDiffResult result;
    int rc = render_diff_files(ref, out, NULL, diff, &result, err, sizeof err);
    if (rc == 0) {
        remove(out);
        remove(diff);
        return 0;
    }
    char json[512];
    render_diff_result_json(&result, json, sizeof json);
    fprintf(stderr, "%s: %s\n  %s\n  see %s and %s%s\n", ref, err, json, out, diff,
            rc == 2 ? " (run with SABLIER_UPDATE_REFERENCES=1 to create references)" : "");
    return 1;
}

/* Straight RGB of pixel (x, y) as 0xRRGGBB. */
static inline uint32_t fixture_pixel(const RenderImage *image, double x, double y)
{
    uint8_t c[4];
    render_image_get_rgba(image, (int)floor(x), (int)floor(y), c);
    return (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
}

#endif
