/* SPDX-License-Identifier: MIT */
/* bench_render_video.c: movie frames at 1920x1080 with 7284 grains and force chains (the size of
 * the crater scene): OSMesa and Cairo drawing rates, and the full draw + convert + encode + mux
 * pipeline for both drawers. Frames move a little each time so the encoder sees motion.
 *
 *     bench_render_video [frames]      (default 120; writes MP4 files under out/bench)
 */
#include "render/render.h"
#include "render/render_gl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

enum { GRAINS = 7284, COLS = 114, WIDTH = 1920, HEIGHT = 1080 };

typedef struct Bench {
    double x0[GRAINS], y0[GRAINS], phase[GRAINS];
    double x[GRAINS], y[GRAINS], r[GRAINS], angle[GRAINS], vx[GRAINS], vy[GRAINS], omega[GRAINS],
        force[GRAINS];
    int species[GRAINS];
    unsigned flags[GRAINS];
    uint32_t id[GRAINS];
    SimContact *contacts;
    double *contact_f0;
    int contact_count;
    SimFrame frame;
} Bench;

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CPU seconds of the whole process (all threads): on a shared machine this shows the cost that
 * wall time hides; on 2 idle cores the wall time is at least half of it. */
static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + 1e-6 * (double)u.ru_utime.tv_usec +
           (double)u.ru_stime.tv_sec + 1e-6 * (double)u.ru_stime.tv_usec;
}

/* Frames per second of wall time, and CPU milliseconds per frame. */
typedef struct Rate {
    double fps, cpu_ms;
} Rate;

static double lcg(uint64_t *state)
{
    *state = *state * 6364136223846793005u + 1442695040888963407u;
    return (double)(*state >> 11) / 9007199254740992.0;
}

/* A jittered triangular packing, 114 grains per row, the bottom row fixed; contacts between
 * lattice neighbours with a skewed force distribution (a few strong chains). */
static int bench_init(Bench *b)
{
    memset(b, 0, sizeof *b);
    uint64_t seed = 2024;
    const double radius = 0.5e-3; /* m */
    int rows = (GRAINS + COLS - 1) / COLS;
    for (int n = 0; n < GRAINS; ++n) {
        /* Frame order: mobile first, so the fixed base row (row 0) goes last. */
        int k = (n + COLS) % (rows * COLS);
        int i = k % COLS, j = k / COLS;
        b->x0[n] = (2 * i + (j % 2) + 1) * radius + 0.1 * radius * (lcg(&seed) - 0.5);
        b->y0[n] = (j * sqrt(3.0) + 1) * radius + 0.1 * radius * (lcg(&seed) - 0.5);
        b->r[n] = radius * (0.92 + 0.08 * lcg(&seed));
        b->phase[n] = 6.283185307179586 * lcg(&seed);
        b->species[n] = (i / 4 + j / 3) % 3;
        b->flags[n] = j == 0 ? SIM_GRAIN_FIXED : 0;
        b->id[n] = (uint32_t)n;
    }
    int mobile = 0;
    for (int n = 0; n < GRAINS; ++n)
        mobile += !(b->flags[n] & SIM_GRAIN_FIXED);
    b->contacts = malloc(sizeof(SimContact) * 3 * GRAINS);
    b->contact_f0 = malloc(sizeof(double) * 3 * GRAINS);
    if (!b->contacts || !b->contact_f0)
        return -1;
    /* Neighbours through a grid of cells one diameter wide. */
    double cell = 2.2 * radius;
    int nx = (int)(2.0 * COLS * radius / cell) + 3, ny = (int)(rows * 2.0 * radius / cell) + 3;
    int *head = malloc(sizeof(int) * (size_t)(nx * ny)), *next = malloc(sizeof(int) * GRAINS);
    if (!head || !next)
        return -1;
    for (int c = 0; c < nx * ny; ++c)
        head[c] = -1;
    for (int n = 0; n < GRAINS; ++n) {
        int c = (int)(b->y0[n] / cell) * nx + (int)(b->x0[n] / cell);
        next[n] = head[c];
        head[c] = n;
    }
    for (int a = 0; a < GRAINS; ++a) {
        int cx = (int)(b->x0[a] / cell), cy = (int)(b->y0[a] / cell);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                int u = cx + dx, v = cy + dy;
                if (u < 0 || v < 0 || u >= nx || v >= ny)
                    continue;
                for (int o = head[v * nx + u]; o >= 0; o = next[o]) {
                    double ex = b->x0[o] - b->x0[a], ey = b->y0[o] - b->y0[a];
                    if (o <= a || ex * ex + ey * ey > 4.6 * radius * radius ||
                        b->contact_count >= 3 * GRAINS)
                        continue;
                    double f = -log(1.0 - lcg(&seed)); /* exponential tail, mean 1 N */
                    b->contact_f0[b->contact_count] = f;
                    b->contacts[b->contact_count++] = (SimContact){.i = a, .j = o};
                }
            }
    }
    free(head);
    free(next);
    b->frame = (SimFrame){.count = GRAINS,
                          .mobile_count = mobile,
                          .x = b->x,
                          .y = b->y,
                          .angle = b->angle,
                          .radius = b->r,
                          .vx = b->vx,
                          .vy = b->vy,
                          .omega = b->omega,
                          .species = b->species,
                          .flags = b->flags,
                          .id = b->id,
                          .force = b->force,
                          .contact_count = b->contact_count,
                          .contacts = b->contacts,
                          .time_scale = 0.01};
    return 0;
}

