/* SPDX-License-Identifier: MIT */
/* state.c: checkpoints. A state file holds the grains (fixed ones included), the walls at rest,
 * the time, the step, the sink counts and the contact history keyed by grain ids, in native byte
 * order (little-endian on x86-64). Written to PATH.tmp and renamed when complete. */
#include "internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Version 2 adds the exact-continuation section (resume.c) after the contact history; version 1
 * files (without it) still load, starting afresh from their grains. */
static const char magic[16] = "SABLIER-STATE-2\n";
static const char magic_v1[16] = "SABLIER-STATE-1\n";

/* The format version of a header's magic: 2, 1, or 0 (not a state file). */
static int magic_version(const char m[16])
{
    return memcmp(m, magic, 16) == 0 ? 2 : memcmp(m, magic_v1, 16) == 0 ? 1 : 0;
}

static SimStatus io_fail(SimError *error, const char *path, const char *what)
{
    if (error) {
        memset(error, 0, sizeof *error);
        error->status = SIM_ERROR_IO;
        snprintf(error->field, sizeof error->field, "state");
        snprintf(error->message, sizeof error->message, "%.280s: %.60s%s%.50s", path, what,
                 errno ? ": " : "", errno ? strerror(errno) : "");
        error->step = error->grain = -1;
    }
    return SIM_ERROR_IO;
}

static SimStatus memory_fail(SimError *error, const char *path, const char *what)
{
    errno = 0;
    io_fail(error, path, what);
    if (error)
        error->status = SIM_ERROR_MEMORY;
    return SIM_ERROR_MEMORY;
}

FILE *sim_open_input(const char *path, const char **why)
{
    const char *reason = NULL;
    FILE *f = NULL;
    struct stat st;
    /* O_NONBLOCK: opening a FIFO returns at once instead of waiting for a writer */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0 || fstat(fd, &st) != 0)
        reason = strerror(errno);
    else if (S_ISDIR(st.st_mode) || !S_ISREG(st.st_mode)) {
        errno = 0;
        reason = S_ISDIR(st.st_mode) ? "it is a folder"
                                     : "not a regular file (a FIFO, socket or device)";
    } else if (fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0 || !(f = fdopen(fd, "rb")))
        reason = strerror(errno);
    if (!f && fd >= 0) {
        int saved = errno;
        close(fd);
        errno = saved;
    }
    if (why)
        *why = reason;
    return f;
}

int sim_output_target(const char *path, const char **why)
{
    struct stat st;
    const char *reason = NULL;
    if (lstat(path, &st) != 0) {
        if (errno != ENOENT)
            reason = strerror(errno);
    } else if (!S_ISREG(st.st_mode)) {
        /* errno for callers that print strerror: ELOOP as O_NOFOLLOW has it for a link */
        errno = S_ISLNK(st.st_mode) ? ELOOP : S_ISDIR(st.st_mode) ? EISDIR : EEXIST;
        reason = S_ISLNK(st.st_mode)   ? "a symbolic link (outputs are regular files only)"
                 : S_ISDIR(st.st_mode) ? "it is a folder"
                                       : "not a regular file (a FIFO, socket or device)";
    }
    if (why)
        *why = reason;
    return reason ? -1 : 0;
}

FILE *sim_open_output(const char *path, const char **why)
{
    if (sim_output_target(path, why) != 0)
        return NULL;
    size_t n = strlen(path) + 5;
    char *tmp = malloc(n);
    if (!tmp) {
        if (why)
            *why = strerror(ENOMEM);
        return NULL;
    }
    snprintf(tmp, n, "%s.tmp", path);
    FILE *f = NULL;
    /* O_EXCL | O_NOFOLLOW: a new regular file, never through a link left at PATH.tmp */
    int fd = unlink(tmp) == 0 || errno == ENOENT
                 ? open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666)
                 : -1;
    if (fd >= 0 && !(f = fdopen(fd, "wb"))) {
        int saved = errno;
        close(fd);
        unlink(tmp);
        errno = saved;
    }
    if (!f && why)
        *why = strerror(errno);
    free(tmp);
    return f;
}

/* A state file opened for reading (sim_open_input): NULL with the reason in *error. */
static FILE *state_open(const char *path, SimError *error)
{
    const char *why = NULL;
    errno = 0;
    FILE *f = sim_open_input(path, &why);
    if (!f)
        io_fail(error, path, errno ? "cannot open state file" : why);
    return f;
}

