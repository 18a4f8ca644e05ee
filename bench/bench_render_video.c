/* SPDX-License-Identifier: MIT */
/* bench_render_video.c: movie frames at 1920x1080 with 7284 grains and force chains (the size of
 * the standard crater scene): OSMesa drawing (grain layer, then with the Cairo overlay of colour
 * bar, time stamp and scale bar), Cairo drawing, and the full draw + convert + encode + mux
 * pipeline for x264 presets. Frames move a little each time so the encoder sees motion. Each
 * stage runs `repeats` times; the best wall time and the best CPU time (all threads) are kept,
 * since other work on a shared machine only ever adds to them.
 *
 *     bench_render_video [frames [repeats [sim_ms [draw]]]]   (default 120 3; MP4s under out/bench)
 *
 * sim_ms: wall milliseconds the simulation takes per 1/30 simulated second (a movie of 30 frames
 * per simulated second); the table then gives each pipeline's CPU per frame as a share of it
 * (target: at most 0.2). A fourth argument `draw` runs the OSMesa drawing stages alone (quick
 * A/B runs of the drawer). */
#include "render/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
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

/* Frames per second of wall time, CPU milliseconds per frame (all threads, and the calling
 * thread alone). */
typedef struct Rate {
    double fps, cpu_ms, caller_ms;
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
    RenderStyle style = render_style_default(); /* colour bar, time stamp, scale bar on */
    style.width = WIDTH;
    style.height = HEIGHT;
    style.color_by = RENDER_COLOR_FORCE;
    style.force_chains = 1;
    style.outline = 1;
    style.range_min = 0.0; /* a fixed range, as movies should have */
    style.range_max = 8.0;
    style.chain_force_max = 4.0;
    return style;
}

enum Stage { STAGE_GL, STAGE_GL_OVERLAY, STAGE_CAIRO };

static Rate best(Rate a, Rate b)
{
    return (Rate){fmax(a.fps, b.fps), a.cpu_ms > 0.0 && a.cpu_ms < b.cpu_ms ? a.cpu_ms : b.cpu_ms,
                  a.caller_ms > 0.0 && a.caller_ms < b.caller_ms ? a.caller_ms : b.caller_ms};
}