/* Frame k: grains wobble, forces breathe, so every frame differs. */
static void bench_frame(Bench *b, int k)
{
    const double t = 0.04 * k;
    for (int n = 0; n < GRAINS; ++n) {
        int fixed = (b->flags[n] & SIM_GRAIN_FIXED) != 0;
        double a = fixed ? 0.0 : 0.15 * b->r[n];
        b->x[n] = b->x0[n] + a * sin(b->phase[n] + 3.0 * t);
        b->y[n] = b->y0[n] + a * cos(1.3 * b->phase[n] + 2.0 * t);
        b->vx[n] = 3.0 * a * cos(b->phase[n] + 3.0 * t);
        b->vy[n] = -2.0 * a * sin(1.3 * b->phase[n] + 2.0 * t);
        b->angle[n] = b->phase[n] + t;
        b->force[n] = 0.0;
    }
    for (int c = 0; c < b->contact_count; ++c) {
        SimContact *k_ = &b->contacts[c];
        double f = b->contact_f0[c] * (1.0 + 0.5 * sin(b->phase[k_->i] + t));
        k_->normal_force = f;
        k_->x = 0.5 * (b->x[k_->i] + b->x[k_->j]);
        k_->y = 0.5 * (b->y[k_->i] + b->y[k_->j]);
        b->force[k_->i] += f;
        b->force[k_->j] += f;
    }
    b->frame.time = t;
    b->frame.step = k;
}

static RenderStyle bench_style(void)
{
    RenderStyle style = render_style_default();
    style.width = WIDTH;
    style.height = HEIGHT;
    style.color_by = RENDER_COLOR_FORCE;
    style.force_chains = 1;
    style.outline = 1;
    style.range_min = 0.0; /* a fixed range, as movies should have */
    style.range_max = 8.0;
    style.chain_force_max = 4.0;
    if (getenv("BENCH_NO_CHAINS"))
        style.force_chains = 0;
    if (getenv("BENCH_NO_OUTLINE"))
        style.outline = 0;
    return style;
}

static Rate draw_rate(Bench *b, RenderDrawer drawer, int frames)
{
    RenderStyle style = bench_style();
    char err[256];
    RenderGl *gl = NULL;
    RenderImage image = {0};
    Rate rate = {0.0, 0.0};
    if (drawer == RENDER_DRAWER_OSMESA) {
        gl = render_gl_create(WIDTH, HEIGHT, err, sizeof err);
        if (!gl) {
            fprintf(stderr, "%s\n", err);
            return rate;
        }
    }
    double start = 0.0, cpu = 0.0;
    for (int k = -1; k < frames; ++k) { /* frame -1 warms up (shader compilation, caches) */
        if (k == 0) {
            start = now_seconds();
            cpu = cpu_seconds();
        }
        bench_frame(b, k + 1);
        if (gl) {
            if (render_gl_frame(gl, &b->frame, &style, &image, err, sizeof err) != 0) {
                fprintf(stderr, "%s\n", err);
                return rate;
            }
        } else {
            if (render_cairo_draw(&b->frame, &style, &image) != 0)
                return rate;
            render_image_free(&image);
        }
    }
    rate.fps = frames / (now_seconds() - start);
    rate.cpu_ms = 1e3 * (cpu_seconds() - cpu) / frames;
    render_gl_destroy(gl);
    return rate;
}