typedef struct StateHeader {
    char magic[16];
    int32_t count, mobile_count, wall_count;
    int32_t wall_size; /* bytes per wall record: 0 = the segment-only LegacyWall, else SimWall */
    double time;
    int64_t step;
    int64_t removed[SIM_MAX_SINKS];
} StateHeader;

/* The wall record of files with segments only (what every state held before arc walls): kept
 * for such walls, so their checkpoints keep their bytes. */
typedef struct LegacyWall {
    double x0, y0, x1, y1;
    int species, motion;
} LegacyWall;

/* 1 when every wall is a plain segment (a LegacyWall says all of it). */
static int walls_legacy(const SimWall *walls, int count)
{
    for (int k = 0; k < count; ++k)
        if (walls[k].shape != SIM_WALL_SEGMENT)
            return 0;
    return 1;
}

static int write_walls(FILE *f, const SimWall *walls, int count, int legacy)
{
    if (!legacy)
        return fwrite(walls, sizeof(SimWall), (size_t)count, f) == (size_t)count;
    for (int k = 0; k < count; ++k) {
        LegacyWall l = {walls[k].x0, walls[k].y0,      walls[k].x1,
                        walls[k].y1, walls[k].species, walls[k].motion};
        if (fwrite(&l, sizeof l, 1, f) != 1)
            return 0;
    }
    return 1;
}

static int read_walls(FILE *f, SimWall *walls, int count, int32_t wall_size)
{
    if (wall_size != 0)
        return wall_size == (int32_t)sizeof(SimWall) &&
               fread(walls, sizeof(SimWall), (size_t)count, f) == (size_t)count;
    for (int k = 0; k < count; ++k) {
        LegacyWall l;
        if (fread(&l, sizeof l, 1, f) != 1)
            return 0;
        walls[k] = (SimWall){.x0 = l.x0,
                             .y0 = l.y0,
                             .x1 = l.x1,
                             .y1 = l.y1,
                             .species = l.species,
                             .motion = l.motion};
    }
    return 1;
}

/* A header whose magic, counts and wall record size a reader can trust (a negative wall_size
 * cancelled the bytes a huge grain count needs: a fuzzed state announced 201 million grains in
 * 280 bytes). */
static int header_sound(const StateHeader *h)
{
    return magic_version(h->magic) != 0 && h->count >= 0 && h->mobile_count >= 0 &&
           h->mobile_count <= h->count && h->wall_count >= 0 &&
           (h->wall_size == 0 || h->wall_size == (int32_t)sizeof(SimWall));
}

static long wall_bytes(const StateHeader *h)
{
    return (long)h->wall_count * (h->wall_size ? (long)h->wall_size : (long)sizeof(LegacyWall));
}

SimStatus sim_world_save(SimWorld *w, const char *path, SimError *error)
{
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return io_fail(error, path, "path too long");
    if (w->out_of_memory) /* its lists are empty: the contact history is lost */
        return memory_fail(error, path, "the world ran out of memory; its state is incomplete");
    const char *why = NULL;
    errno = 0;
    FILE *f = sim_open_output(path, &why);
    if (!f) {
        errno = 0;
        return io_fail(error, path, why);
    }
    StateHeader h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, magic, sizeof magic);
    h.count = w->count;
    h.mobile_count = w->mobile_count;
    h.wall_count = w->wall_count;
    const int legacy = walls_legacy(w->walls_base, w->wall_count);
    h.wall_size = legacy ? 0 : (int32_t)sizeof(SimWall);
    h.time = w->time;
    h.step = w->step;
    for (int s = 0; s < SIM_MAX_SINKS; ++s)
        h.removed[s] = w->removed[s];
    size_t n = (size_t)w->count;
    int ok = fwrite(&h, sizeof h, 1, f) == 1;
    const double *doubles[] = {w->x, w->y, w->vx, w->vy, w->angle, w->omega, w->radius};
    for (size_t a = 0; ok && a < sizeof doubles / sizeof doubles[0]; ++a)
        ok = fwrite(doubles[a], sizeof(double), n, f) == n;
    /* Fixed grains with a motion are stored at their rest position. */
    if (ok) {
        for (size_t i = (size_t)w->mobile_count; i < n && ok; ++i) {
            double rest[2] = {w->x_base[i], w->y_base[i]};
            ok = fwrite(rest, sizeof rest, 1, f) == 1;
        }
    }
    ok = ok && fwrite(w->species, sizeof(int), n, f) == n;
    ok = ok && fwrite(w->motion, sizeof(int), n, f) == n;
    ok = ok && fwrite(w->flags, sizeof(unsigned), n, f) == n;
    ok = ok && fwrite(w->id, sizeof(uint32_t), n, f) == n;
    ok = ok && write_walls(f, w->walls_base, w->wall_count, legacy);
    /* contact history: counts, then the records */
    void *records = NULL, *walls = NULL;
    int32_t counts[2] = {0, 0};
    int rc = 0, wc = 0;
    if (sim_neighbour_history(w, &records, &rc, &walls, &wc) != 0) {
        fclose(f);
        remove(tmp);
        return memory_fail(error, tmp, "out of memory collecting the contact history");
    }
    counts[0] = rc;
    counts[1] = wc;
    ok = ok && fwrite(counts, sizeof counts, 1, f) == 1;
    if (rc > 0) /* no history: the arrays may be NULL, which fwrite must not see */
        ok = ok && fwrite(records, SIM_HISTORY_RECORD_SIZE, (size_t)rc, f) == (size_t)rc;
    if (wc > 0)
        ok = ok && fwrite(walls, SIM_HISTORY_RECORD_SIZE, (size_t)wc, f) == (size_t)wc;
    free(records);
    free(walls);
    ok = ok && sim_exact_write(f, w) == 0;
    ok = ok && sim_wall_bodies_write(f, w) == 0;
    if (fclose(f) != 0)
        ok = 0;
    if (!ok) {
        remove(tmp);
        return io_fail(error, tmp, "write failed");
    }
    if (rename(tmp, path) != 0) {
        remove(tmp);
        return io_fail(error, path, "cannot rename the temporary file");
    }
    return SIM_OK;
}

