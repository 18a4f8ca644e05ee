/* SPDX-License-Identifier: MIT */
/* test_movie_pace.c: the frames a stage's movie gets for output.movie_speed,
 * output.movie_duration and frame_rate (docs/scenes.md#output): a one-grain scene (dt = 1e-3 s,
 * time.end = 1 s, fps 25) run with a renderer whose movie only counts the frames it is given and
 * their times; and the thread count the renderer is told before the movie opens. */
#include "test.h"

#include "run/run.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct Counter {
    int frames;
    double first, last;  ///< simulated times of the first and last frame, s
    int threads;         ///< what the run told the renderer (AppRender.threads), -1: nothing
    int threads_at_open; ///< that count when the movie opened
} Counter;

static void counting_threads(void *context, int threads)
{
    ((Counter *)context)->threads = threads;
}

static int count_frame(void *context, const SimFrame *frame)
{
    Counter *c = context;
    if (c->frames++ == 0)
        c->first = frame->time;
    c->last = frame->time;
    return 0;
}

static int counting_open(void *context, const struct Scene *scene, int stage, const char *path,
                         SimFrameSink *sink, char *err, size_t err_size)
{
    (void)scene, (void)stage, (void)path, (void)err, (void)err_size;
    ((Counter *)context)->threads_at_open = ((Counter *)context)->threads;
    *sink = (SimFrameSink){.consume = count_frame, .context = context};
    return 0;
}

static int counting_close(void *context, char *err, size_t err_size)
{
    (void)context, (void)err, (void)err_size;
    return 0;
}

/* Runs the one-grain scene with `output_keys` in its output group on `threads` (--threads); the
 * movie's frames in c. */
static int run_threads(const char *output_keys, int threads, Counter *c)
{
    char scene_path[256], dir[256];
    snprintf(scene_path, sizeof scene_path, "/tmp/sablier_test_movie_pace_%ld.scene",
             (long)getpid());
    snprintf(dir, sizeof dir, "/tmp/sablier_test_movie_pace_%ld", (long)getpid());
    FILE *f = fopen(scene_path, "w");
    if (!f)
        return -1;
    fprintf(f,
            "name = \"pace\"; seed = 1; time = { dt = 1e-3; end = 1.0; };\n"
            "mass_model = \"disk\"; effects = []; gravity = [0.0, -1.0];\n"
            "species = ( { name = \"g\"; density = 1.0; k_n = 1000.0; gamma_n = 1.0; } );\n"
            "grains = { list = ( { x = 5.0; y = 2.0; r = 0.5; } ); };\n"
            "output = { movie = true; %s };\n",
            output_keys);
    fclose(f);
    char err[2048];
    Scene *scene = scene_load(scene_path, NULL, 0, err, sizeof err);
    remove(scene_path);
    if (!scene) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    memset(c, 0, sizeof *c);
    c->threads = c->threads_at_open = -1;
    AppRender render = {.context = c,
                        .movie_open = counting_open,
                        .movie_close = counting_close,
                        .threads = counting_threads};
    AppRunOptions options = app_run_options_default();
    options.threads = threads;
    options.out_dir = dir;
    options.quiet = 1;
    options.render = &render;
    int status = app_run(scene, &options);
    scene_free(scene);
    char command[300];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        return -1;
    return status;
}

static int run_paced(const char *output_keys, Counter *c)
{
    return run_threads(output_keys, 1, c);
}

/* movie_speed = 0.1 at 25 fps: a frame every 0.004 s, 251 frames over the second (10 s of
 * video, both ends included). */
static int movie_speed_frames(void)
{
    Counter c;
    TEST_ASSERT(run_paced("movie_speed = 0.1;", &c) == 0);
    TEST_ASSERT(c.frames == 251);
    TEST_NEAR(c.first, 0.0, 1e-12);
    TEST_NEAR(c.last, 1.0, 1e-9);
    /* the same pace at another fps: twice the frames per simulated second at 50 fps */
    TEST_ASSERT(run_paced("movie_speed = 0.1; fps = 50.0;", &c) == 0);
    TEST_ASSERT(c.frames == 501);
    return 0;
}

/* movie_duration = 2 s of video for the 1 s stage at 25 fps: a frame every 0.02 s. */
static int movie_duration_frames(void)
{
    Counter c;
    TEST_ASSERT(run_paced("movie_duration = 2.0;", &c) == 0);
    TEST_ASSERT(c.frames == 51);
    TEST_NEAR(c.last, 1.0, 1e-9);
    return 0;
}

/* Without either, frame_rate frames per simulated second as before (default 25). */
static int frame_rate_unchanged(void)
{
    Counter c;
    TEST_ASSERT(run_paced("", &c) == 0);
    TEST_ASSERT(c.frames == 26);
    TEST_ASSERT(run_paced("frame_rate = 100.0;", &c) == 0);
    TEST_ASSERT(c.frames == 101);
    return 0;
}

/* The movie is told the run's thread count before it opens (its frames' drawing stays within
 * it: render.mp4.mp4_threads_bound_drawing): `--threads 3` gives 3, `--threads auto` 0 (the
 * CPUs of the affinity mask). */
static int movie_told_threads(void)
{
    Counter c;
    TEST_ASSERT(run_threads("", 3, &c) == 0);
    TEST_ASSERT(c.frames == 26 && c.threads == 3 && c.threads_at_open == 3);
    TEST_ASSERT(run_threads("", APP_THREADS_AUTO, &c) == 0);
    TEST_ASSERT(c.frames == 26 && c.threads == 0 && c.threads_at_open == 0);
    return 0;
}

TEST_MAIN(TEST_CASE(movie_told_threads), TEST_CASE(movie_speed_frames),
          TEST_CASE(movie_duration_frames), TEST_CASE(frame_rate_unchanged))