static Rate draw_rate(Bench *b, enum Stage stage, int frames)
{
    RenderStyle style = bench_style();
    char err[256];
    RenderGl *gl = NULL;
    RenderImage image = {0};
    Rate rate = {0.0, 0.0, 0.0};
    if (stage != STAGE_CAIRO) {
        gl = render_gl_create(WIDTH, HEIGHT, err, sizeof err);
        if (!gl) {
            fprintf(stderr, "%s\n", err);
            return rate;
        }
    }
    double start = 0.0, cpu = 0.0, caller = 0.0;
    for (int k = -1; k < frames; ++k) { /* frame -1 warms up (shader compilation, caches) */
        if (k == 0) {
            start = sim_clock_seconds(SIM_CLOCK_WALL);
            cpu = sim_clock_seconds(SIM_CLOCK_PROCESS);
            caller = sim_clock_seconds(SIM_CLOCK_THREAD);
        }
        bench_frame(b, k + 1);
        if (gl) {
            if (render_gl_frame(gl, &b->frame, &style, &image, err, sizeof err) != 0) {
                fprintf(stderr, "%s\n", err);
                return rate;
            }
            if (stage == STAGE_GL_OVERLAY && render_cairo_overlay(&b->frame, &style, &image)) {
                fprintf(stderr, "overlay failed\n");
                return rate;
            }
        } else {
            if (render_cairo_draw(&b->frame, &style, &image) != 0)
                return rate;
            render_image_free(&image);
        }
    }
    rate.fps = frames / (sim_clock_seconds(SIM_CLOCK_WALL) - start);
    rate.cpu_ms = 1e3 * (sim_clock_seconds(SIM_CLOCK_PROCESS) - cpu) / frames;
    rate.caller_ms = 1e3 * (sim_clock_seconds(SIM_CLOCK_THREAD) - caller) / frames;
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
    Rate rate = {0.0, 0.0, 0.0};
    double start = sim_clock_seconds(SIM_CLOCK_WALL), cpu = sim_clock_seconds(SIM_CLOCK_PROCESS);
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
    rate.fps = frames / (sim_clock_seconds(SIM_CLOCK_WALL) - start);
    rate.cpu_ms = 1e3 * (sim_clock_seconds(SIM_CLOCK_PROCESS) - cpu) / frames;
    struct stat st;
    *bytes = stat(path, &st) == 0 ? (long)st.st_size : 0;
    return rate;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 120;
    int repeats = argc > 2 ? atoi(argv[2]) : 3;
    double sim_ms = argc > 3 ? atof(argv[3]) : 0.0;
    int draw_only = argc > 4 && strcmp(argv[4], "draw") == 0;
    if (frames < 1)
        frames = 1;
    if (repeats < 1)
        repeats = 1;
    static Bench bench;
    if (bench_init(&bench) != 0) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    mkdir("out", 0755);
    mkdir("out/bench", 0755);
    bench_frame(&bench, 0);
    const char *threads = getenv("LP_NUM_THREADS"), *bands = getenv("SABLIER_BANDS");
    printf("bench_render_video: %d grains, %d contacts, %dx%d, %d frames, best of %d, %ld CPUs, "
           "LP_NUM_THREADS %s, SABLIER_BANDS %s, %s\n",
           GRAINS, bench.contact_count, WIDTH, HEIGHT, frames, repeats,
           sysconf(_SC_NPROCESSORS_ONLN), threads ? threads : "unset (the drawer sets CPUs)",
           bands ? bands : "unset (2 bands on 2 CPUs)", render_library_versions());
    int cairo_frames = frames / 4 > 10 ? frames / 4 : 10;
    static const char *const presets[] = {"veryfast", "superfast", "ultrafast"};

    enum { PRESETS = 3 };

    Rate gl = {0, 1e30, 1e30}, overlay = {0, 1e30, 1e30}, cairo = {0, 1e30, 1e30},
         movies[PRESETS + 1];
    long bytes[PRESETS + 1] = {0};
    for (int p = 0; p <= PRESETS; ++p)
        movies[p] = (Rate){0, 1e30, 1e30};
    for (int r = 0; r < repeats; ++r) { /* interleaved, so load changes hit every stage */
        gl = best(gl, draw_rate(&bench, STAGE_GL, frames));
        overlay = best(overlay, draw_rate(&bench, STAGE_GL_OVERLAY, frames));
        if (draw_only)
            continue;
        cairo = best(cairo, draw_rate(&bench, STAGE_CAIRO, cairo_frames));
        for (int p = 0; p < PRESETS; ++p) {
            char path[96];
            snprintf(path, sizeof path, "out/bench/bench_render_osmesa_%s.mp4", presets[p]);
            movies[p] = best(movies[p], movie_rate(&bench, RENDER_DRAWER_OSMESA, frames, path,
                                                   presets[p], &bytes[p]));
        }
        movies[PRESETS] = best(
            movies[PRESETS], movie_rate(&bench, RENDER_DRAWER_CAIRO, cairo_frames,
                                        "out/bench/bench_render_cairo.mp4", NULL, &bytes[PRESETS]));
    }

    printf("%-52s %9s %9s %12s %8s %9s\n", "stage", "frames/s", "ms/frame", "CPU ms/frame", "MB",
           "CPU/sim");

    struct {
        const char *name;
        Rate rate;
        long bytes;
        int movie;
    } rows[3 + PRESETS + 1] = {
        {"OSMesa draw (grain layer)", gl, -1, 0},
        {"OSMesa draw + Cairo overlay", overlay, -1, 0},
        {"Cairo draw", cairo, -1, 0},
    };

    char names[PRESETS + 1][64];
    for (int p = 0; p <= PRESETS; ++p) {
        snprintf(names[p], sizeof names[p], "%s draw + encode (x264 %s, CRF 20)",
                 p < PRESETS ? "OSMesa" : "Cairo", p < PRESETS ? presets[p] : "default");
        rows[3 + p].name = names[p];
        rows[3 + p].rate = movies[p];
        rows[3 + p].bytes = bytes[p];
        rows[3 + p].movie = 1;
    }
    for (size_t k = 0; k < (draw_only ? 2 : sizeof rows / sizeof rows[0]); ++k) {
        printf("%-52s %9.1f %9.1f %12.1f", rows[k].name, rows[k].rate.fps,
               rows[k].rate.fps > 0 ? 1e3 / rows[k].rate.fps : 0.0, rows[k].rate.cpu_ms);
        if (rows[k].bytes >= 0)
            printf(" %8.1f", rows[k].bytes / 1e6);
        else
            printf(" %8s", "");
        if (rows[k].movie && sim_ms > 0.0)
            printf(" %9.2f", rows[k].rate.cpu_ms / sim_ms);
        printf("\n");
    }
    /* On 2 idle cores the wall time of a frame is about the calling thread's part plus the
     * rasterisation (most of the rest) shared between the cores. */
    printf("calling thread CPU per OSMesa frame (bench frame data included): %.1f ms grain layer, "
           "%.1f ms with overlay\n",
           gl.caller_ms, overlay.caller_ms);
    if (draw_only)
        return 0;
    printf("encoding (convert + x264 + mux) CPU per OSMesa movie frame: %.1f ms veryfast, %.1f ms "
           "superfast, %.1f ms ultrafast\n",
           movies[0].cpu_ms - overlay.cpu_ms, movies[1].cpu_ms - overlay.cpu_ms,
           movies[2].cpu_ms - overlay.cpu_ms);
    return 0;
}