void sim_grain_set_free(SimGrainSet *g)
{
    free((void *)(uintptr_t)g->x);
    free((void *)(uintptr_t)g->y);
    free((void *)(uintptr_t)g->vx);
    free((void *)(uintptr_t)g->vy);
    free((void *)(uintptr_t)g->angle);
    free((void *)(uintptr_t)g->omega);
    free((void *)(uintptr_t)g->radius);
    free((void *)(uintptr_t)g->species);
    free((void *)(uintptr_t)g->motion);
    free((void *)(uintptr_t)g->flags);
    free((void *)(uintptr_t)g->id);
    memset(g, 0, sizeof *g);
}

/* What no saved world holds (x, y, vx, vy, angle, omega, radius in d[0..6]): a non-finite value
 * or a radius <= 0, written into `why` with the grain's id; NULL when every grain is sound. */
static const char *grain_problem(double *const d[7], const uint32_t *id, size_t n, char *why,
                                 size_t size)
{
    for (size_t i = 0; i < n; ++i) {
        int a = 0;
        while (a < 6 && isfinite(d[a][i]))
            ++a;
        if (a < 6) {
            snprintf(why, size, "grain %u has a non-finite position, velocity or angle", id[i]);
            return why;
        }
        if (!(d[6][i] > 0.0) || !isfinite(d[6][i])) {
            snprintf(why, size, "grain %u has a radius %g, not a positive finite number", id[i],
                     d[6][i]);
            return why;
        }
    }
    return NULL;
}

/* A version-2 file at the end of its walls: its contact history skipped, its continuation
 * section's header checked (sim_exact_check), so that a section a world would choke on is
 * refused with the file. NULL when sound. */
static const char *continuation_problem(FILE *f)
{
    int32_t counts[2];
    if (fread(counts, sizeof counts, 1, f) != 1 || counts[0] < 0 || counts[1] < 0 ||
        fseek(f, ((long)counts[0] + (long)counts[1]) * SIM_HISTORY_RECORD_SIZE, SEEK_CUR) != 0)
        return "truncated state file (its contact history)";
    return sim_exact_check(f);
}

