/* SPDX-License-Identifier: MIT */
/* render_helper.c: the drawing helper of the movie drawers (render_gl.c's second band,
 * render_cairo.c's lower rows): one thread that runs one job at a time for the thread that created
 * it, which goes on with its own share and then waits for the job. The thread persists from job to
 * job, because a GL context stays current in the thread that made it current. */
#include "internal.h"

#include <pthread.h>
#include <stdlib.h>

struct RenderHelper {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake, done;
    RenderJobFn *job; /* the job given, NULL once the thread has taken it */
    void *context;
    int busy; /* a job given and not finished */
    int quit;
};

static void *helper_main(void *arg)
{
    RenderHelper *h = arg;
    pthread_mutex_lock(&h->lock);
    for (;;) {
        while (!h->job && !h->quit)
            pthread_cond_wait(&h->wake, &h->lock);
        if (!h->job)
            break;
        RenderJobFn *job = h->job;
        void *context = h->context;
        h->job = NULL;
        pthread_mutex_unlock(&h->lock);
        job(context);
        pthread_mutex_lock(&h->lock);
        h->busy = 0;
        pthread_cond_signal(&h->done);
    }
    pthread_mutex_unlock(&h->lock);
    return NULL;
}

RenderHelper *render_helper_create(void)
{
    RenderHelper *h = calloc(1, sizeof *h);
    if (!h)
        return NULL;
    if (pthread_mutex_init(&h->lock, NULL) != 0) {
        free(h);
        return NULL;
    }
    if (pthread_cond_init(&h->wake, NULL) != 0)
        goto no_wake;
    if (pthread_cond_init(&h->done, NULL) != 0)
        goto no_done;
    if (pthread_create(&h->thread, NULL, helper_main, h) != 0)
        goto no_thread;
    return h;
no_thread:
    pthread_cond_destroy(&h->done);
no_done:
    pthread_cond_destroy(&h->wake);
no_wake:
    pthread_mutex_destroy(&h->lock);
    free(h);
    return NULL;
}

void render_helper_start(RenderHelper *h, RenderJobFn *job, void *context)
{
    pthread_mutex_lock(&h->lock);
    h->job = job;
    h->context = context;
    h->busy = 1;
    pthread_cond_signal(&h->wake);
    pthread_mutex_unlock(&h->lock);
}

void render_helper_wait(RenderHelper *h)
{
    pthread_mutex_lock(&h->lock);
    while (h->busy)
        pthread_cond_wait(&h->done, &h->lock);
    pthread_mutex_unlock(&h->lock);
}

void render_helper_destroy(RenderHelper *h)
{
    if (!h)
        return;
    render_helper_wait(h);
    pthread_mutex_lock(&h->lock);
    h->quit = 1;
    pthread_cond_signal(&h->wake);
    pthread_mutex_unlock(&h->lock);
    pthread_join(h->thread, NULL);
    pthread_cond_destroy(&h->done);
    pthread_cond_destroy(&h->wake);
    pthread_mutex_destroy(&h->lock);
    free(h);
}

int render_band_count(int height, int threads)
{
    const char *forced = getenv("SABLIER_BANDS");
    if (forced && (forced[0] == '1' || forced[0] == '2') && forced[1] == '\0')
        return forced[0] == '2' && height >= 2 ? 2 : 1;
    const int cpus = threads > 0 ? threads : sim_cpu_count();
    return cpus >= 2 && height >= 128 ? 2 : 1;
}