/* Draw + convert + encode + mux, from open to close. */
static Rate movie_rate(Bench *b, RenderDrawer drawer, int frames, const char *path,
                       const char *preset, long *bytes)
{
    RenderStyle style = bench_style();
    RenderMovieDef def = {.path = path,
                          .drawer = drawer,
                          .fps = 30.0,
                          .crf = 20,
                          .quiet = 1,
                          .preset = preset,
                          .frames_expected = frames};
    char err[512];
    Rate rate = {0.0, 0.0};
    double start = now_seconds(), cpu = cpu_seconds();
    RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
    if (!movie) {
        fprintf(stderr, "%s\n", err);
        return rate;
    }
    for (int k = 0; k < frames; ++k) {
        bench_frame(b, k);
        if (render_movie_frame(movie, &b->frame) != 0)
            break;
    }
    if (render_movie_close(movie, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return rate;
    }
    rate.fps = frames / (now_seconds() - start);
    rate.cpu_ms = 1e3 * (cpu_seconds() - cpu) / frames;
    struct stat st;
    *bytes = stat(path, &st) == 0 ? (long)st.st_size : 0;
    return rate;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 120;
    if (frames < 1)
        frames = 1;
    static Bench bench;
    if (bench_init(&bench) != 0) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    mkdir("out", 0755);
    mkdir("out/bench", 0755);
    bench_frame(&bench, 0);
    printf("bench_render_video: %d grains, %d contacts, %dx%d, %d frames, %ld CPUs, %s\n", GRAINS,
           bench.contact_count, WIDTH, HEIGHT, frames, sysconf(_SC_NPROCESSORS_ONLN),
           render_library_versions());
    Rate gl = draw_rate(&bench, RENDER_DRAWER_OSMESA, frames);
    if (argc > 2 && strcmp(argv[2], "gl") == 0) {
        printf("OSMesa draw: %.1f frames/s, %.1f CPU ms/frame\n", gl.fps, gl.cpu_ms);
        return 0;
    }
    Rate cairo = draw_rate(&bench, RENDER_DRAWER_CAIRO, frames / 4 > 10 ? frames / 4 : 10);
    long gl_bytes = 0, cairo_bytes = 0, fast_bytes = 0;
    Rate gl_movie = movie_rate(&bench, RENDER_DRAWER_OSMESA, frames,
                               "out/bench/bench_render_osmesa.mp4", NULL, &gl_bytes);
    Rate gl_fast =
        movie_rate(&bench, RENDER_DRAWER_OSMESA, frames,
                   "out/bench/bench_render_osmesa_superfast.mp4", "superfast", &fast_bytes);
    Rate cairo_movie = movie_rate(&bench, RENDER_DRAWER_CAIRO, frames / 2 > 10 ? frames / 2 : 10,
                                  "out/bench/bench_render_cairo.mp4", NULL, &cairo_bytes);

    struct {
        const char *name;
        Rate rate;
        long bytes;
    } rows[] = {
        {"OSMesa draw", gl, -1},
        {"Cairo draw", cairo, -1},
        {"OSMesa draw + encode (x264 veryfast, CRF 20)", gl_movie, gl_bytes},
        {"OSMesa draw + encode (x264 superfast, CRF 20)", gl_fast, fast_bytes},
        {"Cairo draw + encode (x264 veryfast, CRF 20)", cairo_movie, cairo_bytes},
    };

    printf("%-46s %9s %9s %12s %8s\n", "stage", "frames/s", "ms/frame", "CPU ms/frame", "MB");
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        printf("%-46s %9.1f %9.1f %12.1f", rows[k].name, rows[k].rate.fps,
               rows[k].rate.fps > 0 ? 1e3 / rows[k].rate.fps : 0.0, rows[k].rate.cpu_ms);
        if (rows[k].bytes >= 0)
            printf(" %8.1f", rows[k].bytes / 1e6);
        printf("\n");
    }
    printf("encoding (convert + x264 + mux) CPU per OSMesa movie frame: %.1f ms\n",
           gl_movie.cpu_ms - gl.cpu_ms);
    return 0;
}