/* sim_state_load, with the file's header in *header. */
static SimStatus state_read(const char *path, SimGrainSet *grains, SimWall **walls, int *wall_count,
                            StateHeader *header, SimError *error)
{
    memset(grains, 0, sizeof *grains);
    *walls = NULL;
    *wall_count = 0;
    FILE *f = state_open(path, error);
    if (!f)
        return SIM_ERROR_IO;
    StateHeader h;
    if (fread(&h, sizeof h, 1, f) != 1 || !header_sound(&h)) {
        fclose(f);
        errno = 0;
        return io_fail(error, path, "not a sablier state file (bad header)");
    }
    if (!isfinite(h.time) || h.step < 0) {
        fclose(f);
        errno = 0;
        return io_fail(error, path, "not a sablier state file (time not finite)");
    }
    /* the arrays the header announces must be in the file before anything is allocated */
    size_t n = (size_t)h.count, alloc = n ? n : 1;
    double need =
        (double)sizeof h +
        (double)n *
            (7.0 * sizeof(double) + sizeof(int) * 2.0 + sizeof(unsigned) + sizeof(uint32_t)) +
        (double)(n - (size_t)h.mobile_count) * 2.0 * sizeof(double) + (double)wall_bytes(&h);
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || (double)st.st_size < need) {
        fclose(f);
        errno = 0;
        return io_fail(error, path, "truncated state file (shorter than its header says)");
    }
    double *d[7];
    for (int a = 0; a < 7; ++a)
        d[a] = malloc(alloc * sizeof(double));
    int *species = malloc(alloc * sizeof(int)), *motion = malloc(alloc * sizeof(int));
    unsigned *flags = malloc(alloc * sizeof(unsigned));
    uint32_t *id = malloc(alloc * sizeof(uint32_t));
    SimWall *wl = malloc((size_t)(h.wall_count ? h.wall_count : 1) * sizeof(SimWall));
    int ok = species && motion && flags && id && wl;
    for (int a = 0; a < 7; ++a)
        ok = ok && d[a] && fread(d[a], sizeof(double), n, f) == n;
    for (size_t i = (size_t)h.mobile_count; ok && i < n; ++i) {
        double rest[2];
        ok = fread(rest, sizeof rest, 1, f) == 1;
        d[0][i] = rest[0];
        d[1][i] = rest[1];
    }
    ok = ok && fread(species, sizeof(int), n, f) == n;
    ok = ok && fread(motion, sizeof(int), n, f) == n;
    ok = ok && fread(flags, sizeof(unsigned), n, f) == n;
    ok = ok && fread(id, sizeof(uint32_t), n, f) == n;
    if (h.wall_count > 0)
        ok = ok && read_walls(f, wl, h.wall_count, h.wall_size);
    const char *bad = ok && magic_version(h.magic) == 2 ? continuation_problem(f) : NULL;
    fclose(f);
    char why[128];
    if (ok && !bad)
        bad = grain_problem(d, id, n, why, sizeof why);
    if (!ok || bad) {
        for (int a = 0; a < 7; ++a)
            free(d[a]);
        free(species);
        free(motion);
        free(flags);
        free(id);
        free(wl);
        errno = 0;
        return io_fail(error, path, bad ? bad : "truncated or unreadable state file");
    }
    *grains = (SimGrainSet){.count = h.count,
                            .x = d[0],
                            .y = d[1],
                            .vx = d[2],
                            .vy = d[3],
                            .angle = d[4],
                            .omega = d[5],
                            .radius = d[6],
                            .species = species,
                            .flags = flags,
                            .motion = motion,
                            .id = id};
    *walls = wl;
    *wall_count = h.wall_count;
    *header = h;
    return SIM_OK;
}

SimStatus sim_state_load(const char *path, SimGrainSet *grains, SimWall **walls, int *wall_count,
                         double *time, SimError *error)
{
    StateHeader h;
    SimStatus status = state_read(path, grains, walls, wall_count, &h, error);
    *time = status == SIM_OK ? h.time : 0.0;
    return status;
}

/* Bytes of the grain and wall sections (layout of sim_world_save). */
static long grain_wall_bytes(const StateHeader *h)
{
    return (long)h->count * (7 * (long)sizeof(double) + 2 * (long)sizeof(int) +
                             (long)sizeof(unsigned) + (long)sizeof(uint32_t)) +
           (long)(h->count - h->mobile_count) * 2 * (long)sizeof(double) + wall_bytes(h);
}

SimStatus sim_world_restore_contacts(SimWorld *w, const char *path, SimError *error)
{
    if (w->exact_restored) /* sim_world_load installed the saved lists, history included */
        return SIM_OK;
    FILE *f = state_open(path, error);
    if (!f)
        return SIM_ERROR_IO;
    StateHeader h;
    int ok = fread(&h, sizeof h, 1, f) == 1 && header_sound(&h);
    ok = ok && fseek(f, grain_wall_bytes(&h), SEEK_CUR) == 0;
    int32_t counts[2];
    ok = ok && fread(counts, sizeof counts, 1, f) == 1 && counts[0] >= 0 && counts[1] >= 0;
    /* the records the counts announce must be in the file before they are allocated */
    struct stat st;
    long here = ok ? ftell(f) : -1;
    ok = ok && here >= 0 && fstat(fileno(f), &st) == 0 &&
         ((double)counts[0] + (double)counts[1]) * SIM_HISTORY_RECORD_SIZE <=
             (double)st.st_size - (double)here;
    void *records = NULL, *walls = NULL;
    if (ok) {
        records = malloc(((size_t)counts[0] + 1) * SIM_HISTORY_RECORD_SIZE);
        walls = malloc(((size_t)counts[1] + 1) * SIM_HISTORY_RECORD_SIZE);
        ok = records && walls &&
             fread(records, SIM_HISTORY_RECORD_SIZE, (size_t)counts[0], f) == (size_t)counts[0] &&
             fread(walls, SIM_HISTORY_RECORD_SIZE, (size_t)counts[1], f) == (size_t)counts[1];
    }
    fclose(f);
    if (!ok) {
        free(records);
        free(walls);
        errno = 0;
        return io_fail(error, path, "no contact history in this state file (truncated or older)");
    }
    for (int s = 0; s < SIM_MAX_SINKS; ++s)
        w->removed[s] = h.removed[s];
    int stashed = !w->has_history ||
                  sim_neighbour_stash_records(w, records, counts[0], walls, counts[1]) == 0;
    free(records);
    free(walls);
    if (!stashed)
        return memory_fail(error, path, "out of memory installing the contact history");
    if (w->has_history) {
        sim_world_rebuild_now(w);
        if (w->out_of_memory)
            return memory_fail(error, path, "out of memory rebuilding the lists");
    }
    return SIM_OK;
}

/* The exact-continuation section of a version-2 file applied to the world made from its grains
 * (resume.c). SIM_OK also when the section does not fit the world (it then starts afresh). */
static SimStatus exact_section(SimWorld *world, const char *path, const SimGrainSet *grains,
                               const StateHeader *h, SimError *error)
{
    FILE *f = state_open(path, error);
    if (!f)
        return SIM_ERROR_IO;
    int32_t counts[2];
    int ok = fseek(f, (long)sizeof *h + grain_wall_bytes(h), SEEK_SET) == 0 &&
             fread(counts, sizeof counts, 1, f) == 1 && counts[0] >= 0 && counts[1] >= 0 &&
             fseek(f, ((long)counts[0] + (long)counts[1]) * SIM_HISTORY_RECORD_SIZE, SEEK_CUR) == 0;
    int applied = ok ? sim_exact_apply(world, f, grains, (long)h->step, h->time) : -1;
    fclose(f);
    errno = 0;
    if (applied == -2)
        return memory_fail(error, path, "out of memory restoring the lists");
    if (applied < 0)
        return io_fail(error, path, "truncated state file (its continuation section)");
    if (applied == 1) {
        for (int s = 0; s < SIM_MAX_SINKS; ++s)
            world->removed[s] = h->removed[s];
        world->exact_restored = 1;
    }
    return SIM_OK;
}

/* The responding walls' offsets and speeds from the file's footer (wall_body.c); a world that
 * did not continue exactly evaluates its forces again with the walls where they were saved. */
static SimStatus body_footer(SimWorld *world, const char *path, SimError *error)
{
    FILE *f = state_open(path, error);
    if (!f)
        return SIM_ERROR_IO;
    sim_wall_bodies_read(world, f);
    fclose(f);
    if (!world->exact_restored)
        sim_world_rebuild_now(world);
    return SIM_OK;
}

SimWorld *sim_world_load(const char *path, const SimWorldDef *def, SimError *error)
{
    SimGrainSet grains;
    SimWall *walls = NULL;
    int wall_count = 0;
    StateHeader h;
    if (state_read(path, &grains, &walls, &wall_count, &h, error) != SIM_OK)
        return NULL;
    SimWorldDef d = *def;
    d.grains = grains;
    d.walls = walls;
    d.wall_count = wall_count;
    if (wall_count != def->wall_count) /* the state's walls are not the definition's */
        d.wall_bodies = NULL;
    d.start_time = h.time;
    /* Restored grains: exempt from the start-overlap bound (sim_world_create_restored). */
    SimWorld *world = sim_world_create_restored(&d, error);
    if (world && magic_version(h.magic) == 2 &&
        exact_section(world, path, &grains, &h, error) != SIM_OK) {
        sim_world_destroy(world);
        world = NULL;
    }
    if (world && world->bodies && body_footer(world, path, error) != SIM_OK) {
        sim_world_destroy(world);
        world = NULL;
    }
    sim_grain_set_free(&grains);
    free(walls);
    return world;
}
